//! The simulation loop: integrate `y = [x; u]` under a controller in a maneuvering mode, with
//! actuator limits, recording every quantity into buffers allocated before the first step.
//!
//! Per right-hand-side evaluation (every integrator stage): the controller's [`Command`](crate::control::Command) →
//! joint motor limits → the mode's base-wrench mask → thruster limits → the wrench at the base
//! CM (through the system CM in translation-flying) → forward dynamics by the articulated-body
//! algorithm with `f = [F0; N0; τ]` → `ẏ = [v0; ½ [ω0; 0] ⊗ quat; q̇; u̇]`.
//!
//! Recorded per sample: the state, `u̇`, applied and commanded torques, the applied base
//! wrench, `P`, `L_origin`, `L_com`, mechanical energy (kinetic plus the joint springs'), system CM, end-effector pose, the
//! controller's reference and tracking error, wheel speeds. Saturation events mark the accepted
//! step in which an actuator starts saturating (its onset; the per-sample `tau` against
//! `tau_cmd` shows how long it lasts). The drift of each conserved quantity is its largest
//! deviation from the initial value over the recorded samples, relative to
//! `max(|initial|, scale)` with the scale the largest over the samples of the sum of the
//! magnitudes of the bodies' contributions (`Σ mᵢ|vᵢ|` for `P`, `Σ |rᵢ × mᵢvᵢ| + |Iᵢωᵢ|` about
//! the point for `L`, the energy itself for the energy): the size of the terms whose
//! cancellation the conservation is.

use crate::algorithms::kinematics::{check_velocity, split_configuration};
use crate::control::Controller;
use crate::error::{Result, SpacearmError};
use crate::model::Model;
use crate::math::integrate::{Dopri5, IntegratorKind, OdeSystem, Rk4, StepOutcome};
use crate::sim::events::{locate_root, StopWatch};
use crate::sim::stop::StopEvent;
use crate::sim::record::{onsets, Recorder};
use crate::sim::stepper::Rk4Stepper;

// The run's types in their own files, at their former paths too (`sim::simulate::SimOptions`, ...).
pub use crate::sim::options::{OrbitOptions, SimOptions, DEFAULT_MAX_STEPS};
pub use crate::sim::plant::Plant;
pub use crate::sim::record::admit_records;
pub(crate) use crate::sim::record::finish_result;
pub use crate::sim::result::{Records, SaturationEvent, SimResult};

/// Reports progress as a fraction of the simulated time, at most ~1000 times per run; an error
/// it returns (an interrupted run) stops the simulation.
pub type Progress<'a> = &'a mut dyn FnMut(f64) -> Result<()>;

/// Simulate `model` from `(x0, u0)` for `opts.duration` seconds under `controller`.
///
/// `x0` must be a valid configuration (unit quaternion within
/// [`crate::math::rotations::QUATERNION_TOLERANCE`]; it is normalized exactly); `u0` any finite
/// velocity (non-zero momentum is allowed). Deterministic: the same inputs give bit-identical
/// records.
pub fn simulate(model: &Model, x0: &[f64], u0: &[f64], opts: &SimOptions, controller: &mut dyn Controller, progress: Progress<'_>) -> Result<SimResult> {
    opts.validate()?;
    check_initial_state(model, x0, u0)?;
    let plant = Plant::new(model, opts, controller)?;
    run_plant(plant, x0, u0, opts, progress)
}

/// [`simulate`] with a free target in the loop (docs/contact.md, "Contact with a free target";
/// [`crate::sim::free_target`]): `target` (one rigid body with collision shapes) at the 13-state
/// `target_state` (`[r, quat xyzw, v, ω]`, the topology events' convention), integrated with the
/// robot and touching it by `opts.contact` (required). The records add `target_state`,
/// `ledger_momentum` and `ledger_energy`; the drifts are robot + target's.
#[allow(clippy::too_many_arguments)]
pub fn simulate_with_target(
    model: &Model,
    x0: &[f64],
    u0: &[f64],
    opts: &SimOptions,
    controller: &mut dyn Controller,
    target: &Model,
    target_state: &[f64],
    progress: Progress<'_>,
) -> Result<SimResult> {
    opts.validate()?;
    check_initial_state(model, x0, u0)?;
    let plant = Plant::with_target(model, opts, controller, target, target_state)?;
    run_plant(plant, x0, u0, opts, progress)
}

