//! Resolved-motion-rate control (Whitney 1969) of a point of a free-floating system through the
//! Generalized Jacobian `J*` (Umetani & Yoshida 1989), with damped least squares near dynamic
//! singularities and redundancy resolution in the null space of the task:
//!
//! 1. primary task — the task rows of the point twist follow `v_d = ṗ_d + K (p_d − p)` (linear
//!    rows; `p_d(t)` a quintic straight line from the start to the target) and `K e_R` (angular
//!    rows; `e_R` the rotation vector of `R_d Rᵀ`, `R_d` the point's initial orientation);
//!    `q̇₁ = P Ĵ⁺_λ v_d` with `Ĵ = J P`, where `J` is the m×N task Jacobian, `P = E` or, for
//!    [`Strategy::Reactionless`], the projector onto the reaction null space
//!    ([`super::reaction_null_space`]): then `ω0 = 0` exactly and the base attitude is not
//!    disturbed (Nenchev et al. 1999). `Ĵ⁺_λ` is the damped least-squares inverse of
//!    [`crate::math::dls`], each singular direction damped by the law `λ(σᵢ)` of
//!    [`DampingLaw`] (the reported damping is the largest, `λ(σ_min)`);
//! 2. [`Strategy::MinimumBaseDisturbance`] — the base angular velocity as a second-priority
//!    task (Nakamura, Hanafusa & Yoshikawa 1987 task priority; Yoshida & Nenchev 1995):
//!    `q̇₂ = N₁ (Ω N₁)⁺ (−Ω q̇₁)` with `Ω` the angular rows of `−H0⁻¹ H0m` and `N₁ = P − Ĵ⁺Ĵ`;
//!    it removes as much base rotation as the task's null space allows (the inverse of `Ω N₁`
//!    is damped like the primary one, with `ε = λ_max = 0.01 σ_max(Ω N₁)`, so that base rotations
//!    the null space can hardly reach are reduced rather than chased with unbounded rates);
//! 3. gradient objectives projected into the remaining null space `N`: `q̇₃ = N z`,
//!    `z = k_w ∇w(q) + k_l ∇h(q)`, with `w` the manipulability `Π σᵢ` of the task rows of `J*`
//!    (singularity avoidance, gradient by central differences) and
//!    `h = −½ Σ ((qᵢ − q̄ᵢ)/(q_max,i − q_min,i))²` over the joints with finite limits
//!    (joint-limit avoidance, Liégeois 1977).
//!
//! Velocity limits: the null-space part is shortened first so that the task is kept; only if
//! the task alone exceeds a limit is the whole `q̇` scaled down (direction kept).
//! The closed loop is integrated with the free-floating kinematics of
//! [`super::free_floating_kinematics`] (zero momentum).

use nalgebra::{DMatrix, DVector, Matrix3, Rotation3, UnitQuaternion, Vector3, Vector6};

use super::free_floating_kinematics::{attitude_change, integrate_feedback, ConservedMomentum};
use super::reaction_null_space::null_space_of;
use crate::math::dls::DampingLaw;
use super::{dls_from_svd, Svd, Task};
use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::gjm::compute_generalized_jacobian;
use crate::algorithms::kinematics::{check_body, point_position, split_configuration};
use crate::model::Model;

/// How the primary task treats the base.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strategy {
    /// Plain (damped) pseudo-inverse of the task rows of `J*`: the base rotates as it may.
    Naive,
    /// Task restricted to the reaction null space: zero base angular velocity.
    Reactionless,
    /// Task first, then as little base angular velocity as its null space allows.
    MinimumBaseDisturbance,
}

/// Options of the resolved-motion-rate controller.
#[derive(Debug, Clone)]
pub struct RmrcOptions {
    /// Rows of the point twist that the task controls.
    pub task: Task,
    /// Damping law of the DLS inverse near singularities.
    pub damping: DampingLaw,
    /// Feedback gain `K` on the task error, 1/s.
    pub feedback_gain: f64,
    /// Treatment of the base.
    pub strategy: Strategy,
    /// Gain `k_w` of manipulability ascent in the null space (0: off).
    pub manipulability_gain: f64,
    /// Gain `k_l` of joint-limit avoidance in the null space (0: off).
    pub joint_limit_gain: f64,
}

