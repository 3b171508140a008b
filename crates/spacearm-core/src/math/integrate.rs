//! Time integrators for the state `y = [x; u] = [r0, quat0, q, v0, ω0, q̇]` (length 13 + 2N):
//! fixed-step classical Runge–Kutta 4 and adaptive Dormand–Prince 5(4) with error control and
//! dense output (Hairer, Nørsett & Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
//! 1993, §II.1, §II.4–II.6; the step-size controller and initial step are those of their code
//! `DOPRI5`).
//!
//! ## The base attitude on the quaternion manifold
//!
//! The quaternion obeys `quaṫ = ½ [ω0; 0] ⊗ quat` (Hamilton, `[x, y, z, w]`, `ω0` in 𝒥, hence
//! the left product). Both integrators treat it as four components of this embedded ODE and
//! **renormalize**: every stage value is projected onto the unit sphere before the dynamics are
//! evaluated ([`OdeSystem::project`]), and every accepted step result is projected again. The
//! exact flow of the embedded ODE keeps `|quat|` constant (`ω ⊗ q ⟂ q` for a pure `ω`), so
//! evaluating the right-hand side at the projected stage is the same as integrating the smooth
//! ODE `f(y / |y|)`, whose solutions from a unit quaternion are those of the original one; the
//! final projection is the standard projection method (Hairer, Lubich & Wanner, *Geometric
//! Numerical Integration*, 2nd ed., §IV.4), which keeps the order of the underlying method.
//! After every step `| |quat| − 1 |` is at the level of rounding (tested to 1e-12).
//!
//! Everything here is deterministic: no threads, no randomness, fixed summation orders, so the
//! same inputs give bit-identical results. Workspaces are allocated once; a step allocates
//! nothing.

use crate::error::Result;

/// A first-order system `ẏ = f(t, y)` on a manifold embedded in ℝⁿ.
pub trait OdeSystem {
    /// Length of the state vector.
    fn dim(&self) -> usize;
    /// Map an (almost) valid state back onto the manifold in place (normalize the base
    /// quaternion). Called on every stage value and every accepted step result.
    fn project(&self, y: &mut [f64]);
    /// `dy = f(t, y)`.
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<()>;
}

/// Which integrator a simulation uses. As data it is its name ([`IntegratorKind::NAMES`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "String", into = "&'static str")]
pub enum IntegratorKind {
    /// Classical fourth-order Runge–Kutta with a fixed step `dt`.
    Rk4,
    /// Dormand–Prince 5(4), adaptive step with error control (`rtol`, `atol`); output at a
    /// fixed interval by its fourth-order dense output.
    Dopri5,
}

crate::error::named_by!(IntegratorKind, "integrator", [Rk4 = "rk4", Dopri5 = "dopri5"]);

/// `out = y + h Σ coef_j k_j` (fixed summation order).
#[inline]
fn combine(out: &mut [f64], y: &[f64], h: f64, terms: &[(f64, &[f64])]) {
    for i in 0..out.len() {
        let mut s = 0.0;
        for (c, k) in terms {
            s += c * k[i];
        }
        out[i] = y[i] + h * s;
    }
}

/// Classical Runge–Kutta 4 (Hairer et al. I, Table II.1.1) with preallocated stages.
#[derive(Debug, Clone)]
pub struct Rk4 {
    k1: Vec<f64>,
    k2: Vec<f64>,
    k3: Vec<f64>,
    k4: Vec<f64>,
    stage: Vec<f64>,
}

impl Rk4 {
    /// Workspace for a system of dimension `dim`.
    pub fn new(dim: usize) -> Self {
        Rk4 { k1: vec![0.0; dim], k2: vec![0.0; dim], k3: vec![0.0; dim], k4: vec![0.0; dim], stage: vec![0.0; dim] }
    }

    /// The first stage derivative `k1 = f(t, y)`; a caller that evaluated it already (to record
    /// the state) writes it here and passes `k1_ready = true` to [`Rk4::step`].
    pub fn k1_mut(&mut self) -> &mut [f64] {
        &mut self.k1
    }

    /// The first stage derivative of the last step (or as written through [`Rk4::k1_mut`]).
    pub fn k1(&self) -> &[f64] {
        &self.k1
    }

