//! Forward dynamics through the mass matrix, `u̇ = H⁻¹ (f + Jᵀ w_ext − c)` (the O(N³) route,
//! independent of the articulated-body recursion in [`crate::aba`]).

use nalgebra::DVector;

use crate::crba::crba;
use crate::data::Data;
use crate::error::{Result, SpacearmError};
use crate::kinematics::check_velocity;
use crate::model::Model;
use crate::rnea::rnea;
use crate::wrench::ExternalWrench;

/// Forward dynamics by CRBA + RNEA + Cholesky: the state derivative `u̇` for the generalized
/// force `f = [F0; N0; τ]` and external wrenches.
pub fn forward_dynamics_via_mass_matrix(
    model: &Model,
    data: &mut Data,
    x: &[f64],
    u: &[f64],
    f: &[f64],
    external: &[ExternalWrench],
) -> Result<DVector<f64>> {
    check_velocity(model, "f", f)?;
    let zeros = vec![0.0; model.nu()];
    // c − Jᵀ w_ext is the inverse dynamics at zero acceleration.
    let bias = rnea(model, data, x, u, &zeros, external)?.clone();
    let h = crba(model, data, x)?.clone();
    let chol = h.cholesky().ok_or_else(|| SpacearmError::Singular("the mass matrix H".into()))?;
    Ok(chol.solve(&(DVector::from_column_slice(f) - bias)))
}
