//! Kinematics of free-floating motion: the base pose that follows from prescribed joint motion
//! when the system's momentum is conserved.
//!
//! With no external wrench the linear momentum `P` and the angular momentum `L` about the origin
//! of 𝒥 are constant, so at every instant the base twist is fixed by the joint rates through the
//! momentum map `ẋ0 = H0⁻¹ (M0 − H0m q̇)` (paper eqs. 43, 109; [`crate::gjm::base_velocity_from_momentum`]).
//! Integrating it is therefore an exact consequence of momentum conservation, not an
//! approximation of the dynamics: whatever joint torques produce a joint trajectory `q(t)`,
//! the base of a free-floating system moves as computed here (with zero initial momentum:
//! `P = L = 0`). No joint torques or forces are needed, and none are computed.
//!
//! State: `r0` and the unit quaternion of the base (`[x, y, z, w]`, Hamilton), integrated with
//! the classical fourth-order Runge–Kutta method; `ṙ0 = v0` and, with `ω0` in 𝒥,
//! `q̇uat = ½ [ω0; 0] ⊗ quat`. The quaternion is renormalized after every step (and the
//! intermediate stage quaternions before they are used).

use nalgebra::{DVector, UnitQuaternion, Vector3, Vector6};

use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::gjm::base_velocity_from_momentum;
use crate::algorithms::kinematics::split_configuration;
use crate::math::rotations::{normalize_xyzw, quaternion_from_xyzw, quaternion_rate};
use crate::model::Model;
use crate::math::integrate::{OdeSystem, Rk4};

/// Conserved momenta of the free-floating system: linear momentum `P` and angular momentum
/// about the origin of 𝒥. `Default` is zero momentum (a system that starts at rest).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ConservedMomentum {
    /// `P`, N·s.
    pub linear: Vector3<f64>,
    /// `L_origin`, N·m·s.
    pub angular_about_origin: Vector3<f64>,
}

/// Time derivative of `[r0, quat]` (7 values) for base twist `[v0; ω0]` (both in 𝒥).
fn base_pose_rate(quat: &[f64], twist: &Vector6<f64>) -> [f64; 7] {
    let d = quaternion_rate(quat, &Vector3::new(twist[3], twist[4], twist[5]));
    [twist[0], twist[1], twist[2], d[0], d[1], d[2], d[3]]
}

/// Normalize the base quaternion `x[3..7]` of a configuration.
fn normalize_quaternion(x: &mut [f64]) {
    normalize_xyzw(&mut x[3..7]);
}

/// The configuration `x = [r0, quat, q]` of a free-floating system as an ODE for the
/// simulator's [`Rk4`] (the one RK4 with quaternion projection of the crate): `ṙ0, quaṫ` from
/// the base twist that conserves `momentum`, `q̇` from `joint_rates(stage, x_stage, data)`, and,
/// for prescribed joint motion, `q` at each stage replaced by `joint_positions(stage)`.
/// [`Rk4::step`] evaluates its four stages in order (0 at `t`, 1 and 2 at `t + dt/2`, 3 at
/// `t + dt`), which `stage` counts.
struct FreeFloating<'a, F, G> {
    model: &'a Model,
    data: &'a mut Data,
    momentum: &'a ConservedMomentum,
    joint_rates: F,
    joint_positions: G,
    stage: usize,
    x_stage: Vec<f64>,
}

impl<F, G> OdeSystem for FreeFloating<'_, F, G>
where
    F: FnMut(usize, &[f64], &mut Data) -> Result<DVector<f64>>,
    G: Fn(usize) -> Option<Vec<f64>>,
{
    fn dim(&self) -> usize {
        7 + self.model.n_dof()
    }

    fn project(&self, x: &mut [f64]) {
        normalize_quaternion(x);
    }

    fn rhs(&mut self, _t: f64, x: &[f64], dx: &mut [f64]) -> Result<()> {
        let s = self.stage;
        self.stage = (s + 1) % 4;
        self.x_stage.copy_from_slice(x);
        if let Some(q) = (self.joint_positions)(s) {
            self.x_stage[7..].copy_from_slice(&q);
        }
        let qd = (self.joint_rates)(s, &self.x_stage, self.data)?;
        let m = self.momentum;
        let twist = base_velocity_from_momentum(self.model, self.data, &self.x_stage, qd.as_slice(), &m.linear, &m.angular_about_origin)?;
        dx[..7].copy_from_slice(&base_pose_rate(&self.x_stage[3..7], &twist));
        dx[7..].copy_from_slice(qd.as_slice());
        Ok(())
    }
}

