//! The inertia matrices in the paper's Jacobian-sum form (eqs. 27–36) and the closed-form
//! inverse of the base inertia `H0` (eqs. 52–61).
//!
//! This is the first of the two independent computations of `H`; [`crate::algorithms::crba`] is the
//! second. Nothing here uses spatial recursions: every block is a sum over links of products of
//! the link Jacobians `J_Ti`, `J_Ri` of [`crate::algorithms::kinematics::link_jacobians`] (their non-zero
//! columns, formed in place).

use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3, Vector6};

use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::model::joint::JointType;
use crate::algorithms::kinematics::forward_kinematics;
use crate::model::Model;
use crate::math::scalar::Real;
use crate::math::spatial::skew;

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

/// Admission control of [`inertia_blocks`]: its arithmetic (Σ depth² over the links) and its
/// N² block `H_m` plus the `(6+N)²` matrix a caller assembles from it.
fn admit_paper_form(model: &Model) -> Result<()> {
    let remedy = "use the CRBA mass matrix (method=\"crba\", the same H in O(N·depth)) or a smaller model";
    let n = model.n_dof() as f64;
    crate::admission::admit(
        format_args!("the paper-form inertia blocks of N = {}", model.n_dof()),
        crate::admission::bytes_of::<f64>(n * n + (n + 6.0) * (n + 6.0)),
        remedy,
    )?;
    let operations: f64 = (1..model.n_bodies()).map(|b| (model.path_dofs(b) * model.path_dofs(b)) as f64).sum();
    crate::admission::admit_work(format_args!("the paper-form inertia blocks of N = {}", model.n_dof()), operations, remedy)
}