    /// Advance `y` in place from `t` to `t + h`; the result is projected onto the manifold.
    pub fn step<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, t: f64, h: f64, y: &mut [f64], k1_ready: bool) -> Result<()> {
        if !k1_ready {
            sys.rhs(t, y, &mut self.k1)?;
        }
        combine(&mut self.stage, y, 0.5 * h, &[(1.0, &self.k1)]);
        sys.project(&mut self.stage);
        sys.rhs(t + 0.5 * h, &self.stage, &mut self.k2)?;
        combine(&mut self.stage, y, 0.5 * h, &[(1.0, &self.k2)]);
        sys.project(&mut self.stage);
        sys.rhs(t + 0.5 * h, &self.stage, &mut self.k3)?;
        combine(&mut self.stage, y, h, &[(1.0, &self.k3)]);
        sys.project(&mut self.stage);
        sys.rhs(t + h, &self.stage, &mut self.k4)?;
        for i in 0..y.len() {
            y[i] += h / 6.0 * (self.k1[i] + 2.0 * self.k2[i] + 2.0 * self.k3[i] + self.k4[i]);
        }
        sys.project(y);
        Ok(())
    }

    /// The step from `(t0, y0)` to `t`, into `y` (`y0` left as it is): a step re-taken from its
    /// start to a located event ([`crate::sim::events`], [`crate::sim::contact_onset`]).
    pub fn step_from<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, t0: f64, y0: &[f64], t: f64, y: &mut [f64]) -> Result<()> {
        y.copy_from_slice(y0);
        self.step(sys, t0, t - t0, y, false)
    }
}

// Dormand–Prince 5(4) tableau (Hairer et al. I, Table II.5.2), a row a line: the nodes
// `c2..c5`, the stage rows `a_i = [a_i1, …]` (row 7 holds the fifth-order weights `b`: FSAL),
// the error coefficients `b − b̂` (fifth- minus fourth-order weights) and the dense output
// (Hairer et al. I, §II.6, the continuous extension of order 4 used by DOPRI5). Index `j`
// holds the coefficient of `k_{j+1}`; the zero ones (of `k2` in rows 7, E and D) are skipped.
const C: [f64; 4] = [1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0];
const A2: [f64; 1] = [1.0 / 5.0];
const A3: [f64; 2] = [3.0 / 40.0, 9.0 / 40.0];
const A4: [f64; 3] = [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0];
const A5: [f64; 4] = [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0];
const A6: [f64; 5] = [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0];
const A7: [f64; 6] = [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0];
const E: [f64; 7] = [71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0];
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// Outcome of one attempted adaptive step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOutcome {
    /// Whether the step met the tolerance and `y` now holds the state at `t + h`.
    pub accepted: bool,
    /// Scaled error norm of the attempt (≤ 1 when accepted).
    pub error: f64,
    /// Step size proposed for the next attempt.
    pub next_h: f64,
}

/// Dormand–Prince 5(4) with first-same-as-last, the PI step-size controller of `DOPRI5`
/// (safety 0.9, factor in [0.2, 10], β = 0.04) and dense output.
#[derive(Debug, Clone)]
pub struct Dopri5 {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    k: [Vec<f64>; 7],
    stage: Vec<f64>,
    y_new: Vec<f64>,
    /// Dense-output coefficients of the last accepted step.
    cont: [Vec<f64>; 5],
    fac_old: f64,
    last_rejected: bool,
    k1_valid: bool,
    /// Start of the last accepted step, s (for dense output).
    pub last_t: f64,
    /// Size of the last accepted step, s.
    pub last_h: f64,
}

impl Dopri5 {
    /// Workspace for a system of dimension `dim`.
    pub fn new(dim: usize, rtol: f64, atol: f64) -> Self {
        let v = || vec![0.0; dim];
        Dopri5 {
            rtol,
            atol,
            k: [v(), v(), v(), v(), v(), v(), v()],
            stage: v(),
            y_new: v(),
            cont: [v(), v(), v(), v(), v()],
            fac_old: 1e-4,
            last_rejected: false,
            k1_valid: false,
            last_t: 0.0,
            last_h: 0.0,
        }
    }

    /// `f(t, y)` at the current point, as computed by the last accepted step (first same as
    /// last) or by [`Dopri5::initial_step`].
    pub fn derivative(&self) -> &[f64] {
        &self.k[0]
    }

    #[inline]
    fn scale(&self, a: f64, b: f64) -> f64 {
        self.atol + self.rtol * a.abs().max(b.abs())
    }

