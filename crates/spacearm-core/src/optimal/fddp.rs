//! The FDDP solver loop (Mastalli et al. 2020, Algorithm 1, with box-constrained controls):
//! derivatives along the current trajectory, the backward pass with Levenberg–Marquardt
//! regularization `μ` ([`super::backward`]), a backtracking line search on the nonlinear
//! rollout ([`super::forward`]) judged against the model of the cost decrease, and the update
//! of `μ`; warm started from a guess of states and controls; stopped by convergence, an
//! iteration limit, a time limit or the regularization limit — the reason is reported.
//!
//! Acceptance of a step of length `α` with actual decrease `ΔV = J − J_trial` and predicted
//! `ΔV_exp = α (d₁ + ½ α d₂)` (`d₁ = d_g + d_v`, `d₂ = d_q − 2 d_v`, `d_v = Σ f̄ₖᵀ Pₖ (ẑₖ ⊖ zₖ)`):
//! `ΔV ≥ θ ΔV_exp` when a decrease is predicted; when closing the gaps is predicted to raise
//! the cost (`ΔV_exp < 0`), a rise at most `1/θ` times the predicted one (`θ = 0.1`).
//! Converged: the trajectory is feasible (every gap below `gap_tolerance`) and the predicted
//! decrease of a full step, `d_g`... ½ `Σ Q_cᵀ Q_cc⁻¹ Q_c` at a feasible point, is below `tolerance`.

use std::time::Instant;

use nalgebra::DVector;
use serde::{Deserialize, Serialize};

use super::backward::Backward;
use super::forward::{forward_pass, Trajectory};
use super::shooting::{KnotModel, ShootingProblem};
use crate::error::{Result, SpacearmError};

fn hundred() -> usize {
    100
}
fn inf() -> f64 {
    f64::INFINITY
}
fn tol() -> f64 {
    1e-9
}
fn reg_init() -> f64 {
    1e-9
}

/// The solver's settings (serde data of the run description).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverOptions {
    /// The most iterations (accepted or refused steps), default 100.
    #[serde(default = "hundred")]
    pub max_iterations: usize,
    /// The most wall-clock time, s (checked before each iteration; default none).
    #[serde(default = "inf")]
    pub time_limit: f64,
    /// Converged when feasible and the predicted decrease `d_g` is below this (cost units; default 1e-9).
    #[serde(default = "tol")]
    pub tolerance: f64,
    /// Feasible when every gap's norm is below this (default 1e-9).
    #[serde(default = "tol")]
    pub gap_tolerance: f64,
    /// The initial regularization `μ` (default 1e-9); it is raised ×10 on a failed step and
    /// lowered ÷10 on a full one, within `[1e-9·[initial ≠ 0], 1e9]`.
    #[serde(default = "reg_init")]
    pub regularization: f64,
}

impl Default for SolverOptions {
    fn default() -> Self {
        SolverOptions { max_iterations: 100, time_limit: f64::INFINITY, tolerance: 1e-9, gap_tolerance: 1e-9, regularization: 1e-9 }
    }
}

impl SolverOptions {
    /// Check the numbers.
    pub fn validate(&self) -> Result<()> {
        if self.time_limit.is_nan() || self.time_limit <= 0.0 {
            return Err(SpacearmError::argument(format!("time_limit must be > 0 s, got {}", self.time_limit)));
        }
        for (what, v) in [("tolerance", self.tolerance), ("gap_tolerance", self.gap_tolerance), ("regularization", self.regularization)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SpacearmError::argument(format!("{what} must be a finite number ≥ 0, got {v}")));
            }
        }
        Ok(())
    }
}

/// Why the solver stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// Feasible, and the predicted decrease below the tolerance.
    Converged,
    /// `max_iterations` reached.
    IterationLimit,
    /// `time_limit` reached.
    TimeLimit,
    /// The regularization reached its largest value (no step decreases the cost).
    RegularizationLimit,
}

impl StopReason {
    /// The reason's name (`"converged"`, `"iteration_limit"`, `"time_limit"`, `"regularization_limit"`).
    pub fn name(self) -> &'static str {
        match self {
            StopReason::Converged => "converged",
            StopReason::IterationLimit => "iteration_limit",
            StopReason::TimeLimit => "time_limit",
            StopReason::RegularizationLimit => "regularization_limit",
        }
    }
}

