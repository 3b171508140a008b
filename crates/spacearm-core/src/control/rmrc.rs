//! Resolved-motion-rate control of a point through the Generalized Jacobian `J*` (paper eqs.
//! 109–111; Whitney 1969; Umetani & Yoshida 1989), with damped least squares near singularities:
//! the solver of [`crate::analysis::rmrc_solver`] (the one the analyses run) inside the
//! simulation loop, on the arm joints, with the wheels and the system momentum as drift.
//!
//! The point's twist is `[v; ω] = J*_A q̇_A + v_drift` (`J*_A` the columns of the arm joints;
//! `v_drift` the twist that the system momentum `M0` produces, `J_0X H0⁻¹ M0`, eq. 109
//! generalized to `M0 ≠ 0`, plus the wheels' `J*_W q̇_W`). The joint-rate command solves the task
//! rows ([`Task`], default the three translational rows) of
//! `J q̇_cmd = v_d − v_drift`, `v_d = [ṗ_ref + K (p_ref − p); K e_R]`
//! ([`crate::analysis::rmrc_solver::desired_twist`]; `e_R` the rotation vector of `R_d Rᵀ`
//! with `R_d` the orientation of the point's body at the first evaluation, for angular task
//! rows), with the [`Strategy`] towards the base (default naive: `q̇_cmd = J⁺_λ (v_d − v_drift)`;
//! reactionless: in the reaction null space of the arm, no base rotation from the arm;
//! minimum base disturbance). The reference is a [`PointReference`]: a straight line, a point on
//! a tumbling free body (the grasp point of a capture target) or a sampled path. An optional rate
//! cap scales `q̇_cmd` as a whole so that its largest entry is at most `max_joint_rate` (the
//! direction of the point's motion is kept; with minimum base disturbance the null-space part is
//! shortened first). The damping follows the singular values `σᵢ` of `J` (Nakamura & Hanafusa
//! 1986; Chiaverini 1997), applied per singular direction (the one damped inverse, [`crate::math::dls`]):
//! `λ²(σ) = λ_max² (1 − (σ/ε)²)` for `σ < ε`, `0` otherwise — the exact pseudo-inverse away from
//! singularities, bounded joint rates near them, and no damping of the directions that are
//! well conditioned (a planar arm keeps exact tracking in its plane although `J` has rank 2). The joints follow `q̇_cmd` through the
//! reduced EOM (a computed-torque velocity loop): `τ = H* K_v (q̇_cmd − q̇) + c*`.
//!
//! Passive joints (no motor: slosh, hinged panels) are not resolved: like the wheels, their
//! measured rates add drift to the point twist, and the velocity loop on the actuated joints is
//! the partial feedback linearization of [`super::computed_torque`] (zero torque on them).

use nalgebra::{Matrix3, Vector3, Vector6};

use crate::algorithms::kinematics::{check_body, forward_kinematics, point_position};
use crate::analysis::rmrc_solver::{desired_twist, RmrcOptions, RmrcSolver, Strategy};
use crate::analysis::Task;
use crate::error::{Result, SpacearmError};
use crate::math::dls::DampingLaw;
use crate::model::data::Data;
use crate::model::Model;
use crate::scenario::reference::PointReference;

use super::computed_torque::ReducedInverseDynamics;
use super::controller::split_passive;
use super::{positive, Command, ControlContext, Controller, TrackingKind};

/// Resolved-motion-rate control of a point along a [`PointReference`].
#[derive(Debug, Clone)]
pub struct ResolvedMotionRate {
    reference: PointReference,
    max_joint_rate: f64,
    gain: f64,
    damping: f64,
    threshold: f64,
    velocity_gain: f64,
    body: usize,
    offset: Vector3<f64>,
    task: Task,
    strategy: Strategy,
    model: Option<Model>,
    data: Option<Data>,
    inner: Option<ReducedInverseDynamics>,
    solver: Option<RmrcSolver>,
    arm: Vec<usize>,
    orientation: Option<Matrix3<f64>>,
    qdd_cmd: Vec<f64>,
    /// Damping λ² of the last evaluation (for tests and diagnostics).
    pub last_damping_sq: f64,
    /// `σ_min` of the task Jacobian and `|p_ref − p|` at the last evaluation (NaN before the first).
    last_sigma_min: f64,
    last_distance: f64,
}

