//! Articulated-body algorithm for forward dynamics, floating base (Featherstone 2008, §9.2,
//! Table 9.6): `u̇ = H⁻¹ (f + Jᵀ w_ext − c)` in O(N) without forming `H`.

use nalgebra::{DVector, Vector6};

use crate::data::Data;
use crate::error::{Result, SpacearmError};
use crate::kinematics::{check_velocity, forward_kinematics};
use crate::model::Model;
use crate::rnea::velocity_pass;
use crate::spatial::{angular, cross_force, linear};
use crate::wrench::ExternalWrench;

/// Forward dynamics by ABA: the state derivative `u̇ = [v̇0; ω̇0; q̈]` produced by the generalized
/// force `f = [F0; N0; τ]` (base force at its CM and torque about its CM, in 𝒥; joint torques)
/// and external wrenches. Left in `data.accel`.
pub fn aba<'d>(
    model: &Model,
    data: &'d mut Data,
    x: &[f64],
    u: &[f64],
    f: &[f64],
    external: &[ExternalWrench],
) -> Result<&'d DVector<f64>> {
    forward_kinematics(model, data, x)?;
    check_velocity(model, "u", u)?;
    check_velocity(model, "f", f)?;
    for w in external {
        w.check(model)?;
    }
    velocity_pass(model, data, u);
    let nb = model.n_bodies();
    // Pass 1: articulated inertias start as rigid-body inertias, bias forces as gyroscopic
    // terms minus external wrenches.
    for b in 0..nb {
        let inertia = data.spatial_inertia[b];
        let v = data.body_velocity[b];
        data.subtree_inertia[b] = inertia;
        data.body_force[b] = cross_force(&v, &(inertia * v));
    }
    for w in external {
        let fw = w.at_base_com(data);
        data.body_force[w.body] -= fw;
    }
    // Pass 2: fold each subtree's articulated inertia into its parent.
    for b in (1..nb).rev() {
        let p = model.links[b - 1].parent;
        let ia = data.subtree_inertia[b];
        let pa = data.body_force[b];
        match model.dof_of_body(b) {
            Some(d) => {
                let s = data.motion_subspace[b];
                let u_vec = ia * s;
                let d_scalar = s.dot(&u_vec);
                if !(d_scalar > 1e-12 * ia.abs().max().max(1e-300)) {
                    return Err(SpacearmError::Singular(format!(
                        "the articulated inertia about joint '{}' (D = {d_scalar:e})",
                        model.links[b - 1].joint.name
                    )));
                }
                let small_u = f[6 + d] - s.dot(&pa);
                data.aba_u[b] = u_vec;
                data.aba_d[b] = d_scalar;
                data.aba_small_u[b] = small_u;
                let ia_reduced = ia - u_vec * u_vec.transpose() / d_scalar;
                let pa_reduced = pa + ia_reduced * data.velocity_product[b] + u_vec * (small_u / d_scalar);
                data.subtree_inertia[p] += ia_reduced;
                data.body_force[p] += pa_reduced;
            }
            None => {
                data.subtree_inertia[p] += ia;
                data.body_force[p] += pa;
            }
        }
    }
    // Base: I^A_0 a0 = f_b − p^A_0.
    let rhs = Vector6::from_column_slice(&f[0..6]) - data.body_force[0];
    let a0 = data.subtree_inertia[0]
        .cholesky()
        .ok_or_else(|| SpacearmError::Singular("the articulated inertia of the base".into()))?
        .solve(&rhs);
    data.body_acceleration[0] = a0;
    // Pass 3: accelerations outwards.
    for b in 1..nb {
        let p = model.links[b - 1].parent;
        let mut a = data.body_acceleration[p] + data.velocity_product[b];
        if let Some(d) = model.dof_of_body(b) {
            let qdd = (data.aba_small_u[b] - data.aba_u[b].dot(&a)) / data.aba_d[b];
            data.accel[6 + d] = qdd;
            a += data.motion_subspace[b] * qdd;
        }
        data.body_acceleration[b] = a;
    }
    // Spatial base acceleration back to the classical CM acceleration: v̇0 = a_lin + ω0 × v0.
    let v0 = Vector6::from_column_slice(&u[0..6]);
    let lin = linear(&a0) + angular(&v0).cross(&linear(&v0));
    let ang = angular(&a0);
    data.accel.fixed_rows_mut::<3>(0).copy_from(&lin);
    data.accel.fixed_rows_mut::<3>(3).copy_from(&ang);
    Ok(&data.accel)
}
