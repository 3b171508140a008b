//! The projected Gauss–Seidel solver of the rigid frictional contact problem (docs/contact.md,
//! "Rigid frictional impacts"; the method of Pinocchio 4's `PGSConstraintSolver`, Jean 1999's
//! non-smooth contact dynamics, written here from the equations).
//!
//! Point by point, in order, with the contact velocity `σᵢ = gᵢ + Σⱼ Gᵢⱼ λⱼ` of the latest
//! impulses: the normal impulse takes the step of the normal's diagonal entry and is projected
//! on `λ_n ≥ 0`,
//!
//! `λ_n ← max(0, λ_n − σ_n / G_nn)`,
//!
//! then the tangential impulse, with `σ_t` updated for the new `λ_n`, takes the step of the
//! largest eigenvalue `d_t` of the point's 2×2 tangential block and is projected on the disc of
//! radius `μ λ_n`:
//!
//! `λ_t ← P_{‖·‖ ≤ μ λ_n}(λ_t − σ_t / d_t)`.
//!
//! A fixed point is a solution of Coulomb's law with maximal dissipation (coulomb_cone.rs): a
//! pushing point does not move along its normal, and its slip is zero inside the disc and
//! opposite to the friction impulse on its rim. The sweep stops when the problem's residual is at
//! most the tolerance. PGS needs `G_nn > 0` at every point (a point that cannot move along its
//! normal is refused as singular); unlike ADMM it is not guaranteed to converge when the points
//! are coupled, which the reported `converged` says.

use nalgebra::{DMatrix, DVector, Matrix2, Vector2};

use crate::collision::admm::{check_problem, ConeSolution, SolverSettings};
use crate::error::{Result, SpacearmError};

/// Solve `K ∋ λ ⊥ Gλ + g + Γ(Gλ + g) ∈ K*` by projected Gauss–Seidel (module docs), from `λ = 0`.
pub fn solve_pgs(delassus: &DMatrix<f64>, free_velocity: &DVector<f64>, friction: &[f64], settings: &SolverSettings) -> Result<ConeSolution> {
    check_problem(delassus, free_velocity, friction, settings)?;
    let g = free_velocity;
    let scale = (0..g.len()).map(|k| delassus[(k, k)]).fold(0.0, f64::max);
    let mut steps = Vec::with_capacity(friction.len());
    for i in 0..friction.len() {
        let gnn = delassus[(3 * i + 2, 3 * i + 2)];
        if !(gnn > 1e-14 * scale) {
            return Err(SpacearmError::Singular(format!("the Delassus operator's normal entry of contact {i} (the point cannot move along its normal; PGS needs it)")));
        }
        let block = Matrix2::new(delassus[(3 * i, 3 * i)], delassus[(3 * i, 3 * i + 1)], delassus[(3 * i + 1, 3 * i)], delassus[(3 * i + 1, 3 * i + 1)]);
        let dt = block.symmetric_eigen().eigenvalues.max();
        steps.push((gnn, if dt > 1e-14 * scale { dt } else { gnn }));
    }
    ConeSolution::iterate(delassus, g, friction, settings, "the PGS contact solver's impulses", DVector::zeros(g.len()), |_, lambda, _| {
        for (i, (&mu, &(gnn, dt))) in friction.iter().zip(&steps).enumerate() {
            let (t1, t2, n) = (3 * i, 3 * i + 1, 3 * i + 2);
            let row = |k: usize, lambda: &DVector<f64>| g[k] + delassus.row(k).dot(&lambda.transpose());
            let ln = (lambda[n] - row(n, &lambda) / gnn).max(0.0);
            lambda[n] = ln;
            let st = Vector2::new(row(t1, &lambda), row(t2, &lambda));
            let mut lt = Vector2::new(lambda[t1], lambda[t2]) - st / dt;
            let radius = mu * ln;
            let norm = lt.norm();
            if norm > radius {
                lt *= if norm > 0.0 { radius / norm } else { 0.0 };
            }
            lambda[t1] = lt[0];
            lambda[t2] = lt[1];
        }
        Ok(())
    })
}
