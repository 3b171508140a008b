//! Coordinated base-and-arm control in the flying mode: an end-effector task plus base pose
//! regulation, through the flying-regime reduced EOM `H* q̈ + c* = τ − H0mᵀ H0⁻¹ F_b`
//! (docs/physics.md; the paper leaves the flying case open).
//!
//! 1. Base regulation (acceleration level): `ẍ0_des = [K_pb (r_ref − r0) − K_db v0;
//!    −K_pb e − K_db ω0]` with `e` the attitude error of [`super::attitude`].
//! 2. End-effector task: `a_des = p̈_ref + K_de (ṗ_ref − ṗ) + K_pe (p_ref − p)`. The point's
//!    acceleration is `p̈ = v̇0 + α0 × r_0X + J_mX,T q̈ + b` (`J_0X ẍ0 + J_mX q̈` plus the
//!    velocity-product term `b`, its acceleration at `u̇ = 0`), so with the base acceleration
//!    prescribed, `q̈_des = J⁺_λ (a_des − v̇0_des − α0_des × r_0X − b)` with `J = J_mX,T` (arm
//!    columns) and the damped least-squares inverse of [`crate::math::dls`] (the law of
//!    [`super::rmrc`]).
//! 3. Forces: the base wrench that produces `ẍ0_des` together with `q̈_des` comes from the base
//!    rows, `F_b = H0 ẍ0_des + H0m q̈_des + c0`, and the joint torques from the reduced EOM,
//!    `τ = H* q̈_des + c* + H0mᵀ H0⁻¹ F_b` (equal to the joint rows of `H u̇_des + c`; tested).
//!
//! With the exact model and no saturation both error dynamics are linear and decoupled
//! (`ë + K_d ė + K_p e = 0` for the end effector and for the base pose).

use nalgebra::{DMatrix, DVector, Vector3, Vector6};

use crate::algorithms::crba::crba_after_kinematics;
use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::model::joint::JointType;
use crate::algorithms::kinematics::{check_body, forward_kinematics, point_position};
use crate::model::Model;
use crate::sim::modes::Mode;
use crate::sim::reference::CartesianLine;
use crate::algorithms::rnea::rnea_after_kinematics;
use crate::math::spatial::{angular, linear};

use super::attitude::AttitudeControl;
use super::computed_torque::ReducedInverseDynamics;
use crate::math::dls::{DampingLaw, RowSvd};
use super::{positive, Command, ControlContext, Controller, TrackingKind};

/// Gains of [`CoordinatedFlying`] (acceleration level, 1/s² and 1/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoordinatedGains {
    /// End-effector position gain, 1/s².
    pub kp_ee: f64,
    /// End-effector velocity gain, 1/s.
    pub kd_ee: f64,
    /// Base pose gain, 1/s².
    pub kp_base: f64,
    /// Base velocity gain, 1/s.
    pub kd_base: f64,
}

/// Coordinated end-effector and base-pose control (flying mode).
#[derive(Debug, Clone)]
pub struct CoordinatedFlying {
    line: CartesianLine,
    body: usize,
    offset: Vector3<f64>,
    /// Base pose to hold: `(r0, quat [x, y, z, w])`; `None`: the pose at the first evaluation.
    base_ref: Option<(Vector3<f64>, [f64; 4])>,
    gains: CoordinatedGains,
    damping: f64,
    threshold: f64,
    model: Option<Model>,
    data: Option<Data>,
    attitude: Option<AttitudeControl>,
    base_position_ref: Vector3<f64>,
    inner: Option<ReducedInverseDynamics>,
    arm: Vec<usize>,
    jac: Vec<Vector3<f64>>,
    jac_arm: DMatrix<f64>,
    qdd_arm: DVector<f64>,
    svd: RowSvd,
    qdd: Vec<f64>,
}

impl CoordinatedFlying {
    /// End-effector line for the point on `body` at `offset`; base pose reference (`None`: hold
    /// the initial pose); gains; damped-least-squares `damping` and `threshold` as in
    /// [`super::ResolvedMotionRate`].
    pub fn new(
        line: CartesianLine,
        body: usize,
        offset: Vector3<f64>,
        base_ref: Option<(Vector3<f64>, [f64; 4])>,
        gains: CoordinatedGains,
        damping: f64,
        threshold: f64,
    ) -> Self {
        CoordinatedFlying {
            line,
            body,
            offset,
            base_ref,
            gains,
            damping,
            threshold,
            model: None,
            data: None,
            attitude: None,
            base_position_ref: Vector3::zeros(),
            inner: None,
            arm: vec![],
            jac: vec![],
            jac_arm: DMatrix::zeros(3, 0),
            qdd_arm: DVector::zeros(0),
            svd: RowSvd::new(0),
            qdd: vec![],
        }
    }

