//! The resolved-motion-rate solver (Whitney 1969) of a point of a free-floating system through
//! the Generalized Jacobian `J*` (Umetani & Yoshida 1989; paper eqs. 109–111): the one solver
//! behind the native controller in the simulation loop ([`crate::control::ResolvedMotionRate`])
//! and the analyses ([`super::redundancy::rmrc_rates`], [`super::redundancy::move_to`]).
//!
//! The solver resolves the joint rates `q̇` of a set of **active** joints (the arm; all joints in
//! the analyses). The other joints it is told of (the reaction wheels) and the system momentum
//! `M0` only add **drift** to the point twist: `[v; ω] = J*_A q̇_A + J*_W q̇_W + J_0X H0⁻¹ M0`
//! (eq. 109 generalized to `M0 ≠ 0`), so the task is `J q̇ = v_d − v_drift` on the task rows
//! ([`Task`]), `J` the task rows of `J*` over the active columns. With
//! `Ω` the angular rows of `−H0⁻¹ H0m` over the same columns (the base angular velocity per unit
//! joint rate, [`super::reaction_null_space`]):
//!
//! 1. primary task — `q̇₁ = P Ĵ⁺_λ (v_d − v_drift)` with `Ĵ = J P`, `P = E` or, for
//!    [`Strategy::Reactionless`], the projector onto the null space of `Ω` (rank at `1e-9 σ_max`):
//!    then the arm adds no base rotation (Nenchev et al. 1999). `Ĵ⁺_λ` is the damped least-squares
//!    inverse of [`crate::math::dls`], each singular direction damped by the law `λ(σᵢ)` of
//!    [`DampingLaw`] (the reported damping is the largest, `λ(σ_min)`);
//! 2. [`Strategy::MinimumBaseDisturbance`] — the base angular velocity as a second-priority
//!    task (Nakamura, Hanafusa & Yoshikawa 1987 task priority; Yoshida & Nenchev 1995):
//!    `q̇₂ = N₁ (Ω N₁)⁺ (−Ω q̇₁)` with `N₁ = P − Ĵ⁺Ĵ`; it removes as much of the arm's base rotation
//!    as the task's null space allows (the inverse of `Ω N₁` is damped like the primary one,
//!    with `ε = λ_max = 0.01 σ_max(Ω N₁)`, so that base rotations the null space can hardly reach
//!    are reduced rather than chased with unbounded rates; skipped when `σ_max(Ω N₁) ≤ 1e-9 |Ω|`,
//!    a null space that cannot turn the base at all);
//! 3. gradient objectives projected into the remaining null space `N`: `q̇₃ = N z`,
//!    `z = k_w ∇w(q) + k_l ∇h(q)`, with `w` the manipulability `Π σᵢ` of `J` (singularity
//!    avoidance, gradient by central differences) and `h = −½ Σ ((qᵢ − q̄ᵢ)/(q_max,i − q_min,i))²`
//!    over the active joints with finite limits (joint-limit avoidance, Liégeois 1977);
//! 4. rate caps (one per active joint): the null-space part is shortened first so that the task
//!    is kept (largest `α ∈ [0, 1]` with `|q̇₁ + α (q̇₂ + q̇₃)|` within the caps); only if the task
//!    alone exceeds a cap is the whole `q̇₁` scaled down (direction kept). The analyses cap at the
//!    model's joint velocity limits, the controller at its `max_joint_rate`.
//!
//! Every factorisation is the one-sided Jacobi SVD [`RowSvd`] of [`crate::math::dls`] in
//! buffers allocated once, in [`RmrcSolver::new`]: an evaluation allocates nothing (the
//! controller runs it at every stage of the integrator).

use nalgebra::{DMatrix, DVector, Matrix3, Rotation3, UnitQuaternion, Vector3, Vector6};

use super::Task;
use crate::algorithms::momentum::momentum;
use crate::error::{Result, SpacearmError};
use crate::gjm::{compute_generalized_jacobian, momentum_twist};
use crate::math::dls::{DampingLaw, RowSvd, RANK_TOLERANCE};
use crate::model::data::Data;
use crate::model::Model;

