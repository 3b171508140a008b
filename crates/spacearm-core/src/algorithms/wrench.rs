//! External wrenches applied at points on bodies (contact, capture, thruster plumes on links).

use nalgebra::{Vector3, Vector6};

use crate::model::data::{Data, DataT};
use crate::error::{Result, SpacearmError};
use crate::algorithms::kinematics::{check_velocity, forward_kinematics, point_position};
use crate::model::Model;
use crate::math::scalar::{vector3, Real};
use crate::math::spatial::spatial;

/// A force and torque, both in 𝒥, applied at a point fixed to a body.
///
/// Its generalized force is `J_Xᵀ [f; n]` with `J_X = [J_0X, J_mX]` the point's Jacobian
/// (docs/conventions.md: `H u̇ + c = f + Jᵀ w_ext`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExternalWrench {
    /// Body index (0 = base).
    pub body: usize,
    /// Application point in the body frame (from its CM), m.
    pub offset: Vector3<f64>,
    /// Force in 𝒥, N.
    pub force: Vector3<f64>,
    /// Torque in 𝒥, N·m (a pure couple, added to the moment of `force`).
    pub torque: Vector3<f64>,
}

/// The one check of a dynamics call's loads against the model: the generalized `6+N`-vector `v`
/// named `what` (the force `f` of forward dynamics, the acceleration `du` of inverse dynamics)
/// and every external wrench ([`ExternalWrench::check`]), in that order.
pub fn check_loads(model: &Model, what: &str, v: &[f64], external: &[ExternalWrench]) -> Result<()> {
    check_velocity(model, what, v)?;
    external.iter().try_for_each(|w| w.check(model))
}

/// The prologue of the dynamics entry points ([`crate::algorithms::aba::aba`],
/// [`crate::algorithms::dynamics::compute_forward_dynamics_via_mass_matrix`],
/// [`crate::algorithms::rnea::rnea`]): forward kinematics at `x` into `data`, then `u` and the
/// loads checked ([`check_loads`]).
pub(crate) fn kinematics_and_loads(model: &Model, data: &mut Data, x: &[f64], u: &[f64], what: &str, v: &[f64], external: &[ExternalWrench]) -> Result<()> {
    forward_kinematics(model, data, x)?;
    check_velocity(model, "u", u)?;
    check_loads(model, what, v, external)
}

impl ExternalWrench {
    /// Validate against the model (body exists, values finite).
    pub fn check(&self, model: &Model) -> Result<()> {
        if self.body >= model.n_bodies() {
            return Err(SpacearmError::NotFound(format!(
                "external wrench on body {} but the model has bodies 0..={}",
                self.body,
                model.n_bodies() - 1
            )));
        }
        let all = [self.offset, self.force, self.torque];
        if all.iter().flat_map(|v| v.iter()).any(|v| !v.is_finite()) {
            return Err(SpacearmError::NonFinite { what: "external wrench".into(), index: 0, value: f64::NAN });
        }
        Ok(())
    }

    /// The wrench as a spatial force at the base CM `[f; n + (x − r0) × f]`. Requires forward
    /// kinematics.
    pub fn at_base_com<T: Real>(&self, data: &DataT<T>) -> Vector6<T> {
        let x = point_position(data, self.body, &self.offset);
        let force = vector3(&self.force);
        spatial(&force, &(vector3(&self.torque) + (x - data.base_position).cross(&force)))
    }
}
