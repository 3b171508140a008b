//! The controller interface: what the loop calls ([`Controller`]) and what a controller
//! returns ([`Command`]), the plant it is set up against ([`ControlContext`]), what its
//! tracking error measures ([`TrackingKind`]) and how far from its goal it ended
//! ([`GoalReport`]); [`ZeroTorque`], [`Combined`] (a base controller, then an arm controller)
//! and the small helpers the controllers share. Re-exported by [`crate::control`].
//!
//! Imports: `model`, `scenario` (the maneuvering mode, the actuator limits), `error`; nothing of
//! the controllers beside it, which all use it.

use nalgebra::Vector6;

use crate::scenario::actuators::Actuators;
use crate::error::{Result, SpacearmError};
use crate::model::Model;
use crate::scenario::modes::Mode;
use crate::scenario::reference::JointReference;

/// What a controller commands at one instant.
#[derive(Debug, Clone, PartialEq)]
pub struct Command {
    /// Joint torques (forces for prismatic joints), length N, dof order.
    pub tau: Vec<f64>,
    /// Base wrench `[F0; N0]` in 𝒥 at the base CM.
    pub base_wrench: Vector6<f64>,
    /// The controller's reference at this instant (see [`Controller::reference_len`]).
    pub reference: Vec<f64>,
    /// Tracking error (see [`Controller::tracking`]); NaN if the controller tracks nothing.
    pub tracking_error: f64,
    /// Attitude error angle of the base, rad (attitude control); NaN otherwise.
    pub attitude_error: f64,
    /// An optimizing law's last solve (see [`Controller::reports_solve`]); NaNs otherwise.
    pub solve: SolveReport,
}

/// What an optimizing law (model-predictive control, [`super::mpc`]) reports of the solve that
/// gave the command it holds: recorded per sample (`solve_time`, `solve_iterations`,
/// `solve_cost`, `solve_converged`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveReport {
    /// Wall-clock time of the solve, s (the one record that differs from run to run).
    pub time: f64,
    /// Iterations of the solver.
    pub iterations: f64,
    /// The optimal cost found.
    pub cost: f64,
    /// 1 if the solver converged, 0 if it stopped at a limit.
    pub converged: f64,
}

impl SolveReport {
    /// No solve: NaNs.
    pub const NONE: SolveReport = SolveReport { time: f64::NAN, iterations: f64::NAN, cost: f64::NAN, converged: f64::NAN };
}

impl Command {
    /// A zero command for `n_dof` joints and a reference of `n_ref` entries.
    pub fn new(n_dof: usize, n_ref: usize) -> Self {
        Command { tau: vec![0.0; n_dof], base_wrench: Vector6::zeros(), reference: vec![0.0; n_ref], tracking_error: f64::NAN, attitude_error: f64::NAN, solve: SolveReport::NONE }
    }

    /// Zero torques and wrench (the reference and errors are overwritten by the controller).
    pub fn clear(&mut self) {
        self.tau.fill(0.0);
        self.base_wrench = Vector6::zeros();
        self.tracking_error = f64::NAN;
        self.attitude_error = f64::NAN;
        self.solve = SolveReport::NONE;
    }
}

/// What a tracking error measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrackingKind {
    /// `|q_ref − q|` over the arm joints (rad, or m for prismatic joints).
    Joint,
    /// `|p_ref − p|` of the controlled point, m.
    Cartesian,
}

impl TrackingKind {
    /// `"joint"` or `"cartesian"`.
    pub fn name(self) -> &'static str {
        match self {
            TrackingKind::Joint => "joint",
            TrackingKind::Cartesian => "cartesian",
        }
    }
}

/// The farthest a point controller may end from its reference, m, while its damped least
/// squares is active, before the goal counts as unreachable ([`GoalReport::unreachable`];
/// docs/singularities.md, "Goals out of reach").
pub const GOAL_TOLERANCE: f64 = 1e-3;

