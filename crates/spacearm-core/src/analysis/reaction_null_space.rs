//! The reaction null space (Nenchev, Umetani & Yoshida 1992; Nenchev, Yoshida, Vichitkulsawat &
//! Uchiyama 1999, "Reaction null-space control of flexible structure mounted manipulator
//! systems", IEEE T-RA 15(6)): the joint rates that transfer no momentum to the base.
//!
//! With zero system momentum the base twist is `ẋ0 = −H0⁻¹ H0m q̇` (paper eq. 43), i.e. the
//! generalized Jacobian of a point at the base CM on the base itself (`J_mX = 0`, `J_0X = E`,
//! eq. 110). Its angular rows are `ω0 = −S⁻¹ C q̇` with `C = H_Sq − r̃_0g J_TS` the coupling
//! inertia about the system CM and `S` the Schur complement of eqs. 52–61 (invertible), so
//! the joint rates that leave the base attitude undisturbed are exactly the null space of the
//! coupling inertia `C` — Nenchev's reaction null space. Its dimension is `N − rank C`
//! (`N − 3` for a general spatial arm, `N − 1` for a planar arm whose joints all turn about z).
//!
//! The linear rows add the base translation: motion in the null space of all six rows leaves the
//! whole base at rest. Since the system CM is fixed, that requires joint motion that keeps the
//! arm's CM and angular momentum fixed (possible only when `N > rank H0m`).

use nalgebra::{DMatrix, DVector};

use super::Svd;
use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::gjm::compute_generalized_jacobian;
use crate::model::Model;

/// Which base motion the null space suppresses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BaseMotion {
    /// Base angular velocity `ω0` only (attitude undisturbed): Nenchev's reaction null space.
    Angular,
    /// The whole base twist `[v0; ω0]` (base at rest).
    Full,
}

// The one table every door reads.
crate::error::named_by!(BaseMotion, "base_motion", [Angular = "angular", Full = "full"]);

/// The reaction null space at one configuration.
#[derive(Debug, Clone)]
pub struct ReactionNullSpace {
    /// The map from joint rates to the suppressed base motion (3×N angular rows or 6×N), i.e.
    /// rows of `−H0⁻¹ H0m` (zero momentum).
    pub base_motion_map: DMatrix<f64>,
    /// Singular values of `base_motion_map`, decreasing.
    pub singular_values: DVector<f64>,
    /// Numerical rank of `base_motion_map` (singular values above `tolerance · σ_max`).
    pub rank: usize,
    /// Orthonormal basis of the null space (N×(N − rank)).
    pub basis: DMatrix<f64>,
    /// Orthogonal projector onto the null space, `P = B Bᵀ = E − M⁺ M` (N×N).
    pub projector: DMatrix<f64>,
}

/// The zero-momentum base twist per unit joint rate: `−H0⁻¹ H0m` (6×N), i.e. `J*` of the base
/// CM (paper eqs. 43 and 110).
pub fn base_twist_map(model: &Model, data: &mut Data, x: &[f64]) -> Result<DMatrix<f64>> {
    Ok(compute_generalized_jacobian(model, data, x, 0, &nalgebra::Vector3::zeros())?.clone())
}

/// The reaction null space at `x`: null space of the angular (or all) rows of `−H0⁻¹ H0m`,
/// with rank decided at `relative_tolerance · σ_max` (e.g. `1e-9`).
pub fn reaction_null_space(model: &Model, data: &mut Data, x: &[f64], which: BaseMotion, relative_tolerance: f64) -> Result<ReactionNullSpace> {
    if model.n_dof() == 0 {
        return Err(SpacearmError::InvalidModel(format!("model '{}' has no joints: no reaction null space", model.name())));
    }
    if !(relative_tolerance.is_finite() && relative_tolerance > 0.0 && relative_tolerance < 1.0) {
        return Err(SpacearmError::InvalidArgument(format!("the rank tolerance must be in (0, 1), got {relative_tolerance}")));
    }
    let full = base_twist_map(model, data, x)?;
    let map = match which {
        BaseMotion::Angular => full.rows(3, 3).into_owned(),
        BaseMotion::Full => full,
    };
    null_space_of(map, relative_tolerance)
}

/// Null space, rank and projector of a map (shared with the planners).
pub fn null_space_of(map: DMatrix<f64>, relative_tolerance: f64) -> Result<ReactionNullSpace> {
    let n = map.ncols();
    let svd = Svd::new(&map)?;
    // An all-zero map (e.g. a joint that cannot move the base) has rank 0.
    let rank = if svd.sigma_max() > 0.0 { svd.rank(relative_tolerance) } else { 0 };
    let basis = svd.v.columns(rank, n - rank).into_owned();
    let projector = &basis * basis.transpose();
    Ok(ReactionNullSpace { base_motion_map: map, singular_values: svd.singular_values, rank, basis, projector })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    #[test]
    fn planar_arm_has_a_three_dimensional_reaction_null_space() {
        let m = presets::planar4();
        let mut d = Data::new(&m);
        let x = presets::initial_configuration(&m);
        let rns = reaction_null_space(&m, &mut d, &x, BaseMotion::Angular, 1e-9).unwrap();
        assert_eq!(rns.rank, 1);
        assert_eq!(rns.basis.ncols(), 3);
        assert!((&rns.base_motion_map * &rns.basis).norm() < 1e-12 * rns.singular_values[0]);
        // Base angular velocity from the momentum map (an independent route) vanishes.
        for c in 0..3 {
            let qd: Vec<f64> = rns.basis.column(c).iter().copied().collect();
            let v = crate::gjm::base_velocity_from_momentum(&m, &mut d, &x, &qd, &Default::default(), &Default::default()).unwrap();
            assert!(v.fixed_rows::<3>(3).norm() < 1e-14, "{v}");
            assert!(v.fixed_rows::<3>(0).norm() > 1e-4, "the base still translates");
        }
        let full = reaction_null_space(&m, &mut d, &x, BaseMotion::Full, 1e-9).unwrap();
        assert_eq!(full.rank, 3);
        assert_eq!(full.basis.ncols(), 1);
    }
}