/// The solver's result: the last iterate and how it was reached.
#[derive(Debug, Clone)]
pub struct Solution {
    /// States `z_0 … z_T`.
    pub zs: Vec<Vec<f64>>,
    /// Controls `c_0 … c_{T−1}`.
    pub cs: Vec<Vec<f64>>,
    /// The total cost.
    pub cost: f64,
    /// Iterations run (backward passes that led to a step or to its refusal).
    pub iterations: usize,
    /// Accepted steps.
    pub steps: usize,
    /// Why it stopped.
    pub stop: StopReason,
    /// The largest gap norm of the last iterate.
    pub gap: f64,
    /// The last predicted decrease `d_g`.
    pub expected_decrease: f64,
    /// The last regularization.
    pub regularization: f64,
    /// Wall-clock time of the solve, s.
    pub solve_time: f64,
}

impl Solution {
    /// Whether it converged.
    pub fn converged(&self) -> bool {
        self.stop == StopReason::Converged
    }
}

const MU_MAX: f64 = 1e9;
const FACTOR: f64 = 10.0;
const THETA: f64 = 0.1;
const ALPHAS: usize = 10;

/// The running knots' linearization points, costs and step ends, kept so that a receding-horizon
/// solve shifted by [`Workspace::shift`] recomputes only the knots whose point changed.
struct KnotCache {
    z: Vec<Vec<f64>>,
    c: Vec<Vec<f64>>,
    cost: Vec<f64>,
    next: Vec<Vec<f64>>,
    valid: Vec<bool>,
}

impl KnotCache {
    fn rotate_left(&mut self, shift: usize) {
        let t = self.valid.len();
        let shift = shift.min(t);
        self.z.rotate_left(shift);
        self.c.rotate_left(shift);
        self.cost.rotate_left(shift);
        self.next.rotate_left(shift);
        self.valid.rotate_left(shift);
        self.valid[t - shift..].fill(false);
    }
}

/// Bit for bit the same numbers.
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Evaluate the cost, the step ends and the knot models along `traj`; returns the cost. With
/// `reuse`, a running knot whose state and control are bit for bit those of its kept
/// linearization (`cache`) takes the kept model, cost and step end: the same numbers its
/// evaluation would give (the problem is time invariant: a knot's model is a function of its
/// state and control).
fn calc_diff(problem: &mut dyn ShootingProblem, traj: &mut Trajectory, knots: &mut [KnotModel], cache: &mut KnotCache, reuse: bool) -> Result<f64> {
    let t = problem.horizon();
    let mut cost = 0.0;
    for (k, knot) in knots.iter_mut().take(t).enumerate() {
        if reuse && cache.valid[k] && same_bits(&cache.z[k], &traj.zs[k]) && same_bits(&cache.c[k], &traj.cs[k]) {
            traj.next[k].copy_from_slice(&cache.next[k]);
            cost += cache.cost[k];
            continue;
        }
        cache.valid[k] = false;
        let c = problem.running_with_derivatives(k, &traj.zs[k], &traj.cs[k], &mut traj.next[k], knot)?;
        cache.z[k].copy_from_slice(&traj.zs[k]);
        cache.c[k].copy_from_slice(&traj.cs[k]);
        cache.next[k].copy_from_slice(&traj.next[k]);
        cache.cost[k] = c;
        cache.valid[k] = true;
        cost += c;
    }
    cost += problem.terminal(&traj.zs[t])?;
    problem.terminal_derivatives(&traj.zs[t], &mut knots[t])?;
    Ok(cost)
}

/// The gaps `f̄_0 = z̄_0 ⊖ z_0`, `f̄_{k+1} = Φ(z_k, c_k) ⊖ z_{k+1}`; returns the largest norm.
fn gaps(problem: &dyn ShootingProblem, traj: &Trajectory, out: &mut [DVector<f64>]) -> f64 {
    let mut worst: f64 = 0.0;
    problem.diff(&traj.zs[0], problem.initial_state(), out[0].as_mut_slice());
    worst = worst.max(out[0].norm());
    for k in 0..traj.cs.len() {
        problem.diff(&traj.zs[k + 1], &traj.next[k], out[k + 1].as_mut_slice());
        worst = worst.max(out[k + 1].norm());
    }
    worst
}

