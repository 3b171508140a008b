//! The proximal ADMM solver of the rigid frictional contact problem (docs/contact.md, "Rigid
//! frictional impacts"; Carpentier, Le Lidec, Montaut et al. 2024, "From compliant to rigid
//! contact simulation: a unified and efficient approach", Algorithm 1; the method of Pinocchio 4's
//! `ADMMConstraintSolver`, written here from the paper).
//!
//! The problem of coulomb_cone.rs, `K ∋ λ ⊥ Gλ + g + Γ(Gλ + g) ∈ K*`, is solved as a sequence of
//! convex problems `min ½ λᵀGλ + (g + s)ᵀλ` over `λ ∈ K` with the De Saxcé shift `s` frozen at
//! the current iterate, split as `λ = z`, `z ∈ K` (ρ the penalty, η the proximal weight, y the
//! multiplier — a velocity, minus the contact velocity at the solution):
//!
//! ```text
//! s      = Γ(G z + g)
//! λ⁺     = (G + (ρ + η) I)⁻¹ (ρ z + η λ − y − g − s)
//! z⁺     = P_K(λ⁺ + y / ρ)
//! y⁺     = y + ρ (λ⁺ − z⁺)
//! ```
//!
//! At a fixed point `λ = z`, `y = −(σ + Γ(σ))` with `σ = G z + g`, and `z = P_K(z + y/ρ)` says
//! `y` is in the normal cone of `K` at `z`: the complementarity problem holds. `ρ` starts at
//! `√(L m)` (L, m the extreme eigenvalues of `G + ηI`, Nishihara et al. 2015) and every 20
//! iterations is doubled or halved when the primal residual `‖λ − z‖` and the dual one
//! `ρ ‖z⁺ − z‖` are more than 10 apart (Boyd et al. 2011, §3.4.1). (On 25 random problems of one
//! or two contacts on a 7-joint arm this took a median of 128 iterations to 1e-13 m/s, at most
//! 664; multiplying or dividing `ρ` by 10 at every iteration failed one of them in 20000, and
//! over-relaxation (α = 1.6, Boyd §3.4.3) another: the De Saxcé shift makes the problem
//! nonconvex, and neither is used.) The proximal term makes every
//! step well posed when `G` is singular (more contact rows than mobile coordinates). The stop
//! test is the problem's own residual (coulomb_cone.rs) on `z`, not the splitting's.

use nalgebra::{DMatrix, DVector};

use crate::collision::coulomb_cone::{add_de_saxce, block, project_cone, residual, ConeResidual};
use crate::error::{check_finite, Result, SpacearmError};

/// What a contact solver returns.
#[derive(Debug, Clone, PartialEq)]
pub struct ConeSolution {
    /// The impulses `λ` (3 rows a point, `[t₁, t₂, n]`), each in its cone.
    pub impulse: DVector<f64>,
    /// The contact velocities `σ = G λ + g` (3 rows a point), m/s.
    pub velocity: DVector<f64>,
    /// Whether the residual reached the tolerance within the iteration limit.
    pub converged: bool,
    /// Iterations done.
    pub iterations: usize,
    /// The residual of `impulse` (coulomb_cone.rs), m/s.
    pub residual: ConeResidual,
}

/// Settings shared by the solvers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// Stop when [`ConeResidual::max`] is at most this, m/s (> 0).
    pub tolerance: f64,
    /// The iteration limit (≥ 1).
    pub max_iterations: usize,
    /// ADMM's proximal weight `η` (≥ 0), in the units of `G`; relative to its largest
    /// eigenvalue: `η = proximal · L`.
    pub proximal: f64,
}

/// Check the problem's shapes and values.
pub(crate) fn check_problem(delassus: &DMatrix<f64>, free_velocity: &DVector<f64>, friction: &[f64], settings: &SolverSettings) -> Result<()> {
    let m = 3 * friction.len();
    if friction.is_empty() {
        return Err(SpacearmError::argument("the contact problem has no contact point"));
    }
    if delassus.nrows() != m || delassus.ncols() != m || free_velocity.len() != m {
        return Err(SpacearmError::argument(format!(
            "the contact problem of {} points needs a {m}×{m} Delassus operator and {m} free velocities, got {}×{} and {}",
            friction.len(),
            delassus.nrows(),
            delassus.ncols(),
            free_velocity.len()
        )));
    }
    if let Some((i, mu)) = friction.iter().enumerate().find(|(_, mu)| !(mu.is_finite() && **mu >= 0.0)) {
        return Err(SpacearmError::argument(format!("the friction coefficient of contact {i} must be finite and >= 0, got {mu}")));
    }
    if !(delassus.iter().chain(free_velocity.iter()).all(|v| v.is_finite())) {
        return Err(SpacearmError::argument("the Delassus operator and the free velocities must be finite"));
    }
    settings.validate()
}

