//! Base attitude control with reaction wheels (rotation-floating mode).
//!
//! PD on the attitude error quaternion (Wie, *Space Vehicle Dynamics and Control*, 2nd ed.,
//! 2008, §7.3): with `q_e = q0 ⊗ q_ref⁻¹` (the rotation from the reference to the current
//! attitude, in 𝒥) and `e = 2 sign(w_e) v_e` (`v_e`, `w_e` its vector and scalar parts: the
//! rotation vector for small errors, the short way round), the base torque wanted is
//! `N = −K_p e − K_d ω0`. A wheel motor torque `τ_j` about the wheel axis `k_j` pushes the
//! base with `−τ_j k_j`, so the wheel torques are `τ_W = −A⁺ N` with `A = [k_1 … k_W]` (axes in
//! 𝒥) and `A⁺ = Aᵀ (A Aᵀ)⁺` its Moore–Penrose pseudo-inverse (the minimum-norm torques; with
//! fewer than three independent axes, the component of `N` they cannot produce is left out).
//!
//! **Holding LVLH in orbit** ([`LvlhReference`], docs/orbit.md): the reference turns with the
//! LVLH frame of the orbit's point `O` (read from an [`OrbitTrack`] of the run's orbit, the same
//! nodes as the loop's): `q_ref(t) = q_LVLH(t) ⊗ q_L` (`q_L` the attitude held relative to
//! LVLH) and the rate feedforward `ω_ref = (r × v)/|r|²`, so `N = −K_p e − K_d (ω0 − ω_ref)`.

use nalgebra::{Matrix3, SymmetricEigen, UnitQuaternion, Vector3};

use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::algorithms::kinematics::forward_kinematics;
use crate::math::rotations::quaternion_from_xyzw;
use crate::model::Model;
use crate::scenario::modes::Mode;
use crate::scenario::orbit::{lvlh_rate, lvlh_to_eci, Orbit, OrbitTrack};
use nalgebra::Rotation3;

/// An attitude reference that turns with the LVLH frame of an orbit (module docs).
#[derive(Debug, Clone)]
pub struct LvlhReference {
    track: Box<OrbitTrack>,
    /// The attitude held relative to LVLH (body → LVLH); `None`: latched from the first state.
    quat_in_lvlh: Option<UnitQuaternion<f64>>,
}

impl LvlhReference {
    /// The reference of `orbit` (the run's orbit, at `t = 0`) holding `quat_in_lvlh`
    /// (`[x, y, z, w]`, body → LVLH; `None`: the attitude relative to LVLH at the first command).
    pub fn new(orbit: &Orbit, quat_in_lvlh: Option<[f64; 4]>) -> Result<Self> {
        let q = quat_in_lvlh.map(|q| crate::math::rotations::unit_quaternion_from_xyzw("LVLH attitude reference", &q)).transpose()?;
        Ok(LvlhReference { track: Box::new(OrbitTrack::new(orbit, 1.0)?), quat_in_lvlh: q })
    }

    /// The LVLH frame (LVLH → ECI) and its angular velocity at `t`.
    fn frame(&mut self, t: f64) -> Result<(UnitQuaternion<f64>, Vector3<f64>)> {
        self.track.extend_to(t)?;
        let (r, v) = self.track.state(t);
        let c = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(lvlh_to_eci(&r, &v)));
        Ok((c, lvlh_rate(&r, &v)))
    }

    /// The desired attitude (body → 𝒥) and angular velocity at `t`, given the base attitude
    /// `quat` (`[x, y, z, w]`) to latch the relative attitude from on the first call.
    pub fn at(&mut self, t: f64, quat: &[f64]) -> Result<(UnitQuaternion<f64>, Vector3<f64>)> {
        let (c, w) = self.frame(t)?;
        let q_l = match self.quat_in_lvlh {
            Some(q) => q,
            None => {
                let q = c.inverse() * UnitQuaternion::new_normalize(quaternion_from_xyzw(quat));
                self.quat_in_lvlh = Some(q);
                q
            }
        };
        Ok((c * q_l, w))
    }
}

/// `[x, y, z, w]` of a unit quaternion.
fn xyzw(q: &UnitQuaternion<f64>) -> [f64; 4] {
    [q.i, q.j, q.k, q.w]
}

use super::controller::require_mode;
use super::{Command, ControlContext, Controller};

/// Attitude hold/slew to `quat_ref` with the reaction wheels.
#[derive(Debug, Clone)]
pub struct AttitudeControl {
    quat_ref_xyzw: [f64; 4],
    quat_ref: UnitQuaternion<f64>,
    kp: f64,
    kd: f64,
    model: Option<Model>,
    data: Option<Data>,
    wheels: Vec<usize>,
    axes_body: Vec<usize>,
    lvlh: Option<LvlhReference>,
}

