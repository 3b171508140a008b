//! The Generalized Jacobian Matrix formulation: `H*`, `c*`, `J*`, the momentum map and the
//! reduced joint-space dynamics (paper §4–5, eqs. 39–50 and 104–111; DESIGN.md §2).
//!
//! All functions here take their inertia blocks from the CRBA mass matrix and invert `H0` by
//! the closed-form Schur complement; nothing inverts a 6×6 matrix numerically.

use nalgebra::{DMatrix, DVector, Matrix6, Vector3, Vector6};

use crate::crba::crba;
use crate::data::Data;
use crate::error::{Result, SpacearmError};
use crate::inertia::base_inertia_inverse;
use crate::kinematics::{check_joint_vector, check_velocity, point_jacobians};
use crate::model::Model;
use crate::rnea::bias_forces;
use crate::spatial::spatial;

/// The blocks `H0` (6×6), `H0m` (6×N), `H_m` (N×N) of a mass matrix.
pub fn split_mass_matrix(h: &DMatrix<f64>) -> (Matrix6<f64>, DMatrix<f64>, DMatrix<f64>) {
    let n = h.nrows() - 6;
    (
        h.fixed_view::<6, 6>(0, 0).into_owned(),
        h.view((0, 6), (6, n)).into_owned(),
        h.view((6, 6), (n, n)).into_owned(),
    )
}

/// Everything the reduction needs at one configuration: `H0⁻¹` and `H0⁻¹ H0m`.
struct Reduction {
    h0_inv: Matrix6<f64>,
    h0m: DMatrix<f64>,
    hm: DMatrix<f64>,
    /// `H0⁻¹ H0m` (6×N): minus the base-velocity response to unit joint rates (eq. 109).
    h0_inv_h0m: DMatrix<f64>,
}

fn reduction(model: &Model, data: &mut Data, x: &[f64]) -> Result<Reduction> {
    let h = crba(model, data, x)?;
    let (h0, h0m, hm) = split_mass_matrix(h);
    let h0_inv = base_inertia_inverse(&h0)?;
    let h0_inv_h0m = DMatrix::from_column_slice(6, 6, h0_inv.as_slice()) * &h0m;
    Ok(Reduction { h0_inv, h0m, hm, h0_inv_h0m })
}

/// Generalized inertia matrix `H* = H_m − H0mᵀ H0⁻¹ H0m` (N×N, paper eq. 45).
pub fn generalized_inertia(model: &Model, data: &mut Data, x: &[f64]) -> Result<DMatrix<f64>> {
    let r = reduction(model, data, x)?;
    Ok(&r.hm - r.h0m.transpose() * &r.h0_inv_h0m)
}

/// Generalized bias `c* = c_m − H0mᵀ H0⁻¹ c0` (N, paper eq. 46 with the base velocity `u[0..6]`
/// taken as given).
pub fn generalized_bias(model: &Model, data: &mut Data, x: &[f64], u: &[f64]) -> Result<DVector<f64>> {
    let r = reduction(model, data, x)?;
    let c = bias_forces(model, data, x, u)?.clone();
    let c0 = Vector6::from_column_slice(&c.as_slice()[0..6]);
    let cm = c.rows(6, model.n_dof()).into_owned();
    Ok(cm - r.h0m.transpose() * (r.h0_inv * c0))
}

/// Generalized Jacobian `J* = J_mX − J_0X H0⁻¹ H0m` (6×N, paper eq. 110) of a point fixed to
/// `body` at `offset` (body frame, from its CM): with zero system momentum, the point's twist
/// `[v_X; ω]` in 𝒥 is `J* q̇`.
pub fn generalized_jacobian(model: &Model, data: &mut Data, x: &[f64], body: usize, offset: &Vector3<f64>) -> Result<DMatrix<f64>> {
    let r = reduction(model, data, x)?;
    let (j0, jm) = point_jacobians(model, data, body, offset)?;
    Ok(jm - DMatrix::from_column_slice(6, 6, j0.as_slice()) * r.h0_inv_h0m)
}

