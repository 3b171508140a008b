//! The multiple-shooting problem the FDDP solver sees: knots `k = 0..T` with states `z_k`
//! (points of a manifold with tangent dimension `nd`), controls `c_k` (`k < T`, box bounds),
//!
//! `min Σ_{k<T} ℓ_k(z_k, c_k) + ℓ_T(z_T)` subject to `z_{k+1} = Φ_k(z_k, c_k)`, `z_0 = z̄_0`,
//! `lower ≤ c_k ≤ upper`,
//!
//! and, at every knot, the quadratic model of the cost and the linear model of the step in the
//! tangent space ([`KnotModel`]). The robot's problem is [`super::problem::RobotProblem`]; the
//! tests add a linear-quadratic one with a closed-form solution.

use nalgebra::{DMatrix, DVector};

use crate::error::Result;

/// The derivatives of one knot: the step's tangent Jacobians and the cost's gradient and
/// (Gauss–Newton) Hessian, in tangent coordinates.
#[derive(Debug, Clone)]
pub struct KnotModel {
    /// `A = ∂z⁺/∂δz` (`nd × nd`).
    pub a: DMatrix<f64>,
    /// `B = ∂z⁺/∂c` (`nd × m`).
    pub b: DMatrix<f64>,
    /// `∂ℓ/∂δz`.
    pub lz: DVector<f64>,
    /// `∂ℓ/∂c`.
    pub lc: DVector<f64>,
    /// `∂²ℓ/∂δz²`.
    pub lzz: DMatrix<f64>,
    /// `∂²ℓ/∂c²`.
    pub lcc: DMatrix<f64>,
    /// `∂²ℓ/∂c∂δz` (`m × nd`).
    pub lcz: DMatrix<f64>,
}

impl KnotModel {
    /// Zeros for tangent dimension `nd` and `m` controls.
    pub fn zeros(nd: usize, m: usize) -> Self {
        KnotModel {
            a: DMatrix::zeros(nd, nd),
            b: DMatrix::zeros(nd, m),
            lz: DVector::zeros(nd),
            lc: DVector::zeros(m),
            lzz: DMatrix::zeros(nd, nd),
            lcc: DMatrix::zeros(m, m),
            lcz: DMatrix::zeros(m, nd),
        }
    }

    /// The cost part set to zero (before the cost terms add theirs).
    pub fn clear_cost(&mut self) {
        self.lz.fill(0.0);
        self.lc.fill(0.0);
        self.lzz.fill(0.0);
        self.lcc.fill(0.0);
        self.lcz.fill(0.0);
    }
}

/// A multiple-shooting optimal-control problem (module docs).
pub trait ShootingProblem {
    /// The number of steps `T`.
    fn horizon(&self) -> usize;
    /// Length of a state point `z`.
    fn nz(&self) -> usize;
    /// Tangent dimension of the states.
    fn nd(&self) -> usize;
    /// Length of a control `c`.
    fn nc(&self) -> usize;
    /// The controls' lower bounds (`−∞`: none).
    fn lower(&self) -> &[f64];
    /// The controls' upper bounds (`+∞`: none).
    fn upper(&self) -> &[f64];
    /// The initial state `z̄_0`.
    fn initial_state(&self) -> &[f64];
    /// `δz` with `z1 = z0 ⊕ δz`.
    fn diff(&self, z0: &[f64], z1: &[f64], out: &mut [f64]);
    /// `z ⊕ δz`.
    fn integrate(&self, z: &[f64], dz: &[f64], out: &mut [f64]);
    /// Whether every running knot's model (step, cost and their derivatives) is a function of
    /// the knot's state and control alone, the same at every knot (no cost term depends on the
    /// knot's time); default `false`. A receding-horizon warm start then keeps the shifted
    /// knots' models ([`super::fddp::Workspace::shift`]).
    fn time_invariant(&self) -> bool {
        false
    }
    /// Bring a guessed state onto the manifold (default: nothing).
    fn project(&self, _z: &mut [f64]) {}
    /// The running cost `ℓ_k(z, c)` of knot `k < T`, and `Φ_k(z, c)` into `next`.
    fn running(&mut self, k: usize, z: &[f64], c: &[f64], next: &mut [f64]) -> Result<f64>;
    /// The derivatives of knot `k < T` into `out` (all fields).
    fn running_derivatives(&mut self, k: usize, z: &[f64], c: &[f64], out: &mut KnotModel) -> Result<()>;
    /// [`ShootingProblem::running`] and [`ShootingProblem::running_derivatives`] of knot `k` at
    /// once (a problem whose derivatives give the step and the cost overrides it, so that the
    /// solver's linearization does not evaluate the step twice); returns the cost.
    fn running_with_derivatives(&mut self, k: usize, z: &[f64], c: &[f64], next: &mut [f64], out: &mut KnotModel) -> Result<f64> {
        let cost = self.running(k, z, c, next)?;
        self.running_derivatives(k, z, c, out)?;
        Ok(cost)
    }
    /// The terminal cost `ℓ_T(z)`.
    fn terminal(&mut self, z: &[f64]) -> Result<f64>;
    /// The terminal cost's derivatives into `out.lz`, `out.lzz`.
    fn terminal_derivatives(&mut self, z: &[f64], out: &mut KnotModel) -> Result<()>;
}