/// Run a plant set up for `opts` from `(x0, u0)` (checked by the caller): admission of the
/// records, then the RK4 or DOPRI5 loop.
///
/// Stop conditions ([`crate::sim::events`]): a time condition within the duration makes the run
/// the run of that duration (its last step lands on it); gap and record conditions are watched at every
/// step end and located within the step.
pub(crate) fn run_plant(plant: Plant<'_>, x0: &[f64], u0: &[f64], opts: &SimOptions, progress: Progress<'_>) -> Result<SimResult> {
    let watch = StopWatch::new(&opts.stop, opts.duration, &plant)?;
    let end = watch.end(opts.duration);
    let cut;
    let opts = if end < opts.duration {
        cut = SimOptions { duration: end, ..opts.clone() };
        &cut
    } else {
        opts
    };
    let samples = sample_count(opts) as f64;
    admit_records(opts.integrator, samples, samples * Recorder::values_per_sample_of(&plant) as f64)?;
    let watched = watch.has_watched().then_some(&watch);
    let mut result = match opts.integrator {
        IntegratorKind::Rk4 => simulate_rk4(plant, x0, u0, opts, watched, progress)?,
        IntegratorKind::Dopri5 => simulate_dopri5(plant, x0, u0, opts, watched, progress)?,
    };
    if result.stop.is_none() {
        result.stop = watch.time.map(|(condition, t)| StopEvent { condition, t, value: t });
    }
    check_divergence(&result)?;
    Ok(result)
}

/// Check an initial state against `model`: `x0` of length 7+N with a unit quaternion, `u0` of
/// length 6+N, all finite.
pub fn check_initial_state(model: &Model, x0: &[f64], u0: &[f64]) -> Result<()> {
    crate::error::check_vector("x0", x0, model.nx()).map_err(|e| match e {
        SpacearmError::Dimension { got, .. } => SpacearmError::Dimension { what: "x0".into(), expected: format!("7+N = {}", model.nx()), got },
        other => other,
    })?;
    split_configuration(model, x0)?;
    check_velocity(model, "u0", u0)
}

/// Number of RK4 steps of a run: steps at `t_i = i·dt` up to the duration (the last one may be
/// shorter); also the number of DOPRI5 output intervals.
pub fn rk4_step_count(opts: &SimOptions) -> usize {
    ((opts.duration / opts.dt) * (1.0 - 1e-12)).ceil().max(1.0) as usize
}

/// Number of samples a run records: RK4 every `record_every` steps plus the end; DOPRI5 every
/// `dt` plus the end. Every run of the same options records exactly this many.
pub fn sample_count(opts: &SimOptions) -> usize {
    let n = rk4_step_count(opts);
    match opts.integrator {
        IntegratorKind::Rk4 => n.div_ceil(opts.record_every) + 1,
        IntegratorKind::Dopri5 => n + 1,
    }
}

