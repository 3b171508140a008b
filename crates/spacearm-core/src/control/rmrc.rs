//! Resolved-motion-rate control of a point through the Generalized Jacobian `J*` (paper eqs.
//! 109–111; Whitney 1969; Umetani & Yoshida 1989), with damped least squares near singularities.
//!
//! The point's velocity is `v = J*_T q̇ + v_drift` (translational rows of `J*`; `v_drift` the
//! linear part of `J_0X H0⁻¹ M0`, the motion that the system momentum `M0` produces, eq. 109
//! generalized to `M0 ≠ 0`, plus the wheels' `J*_W q̇_W`). The arm's joint-rate command is
//! `q̇_cmd = Jᵀ (J Jᵀ + λ² E)⁻¹ (ṗ_ref + K (p_ref − p) − v_drift)` with `J` the columns of
//! `J*_T` of the arm joints. The reference is a [`PointReference`]: a straight line, or a point
//! on a tumbling free body (the grasp point of a capture target). An optional rate cap scales
//! `q̇_cmd` as a whole so that its largest entry is at most `max_joint_rate` (the direction of
//! the point's motion is kept). The damping follows the singular values `σᵢ` of `J` (Nakamura &
//! Hanafusa 1986; Chiaverini 1997), applied per singular direction (the one damped inverse, [`crate::math::dls`]):
//! `λ²(σ) = λ_max² (1 − (σ/ε)²)` for `σ < ε`, `0` otherwise — the exact pseudo-inverse away from
//! singularities, bounded joint rates near them, and no damping of the directions that are
//! well conditioned (a planar arm keeps exact tracking in its plane although `J` has rank 2). The joints follow `q̇_cmd` through the
//! reduced EOM (a computed-torque velocity loop): `τ = H* K_v (q̇_cmd − q̇) + c*`.

use nalgebra::{Matrix3, Vector3};

use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::gjm::{compute_generalized_jacobian, momentum_twist};
use crate::algorithms::kinematics::{check_body, point_position};
use crate::model::Model;
use crate::algorithms::momentum::momentum;
use crate::math::dls::{damped_gram_solve, DampingLaw};
use crate::sim::reference::PointReference;

use super::computed_torque::ReducedInverseDynamics;
use super::{positive, Command, ControlContext, Controller, TrackingKind};

/// Resolved-motion-rate control along a Cartesian line.
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
    model: Option<Model>,
    data: Option<Data>,
    inner: Option<ReducedInverseDynamics>,
    arm: Vec<usize>,
    wheels: Vec<usize>,
    qdd_cmd: Vec<f64>,
    /// Damping λ² of the last evaluation (for tests and diagnostics).
    pub last_damping_sq: f64,
}

impl ResolvedMotionRate {
    /// `gain` K (1/s, > 0), `damping` λ_max (≥ 0), `threshold` ε (> 0), `velocity_gain` K_v
    /// (1/s, > 0); the controlled point is fixed to `body` at `offset` (body frame).
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
            model: None,
            data: None,
            inner: None,
            arm: vec![],
            wheels: vec![],
            qdd_cmd: vec![],
            last_damping_sq: 0.0,
        }
    }

    /// Cap the joint-rate command: `q̇_cmd` is scaled as a whole so that `max |q̇_cmd,i| ≤
    /// max_joint_rate` (rad/s or m/s, > 0; infinity: no cap, the default).
    pub fn with_max_joint_rate(mut self, max_joint_rate: f64) -> Self {
        self.max_joint_rate = max_joint_rate;
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
        if ctx.arm_dofs.is_empty() {
            return Err(SpacearmError::argument("resolved-motion-rate control needs at least one arm joint"));
        }
        let model = ctx.plant.clone();
        self.data = Some(Data::new(&model));
        self.inner = Some(ReducedInverseDynamics::new(model.clone(), ctx)?);
        self.model = Some(model);
        self.arm = ctx.arm_dofs.to_vec();
        self.wheels = ctx.wheel_dofs.to_vec();
        self.qdd_cmd = vec![0.0; self.arm.len()];
        Ok(())
    }

    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        let (Some(model), Some(data), Some(inner)) = (self.model.as_ref(), self.data.as_mut(), self.inner.as_mut()) else {
            return Err(SpacearmError::Simulation("resolved-motion-rate control used before setup".into()));
        };
        let (p_ref, v_ref, _) = self.reference.eval(t)?;
        // Drift: the point velocity from the system momentum (J_0X H0⁻¹ M0) and the wheels.
        let m = momentum(model, data, x, u)?;
        let twist = momentum_twist(model, data, x, self.body, &self.offset, &m.linear, &m.angular_about_origin)?;
        let mut drift = Vector3::new(twist[0], twist[1], twist[2]);
        let js = compute_generalized_jacobian(model, data, x, self.body, &self.offset)?;
        for &w in &self.wheels {
            drift += Vector3::new(js[(0, w)], js[(1, w)], js[(2, w)]) * u[6 + w];
        }
        let p = point_position(data, self.body, &self.offset);
        let js = &data.generalized_jacobian;
        let v_cmd = v_ref + (p_ref - p) * self.gain - drift;
        let mut jjt = Matrix3::zeros();
        for &d in &self.arm {
            let c = Vector3::new(js[(0, d)], js[(1, d)], js[(2, d)]);
            jjt += c * c.transpose();
        }
        let law = DampingLaw { threshold: self.threshold, max_damping: self.damping };
        let (z, lambda_sq) = damped_gram_solve(&jjt, &v_cmd, &law);
        self.last_damping_sq = lambda_sq;
        let mut peak = 0.0_f64;
        for (i, &d) in self.arm.iter().enumerate() {
            self.qdd_cmd[i] = js[(0, d)] * z.x + js[(1, d)] * z.y + js[(2, d)] * z.z;
            peak = peak.max(self.qdd_cmd[i].abs());
        }
        // The rate cap scales the command as a whole, so the point still heads for the reference.
        let scale = if peak > self.max_joint_rate { self.max_joint_rate / peak } else { 1.0 };
        for (i, &d) in self.arm.iter().enumerate() {
            self.qdd_cmd[i] = self.velocity_gain * (scale * self.qdd_cmd[i] - u[6 + d]);
        }
        inner.arm_torques(x, u, &self.qdd_cmd, out)?;
        out.reference[..3].copy_from_slice(p_ref.as_slice());
        out.tracking_error = (p_ref - p).norm();
        Ok(())
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
    use crate::sim::reference::CartesianLine;

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
}