/// The solver's workspaces for a problem's sizes (the trajectories, the knot models, the gaps,
/// the backward pass's): a receding-horizon law keeps one across its solves
/// ([`crate::control::mpc`]) and allocates nothing per solve but the result.
pub struct Workspace {
    sizes: (usize, usize, usize, usize),
    traj: Trajectory,
    trial: Trajectory,
    knots: Vec<KnotModel>,
    fbar: Vec<DVector<f64>>,
    bw: Backward,
    dz: Vec<f64>,
    cache: KnotCache,
    /// Whether the next solve may take kept knot models ([`Workspace::shift`]).
    carry: bool,
}

impl Workspace {
    /// Workspaces for `problem`'s horizon and dimensions.
    pub fn new(problem: &dyn ShootingProblem) -> Self {
        let (t, nz, nd, m) = (problem.horizon(), problem.nz(), problem.nd(), problem.nc());
        Workspace {
            sizes: (t, nz, nd, m),
            traj: Trajectory::zeros(problem),
            trial: Trajectory::zeros(problem),
            knots: vec![KnotModel::zeros(nd, m); t + 1],
            fbar: vec![DVector::zeros(nd); t + 1],
            bw: Backward::new(t, nd, m),
            dz: vec![0.0; nd],
            cache: KnotCache { z: vec![vec![0.0; nz]; t], c: vec![vec![0.0; m]; t], cost: vec![0.0; t], next: vec![vec![0.0; nz]; t], valid: vec![false; t] },
            carry: false,
        }
    }

    /// Prepare the next solve's warm start by a receding horizon: the guess it will be given
    /// is the last solution moved `shift` knots towards the start (knot `j` ← knot `j + shift`,
    /// as [`crate::control::mpc`] does), so the knot models kept from the last linearization
    /// move with it; the next solve takes those whose state and control are bit for bit the
    /// guess's (when the problem is time invariant, [`ShootingProblem::time_invariant`]) and
    /// evaluates the others. The result is the one a fresh workspace gives, in less time.
    pub fn shift(&mut self, shift: usize) {
        self.cache.rotate_left(shift);
        let t = self.sizes.0;
        self.knots[..t].rotate_left(shift.min(t));
        self.carry = true;
    }
}

/// Solve `problem` by FDDP (module docs) from the guess `zs` (`T+1` states; `None`: the rollout
/// of the controls from the initial state, a feasible start) and `cs` (`T` controls; `None`:
/// zeros), clamped to the bounds.
pub fn solve(problem: &mut dyn ShootingProblem, zs: Option<&[Vec<f64>]>, cs: Option<&[Vec<f64>]>, opts: &SolverOptions) -> Result<Solution> {
    let mut ws = Workspace::new(problem);
    solve_in(&mut ws, problem, zs, cs, opts)
}