impl ResolvedMotionRate {
    /// `gain` K (1/s, > 0), `damping` λ_max (≥ 0), `threshold` ε (> 0), `velocity_gain` K_v
    /// (1/s, > 0); the controlled point is fixed to `body` at `offset` (body frame). The task is
    /// the translational rows, the strategy naive (see [`ResolvedMotionRate::with_task`],
    /// [`ResolvedMotionRate::with_strategy`]).
    pub fn new(reference: impl Into<PointReference>, gain: f64, damping: f64, threshold: f64, velocity_gain: f64, body: usize, offset: Vector3<f64>) -> Self {
        ResolvedMotionRate {
            reference: reference.into(),
            max_joint_rate: f64::INFINITY,
            gain,
            damping,
            threshold,
            velocity_gain,
            body,
            offset,
            task: Task::position(),
            strategy: Strategy::Naive,
            model: None,
            data: None,
            inner: None,
            solver: None,
            arm: vec![],
            orientation: None,
            qdd_cmd: vec![],
            last_damping_sq: 0.0,
            last_sigma_min: f64::NAN,
            last_distance: f64::NAN,
        }
    }

    /// Cap the joint-rate command: `q̇_cmd` is scaled as a whole so that `max |q̇_cmd,i| ≤
    /// max_joint_rate` (rad/s or m/s, > 0; infinity: no cap, the default).
    pub fn with_max_joint_rate(mut self, max_joint_rate: f64) -> Self {
        self.max_joint_rate = max_joint_rate;
        self
    }

    /// The rows of the point twist the controller drives (default [`Task::position`]); angular
    /// rows hold the orientation of the point's body at the first evaluation.
    pub fn with_task(mut self, task: Task) -> Self {
        self.task = task;
        self
    }

    /// The treatment of the base (default [`Strategy::Naive`]).
    pub fn with_strategy(mut self, strategy: Strategy) -> Self {
        self.strategy = strategy;
        self
    }

    /// The damping law: `λ²` for a smallest singular value `sigma_min` (the same expression
    /// as in [`Controller::command`]).
    pub fn damping_sq(&self, sigma_min: f64) -> f64 {
        self.law().damping_sq(sigma_min)
    }

    /// The damped-least-squares law of [`crate::math::dls`] (checked in `setup`).
    fn law(&self) -> DampingLaw {
        DampingLaw { threshold: self.threshold, max_damping: self.damping }
    }

    /// The joint-rate command `q̇_cmd` of the last evaluation, one per arm joint (ascending dofs).
    pub fn last_rate_command(&self) -> Option<&[f64]> {
        self.solver.as_ref().map(|s| s.rates().as_slice())
    }
}

