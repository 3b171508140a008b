//! Forward dynamics under bilateral constraints, and the loop closure of a two-arm grasp
//! (docs/capture.md, "Two arms: a closed chain").
//!
//! With `m` constraint rows `J u = 0` (J: m × (6+N)) whose acceleration must be
//! `J u̇ = −γ` (`γ = J̇ u` plus any stabilization terms), the dynamics are the index-1 KKT system
//! (Pinocchio's `forwardDynamics(model, data, q, v, tau, J, gamma)`)
//!
//! `[H  −Jᵀ; J  0] [u̇; λ] = [f − c; −γ]`,
//!
//! `λ` the constraint force (a wrench for a weld). It is solved through the Schur complement:
//! `u̇₀ = H⁻¹ (f − c)`, `(J H⁻¹ Jᵀ) λ = −γ − J u̇₀`, `u̇ = u̇₀ + H⁻¹ Jᵀ λ` (Cholesky of `H`, LU of
//! the Delassus operator `J H⁻¹ Jᵀ`).
//!
//! [`LoopClosure`]: the frames at two points `a` and `b` of different bodies welded at their
//! relative pose at some configuration. Frame b moves with a, so its velocity constraint is
//! written at b's origin for both frames: `J_c = J_b − J_a`, both point Jacobians at the world
//! point `p_b` (a's is that of the material point of body a at `p_b`). The base columns cancel
//! (`J_0X` depends on the point only), so `J_c = [0, J_mb(p_b) − J_ma(p_b)]`. The pose error is
//! `e = [p_b − p_a − R_a d; θ]`, `d` b's origin in a's frame at the weld and `θ` the rotation
//! vector of `R_b (R_a R_ab)ᵀ`. Its exact `J̇_c u` is
//! [`crate::derivatives::loop_closure_bias`].
//!
//! Imports: [`crate::math`], [`crate::model`] and the algorithms of this folder.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};

use crate::algorithms::crba::crba_after_kinematics;
use crate::algorithms::kinematics::{check_body, check_velocity, forward_kinematics, joint_jacobian_of_point, point_position, BodyPoint};
use crate::algorithms::passive::add_joint_passive_forces;
use crate::algorithms::rnea::rnea_after_kinematics;
use crate::error::{check_finite, Result, SpacearmError};
use crate::math::rotations::rotation_vector;
use crate::model::data::Data;
use crate::model::Model;

/// The solution of [`constrained_forward_dynamics`].
#[derive(Debug, Clone, PartialEq)]
pub struct ConstrainedDynamics {
    /// The state derivative `u̇`.
    pub du: DVector<f64>,
    /// The constraint force `λ` (m): `H u̇ + c = f + Jᵀ λ`.
    pub lambda: DVector<f64>,
}

/// [`constrained_forward_dynamics`] on the kinematics already in `data` at the joint coordinates
/// `q` (inputs checked; the joints' passive force at `(q, q̇)` added to `f`,
/// [`crate::algorithms::passive`]): the simulator's constrained plant. Leaves `c` in `data.tau`, `H` in `data.mass_matrix` and the
/// body velocities at `u`.
pub(crate) fn constrained_forward_dynamics_after_kinematics(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    u: &[f64],
    f: &[f64],
    jacobian: &DMatrix<f64>,
    gamma: &DVector<f64>,
) -> Result<ConstrainedDynamics> {
    rnea_after_kinematics(model, data, u, None, &[]);
    crba_after_kinematics(model, data, true)?;
    let chol = data.mass_matrix.clone().cholesky().ok_or_else(|| SpacearmError::Singular("the mass matrix H".into()))?;
    let mut rhs = DVector::from_fn(model.nu(), |i, _| f[i] - data.tau[i]);
    add_joint_passive_forces(model, q, &u[6..], &mut rhs.as_mut_slice()[6..]);
    let a0 = chol.solve(&rhs);
    let y = chol.solve(&jacobian.transpose()); // H⁻¹ Jᵀ
    let schur = jacobian * &y;
    let lambda = schur
        .lu()
        .solve(&(-gamma - jacobian * &a0))
        .filter(|l| l.iter().all(|v| v.is_finite()))
        .ok_or_else(|| SpacearmError::Singular("the constraint Jacobian's Delassus operator J H⁻¹ Jᵀ (a singular posture of the loop)".into()))?;
    let du = a0 + y * &lambda;
    Ok(ConstrainedDynamics { du, lambda })
}

