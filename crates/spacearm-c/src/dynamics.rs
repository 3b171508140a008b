//! Every GJM quantity and the forward and inverse dynamics, one thin entry point per core
//! function (docs/c-api.md, "Quantities"; the equations: docs/physics.md).
//!
//! Layouts (docs/conventions.md): `x = [r0, quat0 (x, y, z, w), q]` (7 + N), `u = [v0, ω0, q̇]`
//! (6 + N), `f = [F0, N0, τ]` (6 + N), every vector in the inertial frame 𝒥, spatial vectors
//! linear first. Every matrix is written **row-major** into a caller-owned buffer: element
//! `(i, j)` of an `r × c` matrix at `out[i * c + j]`.

use nalgebra::{Vector3, Vector6};
use spacearm_core::algorithms::{aba, crba, inertia, kinematics, momentum, rnea};
use spacearm_core::gjm;
use spacearm_core::{Data, Model};

use crate::model::{model_ref, SpacearmModel};
use crate::status::{guard, input, optional_input, output, put, put_optional, put_row_major, Outcome, SpacearmStatus};

fn vec3(v: &[f64]) -> Vector3<f64> {
    Vector3::new(v[0], v[1], v[2])
}

/// A point's body and offset from the caller.
///
/// # Safety
/// `offset` 3 readable doubles.
unsafe fn point(m: &SpacearmModel, body: usize, offset: *const f64) -> Outcome<Vector3<f64>> {
    kinematics::check_body(&m.model, body)?;
    // SAFETY: the caller's contract.
    Ok(vec3(unsafe { input(offset, 3, "offset") }?))
}

/// The body of an entry point that computes from the state, under [`guard`]: the handle, then
/// `x` (7+N doubles) are checked, in that order, and `body` runs with them (it checks the other
/// arguments, in the order of the signature).
///
/// # Safety
/// `model` NULL or a live handle; `x` NULL or 7+N readable doubles.
unsafe fn at_state(model: *const SpacearmModel, x: *const f64, body: impl FnOnce(&SpacearmModel, &[f64]) -> Outcome) -> SpacearmStatus {
    guard(|| {
        // SAFETY (this block and below): the caller's contract.
        let m = unsafe { model_ref(model) }?;
        body(m, unsafe { input(x, m.model.nx(), "x") }?)
    })
}

/// [`at_state`] for an entry point of one output: the (6+N)-vectors `vectors` (`(pointer, name)`, in order: `u`, then `f` or `du`), then
/// the output (`(pointer, name)`, `out_len` of the model doubles) are checked — the first bad
/// one is the error reported — and `write` runs on the handle's workspace.
///
/// # Safety
/// `model` NULL or a live handle; every pointer NULL or of its length.
unsafe fn state_entry<const V: usize>(
    model: *const SpacearmModel,
    x: *const f64,
    vectors: [(*const f64, &str); V],
    (out, out_name): (*mut f64, &str),
    out_len: fn(&Model) -> usize,
    write: impl FnOnce(&Model, &mut Data, &[f64], [&[f64]; V], &mut [f64]) -> Outcome,
) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract.
    unsafe {
        at_state(model, x, |m, x| {
            let mut inputs: [&[f64]; V] = [&[]; V];
            for (value, (p, name)) in inputs.iter_mut().zip(vectors) {
                *value = input(p, m.model.nu(), name)?;
            }
            let out = output(out, out_len(&m.model), out_name)?;
            m.with_data(|model, data| write(model, data, x, inputs, out))
        })
    }
}

/// The mass matrix `H` ((6+N)×(6+N), row-major; paper eq. 36) by CRBA.
///
/// # Safety
/// `model` a live handle; `x` 7+N doubles; `h_out` (6+N)² writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_mass_matrix(model: *const SpacearmModel, x: *const f64, h_out: *mut f64) -> SpacearmStatus {
    // SAFETY: the caller's contract, documented above.
    unsafe {
        state_entry(model, x, [], (h_out, "h_out"), |m| m.nu() * m.nu(), |model, data, x, [], out| {
            put_row_major("the mass matrix H", crba::crba(model, data, x)?, out)
        })
    }
}

/// The blocks of `H` in the paper's form (eqs. 30, 31, 34): `H0` (6×6), `H0m` (6×N) and `H_m`
/// (N×N), row-major. Any output may be NULL (not written).
///
/// # Safety
/// `model` a live handle; `x` 7+N doubles; each output NULL or of its size.
#[no_mangle]
pub unsafe extern "C" fn spacearm_inertia_blocks(model: *const SpacearmModel, x: *const f64, h0_out: *mut f64, h0m_out: *mut f64, hm_out: *mut f64) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe {
        at_state(model, x, |m, x| {
            let blocks = m.with_data(|model, data| inertia::inertia_blocks(model, data, x))?;
            put_optional("H0", &blocks.h0, h0_out)?;
            put_optional("H0m", &blocks.h0m, h0m_out)?;
            put_optional("H_m", &blocks.hm, hm_out)
        })
    }
}

