//! Steering inverses of a CMG cluster's Jacobian `A` (3 × n, control/cmg_jacobian.rs;
//! docs/cmg.md): the gimbal rates `δ̇ = A# Ḣ_c` that give the momentum rate `Ḣ_c`.
//!
//! - The **pseudo-inverse** `A⁺ = Aᵀ (A Aᵀ)⁻¹`: the least gimbal rates; they grow without bound
//!   near a singular state (`det(A Aᵀ) → 0`) and do not exist at one.
//! - The **singularity-robust inverse** (Bedrossian, Paradiso & Bergmann, JGCD 13(6), 1990,
//!   after Nakamura & Hanafusa's damped inverse): `A# = Aᵀ (A Aᵀ + λ E)⁻¹` with
//!   `λ = λ₀ h̄² exp(−μ m)`, `m` the measure of [`singularity_measure`] and `h̄` the mean rotor
//!   momentum (so `λ₀` is dimensionless). Near a singularity it trades a small torque error
//!   for bounded rates, and the gimbals pass through the singular surface instead of stopping
//!   on it. At a singular state hit *exactly* along its singular direction `u` (`Aᵀ u = 0`,
//!   `A Aᵀ u = 0`), `(A Aᵀ + λE)⁻¹ u = u / λ` and no such inverse moves the gimbals.
//! - The **generalized SR inverse** (Wie, Bailey & Heiberg, JGCD 24(5), 2001; Wie, JGCD 28(5),
//!   2005): `A# = Aᵀ (A Aᵀ + λ W)⁻¹` with a symmetric positive-definite weight `W` whose
//!   off-diagonal entries are dithered in time (control/cmg_dither.rs): `W` mixes the singular
//!   direction with the others, so `A# u ≠ 0` and the gimbals leave even that state.
//!
//! [`singularity_measure`]: super::cmg_jacobian::singularity_measure

use nalgebra::{DVector, Matrix3, Matrix3xX, Vector3};

use crate::error::{Result, SpacearmError};

/// The SR weight `λ = λ₀ h̄² exp(−μ m)` (module docs).
pub fn sr_weight(lambda0: f64, mu: f64, measure: f64, hbar: f64) -> f64 {
    lambda0 * hbar * hbar * (-mu * measure).exp()
}

/// `Aᵀ (A Aᵀ + λ E)⁻¹ Ḣ_c`: the pseudo-inverse for `λ = 0` (an error where `A Aᵀ` is singular:
/// its least eigenvalue below `1e-12` of its trace), the SR inverse for `λ > 0`.
pub fn steering_rates(a: &Matrix3xX<f64>, hdot: &Vector3<f64>, lambda: f64) -> Result<DVector<f64>> {
    steering_rates_weighted(a, hdot, lambda, &Matrix3::identity())
}

/// `Aᵀ (A Aᵀ + λ W)⁻¹ Ḣ_c` with a symmetric positive-definite weight `W` (the generalized SR
/// inverse, module docs; `W = E`: [`steering_rates`]).
pub fn steering_rates_weighted(a: &Matrix3xX<f64>, hdot: &Vector3<f64>, lambda: f64, weight: &Matrix3<f64>) -> Result<DVector<f64>> {
    if !(lambda.is_finite() && lambda >= 0.0) {
        return Err(SpacearmError::argument(format!("the SR weight lambda must be finite and >= 0, got {lambda}")));
    }
    let aat: Matrix3<f64> = a * a.transpose();
    let least = aat.symmetric_eigenvalues().min();
    let m = aat + weight * lambda;
    let Some(y) = m.cholesky().filter(|_| lambda > 0.0 || least > 1e-12 * aat.trace()).map(|c| c.solve(hdot)) else {
        return Err(SpacearmError::Simulation("the CMG cluster is singular (det(A Aᵀ) = 0): the pseudo-inverse has no solution; use the SR inverse (lambda0 > 0)".into()));
    };
    Ok(a.transpose() * y)
}

#[cfg(test)]
mod tests {
    use super::super::cmg_jacobian::{cluster_momentum, cmg_jacobian, singularity_measure, tests::pyramid};
    use super::*;

