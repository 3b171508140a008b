//! Analytic partial derivatives of inverse dynamics (RNEA) with respect to the configuration
//! (tangent coordinates `[δr0, δθ, δq]`) and the generalized velocity `u`, after Carpentier &
//! Mansard (2018, "Analytical derivatives of rigid body dynamics algorithms", RSS, §III),
//! carried into spacearm's conventions: every spatial vector has the axes of 𝒥 and the base
//! CM as reference point, the base velocity `[v0; ω0]` and the base force `[F0; N0]` are held
//! in those axes, and `δθ` turns the whole system about the base CM.
//!
//! # The recursions
//!
//! RNEA (Featherstone §5.3) computes, for every body `i` with parent `λ(i)`, motion subspace
//! `Sᵢ` (zero for a fixed joint) and spatial inertia `Iᵢ`,
//!
//! ```text
//! vᵢ = v_λ + Sᵢ q̇ᵢ,  aᵢ = a_λ + vᵢ ×ₘ Sᵢ q̇ᵢ + Sᵢ q̈ᵢ,  fᵢ = Iᵢ aᵢ + vᵢ ×* Iᵢ vᵢ − f_ext,ᵢ,
//! Fᵢ = Σ_{k ⪰ i} f_k,  τᵢ = Sᵢᵀ Fᵢ,  [F0; N0] = F_0,
//! ```
//!
//! with `v_0 = [v0; ω0]` and `a_0 = [v̇0 − ω0 × v0; ω̇0]`. A change `δq_j` moves the subtree of
//! joint `j` rigidly with the twist `S_j`; `δθ_m` moves every body with the twist `[0; e_m]`
//! while `v_0` and `a_0` (inputs, in 𝒥) stay put, so it acts like a joint `S = [0; e_m]` above
//! the base whose parent has the velocity `v_0` and the acceleration `a_0`. For such a
//! direction `ψ = S_j` with parent quantities `v_λ`, `a_λ`, every moved body obeys
//! `δS_k = ψ ×ₘ S_k`, `δI_k = ψ ×* I_k − I_k ψ ×ₘ`, and (summing the recursions along the path)
//!
//! ```text
//! δv_k = ψ ×ₘ v_k + ψ̇,    ψ̇ = v_λ ×ₘ ψ,
//! δa_k = ψ ×ₘ a_k + ψ̈ + ψ̇ ×ₘ v_k,    ψ̈ = a_λ ×ₘ ψ + v_λ ×ₘ ψ̇,
//! ```
//!
//! (C&M's `∂v/∂q` and `∂a/∂q` columns in world axes). The parts `ψ ×ₘ (·)` move with the body,
//! so Newton–Euler turns them into `ψ ×* f_k`; what remains is linear in `ψ̇` and `ψ̈`:
//!
//! ```text
//! δf_k = ψ ×* f_k + I_k ψ̈ + C_k ψ̇ + E_k ψ,
//! C_k = (v_k ×*) I_k − I_k (v_k ×ₘ) + (I_k v_k)×̄,    (h×̄) w := w ×* h,
//! ```
//!
//! where `C_k` is the body's Coriolis matrix (C&M's `B`) and `E_k ψ = [ω×f; ω×n + p×(ω×f)]`
//! (ω the angular part of ψ) corrects for external wrenches whose force `f` and couple `n` stay
//! fixed in 𝒥 while their application point `p` (from the base CM) moves with the body.
//! Summed over a subtree with the composite inertia `Yᵢ`, composite Coriolis matrix `Bᵢ` and
//! composite `Kᵢ = Σ E_k`, and using `(ψ ×ₘ Sᵢ)ᵀ Fᵢ + Sᵢᵀ (ψ ×* Fᵢ) = 0`:
//!
//! ```text
//! ∂τᵢ/∂q_j = Sᵢᵀ (Yᵢ ψ̈_j + Bᵢ ψ̇_j + Kᵢ S_j)                       i in the subtree of j,
//!          = Sᵢᵀ (S_j ×* F_j + Y_j ψ̈_j + B_j ψ̇_j + K_j S_j)        i a strict ancestor of j,
//! ∂F_0/∂q_j = S_j ×* F_j + Y_j ψ̈_j + B_j ψ̇_j + K_j S_j            (the base's six rows),
//! ```
//!
//! and the same with `ψ = [0; e_m]`, `ψ̇ = v_0 ×ₘ ψ`, `ψ̈ = a_0 ×ₘ ψ + v_0 ×ₘ ψ̇` and the whole
//! tree (`Y_0`, `B_0`, `K_0`, `F_0`) for `δθ_m`. The velocity partials follow the same way:
//! `δq̇_j` gives `δv_k = S_j`, `δa_k = S_j ×ₘ v_k + 2 ψ̇_j`, so `δFᵢ = Bᵢ S_j + 2 Yᵢ ψ̇_j` in the
//! subtree and `B_j S_j + 2 Y_j ψ̇_j` above it; a base velocity component `e` gives
//! `δv_k = e`, `δa_k = e ×ₘ v_k + γ` with `γ = δa_0 − e ×ₘ v_0` (`δa_0` from the `−ω0 × v0`
//! term of `a_0`), so `δFᵢ = Bᵢ e + Yᵢ γ` for every body. Nothing depends on `r0`: the `δr0`
//! columns are zero. The partial with respect to `u̇` is `H` (CRBA).
//!
//! Cost: O(N) 6×6 products for the per-body matrices, then 36 multiply-adds per pair
//! (joint, joint on its path to the base) — O(N·depth), no dual numbers, no allocation.

