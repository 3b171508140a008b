//! The dithered weight of the generalized singularity-robust (GSR) inverse of a CMG cluster
//! (Wie, "Singularity escape/avoidance steering logic for control moment gyro systems", JGCD
//! 28(5), 2005, eq. 29; docs/cmg.md): `A# = Aᵀ (A Aᵀ + λ W)⁻¹` (control/cmg_sr_inverse.rs) with
//!
//! ```text
//!     ⎡ 1   ε₃  ε₂ ⎤
//! W = ⎢ ε₃  1   ε₁ ⎥ ,   ε_i = ε₀ sin(ω t + φ_i),   φ = (0, π/2, π).
//!     ⎣ ε₂  ε₁  1  ⎦
//! ```
//!
//! At a singular state with the command `u` along its singular direction, `A Aᵀ u = 0`, so the
//! plain SR inverse gives `(A Aᵀ + λE)⁻¹ u = u/λ` and `Aᵀ u = 0`: no gimbal moves. `W`'s
//! off-diagonal entries turn `u` into directions where `Aᵀ` is not zero, so the gimbals move and
//! the cluster leaves the singular state (deliberately, with a small, time-varying torque error
//! of order `λ ε₀`). `W` is positive definite for `ε₀ < 1/2` (Gershgorin: every eigenvalue is
//! within `2ε₀` of 1), which keeps `A Aᵀ + λW` a Cholesky-solvable matrix.

use nalgebra::Matrix3;

/// The phases `φ_i` of the three dither signals (Wie 2005).
pub const DITHER_PHASES: [f64; 3] = [0.0, std::f64::consts::FRAC_PI_2, std::f64::consts::PI];

/// `W(t)` of the module docs for the amplitude `eps0` (dimensionless, `< 1/2`) and the
/// frequency `omega` (rad/s).
pub fn dither_weight(eps0: f64, omega: f64, t: f64) -> Matrix3<f64> {
    let [e1, e2, e3] = DITHER_PHASES.map(|phi| eps0 * (omega * t + phi).sin());
    Matrix3::new(1.0, e3, e2, e3, 1.0, e1, e2, e1, 1.0)
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::super::cmg_jacobian::{cluster_momentum, cmg_jacobian, singularity_measure, tests::pyramid};
    use super::super::cmg_sr_inverse::{sr_weight, steering_rates_weighted};
    use super::*;

    #[test]
    fn the_weight_is_symmetric_positive_definite_below_half_and_the_identity_without_dither() {
        assert_eq!(dither_weight(0.0, 1.3, 0.7), Matrix3::identity());
        for k in 0..50 {
            let w = dither_weight(0.49, 2.0, 0.1 * k as f64);
            assert_eq!(w, w.transpose());
            let least = w.symmetric_eigenvalues().min();
            assert!(least > 1.0 - 2.0 * 0.49 - 1e-15, "{least}");
        }
        // ε₁(t) = ε₀ sin(ωt), ε₂ = ε₀ cos(ωt), ε₃ = −ε₀ sin(ωt): W(0) = E + ε₀ (e₁e₃ᵀ + e₃e₁ᵀ).
        let w = dither_weight(0.1, 3.0, 0.0);
        assert!((w[(0, 2)] - 0.1).abs() < 1e-16 && w[(1, 2)].abs() < 1e-16 && w[(0, 1)].abs() < 1e-16);
    }

    /// Steer the unit-rotor pyramid from `d0` with the constant momentum rate `hdot` for `t` s
    /// (explicit Euler at 1 ms) with the GSR inverse (λ₀ = 0.01, μ = 10, ω = π/2 rad/s):
    /// the final gimbal angles, the momentum and the largest rate.
    fn steer(d0: [f64; 4], hdot: Vector3<f64>, t: f64, eps0: f64) -> ([f64; 4], Vector3<f64>, f64) {
        let c = pyramid((1.0f64 / 3.0f64.sqrt()).acos());
        let h = [1.0; 4];
        let (mut d, mut max_rate, dt) = (d0, 0.0f64, 1e-3);
        for k in 0..(t / dt).round() as usize {
            let a = cmg_jacobian(&c, &d, &h);
            let lambda = sr_weight(0.01, 10.0, singularity_measure(&a, &h), 1.0);
            let w = dither_weight(eps0, std::f64::consts::FRAC_PI_2, k as f64 * dt);
            let r = steering_rates_weighted(&a, &hdot, lambda, &w).unwrap();
            max_rate = max_rate.max(r.amax());
            for i in 0..4 {
                d[i] += dt * r[i];
            }
        }
        (d, cluster_momentum(&c, &d, &h), max_rate)
    }

    #[test]
    fn the_dithered_inverse_leaves_the_internal_singular_state_where_the_sr_inverse_stays() {
        // At δ = (−90°, 0, 90°, 0) the pyramid is singular along x (H = 2h cos β x̂); commanded
        // Ḣ = h x̂ exactly along that direction, the SR inverse moves nothing for 1.5 s, the GSR
        // inverse (ε₀ = 0.05) leaves the state and delivers momentum along x.
        let ds = [-std::f64::consts::FRAC_PI_2, 0.0, std::f64::consts::FRAC_PI_2, 0.0];
        let h_sing = 2.0 * ((1.0f64 / 3.0f64.sqrt()).acos()).cos();
        let (d, h, rate) = steer(ds, Vector3::x(), 1.5, 0.0);
        assert!(rate < 1e-12 && (h.x - h_sing).abs() < 1e-12, "{rate} {h}");
        assert!(d.iter().zip(ds).all(|(a, b)| (a - b).abs() < 1e-12));
        let (d, h, rate) = steer(ds, Vector3::x(), 1.5, 0.05);
        assert!(h.x > h_sing + 0.5, "{h}"); // well beyond the singular state's momentum
        assert!(h.y.abs() < 0.1 && h.z.abs() < 0.2, "{h}"); // the torque error stays small
        assert!(rate < 5.0, "{rate}"); // with bounded gimbal rates
        let c = pyramid((1.0f64 / 3.0f64.sqrt()).acos());
        assert!(singularity_measure(&cmg_jacobian(&c, &d, &[1.0; 4]), &[1.0; 4]) > 0.05);
    }
}
