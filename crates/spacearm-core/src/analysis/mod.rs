//! Analysis of free-floating spacecraft-manipulator systems built on the GJM quantities of
//! [`crate::gjm`]: dynamic singularities ([`singularity`]), workspaces ([`workspace`]), the
//! reaction null space ([`reaction_null_space`]), the resolved-motion-rate solver through `J*`
//! ([`rmrc_solver`], shared with the native controller of [`crate::control::rmrc`]), redundancy
//! resolution with it ([`redundancy`]), the reach and plane of a point ([`reach`]), the kinematics
//! of free-floating motion with conserved momentum ([`free_floating_kinematics`]), and the small
//! oscillations of the joints' springs ([`passive_modes`]).
//!
//! Shared here: the selection of task rows of a point twist ([`Task`]) and the singular value
//! decomposition with sorted singular values and full right singular vectors ([`Svd`]); the
//! damped least-squares inverse is [`crate::math::dls`]'s.
//!
//! Every batch scan runs its samples in parallel with rayon; each sample is computed on its own
//! workspace from its own input only, so the results do not depend on the number of threads.
//!
//! Imports: everything below it (`math`, `model`, `algorithms`, `gjm`), the RK4 integrator
//! of [`crate::math::integrate`] and the point references of [`crate::scenario::reference`]
//! (below it); nothing from `control` (which imports [`rmrc_solver`] and [`Task`] from here).

pub mod cmg_envelope;
pub mod cmg_singular_surface;
pub mod free_floating_kinematics;
pub mod passive_modes;
pub mod reach;
pub mod reaction_null_space;
pub mod redundancy;
pub mod rmrc_solver;
pub mod scan;
pub mod singularity;
pub mod workspace;

use nalgebra::{DMatrix, DVector};

use crate::error::{Result, SpacearmError};

/// The rows of a point twist `[v_x, v_y, v_z, ω_x, ω_y, ω_z]` (in 𝒥) that a task controls or an
/// analysis looks at. `Task::position()` is the usual choice for a spatial arm, `Task::planar()`
/// (`v_x, v_y`) for a planar arm moving in the x–y plane, `Task::full()` for the whole twist.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Task {
    rows: Vec<usize>,
}

impl Task {
    /// A task from row indices into the twist (0–2 linear, 3–5 angular); sorted, unique, at least one.
    pub fn new(rows: &[usize]) -> Result<Self> {
        let mut r = rows.to_vec();
        r.sort_unstable();
        r.dedup();
        if r.is_empty() || r.len() != rows.len() || r.iter().any(|&i| i > 5) {
            return Err(SpacearmError::Dimension {
                what: "task rows".into(),
                expected: "between 1 and 6 distinct indices in 0..=5 (0-2 linear velocity, 3-5 angular velocity)".into(),
                got: rows.len(),
            });
        }
        Ok(Task { rows: r })
    }
    /// Linear velocity rows `[0, 1, 2]`.
    pub fn position() -> Self {
        Task { rows: vec![0, 1, 2] }
    }
    /// In-plane linear velocity `[0, 1]` (planar arms with joint axes along z).
    pub fn planar() -> Self {
        Task { rows: vec![0, 1] }
    }
    /// The whole twist `[0..6]`.
    pub fn full() -> Self {
        Task { rows: (0..6).collect() }
    }
    /// The selected rows.
    pub fn rows(&self) -> &[usize] {
        &self.rows
    }
    /// Number of task rows `m`.
    pub fn len(&self) -> usize {
        self.rows.len()
    }
    /// Never true (a task has at least one row); for clippy.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }
    /// The task rows of a 6×N Jacobian (m×N).
    pub fn select(&self, jacobian: &DMatrix<f64>) -> DMatrix<f64> {
        DMatrix::from_fn(self.rows.len(), jacobian.ncols(), |i, j| jacobian[(self.rows[i], j)])
    }
}

/// Singular value decomposition `A = U Σ Vᵀ` of an m×n matrix with the singular values sorted
/// in decreasing order, `min(m, n)` of them, and the full n×n matrix of right singular vectors
/// (the last `n − rank` columns of `v` span the null space of `A`).
#[derive(Debug, Clone)]
pub struct Svd {
    /// `min(m, n)` singular values, decreasing.
    pub singular_values: DVector<f64>,
    /// Left singular vectors, m×min(m, n), column `i` paired with `singular_values[i]`.
    pub u: DMatrix<f64>,
    /// Right singular vectors, n×n: columns `0..min(m, n)` paired with the singular values,
    /// the rest an orthonormal basis of the complement (null space when `m < n`).
    pub v: DMatrix<f64>,
}

