//! Dynamic singularities (Papadopoulos & Dubowsky 1991, 1993): configurations where the
//! Generalized Jacobian `J*` (paper eq. 110) of the end effector loses rank, so that the end
//! effector of a free-floating system cannot move in some inertial direction whatever the joint
//! rates. They depend on the mass distribution, not on the kinematics alone, and differ from the
//! kinematic singularities of the fixed-base Jacobian `J_m` (eq. 106), which are reported beside
//! them for comparison.
//!
//! Measures of an m×N task Jacobian `J` with singular values `σ₁ ≥ … ≥ σ_k` (`k = min(m, N)`):
//! condition number `σ₁/σ_k`, Yoshikawa's manipulability `w = Π σᵢ` (`= √det(J Jᵀ)` when
//! `m ≤ N`), the singular directions (left vectors: task-space directions, the last one being
//! the direction the end effector can hardly move in; right vectors: joint-space directions).
//!
//! Rotating the base rotates `J*` (`J*(R0, q) = diag(R0, R0) J*(E, q)`) and translating it
//! changes nothing, so every singular value depends on `q` alone (Papadopoulos & Dubowsky 1993,
//! eq. 37); the scans of [`crate::analysis::scan`] therefore run over joint space only.
//!
//! The detector for resolved-motion-rate control ([`detect`]) returns `σ_min`, the condition
//! number and the damping of the damped least-squares inverse recommended by the law of
//! Nakamura & Hanafusa (1986) in the form of Maciejewski & Klein (1988) / Chiaverini (1997):
//! `λ² = λ_max² (1 − (σ_min/ε)²)` for `σ_min < ε`, `λ = 0` otherwise.

use nalgebra::{DMatrix, DVector, Vector3};

use super::{Svd, Task};
use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::gjm::compute_generalized_jacobian;
use crate::algorithms::kinematics::{joint_jacobian_of_point, point_position};
use crate::model::Model;

/// Singular values, condition, manipulability and singular directions of one task Jacobian.
#[derive(Debug, Clone)]
pub struct JacobianMeasures {
    /// The m×N task Jacobian analysed.
    pub jacobian: DMatrix<f64>,
    /// Its singular values, decreasing (`min(m, N)` of them).
    pub singular_values: DVector<f64>,
    /// `σ_max / σ_min` (`+∞` at a singularity).
    pub condition: f64,
    /// Yoshikawa's manipulability `Π σᵢ`.
    pub manipulability: f64,
    /// Left singular vectors (m×min(m, N)): task directions, the last the worst.
    pub task_directions: DMatrix<f64>,
    /// Right singular vectors (N×N): joint directions; columns beyond the rank span the null
    /// space (self-motions).
    pub joint_directions: DMatrix<f64>,
}

impl JacobianMeasures {
    /// Measures of `jacobian`.
    pub fn new(jacobian: DMatrix<f64>) -> Result<Self> {
        let svd = Svd::new(&jacobian)?;
        Ok(JacobianMeasures {
            condition: svd.condition(),
            manipulability: svd.singular_values.iter().product(),
            singular_values: svd.singular_values,
            task_directions: svd.u,
            joint_directions: svd.v,
            jacobian,
        })
    }
    /// Smallest singular value.
    pub fn sigma_min(&self) -> f64 {
        self.singular_values[self.singular_values.len() - 1]
    }
}

/// Singularity analysis at one configuration: the generalized (free-floating) and the
/// fixed-base task Jacobians of a point.
#[derive(Debug, Clone)]
pub struct SingularityAnalysis {
    /// Measures of the task rows of `J*` (free-floating, zero momentum; eq. 110).
    pub generalized: JacobianMeasures,
    /// Measures of the task rows of `J_m` (base held fixed; eq. 106).
    pub fixed_base: JacobianMeasures,
}

