//! The semi-implicit (symplectic) Euler step on the state manifold, `z⁺ = Φ_h(z, c)`
//! (docs/mpc.md "Discretization"; the step of Crocoddyl's `IntegratedActionModelEuler`,
//! Mastalli et al. 2020): the velocity first, then the configuration with the new velocity,
//!
//! `a = FD(x, u, S c)`, `u⁺ = u + h a`, `x⁺ = x ⊕ h u⁺`
//!
//! (`⊕` of [`super::state`]: `r0⁺ = r0 + h v0⁺`, `quat⁺ = exp(h ω0⁺/2) ⊗ quat`, `q⁺ = q + h q̇⁺`;
//! the quaternion stays a unit one exactly). One forward-dynamics derivative evaluation per
//! step (RK4 takes four), at first-order accuracy: the plan's model then differs from the
//! simulator's RK4 plant by `O(h)` per unit time.
//!
//! Tangent Jacobians, with `D_x = ∂a/∂δx`, `D_u = ∂a/∂u`, `H⁻¹ S = ∂a/∂c` (the core's
//! forward-dynamics derivatives, [`crate::derivatives`]), `φ = h ω0⁺` and, on the configuration's
//! tangent, `R_x = blkdiag(E₃, R(φ), E_N)`, `J_x = blkdiag(E₃, J_l(φ), E_N)` (the Jacobians of
//! `x ⊕ δ` in `x` and in `δ`):
//!
//! `∂x⁺/∂δx = R_x + h² J_x D_x`, `∂x⁺/∂δu = h J_x (E + h D_u)`, `∂u⁺/∂δx = h D_x`,
//! `∂u⁺/∂δu = E + h D_u`, `∂x⁺/∂c = h² J_x H⁻¹ S`, `∂u⁺/∂c = h H⁻¹ S`.

use nalgebra::{DMatrix, Rotation3, Vector3};

use super::dynamics::Dynamics;
use super::state::so3_left_jacobian;
use crate::error::Result;
use crate::model::Model;

/// Workspaces of the semi-implicit Euler step and its Jacobians.
pub struct EulerDiscretization {
    /// The continuous dynamics.
    pub dynamics: Dynamics,
    /// The step, s.
    pub h: f64,
    rate: Vec<f64>,
    delta: Vec<f64>,
}

impl EulerDiscretization {
    /// Workspaces for steps of `h` seconds of `dynamics`.
    pub fn new(dynamics: Dynamics, h: f64) -> Self {
        let (nz, nu) = (dynamics.space.nz(), dynamics.space.nu());
        EulerDiscretization { h, rate: vec![0.0; nz], delta: vec![0.0; 2 * nu], dynamics }
    }

    /// `u⁺ = u + h a`, `x⁺ = x ⊕ h u⁺` into `next` from the rates `self.rate` (`a` in the
    /// velocity rows); leaves `δ = [h u⁺; h a]` in `self.delta`.
    fn advance(&mut self, z: &[f64], next: &mut [f64]) {
        let space = self.dynamics.space;
        let (nx, nu) = (space.nx(), space.nu());
        let h = self.h;
        for i in 0..nu {
            let a = self.rate[nx + i];
            self.delta[nu + i] = h * a;
            self.delta[i] = h * (z[nx + i] + h * a);
        }
        space.integrate(z, &self.delta, next);
    }

    /// `z⁺ = Φ(z, c)` into `next` (the acceleration by ABA).
    pub fn step(&mut self, model: &Model, z: &[f64], c: &[f64], next: &mut [f64]) -> Result<()> {
        self.dynamics.rhs(model, z, c, &mut self.rate)?;
        self.advance(z, next);
        Ok(())
    }

