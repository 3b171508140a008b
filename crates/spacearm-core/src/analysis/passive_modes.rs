//! The small oscillations of the joints' springs about a configuration (docs/flexibility.md,
//! "Natural frequencies"): with zero system momentum the joint coordinates obey
//! `H*(q) q̈ + c* = τ + Q_passive` (docs/physics.md), and about a state at rest with `τ = 0`
//! (`q = rest` for an equilibrium) the linear part is `H* δq̈ + C δq̇ + K δq = 0`. Its modes
//! solve the symmetric generalized eigenproblem `K v = ω² H* v`:
//!
//! - [`ActuatedJoints::Held`]: the motors hold the actuated joints still (`δq_a = 0`), and only
//!   the passive coordinates move: the problem on the passive rows and columns of `H*` and `K`;
//! - [`ActuatedJoints::Free`]: no joint is held (motors off): every coordinate moves; an
//!   unsprung joint gives a mode at `ω = 0`.
//!
//! Solved by the Cholesky factor `H*_s = L Lᵀ` and the symmetric eigendecomposition of
//! `L⁻¹ K_s L⁻ᵀ`; the shapes `v = L⁻ᵀ w` are mass-normalized (`vᵀ H*_s v = 1`). The damping
//! ratio of a mode is its modal damping `ζ = vᵀ C v / (2ω)` (exact when the damping is
//! proportional, the usual first estimate otherwise; `inf` for a damped mode at `ω = 0`, 0 for an
//! undamped one). These frequencies are the imaginary parts of the eigenvalues of the
//! linearization ([`crate::derivatives::linearize`]) of the undamped system at rest at
//! `q = rest`, which the tests check.

use nalgebra::{DMatrix, SymmetricEigen};

use crate::error::{Result, SpacearmError};
use crate::gjm::compute_generalized_inertia;
use crate::model::data::Data;
use crate::model::Model;

/// What the actuated joints do during the oscillation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActuatedJoints {
    /// Held still by their motors: only the passive joints move.
    Held,
    /// Free (motors off): every joint moves.
    Free,
}

/// The modes of [`passive_modes`], in ascending frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct PassiveModes {
    /// The degrees of freedom that move (the passive ones, or all), ascending.
    pub dofs: Vec<usize>,
    /// Undamped natural frequencies `ω`, rad/s, ascending.
    pub frequencies: Vec<f64>,
    /// Modal damping ratios `ζ = vᵀ C v / (2ω)`.
    pub damping_ratios: Vec<f64>,
    /// Mode shapes, `N × modes`: column `i` is mode `i`'s joint displacement, mass-normalized
    /// (`vᵀ H* v = 1`), zero on the held joints.
    pub shapes: DMatrix<f64>,
}

/// The small-oscillation modes of the joints' springs at the configuration `x` (module docs).
pub fn passive_modes(model: &Model, data: &mut Data, x: &[f64], actuated: ActuatedJoints) -> Result<PassiveModes> {
    let h = compute_generalized_inertia(model, data, x)?.clone();
    let dyn_ = model.dof_dynamics();
    let dofs: Vec<usize> = (0..model.n_dof()).filter(|&d| actuated == ActuatedJoints::Free || !dyn_[d].actuated).collect();
    let m = dofs.len();
    let hs = DMatrix::from_fn(m, m, |i, j| h[(dofs[i], dofs[j])]);
    let chol = hs.cholesky().ok_or_else(|| SpacearmError::Singular("the generalized inertia H* of the moving joints".into()))?;
    let l = chol.l();
    // B = L⁻¹ K L⁻ᵀ: symmetric, with the eigenvalues ω² of K v = ω² H* v.
    let l_inv = l.clone().try_inverse().ok_or_else(|| SpacearmError::Singular("the Cholesky factor of H*".into()))?;
    let k = DMatrix::from_fn(m, m, |i, j| if i == j { dyn_[dofs[i]].stiffness } else { 0.0 });
    let b = &l_inv * &k * l_inv.transpose();
    let b = (&b + b.transpose()) * 0.5;
    let eig = SymmetricEigen::new(b);
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let mut shapes = DMatrix::zeros(model.n_dof(), m);
    let mut frequencies = Vec::with_capacity(m);
    let mut damping_ratios = Vec::with_capacity(m);
    for (col, &i) in order.iter().enumerate() {
        let w = l_inv.transpose() * eig.eigenvectors.column(i);
        let omega = eig.eigenvalues[i].max(0.0).sqrt();
        let modal_c: f64 = (0..m).map(|r| dyn_[dofs[r]].damping * w[r] * w[r]).sum();
        let zeta = if omega > 0.0 {
            modal_c / (2.0 * omega)
        } else if modal_c > 0.0 {
            f64::INFINITY
        } else {
            0.0
        };
        for (r, &d) in dofs.iter().enumerate() {
            shapes[(d, col)] = w[r];
        }
        frequencies.push(omega);
        damping_ratios.push(zeta);
    }
    Ok(PassiveModes { dofs, frequencies, damping_ratios, shapes })
}
