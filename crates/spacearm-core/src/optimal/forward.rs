//! The nonlinear forward pass of FDDP (Mastalli et al. 2020, §IV-B): with step length `α`,
//!
//! `ẑ_0 = z_0 ⊕ α f̄_0`, `ĉ_k = clamp(c_k + α k_k + K_k (ẑ_k ⊖ z_k))`,
//! `ẑ_{k+1} = Φ(ẑ_k, ĉ_k) ⊕ (α − 1) f̄_{k+1}`,
//!
//! so that every gap shrinks to `(1 − α)` of its size (closed at `α = 1`, where the rollout is
//! the nonlinear dynamics'), the controls kept within their bounds (box-FDDP). Returns the
//! cost of the trial; a step that fails (a non-finite state) gives `+∞`.

use nalgebra::DVector;

use super::backward::Backward;
use super::shooting::ShootingProblem;
use crate::error::Result;

/// A trial trajectory: states `T+1`, controls `T`, `Φ(ẑ_k, ĉ_k)` for `k < T`.
#[derive(Debug, Clone)]
pub struct Trajectory {
    /// States.
    pub zs: Vec<Vec<f64>>,
    /// Controls.
    pub cs: Vec<Vec<f64>>,
    /// The step ends `Φ(z_k, c_k)`.
    pub next: Vec<Vec<f64>>,
}

impl Trajectory {
    /// Zeros of the problem's sizes.
    pub fn zeros(problem: &dyn ShootingProblem) -> Self {
        let t = problem.horizon();
        Trajectory { zs: vec![vec![0.0; problem.nz()]; t + 1], cs: vec![vec![0.0; problem.nc()]; t], next: vec![vec![0.0; problem.nz()]; t] }
    }
}

/// The rollout of module docs from `base` (with its gaps) into `trial`; returns the total cost.
pub fn forward_pass(problem: &mut dyn ShootingProblem, base: &Trajectory, gaps: &[DVector<f64>], bw: &Backward, alpha: f64, feasible: bool, trial: &mut Trajectory) -> Result<f64> {
    let t = problem.horizon();
    let (nd, m) = (problem.nd(), problem.nc());
    let mut dz = vec![0.0; nd];
    let mut scaled = vec![0.0; nd];
    if feasible {
        trial.zs[0].copy_from_slice(&base.zs[0]);
    } else {
        for (s, g) in scaled.iter_mut().zip(gaps[0].iter()) {
            *s = alpha * g;
        }
        problem.integrate(&base.zs[0], &scaled, &mut trial.zs[0]);
    }
    let mut cost = 0.0;
    for k in 0..t {
        problem.diff(&base.zs[k], &trial.zs[k], &mut dz);
        let gain = &bw.gain[k];
        for i in 0..m {
            let fb: f64 = dz.iter().enumerate().map(|(j, d)| gain[(i, j)] * d).sum();
            trial.cs[k][i] = (base.cs[k][i] + alpha * bw.k[k][i] + fb).max(problem.lower()[i]).min(problem.upper()[i]);
        }
        let (zk, rest) = trial.zs.split_at_mut(k + 1);
        let c = match problem.running(k, &zk[k], &trial.cs[k], &mut trial.next[k]) {
            Ok(c) => c,
            Err(_) => return Ok(f64::INFINITY),
        };
        cost += c;
        if feasible || alpha == 1.0 {
            rest[0].copy_from_slice(&trial.next[k]);
        } else {
            for (s, g) in scaled.iter_mut().zip(gaps[k + 1].iter()) {
                *s = (alpha - 1.0) * g;
            }
            problem.integrate(&trial.next[k], &scaled, &mut rest[0]);
        }
        if rest[0].iter().any(|v| !v.is_finite()) {
            return Ok(f64::INFINITY);
        }
    }
    cost += match problem.terminal(&trial.zs[t]) {
        Ok(c) => c,
        Err(_) => return Ok(f64::INFINITY),
    };
    Ok(if cost.is_finite() { cost } else { f64::INFINITY })
}
