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
//! algorithms", RSS, §IV), with the partials of RNEA from their analytic recursions
//! ([`super::rnea_partials`]) or, as the test oracle, from dual numbers.

use nalgebra::{DMatrix, DMatrixView};

use super::rnea_partials::fill_rnea_partials;
use super::dual::{lanes, pose_and_velocity, seed_chunk, seed_chunk_from_kinematics, DerivativeData, Pose, CHUNK};
use crate::algorithms::kinematics::forward_kinematics;
use crate::algorithms::wrench::{check_loads, ExternalWrench};
use super::dense::{neg_product, spd_inverse};
use crate::algorithms::crba::crba_after_kinematics;
use crate::algorithms::kinematics::forward_kinematics_at;
use crate::error::{Result, SpacearmError};
use crate::model::Model;
use crate::algorithms::passive::add_joint_passive_forces;
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

/// How the partials of inverse dynamics are computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DerivativeMethod {
    /// The analytic recursions of Carpentier & Mansard ([`super::rnea_partials`]): O(N·depth).
    #[default]
    Analytic,
    /// Forward-mode automatic differentiation of RNEA on dual numbers, [`CHUNK`] directions per
    /// pass: the independent route the tests hold the analytic one against.
    DualNumbers,
}

/// Jacobians of forward dynamics at `(x, u, f)` (no external wrenches):
/// `(∂u̇/∂x, ∂u̇/∂u, ∂u̇/∂f = H⁻¹)`, each `(6+N)²`, with `x` in tangent coordinates
/// `[δr0, δθ, δq]` (module docs of [`crate::derivatives`]; the `δr0` columns are zero). Left in
/// `work.accel_wrt_configuration`, `work.accel_wrt_velocity`, `work.accel_wrt_force`; the
/// acceleration itself in `work.data.accel`. Analytic route; see
/// [`forward_dynamics_derivatives_with`].
#[allow(clippy::type_complexity)]
pub fn forward_dynamics_derivatives<'w>(
    model: &Model,
    work: &'w mut DerivativeData,
    x: &[f64],
    u: &[f64],
    f: &[f64],
) -> Result<(&'w DMatrix<f64>, &'w DMatrix<f64>, &'w DMatrix<f64>)> {
    forward_dynamics_derivatives_with(model, work, x, u, f, &[], DerivativeMethod::Analytic)
}

/// [`forward_dynamics_derivatives`] with external wrenches (`H u̇ + c = f + Jᵀ w_ext`; each
/// wrench's force and couple held fixed in 𝒥 while its application point moves with its body)
/// and a choice of route for the partials of inverse dynamics.
///
/// Cost: forward kinematics, CRBA and RNEA in `f64`, `H⁻¹` by Cholesky ([`super::dense`]), the partials of RNEA (analytic: O(N·depth); dual: `⌈(9+2N)/CHUNK⌉` passes of RNEA on
/// dual numbers), and one `(6+N) × (6+N) × (9+2N)` matrix product.
#[allow(clippy::type_complexity)]
pub fn forward_dynamics_derivatives_with<'w>(
    model: &Model,
    work: &'w mut DerivativeData,
    x: &[f64],
    u: &[f64],
    f: &[f64],
    external: &[ExternalWrench],
    method: DerivativeMethod,
) -> Result<(&'w DMatrix<f64>, &'w DMatrix<f64>, &'w DMatrix<f64>)> {
    let pose = pose_and_velocity(model, x, u)?;
    check_loads(model, "f", f, external)?;
    let n = model.n_dof();
    let nu = model.nu();
    // H and c − Jᵀ w in f64, H⁻¹ (kept: it is ∂u̇/∂f), u̇ = H⁻¹ (f + Jᵀ w − c).
    forward_kinematics_at(model, &mut work.data, &pose.r0, &pose.base_to_world, pose.q);
    rnea_after_kinematics(model, &mut work.data, u, None, external);
    crba_after_kinematics(model, &mut work.data, true)?;
    if !spd_inverse(&work.data.mass_matrix, &mut work.dense_scratch, &mut work.accel_wrt_force) {
        return Err(SpacearmError::Singular("the mass matrix H".into()));
    }
    for ((a, fi), c) in work.data.accel.iter_mut().zip(f).zip(work.data.tau.iter()) {
        *a = fi - c;
    }
    add_joint_passive_forces(model, pose.q, &u[6..], &mut work.data.accel.as_mut_slice()[6..]);
    work.du_scratch.gemv(1.0, &work.accel_wrt_force, &work.data.accel, 0.0);
    work.data.accel.copy_from(&work.du_scratch);
    // ∂ID/∂(x, u) at fixed u̇ (= work.du_scratch).
    fill_id_partials(model, work, &pose, u, external, method);
    let dx = 3 + n;
    work.accel_wrt_configuration.columns_mut(0, 3).fill(0.0);
    neg_product(&work.accel_wrt_force, work.id_partials.columns(0, dx), work.accel_wrt_configuration.columns_mut(3, dx));
    neg_product(&work.accel_wrt_force, work.id_partials.columns(dx, nu), work.accel_wrt_velocity.columns_mut(0, nu));
    Ok((&work.accel_wrt_configuration, &work.accel_wrt_velocity, &work.accel_wrt_force))
}