/// The generalized inertia matrix `H* = H_m − H0mᵀ H0⁻¹ H0m` (N×N, row-major; paper eq. 45).
///
/// # Safety
/// `model` a live handle; `x` 7+N doubles; `out` N² writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_generalized_inertia(model: *const SpacearmModel, x: *const f64, out: *mut f64) -> SpacearmStatus {
    // SAFETY: the caller's contract, documented above.
    unsafe {
        state_entry(model, x, [], (out, "out"), |m| m.n_dof() * m.n_dof(), |model, data, x, [], out| {
            put_row_major("the generalized inertia H*", gjm::compute_generalized_inertia(model, data, x)?, out)
        })
    }
}

/// The generalized Jacobian `J*` (6×N, row-major, linear rows first; paper eq. 110) of the
/// point fixed to `body` at `offset` (body frame, from the body's CM; see
/// `spacearm_model_point`).
///
/// # Safety
/// `model` a live handle; `x` 7+N doubles; `offset` 3 doubles; `out` 6N writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_generalized_jacobian(model: *const SpacearmModel, x: *const f64, body: usize, offset: *const f64, out: *mut f64) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe {
        at_state(model, x, |m, x| {
            let p = point(m, body, offset)?;
            let out = output(out, 6 * m.model.n_dof(), "out")?;
            m.with_data(|model, data| put_row_major("the generalized Jacobian J*", gjm::compute_generalized_jacobian(model, data, x, body, &p)?, out))
        })
    }
}

/// The bias forces `c(x, u)` (6+N): Coriolis and centrifugal terms of `H u̇ + c = f`.
///
/// # Safety
/// `model` a live handle; `x` 7+N, `u` 6+N doubles; `out` 6+N writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_bias_forces(model: *const SpacearmModel, x: *const f64, u: *const f64, out: *mut f64) -> SpacearmStatus {
    // SAFETY: the caller's contract, documented above.
    unsafe {
        state_entry(model, x, [(u, "u")], (out, "out"), Model::nu, |model, data, x, [u], out| {
            put("the bias forces c", rnea::bias_forces(model, data, x, u)?.as_slice(), out)
        })
    }
}

/// The generalized bias `c* = c_m − H0mᵀ H0⁻¹ c0` (N; paper eq. 46, the base velocity `u[0..6]`
/// taken as given).
///
/// # Safety
/// `model` a live handle; `x` 7+N, `u` 6+N doubles; `out` N writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_generalized_bias(model: *const SpacearmModel, x: *const f64, u: *const f64, out: *mut f64) -> SpacearmStatus {
    // SAFETY: the caller's contract, documented above.
    unsafe {
        state_entry(model, x, [(u, "u")], (out, "out"), Model::n_dof, |model, data, x, [u], out| {
            put("the generalized bias c*", gjm::compute_generalized_bias(model, data, x, u)?.as_slice(), out)
        })
    }
}

/// Forward dynamics by ABA: `u̇` (6+N) from the generalized force `f = [F0, N0, τ]` (6+N; base
/// force at the base CM and torque about it, in 𝒥).
///
/// # Safety
/// `model` a live handle; `x` 7+N, `u` and `f` 6+N doubles; `du_out` 6+N writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_forward_dynamics(model: *const SpacearmModel, x: *const f64, u: *const f64, f: *const f64, du_out: *mut f64) -> SpacearmStatus {
    // SAFETY: the caller's contract, documented above.
    unsafe {
        state_entry(model, x, [(u, "u"), (f, "f")], (du_out, "du_out"), Model::nu, |model, data, x, [u, f], out| {
            put("forward dynamics du_out", aba::aba(model, data, x, u, f, &[])?.as_slice(), out)
        })
    }
}

/// Reduced (GJM) forward dynamics: `q̈ = H*⁻¹ (τ − c* − H0mᵀ H0⁻¹ F_b)`,
/// `ẍ0 = H0⁻¹ (F_b − H0m q̈ − c0)` (docs/physics.md), written as the full `u̇` (6+N). `tau` is
/// N joint torques; `base_wrench` `[F0, N0]` (6) or NULL for a free-floating base (`F_b = 0`).
///
/// # Safety
/// `model` a live handle; `x` 7+N, `u` 6+N, `tau` N doubles; `base_wrench` NULL or 6 doubles;
/// `du_out` 6+N writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_reduced_forward_dynamics(model: *const SpacearmModel, x: *const f64, u: *const f64, tau: *const f64, base_wrench: *const f64, du_out: *mut f64) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe {
        at_state(model, x, |m, x| {
            let (nu, n) = (m.model.nu(), m.model.n_dof());
            let (u, tau) = (input(u, nu, "u")?, input(tau, n, "tau")?);
            let w = optional_input(base_wrench, 6, "base_wrench")?.map(Vector6::from_column_slice).unwrap_or_else(Vector6::zeros);
            let out = output(du_out, nu, "du_out")?;
            m.with_data(|model, data| put("reduced forward dynamics du_out", gjm::compute_reduced_forward_dynamics(model, data, x, u, tau, &w)?.as_slice(), out))
        })
    }
}

