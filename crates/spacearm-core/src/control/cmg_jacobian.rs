//! The Jacobian of a CMG cluster and its singularity measure (docs/cmg.md; Wie, *Space Vehicle
//! Dynamics and Control*, 2nd ed., 2008, §7.6; Bedrossian, Paradiso & Bergmann, "Steering law
//! design for redundant single-gimbal control moment gyroscopes", JGCD 13(6), 1990).
//!
//! CMG `i` turns its rotor's spin axis about its gimbal axis `ĝ_i`:
//! `ŝ_i(δ_i) = cos δ_i ŝ_i⁰ + sin δ_i (ĝ_i × ŝ_i⁰)`, so its momentum `h_i ŝ_i` changes at
//! `h_i (ĝ_i × ŝ_i) δ̇_i`. The cluster's momentum `H = Σ h_i ŝ_i` then moves by `Ḣ = A(δ) δ̇`
//! with the columns `a_i = h_i (ĝ_i × ŝ_i)` (3 × n), and the base feels `τ = −Ḣ = −A δ̇`
//! (the gyroscopic torque `h_i × δ̇_i ĝ_i` summed). The cluster is **singular** where `A` has
//! rank < 3: every `a_i` is then perpendicular to one direction `u`, in which no gimbal rate
//! gives torque. The measure `m = det(A Aᵀ) / h̄⁶` (`h̄` the mean `|h_i|`: dimensionless) is 0
//! there.

use nalgebra::{Matrix3, Matrix3xX, Vector3};

use crate::model::cmg::Cmg;
use crate::model::data::Data;
use crate::model::Model;

/// One CMG of a cluster, as the steering laws see it: axes in one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CmgAxes {
    /// The gimbal axis `ĝ` (unit).
    pub gimbal: Vector3<f64>,
    /// The spin axis at zero gimbal angle `ŝ⁰` (unit, `⟂ ĝ`).
    pub spin0: Vector3<f64>,
}

impl CmgAxes {
    /// The spin axis `ŝ(δ)`.
    pub fn spin(&self, delta: f64) -> Vector3<f64> {
        self.spin0 * delta.cos() + self.gimbal.cross(&self.spin0) * delta.sin()
    }
}

/// The cluster's momentum `H = Σ h_i ŝ_i(δ_i)`.
pub fn cluster_momentum(cmgs: &[CmgAxes], delta: &[f64], h: &[f64]) -> Vector3<f64> {
    cmgs.iter().zip(delta).zip(h).map(|((c, d), h)| c.spin(*d) * *h).sum()
}

/// `A(δ)`: the columns `h_i (ĝ_i × ŝ_i(δ_i))` (module docs), `Ḣ = A δ̇`.
pub fn cmg_jacobian(cmgs: &[CmgAxes], delta: &[f64], h: &[f64]) -> Matrix3xX<f64> {
    Matrix3xX::from_columns(&cmgs.iter().zip(delta).zip(h).map(|((c, d), h)| c.gimbal.cross(&c.spin(*d)) * *h).collect::<Vec<_>>())
}

/// The columns' axes `ĝ_i × ŝ_i` in a frame where the gimbal and spin axes are `gimbal[i]`,
/// `spin[i]` (already turned by `δ_i`): `A` of a cluster read from a model's kinematics.
pub fn cmg_jacobian_from_axes(gimbal: &[Vector3<f64>], spin: &[Vector3<f64>], h: &[f64]) -> Matrix3xX<f64> {
    Matrix3xX::from_columns(&gimbal.iter().zip(spin).zip(h).map(|((g, s), h)| g.cross(s) * *h).collect::<Vec<_>>())
}