/// The RK4 loop: steps at `t_i = i·dt` (computed by multiplication, not accumulation), the last
/// one landing on the duration. With gap and record conditions (`watched`), `f` is evaluated at every step's
/// end for their values, and the step in which one first holds is re-taken from its start with
/// shorter steps to locate the event ([`crate::sim::events`]); the run ends there.
fn simulate_rk4(plant: Plant<'_>, x0: &[f64], u0: &[f64], opts: &SimOptions, watched: Option<&StopWatch>, progress: Progress<'_>) -> Result<SimResult> {
    let n_steps = rk4_step_count(opts);
    let mut stepper = Rk4Stepper::new(plant, x0, u0, Some((sample_count(opts), opts.record_every)))?;
    // A step longer than the fastest mode allows is refused before the first step.
    let y0 = stepper.full_state().to_vec();
    crate::sim::step_limit::check_rk4_step(stepper.plant_mut(), 0.0, &y0, opts.dt.min(opts.duration))?;
    let progress_every = opts.duration / 1000.0;
    let mut next_progress = 0.0;
    // The event watch's workspaces: the state at the step's start, a stage, f, an RK4 for re-taking it.
    let dim = y0.len();
    let (mut y_prev, mut y_try, mut dy) = (y0.clone(), vec![0.0; dim], vec![0.0; dim]);
    let mut rk = Rk4::new(dim);
    let mut stop = None;
    let mut g_prev = vec![0.0; opts.stop.len()];
    if let Some(w) = watched {
        stepper.plant_mut().rhs(0.0, &y0, &mut dy)?;
        if let Some((condition, _, quantity)) = w.holding(stepper.plant_mut(), &y0) {
            stop = Some(StopEvent { condition, t: 0.0, value: quantity });
        }
        w.values_into(stepper.plant_mut(), &y0, &mut g_prev);
    }
    let mut t_prev = 0.0;
    for i in 0..n_steps {
        if stop.is_some() {
            break;
        }
        let t_next = if i + 1 == n_steps { opts.duration } else { (i + 1) as f64 * opts.dt };
        if watched.is_some() {
            y_prev.copy_from_slice(stepper.full_state());
        }
        stepper.step_to(t_next)?;
        if let Some(w) = watched {
            y_try.copy_from_slice(stepper.full_state());
            let plant = stepper.plant_mut();
            plant.rhs(t_next, &y_try, &mut dy)?;
            let g_start = g_prev.clone();
            w.values_into(plant, &y_try, &mut g_prev);
            let mut found: Option<(usize, f64, f64)> = None;
            for condition in w.watched_conditions() {
                if g_prev[condition] > 0.0 {
                    continue;
                }
                // g(t_prev) > 0: no condition held at the previous step's end.
                let mut g_at = |t: f64| -> Result<f64> {
                    rk.step_from(&mut *plant, t_prev, &y_prev, t, &mut y_try)?;
                    plant.rhs(t, &y_try, &mut dy)?;
                    Ok(w.value(plant, &y_try, condition))
                };
                let (t_s, g_s) = locate_root(&mut g_at, (t_prev, g_start[condition]), (t_next, g_prev[condition]))?;
                if found.is_none_or(|f| t_s < f.1) {
                    found = Some((condition, t_s, g_s));
                }
            }
            if let Some((condition, t_s, g_s)) = found {
                stepper.land_retaken(&mut rk, (t_prev, &y_prev), t_s, t_next, &mut y_try)?;
                stop = Some(StopEvent { condition, t: t_s, value: w.quantity(condition, g_s) });
            }
        }
        if t_next >= next_progress {
            progress(t_next / opts.duration)?;
            next_progress = t_next + progress_every;
        }
        t_prev = t_next;
    }
    let mut result = stepper.finish()?;
    result.stop = stop;
    progress(1.0)?;
    Ok(result)
}

/// The DOPRI5 run of one plant: [`dopri5_loop`] over the plant, its recorder recording.
fn simulate_dopri5(mut plant: Plant<'_>, x0: &[f64], u0: &[f64], opts: &SimOptions, watched: Option<&StopWatch>, progress: Progress<'_>) -> Result<SimResult> {
    // With contact the state has one more entry, the contact work (0 at the start).
    let mut y: Vec<f64> = plant.initial_state(x0, u0);
    plant.project(&mut y);
    let mut rec = Recorder::for_plant(&plant, sample_count(opts));
    let words = DopriWords {
        of_run: "",
        budget_remedy: " (loosen rtol/atol, raise max_steps, or use rk4)",
        stiff_remedy: "the dynamics are too stiff or discontinuous there (a saturating actuator switching, a very high gain); loosen \
                       rtol/atol or use rk4",
    };
    let run = dopri5_loop(&mut plant, &mut y, opts, &words, watched, &mut *progress, &mut |p, t, y, dy| rec.record(p, t, y, dy))?;
    progress(1.0)?;
    let mut result = finish_result(&plant, rec, run.events, run.n_steps, run.n_rejected);
    result.stop = run.stop;
    Ok(result)
}

