//! Null-motion steering of a CMG cluster away from singular states (docs/cmg.md; Vadali,
//! Oh & Walker, JGCD 13(6), 1990; Wie, *Space Vehicle Dynamics and Control*, 2008, §7.6): the
//! gimbal rates `δ̇_n = k (E − A⁺A) ∇_δ w` climb the gradient of the measure
//! `w = √det(A Aᵀ) / h̄³ = √m` (control/cmg_jacobian.rs) inside the Jacobian's null space, so
//! they change the gimbal angles and not the cluster's momentum (`A δ̇_n = 0`: no torque on
//! the base). Added to any steering inverse's rates, they move the cluster along its
//! momentum's preimage toward better-conditioned gimbal angles. A gradient method: it escapes
//! hyperbolic singular states, not the elliptic ones (no null motion leaves those; the
//! dithered GSR inverse does, control/cmg_dither.rs).
//!
//! The gradient: `∂(A Aᵀ)/∂δ_i = a_i' a_iᵀ + a_i a_i'ᵀ` with `a_i' = ∂a_i/∂δ_i = h_i ĝ_i × (ĝ_i × ŝ_i)
//! = −h_i ŝ_i`, and Jacobi's formula `∂ det M = tr(adj(M) ∂M)` give
//! `∂ det(A Aᵀ)/∂δ_i = 2 a_i'ᵀ adj(A Aᵀ) a_i` (finite at singular states, where the inverse is
//! not), and `∇w = ∇det / (2 √det h̄³)`.

use nalgebra::{DVector, Matrix3, Matrix3xX, Vector3};

/// The adjugate of a 3 × 3 matrix (the transposed cofactor matrix; `M adj(M) = det(M) E`).
fn adjugate(m: &Matrix3<f64>) -> Matrix3<f64> {
    let c = |r0: usize, r1: usize, c0: usize, c1: usize| m[(r0, c0)] * m[(r1, c1)] - m[(r0, c1)] * m[(r1, c0)];
    Matrix3::new(
        c(1, 2, 1, 2), -c(0, 2, 1, 2), c(0, 1, 1, 2),
        -c(1, 2, 0, 2), c(0, 2, 0, 2), -c(0, 1, 0, 2),
        c(1, 2, 0, 1), -c(0, 2, 0, 1), c(0, 1, 0, 1),
    )
}

/// `∇_δ w`, `w = √det(A Aᵀ) / h̄³` (module docs), for the cluster's Jacobian `a` (columns
/// `h_i ĝ_i × ŝ_i`), its spin axes `spin` (in `a`'s frame) and rotor momenta `h`. Zero at an
/// exactly singular state (`det(A Aᵀ) ≤ 0` in floating point) and for an empty cluster.
pub fn root_measure_gradient(a: &Matrix3xX<f64>, spin: &[Vector3<f64>], h: &[f64]) -> DVector<f64> {
    let n = h.len();
    let aat: Matrix3<f64> = a * a.transpose();
    let det = aat.determinant();
    let hbar = h.iter().map(|v| v.abs()).sum::<f64>() / n.max(1) as f64;
    if n == 0 || !(det > 0.0) || !(hbar > 0.0) {
        return DVector::zeros(n);
    }
    let adj = adjugate(&aat);
    let scale = 1.0 / (2.0 * det.sqrt() * hbar.powi(3));
    DVector::from_iterator(n, (0..n).map(|i| scale * 2.0 * (-h[i] * spin[i]).dot(&(adj * a.column(i)))))
}

/// `gain (E − A⁺A) g`: `g` projected on the null space of `a` (from its SVD; the rank counts
/// the singular values above `1e-10` of the largest) and scaled by `gain` (rad/s per unit of
/// `g`).
pub fn null_motion(a: &Matrix3xX<f64>, g: &DVector<f64>, gain: f64) -> DVector<f64> {
    let svd = a.clone().svd(false, true);
    let Some(v_t) = svd.v_t else {
        return DVector::zeros(g.len());
    };
    let top = svd.singular_values.max();
    let mut out = g.clone();
    for (k, s) in svd.singular_values.iter().enumerate() {
        if *s > 1e-10 * top {
            let v = v_t.row(k).transpose();
            out -= &v * v.dot(g);
        }
    }
    out * gain
}

