//! Jacobians of forward dynamics `u̇ = FD(x, u, f)` and the linearization of the state
//! equation, for LQR/MPC.
//!
//! Forward dynamics is the inverse of inverse dynamics: `ID(x, u, FD(x, u, f)) = f`.
//! Differentiating this identity (`∂ID/∂u̇ = H`) gives, at `u̇ = FD(x, u, f)`,
//!
//! - `∂u̇/∂x = −H⁻¹ ∂ID/∂x`, `∂u̇/∂u = −H⁻¹ ∂ID/∂u` (the partials of RNEA at fixed `u̇`),
//! - `∂u̇/∂f = H⁻¹`,
//!
//! the route of Carpentier & Mansard (2018, "Analytical derivatives of rigid body dynamics
//! algorithms", RSS, §IV) — here with the partials of RNEA (Featherstone §5.3) from dual
//! numbers instead of their analytic recursion.

use nalgebra::{DMatrix, DMatrixView};

use super::{lanes, pose_and_velocity, seed_chunk_from_kinematics, DerivativeData, CHUNK};
use crate::algorithms::dynamics::compute_forward_dynamics_via_mass_matrix;
use crate::error::Result;
use crate::algorithms::kinematics::check_velocity;
use crate::model::Model;
use crate::algorithms::rnea::rnea_after_kinematics;
use crate::math::spatial::skew;

/// Which inputs the `B` matrix of [`linearize`] has columns for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinearizationInputs {
    /// The joint torques `τ` only (N columns): a free-floating system.
    Joints,
    /// The whole generalized force `f = [F0, N0, τ]` (6+N columns): base thrusters too.
    All,
}

/// Jacobians of forward dynamics at `(x, u, f)` (no external wrenches):
/// `(∂u̇/∂x, ∂u̇/∂u, ∂u̇/∂f = H⁻¹)`, each `(6+N)²`, with `x` in tangent coordinates
/// `[δr0, δθ, δq]` (module docs of [`crate::derivatives`]; the `δr0` columns are zero). Left in
/// `work.accel_wrt_configuration`, `work.accel_wrt_velocity`, `work.accel_wrt_force`; the
/// acceleration itself in `work.data.accel`.
///
/// Cost: forward kinematics, CRBA, RNEA and a Cholesky factorization in `f64`, and
/// `⌈(9+2N)/CHUNK⌉` passes of RNEA on dual numbers seeded with the closed-form motion of the
/// bodies (no forward kinematics on dual numbers).
#[allow(clippy::type_complexity)]
pub fn forward_dynamics_derivatives<'w>(
    model: &Model,
    work: &'w mut DerivativeData,
    x: &[f64],
    u: &[f64],
    f: &[f64],
) -> Result<(&'w DMatrix<f64>, &'w DMatrix<f64>, &'w DMatrix<f64>)> {
    let pose = pose_and_velocity(model, x, u)?;
    check_velocity(model, "f", f)?;
    let n = model.n_dof();
    let nu = model.nu();
    // u̇ = H⁻¹ (f − c) in f64; the Cholesky factor of H stays in data.factor.
    compute_forward_dynamics_via_mass_matrix(model, &mut work.data, x, u, f, &[])?;
    let factor = std::mem::take(&mut work.data.factor);
    let chol = nalgebra::Cholesky::pack_dirty(factor);
    work.accel_wrt_force.fill_with_identity();
    chol.solve_mut(&mut work.accel_wrt_force);
    work.data.factor = chol.unpack_dirty();
    // ∂ID/∂(x, u) at fixed u̇, by RNEA on dual numbers.
    for (k, v) in work.chunk.du.iter_mut().enumerate() {
        *v = super::DualChunk::from_re(work.data.accel[k]);
    }
    for (c, chunk) in work.dynamics_dirs.chunks(CHUNK).enumerate() {
        seed_chunk_from_kinematics(model, &work.data, &mut work.chunk, &pose, Some(u), chunk);
        let w = &mut work.chunk;
        rnea_after_kinematics(model, &mut w.data, &w.u, Some(&w.du), &[]);
        for i in 0..nu {
            let e = lanes(&w.data.tau[i]);
            for (lane, v) in e.iter().take(chunk.len()).enumerate() {
                work.id_partials[(i, c * CHUNK + lane)] = *v;
            }
        }
    }
    let dx = 3 + n;
    work.accel_wrt_configuration.columns_mut(0, 3).fill(0.0);
    work.accel_wrt_configuration.columns_mut(3, dx).gemm(-1.0, &work.accel_wrt_force, &work.id_partials.columns(0, dx), 0.0);
    work.accel_wrt_velocity.gemm(-1.0, &work.accel_wrt_force, &work.id_partials.columns(dx, nu), 0.0);
    Ok((&work.accel_wrt_configuration, &work.accel_wrt_velocity, &work.accel_wrt_force))
}

/// Linearization `δż = A δz + B δf` of the first-order state equation `ż = [ẋ; u̇] =
/// [u; FD(x, u, f)]` in the tangent state `δz = [δx (6+N, tangent coordinates); δu (6+N)]`
/// about `(x, u, f)`:
///
/// `A = [[Ω, E], [∂u̇/∂x, ∂u̇/∂u]]`, `B = [[0], [H⁻¹ (columns of the chosen inputs)]]`,
///
/// where `Ω = blkdiag(0₃, ω̃0, 0_N)`: with the world-frame attitude increment
/// `R0 = exp(δθ̃) R̄0`, `Ṙ0 = ω̃0 R0` gives `δθ̇ = δω0 + ω̄0 × δθ` to first order. `A` is
/// `2(6+N)` square; `B` has `6+N` columns (`inputs = All`) or the `N` joint columns
/// (`Joints`). Left in `work.state_matrix` and `work.input_matrix` (all `6+N` columns; the
/// returned view selects the inputs).
pub fn linearize<'w>(
    model: &Model,
    work: &'w mut DerivativeData,
    x: &[f64],
    u: &[f64],
    f: &[f64],
    inputs: LinearizationInputs,
) -> Result<(&'w DMatrix<f64>, DMatrixView<'w, f64>)> {
    forward_dynamics_derivatives(model, work, x, u, f)?;
    let nu = model.nu();
    let a = &mut work.state_matrix;
    a.fill(0.0);
    a.view_mut((0, nu), (nu, nu)).fill_with_identity();
    let w0 = nalgebra::Vector3::new(u[3], u[4], u[5]);
    a.fixed_view_mut::<3, 3>(3, 3).copy_from(&skew(&w0));
    a.view_mut((nu, 0), (nu, nu)).copy_from(&work.accel_wrt_configuration);
    a.view_mut((nu, nu), (nu, nu)).copy_from(&work.accel_wrt_velocity);
    let b = &mut work.input_matrix;
    b.fill(0.0);
    b.view_mut((nu, 0), (nu, nu)).copy_from(&work.accel_wrt_force);
    let view = match inputs {
        LinearizationInputs::All => work.input_matrix.columns(0, nu),
        LinearizationInputs::Joints => work.input_matrix.columns(6, nu - 6),
    };
    Ok((&work.state_matrix, view))
}