    /// Steer a unit-rotor pyramid (β = 54.74°) from `d0` with the constant momentum rate `hdot`
    /// for `t` seconds (explicit Euler at 1 ms): the final gimbal angles and momentum, the
    /// largest gimbal rate and the least measure met.
    fn steer(d0: [f64; 4], hdot: Vector3<f64>, t: f64, lambda0: f64) -> Result<([f64; 4], Vector3<f64>, f64, f64)> {
        let c = pyramid((1.0f64 / 3.0f64.sqrt()).acos());
        let h = [1.0; 4];
        let mut d = d0;
        let (mut max_rate, mut min_m) = (0.0f64, f64::INFINITY);
        let dt = 1e-3;
        for _ in 0..(t / dt).round() as usize {
            let a = cmg_jacobian(&c, &d, &h);
            let m = singularity_measure(&a, &h);
            min_m = min_m.min(m);
            let r = steering_rates(&a, &hdot, sr_weight(lambda0, 10.0, m, 1.0))?;
            max_rate = max_rate.max(r.amax());
            for i in 0..4 {
                d[i] += dt * r[i];
            }
        }
        Ok((d, cluster_momentum(&c, &d, &h), max_rate, min_m))
    }

    #[test]
    fn the_pseudo_inverse_fails_at_the_singular_state_and_the_sr_inverse_does_not() {
        let c = pyramid((1.0f64 / 3.0f64.sqrt()).acos());
        let h = [1.0; 4];
        let d = [-std::f64::consts::FRAC_PI_2, 0.0, std::f64::consts::FRAC_PI_2, 0.0];
        let a = cmg_jacobian(&c, &d, &h);
        let cmd = Vector3::new(0.3, 0.8, 0.5);
        assert!(steering_rates(&a, &cmd, 0.0).is_err());
        let r = steering_rates(&a, &cmd, sr_weight(0.01, 10.0, singularity_measure(&a, &h), 1.0)).unwrap();
        assert!(r.iter().all(|v| v.is_finite()) && r.amax() < 100.0);
        // Away from singularities both give the commanded momentum rate; the SR's error is small.
        let a = cmg_jacobian(&c, &[0.2, -0.4, 0.1, 0.7], &h);
        let pinv = steering_rates(&a, &cmd, 0.0).unwrap();
        assert!((&a * pinv - cmd).norm() < 1e-14);
        let sr = steering_rates(&a, &cmd, sr_weight(0.01, 10.0, singularity_measure(&a, &h), 1.0)).unwrap();
        assert!((&a * sr - cmd).norm() < 1e-3 * cmd.norm());
    }

    #[test]
    fn the_sr_inverse_passes_through_the_internal_singularity_where_the_pseudo_inverse_needs_unbounded_rates() {
        // From δ = (0.05, 0, 0, 0), a constant Ḣ = 1 along x drives the cluster onto the internal
        // singular surface near H_x = 2 h cos β = 1.155 h (δ = (−90°, 0, 90°, 0), the measure 0).
        let (_, _, pinv_rate, pinv_m) = steer([0.05, 0.0, 0.0, 0.0], Vector3::x(), 1.6, 0.0).unwrap();
        let (d, hx, sr_rate, sr_m) = steer([0.05, 0.0, 0.0, 0.0], Vector3::x(), 1.6, 0.01).unwrap();
        // The pseudo-inverse asks > 100 rad/s of the gimbals (no gimbal motor gives it).
        assert!(pinv_rate > 100.0 && pinv_m < 1e-4, "{pinv_rate} {pinv_m}");
        // The SR inverse stays under 5 rad/s, never comes as close to the singular surface, and
        // leaves it behind: the momentum ends beyond the singular state's 1.155 h, the measure
        // well away from 0.
        assert!(sr_rate < 5.0 && sr_m > 10.0 * pinv_m, "{sr_rate} {sr_m}");
        let beta = (1.0f64 / 3.0f64.sqrt()).acos();
        assert!(hx.x > 2.0 * beta.cos() + 0.1, "{hx}");
        let c = pyramid(beta);
        let m_end = singularity_measure(&cmg_jacobian(&c, &d, &[1.0; 4]), &[1.0; 4]);
        assert!(m_end > 0.1, "{m_end}");
    }
}