/// What [`dopri5_loop`] watches of a system besides its ODE: the actuator saturation flags of
/// the current step and whether a stage left the finite numbers, both of the plant whose
/// actuators the run reports ([`Plant`] itself; the robot's plant of a soft capture).
pub(crate) trait StepWatch: OdeSystem {
    /// Clear the step's saturation flags (before a step is tried).
    fn clear_step_flags(&mut self);
    /// The saturation bits OR-ed over the step's evaluations.
    fn step_flags(&self) -> &[u8];
    /// Whether a stage value of the last step was not finite; clears the mark.
    fn take_nonfinite_stage(&mut self) -> bool;
    /// The plant whose evaluation the stop conditions read ([`crate::sim::events`]).
    fn watched_plant(&self) -> &Plant<'_>;
    /// The part of the system's state `y` that is the watched plant's.
    fn watched_state<'y>(&self, y: &'y [f64]) -> &'y [f64];
    /// Before a step (tried) from `(t, y)`: a sampled controller's sample ([`Plant::sample`]).
    fn begin_step(&mut self, t: f64, y: &[f64]) -> Result<()>;
}

impl StepWatch for Plant<'_> {
    fn clear_step_flags(&mut self) {
        self.flags_step.fill(0);
    }

    fn step_flags(&self) -> &[u8] {
        &self.flags_step
    }

    fn take_nonfinite_stage(&mut self) -> bool {
        std::mem::take(&mut self.nonfinite_stage)
    }

    fn watched_plant(&self) -> &Plant<'_> {
        self
    }

    fn watched_state<'y>(&self, y: &'y [f64]) -> &'y [f64] {
        y
    }

    fn begin_step(&mut self, t: f64, y: &[f64]) -> Result<()> {
        self.sample(t, y)
    }
}

/// How a DOPRI5 run's errors name it: ``"DOPRI5 used its budget of … s{of_run}{budget_remedy}"``
/// and ``"DOPRI5 step size fell to … s{of_run}: {stiff_remedy}"``.
pub(crate) struct DopriWords {
    pub of_run: &'static str,
    pub budget_remedy: &'static str,
    pub stiff_remedy: &'static str,
}

/// The counters, saturation onsets and stop event of a DOPRI5 run.
pub(crate) struct DopriRun {
    pub n_steps: usize,
    pub n_rejected: usize,
    pub events: Vec<SaturationEvent>,
    pub stop: Option<StopEvent>,
}

