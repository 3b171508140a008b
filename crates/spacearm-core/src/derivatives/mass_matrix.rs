//! `∂H/∂x_k` and `Ḣ` of the mass matrix (paper eq. 36), by CRBA (Featherstone §6.2) on dual
//! numbers.

use nalgebra::DMatrix;

use super::dual::{lanes, pose_and_velocity, seed_along_velocity, seed_chunk_from_kinematics, DerivativeData, PartialsTensor, CHUNK};
use crate::algorithms::crba::crba_after_kinematics;
use crate::error::Result;
use crate::model::Model;

/// Partial derivatives `∂H/∂x_k` of the mass matrix with respect to the `6+N` tangent
/// coordinates `δx = [δr0, δθ, δq]` (module docs), left in `work.mass_matrix_partials[k]`
/// (each `(6+N)²`, symmetric).
///
/// Only the attitude (`k = 3..6`) and the joint coordinates (`k ≥ 6`) matter; the three `δr0`
/// partials are exactly zero. Cost: forward kinematics in `f64`, then `⌈(3+N)/CHUNK⌉` passes
/// of CRBA on dual numbers seeded with the closed-form motion of the bodies.
pub fn mass_matrix_partials<'w>(model: &Model, work: &'w mut DerivativeData, x: &[f64]) -> Result<&'w [DMatrix<f64>]> {
    let (pose, nu) = work.prepare_partials(model, x, PartialsTensor::MassMatrix)?;
    let dirs = &work.config_dirs;
    for k in 0..3 {
        work.mass_matrix_partials[k].fill(0.0);
    }
    for chunk in dirs.chunks(CHUNK) {
        seed_chunk_from_kinematics(model, &work.data, &mut work.chunk, &pose, None, chunk);
        crba_after_kinematics(model, &mut work.chunk.data, true)?;
        let h = &work.chunk.data.mass_matrix;
        for j in 0..nu {
            for i in 0..=j {
                let e = lanes(&h[(i, j)]);
                for (lane, dir) in chunk.iter().enumerate() {
                    let k = dir.tangent_index().expect("configuration direction");
                    work.mass_matrix_partials[k][(i, j)] = e[lane];
                    work.mass_matrix_partials[k][(j, i)] = e[lane];
                }
            }
        }
    }
    Ok(&work.mass_matrix_partials)
}

/// Time derivative `Ḣ = Σ_k ∂H/∂x_k ẋ_k` of the mass matrix along the motion with generalized
/// velocity `u` (the tangent velocity of `x` is `u` itself: `ṙ0 = v0`, attitude rate `ω0` in
/// 𝒥, `q̇`), left in `work.mass_matrix_derivative` (`(6+N)²`, symmetric). One pass of forward
/// kinematics + CRBA on single-lane dual numbers.
pub fn mass_matrix_derivative<'w>(model: &Model, work: &'w mut DerivativeData, x: &[f64], u: &[f64]) -> Result<&'w DMatrix<f64>> {
    let pose = pose_and_velocity(model, x, u)?;
    seed_along_velocity(model, &mut work.single, &pose, u);
    crba_after_kinematics(model, &mut work.single.data, true)?;
    let h = &work.single.data.mass_matrix;
    for (out, v) in work.mass_matrix_derivative.iter_mut().zip(h.iter()) {
        *out = v.eps;
    }
    Ok(&work.mass_matrix_derivative)
}
