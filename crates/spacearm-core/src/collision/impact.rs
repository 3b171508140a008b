//! The rigid frictional impact (docs/contact.md, "Rigid frictional impacts"): the velocity jump of
//! a model whose bodies meet at a set of point contacts, with Coulomb friction and Newton's
//! restitution, solved on the Delassus operator (delassus.rs) by ADMM (admm.rs) or PGS (pgs.rs).
//!
//! During the impact the configuration is fixed and finite forces contribute nothing (as in
//! algorithms/impulse.rs); the impulses `λ` (3 rows a point, `[t₁, t₂, n]` of its contact frame)
//! change the velocity by
//!
//! `u⁺ = u⁻ + H⁻¹ Jᵀ λ`,  so that the contact velocity is `J u⁺ = G λ + J u⁻`.
//!
//! With the free velocity `g = J u⁻ + e [0; 0; min(v_n⁻, 0)]` per point (Newton's restitution
//! `e` acts on the points that approach), `λ` solves Coulomb's law with maximal dissipation
//! (coulomb_cone.rs): `K_μ ∋ λ ⊥ σ + Γ(σ) ∈ K*_μ`, `σ = G λ + g` — each point is apart
//! (`λ = 0`), sticks (`σ = 0`: its tangential velocity stops and its normal velocity becomes
//! `−e v_n⁻`) or slides (its normal velocity `−e v_n⁻` and the friction impulse `μ λ_n` against
//! the slip). The impulses are internal (equal and opposite on the two bodies), so the momenta
//! of a floating system are kept.

use nalgebra::{DMatrix, DVector, Matrix3};
use serde::{Deserialize, Serialize};

use crate::algorithms::kinematics::check_velocity;
use crate::collision::admm::{solve_admm, ConeSolution, SolverSettings};
use crate::collision::delassus::{delassus, ContactPoint};
use crate::collision::pgs::solve_pgs;
use crate::error::{by_name, Result, SpacearmError};
use crate::model::data::Data;
use crate::model::Model;

/// The solver's name in a description: `"admm"` or `"pgs"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ImpactSolver {
    /// Proximal ADMM (admm.rs): converges whenever a solution exists.
    #[default]
    Admm,
    /// Projected Gauss–Seidel (pgs.rs).
    Pgs,
}

impl ImpactSolver {
    /// The names accepted by [`ImpactSolver::from_name`].
    pub const NAMES: [&'static str; 2] = ["admm", "pgs"];

    /// Parse `"admm"` or `"pgs"`.
    pub fn from_name(name: &str) -> Result<Self> {
        by_name("solver", &Self::NAMES, &[ImpactSolver::Admm, ImpactSolver::Pgs], name)
    }

    /// The solver's name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// The settings of a rigid impact, as data.
///
/// ```toml
/// solver = "admm"        # or "pgs"
/// restitution = 0.0      # Newton's e in [0, 1]
/// tolerance = 1e-10      # on the residual, m/s
/// max_iterations = 1000
/// proximal = 1e-8        # ADMM's η relative to the largest eigenvalue of G
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImpactSpec {
    /// The solver.
    #[serde(default)]
    pub solver: ImpactSolver,
    /// Newton's restitution `e` in [0, 1] (default 0: a plastic impact).
    #[serde(default)]
    pub restitution: f64,
    /// The tolerance on the residual (coulomb_cone.rs), m/s (> 0; default 1e-10).
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    /// The iteration limit (≥ 1; default 1000).
    #[serde(default = "default_iterations")]
    pub max_iterations: usize,
    /// ADMM's proximal weight relative to the largest eigenvalue of `G` (≥ 0; default 1e-8).
    #[serde(default = "default_proximal")]
    pub proximal: f64,
}

fn default_tolerance() -> f64 {
    1e-10
}

fn default_iterations() -> usize {
    1000
}

fn default_proximal() -> f64 {
    1e-8
}

impl Default for ImpactSpec {
    fn default() -> Self {
        ImpactSpec { solver: ImpactSolver::Admm, restitution: 0.0, tolerance: default_tolerance(), max_iterations: default_iterations(), proximal: default_proximal() }
    }
}

impl ImpactSpec {
    /// Check every value.
    pub fn validate(&self) -> Result<()> {
        if !(self.restitution.is_finite() && (0.0..=1.0).contains(&self.restitution)) {
            return Err(SpacearmError::argument(format!("restitution must be in [0, 1], got {}", self.restitution)));
        }
        self.settings().validate()
    }

    fn settings(&self) -> SolverSettings {
        SolverSettings { tolerance: self.tolerance, max_iterations: self.max_iterations, proximal: self.proximal }
    }
}

/// The result of [`rigid_impact`].
#[derive(Debug, Clone, PartialEq)]
pub struct RigidImpact {
    /// `u⁺`.
    pub u_after: DVector<f64>,
    /// `Δu = H⁻¹ Jᵀ λ`.
    pub du: DVector<f64>,
    /// The impulses `λ` (3k: `[t₁, t₂, n]` of each point's frame), N·s; the second body of a
    /// point receives `Rᵢ λᵢ`, the first its opposite.
    pub impulse: DVector<f64>,
    /// The contact velocities before, `J u⁻` (3k, contact frames), m/s.
    pub velocity_before: DVector<f64>,
    /// The contact velocities after, `J u⁺` (3k), m/s.
    pub velocity_after: DVector<f64>,
    /// The contact frames (columns `[t₁, t₂, n]` in 𝒥).
    pub frames: Vec<Matrix3<f64>>,
    /// The contact Jacobian `J` (3k × (6+N)).
    pub jacobian: DMatrix<f64>,
    /// The Delassus operator `G` (3k × 3k).
    pub delassus: DMatrix<f64>,
    /// What the solver reports: converged, iterations, residual.
    pub solution: ConeSolution,
}

/// The velocity jump of `model` at `(x, u_before)` through the rigid frictional contacts
/// `points` (module docs). A solver that stops at its iteration limit is not an error: the
/// result says `converged = false` with the residual it reached.
pub fn rigid_impact(model: &Model, data: &mut Data, x: &[f64], u_before: &[f64], points: &[ContactPoint], spec: &ImpactSpec) -> Result<RigidImpact> {
    spec.validate()?;
    check_velocity(model, "u_before", u_before)?;
    let d = delassus(model, data, x, points)?;
    let u = DVector::from_column_slice(u_before);
    let velocity_before = &d.jacobian * &u;
    let mut g = velocity_before.clone();
    for i in 0..points.len() {
        g[3 * i + 2] += spec.restitution * velocity_before[3 * i + 2].min(0.0);
    }
    let friction: Vec<f64> = points.iter().map(|p| p.friction).collect();
    let solution = match spec.solver {
        ImpactSolver::Admm => solve_admm(&d.delassus, &g, &friction, &spec.settings())?,
        ImpactSolver::Pgs => solve_pgs(&d.delassus, &g, &friction, &spec.settings())?,
    };
    let du = &d.response * &solution.impulse;
    let u_after = &u + &du;
    let velocity_after = &d.jacobian * &u_after;
    Ok(RigidImpact { u_after, du, impulse: solution.impulse.clone(), velocity_before, velocity_after, frames: d.frames, jacobian: d.jacobian, delassus: d.delassus, solution })
}