/// Base momentum vector `M0 = [P; L_base]` from the linear momentum and the angular momentum
/// about the origin of 𝒥: `L_base = L_origin − r0 × P`.
fn momentum_about_base(data: &Data, linear: &Vector3<f64>, angular_about_origin: &Vector3<f64>) -> Vector6<f64> {
    spatial(linear, &(angular_about_origin - data.base_position.cross(linear)))
}

fn check3(what: &str, v: &Vector3<f64>) -> Result<()> {
    crate::error::check_finite(what, v.as_slice())
}

/// Base velocity `ẋ0 = H0⁻¹ (M0 − H0m q̇)` (paper eq. 43/109) that gives the system the
/// linear momentum `P` and the angular momentum `L_origin` (about the origin of 𝒥) while the
/// joints move at `q̇`.
pub fn base_velocity_from_momentum(
    model: &Model,
    data: &mut Data,
    x: &[f64],
    qd: &[f64],
    linear_momentum: &Vector3<f64>,
    angular_momentum_origin: &Vector3<f64>,
) -> Result<Vector6<f64>> {
    check_joint_vector(model, "qd", qd)?;
    check3("linear momentum", linear_momentum)?;
    check3("angular momentum", angular_momentum_origin)?;
    let r = reduction(model, data, x)?;
    let m0 = momentum_about_base(data, linear_momentum, angular_momentum_origin);
    Ok(r.h0_inv * m0 - &r.h0_inv_h0m * DVector::from_column_slice(qd))
}

/// The momentum term of the point twist with non-zero system momentum:
/// `[v_X; ω] = J* q̇ + J_0X H0⁻¹ M0` — this returns `J_0X H0⁻¹ M0`.
pub fn momentum_twist(
    model: &Model,
    data: &mut Data,
    x: &[f64],
    body: usize,
    offset: &Vector3<f64>,
    linear_momentum: &Vector3<f64>,
    angular_momentum_origin: &Vector3<f64>,
) -> Result<Vector6<f64>> {
    check3("linear momentum", linear_momentum)?;
    check3("angular momentum", angular_momentum_origin)?;
    let r = reduction(model, data, x)?;
    let (j0, _) = point_jacobians(model, data, body, offset)?;
    Ok(j0 * r.h0_inv * momentum_about_base(data, linear_momentum, angular_momentum_origin))
}

/// Reduced joint-space forward dynamics (DESIGN.md §2): with base wrench `F_b = [F0; N0]`,
/// `q̈ = H*⁻¹ (τ − c* − H0mᵀ H0⁻¹ F_b)` and `ẍ0 = H0⁻¹ (F_b − H0m q̈ − c0)`. `F_b = 0` is the
/// floating case (eq. 50 generalized to a moving base). Returns the full `u̇ = [ẍ0; q̈]`, which
/// equals the ABA result for `f = [F_b; τ]`.
pub fn reduced_forward_dynamics(
    model: &Model,
    data: &mut Data,
    x: &[f64],
    u: &[f64],
    tau: &[f64],
    base_wrench: &Vector6<f64>,
) -> Result<DVector<f64>> {
    check_velocity(model, "u", u)?;
    check_joint_vector(model, "tau", tau)?;
    crate::error::check_finite("base wrench", base_wrench.as_slice())?;
    let r = reduction(model, data, x)?;
    let c = bias_forces(model, data, x, u)?.clone();
    let n = model.n_dof();
    let c0 = Vector6::from_column_slice(&c.as_slice()[0..6]);
    let cm = c.rows(6, n).into_owned();
    let h_star = &r.hm - r.h0m.transpose() * &r.h0_inv_h0m;
    let c_star = cm - r.h0m.transpose() * (r.h0_inv * c0);
    let rhs = DVector::from_column_slice(tau) - c_star - r.h0m.transpose() * (r.h0_inv * base_wrench);
    let qdd = h_star
        .cholesky()
        .ok_or_else(|| SpacearmError::Singular("the generalized inertia matrix H*".into()))?
        .solve(&rhs);
    let base_acc = r.h0_inv * (base_wrench - &r.h0m * &qdd - c0);
    let mut out = DVector::zeros(6 + n);
    out.fixed_rows_mut::<6>(0).copy_from(&base_acc);
    out.rows_mut(6, n).copy_from(&qdd);
    Ok(out)
}