use nalgebra::{DMatrix, Matrix6, Vector3, Vector6};

use crate::algorithms::kinematics::point_position;
use crate::algorithms::wrench::ExternalWrench;
use crate::math::spatial::{angular, cross_force, cross_motion, dot6, linear, mul6, skew, spatial};
use crate::model::data::Data;
use crate::model::Model;

/// Per-body and per-joint scratch of the analytic RNEA partials (O(N) 6-vectors and 6×6
/// matrices), allocated once with [`super::DerivativeData`].
#[derive(Debug, Clone)]
pub(crate) struct RneaPartialsWork {
    /// Composite spatial inertia `Yᵢ` of each body's subtree.
    composite_inertia: Vec<Matrix6<f64>>,
    /// Composite Coriolis matrix `Bᵢ = Σ C_k` of each body's subtree.
    composite_coriolis: Vec<Matrix6<f64>>,
    /// Composite external-wrench correction `Kᵢ = Σ E_k` (only with external wrenches).
    composite_wrench: Vec<Matrix6<f64>>,
    /// Per joint: `ψ̇_j = v_λ ×ₘ S_j`.
    psi_dot: Vec<Vector6<f64>>,
    /// Per joint: `ψ̈_j = a_λ ×ₘ S_j + v_λ ×ₘ ψ̇_j`.
    psi_ddot: Vec<Vector6<f64>>,
    /// Per joint: `Y_j S_j` (so that `Sᵢᵀ Yᵢ x = (Yᵢ Sᵢ)·x`).
    inertia_row: Vec<Vector6<f64>>,
    /// Per joint: `B_jᵀ S_j`.
    coriolis_row: Vec<Vector6<f64>>,
    /// Per joint: `K_jᵀ S_j`.
    wrench_row: Vec<Vector6<f64>>,
    /// Per joint: `∂F_j/∂q_j = S_j ×* F_j + Y_j ψ̈_j + B_j ψ̇_j + K_j S_j` (what its ancestors see).
    config_force: Vec<Vector6<f64>>,
    /// Per joint: `∂F_j/∂q̇_j = B_j S_j + 2 Y_j ψ̇_j`.
    velocity_force: Vec<Vector6<f64>>,
}

impl RneaPartialsWork {
    pub(crate) fn new(model: &Model) -> Self {
        let (nb, n) = (model.n_bodies(), model.n_dof());
        RneaPartialsWork {
            composite_inertia: vec![Matrix6::zeros(); nb],
            composite_coriolis: vec![Matrix6::zeros(); nb],
            composite_wrench: vec![Matrix6::zeros(); nb],
            psi_dot: vec![Vector6::zeros(); n],
            psi_ddot: vec![Vector6::zeros(); n],
            inertia_row: vec![Vector6::zeros(); n],
            coriolis_row: vec![Vector6::zeros(); n],
            wrench_row: vec![Vector6::zeros(); n],
            config_force: vec![Vector6::zeros(); n],
            velocity_force: vec![Vector6::zeros(); n],
        }
    }
}

