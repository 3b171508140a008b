//! Composite-rigid-body algorithm for the joint-space mass matrix `H` (Featherstone 2008,
//! §6.2, Table 6.2), floating-base form.
//!
//! The second, independent computation of `H` (the first is [`crate::algorithms::inertia`]). Because all
//! spatial quantities share one reference point (the base CM) and world axes, the force
//! `F = Iᶜᵢ Sᵢ` needs no transform on its way up the tree, and the base block of the floating
//! joint is the identity: `H0 = Iᶜ₀`, `H0m[:, i] = Iᶜᵢ Sᵢ`.

use nalgebra::DMatrix;

use crate::model::data::{Data, DataT};
use crate::error::Result;
use crate::algorithms::kinematics::forward_kinematics;
use crate::model::Model;
use crate::math::scalar::Real;
use crate::math::spatial::{add6_assign, dot6, mul6};

/// Mass matrix `H(x)` ((6+N)², symmetric) by CRBA; the result is also left in
/// `data.mass_matrix` and the composite inertias in `data.subtree_inertia`.
pub fn crba<'d>(model: &Model, data: &'d mut Data, x: &[f64]) -> Result<&'d DMatrix<f64>> {
    forward_kinematics(model, data, x)?;
    crba_after_kinematics(model, data, true)?;
    Ok(&data.mass_matrix)
}

/// CRBA on the kinematics already in `data`, for any scalar. With `joint_block == false` only the base rows and
/// columns `[H0, H0m]` (and their transpose) are filled, in O(N): that is all the momentum map
/// and `J*` need; the joint block `H_m` is then left stale. Sizes `data.mass_matrix` on first
/// use (refused by [`crate::admission`] when too large).
pub(crate) fn crba_after_kinematics<T: Real>(model: &Model, data: &mut DataT<T>, joint_block: bool) -> Result<()> {
    data.ensure_mass_matrix()?;
    let nb = model.n_bodies();
    let nu = model.nu();
    data.subtree_inertia[..nb].copy_from_slice(&data.spatial_inertia[..nb]);
    let h = data.mass_matrix.as_mut_slice();
    if joint_block {
        h.fill(T::zero());
    }
    for b in (1..nb).rev() {
        let p = model.links()[b - 1].parent;
        let composite = data.subtree_inertia[b];
        add6_assign(&mut data.subtree_inertia[p], &composite);
        let Some(d) = model.dof_of_body(b) else { continue };
        let s = data.motion_subspace[b];
        let f = mul6(&composite, &s);
        let col = 6 + d;
        // H is column-major: entry (r, c) at c * nu + r.
        for r in 0..6 {
            h[col * nu + r] = f[r];
            h[r * nu + col] = f[r];
        }
        if !joint_block {
            continue;
        }
        h[col * nu + col] = dot6(&s, &f);
        // Walk to the base: every joint on the path couples with this one.
        let mut a = p;
        while a != 0 {
            if let Some(e) = model.dof_of_body(a) {
                let v = dot6(&data.motion_subspace[a], &f);
                h[col * nu + 6 + e] = v;
                h[(6 + e) * nu + col] = v;
            }
            a = model.links()[a - 1].parent;
        }
    }
    let h0 = data.subtree_inertia[0];
    data.mass_matrix.fixed_view_mut::<6, 6>(0, 0).copy_from(&h0);
    Ok(())
}
