//! The Wilson score interval of a success rate (docs/campaigns.md, "A capture-on-contact
//! campaign"; E. B. Wilson, "Probable inference, the law of succession, and statistical
//! inference", J. Am. Stat. Assoc. 22, 1927): of `k` successes in `n` independent trials, the
//! rates `p` at which the observed `p̂ = k/n` lies within `z` standard deviations,
//! `|p̂ − p| ≤ z √(p (1 − p) / n)` — the roots of that quadratic in `p`:
//!
//! `centre = (p̂ + z²/(2n)) / (1 + z²/n)`,
//! `half = z / (1 + z²/n) · √(p̂ (1 − p̂) / n + z² / (4 n²))`,
//!
//! the interval `[centre − half, centre + half]`, inside `[0, 1]` for every `k` (unlike the
//! normal approximation `p̂ ± z √(p̂ (1 − p̂)/n)`, which collapses at `k = 0` and `k = n`).

use crate::error::{Result, SpacearmError};

/// `z` of a two-sided 95 % interval: the standard normal's 0.975 quantile.
pub const Z95: f64 = 1.959_963_984_540_054;

/// A success rate with its Wilson interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SuccessRate {
    /// `k / n`.
    pub rate: f64,
    /// The interval's lower and upper bounds.
    pub low: f64,
    /// See `low`.
    pub high: f64,
}

/// The rate `k / n` and its Wilson interval at `z` (module docs); `n ≥ 1`, `k ≤ n`, `z > 0`.
pub fn wilson_interval(successes: usize, trials: usize, z: f64) -> Result<SuccessRate> {
    if trials == 0 {
        return Err(SpacearmError::argument("a success rate needs at least one trial, got 0"));
    }
    if successes > trials {
        return Err(SpacearmError::argument(format!("{successes} successes in {trials} trials: successes must be at most the trials")));
    }
    if !(z.is_finite() && z > 0.0) {
        return Err(SpacearmError::argument(format!("z must be finite and > 0, got {z}")));
    }
    let (k, n) = (successes as f64, trials as f64);
    let p = k / n;
    let z2 = z * z;
    let denom = 1.0 + z2 / n;
    let centre = (p + z2 / (2.0 * n)) / denom;
    let half = z / denom * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
    // At k = 0 and k = n a bound is exactly 0 or 1 (p̂ = 0 or 1 solves the equation there);
    // the formula's rounding would leave it a few ulps off.
    let low = if successes == 0 { 0.0 } else { (centre - half).max(0.0) };
    let high = if successes == trials { 1.0 } else { (centre + half).min(1.0) };
    Ok(SuccessRate { rate: p, low, high })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bounds are the roots of `(p̂ − p)² = z² p (1 − p) / n`.
    #[test]
    fn the_bounds_solve_the_score_equation() {
        for (k, n) in [(0, 10), (3, 10), (10, 10), (1, 1), (47, 200)] {
            let r = wilson_interval(k, n, Z95).unwrap();
            let p_hat = k as f64 / n as f64;
            for p in [r.low, r.high] {
                let lhs = (p_hat - p).powi(2);
                let rhs = Z95 * Z95 * p * (1.0 - p) / n as f64;
                assert!((lhs - rhs).abs() < 1e-14, "k {k} n {n} p {p}: {lhs} vs {rhs}");
            }
            assert!(r.low <= p_hat && p_hat <= r.high);
        }
        // k = 0: [0, z²/(n + z²)]; k = n: [n/(n + z²), 1].
        let r = wilson_interval(0, 10, 2.0).unwrap();
        assert!(r.low == 0.0 && (r.high - 4.0 / 14.0).abs() < 1e-15);
        let r = wilson_interval(10, 10, 2.0).unwrap();
        assert!((r.low - 10.0 / 14.0).abs() < 1e-15 && r.high == 1.0);
    }

    #[test]
    fn bad_counts_are_refused() {
        assert!(wilson_interval(0, 0, Z95).unwrap_err().to_string().contains("at least one trial"));
        assert!(wilson_interval(3, 2, Z95).unwrap_err().to_string().contains("at most"));
        assert!(wilson_interval(1, 2, -1.0).unwrap_err().to_string().contains("z must be"));
    }
}
