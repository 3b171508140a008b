//! Composite-rigid-body algorithm for the joint-space mass matrix `H` (Featherstone 2008,
//! §6.2, Table 6.2), floating-base form.
//!
//! The second, independent computation of `H` (the first is [`crate::inertia`]). Because all
//! spatial quantities share one reference point (the base CM) and world axes, the force
//! `F = Iᶜᵢ Sᵢ` needs no transform on its way up the tree, and the base block of the floating
//! joint is the identity: `H0 = Iᶜ₀`, `H0m[:, i] = Iᶜᵢ Sᵢ`.

use nalgebra::{DMatrix, Vector6};

use crate::data::Data;
use crate::error::Result;
use crate::kinematics::forward_kinematics;
use crate::model::Model;

/// Mass matrix `H(x)` ((6+N)², symmetric) by CRBA; the result is also left in
/// `data.mass_matrix` and the composite inertias in `data.subtree_inertia`.
pub fn crba<'d>(model: &Model, data: &'d mut Data, x: &[f64]) -> Result<&'d DMatrix<f64>> {
    forward_kinematics(model, data, x)?;
    let nb = model.n_bodies();
    data.subtree_inertia[..nb].copy_from_slice(&data.spatial_inertia[..nb]);
    data.mass_matrix.fill(0.0);
    for b in (1..nb).rev() {
        let p = model.links[b - 1].parent;
        let composite = data.subtree_inertia[b];
        data.subtree_inertia[p] += composite;
        let Some(d) = model.dof_of_body(b) else { continue };
        let f: Vector6<f64> = composite * data.motion_subspace[b];
        data.mass_matrix[(6 + d, 6 + d)] = data.motion_subspace[b].dot(&f);
        // Walk to the base: every joint on the path couples with this one.
        let mut a = p;
        while a != 0 {
            if let Some(e) = model.dof_of_body(a) {
                let h = data.motion_subspace[a].dot(&f);
                data.mass_matrix[(6 + e, 6 + d)] = h;
                data.mass_matrix[(6 + d, 6 + e)] = h;
            }
            a = model.links[a - 1].parent;
        }
        for r in 0..6 {
            data.mass_matrix[(r, 6 + d)] = f[r];
            data.mass_matrix[(6 + d, r)] = f[r];
        }
    }
    let h0 = data.subtree_inertia[0];
    data.mass_matrix.fixed_view_mut::<6, 6>(0, 0).copy_from(&h0);
    Ok(&data.mass_matrix)
}