impl SolverSettings {
    /// Check the tolerance (finite, > 0), the iteration limit (≥ 1) and the proximal weight (≥ 0).
    pub fn validate(&self) -> Result<()> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(SpacearmError::argument(format!("the contact solver's tolerance must be finite and > 0 m/s, got {}", self.tolerance)));
        }
        if self.max_iterations == 0 {
            return Err(SpacearmError::argument("the contact solver's max_iterations must be >= 1"));
        }
        if !(self.proximal.is_finite() && self.proximal >= 0.0) {
            return Err(SpacearmError::argument(format!("the ADMM proximal weight must be finite and >= 0, got {}", self.proximal)));
        }
        Ok(())
    }
}

impl ConeSolution {
    /// The iteration both solvers share (admm.rs, pgs.rs): from the impulses `lambda`, one
    /// `sweep(iteration, λ, σ)` after another (counted from 1, `σ = G λ + g` of the current
    /// iterate) until the problem's residual (coulomb_cone.rs) is at most the tolerance or the
    /// iteration limit is reached; the last iterate, checked finite (`what`), with its contact
    /// velocities and residual.
    pub(crate) fn iterate(
        delassus: &DMatrix<f64>,
        g: &DVector<f64>,
        friction: &[f64],
        settings: &SolverSettings,
        what: &str,
        mut lambda: DVector<f64>,
        mut sweep: impl FnMut(usize, &mut DVector<f64>, &DVector<f64>) -> Result<()>,
    ) -> Result<ConeSolution> {
        let evaluate = |lambda: &DVector<f64>| {
            let sigma = delassus * lambda + g;
            let r = residual(lambda, &sigma, friction);
            (sigma, r)
        };
        let (mut sigma, mut res) = evaluate(&lambda);
        let mut iterations = 0;
        while res.max() > settings.tolerance && iterations < settings.max_iterations {
            iterations += 1;
            sweep(iterations, &mut lambda, &sigma)?;
            (sigma, res) = evaluate(&lambda);
        }
        check_finite(what, lambda.as_slice())?;
        Ok(ConeSolution { converged: res.max() <= settings.tolerance, impulse: lambda, velocity: sigma, iterations, residual: res })
    }
}

/// How often (iterations) `ρ` may be adapted.
const RHO_EVERY: usize = 20;

/// Project every block of `v` on its cone.
fn project_all(v: &DVector<f64>, friction: &[f64]) -> DVector<f64> {
    let mut out = v.clone();
    for (i, &mu) in friction.iter().enumerate() {
        out.fixed_rows_mut::<3>(3 * i).copy_from(&project_cone(&block(v, i), mu));
    }
    out
}

/// Solve `K ∋ λ ⊥ Gλ + g + Γ(Gλ + g) ∈ K*` by proximal ADMM (module docs), from `λ = 0`.
pub fn solve_admm(delassus: &DMatrix<f64>, free_velocity: &DVector<f64>, friction: &[f64], settings: &SolverSettings) -> Result<ConeSolution> {
    check_problem(delassus, free_velocity, friction, settings)?;
    let g = free_velocity;
    let m = g.len();
    let eig = delassus.clone().symmetric_eigen().eigenvalues;
    let largest = eig.max().max(0.0);
    if largest <= 0.0 {
        return Err(SpacearmError::Singular("the Delassus operator (zero: no contact point can move)".into()));
    }
    let eta = settings.proximal * largest;
    // The smallest eigenvalue, floored where G is singular: ρ's initial scale.
    let smallest = (eig.min().max(0.0) + eta).max(1e-9 * largest);
    let mut rho = (largest * smallest).sqrt();
    let factor = |rho: f64| -> Result<nalgebra::Cholesky<f64, nalgebra::Dyn>> {
        let mut a = delassus.clone();
        for k in 0..m {
            a[(k, k)] += rho + eta;
        }
        a.cholesky().ok_or_else(|| SpacearmError::Singular("G + (ρ + η) I in the ADMM contact solver".into()))
    };
    let mut chol = factor(rho)?;
    let mut lambda = DVector::zeros(m);
    let mut y = DVector::zeros(m);
    // The iterate the solver reports, and whose residual it tests, is `z` (module docs).
    ConeSolution::iterate(delassus, g, friction, settings, "the ADMM contact solver's impulses", DVector::zeros(m), |iterations, z, sigma| {
        let mut shifted = sigma.clone();
        add_de_saxce(&mut shifted, friction);
        let shift = &shifted - sigma; // Γ(σ)
        let rhs = &*z * rho + &lambda * eta - &y - g - shift;
        lambda = chol.solve(&rhs);
        let z_previous = std::mem::replace(z, project_all(&(&lambda + &y / rho), friction));
        y += (&lambda - &*z) * rho;
        if iterations % RHO_EVERY == 0 {
            let primal = (&lambda - &*z).amax();
            let dual = rho * (&*z - &z_previous).amax();
            let new_rho = if primal > 10.0 * dual { rho * 2.0 } else if dual > 10.0 * primal { rho / 2.0 } else { rho };
            if new_rho != rho && new_rho > 1e-12 * largest && new_rho < 1e12 * largest {
                rho = new_rho;
                chol = factor(rho)?;
            }
        }
        Ok(())
    })
}