/// One RK4 step of the whole configuration `x = [r0, quat, q]` over `dt` ([`FreeFloating`]).
fn rk4_step<F, G>(model: &Model, data: &mut Data, x: &mut [f64], dt: f64, momentum: &ConservedMomentum, joint_rates: F, joint_positions: G) -> Result<()>
where
    F: FnMut(usize, &[f64], &mut Data) -> Result<DVector<f64>>,
    G: Fn(usize) -> Option<Vec<f64>>,
{
    let mut system = FreeFloating { model, data, momentum, joint_rates, joint_positions, stage: 0, x_stage: x.to_vec() };
    Rk4::new(x.len()).step(&mut system, 0.0, dt, x, false)
}

fn check_step(dt: f64) -> Result<()> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(SpacearmError::InvalidArgument(format!("the time step must be finite and > 0, got {dt}")));
    }
    Ok(())
}

/// Base motion under prescribed joint motion: `q_half` and `qd_half` hold `q` and `q̇` at the
/// `2K + 1` times `t0, t0 + dt/2, t0 + dt, …, t0 + K dt` (row-major, `(2K+1)×N`), which are
/// exactly the RK4 stage times. Returns the configurations `x` at `t0 + k dt`, `k = 0..=K`
/// (row-major `(K+1)×(7+N)`), starting from `x0` (whose `q` part must equal `q_half[0]`).
pub fn integrate_prescribed(
    model: &Model,
    data: &mut Data,
    x0: &[f64],
    dt: f64,
    q_half: &[f64],
    qd_half: &[f64],
    momentum: &ConservedMomentum,
) -> Result<Vec<f64>> {
    split_configuration(model, x0)?;
    check_step(dt)?;
    let n = model.n_dof();
    if n == 0 || !q_half.len().is_multiple_of(n) || q_half.len() / n < 3 || (q_half.len() / n).is_multiple_of(2) {
        return Err(SpacearmError::Dimension {
            what: "prescribed joint positions".into(),
            expected: format!("(2K+1)×N values with K >= 1 and N = {n} (q at every half step)"),
            got: q_half.len(),
        });
    }
    if qd_half.len() != q_half.len() {
        return Err(SpacearmError::Dimension { what: "prescribed joint rates".into(), expected: format!("{} (same as the joint positions)", q_half.len()), got: qd_half.len() });
    }
    crate::error::check_finite("prescribed joint positions", q_half)?;
    crate::error::check_finite("prescribed joint rates", qd_half)?;
    let mismatch = x0[7..].iter().zip(&q_half[..n]).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    if mismatch > 1e-9 * (1.0 + x0[7..].iter().map(|v| v.abs()).fold(0.0, f64::max)) {
        return Err(SpacearmError::InvalidArgument(format!("x0's joint coordinates must equal the first prescribed q (largest difference {mismatch:e})")));
    }
    let steps = (q_half.len() / n - 1) / 2;
    let nx = 7 + n;
    let mut out = Vec::with_capacity((steps + 1) * nx);
    let mut x = x0.to_vec();
    normalize_quaternion(&mut x);
    out.extend_from_slice(&x);
    for k in 0..steps {
        // Stage s uses row 2k (s = 0), 2k+1 (s = 1, 2), 2k+2 (s = 3).
        let row = |s: usize| 2 * k + [0, 1, 1, 2][s];
        rk4_step(
            model,
            data,
            &mut x,
            dt,
            momentum,
            |s, _, _| Ok(DVector::from_column_slice(&qd_half[row(s) * n..(row(s) + 1) * n])),
            |s| Some(q_half[row(s) * n..(row(s) + 1) * n].to_vec()),
        )?;
        // The joints follow the prescription exactly; only the base pose is integrated.
        x[7..].copy_from_slice(&q_half[row(3) * n..(row(3) + 1) * n]);
        out.extend_from_slice(&x);
    }
    Ok(out)
}

/// Free-floating motion under joint rates given by a feedback law `joint_rates(t, x, data)`
/// (e.g. resolved-motion-rate control): `x = [r0, quat, q]` is integrated as a whole with RK4,
/// `steps` steps of `dt` from `x0`. Returns the configurations at `k dt`, `k = 0..=steps`,
/// row-major `(steps+1)×(7+N)`.
pub fn integrate_feedback<F>(model: &Model, data: &mut Data, x0: &[f64], dt: f64, steps: usize, momentum: &ConservedMomentum, mut joint_rates: F) -> Result<Vec<f64>>
where
    F: FnMut(f64, &[f64], &mut Data) -> Result<DVector<f64>>,
{
    split_configuration(model, x0)?;
    check_step(dt)?;
    let nx = 7 + model.n_dof();
    let mut out = Vec::with_capacity((steps + 1) * nx);
    let mut x = x0.to_vec();
    normalize_quaternion(&mut x);
    out.extend_from_slice(&x);
    for k in 0..steps {
        let t = k as f64 * dt;
        rk4_step(model, data, &mut x, dt, momentum, |s, xs, d| joint_rates(t + dt * [0.0, 0.5, 0.5, 1.0][s], xs, d), |_| None)?;
        out.extend_from_slice(&x);
    }
    Ok(out)
}