/// How the primary task treats the base.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strategy {
    /// Plain (damped) pseudo-inverse of the task rows of `J*`: the base rotates as it may.
    Naive,
    /// Task restricted to the reaction null space: zero base angular velocity from the arm.
    Reactionless,
    /// Task first, then as little base angular velocity as its null space allows.
    MinimumBaseDisturbance,
}

// The names, as Python spells them.
crate::error::named_by!(Strategy, "strategy", [Naive = "naive", Reactionless = "reactionless", MinimumBaseDisturbance = "minimum_disturbance"]);

/// Options of the resolved-motion-rate solver.
#[derive(Debug, Clone)]
pub struct RmrcOptions {
    /// Rows of the point twist that the task controls.
    pub task: Task,
    /// Damping law of the DLS inverse near singularities.
    pub damping: DampingLaw,
    /// Feedback gain `K` on the task error, 1/s (used by the callers that form `v_d`).
    pub feedback_gain: f64,
    /// Treatment of the base.
    pub strategy: Strategy,
    /// Gain `k_w` of manipulability ascent in the null space (0: off).
    pub manipulability_gain: f64,
    /// Gain `k_l` of joint-limit avoidance in the null space (0: off).
    pub joint_limit_gain: f64,
}

impl RmrcOptions {
    /// The options of the classic controller: the given task rows, naive, no null-space objectives.
    pub fn task(task: Task, damping: DampingLaw, feedback_gain: f64) -> Self {
        RmrcOptions { task, damping, feedback_gain, strategy: Strategy::Naive, manipulability_gain: 0.0, joint_limit_gain: 0.0 }
    }

    /// Check the gains (finite, ≥ 0).
    pub fn check(&self) -> Result<()> {
        for (what, v) in [("feedback gain", self.feedback_gain), ("manipulability gain", self.manipulability_gain), ("joint-limit gain", self.joint_limit_gain)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SpacearmError::InvalidArgument(format!("the {what} must be finite and >= 0, got {v}")));
            }
        }
        Ok(())
    }
}

/// What one evaluation saw besides the rates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RmrcDiagnostics {
    /// `σ_min` of the (projected) task Jacobian `Ĵ`.
    pub sigma_min: f64,
    /// `λ²(σ_min)`, the largest damping of the directions.
    pub damping_sq: f64,
    /// `Ω q̇`, the base angular velocity the rates produce (zero momentum, no wheels), in 𝒥;
    /// `None` when the solver was built without it and the strategy did not need `Ω`.
    pub base_angular_velocity: Option<Vector3<f64>>,
}

/// The desired point twist `[ṗ_ref + K (p_ref − p); K e_R]` (in 𝒥) of a position reference
/// and an orientation to hold: `e_R` the rotation vector of `R_ref Rᵀ` (`R` the orientation of
/// the point's body). The rows a task does not select are ignored by the solver.
pub fn desired_twist(p_ref: &Vector3<f64>, v_ref: &Vector3<f64>, p: &Vector3<f64>, r_ref: &Matrix3<f64>, r: &Matrix3<f64>, gain: f64) -> Vector6<f64> {
    let lin = v_ref + (p_ref - p) * gain;
    let err = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r_ref * r.transpose())).scaled_axis();
    let ang = err * gain;
    Vector6::new(lin.x, lin.y, lin.z, ang.x, ang.y, ang.z)
}

/// `out = a b` by plain loops: nalgebra's product of dynamic matrices packs them in a buffer
/// it allocates (matrixmultiply) past a few rows, and this runs in the simulation loop.
fn product(a: &DMatrix<f64>, b: &DMatrix<f64>, out: &mut DMatrix<f64>) {
    for c in 0..b.ncols() {
        for r in 0..a.nrows() {
            out[(r, c)] = (0..a.ncols()).map(|i| a[(r, i)] * b[(i, c)]).sum();
        }
    }
}

