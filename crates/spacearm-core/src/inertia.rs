//! The inertia matrices in the paper's Jacobian-sum form (eqs. 27–36) and the closed-form
//! inverse of the base inertia `H0` (eqs. 52–61).
//!
//! This is the first of the two independent computations of `H`; [`crate::crba`] is the
//! second. Nothing here uses spatial recursions: every block is a sum over links of products of
//! the link Jacobians `J_Ti`, `J_Ri` of [`crate::kinematics::link_jacobians`].

use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3};

use crate::data::Data;
use crate::error::{Result, SpacearmError};
use crate::kinematics::{forward_kinematics, link_jacobians};
use crate::model::Model;
use crate::spatial::skew;

/// The inertia blocks of paper eqs. 27–36, all in 𝒥 about the base CM.
#[derive(Debug, Clone, PartialEq)]
pub struct InertiaBlocks {
    /// Total mass `M`.
    pub total_mass: f64,
    /// `r_0g = r_g − r0`, base CM to system CM.
    pub base_to_com: Vector3<f64>,
    /// `H_S = R0 I0 R0ᵀ + Σ (Iᵢ + mᵢ r̃_0iᵀ r̃_0i)` (eq. 29).
    pub h_s: Matrix3<f64>,
    /// `J_TS = Σ mᵢ J_Ti` (3×N, eq. 32).
    pub j_ts: DMatrix<f64>,
    /// `H_Sq = Σ (Iᵢ J_Ri + mᵢ r̃_0i J_Ti)` (3×N, eq. 33).
    pub h_sq: DMatrix<f64>,
    /// `H0 = [[M E, −M r̃_0g], [M r̃_0g, H_S]]` (6×6, eq. 30).
    pub h0: Matrix6<f64>,
    /// `H0m = [J_TS; H_Sq]` (6×N, eq. 31).
    pub h0m: DMatrix<f64>,
    /// `H_m = Σ (J_Riᵀ Iᵢ J_Ri + mᵢ J_Tiᵀ J_Ti)` (N×N, eq. 34).
    pub hm: DMatrix<f64>,
}

impl InertiaBlocks {
    /// The full `(6+N)²` mass matrix `H = [[H0, H0m], [H0mᵀ, H_m]]` (eq. 36).
    pub fn mass_matrix(&self) -> DMatrix<f64> {
        let n = self.hm.nrows();
        let mut h = DMatrix::zeros(6 + n, 6 + n);
        h.fixed_view_mut::<6, 6>(0, 0).copy_from(&self.h0);
        h.view_mut((0, 6), (6, n)).copy_from(&self.h0m);
        h.view_mut((6, 0), (n, 6)).copy_from(&self.h0m.transpose());
        h.view_mut((6, 6), (n, n)).copy_from(&self.hm);
        h
    }
}

/// Compute every inertia block by the paper's Jacobian sums at configuration `x`.
pub fn inertia_blocks(model: &Model, data: &mut Data, x: &[f64]) -> Result<InertiaBlocks> {
    forward_kinematics(model, data, x)?;
    let n = model.n_dof();
    let r0 = data.base_position;
    let total_mass = model.total_mass();
    let mut h_s = data.inertia_in_world[0];
    let mut j_ts = DMatrix::zeros(3, n);
    let mut h_sq = DMatrix::zeros(3, n);
    let mut hm = DMatrix::zeros(n, n);
    let mut first_moment = Vector3::zeros();
    for b in 1..model.n_bodies() {
        let m = model.mass_properties(b).mass;
        let inertia = data.inertia_in_world[b];
        let r_0i = data.com_in_world[b] - r0;
        let r_0i_x = skew(&r_0i);
        first_moment += m * r_0i;
        h_s += inertia + m * r_0i_x.transpose() * r_0i_x;
        let (j_t, j_r) = link_jacobians(model, data, b);
        j_ts += m * &j_t;
        h_sq += inertia * &j_r + m * r_0i_x * &j_t;
        hm += j_r.transpose() * inertia * &j_r + m * j_t.transpose() * &j_t;
    }
    let base_to_com = first_moment / total_mass;
    let rg_x = skew(&base_to_com);
    let mut h0 = Matrix6::zeros();
    h0.fixed_view_mut::<3, 3>(0, 0).copy_from(&(Matrix3::identity() * total_mass));
    h0.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-total_mass * rg_x));
    h0.fixed_view_mut::<3, 3>(3, 0).copy_from(&(total_mass * rg_x));
    h0.fixed_view_mut::<3, 3>(3, 3).copy_from(&h_s);
    let mut h0m = DMatrix::zeros(6, n);
    h0m.rows_mut(0, 3).copy_from(&j_ts);
    h0m.rows_mut(3, 3).copy_from(&h_sq);
    Ok(InertiaBlocks { total_mass, base_to_com, h_s, j_ts, h_sq, h0, h0m, hm })
}

/// Closed-form inverse of a symmetric 3×3 matrix by its adjugate (paper eqs. 54–61).
fn symmetric3_inverse(s: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let (a, b, c) = (s[(0, 0)], s[(1, 1)], s[(2, 2)]);
    let (d, e, f) = (s[(0, 1)], s[(1, 2)], s[(0, 2)]);
    let c11 = b * c - e * e;
    let c12 = f * e - d * c;
    let c13 = d * e - b * f;
    let c22 = a * c - f * f;
    let c23 = d * f - a * e;
    let c33 = a * b - d * d;
    let det = a * c11 + d * c12 + f * c13;
    let scale = s.abs().max().powi(3);
    if !(det.abs() > 1e-14 * scale) || !det.is_finite() {
        return None;
    }
    Some(Matrix3::new(c11, c12, c13, c12, c22, c23, c13, c23, c33) / det)
}

/// Closed-form inverse of the base inertia matrix by the Banachiewicz/Schur-complement formula
/// (paper eqs. 52–53): with `S = H_S + M r̃_0g r̃_0g`,
/// `H0⁻¹ = [[E/M − r̃_0g S⁻¹ r̃_0g, r̃_0g S⁻¹], [−S⁻¹ r̃_0g, S⁻¹]]`.
///
/// `h0` must have the structure of eq. 30; `M`, `r_0g` and `H_S` are read from its blocks.
pub fn base_inertia_inverse(h0: &Matrix6<f64>) -> Result<Matrix6<f64>> {
    let m = h0[(0, 0)];
    if !(m > 0.0) {
        return Err(SpacearmError::Singular(format!("the base inertia H0 (total mass {m})")));
    }
    let rg_x: Matrix3<f64> = h0.fixed_view::<3, 3>(3, 0).into_owned() / m;
    let h_s: Matrix3<f64> = h0.fixed_view::<3, 3>(3, 3).into_owned();
    let schur = h_s + m * rg_x * rg_x;
    let s_inv = symmetric3_inverse(&schur).ok_or_else(|| SpacearmError::Singular("the Schur complement S of H0".into()))?;
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&(Matrix3::identity() / m - rg_x * s_inv * rg_x));
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(rg_x * s_inv));
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&(-s_inv * rg_x));
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&s_inv);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symmetric_inverse_matches_lu() {
        let s = Matrix3::new(4.0, 0.3, -0.2, 0.3, 5.0, 0.7, -0.2, 0.7, 6.0);
        let inv = symmetric3_inverse(&s).unwrap();
        let lu = s.try_inverse().unwrap();
        assert!((inv - lu).abs().max() < 1e-15);
        assert!(symmetric3_inverse(&Matrix3::zeros()).is_none());
    }
}