/// Rotation angle (rad, in [0, π]) between two base attitudes given as `[x, y, z, w]` quaternions.
pub fn attitude_change(quat_a: &[f64], quat_b: &[f64]) -> f64 {
    let a = UnitQuaternion::from_quaternion(quaternion_from_xyzw(quat_a));
    let b = UnitQuaternion::from_quaternion(quaternion_from_xyzw(quat_b));
    a.angle_to(&b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    /// Planar base + one link, zero momentum: dθ0/dq = −(I1 + μ(b² + ab cos q)) /
    /// (I0 + I1 + μ(a² + b² + 2ab cos q)) with μ = m0 m1/(m0 + m1), a the joint offset from
    /// the base CM, b the link CM from the joint (angular momentum about the system CM of a
    /// two-body system). Integrated here by composite Simpson on a fine grid.
    #[test]
    fn one_link_planar_closed_form() {
        use crate::model::joint::{JointLimits, JointType};
        use crate::model::{LinkSpec, ModelBuilder};
        let (m0, i0, m1, i1, a, b) = (50.0, 3.0, 8.0, 0.7, 0.4, 0.6);
        let mut mb = ModelBuilder::new("one", "base", m0, [[i0, 0.0, 0.0], [0.0, i0, 0.0], [0.0, 0.0, i0]]).unwrap();
        mb.add_link(LinkSpec {
            name: "l1".into(),
            parent: "base".into(),
            joint_name: None,
            kind: JointType::Revolute,
            origin_in_parent: [a, 0.0, 0.0],
            rotation_in_parent: [0.0, 0.0, 0.0, 1.0],
            axis: [0.0, 0.0, 1.0],
            com_from_joint: [b, 0.0, 0.0],
            mass: m1,
            inertia: [[i1, 0.0, 0.0], [0.0, i1, 0.0], [0.0, 0.0, i1]],
            limits: JointLimits::unlimited(),
        })
        .unwrap();
        let model = mb.build().unwrap();
        let mut data = Data::new(&model);
        // q(t) = 2 sin(t), t in [0, 2]: K steps.
        let (k, t_end) = (400usize, 2.0);
        let dt = t_end / k as f64;
        let q: Vec<f64> = (0..=2 * k).map(|i| 2.0 * (i as f64 * dt / 2.0).sin()).collect();
        let qd: Vec<f64> = (0..=2 * k).map(|i| 2.0 * (i as f64 * dt / 2.0).cos()).collect();
        let mut x0 = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        x0[7] = q[0];
        let xs = integrate_prescribed(&model, &mut data, &x0, dt, &q, &qd, &ConservedMomentum::default()).unwrap();
        let last = &xs[xs.len() - 8..];
        let theta = 2.0 * last[5].atan2(last[6]);
        let mu = m0 * m1 / (m0 + m1);
        let f = |s: f64| -(i1 + mu * (b * b + a * b * s.cos())) / (i0 + i1 + mu * (a * a + b * b + 2.0 * a * b * s.cos()));
        let q_end = 2.0 * t_end.sin();
        let n = 2000;
        let h = q_end / n as f64;
        let mut simpson = f(0.0) + f(q_end);
        for i in 1..n {
            simpson += if i % 2 == 1 { 4.0 } else { 2.0 } * f(i as f64 * h);
        }
        let expected = simpson * h / 3.0;
        assert!(expected.abs() > 0.1, "reference is not trivial: {expected}");
        assert!((theta - expected).abs() < 1e-9, "θ0 = {theta}, closed form {expected}");
        // The system CM stays where it was (P = 0), while the base moves.
        assert!(last[0].abs() + last[1].abs() > 1e-3);
    }

    #[test]
    fn checks_inputs() {
        let m = presets::planar4();
        let mut d = Data::new(&m);
        let x0 = presets::initial_configuration(&m);
        let q: Vec<f64> = x0[7..].iter().cycle().take(12).copied().collect();
        let qd = vec![0.0; 12];
        // 3 rows = K = 1: fine.
        assert!(integrate_prescribed(&m, &mut d, &x0, 0.1, &q, &qd, &ConservedMomentum::default()).is_ok());
        assert!(integrate_prescribed(&m, &mut d, &x0, 0.1, &q[..8], &qd[..8], &ConservedMomentum::default()).is_err());
        assert!(integrate_prescribed(&m, &mut d, &x0, -0.1, &q, &qd, &ConservedMomentum::default()).is_err());
        let mut bad = q.clone();
        bad[0] += 0.5;
        assert!(integrate_prescribed(&m, &mut d, &x0, 0.1, &bad, &qd, &ConservedMomentum::default()).is_err());
    }
}
