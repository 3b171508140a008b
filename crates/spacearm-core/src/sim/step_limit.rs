//! The longest RK4 step the fastest mode of a motion allows, estimated from the linearization
//! of the plant at the initial state (docs/simulation-core.md, "Errors").
//!
//! The plant `ẏ = f(t, y)` (controller, actuator limits, mode and forward dynamics together) is
//! linearized at `(0, y0)` by central differences, `A = ∂f/∂y`, and the eigenvalues `λ` of `A`
//! are its modes. One RK4 step of length `h` multiplies a mode by the stability function
//! `R(z) = 1 + z + z²/2 + z³/6 + z⁴/24`, `z = λh` (Hairer & Wanner, *Solving ODEs II*, IV.2),
//! the exact motion by `e^z`. The step is too long when some mode is amplified by the step more
//! than by the motion and more than by 1:
//! `|R(λh)| > (1 + STEP_AMPLIFICATION_TOLERANCE) · max(1, |e^{λh}|)` — the integration then
//! grows that mode from one step to the next whatever the physics does (for a real `λ < 0` that
//! is `|λ| h > 2.785`, for an imaginary one `|λ| h > 2√2`).

use nalgebra::{Complex, DMatrix};

use crate::error::{Result, SpacearmError};
use crate::math::integrate::OdeSystem;
use crate::sim::plant::Plant;

/// How much more than `max(1, |e^{λh}|)` an RK4 step may amplify a mode of the linearization
/// before the step counts as too long (room for the finite-difference estimate of `λ`).
pub const STEP_AMPLIFICATION_TOLERANCE: f64 = 0.01;

/// The fastest mode of a plant's linearization and what an RK4 step does to it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeEstimate {
    /// The eigenvalue whose amplification by the step is the worst, 1/s.
    pub lambda: Complex<f64>,
    /// `|R(λh)|`: the step's amplification of that mode.
    pub step_amplification: f64,
    /// `|e^{λh}|`: the motion's own amplification over the step.
    pub exact_amplification: f64,
    /// The longest step that every mode allows, s (`∞` when the step asked for is allowed).
    pub longest_step: f64,
}

/// RK4's stability function `R(z)`.
fn rk4_amplification(z: Complex<f64>) -> f64 {
    let one = Complex::new(1.0, 0.0);
    (one + z * (one + z * (one / 2.0 + z * (one / 6.0 + z / 24.0)))).norm()
}

/// Whether a step `h` is too long for the mode `λ` (the module's criterion); the amplification
/// ratio it is judged by.
fn excess(lambda: Complex<f64>, h: f64) -> f64 {
    let z = lambda * h;
    rk4_amplification(z) / z.re.exp().max(1.0)
}