/// Compute every inertia block by the paper's Jacobian sums at configuration `x`.
///
/// The sums run only over the non-zero columns of each link's Jacobians (the joints on the path
/// from the base to the link, eqs. 20–21); nothing is allocated but the returned blocks. The
/// cost is Σ over links of (joints on its path)², N³/3 on a serial chain: a request beyond
/// [`crate::admission::WORK_LIMIT`] (a chain of about 2,300 joints) or whose `H_m` exceeds the
/// memory limit is refused ([`crate::SpacearmError::ResourceLimit`]); CRBA computes the same
/// matrix in O(N·depth).
pub fn inertia_blocks(model: &Model, data: &mut Data, x: &[f64]) -> Result<InertiaBlocks> {
    admit_paper_form(model)?;
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
        let r_i = data.com_in_world[b];
        let r_0i = r_i - r0;
        let r_0i_x = skew(&r_0i);
        first_moment += m * r_0i;
        h_s += inertia + m * r_0i_x.transpose() * r_0i_x;
        // Non-zero columns of J_Ti and J_Ri: the joints on the path to this link.
        data.work_dofs.clear();
        let mut a = b;
        while a != 0 {
            if let Some(d) = model.dof_of_body(a) {
                let k = data.joint_axis_in_world[a];
                let (t, r) = match model.links()[a - 1].joint.kind {
                    JointType::Revolute => (k.cross(&(r_i - data.joint_position_in_world[a])), k),
                    _ => (k, Vector3::zeros()),
                };
                data.work_lin[data.work_dofs.len()] = t;
                data.work_ang[data.work_dofs.len()] = r;
                data.work_dofs.push(d);
            }
            a = model.links()[a - 1].parent;
        }
        for (p, &j) in data.work_dofs.iter().enumerate() {
            let (t_j, r_j) = (data.work_lin[p], data.work_ang[p]);
            let ts = m * t_j;
            let sq = inertia * r_j + m * r_0i.cross(&t_j);
            for row in 0..3 {
                j_ts[(row, j)] += ts[row];
                h_sq[(row, j)] += sq[row];
            }
            let i_r_j = inertia * r_j;
            for (q, &k) in data.work_dofs.iter().enumerate().skip(p) {
                let v = data.work_ang[q].dot(&i_r_j) + m * data.work_lin[q].dot(&t_j);
                hm[(j, k)] += v;
                if j != k {
                    hm[(k, j)] += v;
                }
            }
        }
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

/// Closed-form inverse of a symmetric 3×3 matrix by its adjugate (paper eqs. 54–61), any
/// scalar (the singularity test reads the real part).
fn symmetric3_inverse<T: Real>(s: &Matrix3<T>) -> Option<Matrix3<T>> {
    let (a, b, c) = (s[(0, 0)], s[(1, 1)], s[(2, 2)]);
    let (d, e, f) = (s[(0, 1)], s[(1, 2)], s[(0, 2)]);
    let c11 = b * c - e * e;
    let c12 = f * e - d * c;
    let c13 = d * e - b * f;
    let c22 = a * c - f * f;
    let c23 = d * f - a * e;
    let c33 = a * b - d * d;
    let det = a * c11 + d * c12 + f * c13;
    let scale = s.iter().fold(0.0_f64, |acc, e| acc.max(e.value().abs())).powi(3);
    if !(det.value().abs() > 1e-14 * scale) || !det.value().is_finite() {
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

/// The closed-form inverse of `H0` kept in factored form (paper eqs. 52–61): total mass `M`,
/// base-to-system-CM vector `r_0g` and `S⁻¹` with `S = H_S + M r̃_0g r̃_0g`. Applying it to a
/// 6-vector costs two cross products and one 3×3 product; see [`BaseInverse::apply`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct BaseInverse<T: Real> {
    pub total_mass: T,
    pub base_to_com: Vector3<T>,
    pub schur_inverse: Matrix3<T>,
}

impl<T: Real> BaseInverse<T> {
    /// Factor `h0` (structure of eq. 30); the same checks and errors as [`base_inertia_inverse`].
    pub fn new(h0: &Matrix6<T>) -> Result<Self> {
        let m = h0[(0, 0)];
        if !(m.value() > 0.0) {
            return Err(SpacearmError::Singular(format!("the base inertia H0 (total mass {})", m.value())));
        }
        // Lower-left block M r̃_0g.
        let r = Vector3::new(h0[(5, 1)], h0[(3, 2)], h0[(4, 0)]) / m;
        let rr = r.norm_squared();
        let h_s: Matrix3<T> = h0.fixed_view::<3, 3>(3, 3).into_owned();
        // M r̃ r̃ = M (r rᵀ − |r|² E), symmetric.
        let mut schur = h_s;
        for i in 0..3 {
            for j in 0..3 {
                let v = m * (r[i] * r[j] - if i == j { rr } else { T::zero() });
                schur[(i, j)] += v;
            }
        }
        let schur_inverse =
            symmetric3_inverse(&schur).ok_or_else(|| SpacearmError::Singular("the Schur complement S of H0".into()))?;
        Ok(BaseInverse { total_mass: m, base_to_com: r, schur_inverse })
    }

    /// `y = S⁻¹ (w_ang − r_0g × w_lin)`, the angular half of `H0⁻¹ w` and the building block
    /// of every reduction.
    #[inline]
    pub fn angular(&self, w_lin: &Vector3<T>, w_ang: &Vector3<T>) -> Vector3<T> {
        self.schur_inverse * (w_ang - self.base_to_com.cross(w_lin))
    }

    /// `H0⁻¹ w = [w_lin / M + r_0g × y; y]` with `y` from [`BaseInverse::angular`].
    #[inline]
    pub fn apply(&self, w: &Vector6<T>) -> Vector6<T> {
        let (w_lin, w_ang) = (w.fixed_rows::<3>(0).into_owned(), w.fixed_rows::<3>(3).into_owned());
        let y = self.angular(&w_lin, &w_ang);
        let top = w_lin / self.total_mass + self.base_to_com.cross(&y);
        Vector6::new(top.x, top.y, top.z, y.x, y.y, y.z)
    }
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
        assert!(symmetric3_inverse(&Matrix3::<f64>::zeros()).is_none());
    }
}