impl RmrcOptions {
    fn check(&self) -> Result<()> {
        for (what, v) in [("feedback gain", self.feedback_gain), ("manipulability gain", self.manipulability_gain), ("joint-limit gain", self.joint_limit_gain)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SpacearmError::InvalidArgument(format!("the {what} must be finite and >= 0, got {v}")));
            }
        }
        Ok(())
    }
}

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

/// Manipulability `Π σᵢ` of the task rows of `J*` at `x`.
fn manipulability(model: &Model, data: &mut Data, x: &[f64], body: usize, offset: &Vector3<f64>, task: &Task) -> Result<f64> {
    let j = task.select(compute_generalized_jacobian(model, data, x, body, offset)?);
    Ok(Svd::new(&j)?.singular_values.iter().product())
}

/// Joint rates that realise the desired point twist `desired` (6 values; only the task rows are
/// used) at configuration `x`, with the null-space objectives of `options` (module docs).
pub fn rmrc_rates(model: &Model, data: &mut Data, x: &[f64], body: usize, offset: &Vector3<f64>, desired: &Vector6<f64>, options: &RmrcOptions) -> Result<RmrcRates> {
    options.check()?;
    let n = model.n_dof();
    let task = &options.task;
    let j = task.select(compute_generalized_jacobian(model, data, x, body, offset)?);
    let base_map = super::reaction_null_space::base_twist_map(model, data, x)?;
    let omega_map = base_map.rows(3, 3).into_owned();
    let v = DVector::from_fn(task.len(), |i, _| desired[task.rows()[i]]);
    let projector = match options.strategy {
        Strategy::Reactionless => null_space_of(omega_map.clone(), 1e-9)?.projector,
        _ => DMatrix::identity(n, n),
    };
    let jp = &j * &projector;
    let svd = Svd::new(&jp)?;
    let sigma_min = svd.sigma_min();
    let lambda = options.damping.damping(sigma_min);
    let primary = &projector * dls_from_svd(&svd, &options.damping) * &v;
    let mut qd = primary.clone();
    // Null space of the primary task within range(P): N₁ = P − Ĵ⁺Ĵ (undamped, rank-cut).
    let jp_pinv = dls_from_svd(&svd, &DampingLaw::none());
    let mut null = &projector - &jp_pinv * &jp;
    if options.strategy == Strategy::MinimumBaseDisturbance {
        let on = &omega_map * &null;
        let svd2 = Svd::new(&on)?;
        // Damped inverse of Ω N₁ (law of module docs with ε = λ_max = 0.01 σ_max(Ω N₁)): base
        // rotations the null space can barely reach are reduced, not chased with huge rates.
        // Damped per direction, structural zeros (e.g. the in-plane rows of Ω for a planar arm)
        // are dropped by the rank cut and do not damp the other directions.
        let scale = svd2.sigma_max();
        let law = if scale > 0.0 { DampingLaw { threshold: 0.01 * scale, max_damping: 0.01 * scale } } else { DampingLaw::none() };
        let on_pinv = dls_from_svd(&svd2, &law);
        let on_pinv_exact = dls_from_svd(&svd2, &DampingLaw::none());
        qd += &null * &on_pinv * (-(&omega_map * &qd));
        null = &null * (DMatrix::identity(n, n) - &on_pinv_exact * &on);
    }
    if options.manipulability_gain > 0.0 || options.joint_limit_gain > 0.0 {
        let mut z = DVector::zeros(n);
        if options.manipulability_gain > 0.0 {
            let h = 1e-6;
            let mut xp = x.to_vec();
            for i in 0..n {
                xp[7 + i] = x[7 + i] + h;
                let up = manipulability(model, data, &xp, body, offset, task)?;
                xp[7 + i] = x[7 + i] - h;
                let down = manipulability(model, data, &xp, body, offset, task)?;
                xp[7 + i] = x[7 + i];
                z[i] += options.manipulability_gain * (up - down) / (2.0 * h);
            }
        }
        if options.joint_limit_gain > 0.0 {
            for i in 0..n {
                let lim = model.links()[model.body_of_dof(i) - 1].joint.limits;
                if lim.lower.is_finite() && lim.upper.is_finite() && lim.upper > lim.lower {
                    let range = lim.upper - lim.lower;
                    let mid = 0.5 * (lim.upper + lim.lower);
                    z[i] -= options.joint_limit_gain * (x[7 + i] - mid) / (range * range);
                }
            }
        }
        qd += &null * z;
    }
    // Velocity limits: first shorten the null-space part (largest α ∈ [0, 1] with
    // |q̇₁ + α q̇ₙ| within the limits), which keeps the task; if the task alone is too fast,
    // scale it down as a whole (direction kept).
    let secondary = &qd - &primary;
    let mut alpha: f64 = 1.0;
    let mut scale: f64 = 1.0;
    for i in 0..n {
        let vmax = model.links()[model.body_of_dof(i) - 1].joint.limits.velocity;
        if !vmax.is_finite() {
            continue;
        }
        if primary[i].abs() > vmax {
            scale = scale.min(vmax / primary[i].abs());
        }
        let (p, d) = (primary[i], secondary[i]);
        if (p + d).abs() > vmax && d != 0.0 {
            // |p + α d| ≤ vmax on the side d pushes towards.
            let bound = if d > 0.0 { (vmax - p) / d } else { (-vmax - p) / d };
            alpha = alpha.min(bound.max(0.0));
        }
    }
    let qd = if scale < 1.0 { primary * scale } else { primary + secondary * alpha };
    let base_angular_velocity = Vector3::from_iterator((&omega_map * &qd).iter().copied());
    Ok(RmrcRates { qd, sigma_min, damping: lambda, base_angular_velocity })
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

/// Quintic time scaling `s(τ) = 10τ³ − 15τ⁴ + 6τ⁵` and its derivative (per second).
fn quintic(t: f64, duration: f64) -> (f64, f64) {
    let tau = (t / duration).clamp(0.0, 1.0);
    let s = tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
    let ds = if t >= duration { 0.0 } else { 30.0 * tau * tau * (1.0 - tau) * (1.0 - tau) / duration };
    (s, ds)
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
    crate::algorithms::kinematics::forward_kinematics(model, data, x0)?;
    let start = point_position(data, body, offset);
    let rot_d: Matrix3<f64> = data.body_to_world[body];
    let k = options.feedback_gain;
    let desired_at = |t: f64, data: &Data| -> Vector6<f64> {
        let (s, ds) = quintic(t, duration);
        let p_d = start + s * (target - start);
        let p = point_position(data, body, offset);
        let lin = ds * (target - start) + k * (p_d - p);
        let err = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(rot_d * data.body_to_world[body].transpose())).scaled_axis();
        let ang = k * err;
        Vector6::new(lin.x, lin.y, lin.z, ang.x, ang.y, ang.z)
    };
    let law = |t: f64, x: &[f64], data: &mut Data| -> Result<RmrcRates> {
        crate::algorithms::kinematics::forward_kinematics(model, data, x)?;
        let desired = desired_at(t, data);
        rmrc_rates(model, data, x, body, offset, &desired, options)
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
        crate::algorithms::kinematics::forward_kinematics(model, data, &x)?;
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
    use crate::model::presets;

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

    #[test]
    fn reactionless_rates_do_not_rotate_the_base() {
        let m = presets::planar4();
        let mut d = Data::new(&m);
        let x = presets::initial_configuration(&m);
        let ee = m.points()[m.end_effector().unwrap()].clone();
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
        let m = presets::planar4();
        let mut d = Data::new(&m);
        let x0 = presets::initial_configuration(&m);
        let ee = m.points()[m.end_effector().unwrap()].clone();
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
