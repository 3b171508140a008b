//! Redundancy resolution through resolved-motion-rate control (Whitney 1969) of a point of a
//! free-floating system (Umetani & Yoshida 1989): one evaluation of the law ([`rmrc_rates`]) and
//! a closed-loop point-to-point motion ([`move_to`]). Both run the one solver of
//! [`super::rmrc_solver`] (damped least squares through `J*`, the strategies towards the base,
//! the null-space objectives and the rate caps; the native controller
//! [`crate::control::ResolvedMotionRate`] runs it too), on every joint, with zero momentum and
//! the model's joint velocity limits as caps.
//!
//! [`move_to`] commands the twist `v_d = [ṗ_d + K (p_d − p); K e_R]` of
//! [`super::rmrc_solver::desired_twist`]: `p_d(t)` a straight line from the start to the target
//! with the quintic timing of [`crate::scenario::reference::quintic_scaling`] (a
//! [`CartesianLine`]), `e_R` the rotation vector of `R_d Rᵀ`, `R_d` the point's initial
//! orientation (used by angular task rows). The closed loop is integrated with the
//! free-floating kinematics of [`super::free_floating_kinematics`] (zero momentum).

use nalgebra::{DVector, Matrix3, Vector3, Vector6};

use super::free_floating_kinematics::{attitude_change, integrate_feedback, ConservedMomentum};
pub use super::rmrc_solver::{RmrcOptions, Strategy};
use super::rmrc_solver::{desired_twist, RmrcSolver};
use crate::algorithms::kinematics::{check_body, forward_kinematics, point_position, split_configuration};
use crate::error::{Result, SpacearmError};
use crate::model::data::Data;
use crate::model::Model;
use crate::scenario::reference::CartesianLine;

/// The joint rates of one controller evaluation and what the detector saw.
#[derive(Debug, Clone)]
pub struct RmrcRates {
    /// Joint rates `q̇`.
    pub qd: DVector<f64>,
    /// `σ_min` of the (projected) task Jacobian `Ĵ`.
    pub sigma_min: f64,
    /// Damping `λ` used.
    pub damping: f64,
    /// Base angular velocity `ω0` these rates produce (zero momentum), in 𝒥.
    pub base_angular_velocity: Vector3<f64>,
}

fn evaluate(solver: &mut RmrcSolver, model: &Model, data: &mut Data, x: &[f64], body: usize, offset: &Vector3<f64>, desired: &Vector6<f64>) -> Result<RmrcRates> {
    let d = solver.solve(model, data, x, None, body, offset, desired)?;
    Ok(RmrcRates {
        qd: solver.rates().clone(),
        sigma_min: d.sigma_min,
        damping: d.damping_sq.sqrt(),
        base_angular_velocity: d.base_angular_velocity.unwrap_or_else(|| Vector3::repeat(f64::NAN)),
    })
}

/// Joint rates that realise the desired point twist `desired` (6 values; only the task rows are
/// used) at configuration `x`, with the strategy and null-space objectives of `options`
/// ([`super::rmrc_solver`]; every joint, zero momentum, the model's velocity limits).
pub fn rmrc_rates(model: &Model, data: &mut Data, x: &[f64], body: usize, offset: &Vector3<f64>, desired: &Vector6<f64>, options: &RmrcOptions) -> Result<RmrcRates> {
    let mut solver = RmrcSolver::for_model(model, options.clone())?;
    evaluate(&mut solver, model, data, x, body, offset, desired)
}

/// A closed-loop point-to-point motion and its record at every time step.
#[derive(Debug, Clone)]
pub struct RmrcMotion {
    /// Times `k dt`, s.
    pub times: Vec<f64>,
    /// Configurations `x` (row-major (K+1)×(7+N)).
    pub x: Vec<f64>,
    /// Joint rates at the nodes (row-major (K+1)×N).
    pub qd: Vec<f64>,
    /// Point position in 𝒥 at the nodes ((K+1)×3).
    pub point_position: Vec<f64>,
    /// `σ_min` of the (projected) task Jacobian at the nodes.
    pub sigma_min: Vec<f64>,
    /// Damping used at the nodes.
    pub damping: Vec<f64>,
    /// Base attitude change from the start (rotation angle, rad) at the nodes.
    pub attitude_change: Vec<f64>,
    /// Distance from the target at the end, m (linear task rows only).
    pub final_position_error: f64,
}