/// What a controller that drives a point found at its last evaluation (the final sample of a
/// run): how far the point was from its reference and how singular the task Jacobian was.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GoalReport {
    /// `|p_ref − p|` at the last evaluation, m.
    pub distance: f64,
    /// The smallest singular value `σ_min` of the task Jacobian there (m per rad on the
    /// translational rows).
    pub sigma_min: f64,
    /// Whether the damping law was active there (`σ_min` below its threshold).
    pub damped: bool,
}

impl GoalReport {
    /// Stopped short: more than [`GOAL_TOLERANCE`] from the reference with the damping active —
    /// the arm stretched into a singularity and the damped least squares holds it there.
    pub fn unreachable(&self) -> bool {
        self.damped && !(self.distance <= GOAL_TOLERANCE)
    }
}

/// The plant and the split of its joints that a controller is set up against.
#[derive(Debug, Clone, Copy)]
pub struct ControlContext<'a> {
    /// The plant's model.
    pub plant: &'a Model,
    /// The maneuvering mode of the simulation.
    pub mode: Mode,
    /// Degrees of freedom of the reaction wheels.
    pub wheel_dofs: &'a [usize],
    /// Degrees of freedom of the arm joints (every dof that is not a wheel), ascending.
    pub arm_dofs: &'a [usize],
    /// The actuator limits the simulation applies to every command.
    pub actuators: &'a Actuators,
}

/// The words a person reads for each controller name of [`Controller::name`] (figure titles,
/// summaries): the one table of them, exported to Python as `_core.CONTROLLER_LABELS`.
pub const CONTROLLER_LABELS: &[(&str, &str)] = &[
    ("none", "no control"),
    ("joint_pd", "joint PD"),
    ("computed_torque", "computed torque"),
    ("resolved_motion_rate", "resolved motion rate (RMRC)"),
    ("attitude", "attitude control"),
    ("cmg_steering", "CMG steering"),
    ("momentum_damping", "momentum damping"),
    ("coordinated_flying", "coordinated flying"),
    ("base_thrusters", "base thrusters"),
    ("combined", "arm and base laws combined"),
    ("mpc", "model-predictive control"),
];

/// A control law evaluated inside the integration loop.
///
/// `Send`, so that a controller can move to the thread that runs its simulation (batch
/// rollouts, [`crate::sim::rollout`]); each run owns its controller, nothing is shared.
pub trait Controller: Send {
    /// Short name for the records (`"joint_pd"`, `"computed_torque"`, ...).
    fn name(&self) -> &str;

    /// Check the controller against the plant and the mode and allocate its workspaces. Called
    /// once, before the first [`Controller::command`]. The default, for a law with nothing to
    /// check or allocate (a door's callback), accepts every plant.
    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        let _ = ctx;
        Ok(())
    }

    /// A sampled law's sample: called by the loops at the start of every integrator step with
    /// the step's (accepted) state, before any evaluation of the step. A law with a sample
    /// period computes its held command here when `t` reaches a sample instant
    /// ([`super::mpc`]); a continuous-time law has nothing to do (the default).
    fn sample(&mut self, _t: f64, _x: &[f64], _u: &[f64]) -> Result<()> {
        Ok(())
    }

    /// Whether the law reports its solves ([`Command::solve`], recorded per sample).
    fn reports_solve(&self) -> bool {
        false
    }

    /// The command at `(t, x, u)`. `out` arrives cleared (zero torques and wrench) except inside
    /// [`Combined`], where the arm controller receives what the base controller commanded.
    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()>;

    /// Length of the recorded reference (0: none).
    fn reference_len(&self) -> usize {
        0
    }

    /// What the tracking error measures, if the controller tracks something.
    fn tracking(&self) -> Option<TrackingKind> {
        None
    }

    /// Whether the controller reports the base attitude error.
    fn reports_attitude_error(&self) -> bool {
        false
    }

    /// Whether the controller never applies any torque or wrench (then the floating modes also
    /// conserve the kinetic energy).
    fn is_torque_free(&self) -> bool {
        false
    }

    /// A point controller's report on its goal at the last evaluation (`None`: it drives no
    /// point through a Jacobian).
    fn goal_report(&self) -> Option<GoalReport> {
        None
    }
}

