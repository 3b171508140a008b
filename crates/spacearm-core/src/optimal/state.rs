//! The state manifold of the optimal-control problems: `z = [x; u]` with the configuration
//! `x = [r0, quat0 [x,y,z,w], q]` and the generalized velocity `u = [v0, ω0, q̇]`
//! (docs/conventions.md), `7+N + 6+N` numbers, and its tangent space of dimension `2(6+N)`,
//! `δz = [δr0, δθ, δq, δv0, δω0, δq̇]` with `δθ` a world-frame (left) rotation increment,
//! `quat ← exp(δθ/2) ⊗ quat` — the tangent coordinates of the core's derivatives
//! ([`crate::derivatives`], module docs). The Riccati recursion of DDP runs in this tangent
//! space (the error state); the trajectories are stored as points `z`.
//!
//! The maps between an ambient quaternion increment `d quat` (4 numbers) and the tangent one
//! `δθ` at a unit quaternion `quat = [v; w]`:
//! `d quat = E(quat) δθ = ½ [δθ; 0] ⊗ quat`, `E = ½ [[w E₃ − ṽ], [−vᵀ]]`, and
//! `δθ = T(quat) d quat = 2 vec(d quat ⊗ quat*)`, `T = 2 [w E₃ + ṽ, −v]`, with `T E = E₃`
//! (and `T quat = 0`: a change of the norm is no rotation).

use nalgebra::{DMatrix, Matrix3, SMatrix, Vector3};

use crate::math::rotations::{xyzw_exp, xyzw_log, xyzw_multiply};
use crate::math::spatial::skew;

/// `E(quat)` (4×3): `d quat = E δθ` for a world-frame rotation increment `δθ` at `quat`.
pub fn quaternion_from_tangent(quat: &[f64]) -> SMatrix<f64, 4, 3> {
    let v = Vector3::new(quat[0], quat[1], quat[2]);
    let top = (Matrix3::identity() * quat[3] - skew(&v)) * 0.5;
    let mut e = SMatrix::<f64, 4, 3>::zeros();
    e.fixed_view_mut::<3, 3>(0, 0).copy_from(&top);
    e.fixed_view_mut::<1, 3>(3, 0).copy_from(&(v.transpose() * -0.5));
    e
}

/// `T(quat)` (3×4): `δθ = T d quat` at a unit `quat`.
pub fn tangent_from_quaternion(quat: &[f64]) -> SMatrix<f64, 3, 4> {
    let v = Vector3::new(quat[0], quat[1], quat[2]);
    let mut t = SMatrix::<f64, 3, 4>::zeros();
    t.fixed_view_mut::<3, 3>(0, 0).copy_from(&((Matrix3::identity() * quat[3] + skew(&v)) * 2.0));
    t.fixed_view_mut::<3, 1>(0, 3).copy_from(&(v * -2.0));
    t
}

/// Dimensions of the state of a model with `n` joint degrees of freedom.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StateSpace {
    /// `N`.
    pub n: usize,
}

impl StateSpace {
    /// Length of `x`: `7+N`.
    pub fn nx(self) -> usize {
        7 + self.n
    }
    /// Length of `u`: `6+N`.
    pub fn nu(self) -> usize {
        6 + self.n
    }
    /// Length of `z = [x; u]`: `13+2N`.
    pub fn nz(self) -> usize {
        13 + 2 * self.n
    }
    /// Tangent dimension: `2(6+N)`.
    pub fn nd(self) -> usize {
        12 + 2 * self.n
    }

    /// `δz` with `z1 = z0 ⊕ δz`: differences everywhere except `δθ = log(quat1 ⊗ quat0*)`.
    pub fn diff(self, z0: &[f64], z1: &[f64], out: &mut [f64]) {
        for i in 0..3 {
            out[i] = z1[i] - z0[i];
        }
        let q0 = [-z0[3], -z0[4], -z0[5], z0[6]];
        let q1 = [z1[3], z1[4], z1[5], z1[6]];
        let th = xyzw_log(&xyzw_multiply(&q1, &q0));
        out[3..6].copy_from_slice(th.as_slice());
        for i in 7..z0.len() {
            out[i - 1] = z1[i] - z0[i];
        }
    }