/// The task rows of `J*` and of `J_m` of the point fixed to `body` at `offset` (body frame,
/// from its CM), at configuration `x`.
pub fn task_jacobians(model: &Model, data: &mut Data, x: &[f64], body: usize, offset: &Vector3<f64>, task: &Task) -> Result<(DMatrix<f64>, DMatrix<f64>)> {
    let jstar = task.select(compute_generalized_jacobian(model, data, x, body, offset)?);
    // compute_generalized_jacobian ran forward kinematics at x.
    let point = point_position(data, body, offset);
    let jm = task.select(&joint_jacobian_of_point(model, data, body, &point));
    Ok((jstar, jm))
}

/// Singular values, condition, manipulability and singular directions of `J*` and `J_m` at `x`.
pub fn analyze(model: &Model, data: &mut Data, x: &[f64], body: usize, offset: &Vector3<f64>, task: &Task) -> Result<SingularityAnalysis> {
    check_has_dofs(model)?;
    let (jstar, jm) = task_jacobians(model, data, x, body, offset, task)?;
    Ok(SingularityAnalysis { generalized: JacobianMeasures::new(jstar)?, fixed_base: JacobianMeasures::new(jm)? })
}

pub(crate) fn check_has_dofs(model: &Model) -> Result<()> {
    if model.n_dof() == 0 {
        return Err(SpacearmError::InvalidModel(format!("model '{}' has no joint degrees of freedom to analyse", model.name())));
    }
    Ok(())
}

/// The damping law, defined once with the damped inverse in [`crate::math::dls`].
pub use crate::math::dls::DampingLaw;

/// What the singularity detector tells a resolved-motion-rate controller.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Detection {
    /// Smallest singular value of the task Jacobian.
    pub sigma_min: f64,
    /// Condition number `σ_max / σ_min`.
    pub condition: f64,
    /// Recommended damping `λ(σ_min)` of the DLS inverse ([`DampingLaw`]).
    pub damping: f64,
    /// `σ_min < ε`: inside the singular region.
    pub near_singular: bool,
}

/// Singularity detector on a task Jacobian (usually the task rows of `J*`).
pub fn detect(jacobian: &DMatrix<f64>, law: &DampingLaw) -> Result<Detection> {
    let svd = Svd::new(jacobian)?;
    Ok(detection_from_svd(&svd, law))
}

/// [`detect`] from an existing decomposition.
pub fn detection_from_svd(svd: &Svd, law: &DampingLaw) -> Detection {
    let s = svd.sigma_min();
    Detection { sigma_min: s, condition: svd.condition(), damping: law.damping(s), near_singular: s < law.threshold }
}

/// [`detect`] on the task rows of `J*` of a point at configuration `x`.
pub fn detect_at(model: &Model, data: &mut Data, x: &[f64], body: usize, offset: &Vector3<f64>, task: &Task, law: &DampingLaw) -> Result<Detection> {
    check_has_dofs(model)?;
    let j = task.select(compute_generalized_jacobian(model, data, x, body, offset)?);
    detect(&j, law)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    #[test]
    fn attitude_does_not_change_singular_values() {
        let m = presets::spatial6();
        let mut d = Data::new(&m);
        let ee = m.points()[m.end_effector().unwrap()].clone();
        let mut x = presets::initial_configuration(&m);
        let a = analyze(&m, &mut d, &x, ee.body, &ee.offset, &Task::full()).unwrap();
        // A rotated, translated base: same q.
        let h = (0.5f64).sqrt();
        x[0..7].copy_from_slice(&[3.0, -1.0, 2.0, 0.0, h * 0.6, h * 0.8, h]);
        let b = analyze(&m, &mut d, &x, ee.body, &ee.offset, &Task::full()).unwrap();
        assert!((&a.generalized.singular_values - &b.generalized.singular_values).norm() < 1e-10);
        assert!((&a.fixed_base.singular_values - &b.fixed_base.singular_values).norm() < 1e-10);
        assert!(a.generalized.sigma_min() > 1e-3);
    }
}
