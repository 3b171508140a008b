//! Recursive Newton–Euler algorithm: inverse dynamics and the bias vector `c(x, u)`
//! (Featherstone 2008, §5.3, Table 5.1), floating-base form.
//!
//! Spatial quantities use world axes and the base CM as reference point, so the base velocity
//! is `V0 = [v0; ω0]`. The base CM acceleration `v̇0` of the state derivative is classical; the
//! spatial acceleration of the base at its (instantaneous) CM is `[v̇0 − ω0 × v0; ω̇0]`.

use nalgebra::{DVector, Vector6};

use crate::model::data::{Data, DataT};
use crate::error::Result;
use crate::algorithms::kinematics::{check_velocity, forward_kinematics};
use crate::model::Model;
use crate::math::scalar::Real;
use crate::math::spatial::{angular, cross_force, cross_motion, dot6, linear, mul6, spatial};
use crate::algorithms::passive::subtract_joint_passive_forces;
use crate::algorithms::wrench::ExternalWrench;

/// Forward pass of body velocities `Vᵢ = V_λ(i) + Sᵢ q̇ᵢ` and velocity-product accelerations
/// `Vᵢ ×ₘ Sᵢ q̇ᵢ`. Requires forward kinematics; `u` must be checked.
pub(crate) fn velocity_pass<T: Real>(model: &Model, data: &mut DataT<T>, u: &[T]) {
    data.body_velocity[0] = Vector6::from_column_slice(&u[0..6]);
    data.velocity_product[0] = Vector6::zeros();
    for b in 1..model.n_bodies() {
        let p = model.links()[b - 1].parent;
        match model.dof_of_body(b) {
            Some(d) => {
                let vj = data.motion_subspace[b] * u[6 + d];
                let v = data.body_velocity[p] + vj;
                data.body_velocity[b] = v;
                data.velocity_product[b] = cross_motion(&v, &vj);
            }
            None => {
                data.body_velocity[b] = data.body_velocity[p];
                data.velocity_product[b] = Vector6::zeros();
            }
        }
    }
}

/// Spatial acceleration of the base at its CM from the state derivative `[v̇0; ω̇0]`.
pub(crate) fn base_spatial_acceleration<T: Real>(u: &[T], du: &[T]) -> Vector6<T> {
    let v0 = Vector6::from_column_slice(&u[0..6]);
    let a0 = Vector6::from_column_slice(&du[0..6]);
    spatial(&(linear(&a0) - angular(&v0).cross(&linear(&v0))), &angular(&a0))
}

/// Inverse dynamics: the generalized force `f = [F0; N0; τ]` that produces `u̇` at `(x, u)`,
/// given external wrenches and the joints' passive forces, i.e.
/// `f = H u̇ + c − Q_passive − Jᵀ w_ext` ([`crate::algorithms::passive`]). Left in `data.tau`.
pub fn rnea<'d>(
    model: &Model,
    data: &'d mut Data,
    x: &[f64],
    u: &[f64],
    du: &[f64],
    external: &[ExternalWrench],
) -> Result<&'d DVector<f64>> {
    forward_kinematics(model, data, x)?;
    check_velocity(model, "u", u)?;
    check_velocity(model, "du", du)?;
    for w in external {
        w.check(model)?;
    }
    rnea_after_kinematics(model, data, u, Some(du), external);
    subtract_joint_passive_forces(model, &x[7..], &u[6..], &mut data.tau.as_mut_slice()[6..]);
    Ok(&data.tau)
}

/// RNEA on the kinematics already in `data`, with checked inputs; `du = None` means `u̇ = 0`
/// (the bias vector). Fills `data.tau`. Any scalar.
pub(crate) fn rnea_after_kinematics<T: Real>(model: &Model, data: &mut DataT<T>, u: &[T], du: Option<&[T]>, external: &[ExternalWrench]) {
    velocity_pass(model, data, u);
    let nb = model.n_bodies();
    data.body_acceleration[0] = match du {
        Some(du) => base_spatial_acceleration(u, du),
        None => base_spatial_acceleration(u, &[T::zero(); 6]),
    };
    for b in 1..nb {
        let p = model.links()[b - 1].parent;
        let mut a = data.body_acceleration[p] + data.velocity_product[b];
        if let (Some(d), Some(du)) = (model.dof_of_body(b), du) {
            a += data.motion_subspace[b] * du[6 + d];
        }
        data.body_acceleration[b] = a;
    }
    for b in 0..nb {
        let inertia = &data.spatial_inertia[b];
        let v = data.body_velocity[b];
        data.body_force[b] = mul6(inertia, &data.body_acceleration[b]) + cross_force(&v, &mul6(inertia, &v));
    }
    for w in external {
        let f = w.at_base_com(data);
        data.body_force[w.body] -= f;
    }
    for b in (1..nb).rev() {
        let p = model.links()[b - 1].parent;
        if let Some(d) = model.dof_of_body(b) {
            data.tau[6 + d] = dot6(&data.motion_subspace[b], &data.body_force[b]);
        }
        let f = data.body_force[b];
        data.body_force[p] += f;
    }
    let f0 = data.body_force[0];
    data.tau.fixed_rows_mut::<6>(0).copy_from(&f0);
}

/// Bias vector `c(x, u)` (Coriolis and centrifugal terms; no gravity in orbit): the inverse
/// dynamics at `u̇ = 0` with no external wrench.
pub fn bias_forces<'d>(model: &Model, data: &'d mut Data, x: &[f64], u: &[f64]) -> Result<&'d DVector<f64>> {
    forward_kinematics(model, data, x)?;
    check_velocity(model, "u", u)?;
    rnea_after_kinematics(model, data, u, None, &[]);
    Ok(&data.tau)
}
