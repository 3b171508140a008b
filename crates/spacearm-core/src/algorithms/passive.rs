//! The passive generalized force of the joints' springs and dampers and the springs' potential
//! energy (docs/flexibility.md):
//!
//! `Q_passive = [0₆; −K (q − q_rest) − C q̇]`, `V = ½ (q − q_rest)ᵀ K (q − q_rest)`,
//!
//! with `K`, `C` diagonal (one linear spring–damper per joint, [`JointDynamics`]). The force
//! is MuJoCo's `qfrc_passive` of joints with `stiffness`, `springref` and `damping`. Every
//! forward dynamics adds it to the applied force, `H u̇ + c = f + Q_passive + Jᵀ w_ext`, and the
//! inverse dynamics subtracts it, `f = H u̇ + c − Q_passive − Jᵀ w_ext`, so that the two stay
//! inverse of each other; the bias `c` (and so `c*`) stays the velocity-product term alone.

use nalgebra::DVector;

use crate::algorithms::kinematics::{check_velocity, split_configuration};
use crate::error::Result;
use crate::math::scalar::Real;
use crate::model::joint::JointDynamics;
use crate::model::Model;

/// Call `apply(d, k (q − rest) + c q̇)` for each joint dof `d` with a spring or a damper (its
/// passive force is the negative of that); nothing when the model has none.
#[inline]
fn each_spring_damper<T: Real>(model: &Model, q: &[T], qd: &[T], mut apply: impl FnMut(usize, T)) {
    if !model.has_passive_forces() {
        return;
    }
    for (d, jd) in model.dof_dynamics().iter().enumerate() {
        if jd.has_passive_force() {
            apply(d, (q[d] - T::c(jd.rest)) * T::c(jd.stiffness) + qd[d] * T::c(jd.damping));
        }
    }
}

/// Add the joints' passive force `−k (q − rest) − c q̇` to `tau` (length N, joint rows), any
/// scalar; nothing when the model has no spring or damper.
#[inline]
pub fn add_joint_passive_forces<T: Real>(model: &Model, q: &[T], qd: &[T], tau: &mut [T]) {
    each_spring_damper(model, q, qd, |d, r| tau[d] -= r);
}

/// Subtract the joints' passive force from `tau` (length N, joint rows): the inverse dynamics'
/// `f = H u̇ + c − Q_passive`. Any scalar.
#[inline]
pub fn subtract_joint_passive_forces<T: Real>(model: &Model, q: &[T], qd: &[T], tau: &mut [T]) {
    each_spring_damper(model, q, qd, |d, r| tau[d] += r);
}

/// The passive generalized force `Q_passive` at `(x, u)`: length `6+N`, zero on the base rows.
pub fn passive_forces(model: &Model, x: &[f64], u: &[f64]) -> Result<DVector<f64>> {
    let (_, _, q) = split_configuration(model, x)?;
    check_velocity(model, "u", u)?;
    let mut out = DVector::zeros(model.nu());
    add_joint_passive_forces(model, q, &u[6..], &mut out.as_mut_slice()[6..]);
    Ok(out)
}

/// The springs' potential energy `½ Σ kⱼ (qⱼ − restⱼ)²` at the joint coordinates `q`
/// (length N, unchecked), J.
pub fn spring_energy_of_q(model: &Model, q: &[f64]) -> f64 {
    model.dof_dynamics().iter().zip(q).map(|(jd, &qj)| jd.spring_energy(qj)).sum()
}

/// The springs' potential energy at the configuration `x`, J.
pub fn spring_energy(model: &Model, x: &[f64]) -> Result<f64> {
    let (_, _, q) = split_configuration(model, x)?;
    Ok(spring_energy_of_q(model, q))
}

/// The joint stiffness and damping as `(K, C)` diagonals (length N): the partials
/// `−∂Q/∂q`, `−∂Q/∂q̇` of the passive force.
pub fn passive_gains(model: &Model) -> (Vec<f64>, Vec<f64>) {
    let dyn_: &[JointDynamics] = model.dof_dynamics();
    (dyn_.iter().map(|d| d.stiffness).collect(), dyn_.iter().map(|d| d.damping).collect())
}
