//! Input shaping of a joint reference against a lightly damped mode (Singer & Seering,
//! "Preshaping command inputs to reduce system vibration", J. Dyn. Sys. Meas. Control 112(1),
//! 1990, 76–82; Singhose, Seering & Singer 1994 for the residual-vibration expression).
//!
//! A shaper is a train of impulses `Σ Aᵢ δ(t − tᵢ)` (`Σ Aᵢ = 1`, so the shaped move ends where the
//! original does); the shaped reference is the convolution `q_s(t) = Σ Aᵢ q(t − tᵢ)` (and the
//! same for `q̇`, `q̈`), which lengthens the move by the last `tᵢ`. For a mode of natural
//! frequency `ω` and damping ratio `ζ` (`0 ≤ ζ < 1`), with `ω_d = ω √(1 − ζ²)`, the damped
//! period `T_d = 2π/ω_d` and `K = exp(−ζπ/√(1 − ζ²))`:
//!
//! - ZV (zero vibration): `A = [1, K]/(1 + K)`, `t = [0, T_d/2]`;
//! - ZVD (zero vibration and derivative: also robust to a frequency error):
//!   `A = [1, 2K, K²]/(1 + K)²`, `t = [0, T_d/2, T_d]`.
//!
//! The residual vibration after the last impulse of a mode `(ω, ζ)`, relative to that of a
//! single unit impulse, is
//! `V = exp(−ζω t_n) √((Σ Aᵢ e^{ζω tᵢ} cos ω_d tᵢ)² + (Σ Aᵢ e^{ζω tᵢ} sin ω_d tᵢ)²)`:
//! zero at the design mode for both shapers, and for ZVD also its derivative in `ω`.

use crate::error::{Result, SpacearmError};
use crate::scenario::reference::JointReference;

/// Which shaper.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShaperKind {
    /// Zero vibration: two impulses.
    Zv,
    /// Zero vibration and derivative: three impulses.
    Zvd,
}

crate::error::named_by!(ShaperKind, "an input shaper's kind", [Zv = "zv", Zvd = "zvd"]);

/// An input shaper designed for one mode (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct InputShaper {
    /// The kind.
    pub kind: ShaperKind,
    /// The design natural frequency ω, rad/s.
    pub frequency: f64,
    /// The design damping ratio ζ.
    pub damping: f64,
    /// Impulse amplitudes (sum 1).
    pub amplitudes: Vec<f64>,
    /// Impulse times, s (the first 0, ascending).
    pub times: Vec<f64>,
}

impl InputShaper {
    /// The shaper of `kind` for the mode of natural frequency `frequency` (rad/s, finite, > 0)
    /// and damping ratio `damping` (`0 ≤ ζ < 1`).
    pub fn new(kind: ShaperKind, frequency: f64, damping: f64) -> Result<Self> {
        if !(frequency.is_finite() && frequency > 0.0) {
            return Err(SpacearmError::argument(format!("an input shaper's frequency must be finite and > 0 rad/s, got {frequency}")));
        }
        if !(damping.is_finite() && (0.0..1.0).contains(&damping)) {
            return Err(SpacearmError::argument(format!("an input shaper's damping ratio must be in [0, 1), got {damping}")));
        }
        let root = (1.0 - damping * damping).sqrt();
        let k = (-damping * std::f64::consts::PI / root).exp();
        let half = std::f64::consts::PI / (frequency * root);
        let (amplitudes, times) = match kind {
            ShaperKind::Zv => (vec![1.0 / (1.0 + k), k / (1.0 + k)], vec![0.0, half]),
            ShaperKind::Zvd => {
                let s = (1.0 + k) * (1.0 + k);
                (vec![1.0 / s, 2.0 * k / s, k * k / s], vec![0.0, half, 2.0 * half])
            }
        };
        Ok(InputShaper { kind, frequency, damping, amplitudes, times })
    }