/// Move the point fixed to `body` at `offset` from its position at `x0` to `target` (in 𝒥) along
/// a straight line with quintic timing over `duration`, holding its orientation where the task
/// has angular rows; integrated for `duration + settle` seconds with step `dt` (zero momentum).
#[allow(clippy::too_many_arguments)]
pub fn move_to(
    model: &Model,
    data: &mut Data,
    x0: &[f64],
    body: usize,
    offset: &Vector3<f64>,
    target: &Vector3<f64>,
    duration: f64,
    settle: f64,
    dt: f64,
    options: &RmrcOptions,
) -> Result<RmrcMotion> {
    options.check()?;
    split_configuration(model, x0)?;
    check_body(model, body)?;
    crate::error::check_finite("target", target.as_slice())?;
    if model.n_dof() == 0 {
        return Err(SpacearmError::InvalidModel("the model has no joints to move".into()));
    }
    for (what, v) in [("duration", duration), ("time step", dt)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(SpacearmError::InvalidArgument(format!("the {what} must be finite and > 0, got {v}")));
        }
    }
    if !(settle.is_finite() && settle >= 0.0) {
        return Err(SpacearmError::InvalidArgument(format!("the settling time must be finite and >= 0, got {settle}")));
    }
    let steps = ((duration + settle) / dt).round() as usize;
    if steps == 0 || steps > 10_000_000 {
        return Err(SpacearmError::InvalidArgument(format!("(duration + settle) / dt = {steps} steps: expected between 1 and 1e7")));
    }
    forward_kinematics(model, data, x0)?;
    let start = point_position(data, body, offset);
    let line = CartesianLine::new(start, *target, 0.0, duration)?;
    let rot_d: Matrix3<f64> = data.body_to_world[body];
    let k = options.feedback_gain;
    let mut solver = RmrcSolver::for_model(model, options.clone())?;
    let mut law = |t: f64, x: &[f64], data: &mut Data| -> Result<RmrcRates> {
        forward_kinematics(model, data, x)?;
        let (p_d, v_d, _) = line.eval(t);
        let desired = desired_twist(&p_d, &v_d, &point_position(data, body, offset), &rot_d, &data.body_to_world[body], k);
        evaluate(&mut solver, model, data, x, body, offset, &desired)
    };
    let xs = integrate_feedback(model, data, x0, dt, steps, &ConservedMomentum::default(), |t, x, d| Ok(law(t, x, d)?.qd))?;
    let nx = 7 + model.n_dof();
    let mut motion = RmrcMotion {
        times: (0..=steps).map(|i| i as f64 * dt).collect(),
        x: xs,
        qd: Vec::with_capacity((steps + 1) * model.n_dof()),
        point_position: Vec::with_capacity((steps + 1) * 3),
        sigma_min: Vec::with_capacity(steps + 1),
        damping: Vec::with_capacity(steps + 1),
        attitude_change: Vec::with_capacity(steps + 1),
        final_position_error: 0.0,
    };
    for i in 0..=steps {
        let x = motion.x[i * nx..(i + 1) * nx].to_vec();
        let r = law(motion.times[i], &x, data)?;
        forward_kinematics(model, data, &x)?;
        let p = point_position(data, body, offset);
        motion.qd.extend(r.qd.iter());
        motion.point_position.extend(p.iter());
        motion.sigma_min.push(r.sigma_min);
        motion.damping.push(r.damping);
        motion.attitude_change.push(attitude_change(&x0[3..7], &x[3..7]));
    }
    let end = &motion.point_position[steps * 3..];
    let linear_rows: Vec<usize> = options.task.rows().iter().copied().filter(|&r| r < 3).collect();
    motion.final_position_error = linear_rows.iter().map(|&r| (end[r] - target[r]).powi(2)).sum::<f64>().sqrt();
    Ok(motion)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::Task;
    use crate::gjm::compute_generalized_jacobian;
    use crate::math::dls::DampingLaw;
    use crate::model::presets;
    use crate::model::system::Point;

    fn options(strategy: Strategy) -> RmrcOptions {
        RmrcOptions {
            task: Task::planar(),
            damping: DampingLaw::new(0.05, 0.05).unwrap(),
            feedback_gain: 5.0,
            strategy,
            manipulability_gain: 0.0,
            joint_limit_gain: 0.0,
        }
    }

    /// planar4, a workspace, its initial configuration and its end effector.
    fn planar4_at_start() -> (Model, Data, Vec<f64>, Point) {
        let m = presets::planar4();
        let d = Data::new(&m);
        let x = presets::initial_configuration(&m);
        let ee = m.points()[m.end_effector().unwrap()].clone();
        (m, d, x, ee)
    }

    #[test]
    fn reactionless_rates_do_not_rotate_the_base() {
        let (m, mut d, x, ee) = planar4_at_start();
        let desired = Vector6::new(0.1, -0.05, 0.0, 0.0, 0.0, 0.0);
        let r = rmrc_rates(&m, &mut d, &x, ee.body, &ee.offset, &desired, &options(Strategy::Reactionless)).unwrap();
        assert!(r.base_angular_velocity.norm() < 1e-12);
        // The task is met: J* q̇ = desired in the task rows.
        let j = compute_generalized_jacobian(&m, &mut d, &x, ee.body, &ee.offset).unwrap().clone();
        let v = &j * &r.qd;
        assert!((v[0] - 0.1).abs() < 1e-9 && (v[1] + 0.05).abs() < 1e-9, "{v}");
        let naive = rmrc_rates(&m, &mut d, &x, ee.body, &ee.offset, &desired, &options(Strategy::Naive)).unwrap();
        assert!(naive.base_angular_velocity.norm() > 1e-3);
    }

    #[test]
    fn reactionless_motion_keeps_attitude() {
        let (m, mut d, x0, ee) = planar4_at_start();
        crate::algorithms::kinematics::forward_kinematics(&m, &mut d, &x0).unwrap();
        let p0 = point_position(&d, ee.body, &ee.offset);
        let target = p0 + Vector3::new(-0.5, 0.6, 0.0);
        let r = move_to(&m, &mut d, &x0, ee.body, &ee.offset, &target, 4.0, 1.0, 0.01, &options(Strategy::Reactionless)).unwrap();
        let n = move_to(&m, &mut d, &x0, ee.body, &ee.offset, &target, 4.0, 1.0, 0.01, &options(Strategy::Naive)).unwrap();
        assert!(r.final_position_error < 1e-3, "{}", r.final_position_error);
        assert!(n.final_position_error < 1e-3, "{}", n.final_position_error);
        let ra = r.attitude_change.iter().copied().fold(0.0, f64::max);
        let na = n.attitude_change.last().copied().unwrap();
        assert!(ra < 1e-8, "reactionless attitude change {ra}");
        assert!(na > 1e-2, "naive attitude change {na}");
    }
}
