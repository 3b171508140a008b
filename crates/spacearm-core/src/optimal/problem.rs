//! The run description of an optimal-control problem on a robot ([`ProblemSpec`], serde data
//! read by every door) and the shooting problem it builds ([`RobotProblem`]): the mode's
//! controls ([`super::dynamics`]), the RK4 step ([`super::discretization`]), the cost terms
//! ([`super::costs`]) and the control bounds.
//!
//! The objective is `Σ_{k<T} h ℓ(z_k, c_k) + ℓ_T(z_T)`: the running terms weighted by the step
//! `h` (a rectangle rule of `∫ ℓ dt`, so weights do not depend on the number of knots), the
//! terminal terms once.

use std::borrow::Cow;

use serde::{Deserialize, Serialize};

use super::costs::{cost_derivatives, cost_value, Cost, CostSpec, CostWork, Numbers};
use super::discretization::{Discretization, DiscretizationKind};
use super::dynamics::Dynamics;
use super::shooting::{KnotModel, ShootingProblem};
use super::state::StateSpace;
use crate::error::{Result, SpacearmError};
use crate::model::Model;
use crate::scenario::modes::Mode;

fn floating() -> String {
    "floating".into()
}

fn unbounded() -> Numbers {
    Numbers::One(f64::INFINITY)
}

/// An optimal-control problem as data (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProblemSpec {
    /// The number of steps `T` (≥ 1).
    pub horizon: usize,
    /// The step `h`, s (> 0).
    pub dt: f64,
    /// The maneuvering mode (its controls: the joint torques, then the base wrench components
    /// it allows); default `"floating"`.
    #[serde(default = "floating")]
    pub mode: String,
    /// The running cost terms.
    #[serde(default)]
    pub running: Vec<CostSpec>,
    /// The terminal cost terms.
    #[serde(default)]
    pub terminal: Vec<CostSpec>,
    /// Bound on the size of every control (one or m; default: none, `inf`): `|c_i| ≤ limit_i`.
    #[serde(default = "unbounded")]
    pub control_limit: Numbers,
    /// The time of knot 0 on the references' clock, s (≥ 0; default 0): knot `k` is at
    /// `start_time + k·dt`, where a moving target is evaluated ([`super::costs::PointTarget`]).
    /// The native law adds the run's sample time ([`crate::control::mpc`]).
    #[serde(default)]
    pub start_time: f64,
    /// The knots' step: `"rk4"` (default; the simulator's step, so a solution re-simulates
    /// exactly) or `"euler"` (semi-implicit Euler: one derivative evaluation per knot, a model
    /// that differs from the RK4 plant by `O(h)`; [`super::euler`]).
    #[serde(default)]
    pub discretization: DiscretizationKind,
}

impl ProblemSpec {
    /// Check the numbers that do not need a model.
    pub fn validate(&self) -> Result<()> {
        if self.horizon == 0 {
            return Err(SpacearmError::argument("a problem's horizon must be at least 1 step"));
        }
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(SpacearmError::argument(format!("a problem's dt must be a finite positive number of seconds, got {}", self.dt)));
        }
        if !(self.start_time.is_finite() && self.start_time >= 0.0) {
            return Err(SpacearmError::argument(format!("a problem's start_time must be a finite number of seconds >= 0, got {}", self.start_time)));
        }
        Mode::from_name(&self.mode)?;
        Ok(())
    }
}

/// The shooting problem of a [`ProblemSpec`] on a model from an initial state.
pub struct RobotProblem<'a> {
    model: Cow<'a, Model>,
    /// The knots' step (RK4 or semi-implicit Euler).
    pub step: Discretization,
    running: Vec<Cost>,
    terminal: Vec<Cost>,
    work: CostWork,
    z0: Vec<f64>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    horizon: usize,
    next: Vec<f64>,
    start_time: f64,
}

impl<'a> RobotProblem<'a> {
    /// The problem of `spec` on `model` from `z0 = [x0; u0]` (checked: lengths, finite, a unit
    /// quaternion).
    pub fn new(model: &'a Model, spec: &ProblemSpec, z0: &[f64]) -> Result<Self> {
        Self::build(Cow::Borrowed(model), spec, z0)
    }

