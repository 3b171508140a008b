//! Rigid frictional contact inside a run (docs/contact.md, "Rigid contact in a run"): a
//! velocity-level time-stepping scheme in the manner of Moreau–Jean and Anitescu–Potra, the cone
//! problem of each step solved on the Delassus operator by the core's ADMM or PGS
//! (collision/admm.rs, collision/pgs.rs).
//!
//! Each step from `(t_k, x_k, u_k)` of length `h` (RK4 runs only; [`crate::sim::stepper`]):
//!
//! 1. the contacts of `x_k` between the admitted pairs, signed distance `d_i ≤ margin`
//!    (collision/detect.rs), each a point contact at the midpoint of its two surface points with
//!    its normal and the run's `μ` (collision/delassus.rs);
//! 2. the free velocity `u_free = u_k + ½ h u̇_k`, `u̇_k = H⁻¹(τ − C)` the plant's forward
//!    dynamics at `(t_k, y_k)` without contact (the RK4's first stage): the impulse acts at the
//!    step's start and the forces through it (step 5), so `u_free + H⁻¹Jᵀλ` is the mean velocity
//!    over the step, `ū = u_k⁺ + ½ h u̇_k`, to `O(h²)`, and the step moves the points by
//!    `h J ū` — the velocity that the cone problem constrains is the one that moves them (a point
//!    held by friction does not creep, a gap closes to 0, not to `O(h²)`). Moreau–Jean's
//!    `u_k + h u̇_k` constrains the velocity at the step's end, which is the right one when the
//!    position is updated with it (`q_{k+1} = q_k + h u_{k+1}`), not after an RK4 step;
//! 3. the cone problem of collision/coulomb_cone.rs, `K_μ ∋ λ ⊥ σ + Γ(σ) ∈ K*_μ`,
//!    `σ = G λ + g`, `G = J H⁻¹ Jᵀ`, with `g = J u_free + b` where each point's normal row gets
//!    the bias
//!
//!    `b_i = d_i / h` (apart, `d_i ≥ 0`: the gap may close in the step, no more),
//!    `b_i = β d_i / h` (interpenetrating: pushed out at `β δ / h`, a Baumgarte velocity bias),
//!
//!    and, at an impact (`d_i + h (J u_free)_n,i ≤ 0`: the point reaches the other surface in
//!    the step), `b_i ← min(b_i, e min(v⁻_n,i, 0))`, `v⁻ = J u_k`: Newton's restitution, the
//!    normal velocity after it at least `−e v⁻_n`, as in collision/impact.rs; the bias vector
//!    enters `g` by its part in the range of `G` ([`range_part`]: all of it when `G` is regular);
//! 4. the velocity jump `u_k⁺ = u_k + H⁻¹ Jᵀ λ` at `x_k` (collision/impact.rs's `Δu`);
//! 5. the smooth motion from `(x_k, u_k⁺)` over `h` by the run's RK4 (the quaternion kept on its
//!    manifold by the plant's projection, as in every run).
//!
//! The impulses are internal (equal and opposite on the two bodies, the base's columns of `J`
//! cancel), so the jump keeps the system's momentum exactly and the RK4 step keeps it to its
//! accuracy. The jump changes the kinetic energy by `λᵀ J (u_k + u_k⁺) / 2` (exact:
//! `½ u⁺ᵀ H u⁺ − ½ uᵀ H u` with `H Δu = Jᵀ λ`), added to the contact work `W_c`, the state's
//! entry after `[x; u]`: the ledger `E − W_c` is the compliant contact's. The velocity sampled
//! at a step's start is the one after the previous step's forces: a point resting under a steady
//! push `F` shows `−½ h F / m` there, its mean over each step 0.
//!
//! Imports: [`crate::collision`] (Delassus, solvers). The contacts of a state come from the
//! plant's contact ([`crate::sim::contact`], which holds a [`RigidContact`]).

use nalgebra::{DMatrix, DVector, SymmetricEigen, Vector3};

use crate::collision::admm::{solve_admm, SolverSettings};
use crate::collision::delassus::{delassus, ContactPoint};
use crate::collision::pgs::solve_pgs;
use crate::collision::{Contact, ImpactSolver, ImpactSpec};
use crate::error::{Result, SpacearmError};
use crate::model::data::Data;
use crate::model::Model;

/// The rigid contact of a run: its settings and what the steps so far did.
#[derive(Debug, Clone)]
pub(crate) struct RigidContact {
    /// Solver, restitution, tolerance, iteration limit.
    pub(crate) impact: ImpactSpec,
    /// `β` in [0, 1].
    pub(crate) stabilization: f64,
    /// Coulomb's `μ` of every point.
    pub(crate) friction: f64,
    /// The sum since `t = 0` of the impulses `Rᵢ λᵢ` received by the second body of each point
    /// (in 𝒥, N·s; the first received the opposite).
    pub(crate) impulse: Vector3<f64>,
    /// The last step's cone problem: iterations and residual (m/s), and the largest residual
    /// over the run.
    pub(crate) iterations: usize,
    pub(crate) residual: f64,
    pub(crate) max_residual: f64,
}

/// The default position-error stabilization `β`.
pub const RIGID_STABILIZATION: f64 = 0.2;

impl RigidContact {
    /// From the validated settings of a description of kind `"rigid"`.
    pub(crate) fn new(impact: ImpactSpec, stabilization: f64, friction: f64) -> Self {
        RigidContact {
            impact,
            stabilization,
            friction,
            impulse: Vector3::zeros(),
            iterations: 0,
            residual: 0.0,
            max_residual: 0.0,
        }
    }

    fn settings(&self) -> SolverSettings {
        SolverSettings { tolerance: self.impact.tolerance, max_iterations: self.impact.max_iterations, proximal: self.impact.proximal }
    }
}