/// Inverse dynamics by RNEA: the generalized force `f = H u̇ + c` (6+N) that produces `du`.
///
/// # Safety
/// `model` a live handle; `x` 7+N, `u` and `du` 6+N doubles; `f_out` 6+N writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_inverse_dynamics(model: *const SpacearmModel, x: *const f64, u: *const f64, du: *const f64, f_out: *mut f64) -> SpacearmStatus {
    // SAFETY: the caller's contract, documented above.
    unsafe {
        state_entry(model, x, [(u, "u"), (du, "du")], (f_out, "f_out"), Model::nu, |model, data, x, [u, du], out| {
            put("inverse dynamics f_out", rnea::rnea(model, data, x, u, du, &[])?.as_slice(), out)
        })
    }
}

/// The system's momenta at `(x, u)`, 9 doubles: linear momentum `P` (N·s), angular momentum
/// about the origin of 𝒥 and about the system CM (N·m·s), all in 𝒥 (paper eq. 27).
///
/// # Safety
/// `model` a live handle; `x` 7+N, `u` 6+N doubles; `out` 9 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_momentum(model: *const SpacearmModel, x: *const f64, u: *const f64, out: *mut f64) -> SpacearmStatus {
    // SAFETY: the caller's contract, documented above.
    unsafe {
        state_entry(model, x, [(u, "u")], (out, "out"), |_| 9, |model, data, x, [u], out| {
            let p = momentum::momentum(model, data, x, u)?;
            let mut all = [0.0; 9];
            all[0..3].copy_from_slice(p.linear.as_slice());
            all[3..6].copy_from_slice(p.angular_about_origin.as_slice());
            all[6..9].copy_from_slice(p.angular_about_com.as_slice());
            put("the momenta", &all, out)
        })
    }
}

/// The momentum map: the base velocity `[v0, ω0] = H0⁻¹ (M0 − H0m q̇)` (6; paper eqs. 42–43, 109)
/// that gives the system linear momentum `p` (3) and angular momentum `l` (3, about the origin
/// of 𝒥) while the joints move at `qd` (N).
///
/// # Safety
/// `model` a live handle; `x` 7+N, `qd` N, `p` and `l` 3 doubles; `out` 6 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_base_velocity_from_momentum(model: *const SpacearmModel, x: *const f64, qd: *const f64, p: *const f64, l: *const f64, out: *mut f64) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe {
        at_state(model, x, |m, x| {
            let qd = input(qd, m.model.n_dof(), "qd")?;
            let (p, l) = (vec3(input(p, 3, "p")?), vec3(input(l, 3, "l")?));
            let out = output(out, 6, "out")?;
            let v = m.with_data(|model, data| gjm::base_velocity_from_momentum(model, data, x, qd, &p, &l))?;
            put("the base velocity", v.as_slice(), out)
        })
    }
}

/// The pose of the point fixed to `body` at `offset`: its position in 𝒥 (3) and its body's
/// rotation body→𝒥 (3×3, row-major). Either output may be NULL.
///
/// # Safety
/// `model` a live handle; `x` 7+N, `offset` 3 doubles; `position_out` NULL or 3 and
/// `rotation_out` NULL or 9 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_point_pose(model: *const SpacearmModel, x: *const f64, body: usize, offset: *const f64, position_out: *mut f64, rotation_out: *mut f64) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe {
        at_state(model, x, |m, x| {
            let p = point(m, body, offset)?;
            let (pos, rot) = m.with_data(|model, data| -> Outcome<_> {
                kinematics::forward_kinematics(model, data, x)?;
                Ok((kinematics::point_position(data, body, &p), data.body_to_world[body]))
            })?;
            put_optional("the point's position", &pos, position_out)?;
            put_optional("the body's rotation", &rot, rotation_out)
        })
    }
}

/// Jacobians of forward dynamics at `(x, u, f)`: `∂u̇/∂x`, `∂u̇/∂u`, `∂u̇/∂f = H⁻¹`, each
/// (6+N)×(6+N) row-major, with `x` in tangent coordinates `[δr0, δθ, δq]` (docs/derivatives.md;
/// the `δr0` columns are zero). Any output may be NULL (not written); all three NULL is a valid
/// call that writes nothing (the inputs are still checked).
///
/// # Safety
/// `model` a live handle; `x` 7+N, `u` and `f` 6+N doubles; each output NULL or (6+N)²
/// writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_forward_dynamics_derivatives(model: *const SpacearmModel, x: *const f64, u: *const f64, f: *const f64, d_dx_out: *mut f64, d_du_out: *mut f64, d_df_out: *mut f64) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe {
        at_state(model, x, |m, x| {
            let (u, f) = (input(u, m.model.nu(), "u")?, input(f, m.model.nu(), "f")?);
            // Every output NULL is a valid call (the header allows each to be NULL): the inputs
            // are still checked and the derivatives computed, nothing is written.
            m.with_derivatives(|model, work| {
                let (a, b, c) = spacearm_core::derivatives::forward_dynamics_derivatives(model, work, x, u, f)?;
                put_optional("d_dx_out", a, d_dx_out)?;
                put_optional("d_du_out", b, d_du_out)?;
                put_optional("d_df_out", c, d_df_out)
            })
        })
    }
}