    fn latch_base_reference(&mut self, x: &[f64]) -> Result<()> {
        let (r, q) = match self.base_ref {
            Some(pose) => pose,
            None => (Vector3::new(x[0], x[1], x[2]), [x[3], x[4], x[5], x[6]]),
        };
        crate::error::check_finite("coordinated flying base position reference", r.as_slice())?;
        let mut att = AttitudeControl::new(q, self.gains.kp_base, self.gains.kd_base);
        att.set_reference(q)?;
        self.attitude = Some(att);
        self.base_position_ref = r;
        Ok(())
    }
}

/// Classical acceleration at `u̇ = 0` of a point fixed to `body` at world position `p`, from the
/// body velocities and accelerations of an RNEA pass at `u̇ = 0` (spatial, at the base CM `r0`):
/// `a = a_O + α × d + ω × (v_O + ω × d)`, `d = p − r0` (Featherstone §2.11).
pub(crate) fn point_acceleration_bias(data: &Data, body: usize, p: &Vector3<f64>) -> Vector3<f64> {
    let d = p - data.base_position;
    let v = data.body_velocity[body];
    let a = data.body_acceleration[body];
    let w = angular(&v);
    linear(&a) + angular(&a).cross(&d) + w.cross(&(linear(&v) + w.cross(&d)))
}