/// The eigenvalues of the linearization of `plant` at `(t, y)` by central differences. The
/// plant's counters and saturation flags are left as they were (the estimate is no part of the
/// run); `None` when the eigenvalue iteration does not converge.
pub fn linearization_eigenvalues(plant: &mut Plant<'_>, t: f64, y: &[f64]) -> Result<Option<Vec<Complex<f64>>>> {
    let saved = (plant.n_evals, plant.dropped_max, plant.dropped_count, plant.flags_step.clone());
    let dim = y.len();
    let mut f0 = vec![0.0; dim];
    // The unperturbed evaluation first: a controller that fixes something at its first
    // evaluation (RMRC's orientation reference) fixes it at the true initial state.
    plant.rhs(t, y, &mut f0)?;
    let mut a = DMatrix::<f64>::zeros(dim, dim);
    let (mut yp, mut fp, mut fm) = (y.to_vec(), vec![0.0; dim], vec![0.0; dim]);
    for j in 0..dim {
        let h = f64::EPSILON.sqrt() * y[j].abs().max(1.0);
        yp[j] = y[j] + h;
        plant.rhs(t, &yp, &mut fp)?;
        yp[j] = y[j] - h;
        plant.rhs(t, &yp, &mut fm)?;
        yp[j] = y[j];
        for i in 0..dim {
            a[(i, j)] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    (plant.n_evals, plant.dropped_max, plant.dropped_count) = (saved.0, saved.1, saved.2);
    plant.flags_step.copy_from_slice(&saved.3);
    if a.iter().any(|v| !v.is_finite()) {
        return Ok(None);
    }
    Ok(nalgebra::linalg::Schur::try_new(a, 1e-12, 10_000).map(|s| s.complex_eigenvalues().iter().copied().collect()))
}

/// The fastest mode of `plant` at `(t, y)` for an RK4 step `h` (`None`: the eigenvalues could
/// not be computed, and nothing is judged).
pub fn estimate(plant: &mut Plant<'_>, t: f64, y: &[f64], h: f64) -> Result<Option<ModeEstimate>> {
    let Some(lambdas) = linearization_eigenvalues(plant, t, y)? else { return Ok(None) };
    let Some(&worst) = lambdas.iter().max_by(|a, b| excess(**a, h).total_cmp(&excess(**b, h))) else { return Ok(None) };
    let too_long = |h: f64| lambdas.iter().any(|&l| excess(l, h) > 1.0 + STEP_AMPLIFICATION_TOLERANCE);
    // The longest step allowed: bisection on a log scale between a step every mode allows
    // (|λ|h = 1e-3) and the step asked for, when that one is too long.
    let fastest = lambdas.iter().map(|l| l.norm()).fold(0.0, f64::max);
    let longest_step = if !too_long(h) || fastest == 0.0 {
        f64::INFINITY
    } else {
        let (mut lo, mut hi) = ((1e-3 / fastest).min(h), h);
        for _ in 0..60 {
            let mid = (lo * hi).sqrt();
            if too_long(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        lo
    };
    let z = worst * h;
    Ok(Some(ModeEstimate { lambda: worst, step_amplification: rk4_amplification(z), exact_amplification: z.re.exp(), longest_step }))
}

/// Refuse an RK4 step `h` that the fastest mode of `plant` at `(t, y)` does not allow (the
/// module's criterion): a `SimulationError` naming the mode and the longest step it allows.
pub fn check_rk4_step(plant: &mut Plant<'_>, t: f64, y: &[f64], h: f64) -> Result<()> {
    let Some(m) = estimate(plant, t, y, h)? else { return Ok(()) };
    if m.step_amplification <= (1.0 + STEP_AMPLIFICATION_TOLERANCE) * m.exact_amplification.max(1.0) {
        return Ok(());
    }
    Err(SpacearmError::Simulation(format!(
        "dt = {h} s is longer than the fastest mode of the motion allows: the linearization at t = {t} s has the mode \
         λ = {:.4} {} {:.4}i 1/s, which one RK4 step multiplies by {:.3} (the motion itself by {:.3}); the steps would \
         grow it without bound — use dt <= {:.3e} s, or integrator='dopri5'",
        m.lambda.re,
        if m.lambda.im < 0.0 { "-" } else { "+" },
        m.lambda.im.abs(),
        m.step_amplification,
        m.exact_amplification,
        m.longest_step
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stability_function_meets_the_known_rk4_bounds() {
        // Real axis: |R(-2.785)| ≈ 1 (Hairer & Wanner, Fig. IV.2.1); imaginary axis: |R(2√2 i)| = 1.
        assert!(rk4_amplification(Complex::new(-2.78, 0.0)) < 1.0);
        assert!(rk4_amplification(Complex::new(-2.79, 0.0)) > 1.0);
        let b = 8f64.sqrt();
        assert!((rk4_amplification(Complex::new(0.0, b)) - 1.0).abs() < 1e-12);
        assert!(rk4_amplification(Complex::new(0.0, b * 0.99)) < 1.0);
    }

    #[test]
    fn a_short_step_of_an_unstable_mode_is_no_excess() {
        // A physically growing mode (λ = 1/s) at h = 0.1: RK4 follows e^{0.1}, no excess.
        assert!(excess(Complex::new(1.0, 0.0), 0.1) <= 1.0);
        assert!(excess(Complex::new(-1.0, 0.0), 3.0) > 1.0 + STEP_AMPLIFICATION_TOLERANCE);
    }
}