impl Controller for ResolvedMotionRate {
    fn name(&self) -> &str {
        "resolved_motion_rate"
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        positive("resolved-motion-rate gain", self.gain)?;
        positive("resolved-motion-rate threshold", self.threshold)?;
        positive("resolved-motion-rate velocity_gain", self.velocity_gain)?;
        if !(self.max_joint_rate > 0.0) {
            return Err(SpacearmError::argument(format!("resolved-motion-rate max_joint_rate must be > 0 (infinity: no cap), got {}", self.max_joint_rate)));
        }
        if !(self.damping.is_finite() && self.damping >= 0.0) {
            return Err(SpacearmError::argument(format!("resolved-motion-rate max_damping must be finite and >= 0, got {}", self.damping)));
        }
        check_body(ctx.plant, self.body)?;
        crate::error::check_finite("resolved-motion-rate point offset", self.offset.as_slice())?;
        // The actuated arm joints are resolved; the wheels and the passive joints add drift.
        let (arm, passive) = split_passive(ctx);
        if arm.is_empty() {
            return Err(SpacearmError::argument("resolved-motion-rate control needs at least one actuated arm joint"));
        }
        let model = ctx.plant.clone();
        let options = RmrcOptions { strategy: self.strategy, ..RmrcOptions::task(self.task.clone(), self.law(), self.gain) };
        let caps = vec![self.max_joint_rate; arm.len()];
        let drift: Vec<usize> = ctx.wheel_dofs.iter().chain(passive.iter()).copied().collect();
        self.solver = Some(RmrcSolver::new(&model, options, arm.clone(), drift, caps, false)?);
        self.data = Some(Data::new(&model));
        self.inner = Some(ReducedInverseDynamics::new(model.clone(), ctx)?);
        self.model = Some(model);
        self.arm = arm;
        self.orientation = None;
        self.qdd_cmd = vec![0.0; self.arm.len()];
        Ok(())
    }

    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        let (Some(model), Some(data), Some(inner), Some(solver)) = (self.model.as_ref(), self.data.as_mut(), self.inner.as_mut(), self.solver.as_mut()) else {
            return Err(SpacearmError::Simulation("resolved-motion-rate control used before setup".into()));
        };
        let (p_ref, v_ref, _) = self.reference.eval(t)?;
        forward_kinematics(model, data, x)?;
        let p = point_position(data, self.body, &self.offset);
        let r = data.body_to_world[self.body];
        let r_ref = *self.orientation.get_or_insert(r);
        let desired: Vector6<f64> = desired_twist(&p_ref, &v_ref, &p, &r_ref, &r, self.gain);
        let d = solver.solve(model, data, x, Some(u), self.body, &self.offset, &desired)?;
        self.last_damping_sq = d.damping_sq;
        self.last_sigma_min = d.sigma_min;
        let qd = solver.rates();
        for (i, &dof) in self.arm.iter().enumerate() {
            self.qdd_cmd[i] = self.velocity_gain * (qd[i] - u[6 + dof]);
        }
        inner.arm_torques(x, u, &self.qdd_cmd, out)?;
        out.reference[..3].copy_from_slice(p_ref.as_slice());
        out.tracking_error = (p_ref - p).norm();
        self.last_distance = out.tracking_error;
        Ok(())
    }

    /// The distance and `σ_min` of the last evaluation; damped when `λ² > 0` there.
    fn goal_report(&self) -> Option<super::GoalReport> {
        self.last_distance.is_finite().then_some(super::GoalReport {
            distance: self.last_distance,
            sigma_min: self.last_sigma_min,
            damped: self.last_damping_sq > 0.0,
        })
    }

    fn reference_len(&self) -> usize {
        3
    }

    fn tracking(&self) -> Option<TrackingKind> {
        Some(TrackingKind::Cartesian)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::reference::CartesianLine;

    #[test]
    fn damping_rises_as_the_smallest_singular_value_falls() {
        let line = CartesianLine::new(Vector3::zeros(), Vector3::x(), 0.0, 1.0).unwrap();
        let c = ResolvedMotionRate::new(line, 1.0, 0.1, 0.05, 10.0, 1, Vector3::zeros());
        assert_eq!(c.damping_sq(0.2), 0.0);
        assert_eq!(c.damping_sq(0.05), 0.0);
        assert!((c.damping_sq(0.0) - 0.01).abs() < 1e-15);
        let (a, b) = (c.damping_sq(0.04), c.damping_sq(0.01));
        assert!(a > 0.0 && b > a && b < 0.01);
    }

    #[test]
    fn the_command_is_the_analysis_rmrc_rates() {
        use crate::analysis::redundancy::rmrc_rates;
        use crate::model::presets;
        use crate::scenario::actuators::Actuators;
        use crate::scenario::modes::Mode;
        let m = presets::spatial7();
        let x = presets::initial_configuration(&m);
        let u = vec![0.0; m.nu()];
        let ee = m.points()[m.end_effector().unwrap()].clone();
        let mut d = Data::new(&m);
        crate::algorithms::kinematics::forward_kinematics(&m, &mut d, &x).unwrap();
        let p = point_position(&d, ee.body, &ee.offset);
        let dp = Vector3::new(0.02, -0.015, 0.01);
        let line = CartesianLine::new(p + dp, p + dp, 0.0, 1.0).unwrap();
        let arm: Vec<usize> = (0..m.n_dof()).collect();
        let actuators = Actuators::new(&m, false, None);
        let ctx = ControlContext { plant: &m, mode: Mode::Floating, wheel_dofs: &[], arm_dofs: &arm, actuators: &actuators };
        for strategy in [Strategy::Naive, Strategy::Reactionless, Strategy::MinimumBaseDisturbance] {
            for task in [Task::position(), Task::full()] {
                let mut c = ResolvedMotionRate::new(line, 5.0, 0.05, 0.05, 50.0, ee.body, ee.offset).with_strategy(strategy).with_task(task.clone());
                c.setup(&ctx).unwrap();
                let mut out = Command::new(m.n_dof(), 3);
                c.command(0.0, &x, &u, &mut out).unwrap();
                let options = RmrcOptions { strategy, ..RmrcOptions::task(task, c.law(), 5.0) };
                let desired = Vector6::new(5.0 * dp.x, 5.0 * dp.y, 5.0 * dp.z, 0.0, 0.0, 0.0);
                let r = rmrc_rates(&m, &mut d, &x, ee.body, &ee.offset, &desired, &options).unwrap();
                let cmd = c.last_rate_command().unwrap();
                assert!(r.qd.amax() > 0.1 && r.qd.amax() < 1.5, "{strategy:?}: no cap in play");
                for i in 0..m.n_dof() {
                    assert!((cmd[i] - r.qd[i]).abs() < 1e-14, "{strategy:?}: {} vs {}", cmd[i], r.qd[i]);
                }
                assert_eq!(c.last_damping_sq, r.damping * r.damping);
            }
        }
    }
}
