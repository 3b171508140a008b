//! Steering of a variable-speed CMG cluster (VSCMG) over its gimbal rates and wheel
//! accelerations together (docs/cmg.md, "VSCMG steering"; Schaub, Vadali & Junkins, "Feedback
//! control law for variable speed control moment gyros", J. Astronaut. Sci. 46(3), 1998;
//! Schaub & Junkins, *Analytical Mechanics of Space Systems*, 4th ed., 2018, the VSCMG chapter).
//!
//! A VSCMG changes the cluster's momentum `H = Σ h_i ŝ_i` by turning its gimbals (the CMG mode,
//! `A δ̇` with `A`'s columns `h_i (ĝ_i × ŝ_i)`, control/cmg_jacobian.rs) and by accelerating its
//! wheels (the reaction-wheel mode, `B Ω̇` with `B`'s columns `J_s,i ŝ_i`):
//!
//! `Ḣ = Q η`, `Q = [A  B]` (3 × 2n), `η = [δ̇; Ω̇]`.
//!
//! The steering is the weighted minimum-norm solution (least `ηᵀ W⁻¹ η` with `Q η = Ḣ_c`)
//!
//! `η = W Qᵀ (Q W Qᵀ)⁻¹ Ḣ_c`, `W = diag(W_g E_n, W_s,i)`, `W_s,i = W_s0 exp(−μ m)`,
//!
//! with `m` the CMG singularity measure (control/cmg_jacobian.rs; Schaub & Junkins weigh with
//! their own measure of `A`, the same idea): far from a singular state (`m` of order 1, `μ`
//! large) the wheel weights vanish and the cluster steers as a CMG cluster (the wheel
//! accelerations go to zero with `W_s`); near one (`m → 0`) they rise to `W_s0` and the wheels
//! supply the torque along the singular direction that no gimbal rate gives (`Aᵀ u = 0`), so
//! `Q W Qᵀ` stays invertible and the commanded torque is delivered exactly, where the pure-CMG
//! pseudo-inverse has no solution.

use nalgebra::{DMatrix, DVector, Matrix3, Matrix3xX, Vector3};

use crate::error::{Result, SpacearmError};

/// `B = [J_s,i ŝ_i]` (3 × n): the momentum rate of unit wheel accelerations.
pub fn wheel_matrix(spin: &[Vector3<f64>], rotor_inertia: &[f64]) -> Matrix3xX<f64> {
    Matrix3xX::from_columns(&spin.iter().zip(rotor_inertia).map(|(s, j)| s * *j).collect::<Vec<_>>())
}

/// The wheel weight `W_s = W_s0 exp(−μ m)` (module docs).
pub fn wheel_weight(w_s0: f64, mu: f64, measure: f64) -> f64 {
    w_s0 * (-mu * measure).exp()
}

/// `η = W Qᵀ (Q W Qᵀ)⁻¹ Ḣ_c` with `Q = [A B]` and `W = diag(E_n, w_s E_n)` (module docs; the
/// gimbal weight 1): the gimbal rates `δ̇` (rad/s) and wheel accelerations `Ω̇` (rad/s²).
/// An error where `Q W Qᵀ` is singular (its least eigenvalue below `1e-14` of its trace).
pub fn vscmg_rates(a: &Matrix3xX<f64>, b: &Matrix3xX<f64>, hdot: &Vector3<f64>, w_s: f64) -> Result<(DVector<f64>, DVector<f64>)> {
    if !(w_s.is_finite() && w_s >= 0.0) {
        return Err(SpacearmError::argument(format!("the VSCMG wheel weight must be finite and >= 0, got {w_s}")));
    }
    let m: Matrix3<f64> = a * a.transpose() + b * b.transpose() * w_s;
    let least = m.symmetric_eigenvalues().min();
    let Some(y) = m.cholesky().filter(|_| least > 1e-14 * m.trace()).map(|c| c.solve(hdot)) else {
        return Err(SpacearmError::Simulation(
            "the VSCMG cluster is singular with its wheel weight (Q W Qᵀ = A Aᵀ + W_s B Bᵀ loses rank): raise wheel_weight".into(),
        ));
    };
    Ok((a.transpose() * y, b.transpose() * y * w_s))
}

/// `Q = [A B]` as one matrix (3 × 2n), for checks.
pub fn stacked(a: &Matrix3xX<f64>, b: &Matrix3xX<f64>) -> DMatrix<f64> {
    let n = a.ncols();
    let mut q = DMatrix::zeros(3, n + b.ncols());
    q.view_mut((0, 0), (3, n)).copy_from(a);
    q.view_mut((0, n), (3, b.ncols())).copy_from(b);
    q
}

#[cfg(test)]
mod tests {
    use super::super::cmg_jacobian::{cmg_jacobian, singularity_measure, tests::pyramid};
    use super::super::cmg_sr_inverse::steering_rates;
    use super::*;

    const J_S: f64 = 0.05;

    /// A pyramid's `A`, `B` and measure at gimbal angles `d`, rotors of momentum `h` each.
    fn cluster(d: &[f64; 4], h: f64) -> (Matrix3xX<f64>, Matrix3xX<f64>, f64) {
        let c = pyramid((1.0f64 / 3.0f64.sqrt()).acos());
        let hs = [h; 4];
        let a = cmg_jacobian(&c, d, &hs);
        let spin: Vec<Vector3<f64>> = c.iter().zip(d).map(|(c, d)| c.spin(*d)).collect();
        let m = singularity_measure(&a, &hs);
        (a, wheel_matrix(&spin, &[J_S; 4]), m)
    }