impl AttitudeControl {
    /// `quat_ref` `[x, y, z, w]` (unit within [`crate::math::rotations::QUATERNION_TOLERANCE`]), gains `kp` (N·m/rad)
    /// and `kd` (N·m·s/rad), finite and ≥ 0.
    pub fn new(quat_ref: [f64; 4], kp: f64, kd: f64) -> Self {
        AttitudeControl {
            quat_ref_xyzw: quat_ref,
            quat_ref: UnitQuaternion::identity(),
            kp,
            kd,
            model: None,
            data: None,
            wheels: vec![],
            axes_body: vec![],
            lvlh: None,
        }
    }

    /// Hold an attitude relative to the LVLH frame of `reference` instead of a fixed one (the
    /// `quat_ref` given to [`AttitudeControl::new`] is then unused).
    pub fn with_lvlh(mut self, reference: LvlhReference) -> Self {
        self.lvlh = Some(reference);
        self
    }

    /// Set the reference attitude `[x, y, z, w]` (checked: unit within
    /// [`crate::math::rotations::QUATERNION_TOLERANCE`]).
    pub fn set_reference(&mut self, quat_ref: [f64; 4]) -> Result<()> {
        self.quat_ref = crate::math::rotations::unit_quaternion_from_xyzw("attitude quat_ref", &quat_ref)?;
        self.quat_ref_xyzw = quat_ref;
        Ok(())
    }

    /// Attitude error `e = 2 sign(w_e) v_e` of `quat` (`[x, y, z, w]`, unit) and its angle.
    pub fn error(&self, quat: &[f64]) -> (Vector3<f64>, f64) {
        let q = UnitQuaternion::new_unchecked(quaternion_from_xyzw(quat));
        let qe = q * self.quat_ref.inverse();
        let sign = if qe.w < 0.0 { -1.0 } else { 1.0 };
        let v = qe.vector() * (2.0 * sign);
        (Vector3::new(v.x, v.y, v.z), 2.0 * qe.w.abs().min(1.0).acos())
    }
}

impl Controller for AttitudeControl {
    fn name(&self) -> &str {
        "attitude"
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        require_mode(ctx, ctx.mode == Mode::RotationFloating, "attitude control with reaction wheels is the 'rotation-floating' mode")?;
        if ctx.wheel_dofs.is_empty() {
            return Err(SpacearmError::argument(
                "attitude control needs reaction wheels: add them with RobotBuilder.add_reaction_wheel or name them in wheels=",
            ));
        }
        for (what, v) in [("kp", self.kp), ("kd", self.kd)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SpacearmError::argument(format!("attitude control {what} must be finite and >= 0, got {v}")));
            }
        }
        self.quat_ref = crate::math::rotations::unit_quaternion_from_xyzw("attitude control quat_ref", &self.quat_ref_xyzw)?;
        let model = ctx.plant.clone();
        self.data = Some(Data::new(&model));
        self.axes_body = ctx.wheel_dofs.iter().map(|&d| model.body_of_dof(d)).collect();
        self.model = Some(model);
        self.wheels = ctx.wheel_dofs.to_vec();
        Ok(())
    }

    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        let mut w_ref = Vector3::zeros();
        if let Some(l) = self.lvlh.as_mut() {
            let (q, w) = l.at(t, &x[3..7])?;
            self.quat_ref = q;
            self.quat_ref_xyzw = xyzw(&q);
            w_ref = w;
        }
        let (e, angle) = self.error(&x[3..7]);
        let (Some(model), Some(data)) = (self.model.as_ref(), self.data.as_mut()) else {
            return Err(SpacearmError::Simulation("attitude control used before setup".into()));
        };
        forward_kinematics(model, data, x)?;
        let w0 = Vector3::new(u[3], u[4], u[5]);
        let torque = -e * self.kp - (w0 - w_ref) * self.kd;
        // τ_W = −Aᵀ (A Aᵀ)⁺ N.
        let mut aat = Matrix3::zeros();
        for &b in &self.axes_body {
            let k = data.joint_axis_in_world[b];
            aat += k * k.transpose();
        }
        let eig = SymmetricEigen::new(aat);
        let cutoff = 1e-9 * eig.eigenvalues.amax();
        let mut y = Vector3::zeros();
        for i in 0..3 {
            let lambda = eig.eigenvalues[i];
            if lambda > cutoff {
                let v = eig.eigenvectors.column(i);
                y += v * (v.dot(&torque) / lambda);
            }
        }
        for (&d, &b) in self.wheels.iter().zip(&self.axes_body) {
            out.tau[d] = -data.joint_axis_in_world[b].dot(&y);
        }
        out.attitude_error = angle;
        Ok(())
    }

    fn reports_attitude_error(&self) -> bool {
        true
    }
}
