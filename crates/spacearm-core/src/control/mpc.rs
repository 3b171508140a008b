//! Receding-horizon model-predictive control as a native law ([`ModelPredictive`], spec kind
//! `mpc`; docs/mpc.md, "The native law"): at every sample instant `t_k = k·h` (`h` the law's
//! `dt`, its sample period) the optimal-control problem of [`crate::optimal`] — the same
//! [`ProblemSpec`] a one-off `spacearm.mpc.solve` reads, with the law's horizon `T` and step
//! `h` — is solved from the measured state `z(t_k) = [x; u]` by box-FDDP, and its first control
//! `c_0` is held until the next instant (sample and hold, a zero-order hold of the plan's own
//! RK4 step, so the plan's first step is the plant's next `h` seconds).
//!
//! Warm start: the previous solution shifted by the samples elapsed (`z_j ← z_{j+1}`,
//! `c_j ← c_{j+1}`, the last knot and control repeated); its first state differs from the
//! measured one by the gap `f̄_0 = z̄_0 ⊖ z_0`, which FDDP closes. The first sample is a cold
//! solve (zero controls rolled out from the state), so its control equals a one-off solve's.
//!
//! Time: knot `j` of the solve at sample `k` stands for `t = (k + j) h` of the run, whose time
//! starts at 0; a moving target (a tumbling body's grasp point, [`crate::optimal::costs::PointTarget`])
//! is evaluated at `start_time + (k + j) h` (the problem's `start_time`, default 0: the run's
//! clock), so the reference moves on with the samples.
//!
//! Samples are taken by [`Controller::sample`], which the loops call at the start of every
//! integrator step with the step's state: a sample instant must fall on a step start (RK4 with
//! a step that divides `h`); a stage past the next instant is refused (DOPRI5's steps do not land
//! on the instants). With an iteration limit only (no `time_limit`) the law is deterministic:
//! every door gives the same states bit for bit. Each sample's solve time, iterations, cost and
//! convergence are recorded ([`super::SolveReport`]).

use super::controller::{Command, ControlContext, Controller, SolveReport};
use crate::error::{Result, SpacearmError};
use crate::optimal::fddp::{solve_in, Workspace};
use crate::optimal::{ProblemSpec, RobotProblem, SolverOptions};
use crate::scenario::modes::Mode;

/// The receding-horizon law (module docs).
pub struct ModelPredictive {
    spec: ProblemSpec,
    options: SolverOptions,
    problem: Option<RobotProblem<'static>>,
    workspace: Option<Workspace>,
    /// `f[columns[i]] = c[i]` (generalized-force columns: `6..` the joints, `..6` the base wrench).
    columns: Vec<usize>,
    zs: Vec<Vec<f64>>,
    cs: Vec<Vec<f64>>,
    warm: bool,
    z: Vec<f64>,
    control: Vec<f64>,
    report: SolveReport,
    /// Index of the next sample instant, and of the last one sampled.
    next: u64,
    last: u64,
    sampled: bool,
}

impl ModelPredictive {
    /// The law of `problem` solved over `horizon` steps of `dt` seconds (its sample period),
    /// within `max_iterations` iterations and `time_limit` seconds per solve (infinity: none).
    pub fn new(problem: &ProblemSpec, horizon: usize, dt: f64, max_iterations: usize, time_limit: f64) -> Result<Self> {
        let spec = ProblemSpec { horizon, dt, ..problem.clone() };
        spec.validate()?;
        if max_iterations == 0 {
            return Err(SpacearmError::argument("mpc 'max_iterations' must be an integer >= 1"));
        }
        let options = SolverOptions { max_iterations, time_limit, ..SolverOptions::default() };
        options.validate().map_err(|e| SpacearmError::argument(format!("mpc: {e}")))?;
        Ok(ModelPredictive {
            spec,
            options,
            problem: None,
            workspace: None,
            columns: Vec::new(),
            zs: Vec::new(),
            cs: Vec::new(),
            warm: false,
            z: Vec::new(),
            control: Vec::new(),
            report: SolveReport::NONE,
            next: 0,
            last: 0,
            sampled: false,
        })
    }