/// The resolved-motion-rate solver with its workspace (module docs).
#[derive(Debug, Clone)]
pub struct RmrcSolver {
    options: RmrcOptions,
    active: Vec<usize>,
    drift: Vec<usize>,
    caps: Vec<f64>,
    with_base_velocity: bool,
    // Workspaces (k = number of active joints, m = task rows).
    j: DMatrix<f64>,
    omega: DMatrix<f64>,
    proj: DMatrix<f64>,
    jp: DMatrix<f64>,
    null: DMatrix<f64>,
    square: DMatrix<f64>,
    square2: DMatrix<f64>,
    on: DMatrix<f64>,
    primary: DVector<f64>,
    qd: DVector<f64>,
    vec_k: DVector<f64>,
    vec_k2: DVector<f64>,
    vec_3: DVector<f64>,
    rhs: [f64; 6],
    svd: RowSvd,
    xp: Vec<f64>,
}

impl RmrcSolver {
    /// A solver of the joint rates of the `active` dofs (distinct, at least one), with the
    /// rates of the `drift` dofs (e.g. the wheels; distinct, none active) as drift, one rate cap
    /// per active dof (> 0; infinity: none). `with_base_velocity`: always report `Ω q̇`.
    pub fn new(model: &Model, options: RmrcOptions, active: Vec<usize>, drift: Vec<usize>, caps: Vec<f64>, with_base_velocity: bool) -> Result<Self> {
        options.check()?;
        let n = model.n_dof();
        let k = active.len();
        if k == 0 {
            return Err(SpacearmError::InvalidModel("the model has no joints to move".into()));
        }
        let mut seen = vec![false; n];
        for &d in active.iter().chain(drift.iter()) {
            if d >= n || seen[d] {
                return Err(SpacearmError::InvalidArgument(format!("resolved-motion-rate dofs: {d} is out of range (N = {n}) or listed twice")));
            }
            seen[d] = true;
        }
        if caps.len() != k {
            return Err(SpacearmError::Dimension { what: "joint-rate caps".into(), expected: format!("one per active joint ({k})"), got: caps.len() });
        }
        if let Some(c) = caps.iter().find(|&&c| !(c > 0.0)) {
            return Err(SpacearmError::InvalidArgument(format!("a joint-rate cap must be > 0 (infinity: none), got {c}")));
        }
        let m = options.task.len();
        Ok(RmrcSolver {
            options,
            active,
            drift,
            caps,
            with_base_velocity,
            j: DMatrix::zeros(m, k),
            omega: DMatrix::zeros(3, k),
            proj: DMatrix::zeros(k, k),
            jp: DMatrix::zeros(m, k),
            null: DMatrix::zeros(k, k),
            square: DMatrix::zeros(k, k),
            square2: DMatrix::zeros(k, k),
            on: DMatrix::zeros(3, k),
            primary: DVector::zeros(k),
            qd: DVector::zeros(k),
            vec_k: DVector::zeros(k),
            vec_k2: DVector::zeros(k),
            vec_3: DVector::zeros(3),
            rhs: [0.0; 6],
            svd: RowSvd::new(k),
            xp: vec![0.0; 7 + n],
        })
    }

    /// The analyses' solver: every joint active, no drift, the model's joint velocity limits as
    /// caps, `Ω q̇` always reported.
    pub fn for_model(model: &Model, options: RmrcOptions) -> Result<Self> {
        let caps = (0..model.n_dof())
            .map(|i| {
                let v = model.links()[model.body_of_dof(i) - 1].joint.limits.velocity;
                if v.is_finite() && v > 0.0 { v } else { f64::INFINITY }
            })
            .collect();
        RmrcSolver::new(model, options, (0..model.n_dof()).collect(), vec![], caps, true)
    }

    /// The options.
    pub fn options(&self) -> &RmrcOptions {
        &self.options
    }

    /// The joint rates of the last [`RmrcSolver::solve`], one per active dof (in their order).
    pub fn rates(&self) -> &DVector<f64> {
        &self.qd
    }

    /// Copy the task rows of `js` (6×N) over the active columns into `self.j`.
    fn take_task_rows(&mut self, js: &DMatrix<f64>) {
        for (i, &r) in self.options.task.rows().iter().enumerate() {
            for (c, &d) in self.active.iter().enumerate() {
                self.j[(i, c)] = js[(r, d)];
            }
        }
    }