    /// `z⁺ = Φ(z, c)` into `next` and the tangent Jacobians `A = ∂z⁺/∂δz` into `a` (`nd × nd`)
    /// and `B = ∂z⁺/∂c` into `b` (`nd × m`) (module docs), from one forward-dynamics derivative
    /// evaluation (its acceleration `H⁻¹(f − c)`, equal to ABA's to rounding).
    pub fn step_derivatives(&mut self, model: &Model, z: &[f64], c: &[f64], next: &mut [f64], a: &mut DMatrix<f64>, b: &mut DMatrix<f64>) -> Result<()> {
        let h = self.h;
        self.dynamics.rhs_derivatives(model, z, c, &mut self.rate)?;
        self.advance(z, next);
        let nu = self.dynamics.space.nu();
        let phi = Vector3::new(self.delta[3], self.delta[4], self.delta[5]);
        let rot = Rotation3::new(phi);
        let jl = so3_left_jacobian(&phi);
        let (dx, du, hinv) = self.dynamics.partials();
        // The lower rows: ∂u⁺/∂δx = h D_x, ∂u⁺/∂δu = E + h D_u, ∂u⁺/∂c = h H⁻¹ S.
        for j in 0..nu {
            for i in 0..nu {
                a[(nu + i, j)] = h * dx[(i, j)];
                a[(nu + i, nu + j)] = h * du[(i, j)] + if i == j { 1.0 } else { 0.0 };
            }
        }
        for (k, col) in self.dynamics.controls.columns.iter().enumerate() {
            for i in 0..nu {
                b[(nu + i, k)] = h * hinv[(i, *col)];
            }
        }
        // The upper rows: h J_x times the lower rows, plus R_x in the configuration block.
        for j in 0..nu {
            top_rows(a, j, nu, h, &jl);
            top_rows(a, nu + j, nu, h, &jl);
            a[(j, j)] += if (3..6).contains(&j) { 0.0 } else { 1.0 };
        }
        for r in 0..3 {
            for s in 0..3 {
                a[(3 + r, 3 + s)] += rot[(r, s)];
            }
        }
        for k in 0..b.ncols() {
            top_rows(b, k, nu, h, &jl);
        }
        Ok(())
    }
}

/// Rows `0..nu` of column `col` of `m` ← `h J_x` times its rows `nu..2nu` (`J_x` the identity
/// but `J_l` on rows 3..6).
fn top_rows(m: &mut DMatrix<f64>, col: usize, nu: usize, h: f64, jl: &nalgebra::Matrix3<f64>) {
    for i in 0..nu {
        m[(i, col)] = h * m[(nu + i, col)];
    }
    let v = Vector3::new(m[(nu + 3, col)], m[(nu + 4, col)], m[(nu + 5, col)]);
    let w = jl * v * h;
    for r in 0..3 {
        m[(3 + r, col)] = w[r];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimal::discretization::{check_step_jacobians, DiscretizationKind};

    /// `A` and `B` against central differences (Richardson-extrapolated) of the step in tangent
    /// coordinates, for a spatial arm in every mode with controls, at a tumbling, moving state;
    /// the step against its definition written out (velocity first, then the configuration).
    #[test]
    fn euler_step_and_jacobians_match_finite_differences() {
        let h = 0.05;
        check_step_jacobians(DiscretizationKind::Euler, h, |model, mode, z, c, plain, a, b| {
            let (nu, nz) = (model.nu(), z.len());
            let nx = nz - nu;
            // The step written out: ABA's acceleration, u⁺ = u + h a, then x⁺ with u⁺.
            let mut rates = vec![0.0; nz];
            let mut dyn2 = Dynamics::new(model, mode).unwrap();
            dyn2.rhs(model, z, c, &mut rates).unwrap();
            let up: Vec<f64> = (0..nu).map(|i| z[nx + i] + h * rates[nx + i]).collect();
            let mut expected = z.to_vec();
            for i in 0..3 {
                expected[i] += h * up[i];
            }
            let turn = crate::math::rotations::xyzw_exp(&Vector3::new(h * up[3], h * up[4], h * up[5]));
            let quat = crate::math::rotations::xyzw_multiply(&turn, &[z[3], z[4], z[5], z[6]]);
            expected[3..7].copy_from_slice(&quat);
            for i in 7..nx {
                expected[i] += h * up[i - 1];
            }
            expected[nx..].copy_from_slice(&up);
            for (p, e) in plain.iter().zip(&expected) {
                assert!((p - e).abs() < 1e-14 * (1.0 + e.abs()), "{mode:?}: {p} {e}");
            }
            // Not the identity: the attitude block turns, the accelerations depend on the state.
            assert!((a.view((3, 3), (3, 3)) - nalgebra::Matrix3::identity()).norm() > 1e-3, "{mode:?}: R(φ) is the identity");
            assert!(a.view((nu, 0), (nu, nu)).norm() > 1e-3 && b.norm() > 1e-3, "{mode:?}: a trivial Jacobian");
        });
    }
}
