//! Derivatives of the Generalized Inertia Matrix `H* = H_m − H0mᵀ H0⁻¹ H0m` (paper eq. 45) and
//! of the Generalized Jacobian `J* = J_mX − J_0X H0⁻¹ H0m` (eq. 110): the GJM reduction of
//! [`crate::gjm`] on dual numbers.

use nalgebra::{DMatrix, Vector3};

use super::dual::{lanes, pose_and_velocity, seed_along_velocity, seed_chunk, seed_chunk_from_kinematics, DerivativeData, PartialsTensor, Pose, CHUNK};
use crate::error::Result;
use crate::gjm::{fill_generalized_inertia, generalized_jacobian_after_reduction, reduce_after_kinematics, reduction_columns};
use crate::algorithms::kinematics::check_body;
use crate::model::Model;

/// Partial derivatives `∂H*/∂q_k` (each N×N, symmetric) of the generalized inertia with
/// respect to the joint coordinates, left in `work.generalized_inertia_partials[k]`.
///
/// `H*` depends on the joint coordinates only: a rigid motion of the whole system (base
/// position and attitude) rotates `H0`, `H0m` covariantly and leaves `H_m` unchanged, so the
/// reduction is invariant and its tangent partials with respect to `δr0`, `δθ` vanish.
pub fn generalized_inertia_partials<'w>(model: &Model, work: &'w mut DerivativeData, x: &[f64]) -> Result<&'w [DMatrix<f64>]> {
    let (pose, n) = work.prepare_partials(model, x, PartialsTensor::GeneralizedInertia)?;
    let dirs = &work.joint_dirs;
    for (c, chunk) in dirs.chunks(CHUNK).enumerate() {
        seed_chunk_from_kinematics(model, &work.data, &mut work.chunk, &pose, None, chunk);
        let data = &mut work.chunk.data;
        let inv = reduce_after_kinematics(model, data, true)?;
        reduction_columns(model, data, &inv);
        fill_generalized_inertia(model, data, &inv, false)?;
        let hs = &data.generalized_inertia;
        for j in 0..n {
            for i in 0..=j {
                let e = lanes(&hs[(i, j)]);
                for (lane, v) in e.iter().take(chunk.len()).enumerate() {
                    let k = c * CHUNK + lane;
                    work.generalized_inertia_partials[k][(i, j)] = *v;
                    work.generalized_inertia_partials[k][(j, i)] = *v;
                }
            }
        }
    }
    Ok(&work.generalized_inertia_partials)
}

/// Time derivative `Ḣ* = Σ_k ∂H*/∂q_k q̇_k` (N×N) along the generalized velocity `u`, left in
/// `work.generalized_inertia_derivative`. (The whole tangent velocity is applied; the base
/// part contributes nothing, see [`generalized_inertia_partials`].)
pub fn generalized_inertia_derivative<'w>(model: &Model, work: &'w mut DerivativeData, x: &[f64], u: &[f64]) -> Result<&'w DMatrix<f64>> {
    let pose = pose_and_velocity(model, x, u)?;
    seed_along_velocity(model, &mut work.single, &pose, u);
    let data = &mut work.single.data;
    let inv = reduce_after_kinematics(model, data, true)?;
    reduction_columns(model, data, &inv);
    fill_generalized_inertia(model, data, &inv, false)?;
    for (out, v) in work.generalized_inertia_derivative.iter_mut().zip(data.generalized_inertia.iter()) {
        *out = v.eps;
    }
    Ok(&work.generalized_inertia_derivative)
}

/// Partial derivatives `∂J*/∂x_k` (each 6×N) of the generalized Jacobian of the point fixed
/// to `body` at `offset` (body frame, from its CM) with respect to the `6+N` tangent
/// coordinates, left in `work.generalized_jacobian_partials[k]`. `J*` rotates with the base
/// attitude (its rows are in 𝒥), so the attitude partials `k = 3..6` are non-zero; the `δr0`
/// partials are exactly zero.
pub fn generalized_jacobian_partials<'w>(
    model: &Model,
    work: &'w mut DerivativeData,
    x: &[f64],
    body: usize,
    offset: &Vector3<f64>,
) -> Result<&'w [DMatrix<f64>]> {
    let pose = Pose::new(model, x)?;
    check_body(model, body)?;
    crate::error::check_finite("offset", offset.as_slice())?;
    let n = model.n_dof();
    for k in 0..3 {
        work.generalized_jacobian_partials[k].fill(0.0);
    }
    let dirs = &work.config_dirs;
    for chunk in dirs.chunks(CHUNK) {
        seed_chunk(model, &mut work.chunk, &pose, None, chunk);
        let data = &mut work.chunk.data;
        let inv = reduce_after_kinematics(model, data, false)?;
        generalized_jacobian_after_reduction(model, data, &inv, body, offset)?;
        let js = &data.generalized_jacobian;
        for j in 0..n {
            for i in 0..6 {
                let e = lanes(&js[(i, j)]);
                for (lane, dir) in chunk.iter().enumerate() {
                    let k = dir.tangent_index().expect("configuration direction");
                    work.generalized_jacobian_partials[k][(i, j)] = e[lane];
                }
            }
        }
    }
    Ok(&work.generalized_jacobian_partials)
}

/// Time derivative `J̇* = Σ_k ∂J*/∂x_k ẋ_k` (6×N) of the generalized Jacobian of a point along
/// the generalized velocity `u` (tangent velocity of `x`), left in
/// `work.generalized_jacobian_derivative`.
pub fn generalized_jacobian_derivative<'w>(
    model: &Model,
    work: &'w mut DerivativeData,
    x: &[f64],
    u: &[f64],
    body: usize,
    offset: &Vector3<f64>,
) -> Result<&'w DMatrix<f64>> {
    let pose = pose_and_velocity(model, x, u)?;
    check_body(model, body)?;
    crate::error::check_finite("offset", offset.as_slice())?;
    seed_along_velocity(model, &mut work.single, &pose, u);
    let data = &mut work.single.data;
    let inv = reduce_after_kinematics(model, data, false)?;
    generalized_jacobian_after_reduction(model, data, &inv, body, offset)?;
    for (out, v) in work.generalized_jacobian_derivative.iter_mut().zip(data.generalized_jacobian.iter()) {
        *out = v.eps;
    }
    Ok(&work.generalized_jacobian_derivative)
}
