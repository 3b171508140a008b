//! External wrenches applied at points on bodies (contact, capture, thruster plumes on links).

use nalgebra::{Vector3, Vector6};

use crate::model::data::DataT;
use crate::error::{Result, SpacearmError};
use crate::algorithms::kinematics::point_position;
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