/// A borrowed controller is a controller: [`crate::sim::simulate::Plant`] owns a boxed
/// controller, and this lets it run one the caller keeps.
impl<C: Controller + ?Sized> Controller for &mut C {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        (**self).setup(ctx)
    }
    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        (**self).command(t, x, u, out)
    }
    fn sample(&mut self, t: f64, x: &[f64], u: &[f64]) -> Result<()> {
        (**self).sample(t, x, u)
    }
    fn reports_solve(&self) -> bool {
        (**self).reports_solve()
    }
    fn reference_len(&self) -> usize {
        (**self).reference_len()
    }
    fn tracking(&self) -> Option<TrackingKind> {
        (**self).tracking()
    }
    fn reports_attitude_error(&self) -> bool {
        (**self).reports_attitude_error()
    }
    fn is_torque_free(&self) -> bool {
        (**self).is_torque_free()
    }
    fn goal_report(&self) -> Option<GoalReport> {
        (**self).goal_report()
    }
}

/// No control: zero joint torques and no base wrench.
#[derive(Debug, Clone, Copy, Default)]
pub struct ZeroTorque;

impl Controller for ZeroTorque {
    fn name(&self) -> &str {
        "none"
    }
    fn command(&mut self, _t: f64, _x: &[f64], _u: &[f64], _out: &mut Command) -> Result<()> {
        Ok(())
    }
    fn is_torque_free(&self) -> bool {
        true
    }
}

/// A base controller and an arm controller together: the base controller runs first (wheel
/// torques or base wrench), then the arm controller with that command in view.
///
/// The arm controller sees the base command as the actuators will apply it (wheel torques and
/// base wrench clamped to their torque, speed and thruster limits): a computed-torque arm
/// controller then compensates the coupling of what the wheels actually do, so the arm keeps
/// tracking while the wheels saturate. The command returned is still the unclamped one, so the
/// simulation records `tau_cmd` and the saturation events as they happen.
pub struct Combined {
    /// The controller of the arm joints.
    pub arm: Box<dyn Controller>,
    /// The controller of the base (wheels or base wrench).
    pub base: Box<dyn Controller>,
    base_cmd: Command,
    arm_dofs: Vec<usize>,
    actuators: Option<Actuators>,
    commanded_tau: Vec<f64>,
    flags: Vec<u8>,
}

impl Combined {
    /// Combine an arm controller and a base controller.
    pub fn new(arm: Box<dyn Controller>, base: Box<dyn Controller>) -> Self {
        Combined {
            arm,
            base,
            base_cmd: Command::new(0, 0),
            arm_dofs: Vec::new(),
            actuators: None,
            commanded_tau: Vec::new(),
            flags: Vec::new(),
        }
    }
}

