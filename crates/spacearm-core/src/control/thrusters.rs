//! Base regulation by thrusters in the flying modes: the system CM position by a force through
//! the CM, the base attitude by a torque — each only where the mode allows it
//! (rotation-flying: attitude; translation-flying: CM position; flying: both).
//!
//! - Position: `F0 = M (K_pp (r_ref − r_g) − K_dp ṙ_g)` with `r_g` the system CM and
//!   `ṙ_g = P / M`. An external force on any body moves the system CM by `M r̈_g = F0`, so the CM
//!   error obeys `ë + K_dp ė + K_pp e = 0` exactly, whatever the arm does.
//! - Attitude: `N0 = −K_pa e − K_da ω0` (`e` as in [`super::attitude`]).
//!
//! The references default to the CM position and base attitude at the first evaluation.

use nalgebra::Vector3;

use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::algorithms::kinematics::forward_kinematics;
use crate::model::Model;
use crate::algorithms::momentum::{center_of_mass_from_data, momentum};

use super::attitude::{AttitudeControl, LvlhReference};
use super::controller::thruster_axes;
use super::{Command, ControlContext, Controller};

/// Thruster regulation of the system CM position and the base attitude.
#[derive(Debug, Clone)]
pub struct BaseThrusterControl {
    com_ref: Option<Vector3<f64>>,
    quat_ref: Option<[f64; 4]>,
    kp_position: f64,
    kd_position: f64,
    kp_attitude: f64,
    kd_attitude: f64,
    use_force: bool,
    use_torque: bool,
    model: Option<Model>,
    data: Option<Data>,
    attitude: Option<AttitudeControl>,
    com_target: Vector3<f64>,
    lvlh: Option<LvlhReference>,
}

impl BaseThrusterControl {
    /// References (`None`: the initial CM / attitude) and gains: position (1/s², 1/s),
    /// attitude (N·m/rad, N·m·s/rad).
    pub fn new(com_ref: Option<Vector3<f64>>, quat_ref: Option<[f64; 4]>, kp_position: f64, kd_position: f64, kp_attitude: f64, kd_attitude: f64) -> Self {
        BaseThrusterControl {
            com_ref,
            quat_ref,
            kp_position,
            kd_position,
            kp_attitude,
            kd_attitude,
            use_force: false,
            use_torque: false,
            model: None,
            data: None,
            attitude: None,
            com_target: Vector3::zeros(),
            lvlh: None,
        }
    }

    /// Hold the attitude relative to the LVLH frame of `reference` (its own attitude, or the
    /// initial one relative to LVLH), with the LVLH rate as the rate reference
    /// ([`super::attitude`]); the `quat_ref` of [`BaseThrusterControl::new`] is then unused.
    pub fn with_lvlh(mut self, reference: LvlhReference) -> Self {
        self.lvlh = Some(reference);
        self
    }
}

impl Controller for BaseThrusterControl {
    fn name(&self) -> &str {
        "base_thrusters"
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        (self.use_force, self.use_torque) = thruster_axes(ctx, "thruster control")?;
        for (what, v) in [("kp_position", self.kp_position), ("kd_position", self.kd_position), ("kp_attitude", self.kp_attitude), ("kd_attitude", self.kd_attitude)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SpacearmError::argument(format!("thruster control {what} must be finite and >= 0, got {v}")));
            }
        }
        if let Some(r) = self.com_ref {
            crate::error::check_finite("thruster control CM reference", r.as_slice())?;
        }
        if let Some(q) = self.quat_ref {
            crate::math::rotations::unit_quaternion_from_xyzw("thruster control quat_ref", &q)?;
        }
        let model = ctx.plant.clone();
        self.data = Some(Data::new(&model));
        self.model = Some(model);
        self.attitude = None;
        Ok(())
    }

    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        let (Some(model), Some(data)) = (self.model.as_ref(), self.data.as_mut()) else {
            return Err(SpacearmError::Simulation("thruster control used before setup".into()));
        };
        if self.attitude.is_none() {
            forward_kinematics(model, data, x)?;
            self.com_target = self.com_ref.unwrap_or_else(|| center_of_mass_from_data(model, data));
            let q = self.quat_ref.unwrap_or([x[3], x[4], x[5], x[6]]);
            let mut att = AttitudeControl::new(q, self.kp_attitude, self.kd_attitude);
            att.set_reference(q)?;
            self.attitude = Some(att);
        }
        let mut w_ref = Vector3::zeros();
        if let Some(l) = self.lvlh.as_mut() {
            let (q, w) = l.at(t, &x[3..7])?;
            self.attitude.as_mut().expect("latched above").set_reference([q.i, q.j, q.k, q.w])?;
            w_ref = w;
        }
        let att = self.attitude.as_ref().expect("latched above");
        if self.use_force {
            let m = momentum(model, data, x, u)?;
            let mass = model.total_mass();
            let rg = center_of_mass_from_data(model, data);
            let f = ((self.com_target - rg) * self.kp_position - m.linear / mass * self.kd_position) * mass;
            out.base_wrench[0] = f.x;
            out.base_wrench[1] = f.y;
            out.base_wrench[2] = f.z;
        }
        let (e, angle) = att.error(&x[3..7]);
        if self.use_torque {
            let n = -e * self.kp_attitude - (Vector3::new(u[3], u[4], u[5]) - w_ref) * self.kd_attitude;
            out.base_wrench[3] = n.x;
            out.base_wrench[4] = n.y;
            out.base_wrench[5] = n.z;
        }
        out.attitude_error = angle;
        Ok(())
    }

    fn reports_attitude_error(&self) -> bool {
        true
    }
}