    /// Initial step size by the heuristic of `DOPRI5`'s `HINIT` (Hairer et al. I, §II.4):
    /// evaluates `f(t, y)` (kept for the first step) and one trial Euler step.
    pub fn initial_step<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, t: f64, y: &[f64], h_max: f64) -> Result<f64> {
        sys.rhs(t, y, &mut self.k[0])?;
        self.k1_valid = true;
        let (mut dnf, mut dny) = (0.0, 0.0);
        for i in 0..y.len() {
            let sk = self.scale(y[i], y[i]);
            dnf += (self.k[0][i] / sk).powi(2);
            dny += (y[i] / sk).powi(2);
        }
        let mut h = if dnf <= 1e-10 || dny <= 1e-10 { 1e-6 } else { (dny / dnf).sqrt() * 0.01 };
        h = h.min(h_max);
        combine(&mut self.stage, y, h, &[(1.0, &self.k[0])]);
        sys.project(&mut self.stage);
        sys.rhs(t + h, &self.stage, &mut self.k[1])?;
        let mut der2 = 0.0;
        for i in 0..y.len() {
            let sk = self.scale(y[i], y[i]);
            der2 += ((self.k[1][i] - self.k[0][i]) / sk).powi(2);
        }
        let der2 = der2.sqrt() / h;
        let der12 = der2.abs().max(dnf.sqrt());
        let h1 = if der12 <= 1e-15 { (h * 1e-3).max(1e-6) } else { (0.01 / der12).powf(1.0 / 5.0) };
        Ok((100.0 * h).min(h1).min(h_max))
    }

    /// Attempt one step of size `h` from `(t, y)`. On acceptance `y` holds the (projected)
    /// state at `t + h`, the dense output covers `[t, t + h]` and `f` at the new point is kept
    /// for the next step. [`Dopri5::initial_step`] must have run first.
    pub fn try_step<S: OdeSystem + ?Sized>(&mut self, sys: &mut S, t: f64, h: f64, y: &mut [f64]) -> Result<StepOutcome> {
        if !self.k1_valid {
            sys.rhs(t, y, &mut self.k[0])?;
            self.k1_valid = true;
        }
        let [k1, k2, k3, k4, k5, k6, k7] = &mut self.k;
        combine(&mut self.stage, y, h, &[(A2[0], k1)]);
        sys.project(&mut self.stage);
        sys.rhs(t + C[0] * h, &self.stage, k2)?;
        combine(&mut self.stage, y, h, &[(A3[0], k1), (A3[1], k2)]);
        sys.project(&mut self.stage);
        sys.rhs(t + C[1] * h, &self.stage, k3)?;
        combine(&mut self.stage, y, h, &[(A4[0], k1), (A4[1], k2), (A4[2], k3)]);
        sys.project(&mut self.stage);
        sys.rhs(t + C[2] * h, &self.stage, k4)?;
        combine(&mut self.stage, y, h, &[(A5[0], k1), (A5[1], k2), (A5[2], k3), (A5[3], k4)]);
        sys.project(&mut self.stage);
        sys.rhs(t + C[3] * h, &self.stage, k5)?;
        combine(&mut self.stage, y, h, &[(A6[0], k1), (A6[1], k2), (A6[2], k3), (A6[3], k4), (A6[4], k5)]);
        sys.project(&mut self.stage);
        sys.rhs(t + h, &self.stage, k6)?;
        combine(&mut self.y_new, y, h, &[(A7[0], k1), (A7[2], k3), (A7[3], k4), (A7[4], k5), (A7[5], k6)]);
        sys.project(&mut self.y_new);
        sys.rhs(t + h, &self.y_new, k7)?;
        // Scaled RMS error norm (Hairer et al. I, eq. II.4.11).
        let n = y.len();
        let mut err = 0.0;
        for i in 0..n {
            let e = h * (E[0] * k1[i] + E[2] * k3[i] + E[3] * k4[i] + E[4] * k5[i] + E[5] * k6[i] + E[6] * k7[i]);
            let sk = self.atol + self.rtol * y[i].abs().max(self.y_new[i].abs());
            err += (e / sk).powi(2);
        }
        let err = (err / n as f64).sqrt();
        // PI controller of DOPRI5 (β = 0.04, exponent 1/5 − 0.75 β).
        const SAFE: f64 = 0.9;
        const BETA: f64 = 0.04;
        let expo1 = 0.2 - BETA * 0.75;
        let fac11 = err.powf(expo1);
        if err <= 1.0 {
            let fac = (fac11 / self.fac_old.powf(BETA)) / SAFE;
            let fac = fac.clamp(0.1, 5.0);
            let mut next_h = h / fac;
            if self.last_rejected {
                next_h = next_h.min(h);
            }
            self.fac_old = err.max(1e-4);
            self.last_rejected = false;
            // Dense output coefficients before y is overwritten.
            let [c1, c2, c3, c4, c5] = &mut self.cont;
            for i in 0..n {
                let ydiff = self.y_new[i] - y[i];
                let bspl = h * k1[i] - ydiff;
                c1[i] = y[i];
                c2[i] = ydiff;
                c3[i] = bspl;
                c4[i] = ydiff - h * k7[i] - bspl;
                c5[i] = h * (D[0] * k1[i] + D[2] * k3[i] + D[3] * k4[i] + D[4] * k5[i] + D[5] * k6[i] + D[6] * k7[i]);
            }
            y.copy_from_slice(&self.y_new);
            // First same as last: f at the new point starts the next step.
            std::mem::swap(k1, k7);
            self.last_t = t;
            self.last_h = h;
            Ok(StepOutcome { accepted: true, error: err, next_h })
        } else {
            let next_h = h / (fac11 / SAFE).min(5.0);
            self.last_rejected = true;
            Ok(StepOutcome { accepted: false, error: err, next_h })
        }
    }

    /// Dense output at `t_out` in the last accepted step `[last_t, last_t + last_h]`, written to
    /// `out` (not projected: the caller projects).
    pub fn dense_output(&self, t_out: f64, out: &mut [f64]) {
        let theta = (t_out - self.last_t) / self.last_h;
        let theta1 = 1.0 - theta;
        let [c1, c2, c3, c4, c5] = &self.cont;
        for i in 0..out.len() {
            out[i] = c1[i] + theta * (c2[i] + theta1 * (c3[i] + theta * (c4[i] + theta1 * c5[i])));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `ẏ = λ y` in ℝ¹ (no manifold).
    struct Linear(f64);
    impl OdeSystem for Linear {
        fn dim(&self) -> usize {
            1
        }
        fn project(&self, _y: &mut [f64]) {}
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
            dy[0] = self.0 * y[0];
            Ok(())
        }
    }

    /// `ẏ = 4 t³ + 3 t²` (solution `t⁴ + t³`): a degree-4 polynomial that the fifth-order
    /// step and the fourth-order dense output must reproduce exactly.
    struct Poly;
    impl OdeSystem for Poly {
        fn dim(&self) -> usize {
            1
        }
        fn project(&self, _y: &mut [f64]) {}
        fn rhs(&mut self, t: f64, _y: &[f64], dy: &mut [f64]) -> Result<()> {
            dy[0] = 4.0 * t.powi(3) + 3.0 * t * t;
            Ok(())
        }
    }

    fn rk4_error(h: f64) -> f64 {
        let mut sys = Linear(-1.3);
        let mut rk = Rk4::new(1);
        let mut y = [1.0];
        let n = (1.0 / h).round() as usize;
        for i in 0..n {
            rk.step(&mut sys, i as f64 * h, h, &mut y, false).unwrap();
        }
        (y[0] - (-1.3f64).exp()).abs()
    }

    #[test]
    fn rk4_is_fourth_order_on_a_linear_ode() {
        let (e1, e2) = (rk4_error(0.1), rk4_error(0.05));
        assert!(e1 > 1e-8, "the coarse error must be measurable, got {e1:e}");
        let ratio = e1 / e2;
        assert!((ratio - 16.0).abs() < 1.0, "error ratio {ratio} (expected ≈ 16 for order 4)");
    }

    #[test]
    fn dopri5_step_and_dense_output_are_exact_for_a_quartic() {
        let mut sys = Poly;
        let mut d = Dopri5::new(1, 1e-6, 1e-6);
        let mut y = [0.0];
        d.initial_step(&mut sys, 0.0, &y, 1.0).unwrap();
        let out = d.try_step(&mut sys, 0.0, 0.7, &mut y).unwrap();
        assert!(out.accepted);
        let exact = |t: f64| t.powi(4) + t.powi(3);
        assert!((y[0] - exact(0.7)).abs() < 1e-14, "{} vs {}", y[0], exact(0.7));
        for theta in [0.1, 0.25, 0.5, 0.8] {
            let mut o = [0.0];
            d.dense_output(0.7 * theta, &mut o);
            assert!((o[0] - exact(0.7 * theta)).abs() < 1e-14, "dense output at θ = {theta}: {} vs {}", o[0], exact(0.7 * theta));
        }
    }

    #[test]
    fn dopri5_meets_its_tolerance_on_a_linear_ode() {
        for tol in [1e-6, 1e-9] {
            let mut sys = Linear(-2.0);
            let mut d = Dopri5::new(1, tol, tol * 1e-3);
            let mut y = [1.0];
            let mut t = 0.0;
            let mut h = d.initial_step(&mut sys, t, &y, 1.0).unwrap();
            while t < 2.0 {
                h = h.min(2.0 - t);
                let out = d.try_step(&mut sys, t, h, &mut y).unwrap();
                if out.accepted {
                    t += h;
                }
                h = out.next_h;
            }
            let err = (y[0] - (-4.0f64).exp()).abs() / (-4.0f64).exp();
            assert!(err < 20.0 * tol, "relative error {err:e} at rtol {tol:e}");
            assert!(err > 1e-3 * tol, "suspiciously exact: {err:e}");
        }
    }
}