impl Controller for CoordinatedFlying {
    fn name(&self) -> &str {
        "coordinated_flying"
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        if ctx.mode != Mode::Flying {
            return Err(SpacearmError::argument(format!(
                "coordinated base-and-arm control needs the full base wrench of the 'flying' mode, but the simulation mode is '{}'",
                ctx.mode.name()
            )));
        }
        if !ctx.wheel_dofs.is_empty() {
            return Err(SpacearmError::argument(
                "coordinated flying control does not drive reaction wheels; pass wheels=[] to treat them as joints held at constant speed",
            ));
        }
        let g = self.gains;
        for (what, v) in [("kp_ee", g.kp_ee), ("kd_ee", g.kd_ee), ("kp_base", g.kp_base), ("kd_base", g.kd_base)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SpacearmError::argument(format!("coordinated flying {what} must be finite and >= 0, got {v}")));
            }
        }
        positive("coordinated flying threshold", self.threshold)?;
        if !(self.damping.is_finite() && self.damping >= 0.0) {
            return Err(SpacearmError::argument(format!("coordinated flying max_damping must be finite and >= 0, got {}", self.damping)));
        }
        check_body(ctx.plant, self.body)?;
        if let Some((_, q)) = self.base_ref {
            crate::math::rotations::unit_quaternion_from_xyzw("coordinated flying base quaternion reference", &q)?;
        }
        let model = ctx.plant.clone();
        self.data = Some(Data::new(&model));
        // Every arm joint commanded, passive ones too (issue 24: not yet partial feedback linearization here).
        self.inner = Some(ReducedInverseDynamics::commanding_every_arm_joint(model.clone(), ctx)?);
        self.model = Some(model);
        self.arm = ctx.arm_dofs.to_vec();
        self.jac = vec![Vector3::zeros(); ctx.plant.n_dof()];
        self.jac_arm = DMatrix::zeros(3, self.arm.len());
        self.qdd_arm = DVector::zeros(self.arm.len());
        self.svd = RowSvd::new(self.arm.len());
        self.qdd = vec![0.0; ctx.plant.n_dof()];
        self.attitude = None;
        Ok(())
    }

    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        if self.attitude.is_none() {
            self.latch_base_reference(x)?;
        }
        let (Some(model), Some(data), Some(inner), Some(att)) = (self.model.as_ref(), self.data.as_mut(), self.inner.as_mut(), self.attitude.as_ref()) else {
            return Err(SpacearmError::Simulation("coordinated flying control used before setup".into()));
        };
        let g = self.gains;
        // 1. Base regulation.
        let r0 = Vector3::new(x[0], x[1], x[2]);
        let v0 = Vector3::new(u[0], u[1], u[2]);
        let w0 = Vector3::new(u[3], u[4], u[5]);
        let (e_att, angle) = att.error(&x[3..7]);
        let acc_lin = (self.base_position_ref - r0) * g.kp_base - v0 * g.kd_base;
        let acc_ang = -e_att * g.kp_base - w0 * g.kd_base;
        // 2. End-effector task: kinematics, velocity and u̇ = 0 acceleration of the point.
        forward_kinematics(model, data, x)?;
        crba_after_kinematics(model, data, false)?;
        rnea_after_kinematics(model, data, u, None, &[]);
        let p = point_position(data, self.body, &self.offset);
        let d = p - data.base_position;
        let vb = data.body_velocity[self.body];
        let p_dot = linear(&vb) + angular(&vb).cross(&d);
        let bias = point_acceleration_bias(data, self.body, &p);
        let (p_ref, v_ref, a_ref) = self.line.eval(t);
        let a_des = a_ref + (v_ref - p_dot) * g.kd_ee + (p_ref - p) * g.kp_ee;
        let rhs = a_des - acc_lin - acc_ang.cross(&d) - bias;
        // J_mX translational columns of the arm joints on the path to the point.
        for c in self.jac.iter_mut() {
            *c = Vector3::zeros();
        }
        let mut b = self.body;
        while b != 0 {
            if let Some(dof) = model.dof_of_body(b) {
                let k = data.joint_axis_in_world[b];
                self.jac[dof] = match model.links()[b - 1].joint.kind {
                    JointType::Revolute => k.cross(&(p - data.joint_position_in_world[b])),
                    _ => k,
                };
            }
            b = model.links()[b - 1].parent;
        }
        for (c, &dof) in self.arm.iter().enumerate() {
            for r in 0..3 {
                self.jac_arm[(r, c)] = self.jac[dof][r];
            }
        }
        self.svd.factor(&self.jac_arm);
        self.svd.solve(rhs.as_slice(), &DampingLaw { threshold: self.threshold, max_damping: self.damping }, &mut self.qdd_arm);
        for (c, &dof) in self.arm.iter().enumerate() {
            self.qdd[dof] = self.qdd_arm[c];
        }
        // 3. Base rows: F_b = H0 ẍ0_des + H0m q̈_des + c0.
        let xdd0 = Vector6::new(acc_lin.x, acc_lin.y, acc_lin.z, acc_ang.x, acc_ang.y, acc_ang.z);
        let mut f_b = data.subtree_inertia[0] * xdd0 + data.tau.fixed_rows::<6>(0);
        for (j, qdd) in self.qdd.iter().enumerate() {
            f_b += data.mass_matrix.fixed_view::<6, 1>(0, 6 + j) * *qdd;
        }
        out.base_wrench = f_b;
        // Joint torques from the reduced EOM with that base wrench.
        inner.arm_torques(x, u, &self.qdd, out)?;
        out.reference[..3].copy_from_slice(p_ref.as_slice());
        out.tracking_error = (p_ref - p).norm();
        out.attitude_error = angle;
        Ok(())
    }

    fn reference_len(&self) -> usize {
        3
    }

    fn tracking(&self) -> Option<TrackingKind> {
        Some(TrackingKind::Cartesian)
    }

    fn reports_attitude_error(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithms::kinematics::point_jacobians;
    use nalgebra::UnitQuaternion;
    use crate::model::presets;

    /// Configuration advanced by `h` along constant `u` (u̇ = 0): exact for the base (constant
    /// v0, ω0 in 𝒥) and the joints.
    fn advance(x: &[f64], u: &[f64], h: f64) -> Vec<f64> {
        let mut y = x.to_vec();
        for i in 0..3 {
            y[i] += h * u[i];
        }
        let w = Vector3::new(u[3], u[4], u[5]);
        let dq = UnitQuaternion::from_scaled_axis(w * h);
        let q = UnitQuaternion::new_normalize(nalgebra::Quaternion::new(x[6], x[3], x[4], x[5]));
        let qn = dq * q;
        y[3] = qn.i;
        y[4] = qn.j;
        y[5] = qn.k;
        y[6] = qn.w;
        for i in 7..x.len() {
            y[i] += h * u[i - 1];
        }
        y
    }

    #[test]
    fn point_bias_acceleration_matches_finite_differences_of_the_point_velocity() {
        let model = presets::spatial6();
        let mut data = Data::new(&model);
        let mut x = presets::initial_configuration(&model);
        x[0] = 3.0;
        x[2] = -1.0;
        let u = vec![0.3, -0.2, 0.1, 0.4, -0.5, 0.3, 0.7, -0.4, 0.6, 0.5, -0.8, 0.9];
        let pt = &model.points()[model.end_effector().unwrap()];
        let (body, offset) = (pt.body, pt.offset);
        let velocity = |data: &mut Data, x: &[f64]| {
            forward_kinematics(&model, data, x).unwrap();
            let (j0, jm) = point_jacobians(&model, data, body, &offset).unwrap();
            let v = j0 * Vector6::from_column_slice(&u[0..6]) + jm * nalgebra::DVector::from_column_slice(&u[6..]);
            Vector3::new(v[0], v[1], v[2])
        };
        let h = 1e-5;
        let fd = (velocity(&mut data, &advance(&x, &u, h)) - velocity(&mut data, &advance(&x, &u, -h))) / (2.0 * h);
        forward_kinematics(&model, &mut data, &x).unwrap();
        rnea_after_kinematics(&model, &mut data, &u, None, &[]);
        let p = point_position(&data, body, &offset);
        let bias = point_acceleration_bias(&data, body, &p);
        assert!(bias.norm() > 0.1, "reference not trivial: {bias}");
        assert!((bias - fd).norm() < 1e-7 * fd.norm().max(1.0), "{bias} vs finite differences {fd}");
    }
}