    /// The shaper's length: the time of its last impulse, s (what it adds to a move).
    pub fn duration(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// Singer & Seering's residual vibration `V(ω, ζ) = e^{−ζω t_N} √(C² + S²)` of a mode
    /// `(frequency, damping)`: the amplitude of the mode after the last impulse (at `t_N`),
    /// relative to that left by one unit impulse applied at `t_N`; 0 at the design mode. For
    /// `ζ = 0` it is also the ratio to the unshaped move (a unit impulse at 0); for `ζ > 0` that
    /// ratio is `V e^{ζω t_N}` (the unshaped move's vibration has decayed by `e^{−ζω t_N}` more).
    pub fn residual_vibration(&self, frequency: f64, damping: f64) -> f64 {
        let wd = frequency * (1.0 - damping * damping).max(0.0).sqrt();
        let (mut c, mut s) = (0.0, 0.0);
        for (&a, &t) in self.amplitudes.iter().zip(&self.times) {
            let e = a * (damping * frequency * t).exp();
            c += e * (wd * t).cos();
            s += e * (wd * t).sin();
        }
        (-damping * frequency * self.duration()).exp() * (c * c + s * s).sqrt()
    }

    /// The shaped reference `Σ Aᵢ r(t − tᵢ)` of `reference`.
    pub fn shape(&self, reference: JointReference) -> JointReference {
        JointReference::Shaped { base: Box::new(reference), amplitudes: self.amplitudes.clone(), delays: self.times.clone() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zv_and_zvd_match_the_closed_forms() {
        let (w, z) = (2.0, 0.05);
        let k = (-z * std::f64::consts::PI / (1.0f64 - z * z).sqrt()).exp();
        let td = 2.0 * std::f64::consts::PI / (w * (1.0f64 - z * z).sqrt());
        let zv = InputShaper::new(ShaperKind::Zv, w, z).unwrap();
        assert!((zv.amplitudes[0] - 1.0 / (1.0 + k)).abs() < 1e-15 && (zv.amplitudes[1] - k / (1.0 + k)).abs() < 1e-15);
        assert!((zv.times[1] - td / 2.0).abs() < 1e-14);
        let zvd = InputShaper::new(ShaperKind::Zvd, w, z).unwrap();
        assert!((zvd.times[2] - td).abs() < 1e-14);
        assert!((zvd.amplitudes.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        for s in [&zv, &zvd] {
            assert!(s.residual_vibration(w, z) < 1e-12);
            assert!(s.residual_vibration(1.3 * w, z) > 1e-3);
        }
        // ZVD: zero derivative in ω too, so it is flatter than ZV near the design frequency.
        assert!(zvd.residual_vibration(1.1 * w, z) < 0.5 * zv.residual_vibration(1.1 * w, z));
        assert!(InputShaper::new(ShaperKind::Zv, 0.0, 0.0).is_err());
        assert!(InputShaper::new(ShaperKind::Zv, 1.0, 1.0).is_err());
    }

    #[test]
    fn a_shaped_quintic_is_the_weighted_sum_of_delayed_quintics() {
        let s = InputShaper::new(ShaperKind::Zvd, 3.0, 0.1).unwrap();
        let base = JointReference::quintic(vec![0.0, 1.0], vec![1.0, -1.0], 0.5, 2.0).unwrap();
        let shaped = s.shape(base.clone());
        let (mut q, mut qd, mut qdd) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        let (mut bq, mut bqd, mut bqdd) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        for &t in &[0.0, 0.7, 1.3, 2.2, 2.9, 10.0] {
            shaped.eval(t, &mut q, &mut qd, &mut qdd);
            let mut expect = [[0.0; 2]; 3];
            for (a, d) in s.amplitudes.iter().zip(&s.times) {
                base.eval(t - d, &mut bq, &mut bqd, &mut bqdd);
                for j in 0..2 {
                    expect[0][j] += a * bq[j];
                    expect[1][j] += a * bqd[j];
                    expect[2][j] += a * bqdd[j];
                }
            }
            for j in 0..2 {
                assert!((q[j] - expect[0][j]).abs() < 1e-14 && (qd[j] - expect[1][j]).abs() < 1e-14 && (qdd[j] - expect[2][j]).abs() < 1e-13);
            }
        }
        shaped.eval(10.0, &mut q, &mut qd, &mut qdd);
        assert!((q[0] - 1.0).abs() < 1e-15 && (q[1] + 1.0).abs() < 1e-15);
    }
}