/// The one DOPRI5 loop (docs/simulation-core.md): adaptive steps over `sys` from `y` (projected
/// by the caller) at t = 0 to `opts.duration`, a trial step whose stages left the finite numbers
/// retried a quarter as long, samples at `t_k = k·dt` (the last on the duration) by dense output,
/// each handed to `record` with `f(t_k, y_k)` evaluated there; `y` ends at the duration. Used by
/// [`simulate`] (one plant) and [`crate::sim::soft_capture`] (robot + target); the caller reports
/// `progress(1.0)` when it has finished.
///
/// With gap and record conditions (`watched`), their values are read at every accepted step's end from the
/// last stage's evaluation (at the new point: first same as last) and at every sample's
/// evaluation; at the first of these where one holds, the event is located on the dense output ([`crate::sim::events`]), the samples before
/// it are recorded, the last sample is the event's and `y` ends there.
pub(crate) fn dopri5_loop<S: StepWatch>(
    sys: &mut S,
    y: &mut [f64],
    opts: &SimOptions,
    words: &DopriWords,
    watched: Option<&StopWatch>,
    progress: Progress<'_>,
    record: &mut dyn FnMut(&S, f64, &[f64], &[f64]),
) -> Result<DopriRun> {
    let dim = y.len();
    let mut events = Vec::new();
    let mut prev_flags = vec![0u8; sys.step_flags().len()];
    let mut dy = vec![0.0; dim];
    let (mut n_steps, mut n_rejected) = (0usize, 0usize);
    let progress_every = opts.duration / 1000.0;
    let mut next_progress = 0.0;
    let mut dp = Dopri5::new(dim, opts.rtol, opts.atol);
    sys.begin_step(0.0, y)?;
    sys.rhs(0.0, y, &mut dy)?;
    record(sys, 0.0, y, &dy);
    if let Some((condition, _, quantity)) = watched.and_then(|w| w.holding(sys.watched_plant(), sys.watched_state(y))) {
        return Ok(DopriRun { n_steps, n_rejected, events, stop: Some(StopEvent { condition, t: 0.0, value: quantity }) });
    }
    let mut g_prev = vec![0.0; opts.stop.len()];
    let (mut g_end, mut g_sample) = (g_prev.clone(), g_prev.clone());
    if let Some(w) = watched {
        w.values_into(sys.watched_plant(), sys.watched_state(y), &mut g_prev);
    }
    let mut y_try = vec![0.0; dim];
    let n_out = rk4_step_count(opts);
    let mut k_out = 1;
    let out_time = |k: usize| if k == n_out { opts.duration } else { k as f64 * opts.dt };
    let mut t = 0.0;
    let mut h = dp.initial_step(sys, t, y, opts.duration)?;
    let mut y_out = vec![0.0; dim];
    while t < opts.duration {
        if n_steps + n_rejected >= opts.max_steps {
            return Err(SpacearmError::Simulation(format!(
                "DOPRI5 used its budget of {} steps and reached only t = {t} s of {} s{}{}",
                opts.max_steps, opts.duration, words.of_run, words.budget_remedy
            )));
        }
        let remaining = opts.duration - t;
        // Land exactly on the end; avoid a sliver of a last step.
        if h >= remaining || remaining - h < 1e-10 * opts.duration {
            h = remaining;
        }
        sys.clear_step_flags();
        sys.begin_step(t, y)?;
        let outcome = match dp.try_step(sys, t, h, y) {
            Ok(o) => o,
            // A trial step so long that a stage left the finite numbers: reject it and
            // retry shorter (y and f(t, y) are untouched by a failed attempt).
            Err(SpacearmError::Simulation(_)) if sys.take_nonfinite_stage() => StepOutcome { accepted: false, error: f64::INFINITY, next_h: 0.25 * h },
            Err(e) => return Err(e),
        };
        if outcome.accepted {
            n_steps += 1;
            onsets(t, &mut prev_flags, sys.step_flags(), &mut events);
            let t_new = if h == remaining { opts.duration } else { t + h };
            // Stop conditions: their values at the step's end (the last stage evaluated f
            // there), then at each sample in the step (evaluated for the record anyway) and
            // the end, in time order; the first point where one holds brackets the event with
            // the last point where none did.
            let mut stop: Option<StopEvent> = None;
            if let Some(w) = watched {
                w.values_into(sys.watched_plant(), sys.watched_state(y), &mut g_end);
            }
            let mut t_a = t;
            while k_out <= n_out && out_time(k_out) <= t_new {
                let t_o = out_time(k_out);
                if t_o == t_new {
                    y_out.copy_from_slice(y);
                } else {
                    dp.dense_output(t_o, &mut y_out);
                    sys.project(&mut y_out);
                }
                sys.rhs(t_o, &y_out, &mut dy)?;
                if let Some(w) = watched {
                    w.values_into(sys.watched_plant(), sys.watched_state(&y_out), &mut g_sample);
                    if w.any_holds(&g_sample) {
                        stop = locate_on_dense_output(sys, &dp, w, (t_a, &g_prev), (t_o, &g_sample), &mut y_try, &mut dy)?;
                        break;
                    }
                    t_a = t_o;
                    g_prev.copy_from_slice(&g_sample);
                }
                record(sys, t_o, &y_out, &dy);
                k_out += 1;
                // A dense output grid can put many samples in one step: report (and let
                // the caller interrupt) between them too.
                if t_o >= next_progress {
                    progress(t_o / opts.duration)?;
                    next_progress = t_o + progress_every;
                }
            }
            if let (None, Some(w)) = (stop, watched) {
                if t_a < t_new && w.any_holds(&g_end) {
                    stop = locate_on_dense_output(sys, &dp, w, (t_a, &g_prev), (t_new, &g_end), &mut y_try, &mut dy)?;
                } else {
                    g_prev.copy_from_slice(&g_end);
                }
            }
            if let Some(s) = stop {
                // The last sample: the state at the event.
                if s.t < t_new {
                    dp.dense_output(s.t, &mut y_try);
                    sys.project(&mut y_try);
                    y.copy_from_slice(&y_try);
                }
                sys.rhs(s.t, y, &mut dy)?;
                record(sys, s.t, y, &dy);
                return Ok(DopriRun { n_steps, n_rejected, events, stop });
            }
            t = t_new;
            if t >= next_progress {
                progress(t / opts.duration)?;
                next_progress = t + progress_every;
            }
        } else {
            n_rejected += 1;
        }
        h = outcome.next_h;
        if !(h.is_finite() && h > 1e-14 * t.abs().max(opts.duration)) {
            return Err(SpacearmError::Simulation(format!("DOPRI5 step size fell to {h:e} s at t = {t} s{}: {}", words.of_run, words.stiff_remedy)));
        }
    }
    Ok(DopriRun { n_steps, n_rejected, events, stop: None })
}