    /// `z ⊕ δz`: sums everywhere except `quat ← exp(δθ/2) ⊗ quat`.
    pub fn integrate(self, z: &[f64], dz: &[f64], out: &mut [f64]) {
        for i in 0..3 {
            out[i] = z[i] + dz[i];
        }
        let e = xyzw_exp(&Vector3::new(dz[3], dz[4], dz[5]));
        let q = xyzw_multiply(&e, &[z[3], z[4], z[5], z[6]]);
        out[3..7].copy_from_slice(&q);
        for i in 7..z.len() {
            out[i] = z[i] + dz[i - 1];
        }
    }

    /// The ambient increment of a tangent one at `z` (`nz × nd`, identity except the quaternion
    /// rows, [`quaternion_from_tangent`]), written into `out`.
    pub fn ambient_from_tangent(self, z: &[f64], out: &mut DMatrix<f64>) {
        self.identity_but_attitude(out, |i| (i, i - 1));
        out.fixed_view_mut::<4, 3>(3, 3).copy_from(&quaternion_from_tangent(&z[3..7]));
    }

    /// The tangent increment of an ambient one at a unit-quaternion `z` (`nd × nz`,
    /// [`tangent_from_quaternion`]), written into `out`.
    pub fn tangent_from_ambient(self, z: &[f64], out: &mut DMatrix<f64>) {
        self.identity_but_attitude(out, |i| (i - 1, i));
        out.fixed_view_mut::<3, 4>(3, 3).copy_from(&tangent_from_quaternion(&z[3..7]));
    }

    /// `out` zeroed, then 1 where a position or joint coordinate maps to itself: `(i, i)` for
    /// the position (`i < 3`), `joint(i)` for the ambient joint index `i ≥ 7` (the ambient and
    /// tangent indices differ by one there); the attitude block is the caller's.
    fn identity_but_attitude(self, out: &mut DMatrix<f64>, joint: impl Fn(usize) -> (usize, usize)) {
        out.fill(0.0);
        for i in 0..3 {
            out[(i, i)] = 1.0;
        }
        for i in 7..self.nz() {
            out[joint(i)] = 1.0;
        }
    }
}

/// The left Jacobian of SO(3), `J_l(φ) = E + (1 − cos|φ|)/|φ|² φ̃ + (|φ| − sin|φ|)/|φ|³ φ̃²`:
/// `exp(φ + δφ) = exp(J_l(φ) δφ) exp(φ) + O(δφ²)` (the world-frame increment of the rotation
/// a change of its rotation vector makes). Series `½ − |φ|²/24`, `1/6 − |φ|²/120` below `|φ| = 1e-4`.
pub fn so3_left_jacobian(phi: &Vector3<f64>) -> Matrix3<f64> {
    let a = phi.norm();
    let s = skew(phi);
    let (b, c) = if a < 1e-4 { (0.5 - a * a / 24.0, 1.0 / 6.0 - a * a / 120.0) } else { ((1.0 - a.cos()) / (a * a), (a - a.sin()) / (a * a * a)) };
    Matrix3::identity() + s * b + s * s * c
}