    /// Joint rates for the desired point twist `desired` (6 values in 𝒥; the task rows used) of
    /// the point fixed to `body` at `offset`, at configuration `x`. With `u` (the generalized
    /// velocity) the drift of the momentum and of the drift dofs is subtracted; without it the
    /// momentum is zero and the drift dofs at rest. The rates are left in [`RmrcSolver::rates`].
    #[allow(clippy::too_many_arguments)]
    pub fn solve(&mut self, model: &Model, data: &mut Data, x: &[f64], u: Option<&[f64]>, body: usize, offset: &Vector3<f64>, desired: &Vector6<f64>) -> Result<RmrcDiagnostics> {
        let k = self.active.len();
        let mut drift = Vector6::zeros();
        if let Some(u) = u {
            // The point twist from the system momentum (J_0X H0⁻¹ M0).
            let mom = momentum(model, data, x, u)?;
            drift = momentum_twist(model, data, x, body, offset, &mom.linear, &mom.angular_about_origin)?;
        }
        let js = compute_generalized_jacobian(model, data, x, body, offset)?;
        if let Some(u) = u {
            for &w in &self.drift {
                for r in 0..6 {
                    drift[r] += js[(r, w)] * u[6 + w];
                }
            }
        }
        self.take_task_rows(js);
        for (i, &r) in self.options.task.rows().iter().enumerate() {
            self.rhs[i] = desired[r] - drift[r];
        }
        crate::error::check_finite("task Jacobian", self.j.as_slice())?;
        let strategy = self.options.strategy;
        let need_omega = self.with_base_velocity || strategy != Strategy::Naive;
        if need_omega {
            let base = compute_generalized_jacobian(model, data, x, 0, &Vector3::zeros())?;
            for (c, &d) in self.active.iter().enumerate() {
                for r in 0..3 {
                    self.omega[(r, c)] = base[(3 + r, d)];
                }
            }
        }
        let m = self.options.task.len();
        // 1. Primary task, in the reaction null space for the reactionless strategy.
        let reactionless = strategy == Strategy::Reactionless;
        if reactionless {
            self.svd.factor(&self.omega);
            self.proj.fill_with_identity();
            self.svd.subtract_row_space(1e-9, &mut self.proj);
            product(&self.j, &self.proj, &mut self.jp);
        } else {
            self.jp.copy_from(&self.j);
        }
        self.svd.factor(&self.jp);
        let sigma_min = self.svd.sigma_min();
        let damping_sq = self.options.damping.damping_sq(sigma_min);
        if reactionless {
            self.svd.solve(&self.rhs[..m], &self.options.damping, &mut self.vec_k);
            self.proj.mul_to(&self.vec_k, &mut self.primary);
        } else {
            self.svd.solve(&self.rhs[..m], &self.options.damping, &mut self.primary);
        }
        self.qd.copy_from(&self.primary);
        let objectives = self.options.manipulability_gain > 0.0 || self.options.joint_limit_gain > 0.0;
        if strategy == Strategy::MinimumBaseDisturbance || objectives {
            // Null space of the primary task within range(P): N₁ = P − Ĵ⁺Ĵ (undamped, rank-cut).
            if reactionless {
                self.null.copy_from(&self.proj);
            } else {
                self.null.fill_with_identity();
            }
            self.svd.subtract_row_space(RANK_TOLERANCE, &mut self.null);
        }
        // 2. The arm's base rotation as the second task, unless the task's null space cannot
        // turn the base at all (Ω N₁ zero to rounding: its "inverse" would amplify rounding).
        if strategy == Strategy::MinimumBaseDisturbance {
            product(&self.omega, &self.null, &mut self.on);
            self.svd.factor(&self.on);
            let scale = self.svd.sigma_max();
            if scale > 1e-9 * self.omega.norm() {
                let law = DampingLaw { threshold: 0.01 * scale, max_damping: 0.01 * scale };
                self.omega.mul_to(&self.qd, &mut self.vec_3);
                self.vec_3.neg_mut();
                self.svd.solve(self.vec_3.as_slice(), &law, &mut self.vec_k);
                self.null.mul_to(&self.vec_k, &mut self.vec_k2);
                self.qd += &self.vec_k2;
                // N = N₁ (E − (Ω N₁)⁺ (Ω N₁)).
                self.square.fill_with_identity();
                self.svd.subtract_row_space(RANK_TOLERANCE, &mut self.square);
                product(&self.null, &self.square, &mut self.square2);
                std::mem::swap(&mut self.null, &mut self.square2);
            }
        }
        // 3. Gradient objectives in the remaining null space.
        if objectives {
            self.vec_k.fill(0.0);
            if self.options.manipulability_gain > 0.0 {
                let h = 1e-6;
                self.xp.copy_from_slice(x);
                for c in 0..k {
                    let i = 7 + self.active[c];
                    self.xp[i] = x[i] + h;
                    let up = self.manipulability(model, data, body, offset)?;
                    self.xp[i] = x[i] - h;
                    let down = self.manipulability(model, data, body, offset)?;
                    self.xp[i] = x[i];
                    self.vec_k[c] += self.options.manipulability_gain * (up - down) / (2.0 * h);
                }
            }
            if self.options.joint_limit_gain > 0.0 {
                for (c, &d) in self.active.iter().enumerate() {
                    let lim = model.links()[model.body_of_dof(d) - 1].joint.limits;
                    if lim.lower.is_finite() && lim.upper.is_finite() && lim.upper > lim.lower {
                        let range = lim.upper - lim.lower;
                        let mid = 0.5 * (lim.upper + lim.lower);
                        self.vec_k[c] -= self.options.joint_limit_gain * (x[7 + d] - mid) / (range * range);
                    }
                }
            }
            self.null.mul_to(&self.vec_k, &mut self.vec_k2);
            self.qd += &self.vec_k2;
        }
        // 4. Rate caps: first shorten the null-space part (largest α ∈ [0, 1] with
        // |q̇₁ + α q̇ₙ| within the caps), which keeps the task; if the task alone is too fast,
        // scale it down as a whole (direction kept).
        let mut alpha: f64 = 1.0;
        let mut scale: f64 = 1.0;
        for c in 0..k {
            let vmax = self.caps[c];
            if !vmax.is_finite() {
                continue;
            }
            let p = self.primary[c];
            if p.abs() > vmax {
                scale = scale.min(vmax / p.abs());
            }
            let d = self.qd[c] - p;
            if (p + d).abs() > vmax && d != 0.0 {
                // |p + α d| ≤ vmax on the side d pushes towards.
                let bound = if d > 0.0 { (vmax - p) / d } else { (-vmax - p) / d };
                alpha = alpha.min(bound.max(0.0));
            }
        }
        if scale < 1.0 {
            for c in 0..k {
                self.qd[c] = self.primary[c] * scale;
            }
        } else if alpha < 1.0 {
            for c in 0..k {
                self.qd[c] = self.primary[c] + (self.qd[c] - self.primary[c]) * alpha;
            }
        }
        let base_angular_velocity = if need_omega {
            self.omega.mul_to(&self.qd, &mut self.vec_3);
            Some(Vector3::new(self.vec_3[0], self.vec_3[1], self.vec_3[2]))
        } else {
            None
        };
        Ok(RmrcDiagnostics { sigma_min, damping_sq, base_angular_velocity })
    }

    /// Manipulability `Π σᵢ` of the task rows of `J*` over the active columns at `self.xp`.
    fn manipulability(&mut self, model: &Model, data: &mut Data, body: usize, offset: &Vector3<f64>) -> Result<f64> {
        let js = compute_generalized_jacobian(model, data, &self.xp, body, offset)?;
        for (i, &r) in self.options.task.rows().iter().enumerate() {
            for (c, &d) in self.active.iter().enumerate() {
                self.j[(i, c)] = js[(r, d)];
            }
        }
        crate::error::check_finite("task Jacobian", self.j.as_slice())?;
        self.svd.factor(&self.j);
        Ok(self.svd.product())
    }
}