/// The earliest event of the watched conditions that hold at `b` (values `gb`), none holding at `a`
/// (values `ga`): each located on the last step's dense output, projected
/// ([`crate::sim::events`]).
fn locate_on_dense_output<S: StepWatch>(
    sys: &mut S,
    dp: &Dopri5,
    w: &StopWatch,
    (a, ga): (f64, &[f64]),
    (b, gb): (f64, &[f64]),
    y_try: &mut [f64],
    dy: &mut [f64],
) -> Result<Option<StopEvent>> {
    let mut stop: Option<StopEvent> = None;
    for condition in w.watched_conditions() {
        if gb[condition] > 0.0 {
            continue;
        }
        let mut g_at = |tc: f64| -> Result<f64> {
            dp.dense_output(tc, y_try);
            sys.project(y_try);
            sys.rhs(tc, y_try, dy)?;
            Ok(w.value(sys.watched_plant(), sys.watched_state(y_try), condition))
        };
        let (t_s, g_s) = locate_root(&mut g_at, (a, ga[condition]), (b, gb[condition]))?;
        if stop.is_none_or(|s| t_s < s.t) {
            stop = Some(StopEvent { condition, t: t_s, value: w.quantity(condition, g_s) });
        }
    }
    Ok(stop)
}

/// The largest relative drift of a conserved quantity that a run may show and still be returned
/// (docs/simulation-core.md, "Errors"): beyond it the integration has lost the motion (a step far
/// longer than the fastest mode allows), whatever the records look like.
pub const DIVERGED_DRIFT: f64 = 0.1;

/// A run whose conserved quantities drifted beyond [`DIVERGED_DRIFT`] (or overflowed to a
/// non-finite value) diverged: a `SimulationError`, not a normal-looking result.
fn check_divergence(result: &SimResult) -> Result<()> {
    for (c, d) in &result.drift {
        if !(d.is_finite() && *d <= DIVERGED_DRIFT) {
            return Err(SpacearmError::Simulation(format!(
                "the run diverged: the {} drifted by {} (relative; a conserved quantity may drift by at most {DIVERGED_DRIFT}) — \
                 the step is too long for the motion: reduce dt, or use integrator='dopri5'",
                c.name(),
                if d.is_finite() { format!("{d:.3e}") } else { "a non-finite amount".to_string() }
            )));
        }
    }
    Ok(())
}