/// A cluster on the base read from a model's kinematics (`data` at the state `x`, its joint
/// axes in 𝒥) and the velocity `u`: each CMG's gimbal axis `ĝ_i` and spin axis `ŝ_i` in 𝒥 and
/// its rotor momentum `h_i = J_s,i (ŝ_i · ω0 + Ω_i)` (the rotor's absolute spin; `ĝ_i ⟂ ŝ_i`,
/// so the gimbal rate adds none).
pub fn cluster_from_kinematics(model: &Model, data: &Data, cmgs: &[Cmg], u: &[f64]) -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>, Vec<f64>) {
    let w0 = Vector3::new(u[3], u[4], u[5]);
    let (mut g, mut s, mut h) = (Vec::with_capacity(cmgs.len()), Vec::with_capacity(cmgs.len()), Vec::with_capacity(cmgs.len()));
    for c in cmgs {
        let si = data.joint_axis_in_world[model.body_of_dof(c.rotor_dof)];
        h.push(c.rotor_inertia * (si.dot(&w0) + u[6 + c.rotor_dof]));
        g.push(data.joint_axis_in_world[model.body_of_dof(c.gimbal_dof)]);
        s.push(si);
    }
    (g, s, h)
}

/// The singularity measure `m = det(A Aᵀ) / h̄⁶` (module docs); 0 for an empty cluster.
pub fn singularity_measure(a: &Matrix3xX<f64>, h: &[f64]) -> f64 {
    if h.is_empty() {
        return 0.0;
    }
    let hbar = h.iter().map(|v| v.abs()).sum::<f64>() / h.len() as f64;
    let aat: Matrix3<f64> = a * a.transpose();
    if hbar > 0.0 {
        aat.determinant() / hbar.powi(6)
    } else {
        0.0
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Wie's 4-CMG pyramid of skew angle `β`.
    pub fn pyramid(beta: f64) -> Vec<CmgAxes> {
        let (sb, cb) = beta.sin_cos();
        let g = [[sb, 0.0, cb], [0.0, sb, cb], [-sb, 0.0, cb], [0.0, -sb, cb]];
        let s = [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]];
        g.iter().zip(s).map(|(g, s)| CmgAxes { gimbal: Vector3::from(*g), spin0: Vector3::from(s) }).collect()
    }

    #[test]
    fn the_jacobian_is_the_derivative_of_the_momentum() {
        let c = pyramid(0.95);
        let d = [0.3, -1.1, 2.0, 0.4];
        let h = [10.0, 11.0, 9.0, 10.5];
        let a = cmg_jacobian(&c, &d, &h);
        for i in 0..4 {
            let e = 1e-6;
            let mut dp = d;
            dp[i] += e;
            let mut dm = d;
            dm[i] -= e;
            let fd = (cluster_momentum(&c, &dp, &h) - cluster_momentum(&c, &dm, &h)) / (2.0 * e);
            assert!((fd - a.column(i)).norm() < 1e-8 * h[i], "{i}");
        }
    }

    #[test]
    fn the_measure_vanishes_at_the_pyramids_internal_singularity() {
        // δ = (−90°, 0, 90°, 0) at β = 54.74°: H = (2 h cos β, 0, 0), inside the envelope, is
        // an internal singular state: A Aᵀ loses rank along x.
        let beta = (1.0f64 / 3.0f64.sqrt()).acos();
        let c = pyramid(beta);
        let h = [1.0; 4];
        let d = [-std::f64::consts::FRAC_PI_2, 0.0, std::f64::consts::FRAC_PI_2, 0.0];
        let a = cmg_jacobian(&c, &d, &h);
        assert!(singularity_measure(&a, &h).abs() < 1e-14);
        let x = Vector3::x();
        assert!((a.transpose() * x).norm() < 1e-15); // no gimbal rate gives torque along x
        let hx = cluster_momentum(&c, &d, &h);
        assert!((hx - Vector3::new(2.0 * beta.cos(), 0.0, 0.0)).norm() < 1e-14, "{hx}");
        // The zero-momentum state is far from singular: m = 32/27 at β = 54.74°.
        let m0 = singularity_measure(&cmg_jacobian(&c, &[0.0; 4], &h), &h);
        assert!((m0 - 32.0 / 27.0).abs() < 1e-14, "{m0}");
    }
}
