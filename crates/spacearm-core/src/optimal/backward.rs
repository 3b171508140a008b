//! The backward (Riccati) pass of FDDP with box-constrained controls, in the tangent space.
//!
//! Around the current, possibly infeasible, trajectory with gaps `f̄_{k+1} = Φ(z_k, c_k) ⊖
//! z_{k+1}` (and `f̄_0 = z̄_0 ⊖ z_0`), the value function `V_k(δz) ≈ pₖᵀ δz + ½ δzᵀ Pₖ δz`
//! follows from `P_T = ℓ_zz,T`, `p_T = ℓ_z,T` and, for `k = T−1 … 0`, with
//! `p⁺ = p_{k+1} + P_{k+1} f̄_{k+1}` (the gradient at the end of the gap, Mastalli et al. 2020):
//!
//! `Q_z = ℓ_z + Aᵀ p⁺`, `Q_c = ℓ_c + Bᵀ p⁺`, `Q_zz = ℓ_zz + Aᵀ P A`, `Q_cz = ℓ_cz + Bᵀ P A`,
//! `Q_cc = ℓ_cc + Bᵀ P B + μ E` (Levenberg–Marquardt regularization `μ`);
//!
//! the step `δc = k + K δz` minimizes `Q` within the bounds `lower − c_k ≤ δc ≤ upper − c_k`
//! ([`super::box_qp`]; `K` zero on the clamped rows), and
//!
//! `pₖ = Q_z + Kᵀ Q_cc k + Kᵀ Q_c + Q_czᵀ k`, `Pₖ = Q_zz + Kᵀ Q_cc K + Kᵀ Q_cz + Q_czᵀ K`.

use nalgebra::{DMatrix, DVector};

use super::box_qp::solve_box_qp;
use super::shooting::KnotModel;

/// The backward pass's results and workspaces, per knot.
pub struct Backward {
    /// `pₖ` (`T+1`).
    pub p: Vec<DVector<f64>>,
    /// `Pₖ` (`T+1`).
    pub pm: Vec<DMatrix<f64>>,
    /// Feedforward `kₖ` (`T`).
    pub k: Vec<DVector<f64>>,
    /// Feedback `Kₖ` (`T`).
    pub gain: Vec<DMatrix<f64>>,
    /// `Q_c` (`T`).
    pub qc: Vec<DVector<f64>>,
    /// `Q_cc` with the regularization (`T`).
    pub qcc: Vec<DMatrix<f64>>,
}

impl Backward {
    /// Workspaces for `t` steps, tangent dimension `nd`, `m` controls.
    pub fn new(t: usize, nd: usize, m: usize) -> Self {
        Backward {
            p: vec![DVector::zeros(nd); t + 1],
            pm: vec![DMatrix::zeros(nd, nd); t + 1],
            k: vec![DVector::zeros(m); t],
            gain: vec![DMatrix::zeros(m, nd); t],
            qc: vec![DVector::zeros(m); t],
            qcc: vec![DMatrix::zeros(m, m); t],
        }
    }

    /// Run the pass (module docs) on the knot models `knots` (`T+1`, the last the terminal
    /// cost's), the gaps `gaps` (`T+1`), the controls `cs` and their bounds, with regularization
    /// `mu`. `false` when a `Q_cc` is not positive definite (raise `mu`).
    #[allow(clippy::too_many_arguments)]
    pub fn run(&mut self, knots: &[KnotModel], gaps: &[DVector<f64>], cs: &[Vec<f64>], lower: &[f64], upper: &[f64], mu: f64, feasible: bool) -> bool {
        let t = cs.len();
        self.pm[t].copy_from(&knots[t].lzz);
        self.p[t].copy_from(&knots[t].lz);
        let bounded = lower.iter().chain(upper).any(|b| b.is_finite());
        for k in (0..t).rev() {
            let kn = &knots[k];
            let pn = &self.pm[k + 1];
            let mut pplus = self.p[k + 1].clone();
            if !feasible {
                pplus.gemv(1.0, pn, &gaps[k + 1], 1.0);
            }
            let pa = pn * &kn.a;
            let qz = &kn.lz + kn.a.transpose() * &pplus;
            let qc = &kn.lc + kn.b.transpose() * &pplus;
            let qzz = &kn.lzz + kn.a.transpose() * &pa;
            let qcz = &kn.lcz + kn.b.transpose() * &pa;
            let mut qcc = &kn.lcc + kn.b.transpose() * pn * &kn.b;
            for i in 0..qcc.nrows() {
                qcc[(i, i)] += mu;
            }
            let m = qc.len();
            let (kff, gain) = if bounded {
                let lo: Vec<f64> = (0..m).map(|i| lower[i] - cs[k][i]).collect();
                let hi: Vec<f64> = (0..m).map(|i| upper[i] - cs[k][i]).collect();
                let Some(sol) = solve_box_qp(&qcc, &qc, &lo, &hi, &self.k[k]) else {
                    return false;
                };
                let mut gain = DMatrix::zeros(m, qz.len());
                if let Some(f) = &sol.free_factor {
                    let idx: Vec<usize> = (0..m).filter(|i| sol.free[*i]).collect();
                    let rows = DMatrix::from_fn(idx.len(), qz.len(), |a, b| qcz[(idx[a], b)]);
                    let kf = -f.solve(&rows);
                    for (a, i) in idx.iter().enumerate() {
                        gain.row_mut(*i).copy_from(&kf.row(a));
                    }
                }
                (sol.x, gain)
            } else {
                let Some(chol) = qcc.clone().cholesky() else {
                    return false;
                };
                (-chol.solve(&qc), -chol.solve(&qcz))
            };
            // pₖ = Q_z + Kᵀ Q_cc k + Kᵀ Q_c + Q_czᵀ k; Pₖ = Q_zz + Kᵀ Q_cc K + Kᵀ Q_cz + Q_czᵀ K.
            let qcc_k = &qcc * &kff;
            let qcc_gain = &qcc * &gain;
            self.p[k] = qz + gain.transpose() * (&qcc_k + &qc) + qcz.transpose() * &kff;
            let mut pk = qzz + gain.transpose() * (&qcc_gain + &qcz) + qcz.transpose() * &gain;
            let sym = (&pk + pk.transpose()) * 0.5;
            pk.copy_from(&sym);
            self.pm[k] = pk;
            self.k[k] = kff;
            self.gain[k] = gain;
            self.qc[k] = qc;
            self.qcc[k] = qcc;
        }
        true
    }

    /// The terms of the model of the cost decrease (Mastalli et al. 2020, eq. 19, written for
    /// this file's signs): `(d_g, d_q)` with `d_g = −Σ Q_cᵀ k − Σ (p + P f̄)ᵀ f̄` and
    /// `d_q = −Σ kᵀ Q_cc k + Σ f̄ᵀ P f̄` (the gap terms only when infeasible).
    pub fn expected_terms(&self, gaps: &[DVector<f64>], feasible: bool) -> (f64, f64) {
        let (mut dg, mut dq) = (0.0, 0.0);
        for k in 0..self.k.len() {
            dg -= self.qc[k].dot(&self.k[k]);
            dq -= self.k[k].dot(&(&self.qcc[k] * &self.k[k]));
        }
        if !feasible {
            for (k, f) in gaps.iter().enumerate() {
                let pf = &self.pm[k] * f;
                dg -= (&self.p[k] + &pf).dot(f);
                dq += f.dot(&pf);
            }
        }
        (dg, dq)
    }
}