impl Controller for Combined {
    fn name(&self) -> &str {
        "combined"
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        self.arm.setup(ctx)?;
        self.base.setup(ctx)?;
        self.base_cmd = Command::new(ctx.plant.n_dof(), self.base.reference_len());
        self.arm_dofs = ctx.arm_dofs.to_vec();
        self.actuators = Some(ctx.actuators.clone());
        self.commanded_tau = vec![0.0; ctx.plant.n_dof()];
        self.flags = vec![0; ctx.plant.n_dof() + 6];
        Ok(())
    }

    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        self.base_cmd.clear();
        self.base.command(t, x, u, &mut self.base_cmd)?;
        // The base controller owns the wheels and the base wrench; the arm joints are the arm
        // controller's.
        out.tau.copy_from_slice(&self.base_cmd.tau);
        for &d in &self.arm_dofs {
            out.tau[d] = 0.0;
        }
        out.base_wrench = self.base_cmd.base_wrench;
        // Show the arm controller the base command as it will be applied (see the type's docs).
        if let Some(actuators) = &self.actuators {
            self.commanded_tau.copy_from_slice(&out.tau);
            actuators.saturate_joints(&mut out.tau, &u[6..], &mut self.flags);
            actuators.saturate_thrusters(&mut out.base_wrench, &mut self.flags[..6]);
        }
        self.arm.command(t, x, u, out)?;
        if self.actuators.is_some() {
            // Hand back the base controller's unclamped command: the loop clamps it to the same
            // values and records the saturation.
            for (d, &tau) in self.commanded_tau.iter().enumerate() {
                if !self.arm_dofs.contains(&d) {
                    out.tau[d] = tau;
                }
            }
            out.base_wrench = self.base_cmd.base_wrench;
        }
        let n_arm = self.arm.reference_len();
        out.reference[n_arm..].copy_from_slice(&self.base_cmd.reference);
        out.attitude_error = self.base_cmd.attitude_error;
        if self.base.reports_solve() && !self.arm.reports_solve() {
            out.solve = self.base_cmd.solve;
        }
        if self.arm.tracking().is_none() {
            out.tracking_error = self.base_cmd.tracking_error;
        }
        Ok(())
    }

    /// The arm's reference followed by the base's.
    fn reference_len(&self) -> usize {
        self.arm.reference_len() + self.base.reference_len()
    }

    /// The arm's tracking, else the base's.
    fn tracking(&self) -> Option<TrackingKind> {
        self.arm.tracking().or(self.base.tracking())
    }

    fn reports_attitude_error(&self) -> bool {
        self.base.reports_attitude_error()
    }

    /// Both sample (the base first); the arm's solves are recorded, else the base's.
    fn sample(&mut self, t: f64, x: &[f64], u: &[f64]) -> Result<()> {
        self.base.sample(t, x, u)?;
        self.arm.sample(t, x, u)
    }

    fn reports_solve(&self) -> bool {
        self.arm.reports_solve() || self.base.reports_solve()
    }

    /// The arm's report, else the base's.
    fn goal_report(&self) -> Option<GoalReport> {
        self.arm.goal_report().or(self.base.goal_report())
    }
}

/// Gains given as one value (broadcast) or one per arm joint; each finite and ≥ 0.
pub fn broadcast_gains(what: &str, gains: &[f64], n: usize) -> Result<Vec<f64>> {
    if let Some(g) = gains.iter().find(|g| !(g.is_finite() && **g >= 0.0)) {
        return Err(SpacearmError::argument(format!("{what} must be finite and >= 0, got {g}")));
    }
    match gains.len() {
        1 => Ok(vec![gains[0]; n]),
        len if len == n => Ok(gains.to_vec()),
        len => Err(SpacearmError::Dimension { what: what.into(), expected: format!("1 or the number of arm joints {n}"), got: len }),
    }
}

/// A scalar gain: finite and > 0.
pub fn positive(what: &str, v: f64) -> Result<f64> {
    if !(v.is_finite() && v > 0.0) {
        return Err(SpacearmError::argument(format!("{what} must be finite and > 0, got {v}")));
    }
    Ok(v)
}

/// Solve `A z = b` in place for a symmetric positive definite `A` (n×n, column-major, only the
/// lower triangle read, overwritten by its Cholesky factor); `b` becomes `z`. Allocation-free,
/// for the small systems of the controllers. Returns `false` if `A` is not positive definite.
pub fn cholesky_solve_in_place(a: &mut [f64], n: usize, b: &mut [f64]) -> bool {
    for j in 0..n {
        let mut d = a[j + j * n];
        for k in 0..j {
            d -= a[j + k * n] * a[j + k * n];
        }
        if !(d > 0.0) {
            return false;
        }
        let d = d.sqrt();
        a[j + j * n] = d;
        for i in j + 1..n {
            let mut s = a[i + j * n];
            for k in 0..j {
                s -= a[i + k * n] * a[j + k * n];
            }
            a[i + j * n] = s / d;
        }
    }
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= a[i + k * n] * b[k];
        }
        b[i] = s / a[i + i * n];
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= a[k + i * n] * b[k];
        }
        b[i] = s / a[i + i * n];
    }
    true
}

/// The arm joints: every dof not in `wheels`, ascending.
pub fn arm_dofs(n_dof: usize, wheels: &[usize]) -> Vec<usize> {
    (0..n_dof).filter(|d| !wheels.contains(d)).collect()
}

