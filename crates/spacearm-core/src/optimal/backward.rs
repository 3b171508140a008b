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
    /// Workspaces of one knot (allocated once: the pass allocates nothing but the box QP's).
    work: Work,
}

struct Work {
    pplus: DVector<f64>,
    pa: DMatrix<f64>,
    pb: DMatrix<f64>,
    qz: DVector<f64>,
    qzz: DMatrix<f64>,
    qcz: DMatrix<f64>,
    vm: DVector<f64>,
    mnd: DMatrix<f64>,
    chol: DMatrix<f64>,
    at: DMatrix<f64>,
    bt: DMatrix<f64>,
    gt: DMatrix<f64>,
    qczt: DMatrix<f64>,
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
            work: Work {
                pplus: DVector::zeros(nd),
                pa: DMatrix::zeros(nd, nd),
                pb: DMatrix::zeros(nd, m),
                qz: DVector::zeros(nd),
                qzz: DMatrix::zeros(nd, nd),
                qcz: DMatrix::zeros(m, nd),
                vm: DVector::zeros(m),
                mnd: DMatrix::zeros(m, nd),
                chol: DMatrix::zeros(m, m),
                at: DMatrix::zeros(nd, nd),
                bt: DMatrix::zeros(m, nd),
                gt: DMatrix::zeros(nd, m),
                qczt: DMatrix::zeros(nd, m),
            },
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
        let w = &mut self.work;
        for k in (0..t).rev() {
            let kn = &knots[k];
            let (head, tail) = self.pm.split_at_mut(k + 1);
            let pn = &tail[0];
            w.pplus.copy_from(&self.p[k + 1]);
            if !feasible {
                w.pplus.gemv(1.0, pn, &gaps[k + 1], 1.0);
            }
            w.pa.gemm(1.0, pn, &kn.a, 0.0);
            w.pb.gemm(1.0, pn, &kn.b, 0.0);
            w.qz.copy_from(&kn.lz);
            w.qz.gemv_tr(1.0, &kn.a, &w.pplus, 1.0);
            let qc = &mut self.qc[k];
            qc.copy_from(&kn.lc);
            qc.gemv_tr(1.0, &kn.b, &w.pplus, 1.0);
            // The transposed products through explicit transposes (the blocked gemm is faster
            // than the dot-product gemm_tr at these sizes).
            kn.a.transpose_to(&mut w.at);
            kn.b.transpose_to(&mut w.bt);
            w.qzz.copy_from(&kn.lzz);
            w.qzz.gemm(1.0, &w.at, &w.pa, 1.0);
            w.qcz.copy_from(&kn.lcz);
            w.qcz.gemm(1.0, &w.bt, &w.pa, 1.0);
            let qcc = &mut self.qcc[k];
            qcc.copy_from(&kn.lcc);
            qcc.gemm(1.0, &w.bt, &w.pb, 1.0);
            for i in 0..qcc.nrows() {
                qcc[(i, i)] += mu;
            }
            let m = qc.len();
            let (kff, gain) = (&mut self.k[k], &mut self.gain[k]);
            if bounded {
                let lo: Vec<f64> = (0..m).map(|i| lower[i] - cs[k][i]).collect();
                let hi: Vec<f64> = (0..m).map(|i| upper[i] - cs[k][i]).collect();
                let Some(sol) = solve_box_qp(qcc, qc, &lo, &hi, kff) else {
                    return false;
                };
                gain.fill(0.0);
                if let Some(f) = &sol.free_factor {
                    let idx: Vec<usize> = (0..m).filter(|i| sol.free[*i]).collect();
                    let rows = DMatrix::from_fn(idx.len(), w.qz.len(), |a, b| w.qcz[(idx[a], b)]);
                    let kf = -f.solve(&rows);
                    for (a, i) in idx.iter().enumerate() {
                        gain.row_mut(*i).copy_from(&kf.row(a));
                    }
                }
                kff.copy_from(&sol.x);
            } else {
                w.chol.copy_from(qcc);
                let Some(chol) = w.chol.clone().cholesky() else {
                    return false;
                };
                kff.copy_from(qc);
                chol.solve_mut(kff);
                kff.neg_mut();
                gain.copy_from(&w.qcz);
                chol.solve_mut(gain);
                gain.neg_mut();
            }
            // pₖ = Q_z + Kᵀ (Q_cc k + Q_c) + Q_czᵀ k; Pₖ = Q_zz + Kᵀ (Q_cc K + Q_cz) + Q_czᵀ K.
            w.vm.copy_from(qc);
            w.vm.gemv(1.0, qcc, kff, 1.0);
            let p = &mut self.p[k];
            p.copy_from(&w.qz);
            p.gemv_tr(1.0, gain, &w.vm, 1.0);
            p.gemv_tr(1.0, &w.qcz, kff, 1.0);
            w.mnd.copy_from(&w.qcz);
            w.mnd.gemm(1.0, qcc, gain, 1.0);
            let pk = &mut head[k];
            pk.copy_from(&w.qzz);
            gain.transpose_to(&mut w.gt);
            w.qcz.transpose_to(&mut w.qczt);
            pk.gemm(1.0, &w.gt, &w.mnd, 1.0);
            pk.gemm(1.0, &w.qczt, gain, 1.0);
            let n = pk.nrows();
            for i in 0..n {
                for j in i + 1..n {
                    let v = 0.5 * (pk[(i, j)] + pk[(j, i)]);
                    pk[(i, j)] = v;
                    pk[(j, i)] = v;
                }
            }
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