/// Forward dynamics under the constraints `J u̇ = −γ` (module docs): `u̇` and the constraint
/// force `λ` for the generalized force `f = [F0; N0; τ]` at `(x, u)`.
pub fn constrained_forward_dynamics(
    model: &Model,
    data: &mut Data,
    x: &[f64],
    u: &[f64],
    f: &[f64],
    jacobian: &DMatrix<f64>,
    gamma: &[f64],
) -> Result<ConstrainedDynamics> {
    forward_kinematics(model, data, x)?;
    check_velocity(model, "u", u)?;
    check_velocity(model, "f", f)?;
    if jacobian.ncols() != model.nu() || jacobian.nrows() == 0 {
        return Err(SpacearmError::Dimension { what: "constraint Jacobian (columns)".into(), expected: format!("6+N = {}", model.nu()), got: jacobian.ncols() });
    }
    if gamma.len() != jacobian.nrows() {
        return Err(SpacearmError::Dimension { what: "gamma".into(), expected: format!("{} (the constraint rows)", jacobian.nrows()), got: gamma.len() });
    }
    check_finite("constraint Jacobian", jacobian.as_slice())?;
    check_finite("gamma", gamma)?;
    constrained_forward_dynamics_after_kinematics(model, data, &x[7..], u, f, jacobian, &DVector::from_column_slice(gamma))
}

/// Two frames welded at their relative pose (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopClosure {
    /// Frame a: a body and the frame's origin (offset from the body's CM, in its frame).
    pub a: BodyPoint,
    /// Frame b.
    pub b: BodyPoint,
    /// b's origin in a's frame at the weld, m.
    pub d: Vector3<f64>,
    /// b's attitude relative to a at the weld (a's axes → b's axes).
    pub relative_rotation: Matrix3<f64>,
}

impl LoopClosure {
    /// The weld of the frames at `a` and `b` at configuration `x` (two different bodies).
    pub fn at(model: &Model, data: &mut Data, x: &[f64], a: BodyPoint, b: BodyPoint) -> Result<Self> {
        check_body(model, a.body)?;
        check_body(model, b.body)?;
        check_finite("the offset of frame a", a.offset.as_slice())?;
        check_finite("the offset of frame b", b.offset.as_slice())?;
        if a.body == b.body {
            return Err(SpacearmError::argument("the two grasp frames are on the same body: no loop to close"));
        }
        forward_kinematics(model, data, x)?;
        let (pa, pb) = (point_position(data, a.body, &a.offset), point_position(data, b.body, &b.offset));
        let ra = data.body_to_world[a.body];
        Ok(LoopClosure { a, b, d: ra.transpose() * (pb - pa), relative_rotation: ra.transpose() * data.body_to_world[b.body] })
    }

    /// `J_c = J_b − J_a` at b's origin (6 × (6+N); the base columns zero). Requires forward
    /// kinematics.
    pub fn jacobian(&self, model: &Model, data: &Data) -> DMatrix<f64> {
        let pb = point_position(data, self.b.body, &self.b.offset);
        let diff = joint_jacobian_of_point(model, data, self.b.body, &pb) - joint_jacobian_of_point(model, data, self.a.body, &pb);
        let mut j = DMatrix::zeros(6, model.nu());
        j.view_mut((0, 6), (6, model.n_dof())).copy_from(&diff);
        j
    }

    /// The pose error `e = [p_b − p_a − R_a d; θ]` (m; rad). Requires forward kinematics.
    pub fn error(&self, data: &Data) -> Vector6<f64> {
        let (pa, pb) = (point_position(data, self.a.body, &self.a.offset), point_position(data, self.b.body, &self.b.offset));
        let ra = data.body_to_world[self.a.body];
        let lin = pb - pa - ra * self.d;
        let theta = rotation_vector(&(data.body_to_world[self.b.body] * (ra * self.relative_rotation).transpose()));
        Vector6::new(lin.x, lin.y, lin.z, theta.x, theta.y, theta.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets::{dual_arm, initial_configuration};

    #[test]
    fn the_kkt_solution_satisfies_both_block_rows() {
        let model = dual_arm();
        let mut data = Data::new(&model);
        let mut x = initial_configuration(&model);
        x[7..].iter_mut().enumerate().for_each(|(j, q)| *q += 0.1 * (j as f64).sin());
        let u: Vec<f64> = (0..model.nu()).map(|k| 0.03 * (k as f64).cos()).collect();
        let f: Vec<f64> = (0..model.nu()).map(|k| 0.5 * (k as f64 * 0.7).sin()).collect();
        let (nb, n) = (model.n_bodies(), model.n_dof());
        let closure = LoopClosure::at(&model, &mut data, &x, BodyPoint { body: n / 2, offset: Vector3::new(0.1, 0.0, 0.0) },
                                      BodyPoint { body: nb - 1, offset: Vector3::zeros() })
            .unwrap();
        forward_kinematics(&model, &mut data, &x).unwrap();
        assert!(closure.error(&data).norm() < 1e-15);
        let j = closure.jacobian(&model, &data);
        let gamma = [0.1, -0.2, 0.3, 0.0, 0.05, -0.01];
        let r = constrained_forward_dynamics(&model, &mut data, &x, &u, &f, &j, &gamma).unwrap();
        let h = data.mass_matrix.clone();
        let c = data.tau.clone();
        let fv = DVector::from_column_slice(&f);
        assert!((&h * &r.du + &c - &fv - j.transpose() * &r.lambda).norm() < 1e-10 * fv.norm().max(1.0));
        assert!((&j * &r.du + DVector::from_column_slice(&gamma)).norm() < 1e-12);
    }
}
