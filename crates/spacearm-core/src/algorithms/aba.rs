//! Articulated-body algorithm for forward dynamics, floating base (Featherstone 2008, §9.2,
//! Table 9.6): `u̇ = H⁻¹ (f + Jᵀ w_ext − c)` in O(N) without forming `H`.

use nalgebra::{DVector, Matrix6, Vector6};

use crate::model::data::{Data, DataT};
use crate::error::{Result, SpacearmError};
use crate::model::Model;
use crate::algorithms::rnea::velocity_pass;
use crate::math::scalar::Real;
use crate::math::spatial::{add6_assign, angular, cross_force, dot6, linear, mul6};
use crate::algorithms::wrench::{kinematics_and_loads, ExternalWrench};

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
    kinematics_and_loads(model, data, x, u, "f", f, external)?;
    aba_passes_1_2(model, data, &x[7..], u, f, external)?;
    aba_pass_3(model, data, u, f)?;
    Ok(&data.accel)
}

/// ABA on the kinematics already in `data` (forward kinematics done by the caller at the joint
/// coordinates `q`, `u` and `f` checked; the joints' passive force at `(q, q̇)` is added to `f`,
/// [`crate::algorithms::passive`]): the simulator computes the system CM from the same kinematics before choosing the
/// base wrench, so it runs forward kinematics once per stage. Fills `data.accel`. Any scalar:
/// the one implementation behind [`aba`] and the recorded forward dynamics of [`crate::taped`].
pub(crate) fn aba_after_kinematics<T: Real>(model: &Model, data: &mut DataT<T>, q: &[T], u: &[T], f: &[T]) -> Result<()> {
    aba_passes_1_2(model, data, q, u, f, &[])?;
    aba_pass_3(model, data, u, f)
}

/// [`aba_after_kinematics`] with external wrenches on bodies (checked by the caller): the
/// simulator's plant under a coupling wrench ([`crate::sim::soft_capture`]).
pub(crate) fn aba_with_wrenches_after_kinematics(model: &Model, data: &mut Data, q: &[f64], u: &[f64], f: &[f64], external: &[ExternalWrench]) -> Result<()> {
    aba_passes_1_2(model, data, q, u, f, external)?;
    aba_pass_3(model, data, u, f)
}

/// ABA passes 1 and 2 on the kinematics already in `data`, inputs checked: body velocities,
/// articulated inertias and bias forces folded down to the base. The joint force of each
/// degree of freedom is `f[6 + d]` plus its passive force at `(q, q̇)`.
///
/// Generic over the scalar; its one value test (`D > 0` relative to the size of `Iᴬ`) is a
/// validity check that holds at every state of a valid model, so a recorded tape
/// ([`crate::math::tape`]) takes the branch every state takes.
fn aba_passes_1_2<T: Real>(model: &Model, data: &mut DataT<T>, q: &[T], u: &[T], f: &[T], external: &[ExternalWrench]) -> Result<()> {
    velocity_pass(model, data, u);
    let nb = model.n_bodies();
    // Pass 1: articulated inertias start as rigid-body inertias, bias forces as gyroscopic
    // terms minus external wrenches.
    data.subtree_inertia[..nb].copy_from_slice(&data.spatial_inertia[..nb]);
    for b in 0..nb {
        let v = data.body_velocity[b];
        data.body_force[b] = cross_force(&v, &mul6(&data.spatial_inertia[b], &v));
    }
    for w in external {
        let fw = w.at_base_com(data);
        data.body_force[w.body] -= fw;
    }
    // Pass 2: fold each subtree's articulated inertia into its parent (p < b: split borrows).
    for b in (1..nb).rev() {
        let p = model.links()[b - 1].parent;
        let (head, tail) = data.subtree_inertia.split_at_mut(b);
        let ia = &mut tail[0];
        let pa = data.body_force[b];
        match model.dof_of_body(b) {
            Some(d) => {
                let s = data.motion_subspace[b];
                let u_vec = mul6(ia, &s);
                let d_scalar = dot6(&s, &u_vec);
                if !(d_scalar.value() > 1e-12 * max_abs(ia).max(1e-300)) {
                    return Err(SpacearmError::Singular(format!(
                        "the articulated inertia about joint '{}' (D = {:e})",
                        model.links()[b - 1].joint.name,
                        d_scalar.value()
                    )));
                }
                let mut small_u = f[6 + d] - dot6(&s, &pa);
                if model.has_passive_forces() {
                    let jd = &model.dof_dynamics()[d];
                    small_u -= (q[d] - T::c(jd.rest)) * T::c(jd.stiffness) + u[6 + d] * T::c(jd.damping);
                }
                data.aba_u[b] = u_vec;
                data.aba_d[b] = d_scalar;
                data.aba_small_u[b] = small_u;
                // Iᴬ − U Uᵀ / D in place (Iᴬ of this body is not needed again), column by
                // column; (Uᵢ Uⱼ) / D keeps it exactly symmetric.
                let inv_d = T::one() / d_scalar;
                for (j, col) in ia.as_mut_slice().chunks_exact_mut(6).enumerate() {
                    let uj = u_vec[j];
                    for (e, ui) in col.iter_mut().zip(u_vec.iter()) {
                        *e -= (*ui * uj) * inv_d;
                    }
                }
                let pa_reduced = pa + mul6(ia, &data.velocity_product[b]) + u_vec * (small_u / d_scalar);
                add6_assign(&mut head[p], ia);
                data.body_force[p] += pa_reduced;
            }
            None => {
                add6_assign(&mut head[p], ia);
                data.body_force[p] += pa;
            }
        }
    }
    Ok(())
}

/// Largest `|entry|` of a 6×6 matrix, of the values (two independent running maxima per pair
/// of rows: the same result as a single scan, with half the dependency chain).
#[inline]
fn max_abs<T: Real>(m: &Matrix6<T>) -> f64 {
    let (mut a, mut b) = (0.0_f64, 0.0_f64);
    for pair in m.as_slice().chunks_exact(2) {
        a = a.max(pair[0].value().abs());
        b = b.max(pair[1].value().abs());
    }
    a.max(b)
}

/// ABA pass 3: base acceleration, then joint accelerations outwards; fills `data.accel`.
fn aba_pass_3<T: Real>(model: &Model, data: &mut DataT<T>, u: &[T], f: &[T]) -> Result<()> {
    let nb = model.n_bodies();
    // Base: I^A_0 a0 = f_b − p^A_0.
    let rhs = Vector6::from_column_slice(&f[0..6]) - data.body_force[0];
    let a0 = data.subtree_inertia[0]
        .cholesky()
        .ok_or_else(|| SpacearmError::Singular("the articulated inertia of the base".into()))?
        .solve(&rhs);
    data.body_acceleration[0] = a0;
    // Pass 3: accelerations outwards.
    for b in 1..nb {
        let p = model.links()[b - 1].parent;
        let mut a = data.body_acceleration[p] + data.velocity_product[b];
        if let Some(d) = model.dof_of_body(b) {
            let qdd = (data.aba_small_u[b] - dot6(&data.aba_u[b], &a)) / data.aba_d[b];
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
    Ok(())
}