    /// The weighted minimum-norm solution by another road: `W^{1/2} (Q W^{1/2})⁺ Ḣ` with the
    /// SVD pseudo-inverse.
    fn by_svd(a: &Matrix3xX<f64>, b: &Matrix3xX<f64>, hdot: &Vector3<f64>, w_s: f64) -> DVector<f64> {
        let n = a.ncols();
        let mut q = stacked(a, b);
        for j in n..2 * n {
            q.column_mut(j).scale_mut(w_s.sqrt());
        }
        let mut eta = q.pseudo_inverse(1e-12).unwrap() * DVector::from_column_slice(hdot.as_slice());
        for j in n..2 * n {
            eta[j] *= w_s.sqrt();
        }
        eta
    }

    #[test]
    fn at_the_internal_singularity_the_vscmg_law_delivers_the_torque_the_cmg_pseudo_inverse_cannot() {
        // δ = (−90°, 0, 90°, 0): no gimbal rate gives momentum along x (cmg_jacobian.rs).
        let h = J_S * 500.0;
        let (a, b, m) = cluster(&[-std::f64::consts::FRAC_PI_2, 0.0, std::f64::consts::FRAC_PI_2, 0.0], h);
        assert!(m.abs() < 1e-14);
        let cmd = Vector3::new(0.3, 0.8, 0.5);
        assert!(steering_rates(&a, &cmd, 0.0).is_err());
        // The best any gimbal rates do: the x part of the command is lost.
        let best = a.clone() * a.clone().pseudo_inverse(1e-12).unwrap() * cmd;
        assert!(((best - cmd).norm() - 0.3).abs() < 1e-12, "{}", (best - cmd).norm());
        let w_s = wheel_weight(1.0, 10.0, m);
        assert_eq!(w_s, 1.0);
        let (rates, accel) = vscmg_rates(&a, &b, &cmd, w_s).unwrap();
        let delivered = &a * &rates + &b * &accel;
        assert!((delivered - cmd).norm() <= 1e-10 * cmd.norm(), "{}", (delivered - cmd).norm());
        // The wheels carry the x part; the solution is the weighted minimum-norm one.
        assert!((&b * &accel).x > 0.3 - 1e-12 && accel.amax() > 1.0);
        let svd = by_svd(&a, &b, &cmd, w_s);
        let eta: DVector<f64> = DVector::from_iterator(8, rates.iter().chain(accel.iter()).copied());
        assert!((&eta - &svd).norm() <= 1e-9 * svd.norm(), "{eta} vs {svd}");
    }

    #[test]
    fn away_from_singularities_the_wheel_accelerations_vanish_with_their_weight() {
        let h = J_S * 500.0;
        let (a, b, m) = cluster(&[0.2, -0.4, 0.1, 0.7], h);
        assert!(m > 0.5, "{m}");
        let cmd = Vector3::new(0.3, -0.8, 0.5);
        let pinv = steering_rates(&a, &cmd, 0.0).unwrap();
        for mu in [0.0, 5.0, 10.0, 20.0] {
            let w_s = wheel_weight(1.0, mu, m);
            let (rates, accel) = vscmg_rates(&a, &b, &cmd, w_s).unwrap();
            assert!((&a * &rates + &b * &accel - cmd).norm() <= 1e-12 * cmd.norm());
            let eta: DVector<f64> = DVector::from_iterator(8, rates.iter().chain(accel.iter()).copied());
            assert!((&eta - by_svd(&a, &b, &cmd, w_s)).norm() <= 1e-9 * eta.norm());
            // Ω̇ = W_s Bᵀ (Q W Qᵀ)⁻¹ Ḣ: to first order in W_s, W_s Bᵀ (A Aᵀ)⁻¹ Ḣ, and the gimbal
            // rates the CMG pseudo-inverse's.
            let first_order = b.transpose() * (a.clone() * a.transpose()).try_inverse().unwrap() * cmd * w_s;
            assert!((&accel - &first_order).norm() <= 1e-3 * first_order.norm() + 1e-300, "{mu}: {accel} vs {first_order}");
            // δ̇ − A⁺Ḣ = Aᵀ [(A Aᵀ + W_s B Bᵀ)⁻¹ − (A Aᵀ)⁻¹] Ḣ: of relative size W_s |B Bᵀ| / λ_min(A Aᵀ) at most (to first order).
            let aat: Matrix3<f64> = a.clone() * a.transpose();
            let bound = w_s * (b.clone() * b.transpose()).norm() / aat.symmetric_eigenvalues().min();
            assert!((&rates - &pinv).norm() <= 2.0 * bound * pinv.norm() * aat.norm().sqrt() / aat.symmetric_eigenvalues().min().sqrt(), "{mu}");
            if mu >= 10.0 {
                assert!(accel.amax() < 1e-4 * rates.amax(), "{mu}: {}", accel.amax());
            }
        }
        assert!(vscmg_rates(&a, &b, &cmd, f64::NAN).is_err());
        // A zero weight at the singular state: Q W Qᵀ = A Aᵀ, singular.
        let (a, b, _) = cluster(&[-std::f64::consts::FRAC_PI_2, 0.0, std::f64::consts::FRAC_PI_2, 0.0], h);
        assert!(vscmg_rates(&a, &b, &cmd, 0.0).is_err());
    }
}