    /// The problem on a model it owns (a receding-horizon law keeps its problem, [`crate::control::mpc`]).
    pub fn owned(model: Model, spec: &ProblemSpec, z0: &[f64]) -> Result<RobotProblem<'static>> {
        RobotProblem::build(Cow::Owned(model), spec, z0)
    }

    fn build(model: Cow<'a, Model>, spec: &ProblemSpec, z0: &[f64]) -> Result<Self> {
        spec.validate()?;
        let dynamics = Dynamics::new(&model, Mode::from_name(&spec.mode)?)?;
        let m = dynamics.controls.len();
        if m == 0 {
            return Err(SpacearmError::argument("the model has no control in this mode (no joint and no base actuation)"));
        }
        let space = dynamics.space;
        check_state(space, z0)?;
        let limit = spec.control_limit.expand(m, "control_limit", true, true)?;
        if let Some(l) = limit.iter().find(|l| **l == 0.0) {
            return Err(SpacearmError::argument(format!("control_limit must be > 0, got {l}")));
        }
        let running = spec.running.iter().map(|c| c.build(&model, m, false)).collect::<Result<Vec<_>>>()?;
        let terminal = spec.terminal.iter().map(|c| c.build(&model, m, true)).collect::<Result<Vec<_>>>()?;
        if running.is_empty() && terminal.is_empty() {
            return Err(SpacearmError::argument("a problem needs at least one cost term (running or terminal)"));
        }
        let mut problem = RobotProblem {
            work: CostWork::new(&model),
            model,
            step: Discretization::new(spec.discretization, dynamics, spec.dt),
            running,
            terminal,
            z0: z0.to_vec(),
            lower: limit.iter().map(|l| -l).collect(),
            upper: limit,
            horizon: spec.horizon,
            next: vec![0.0; space.nz()],
            start_time: f64::NAN,
        };
        problem.set_start_time(spec.start_time)?;
        Ok(problem)
    }

    /// Set the time of knot 0 (s ≥ 0, the references' clock): the moving targets are evaluated
    /// at the knots' times `t₀ + k h`, `k = 0..=T` (the terminal knot's is `t₀ + T h`).
    pub fn set_start_time(&mut self, t0: f64) -> Result<()> {
        if !(t0.is_finite() && t0 >= 0.0) {
            return Err(SpacearmError::argument(format!("a problem's start time must be a finite number of seconds >= 0, got {t0}")));
        }
        if t0 == self.start_time {
            return Ok(());
        }
        let (h, knots) = (self.step.h(), self.horizon + 1);
        for cost in self.running.iter_mut().chain(self.terminal.iter_mut()) {
            cost.retime(t0, h, knots)?;
        }
        self.start_time = t0;
        Ok(())
    }

    /// Whether a cost term depends on time (a moving target).
    pub fn is_timed(&self) -> bool {
        self.running.iter().chain(&self.terminal).any(|c| c.is_timed())
    }

    /// The state's dimensions.
    pub fn space(&self) -> StateSpace {
        self.step.dynamics().space
    }

    /// The generalized-force columns the controls drive (`f[columns[i]] = c[i]`).
    pub fn control_columns(&self) -> &[usize] {
        &self.step.dynamics().controls.columns
    }

    /// Set the initial state (checked), for a receding horizon.
    pub fn set_initial_state(&mut self, z0: &[f64]) -> Result<()> {
        check_state(self.space(), z0)?;
        self.z0.copy_from_slice(z0);
        Ok(())
    }
}

/// `z = [x; u]` of the right length, finite, with a unit quaternion.
fn check_state(space: StateSpace, z: &[f64]) -> Result<()> {
    if z.len() != space.nz() {
        return Err(SpacearmError::argument(format!("the initial state [x; u] must have 7+N + 6+N = {} numbers, got {}", space.nz(), z.len())));
    }
    if let Some(i) = z.iter().position(|v| !v.is_finite()) {
        return Err(SpacearmError::argument(format!("the initial state must be finite (entry {i} is {})", z[i])));
    }
    let norm = z[3..7].iter().map(|v| v * v).sum::<f64>().sqrt();
    if (norm - 1.0).abs() > 1e-6 {
        return Err(SpacearmError::argument(format!("the initial state's quaternion x[3:7] must have norm 1, got {norm}")));
    }
    Ok(())
}

impl ShootingProblem for RobotProblem<'_> {
    fn horizon(&self) -> usize {
        self.horizon
    }
    fn nz(&self) -> usize {
        self.space().nz()
    }
    fn nd(&self) -> usize {
        self.space().nd()
    }
    fn nc(&self) -> usize {
        self.upper.len()
    }
    fn lower(&self) -> &[f64] {
        &self.lower
    }
    fn upper(&self) -> &[f64] {
        &self.upper
    }
    fn initial_state(&self) -> &[f64] {
        &self.z0
    }
    fn diff(&self, z0: &[f64], z1: &[f64], out: &mut [f64]) {
        self.space().diff(z0, z1, out)
    }
    fn integrate(&self, z: &[f64], dz: &[f64], out: &mut [f64]) {
        self.space().integrate(z, dz, out)
    }
    fn time_invariant(&self) -> bool {
        !self.is_timed()
    }
    fn project(&self, z: &mut [f64]) {
        crate::math::rotations::normalize_xyzw(&mut z[3..7]);
    }
    fn running(&mut self, k: usize, z: &[f64], c: &[f64], next: &mut [f64]) -> Result<f64> {
        self.step.step(&self.model, z, c, next)?;
        cost_value(&self.model, &mut self.work, &self.running, k, z, c, self.step.h())
    }
    fn running_derivatives(&mut self, k: usize, z: &[f64], c: &[f64], out: &mut KnotModel) -> Result<()> {
        self.step.step_derivatives(&self.model, z, c, &mut self.next, &mut out.a, &mut out.b)?;
        out.clear_cost();
        cost_derivatives(&self.model, &mut self.work, &self.running, k, z, c, self.step.h(), &mut out.lz, &mut out.lc, &mut out.lzz, &mut out.lcc)?;
        Ok(())
    }
    /// One RK4 pass with its Jacobians gives the step end (the derivative routine's
    /// acceleration, equal to ABA's to rounding) and the cost terms their value with their
    /// derivatives.
    fn running_with_derivatives(&mut self, k: usize, z: &[f64], c: &[f64], next: &mut [f64], out: &mut KnotModel) -> Result<f64> {
        self.step.step_derivatives(&self.model, z, c, next, &mut out.a, &mut out.b)?;
        out.clear_cost();
        cost_derivatives(&self.model, &mut self.work, &self.running, k, z, c, self.step.h(), &mut out.lz, &mut out.lc, &mut out.lzz, &mut out.lcc)
    }
    fn terminal(&mut self, z: &[f64]) -> Result<f64> {
        cost_value(&self.model, &mut self.work, &self.terminal, self.horizon, z, &[], 1.0)
    }
    fn terminal_derivatives(&mut self, z: &[f64], out: &mut KnotModel) -> Result<()> {
        out.clear_cost();
        cost_derivatives(&self.model, &mut self.work, &self.terminal, self.horizon, z, &[], 1.0, &mut out.lz, &mut out.lc, &mut out.lzz, &mut out.lcc)?;
        Ok(())
    }
}