/// What one step's jump did: the points that took a normal impulse and `Σ λ_n / h` (N).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct JumpSummary {
    pub(crate) count: usize,
    pub(crate) normal_force: f64,
}

/// The velocity jump of the step of length `h` from the ODE state `y` (`[x; u; W_c]`) at time
/// `t` through the contacts `found` of its `x` (step 1 of the module docs, done by the caller),
/// whose forward dynamics `du` (`u̇`, width 6+N) the plant has just evaluated: steps 2–4. `y`'s
/// `u` and `W_c` are updated.
#[allow(clippy::too_many_arguments)]
pub(crate) fn rigid_jump(model: &Model, data: &mut Data, rigid: &mut RigidContact, found: &[Contact], t: f64, h: f64, y: &mut [f64], du: &[f64]) -> Result<JumpSummary> {
    let (nx, nu) = (model.nx(), model.nu());
    let mut summary = JumpSummary::default();
    if found.is_empty() {
        return Ok(summary);
    }
    let points: Vec<ContactPoint> =
        found.iter().map(|c| ContactPoint { body: c.body, point: 0.5 * (c.point[0] + c.point[1]), normal: c.normal, friction: rigid.friction }).collect();
    let d = delassus(model, data, &y[..nx], &points)?;
    let u = DVector::from_column_slice(&y[nx..nx + nu]);
    let u_free = &u + DVector::from_column_slice(du) * (0.5 * h);
    let v_before = &d.jacobian * &u;
    let mut g = &d.jacobian * &u_free;
    let e = rigid.impact.restitution;
    let mut bias = DVector::zeros(g.len());
    for (i, c) in found.iter().enumerate() {
        let n = 3 * i + 2;
        let mut b = if c.distance >= 0.0 { c.distance / h } else { rigid.stabilization * c.distance / h };
        if e > 0.0 && c.distance + h * g[n] <= 0.0 {
            b = b.min(e * v_before[n].min(0.0));
        }
        bias[n] = b;
    }
    g += range_part(&d.delassus, &bias);
    let friction: Vec<f64> = points.iter().map(|p| p.friction).collect();
    let solution = match rigid.impact.solver {
        ImpactSolver::Admm => solve_admm(&d.delassus, &g, &friction, &rigid.settings()),
        ImpactSolver::Pgs => solve_pgs(&d.delassus, &g, &friction, &rigid.settings()),
    }
    .map_err(|e| {
        SpacearmError::Simulation(format!(
            "the rigid contact's {} solver failed at t = {t} s ({} contact points): {e}{}",
            rigid.impact.solver.name(),
            points.len(),
            if rigid.impact.solver == ImpactSolver::Admm { " — try solver=\"pgs\"" } else { "" }
        ))
    })?;
    let residual = solution.residual.max();
    if !solution.converged {
        return Err(SpacearmError::Simulation(format!(
            "the rigid contact's {} solver did not reach its tolerance {:e} m/s in {} iterations at t = {t} s ({} contact points, residual {residual:.3e} m/s): \
             raise max_iterations, loosen tolerance{}",
            rigid.impact.solver.name(),
            rigid.impact.tolerance,
            rigid.impact.max_iterations,
            points.len(),
            if rigid.impact.solver == ImpactSolver::Pgs { ", or use solver=\"admm\" (PGS need not converge on coupled points)" } else { "" }
        )));
    }
    rigid.iterations = solution.iterations;
    rigid.residual = residual;
    rigid.max_residual = rigid.max_residual.max(residual);
    let lambda = &solution.impulse;
    if lambda.iter().all(|v| *v == 0.0) {
        return Ok(summary);
    }
    let du_jump = &d.response * lambda;
    let u_after = &u + &du_jump;
    let v_after = &d.jacobian * &u_after;
    // ΔT = λᵀ J (u + u⁺) / 2 (module docs).
    let work = 0.5 * lambda.dot(&(&v_before + &v_after));
    for (i, frame) in d.frames.iter().enumerate() {
        let l = Vector3::new(lambda[3 * i], lambda[3 * i + 1], lambda[3 * i + 2]);
        if l[2] > 0.0 {
            summary.count += 1;
            summary.normal_force += l[2] / h;
        }
        rigid.impulse += frame * l;
    }
    y[nx..nx + nu].copy_from_slice(u_after.as_slice());
    y[nx + nu] += work;
    Ok(summary)
}

/// The part of the bias `b` in the range of `G` (= the range of `J`: the contact velocities the
/// system's motion can take), `Σ vᵢ vᵢᵀ b` over the eigenvectors of eigenvalues above
/// [`RANGE_TOLERANCE`] times the largest; `b` itself when `G` is regular. A bias outside that
/// range asks a point for a velocity that no motion gives (a planar arm's tip on a face whose
/// normal leaves the arm's plane), and the cone problem then has no solution; its part in the
/// range closes the same gap along the directions the points can move.
fn range_part(delassus: &DMatrix<f64>, bias: &DVector<f64>) -> DVector<f64> {
    let eig = SymmetricEigen::new(delassus.clone());
    let largest = eig.eigenvalues.iter().fold(0.0_f64, |m, v| m.max(*v));
    if eig.eigenvalues.iter().all(|v| *v > RANGE_TOLERANCE * largest) {
        return bias.clone();
    }
    let mut out = DVector::zeros(bias.len());
    for (i, v) in eig.eigenvalues.iter().enumerate() {
        if *v > RANGE_TOLERANCE * largest {
            let col = eig.eigenvectors.column(i);
            out += col * col.dot(bias);
        }
    }
    out
}

/// Eigenvalues of `G` at most this times its largest are its null space ([`range_part`]).
const RANGE_TOLERANCE: f64 = 1e-10;