/// [`solve`] in the workspaces `ws` (made for a problem of the same sizes).
pub fn solve_in(ws: &mut Workspace, problem: &mut dyn ShootingProblem, zs: Option<&[Vec<f64>]>, cs: Option<&[Vec<f64>]>, opts: &SolverOptions) -> Result<Solution> {
    opts.validate()?;
    let start = Instant::now();
    let t = problem.horizon();
    let (nz, nd, m) = (problem.nz(), problem.nd(), problem.nc());
    if ws.sizes != (t, nz, nd, m) {
        return Err(SpacearmError::argument("the solver's workspace was made for a problem of other sizes"));
    }
    let Workspace { traj, trial, knots, fbar, bw, dz, cache, carry, .. } = ws;
    let reuse = std::mem::take(carry) && problem.time_invariant();
    // A solve owes nothing to the workspace's last one (the box QPs start from the feedforward
    // kept there): a kept workspace and a fresh one give the same numbers.
    for k in bw.k.iter_mut() {
        k.fill(0.0);
    }
    for c in traj.cs.iter_mut() {
        c.fill(0.0);
    }
    if let Some(cs) = cs {
        if cs.len() != t || cs.iter().any(|c| c.len() != m || c.iter().any(|v| !v.is_finite())) {
            return Err(SpacearmError::argument(format!("the initial controls must be {t} finite rows of {m}")));
        }
        for (dst, src) in traj.cs.iter_mut().zip(cs) {
            for i in 0..m {
                dst[i] = src[i].max(problem.lower()[i]).min(problem.upper()[i]);
            }
        }
    }
    match zs {
        Some(zs) => {
            if zs.len() != t + 1 || zs.iter().any(|z| z.len() != nz || z.iter().any(|v| !v.is_finite())) {
                return Err(SpacearmError::argument(format!("the initial states must be {} finite rows of {nz}", t + 1)));
            }
            for (dst, src) in traj.zs.iter_mut().zip(zs) {
                dst.copy_from_slice(src);
                problem.project(dst);
            }
        }
        None => {
            traj.zs[0].copy_from_slice(problem.initial_state());
            for k in 0..t {
                let (a, b) = traj.zs.split_at_mut(k + 1);
                problem.running(k, &a[k], &traj.cs[k], &mut b[0])?;
            }
        }
    }
    let mut cost = calc_diff(problem, traj, knots, cache, reuse)?;
    let mut gap = gaps(problem, traj, fbar);
    let mut feasible = gap < opts.gap_tolerance;
    let mu_min = if opts.regularization > 0.0 { 1e-9f64.min(opts.regularization) } else { 0.0 };
    let mut mu = opts.regularization;
    let (mut iterations, mut steps, mut dg) = (0, 0, f64::INFINITY);
    let (lower, upper) = (problem.lower().to_vec(), problem.upper().to_vec());
    let stop = loop {
        if start.elapsed().as_secs_f64() >= opts.time_limit {
            break StopReason::TimeLimit;
        }
        if iterations >= opts.max_iterations {
            break StopReason::IterationLimit;
        }
        if !bw.run(knots, fbar, &traj.cs, &lower, &upper, mu, feasible) {
            mu = if mu == 0.0 { 1e-9 } else { mu * FACTOR };
            if mu > MU_MAX {
                break StopReason::RegularizationLimit;
            }
            continue;
        }
        let (g, q) = bw.expected_terms(fbar, feasible);
        dg = g;
        if feasible && dg.abs() < opts.tolerance {
            break StopReason::Converged;
        }
        iterations += 1;
        let mut accepted = false;
        let mut alpha: f64 = 1.0;
        let mut cost_try = f64::INFINITY;
        for _ in 0..ALPHAS {
            cost_try = forward_pass(problem, traj, fbar, bw, alpha, feasible, trial)?;
            if cost_try.is_finite() {
                let mut dv = 0.0;
                if !feasible {
                    for (k, f) in fbar.iter().enumerate() {
                        problem.diff(&traj.zs[k], &trial.zs[k], dz);
                        let pm = &bw.pm[k];
                        for (j, d) in dz.iter().enumerate() {
                            dv += d * f.dot(&pm.column(j));
                        }
                    }
                }
                let (d1, d2) = (g + dv, q - 2.0 * dv);
                let expected = alpha * (d1 + 0.5 * alpha * d2);
                let actual = cost - cost_try;
                let ok = if expected >= 0.0 { actual >= THETA * expected || d1.abs() < opts.tolerance } else { actual >= expected / THETA };
                if ok {
                    accepted = true;
                    break;
                }
            }
            alpha *= 0.5;
        }
        if !accepted {
            mu = if mu == 0.0 { 1e-9 } else { mu * FACTOR };
            if mu > MU_MAX {
                break StopReason::RegularizationLimit;
            }
            continue;
        }
        steps += 1;
        std::mem::swap(traj, trial);
        if alpha == 1.0 {
            mu = (mu / FACTOR).max(mu_min);
        }
        // The derivatives at the new iterate are for the next iteration: none comes when a
        // limit stops the solver (the loop's checks above), so skip them then (the rollout gave
        // the cost and the step ends).
        cost = if iterations >= opts.max_iterations || start.elapsed().as_secs_f64() >= opts.time_limit { cost_try } else { calc_diff(problem, traj, knots, cache, false)? };
        gap = gaps(problem, traj, fbar);
        feasible = feasible || alpha == 1.0 || gap < opts.gap_tolerance;
        if feasible {
            gap = 0.0;
            for f in fbar.iter_mut() {
                f.fill(0.0);
            }
        }
    };
    Ok(Solution {
        zs: traj.zs.clone(),
        cs: traj.cs.clone(),
        cost,
        iterations,
        steps,
        stop,
        gap,
        expected_decrease: dg,
        regularization: mu,
        solve_time: start.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;
    use crate::optimal::costs::{CostSpec, Numbers};
    use crate::optimal::problem::{ProblemSpec, RobotProblem};
    use nalgebra::DMatrix;

    /// A linear-quadratic problem on ℝⁿ: `z⁺ = A z + B c + d`, `ℓ = ½ zᵀ Q z + qᵀ z + ½ cᵀ R c`,
    /// `ℓ_T = ½ zᵀ Q_T z`.
    struct Lq {
        a: DMatrix<f64>,
        b: DMatrix<f64>,
        d: DVector<f64>,
        q: DMatrix<f64>,
        qv: DVector<f64>,
        r: DMatrix<f64>,
        qt: DMatrix<f64>,
        z0: Vec<f64>,
        t: usize,
        lo: Vec<f64>,
        hi: Vec<f64>,
        /// Knot linearizations evaluated.
        evals: usize,
    }

    impl Lq {
        fn new() -> Lq {
            let a = DMatrix::from_row_slice(3, 3, &[1.0, 0.1, 0.0, -0.2, 1.0, 0.1, 0.05, 0.0, 0.9]);
            let b = DMatrix::from_row_slice(3, 2, &[0.0, 0.1, 0.1, 0.0, 0.05, -0.1]);
            let q = DMatrix::from_row_slice(3, 3, &[2.0, 0.3, 0.0, 0.3, 1.0, 0.1, 0.0, 0.1, 0.5]);
            let inf = f64::INFINITY;
            Lq {
                a,
                b,
                d: DVector::from_row_slice(&[0.01, -0.02, 0.03]),
                q: q.clone(),
                qv: DVector::from_row_slice(&[0.1, -0.2, 0.3]),
                r: DMatrix::from_row_slice(2, 2, &[0.5, 0.1, 0.1, 0.3]),
                qt: q * 10.0,
                z0: vec![1.0, -0.5, 0.25],
                t: 6,
                lo: vec![-inf; 2],
                hi: vec![inf; 2],
                evals: 0,
            }
        }

        /// The minimizer by elimination of the states: `z = S z0 + s + M c` stacked, one
        /// symmetric linear system in all controls (not a Riccati recursion).
        fn closed_form(&self) -> (Vec<Vec<f64>>, f64) {
            let (n, m, t) = (3, 2, self.t);
            // z_k = Φ_k (affine in c): z_k = c0_k + Σ_j G_kj c_j.
            let mut offs = vec![DVector::from_column_slice(&self.z0)];
            let mut g: Vec<DMatrix<f64>> = vec![DMatrix::zeros(n, m * t)];
            for k in 0..t {
                let o = &self.a * &offs[k] + &self.d;
                let mut gk = &self.a * &g[k];
                let mut col = gk.columns_mut(k * m, m);
                col += &self.b;
                offs.push(o);
                g.push(gk);
            }
            let mut h = DMatrix::zeros(m * t, m * t);
            let mut grad = DVector::zeros(m * t);
            for k in 0..=t {
                let qk = if k == t { &self.qt } else { &self.q };
                h += g[k].transpose() * qk * &g[k];
                grad += g[k].transpose() * (qk * &offs[k]);
                if k < t {
                    grad += g[k].transpose() * &self.qv;
                    let mut blk = h.view_mut((k * m, k * m), (m, m));
                    blk += &self.r;
                }
            }
            let c = -h.clone().cholesky().unwrap().solve(&grad);
            let cs: Vec<Vec<f64>> = (0..t).map(|k| c.rows(k * m, m).iter().copied().collect()).collect();
            let mut cost = 0.0;
            for k in 0..=t {
                let z = &offs[k] + &g[k] * &c;
                if k < t {
                    let ck = c.rows(k * m, m);
                    cost += 0.5 * z.dot(&(&self.q * &z)) + self.qv.dot(&z) + 0.5 * ck.dot(&(&self.r * ck));
                } else {
                    cost += 0.5 * z.dot(&(&self.qt * &z));
                }
            }
            (cs, cost)
        }
    }

    impl ShootingProblem for Lq {
        fn horizon(&self) -> usize {
            self.t
        }
        fn nz(&self) -> usize {
            3
        }
        fn nd(&self) -> usize {
            3
        }
        fn nc(&self) -> usize {
            2
        }
        fn lower(&self) -> &[f64] {
            &self.lo
        }
        fn upper(&self) -> &[f64] {
            &self.hi
        }
        fn initial_state(&self) -> &[f64] {
            &self.z0
        }
        fn diff(&self, z0: &[f64], z1: &[f64], out: &mut [f64]) {
            for i in 0..3 {
                out[i] = z1[i] - z0[i];
            }
        }
        fn integrate(&self, z: &[f64], dz: &[f64], out: &mut [f64]) {
            for i in 0..3 {
                out[i] = z[i] + dz[i];
            }
        }
        fn running(&mut self, _k: usize, z: &[f64], c: &[f64], next: &mut [f64]) -> Result<f64> {
            let (zv, cv) = (DVector::from_column_slice(z), DVector::from_column_slice(c));
            next.copy_from_slice((&self.a * &zv + &self.b * &cv + &self.d).as_slice());
            Ok(0.5 * zv.dot(&(&self.q * &zv)) + self.qv.dot(&zv) + 0.5 * cv.dot(&(&self.r * &cv)))
        }
        fn time_invariant(&self) -> bool {
            true
        }
        fn running_derivatives(&mut self, _k: usize, z: &[f64], c: &[f64], out: &mut KnotModel) -> Result<()> {
            self.evals += 1;
            let (zv, cv) = (DVector::from_column_slice(z), DVector::from_column_slice(c));
            out.a.copy_from(&self.a);
            out.b.copy_from(&self.b);
            out.lz = &self.q * &zv + &self.qv;
            out.lc = &self.r * &cv;
            out.lzz.copy_from(&self.q);
            out.lcc.copy_from(&self.r);
            out.lcz.fill(0.0);
            Ok(())
        }
        fn terminal(&mut self, z: &[f64]) -> Result<f64> {
            let zv = DVector::from_column_slice(z);
            Ok(0.5 * zv.dot(&(&self.qt * &zv)))
        }
        fn terminal_derivatives(&mut self, z: &[f64], out: &mut KnotModel) -> Result<()> {
            out.clear_cost();
            out.lz = &self.qt * DVector::from_column_slice(z);
            out.lzz.copy_from(&self.qt);
            Ok(())
        }
    }

    #[test]
    fn the_unconstrained_lq_problem_converges_in_one_step_to_the_closed_form() {
        let mut lq = Lq::new();
        let (exact, exact_cost) = lq.closed_form();
        let opts = SolverOptions { regularization: 0.0, ..Default::default() };
        // Feasible start (the rollout of zero controls) and an infeasible one (arbitrary states:
        // gaps everywhere, closed by the one full step).
        let wild: Vec<Vec<f64>> = (0..=lq.t).map(|k| vec![k as f64, -(k as f64) * 0.5, 2.0]).collect();
        for zs in [None, Some(wild.as_slice())] {
            let sol = solve(&mut lq, zs, None, &opts).unwrap();
            assert_eq!(sol.stop, StopReason::Converged, "{:?}", sol.stop);
            assert_eq!(sol.steps, 1, "one Newton step solves an LQ problem");
            assert!((sol.cost - exact_cost).abs() < 1e-12 * (1.0 + exact_cost.abs()), "{} vs {exact_cost}", sol.cost);
            for (c, e) in sol.cs.iter().zip(&exact) {
                for (a, b) in c.iter().zip(e) {
                    assert!((a - b).abs() < 1e-10, "{a} vs {b}");
                }
            }
            assert!(exact.iter().flatten().any(|c| c.abs() > 1e-2), "a trivial solution");
        }
    }

    #[test]
    fn bounded_lq_solution_satisfies_the_kkt_conditions() {
        let mut lq = Lq::new();
        lq.lo = vec![-0.3; 2];
        lq.hi = vec![0.3; 2];
        let sol = solve(&mut lq, None, None, &SolverOptions::default()).unwrap();
        assert!(sol.converged(), "{:?}", sol.stop);
        // The gradient of the single-shooting cost J(c) by central differences: zero on the free
        // controls, pointing out of the box on the clamped ones.
        let cost = |lq: &mut Lq, cs: &[Vec<f64>]| {
            let mut z = lq.z0.clone();
            let mut next = vec![0.0; 3];
            let mut j = 0.0;
            for c in cs {
                j += lq.running(0, &z, c, &mut next).unwrap();
                z.copy_from_slice(&next);
            }
            j + lq.terminal(&z).unwrap()
        };
        let mut clamped = 0;
        for k in 0..lq.t {
            for i in 0..2 {
                let (mut p, mut m) = (sol.cs.clone(), sol.cs.clone());
                p[k][i] += 1e-6;
                m[k][i] -= 1e-6;
                let g = (cost(&mut lq, &p) - cost(&mut lq, &m)) / 2e-6;
                let c = sol.cs[k][i];
                if (c.abs() - 0.3).abs() < 1e-12 {
                    clamped += 1;
                    assert!(g * c < 0.0, "clamped control {k},{i} = {c} with gradient {g}");
                } else {
                    assert!(g.abs() < 1e-6, "free control {k},{i}: gradient {g}");
                }
            }
        }
        assert!(clamped > 0, "the bounds bind");
    }

    /// A receding-horizon warm start through [`Workspace::shift`] gives a fresh workspace's
    /// numbers bit for bit and evaluates only the knots that changed.
    #[test]
    fn a_shifted_warm_start_keeps_the_unchanged_knots_and_their_numbers() {
        let mut lq = Lq::new();
        lq.lo = vec![-0.3; 2];
        lq.hi = vec![0.3; 2];
        let t = lq.t;
        let opts = SolverOptions::default();
        let mut ws = Workspace::new(&lq);
        let first = solve_in(&mut ws, &mut lq, None, None, &opts).unwrap();
        assert!(first.converged());
        for shift in [1, 2, t + 3] {
            let s = shift.min(t);
            let mut zs = first.zs.clone();
            let mut cs = first.cs.clone();
            zs.rotate_left(s);
            cs.rotate_left(s);
            for z in &mut zs[t + 1 - s..] {
                z.copy_from_slice(&first.zs[t]);
            }
            for c in &mut cs[t - s..] {
                c.copy_from_slice(&first.cs[t - 1]);
            }
            lq.z0 = first.zs[s].clone();
            lq.z0[0] += 0.05; // a measured state off the plan: a gap at the start
            let mut kept = Workspace::new(&lq);
            solve_in(&mut kept, &mut lq, None, None, &opts).unwrap();
            // The kept workspace must have been linearized at `first`: solve it again there.
            lq.z0 = vec![1.0, -0.5, 0.25];
            let again = solve_in(&mut kept, &mut lq, Some(&first.zs), Some(&first.cs), &opts).unwrap();
            assert!(again.converged());
            lq.z0 = first.zs[s].clone();
            lq.z0[0] += 0.05;
            kept.shift(shift);
            lq.evals = 0;
            let warm = solve_in(&mut kept, &mut lq, Some(&zs), Some(&cs), &opts).unwrap();
            let warm_evals = lq.evals;
            lq.evals = 0;
            let fresh = solve(&mut lq, Some(&zs), Some(&cs), &opts).unwrap();
            assert_eq!((warm.cs.clone(), warm.zs.clone(), warm.cost.to_bits(), warm.iterations), (fresh.cs.clone(), fresh.zs.clone(), fresh.cost.to_bits(), fresh.iterations));
            assert!(fresh.converged() && fresh.steps >= 1);
            assert_eq!(lq.evals - warm_evals, t - s, "shift {shift}: only the {s} last knots are evaluated again ({warm_evals} vs {})", lq.evals);
        }
    }

    fn planar_problem(limit: f64) -> (crate::Model, ProblemSpec, Vec<f64>) {
        let model = presets::planar4();
        let n = model.n_dof();
        let goal: Vec<f64> = model.initial_q().iter().zip([0.4, -0.3, 0.3, -0.2]).map(|(q, d)| q + d).collect();
        let spec = ProblemSpec {
            horizon: 10,
            dt: 0.1,
            mode: "floating".into(),
            running: vec![
                CostSpec::Joint { weight_q: Numbers::One(1.0), reference: goal.clone(), weight_qd: Numbers::One(0.1), velocity_reference: None },
                CostSpec::Control { weights: Numbers::One(1e-3), reference: None },
            ],
            terminal: vec![CostSpec::Joint { weight_q: Numbers::One(100.0), reference: goal, weight_qd: Numbers::One(10.0), velocity_reference: None }],
            control_limit: Numbers::One(limit),
            start_time: 0.0,
            discretization: Default::default(),
        };
        let mut z0 = vec![0.0; 13 + 2 * n];
        z0[6] = 1.0;
        z0[7..7 + n].copy_from_slice(model.initial_q());
        (model, spec, z0)
    }

    /// The robot's solution is a stationary point of the single-shooting cost `J(c)` (central
    /// differences of the simulator-step rollout: the derivative chain checked end to end).
    #[test]
    fn planar_arm_solution_is_stationary_and_respects_the_bounds() {
        for limit in [f64::INFINITY, 0.5] {
            let (model, spec, z0) = planar_problem(limit);
            let mut problem = RobotProblem::new(&model, &spec, &z0).unwrap();
            let opts = SolverOptions { tolerance: 1e-12, ..Default::default() };
            let sol = solve(&mut problem, None, None, &opts).unwrap();
            assert!(sol.converged(), "{:?} after {} iterations", sol.stop, sol.iterations);
            assert!(sol.cs.iter().flatten().all(|c| c.abs() <= limit));
            let cost = |p: &mut RobotProblem, cs: &[Vec<f64>]| {
                let mut z = z0.clone();
                let mut next = z.clone();
                let mut j = 0.0;
                for (k, c) in cs.iter().enumerate() {
                    j += p.running(k, &z, c, &mut next).unwrap();
                    z.copy_from_slice(&next);
                }
                j + p.terminal(&z).unwrap()
            };
            assert!((cost(&mut problem, &sol.cs) - sol.cost).abs() < 1e-12 * sol.cost);
            let mut clamped = 0;
            for k in [0, 4, 9] {
                for i in 0..4 {
                    let (mut p, mut m) = (sol.cs.clone(), sol.cs.clone());
                    let h = 1e-5;
                    p[k][i] += h;
                    m[k][i] -= h;
                    let g = (cost(&mut problem, &p) - cost(&mut problem, &m)) / (2.0 * h);
                    let c = sol.cs[k][i];
                    if (c.abs() - limit).abs() < 1e-12 {
                        clamped += 1;
                        assert!(g * c < 0.0, "clamped control {k},{i}: gradient {g}");
                    } else {
                        assert!(g.abs() < 1e-6, "limit {limit}: free control {k},{i}: gradient {g}");
                    }
                }
            }
            if limit.is_finite() {
                assert!(clamped > 0, "the bounds bind");
            }
            let zero_cost = cost(&mut problem, &vec![vec![0.0; 4]; 10]);
            assert!(sol.cost < 0.5 * zero_cost, "{} vs {zero_cost}", sol.cost);
        }
    }

    #[test]
    fn limits_are_reported_not_hidden() {
        let (model, spec, z0) = planar_problem(f64::INFINITY);
        let mut problem = RobotProblem::new(&model, &spec, &z0).unwrap();
        let sol = solve(&mut problem, None, None, &SolverOptions { max_iterations: 1, ..Default::default() }).unwrap();
        assert_eq!((sol.stop, sol.iterations), (StopReason::IterationLimit, 1));
        let sol = solve(&mut problem, None, None, &SolverOptions { time_limit: 1e-9, ..Default::default() }).unwrap();
        assert_eq!((sol.stop, sol.iterations), (StopReason::TimeLimit, 0));
        // A warm start from the solution converges at once.
        let full = solve(&mut problem, None, None, &SolverOptions::default()).unwrap();
        let warm = solve(&mut problem, Some(&full.zs), Some(&full.cs), &SolverOptions::default()).unwrap();
        assert!(warm.converged() && warm.steps <= 1, "{:?} {}", warm.stop, warm.steps);
        assert!(matches!(solve(&mut problem, None, Some(&[vec![0.0; 3]]), &SolverOptions::default()), Err(SpacearmError::InvalidArgument(_))));
    }
}
