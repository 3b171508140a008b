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
use crate::algorithms::wrench::{kinematics_and_loads, ExternalWrench};

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
    kinematics_and_loads(model, data, x, u, "du", du, external)?;
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

/// The wrench `[f; n]` (𝒥) that the joint of `body` (≥ 1) transmits from its parent to the
/// subtree it carries at `(x, u, u̇)`, the moment about `body`'s CM: RNEA's joint force
/// (Featherstone 2008, §5.3) moved from the base CM to the body's CM. For a leaf body on a fixed
/// joint (a captured payload, docs/capture.md) it is the wrench that holds the body on its
/// motion, `f = m a_c`, `n = d(I ω)/dt`: the exact derivative of the body's momentum.
pub fn joint_wrench(model: &Model, data: &mut Data, x: &[f64], u: &[f64], du: &[f64], body: usize) -> Result<Vector6<f64>> {
    crate::algorithms::kinematics::check_body(model, body)?;
    if body == 0 {
        return Err(crate::error::SpacearmError::argument("body 0 is the base: it has no joint to transmit a wrench (give a link, >= 1)"));
    }
    rnea(model, data, x, u, du, &[])?;
    let w = data.body_force[body];
    let (f, n_base) = (linear(&w), angular(&w));
    let n = n_base - (data.com_in_world[body] - data.base_position).cross(&f);
    Ok(spatial(&f, &n))
}

/// Bias vector `c(x, u)` (Coriolis and centrifugal terms; no gravity in orbit): the inverse
/// dynamics at `u̇ = 0` with no external wrench.
pub fn bias_forces<'d>(model: &Model, data: &'d mut Data, x: &[f64], u: &[f64]) -> Result<&'d DVector<f64>> {
    forward_kinematics(model, data, x)?;
    check_velocity(model, "u", u)?;
    rnea_after_kinematics(model, data, u, None, &[]);
    Ok(&data.tau)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithms::kinematics::point_jacobians;
    use crate::model::presets::{initial_configuration, spatial6};
    use nalgebra::Vector3;

    #[test]
    fn from_rest_the_last_link_s_joint_wrench_is_its_mass_times_the_jacobian_acceleration() {
        // At rest (u = 0) a body's CM accelerates by J_v u̇ and its frame by J_ω u̇ (J̇u = 0), so
        // the wrench holding the last link is [m J_v u̇; I_w J_ω u̇]: independent of the RNEA passes.
        let robot = spatial6();
        let mut x = initial_configuration(&robot);
        x[7..].iter_mut().enumerate().for_each(|(j, q)| *q += 0.4 * (j as f64 + 0.5).sin());
        let du: Vec<f64> = (0..robot.nu()).map(|k| 0.3 * ((k as f64) * 0.7 + 0.2).cos()).collect();
        let b = robot.n_bodies() - 1;
        let mut d = Data::new(&robot);
        let w = joint_wrench(&robot, &mut d, &x, &vec![0.0; robot.nu()], &du, b).unwrap();
        let (j0, jm) = point_jacobians(&robot, &d, b, &Vector3::zeros()).unwrap();
        let a = j0 * Vector6::from_column_slice(&du[..6]) + Vector6::from_column_slice((jm * DVector::from_column_slice(&du[6..])).as_slice());
        let m = robot.links()[b - 1].mass.mass;
        let f = linear(&a) * m;
        let n = d.inertia_in_world[b] * angular(&a);
        let want = spatial(&f, &n);
        assert!((w - want).norm() < 1e-12 * want.norm(), "{w:?} vs {want:?}");
        assert!(joint_wrench(&robot, &mut d, &x, &du, &du, 0).is_err());
    }
}