/// Coriolis matrix of one body, `C = (v ×*) I − I (v ×ₘ) + (I v)×̄`: the linear map
/// `w ↦ I (w ×ₘ v) + w ×* (I v) + v ×* (I w)`, the first-order change of `I a + v ×* I v`
/// when the velocity changes by `w` and the acceleration by `w ×ₘ v`.
fn coriolis_matrix(inertia: &Matrix6<f64>, v: &Vector6<f64>) -> Matrix6<f64> {
    // (v ×*) = [[ω̃, 0], [ṽ, ω̃]] and (v ×ₘ) = −(v ×*)ᵀ, so with I symmetric
    // −I (v ×ₘ) = I (v ×*)ᵀ = ((v ×*) I)ᵀ: C = X + Xᵀ + (I v)×̄ with X = (v ×*) I. Column by
    // column, X's top half is ω × (top of I's column) and its bottom half
    // v × (top) + ω × (bottom): cross products, no 6×6 product.
    let (lin, ang) = (linear(v), angular(v));
    let mut x = Matrix6::zeros();
    for c in 0..6 {
        let col = inertia.column(c);
        let (top, bottom) = (Vector3::new(col[0], col[1], col[2]), Vector3::new(col[3], col[4], col[5]));
        let xt = ang.cross(&top);
        let xb = lin.cross(&top) + ang.cross(&bottom);
        x.fixed_view_mut::<3, 1>(0, c).copy_from(&xt);
        x.fixed_view_mut::<3, 1>(3, c).copy_from(&xb);
    }
    let h = mul6(inertia, v);
    // (h×̄) w = w ×* h = [w_ang × h_lin; w_ang × h_ang + w_lin × h_lin] = [[0, −h̃_lin], [−h̃_lin, −h̃_ang]] w.
    let (hl, ha) = (skew(&linear(&h)), skew(&angular(&h)));
    let mut out = x + x.transpose();
    for r in 0..3 {
        for c in 0..3 {
            out[(r, 3 + c)] -= hl[(r, c)];
            out[(3 + r, c)] -= hl[(r, c)];
            out[(3 + r, 3 + c)] -= ha[(r, c)];
        }
    }
    out
}

/// `E ψ = [ω × f; ω × n + p × (ω × f)]` as a 6×6 matrix acting on `ψ = [v; ω]`, for a wrench of
/// force `f` and couple `n` (both fixed in 𝒥) applied at `p` (from the base CM) on a body that
/// moves with the twist `ψ`: the difference between the change of the body-fixed spatial force
/// (`ψ ×* f_ext`) and that of the applied one (`[0; δp × f]`).
fn wrench_correction(force: &Vector3<f64>, couple: &Vector3<f64>, p: &Vector3<f64>) -> Matrix6<f64> {
    let f = skew(force);
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-f));
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&(-skew(couple) - skew(p) * f));
    out
}