/// The inverse left Jacobian of SO(3), `J_l⁻¹(φ) = E − ½ φ̃ + (1/|φ|² − (1 + cos|φ|)/(2|φ| sin|φ|)) φ̃²`:
/// `log(exp(δθ) exp(φ)) = φ + J_l⁻¹(φ) δθ + O(δθ²)` (a world-frame increment of the rotation
/// whose rotation vector is `φ`). Series `1/12 + |φ|²/720` of the last factor below `|φ| = 1e-4`.
pub fn so3_left_jacobian_inverse(phi: &Vector3<f64>) -> Matrix3<f64> {
    let a = phi.norm();
    let s = skew(phi);
    let c = if a < 1e-4 { 1.0 / 12.0 + a * a / 720.0 } else { 1.0 / (a * a) - (1.0 + a.cos()) / (2.0 * a * a.sin()) };
    Matrix3::identity() - s * 0.5 + s * s * c
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(q: [f64; 4]) -> [f64; 4] {
        let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
        q.map(|v| v / n)
    }

    #[test]
    fn tangent_maps_are_inverse_and_match_the_exponential() {
        let q = unit([0.3, -0.2, 0.5, 0.8]);
        let t = tangent_from_quaternion(&q);
        let e = quaternion_from_tangent(&q);
        assert!((t * e - Matrix3::identity()).norm() < 1e-14);
        // T quat = 0: a change of the norm is no rotation.
        assert!((t * nalgebra::Vector4::from(q)).norm() < 1e-14);
        // E δθ is the derivative of exp(εδθ/2) ⊗ q at ε = 0 (central differences).
        let d = Vector3::new(0.2, -0.7, 0.4);
        let h = 1e-6;
        let qp = xyzw_multiply(&xyzw_exp(&(d * h)), &q);
        let qm = xyzw_multiply(&xyzw_exp(&(d * -h)), &q);
        let fd = nalgebra::Vector4::from_iterator((0..4).map(|i| (qp[i] - qm[i]) / (2.0 * h)));
        assert!((e * d - fd).norm() < 1e-9, "{} vs {}", e * d, fd);
    }

    #[test]
    fn diff_and_integrate_are_inverse() {
        let s = StateSpace { n: 2 };
        let q = unit([0.1, 0.2, -0.3, 0.9]);
        let z0: Vec<f64> = [1.0, 2.0, 3.0].iter().chain(q.iter()).chain([0.4, -0.5, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8].iter()).copied().collect();
        let dz: Vec<f64> = (0..s.nd()).map(|i| 0.1 * (i as f64 + 1.0).sin()).collect();
        let mut z1 = vec![0.0; s.nz()];
        s.integrate(&z0, &dz, &mut z1);
        let mut back = vec![0.0; s.nd()];
        s.diff(&z0, &z1, &mut back);
        for (a, b) in dz.iter().zip(&back) {
            assert!((a - b).abs() < 1e-14, "{dz:?} vs {back:?}");
        }
    }

    #[test]
    fn left_jacobian_matches_finite_differences_and_its_inverse() {
        for phi in [Vector3::new(0.3, -1.1, 0.7), Vector3::new(1e-6, 2e-6, -1e-6)] {
            let j = so3_left_jacobian(&phi);
            assert!((j * so3_left_jacobian_inverse(&phi) - Matrix3::identity()).norm() < 1e-12);
            let h = 1e-6;
            for k in 0..3 {
                let mut d = Vector3::zeros();
                d[k] = h;
                // exp(φ ± h e_k) exp(φ)⁻¹ = exp(± h J_l e_k): its log over 2h, central.
                let inv = xyzw_exp(&-phi);
                let p = xyzw_log(&xyzw_multiply(&xyzw_exp(&(phi + d)), &inv));
                let m = xyzw_log(&xyzw_multiply(&xyzw_exp(&(phi - d)), &inv));
                let col = (p - m) / (2.0 * h);
                assert!((col - j.column(k)).norm() < 1e-8, "{phi}: {col} vs {}", j.column(k));
            }
            assert!((j - Matrix3::identity()).norm() > 1e-7, "a trivial Jacobian");
        }
    }

    #[test]
    fn left_jacobian_inverse_matches_finite_differences() {
        for phi in [Vector3::new(0.3, -1.1, 0.7), Vector3::new(1e-6, 2e-6, -1e-6)] {
            let j = so3_left_jacobian_inverse(&phi);
            let q = xyzw_exp(&phi);
            let h = 1e-6;
            for k in 0..3 {
                let mut d = Vector3::zeros();
                d[k] = h;
                let p = xyzw_log(&xyzw_multiply(&xyzw_exp(&d), &q));
                let m = xyzw_log(&xyzw_multiply(&xyzw_exp(&-d), &q));
                let col = (p - m) / (2.0 * h);
                assert!((col - j.column(k)).norm() < 1e-8, "{phi}: {col} vs {}", j.column(k));
            }
        }
    }
}