/// Partials of inverse dynamics `ID(x, u, u̇) = H u̇ + c − Q_passive − Jᵀ w_ext` at `(x, u, u̇)`:
/// `(∂ID/∂x, ∂ID/∂u)`, each `(6+N)²`, `x` in tangent coordinates `[δr0, δθ, δq]` (the `δr0`
/// columns are zero); `∂ID/∂u̇ = H`. External wrenches keep their force and couple fixed in 𝒥
/// while their application point moves with its body. Left in `work.id_wrt_configuration` and
/// `work.id_wrt_velocity`.
pub fn inverse_dynamics_partials<'w>(
    model: &Model,
    work: &'w mut DerivativeData,
    x: &[f64],
    u: &[f64],
    du: &[f64],
    external: &[ExternalWrench],
    method: DerivativeMethod,
) -> Result<(&'w DMatrix<f64>, &'w DMatrix<f64>)> {
    let pose = pose_and_velocity(model, x, u)?;
    check_loads(model, "du", du, external)?;
    forward_kinematics(model, &mut work.data, x)?;
    work.du_scratch.copy_from_slice(du);
    fill_id_partials(model, work, &pose, u, external, method);
    let (n, nu) = (model.n_dof(), model.nu());
    work.id_wrt_configuration.columns_mut(0, 3).fill(0.0);
    work.id_wrt_configuration.columns_mut(3, 3 + n).copy_from(&work.id_partials.columns(0, 3 + n));
    work.id_wrt_velocity.copy_from(&work.id_partials.columns(3 + n, nu));
    Ok((&work.id_wrt_configuration, &work.id_wrt_velocity))
}

/// `work.id_partials` ← the partials of inverse dynamics at `(x, u, u̇ = work.du_scratch)`,
/// columns `[δθ (3), δq (N), δu (6+N)]`, the joints' springs and dampers included
/// (`∂(−Q_passive)/∂q = K`, `∂(−Q_passive)/∂q̇ = C`, diagonal; [`crate::algorithms::passive`]). Requires forward kinematics in `work.data`; validated
/// inputs.
fn fill_id_partials(model: &Model, work: &mut DerivativeData, pose: &Pose, u: &[f64], external: &[ExternalWrench], method: DerivativeMethod) {
    match method {
        DerivativeMethod::Analytic => {
            rnea_after_kinematics(model, &mut work.data, u, Some(work.du_scratch.as_slice()), external);
            fill_rnea_partials(model, &work.data, external, &mut work.rnea, &mut work.id_partials);
        }
        DerivativeMethod::DualNumbers => {
            for (k, v) in work.chunk.du.iter_mut().enumerate() {
                *v = super::dual::DualChunk::from_re(work.du_scratch[k]);
            }
            for (c, chunk) in work.dynamics_dirs.chunks(CHUNK).enumerate() {
                if external.is_empty() {
                    seed_chunk_from_kinematics(model, &work.data, &mut work.chunk, pose, Some(u), chunk);
                } else {
                    // The wrenches read the poses, which only forward kinematics on duals moves.
                    seed_chunk(model, &mut work.chunk, pose, Some(u), chunk);
                }
                let w = &mut work.chunk;
                rnea_after_kinematics(model, &mut w.data, &w.u, Some(&w.du), external);
                for i in 0..model.nu() {
                    let e = lanes(&w.data.tau[i]);
                    for (lane, v) in e.iter().take(chunk.len()).enumerate() {
                        work.id_partials[(i, c * CHUNK + lane)] = *v;
                    }
                }
            }
        }
    }
    if model.has_passive_forces() {
        let n = model.n_dof();
        for (j, jd) in model.dof_dynamics().iter().enumerate() {
            work.id_partials[(6 + j, 3 + j)] += jd.stiffness;
            work.id_partials[(6 + j, 3 + n + 6 + j)] += jd.damping;
        }
    }
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
    linearize_with(model, work, x, u, f, inputs, DerivativeMethod::Analytic)
}

/// [`linearize`] with a choice of route for the partials of inverse dynamics.
pub fn linearize_with<'w>(
    model: &Model,
    work: &'w mut DerivativeData,
    x: &[f64],
    u: &[f64],
    f: &[f64],
    inputs: LinearizationInputs,
    method: DerivativeMethod,
) -> Result<(&'w DMatrix<f64>, DMatrixView<'w, f64>)> {
    forward_dynamics_derivatives_with(model, work, x, u, f, &[], method)?;
    let nu = model.nu();
    let a = &mut work.state_matrix;
    // The bottom half is overwritten below; the top half is [[Ω, E]].
    a.view_mut((0, 0), (nu, 2 * nu)).fill(0.0);
    a.view_mut((0, nu), (nu, nu)).fill_with_identity();
    let w0 = nalgebra::Vector3::new(u[3], u[4], u[5]);
    a.fixed_view_mut::<3, 3>(3, 3).copy_from(&skew(&w0));
    a.view_mut((nu, 0), (nu, nu)).copy_from(&work.accel_wrt_configuration);
    a.view_mut((nu, nu), (nu, nu)).copy_from(&work.accel_wrt_velocity);
    let b = &mut work.input_matrix;
    b.view_mut((0, 0), (nu, nu)).fill(0.0);
    b.view_mut((nu, 0), (nu, nu)).copy_from(&work.accel_wrt_force);
    let view = match inputs {
        LinearizationInputs::All => work.input_matrix.columns(0, nu),
        LinearizationInputs::Joints => work.input_matrix.columns(6, nu - 6),
    };
    Ok((&work.state_matrix, view))
}