    /// Solve from `(x, u)` at sample `k` and hold the first control.
    fn solve_at(&mut self, k: u64, x: &[f64], u: &[f64]) -> Result<()> {
        let (Some(problem), Some(ws)) = (self.problem.as_mut(), self.workspace.as_mut()) else {
            return Err(SpacearmError::Simulation("the mpc law was used before its setup".into()));
        };
        self.z[..x.len()].copy_from_slice(x);
        self.z[x.len()..].copy_from_slice(u);
        problem.set_initial_state(&self.z)?;
        problem.set_start_time(self.spec.start_time + k as f64 * self.spec.dt)?;
        let solution = if self.warm {
            let t = self.spec.horizon;
            let shift = (k.saturating_sub(self.last).max(1) as usize).min(t);
            let (last_z, last_c) = (self.zs[t].clone(), self.cs[t - 1].clone());
            self.zs.rotate_left(shift);
            self.cs.rotate_left(shift);
            for z in &mut self.zs[t + 1 - shift..] {
                z.copy_from_slice(&last_z);
            }
            for c in &mut self.cs[t - shift..] {
                c.copy_from_slice(&last_c);
            }
            // The knot models of the last solve's final iterate move with the guess: only the
            // knots that changed are linearized again (the same numbers, less time).
            ws.shift(shift);
            solve_in(ws, problem, Some(&self.zs), Some(&self.cs), &self.options)?
        } else {
            solve_in(ws, problem, None, None, &self.options)?
        };
        self.control.copy_from_slice(&solution.cs[0]);
        self.report = SolveReport {
            time: solution.solve_time,
            iterations: solution.iterations as f64,
            cost: solution.cost,
            converged: if solution.converged() { 1.0 } else { 0.0 },
        };
        self.zs = solution.zs;
        self.cs = solution.cs;
        self.warm = true;
        self.last = k;
        Ok(())
    }
}

impl Controller for ModelPredictive {
    fn name(&self) -> &str {
        "mpc"
    }

    fn setup(&mut self, ctx: &ControlContext<'_>) -> Result<()> {
        let mode = Mode::from_name(&self.spec.mode)?;
        if mode != ctx.mode {
            return Err(SpacearmError::argument(format!(
                "the mpc law's problem is in the '{}' mode but the simulation mode is '{}': give the problem the run's mode (its controls are that mode's)",
                mode.name(),
                ctx.mode.name()
            )));
        }
        let plant = ctx.plant;
        let mut z0 = vec![0.0; plant.nx() + plant.nu()];
        z0[6] = 1.0;
        let problem = RobotProblem::owned(plant.clone(), &self.spec, &z0)?;
        self.columns = problem.control_columns().to_vec();
        self.control = vec![0.0; self.columns.len()];
        self.z = z0;
        self.workspace = Some(Workspace::new(&problem));
        self.problem = Some(problem);
        self.warm = false;
        self.sampled = false;
        self.next = 0;
        self.report = SolveReport::NONE;
        Ok(())
    }

    /// At the start of a step: solve if `t` reached the next sample instant (module docs).
    fn sample(&mut self, t: f64, x: &[f64], u: &[f64]) -> Result<()> {
        let h = self.spec.dt;
        if self.sampled && t < self.next as f64 * h - 1e-9 * h {
            return Ok(());
        }
        let k = (t / h + 1e-9).floor().max(0.0) as u64;
        self.solve_at(k, x, u)?;
        self.next = k + 1;
        self.sampled = true;
        Ok(())
    }

    fn reports_solve(&self) -> bool {
        true
    }

    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> Result<()> {
        if !self.sampled {
            self.sample(t, x, u)?;
        }
        let h = self.spec.dt;
        let next = self.next as f64 * h;
        if t > next + 1e-6 * h {
            return Err(SpacearmError::Simulation(format!(
                "the mpc law holds each control for its dt = {h} s and samples at the start of an integrator step, but it was evaluated at t = {t} s, past its \
                 next sample instant {next} s: use the rk4 integrator with a step dt that divides the law's dt"
            )));
        }
        for (c, col) in self.control.iter().zip(&self.columns) {
            if *col >= 6 {
                out.tau[col - 6] = *c;
            } else {
                out.base_wrench[*col] = *c;
            }
        }
        out.solve = self.report;
        Ok(())
    }
}