/// Fill `out` ((6+N) × (9+2N)) with the partials of inverse dynamics at the state whose RNEA
/// is in `data` (forward kinematics, then RNEA at `(u, u̇)` with `external`): columns
/// `[δθ (3), δq (N), δu (6+N)]` (the `δr0` columns, all zero, are left out).
pub(crate) fn fill_rnea_partials(model: &Model, data: &Data, external: &[ExternalWrench], ws: &mut RneaPartialsWork, out: &mut DMatrix<f64>) {
    let nb = model.n_bodies();
    let n = model.n_dof();
    let links = model.links();
    let has_wrench = !external.is_empty();
    // Joints on different branches (neither on the other's path) are not coupled: zeros. The
    // loops below write every other entry, so on a chain (each body the child of the one
    // before) there is nothing to clear.
    let chain = links.iter().enumerate().all(|(k, link)| link.parent == k);
    if !chain {
        out.as_mut_slice().fill(0.0);
    }
    // Backward sweep: composite Y, B (and K), then the per-joint vectors that need them.
    for b in 0..nb {
        let inertia = &data.spatial_inertia[b];
        ws.composite_inertia[b] = *inertia;
        ws.composite_coriolis[b] = coriolis_matrix(inertia, &data.body_velocity[b]);
        if has_wrench {
            ws.composite_wrench[b] = Matrix6::zeros();
        }
    }
    for w in external {
        let p = point_position(data, w.body, &w.offset) - data.base_position;
        ws.composite_wrench[w.body] += wrench_correction(&w.force, &w.torque, &p);
    }
    for b in (0..nb).rev() {
        if b > 0 {
            let p = links[b - 1].parent;
            let (y, c) = (ws.composite_inertia[b], ws.composite_coriolis[b]);
            ws.composite_inertia[p] += y;
            ws.composite_coriolis[p] += c;
            if has_wrench {
                let k = ws.composite_wrench[b];
                ws.composite_wrench[p] += k;
            }
        }
    }
    for b in 1..nb {
        let Some(j) = model.dof_of_body(b) else { continue };
        let p = links[b - 1].parent;
        let s = data.motion_subspace[b];
        let (v_parent, a_parent) = (data.body_velocity[p], data.body_acceleration[p]);
        let psi_dot = cross_motion(&v_parent, &s);
        let psi_ddot = cross_motion(&a_parent, &s) + cross_motion(&v_parent, &psi_dot);
        let (y, bc) = (&ws.composite_inertia[b], &ws.composite_coriolis[b]);
        let y_psi_dot = mul6(y, &psi_dot);
        let mut g = cross_force(&s, &data.body_force[b]) + mul6(y, &psi_ddot) + mul6(bc, &psi_dot);
        if has_wrench {
            g += mul6(&ws.composite_wrench[b], &s);
            ws.wrench_row[j] = ws.composite_wrench[b].tr_mul(&s);
        }
        ws.psi_dot[j] = psi_dot;
        ws.psi_ddot[j] = psi_ddot;
        ws.inertia_row[j] = mul6(y, &s);
        ws.coriolis_row[j] = bc.tr_mul(&s);
        ws.config_force[j] = g;
        ws.velocity_force[j] = mul6(bc, &s) + 2.0 * y_psi_dot;
    }
    let (col_q, col_u) = (3, 3 + n);
    let rows = out.nrows();
    let o = out.as_mut_slice();
    let at = |r: usize, c: usize| c * rows + r;
    // Base rows of the joint columns; joint rows of the pairs (joint k, joint a on k's path).
    for b in 1..nb {
        let Some(k) = model.dof_of_body(b) else { continue };
        let (g, pv) = (ws.config_force[k], ws.velocity_force[k]);
        for r in 0..6 {
            o[at(r, col_q + k)] = g[r];
            o[at(r, col_u + 6 + k)] = pv[r];
        }
        let (sy, sb, sk) = (ws.inertia_row[k], ws.coriolis_row[k], ws.wrench_row[k]);
        let mut a_body = b;
        while a_body != 0 {
            if let Some(a) = model.dof_of_body(a_body) {
                let (pd, pdd) = (ws.psi_dot[a], ws.psi_ddot[a]);
                let s_a = data.motion_subspace[a_body];
                // Row k (in a's subtree), column a.
                let mut dq = dot6(&sy, &pdd) + dot6(&sb, &pd);
                if has_wrench {
                    dq += dot6(&sk, &s_a);
                }
                o[at(6 + k, col_q + a)] = dq;
                o[at(6 + k, col_u + 6 + a)] = dot6(&sb, &s_a) + 2.0 * dot6(&sy, &pd);
                if a != k {
                    // Row a (a strict ancestor of k), column k.
                    o[at(6 + a, col_q + k)] = dot6(&s_a, &g);
                    o[at(6 + a, col_u + 6 + k)] = dot6(&s_a, &pv);
                }
            }
            a_body = links[a_body - 1].parent;
        }
    }
    // The whole tree: the attitude increments and the base velocity components.
    let (v0, a0) = (data.body_velocity[0], data.body_acceleration[0]);
    let (y0, b0) = (&ws.composite_inertia[0], &ws.composite_coriolis[0]);
    let f0 = data.body_force[0];
    for m in 0..3 {
        let mut psi = Vector6::zeros();
        psi[3 + m] = 1.0;
        let psi_dot = cross_motion(&v0, &psi);
        let psi_ddot = cross_motion(&a0, &psi) + cross_motion(&v0, &psi_dot);
        let mut base = cross_force(&psi, &f0) + mul6(y0, &psi_ddot) + mul6(b0, &psi_dot);
        if has_wrench {
            base += mul6(&ws.composite_wrench[0], &psi);
        }
        for r in 0..6 {
            o[at(r, m)] = base[r];
        }
        for b in 1..nb {
            let Some(j) = model.dof_of_body(b) else { continue };
            let mut d = dot6(&ws.inertia_row[j], &psi_ddot) + dot6(&ws.coriolis_row[j], &psi_dot);
            if has_wrench {
                d += dot6(&ws.wrench_row[j], &psi);
            }
            o[at(6 + j, m)] = d;
        }
    }
    let (lin_v0, ang_w0) = (linear(&v0), angular(&v0));
    for k in 0..6 {
        let mut e = Vector6::zeros();
        e[k] = 1.0;
        // δa_0 = [−(δω0 × v0 + ω0 × δv0); 0] from a_0 = [v̇0 − ω0 × v0; ω̇0].
        let (dv, dw) = (linear(&e), angular(&e));
        let da0 = spatial(&(-(dw.cross(&lin_v0) + ang_w0.cross(&dv))), &Vector3::zeros());
        let gamma = da0 - cross_motion(&e, &v0);
        let base = b0.column(k) + mul6(y0, &gamma);
        for r in 0..6 {
            o[at(r, col_u + k)] = base[r];
        }
        for b in 1..nb {
            let Some(j) = model.dof_of_body(b) else { continue };
            o[at(6 + j, col_u + k)] = ws.coriolis_row[j][k] + dot6(&ws.inertia_row[j], &gamma);
        }
    }
}