impl Svd {
    /// Decompose `a`. Wide matrices are padded with zero rows to n×n so that `v` is complete.
    pub fn new(a: &DMatrix<f64>) -> Result<Self> {
        let (m, n) = a.shape();
        crate::error::check_finite("matrix to decompose", a.as_slice())?;
        let padded = if m < n {
            let mut p = DMatrix::zeros(n, n);
            p.view_mut((0, 0), (m, n)).copy_from(a);
            p
        } else {
            a.clone()
        };
        let svd = padded.svd_unordered(true, true);
        let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
            return Err(SpacearmError::Singular("the singular value decomposition did not converge: the matrix".into()));
        };
        let s = svd.singular_values;
        let k = s.len();
        // Sort decreasing (nalgebra's order is not guaranteed), pairing the vectors.
        let mut order: Vec<usize> = (0..k).collect();
        order.sort_by(|&i, &j| s[j].partial_cmp(&s[i]).unwrap_or(std::cmp::Ordering::Equal));
        let keep = m.min(n);
        let singular_values = DVector::from_fn(keep, |i, _| s[order[i]]);
        let v = DMatrix::from_fn(n, n, |r, c| if c < k { v_t[(order[c], r)] } else { 0.0 });
        // Left vectors: nalgebra's are inaccurate for (near-)zero singular values of small
        // matrices, so rebuild them as uᵢ = A vᵢ / σᵢ where σᵢ is well above round-off, and
        // complete an orthonormal set (modified Gram–Schmidt, twice) for the rest.
        let mut u_sorted = DMatrix::from_fn(m, keep, |r, c| u[(r, order[c])]);
        let floor = 1e-8 * singular_values[0];
        for c in 0..keep {
            if singular_values[c] > floor {
                let col = a * v.column(c) / singular_values[c];
                u_sorted.set_column(c, &col);
            }
        }
        orthonormalize_columns(&mut u_sorted);
        Ok(Svd { singular_values, u: u_sorted, v })
    }

    /// Smallest of the `min(m, n)` singular values.
    pub fn sigma_min(&self) -> f64 {
        self.singular_values[self.singular_values.len() - 1]
    }

    /// Largest singular value.
    pub fn sigma_max(&self) -> f64 {
        self.singular_values[0]
    }

    /// Condition number `σ_max / σ_min` (`+∞` when `σ_min = 0`).
    pub fn condition(&self) -> f64 {
        let s = self.sigma_min();
        if s > 0.0 { self.sigma_max() / s } else { f64::INFINITY }
    }

    /// Number of singular values above `relative_tolerance · σ_max` (and above 0).
    pub fn rank(&self, relative_tolerance: f64) -> usize {
        let cut = relative_tolerance * self.sigma_max();
        self.singular_values.iter().filter(|&&s| s > cut && s > 0.0).count()
    }
}

/// Make the columns of `u` orthonormal in order (modified Gram–Schmidt applied twice); a column
/// that is (nearly) dependent on the previous ones is replaced by the first coordinate axis that
/// is not.
fn orthonormalize_columns(u: &mut DMatrix<f64>) {
    let (m, k) = u.shape();
    for c in 0..k {
        let candidates = std::iter::once(u.column(c).into_owned()).chain((0..m).map(|i| {
            let mut e = DVector::zeros(m);
            e[i] = 1.0;
            e
        }));
        for mut col in candidates {
            for _ in 0..2 {
                for p in 0..c {
                    let prev = u.column(p).into_owned();
                    col -= prev.dot(&col) * prev;
                }
            }
            let norm = col.norm();
            if norm > 1e-6 {
                u.set_column(c, &(col / norm));
                break;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn svd_sorted_complete_and_reconstructs() {
        let a = DMatrix::from_row_slice(2, 4, &[1.0, 2.0, 0.0, -1.0, 0.5, 0.0, 3.0, 1.0]);
        let s = Svd::new(&a).unwrap();
        assert_eq!(s.singular_values.len(), 2);
        assert!(s.singular_values[0] >= s.singular_values[1]);
        assert_eq!(s.v.shape(), (4, 4));
        // V orthonormal.
        let vtv = s.v.transpose() * &s.v;
        assert!((vtv - DMatrix::identity(4, 4)).norm() < 1e-12);
        // A = U Σ V[:, :2]ᵀ and the last two columns of V are in the null space.
        let recon = &s.u * DMatrix::from_diagonal(&s.singular_values) * s.v.columns(0, 2).transpose();
        assert!((recon - &a).norm() < 1e-12);
        assert!((&a * s.v.columns(2, 2)).norm() < 1e-12);
    }

    #[test]
    fn task_validation() {
        assert!(Task::new(&[]).is_err());
        assert!(Task::new(&[0, 0]).is_err());
        assert!(Task::new(&[6]).is_err());
        assert_eq!(Task::new(&[5, 0, 1]).unwrap().rows(), &[0, 1, 5]);
    }
}
