//! Momentum damping by the base thrusters (flying modes): the law that detumbles a captured
//! system (docs/capture.md) and holds the system momentum at zero during an approach.
//!
//! `F0 = clamp(−P / τ_d, F_max)` and `N0 = clamp(−L_G / τ_d − (r0 − r_g) × F0, N_max)`, with `P`
//! the linear momentum, `L_G` the angular momentum about the system CM `r_g`, `r0` the base CM
//! and `clamp(v, a) = v min(1, a / |v|)` (a norm limit, the direction kept). Applied at the base
//! CM, the wrench changes the momenta by `Ṗ = F0` and `L̇_G = N0 + (r0 − r_g) × F0`; unclamped
//! both decay as `e^{−t/τ_d}`, whatever the arm does. The momenta come from the controller's
//! model (the plant's by default; an estimate of the captured system otherwise).
//!
//! Only the components the mode allows are commanded (force in `translation-flying` and
//! `flying`, torque in `rotation-flying` and `flying`); a floating mode is refused.

use nalgebra::Vector3;

use crate::algorithms::momentum::{center_of_mass_from_data, momentum};
use crate::error::{Result, SpacearmError};
use crate::model::data::Data;
use crate::model::Model;

use super::controller::{check_model_dofs, thruster_axes};
use super::{positive, Command, ControlContext, Controller};

/// Thruster damping of the system momentum (module docs).
#[derive(Debug, Clone)]
pub struct MomentumDamping {
    time_constant: f64,
    max_force: f64,
    max_torque: f64,
    model_given: Option<Model>,
    model: Option<Model>,
    data: Option<Data>,
    use_force: bool,
    use_torque: bool,
}

fn clamp_norm(v: Vector3<f64>, limit: f64) -> Vector3<f64> {
    let n = v.norm();
    if n <= limit {
        v
    } else {
        v * (limit / n)
    }
}

impl MomentumDamping {
    /// Time constant `τ_d` (s, > 0), norm limits of the force (N) and torque (N·m) (> 0;
    /// infinity: none), and the controller's model (`None`: the plant's).
    pub fn new(time_constant: f64, max_force: f64, max_torque: f64, model: Option<Model>) -> Self {
        MomentumDamping { time_constant, max_force, max_torque, model_given: model, model: None, data: None, use_force: false, use_torque: false }
    }
}

impl Controller for MomentumDamping {
    fn name(&self) -> &str {
        "momentum_damping"
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        positive("momentum damping time_constant", self.time_constant)?;
        for (what, v) in [("max_force", self.max_force), ("max_torque", self.max_torque)] {
            if !(v > 0.0) {
                return Err(SpacearmError::argument(format!("momentum damping {what} must be > 0 (infinity: no limit), got {v}")));
            }
        }
        (self.use_force, self.use_torque) = thruster_axes(ctx, "momentum damping acts through the base thrusters and")?;
        let model = self.model_given.clone().unwrap_or_else(|| ctx.plant.clone());
        check_model_dofs("the momentum-damping model", &model, ctx)?;
        self.data = Some(Data::new(&model));
        self.model = Some(model);
        Ok(())
    }

    fn command(&mut self, _t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        let (Some(model), Some(data)) = (self.model.as_ref(), self.data.as_mut()) else {
            return Err(SpacearmError::Simulation("momentum damping used before setup".into()));
        };
        let m = momentum(model, data, x, u)?;
        let rg = center_of_mass_from_data(model, data);
        let f = if self.use_force { clamp_norm(-m.linear / self.time_constant, self.max_force) } else { Vector3::zeros() };
        let lever = Vector3::new(x[0], x[1], x[2]) - rg;
        if self.use_force {
            out.base_wrench.fixed_rows_mut::<3>(0).copy_from(&f);
        }
        if self.use_torque {
            let n = clamp_norm(-m.angular_about_com / self.time_constant - lever.cross(&f), self.max_torque);
            out.base_wrench.fixed_rows_mut::<3>(3).copy_from(&n);
        }
        Ok(())
    }
}

/// Joint torques of another controller clamped to `±limit` on every joint (the command the
/// actuators can give; the simulation's own effort limits apply on top).
pub struct JointTorqueLimit {
    inner: Box<dyn Controller>,
    limit: f64,
}

impl JointTorqueLimit {
    /// Clamp the joint torques of `inner` to `±limit` (N·m or N, > 0).
    pub fn new(inner: Box<dyn Controller>, limit: f64) -> Self {
        JointTorqueLimit { inner, limit }
    }
}

impl Controller for JointTorqueLimit {
    fn name(&self) -> &str {
        self.inner.name()
    }
    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        if !(self.limit > 0.0) {
            return Err(SpacearmError::argument(format!("a joint torque limit must be > 0 (infinity: no limit), got {}", self.limit)));
        }
        self.inner.setup(ctx)
    }
    fn goal_report(&self) -> Option<super::GoalReport> {
        self.inner.goal_report()
    }
    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        self.inner.command(t, x, u, out)?;
        for v in &mut out.tau {
            *v = v.clamp(-self.limit, self.limit);
        }
        Ok(())
    }
    fn reference_len(&self) -> usize {
        self.inner.reference_len()
    }
    fn tracking(&self) -> Option<super::TrackingKind> {
        self.inner.tracking()
    }
    fn reports_attitude_error(&self) -> bool {
        self.inner.reports_attitude_error()
    }
    fn is_torque_free(&self) -> bool {
        self.inner.is_torque_free()
    }
    fn sample(&mut self, t: f64, x: &[f64], u: &[f64]) -> Result<()> {
        self.inner.sample(t, x, u)
    }
    fn reports_solve(&self) -> bool {
        self.inner.reports_solve()
    }
}