#[cfg(test)]
mod tests {
    use super::super::cmg_jacobian::{cluster_momentum, cmg_jacobian, singularity_measure, tests::pyramid, CmgAxes};
    use super::*;

    fn root_measure(c: &[CmgAxes], d: &[f64; 4], h: &[f64; 4]) -> f64 {
        singularity_measure(&cmg_jacobian(c, d, h), h).sqrt()
    }

    fn gradient(c: &[CmgAxes], d: &[f64; 4], h: &[f64; 4]) -> DVector<f64> {
        let spin: Vec<_> = c.iter().zip(d).map(|(c, d)| c.spin(*d)).collect();
        root_measure_gradient(&cmg_jacobian(c, d, h), &spin, h)
    }

    #[test]
    fn the_gradient_is_the_finite_difference_of_the_root_measure_and_adj_is_the_adjugate() {
        let m = Matrix3::new(2.0, 0.3, -0.1, 0.3, 1.5, 0.2, -0.1, 0.2, 0.9);
        assert!((m * adjugate(&m) - Matrix3::identity() * m.determinant()).norm() < 1e-14);
        let c = pyramid(0.95);
        let h = [10.0, 11.0, 9.0, 10.5];
        for d in [[0.3, -1.1, 2.0, 0.4], [-1.5, 0.1, 1.6, 0.05]] {
            let g = gradient(&c, &d, &h);
            for i in 0..4 {
                let e = 1e-6;
                let (mut dp, mut dm) = (d, d);
                dp[i] += e;
                dm[i] -= e;
                let fd = (root_measure(&c, &dp, &h) - root_measure(&c, &dm, &h)) / (2.0 * e);
                assert!((fd - g[i]).abs() < 1e-7 * g.amax().max(1.0), "{i}: {fd} vs {}", g[i]);
            }
        }
    }

    #[test]
    fn null_motion_keeps_the_momentum_and_climbs_away_from_a_singular_state() {
        // Near the hyperbolic singular state δ = (90°, ~0, −90°, 0) (m = 3.3e-3), null motion alone
        // (no torque commanded) raises the measure fourfold in 2 s and the momentum stays.
        let c = pyramid((1.0f64 / 3.0f64.sqrt()).acos());
        let h = [1.0; 4];
        let mut d = [std::f64::consts::FRAC_PI_2, 0.05, -std::f64::consts::FRAC_PI_2, 0.0];
        let (h0, w0) = (cluster_momentum(&c, &d, &h), root_measure(&c, &d, &h));
        let dt = 1e-3;
        let rates = |d: &[f64; 4]| null_motion(&cmg_jacobian(&c, d, &h), &gradient(&c, d, &h), 1.0);
        for _ in 0..2000 {
            let r = rates(&d);
            // No momentum rate: A δ̇_n = 0 to rounding.
            assert!((cmg_jacobian(&c, &d, &h) * &r).norm() < 1e-14 * r.norm().max(1.0));
            let mid: [f64; 4] = std::array::from_fn(|i| d[i] + 0.5 * dt * r[i]);
            let r = rates(&mid);
            for i in 0..4 {
                d[i] += dt * r[i];
            }
        }
        let w1 = root_measure(&c, &d, &h);
        assert!(w1 * w1 > 4.0 * w0 * w0, "{w0} -> {w1}");
        assert!((cluster_momentum(&c, &d, &h) - h0).norm() < 1e-8, "{}", (cluster_momentum(&c, &d, &h) - h0).norm());
        // At an exactly singular state the gradient is zero, not NaN.
        let ds = [-std::f64::consts::FRAC_PI_2, 0.0, std::f64::consts::FRAC_PI_2, 0.0];
        assert!(gradient(&c, &ds, &h).iter().all(|v| v.is_finite()));
    }
}