/// The arm dofs of `ctx` split into the actuated ones and the passive ones (the plant's
/// `actuated` flags), each ascending.
pub fn split_passive(ctx: &ControlContext<'_>) -> (Vec<usize>, Vec<usize>) {
    let dynamics = ctx.plant.dof_dynamics();
    ctx.arm_dofs.iter().partition(|&&d| dynamics[d].actuated)
}

/// Refuse the simulation mode of `ctx` unless `ok`: "`needs`, but the simulation mode is '…'".
pub(crate) fn require_mode(ctx: &ControlContext<'_>, ok: bool, needs: &str) -> Result<()> {
    if ok {
        return Ok(());
    }
    Err(SpacearmError::argument(format!("{needs}, but the simulation mode is '{}'", ctx.mode.name())))
}

/// The base-thruster axes the mode of `ctx` opens, `(force, torque)`; a mode with neither (not
/// a flying mode) is refused with "`who` needs a flying mode …".
pub(crate) fn thruster_axes(ctx: &ControlContext<'_>, who: &str) -> Result<(bool, bool)> {
    let (force, torque) = (ctx.mode.allows_force(), ctx.mode.allows_torque());
    require_mode(ctx, force || torque, &format!("{who} needs a flying mode ('rotation-flying', 'translation-flying' or 'flying')"))?;
    Ok((force, torque))
}

/// Refuse a controller's own `model` (described as `what`) whose joint dofs differ from the
/// plant's.
pub(crate) fn check_model_dofs(what: &str, model: &Model, ctx: &ControlContext<'_>) -> Result<()> {
    if model.n_dof() != ctx.plant.n_dof() {
        return Err(SpacearmError::argument(format!(
            "{what} '{}' has {} joint dofs but the plant '{}' has {}",
            model.name(),
            model.n_dof(),
            ctx.plant.name(),
            ctx.plant.n_dof()
        )));
    }
    Ok(())
}

/// Check that a joint reference has `n_arm` entries: the arm joints less `n_passive` passive
/// ones (which no arm controller commands).
pub(crate) fn check_len(reference: &JointReference, n_arm: usize, n_passive: usize, ctx: &ControlContext<'_>) -> Result<()> {
    if reference.len() != n_arm {
        let mut less = vec![];
        if !ctx.wheel_dofs.is_empty() {
            less.push(format!("{} reaction wheels", ctx.wheel_dofs.len()));
        }
        if n_passive > 0 {
            less.push(format!("{n_passive} passive joints"));
        }
        let note = if less.is_empty() { String::new() } else { format!(" (N = {} minus {})", ctx.plant.n_dof(), less.join(" and ")) };
        let what = if n_passive > 0 { "actuated arm joints" } else { "arm joints" };
        return Err(SpacearmError::Dimension { what: "the joint reference".into(), expected: format!("the number of {what} {n_arm}{note}"), got: reference.len() });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_cholesky_solves_spd_systems() {
        let m = nalgebra::Matrix3::new(4.0, 1.0, -0.5, 1.0, 3.0, 0.2, -0.5, 0.2, 2.0);
        let b = nalgebra::Vector3::new(1.0, -2.0, 0.5);
        let mut a = m.as_slice().to_vec();
        let mut z = b.as_slice().to_vec();
        assert!(cholesky_solve_in_place(&mut a, 3, &mut z));
        let expect = m.lu().solve(&b).unwrap();
        for i in 0..3 {
            assert!((z[i] - expect[i]).abs() < 1e-14);
        }
        let mut bad = vec![1.0, 2.0, 2.0, 1.0];
        assert!(!cholesky_solve_in_place(&mut bad, 2, &mut [1.0, 1.0]));
    }

    #[test]
    fn gains_broadcast_or_match() {
        assert_eq!(broadcast_gains("kp", &[2.0], 3).unwrap(), vec![2.0; 3]);
        assert!(broadcast_gains("kp", &[1.0, 2.0], 3).is_err());
        assert!(broadcast_gains("kp", &[-1.0], 3).is_err());
        assert!(positive("gain", 0.0).is_err());
    }
}
