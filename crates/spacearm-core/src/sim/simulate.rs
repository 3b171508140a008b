//! The simulation loop: integrate `y = [x; u]` under a controller in a maneuvering mode, with
//! actuator limits, recording every quantity into buffers allocated before the first step.
//!
//! Per right-hand-side evaluation (every integrator stage): the controller's [`Command`] →
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

use std::borrow::Cow;

use nalgebra::{Vector3, Vector6};

use crate::algorithms::aba::{aba_after_kinematics, aba_with_wrenches_after_kinematics};
use crate::algorithms::wrench::ExternalWrench;
use crate::algorithms::kinematics::{check_velocity, forward_kinematics, split_configuration};
use crate::algorithms::momentum::center_of_mass_from_data;
use crate::control::{arm_dofs, Command, ControlContext, Controller, TrackingKind};
use crate::error::{Result, SpacearmError};
use crate::math::rotations::quaternion_rate;
use crate::model::data::Data;
use crate::model::Model;
use crate::sim::actuators::{check_wheels, detect_reaction_wheels, Actuators, SaturationKind, ThrusterLimits};
use crate::sim::events::{locate_root, StopCondition, StopEvent, StopWatch};
use crate::sim::integrate::{Dopri5, IntegratorKind, OdeSystem, Rk4, StepOutcome};
use crate::sim::modes::{Conserved, Mode};
use crate::sim::orbit::{gravity_gradient_tensor, tidal_wrenches_into, Orbit, OrbitTrack};
use crate::sim::record::{onsets, Recorder};
use crate::sim::stepper::Rk4Stepper;

/// Options of a simulation.
#[derive(Debug, Clone, PartialEq)]
pub struct SimOptions {
    /// Maneuvering mode.
    pub mode: Mode,
    /// Integrator.
    pub integrator: IntegratorKind,
    /// Simulated time, s (> 0).
    pub duration: f64,
    /// RK4: the step; DOPRI5: the output (recording) interval. s, > 0.
    pub dt: f64,
    /// DOPRI5 relative tolerance (> 0).
    pub rtol: f64,
    /// DOPRI5 absolute tolerance (≥ 0).
    pub atol: f64,
    /// RK4: keep every k-th step (≥ 1); the final state is always kept.
    pub record_every: usize,
    /// Wheel degrees of freedom; `None`: [`detect_reaction_wheels`].
    pub wheels: Option<Vec<usize>>,
    /// Thruster limits (flying modes); `None`: unlimited.
    pub thrusters: Option<ThrusterLimits>,
    /// Whether the joints' effort and velocity limits apply (they always do to nothing else).
    pub joint_limits: bool,
    /// Largest number of attempted steps (DOPRI5) before giving up.
    pub max_steps: usize,
    /// The orbit of the run ([`OrbitOptions`]); `None`: empty, inertial space.
    pub orbit: Option<OrbitOptions>,
    /// Conditions that stop the run before its duration, the first to hold wins
    /// ([`crate::sim::events`]; [`SimResult::stop`] says which and when); empty: none. Honoured
    /// by [`simulate`] (both integrators); the entry points that stack equal-length runs or step
    /// a plant refuse them ([`SimOptions::refuse_stop`]).
    pub stop: Vec<StopCondition>,
}

/// A run in orbit (docs/orbit.md): the origin of 𝒥 is the orbit's point `O`, propagated on its
/// own (point mass, two-body + J2, [`OrbitTrack`]), with 𝒥's axes those of ECI; the states stay
/// relative to `O`. With `gravity_gradient`, every body feels the tidal force `mᵢ G ρᵢ` at its CM
/// (`ρᵢ` its CM from `O`) and the torque `axial(Iᵢ G − G Iᵢ)` about it, `G` the gradient at `O`
/// ([`crate::sim::orbit`]); the uniform part of gravity moves `O` and with it everything. The
/// conserved quantities of the mode are then monitored as balances: the change of each equals
/// the integral of the tidal wrenches (trapezoid over the samples), the energy is dropped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitOptions {
    /// The orbit of `O` (at `t = 0`).
    pub orbit: Orbit,
    /// Whether the tidal wrenches act on the bodies.
    pub gravity_gradient: bool,
}

/// The default step budget of a DOPRI5 run ([`SimOptions::max_steps`], accepted and rejected
/// steps): spent, the run stops with a `SimulationError` naming the time reached and the
/// budget. About two minutes of spatial6 (a run of 10⁶ s at rtol 1e-12 reaches t = 1.2·10⁴ s).
pub const DEFAULT_MAX_STEPS: usize = 10_000_000;

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            mode: Mode::Floating,
            integrator: IntegratorKind::Rk4,
            duration: 1.0,
            dt: 1e-3,
            rtol: 1e-9,
            atol: 1e-12,
            record_every: 1,
            wheels: None,
            thrusters: None,
            joint_limits: true,
            max_steps: DEFAULT_MAX_STEPS,
            orbit: None,
            stop: Vec::new(),
        }
    }
}

impl SimOptions {
    /// Check every value (positive duration and step, tolerances, counts).
    pub fn validate(&self) -> Result<()> {
        let arg = |msg: String| Err(SpacearmError::argument(msg));
        if !(self.duration.is_finite() && self.duration > 0.0) {
            return arg(format!("duration must be finite and > 0 s, got {}", self.duration));
        }
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return arg(format!("dt must be finite and > 0 s, got {}", self.dt));
        }
        if self.duration / self.dt > 1e9 {
            return arg(format!("duration / dt = {:e} steps or samples is more than the 1e9 allowed", self.duration / self.dt));
        }
        if !(self.rtol.is_finite() && self.rtol > 0.0) {
            return arg(format!("rtol must be finite and > 0, got {}", self.rtol));
        }
        if !(self.atol.is_finite() && self.atol >= 0.0) {
            return arg(format!("atol must be finite and >= 0, got {}", self.atol));
        }
        if self.record_every == 0 {
            return arg("record_every must be >= 1".into());
        }
        if self.max_steps == 0 {
            return arg("max_steps must be >= 1".into());
        }
        crate::sim::events::validate(&self.stop)
    }

    /// Refuse stop conditions where `entry` (a run that is not [`simulate`]'s) cannot honour them.
    pub fn refuse_stop(&self, entry: &str) -> Result<()> {
        if self.stop.is_empty() {
            return Ok(());
        }
        Err(SpacearmError::argument(format!(
            "{entry} does not take stop conditions (a run that stops early has its own length): use simulate for a run with stop="
        )))
    }
}

/// A saturation onset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SaturationEvent {
    /// Start time of the step in which the actuator started saturating, s.
    pub t: f64,
    /// Actuator index: dof `0..N`, then the six thruster channels `N..N+6`.
    pub actuator: usize,
    /// Which limit it reached.
    pub kind: SaturationKind,
}

/// Recorded samples, each field row-major with one row per sample.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Records {
    /// Number of samples (rows).
    pub n_samples: usize,
    /// Sample times, s.
    pub t: Vec<f64>,
    /// Configurations `x = [r0, quat0, q]` (width `7 + N`).
    pub x: Vec<f64>,
    /// Generalized velocities `u = [v0, ω0, q̇]` (width `6 + N`).
    pub u: Vec<f64>,
    /// Generalized accelerations `u̇` (width `6 + N`).
    pub du: Vec<f64>,
    /// Joint torques applied, after the actuator limits (width `N`).
    pub tau: Vec<f64>,
    /// Joint torques commanded by the controller, before the limits (width `N`).
    pub tau_cmd: Vec<f64>,
    /// Base wrench `[F0; N0]` applied, in 𝒥 at the base CM (width 6).
    pub base_wrench: Vec<f64>,
    /// Linear momentum `P`, N·s (width 3).
    pub linear_momentum: Vec<f64>,
    /// Angular momentum about the origin of 𝒥, N·m·s (width 3).
    pub angular_momentum_origin: Vec<f64>,
    /// Angular momentum about the system CM, N·m·s (width 3).
    pub angular_momentum_com: Vec<f64>,
    /// Mechanical energy: kinetic energy plus the joint springs' potential energy, J (width 1).
    pub energy: Vec<f64>,
    /// System CM in 𝒥, m (width 3).
    pub com: Vec<f64>,
    /// End-effector position (if the model has an end effector).
    pub ee_position: Option<Vec<f64>>,
    /// End-effector body orientation `[x, y, z, w]`, sign kept continuous.
    pub ee_quat: Option<Vec<f64>>,
    /// Controller reference (width [`SimResult::reference_width`]).
    pub reference: Option<Vec<f64>>,
    /// The controller's tracking error (see [`SimResult::tracking`]), if it reports one.
    pub tracking_error: Option<Vec<f64>>,
    /// With a joint-space tracking controller on a plant with compliant joints: the error of the
    /// links, `|q_ref − (θ + δ)|` over the same joints, the compliant joints' deflection `δ`
    /// added to their motor angle `θ` ([`crate::model::appendage::compliant_pairs`]; a rigid
    /// joint's link angle is its own); the motor's is [`Self::tracking_error`]. `None` otherwise
    /// (no compliant joint tracked, or a Cartesian controller, whose point already moves with the
    /// links).
    pub link_tracking_error: Option<Vec<f64>>,
    /// The controller's base attitude error angle, rad, if it reports one.
    pub attitude_error: Option<Vec<f64>>,
    /// Wheel rates relative to the base, rad/s.
    pub wheel_speed: Option<Vec<f64>>,
    /// An orbital run's system CM in ECI, `r_O + r_g`, m (width 3).
    pub r_cm_eci: Option<Vec<f64>>,
    /// An orbital run's system CM velocity in ECI, `v_O + P/M`, m/s (width 3).
    pub v_cm_eci: Option<Vec<f64>>,
    /// An orbital run's total tidal wrench `[Σ fᵢ; Σ (ρᵢ × fᵢ + Nᵢ)]` (the torque about `O`),
    /// N and N·m (width 6; zeros without the gravity gradient).
    pub gravity_wrench: Option<Vec<f64>>,
    /// A closed chain's constraint wrench `λ` on frame b at its origin, `[force; torque]` in 𝒥
    /// (width 6; [`crate::sim::closed_chain`]).
    pub constraint_wrench: Option<Vec<f64>>,
    /// A closed chain's pose error `e = [position (m); rotation (rad)]` (width 6).
    pub constraint_error: Option<Vec<f64>>,
}

/// Everything a simulation returns.
#[derive(Debug, Clone)]
pub struct SimResult {
    /// The recorded samples.
    pub records: Records,
    /// Number of reference values per sample in [`Records::reference`].
    pub reference_width: usize,
    /// Saturation onsets, in time order.
    pub events: Vec<SaturationEvent>,
    /// Quantities the mode conserves, with their drift.
    pub drift: Vec<(Conserved, f64)>,
    /// The scale each drift was measured against when the initial value is smaller (see the
    /// module docs), so that a recomputation from the records gives the same number.
    pub drift_scales: Vec<(Conserved, f64)>,
    /// `true` in an orbital run with the gravity gradient: the quantities of [`Self::drift`] are
    /// not conserved (the tidal wrenches change them), and each drift is the residual of the
    /// quantity's balance — its change less the time integral of the recorded tidal wrench
    /// (docs/orbit.md); `false`: they are conserved and each drift is their change.
    pub balance: bool,
    /// Accepted integration steps.
    pub n_steps: usize,
    /// Rejected steps (adaptive integrator only).
    pub n_rejected: usize,
    /// Evaluations of the right-hand side (each one forward-dynamics solve).
    pub n_rhs_evals: usize,
    /// Name of each actuator index of [`SaturationEvent::actuator`].
    pub actuator_names: Vec<String>,
    /// Degrees of freedom that are reaction wheels.
    pub wheel_dofs: Vec<usize>,
    /// What [`Records::tracking_error`] measures, if recorded.
    pub tracking: Option<TrackingKind>,
    /// Name of the controller that ran.
    pub controller: String,
    /// Largest norm of a commanded base-wrench part the mode does not allow, and the number of
    /// evaluations in which one was commanded.
    pub dropped_wrench_max: f64,
    /// Number of evaluations that commanded such a part.
    pub dropped_wrench_count: usize,
    /// A point controller's report on its goal at the final sample ([`Controller::goal_report`]).
    pub goal: Option<crate::control::GoalReport>,
    /// The stop condition that ended the run ([`SimOptions::stop`]); `None`: it ran its duration.
    pub stop: Option<StopEvent>,
}

impl SimResult {
    /// Whether the point controller's goal was out of reach ([`crate::control::GoalReport::unreachable`]),
    /// judged at the natural end of a run only: a run stopped by an event ended before its
    /// goal's time, so its last distance says nothing about reach (`Some(false)`); `None`
    /// without a point controller.
    pub fn goal_unreachable(&self) -> Option<bool> {
        self.goal.map(|g| self.stop.is_none() && g.unreachable())
    }
}

/// The plant as an ODE `ẏ = f(t, y)` for the integrators: model, mode, actuators and controller
/// (public so that single steps can be timed; [`simulate`] is the way to run a simulation).
///
/// It borrows or owns its model and controller (`Plant<'static>` owns both: a plant that can
/// live in a Python object or move to another thread).
pub struct Plant<'a> {
    pub(crate) model: Cow<'a, Model>,
    pub(crate) data: Data,
    mode: Mode,
    actuators: Actuators,
    pub(crate) controller: Box<dyn Controller + 'a>,
    pub(crate) cmd: Command,
    /// A joint torque and base wrench added to the controller's command at every evaluation
    /// (held constant over a step: the input of a step-by-step simulation); `None`: nothing added.
    held_input: Option<(Vec<f64>, Vector6<f64>)>,
    pub(crate) tau_applied: Vec<f64>,
    pub(crate) wrench_applied: Vector6<f64>,
    f: Vec<f64>,
    /// Saturation bits of the last evaluation, and OR-ed over the current step.
    flags_eval: Vec<u8>,
    pub(crate) flags_step: Vec<u8>,
    pub(crate) nx: usize,
    pub(crate) n_evals: usize,
    pub(crate) dropped_max: f64,
    pub(crate) dropped_count: usize,
    pub(crate) wheels: Vec<usize>,
    /// Set when a stage value was not finite (an adaptive step that was far too long).
    pub(crate) nonfinite_stage: bool,
    /// Wrenches on bodies added at every evaluation (a coupling to another body, set by the
    /// caller before each evaluation: [`crate::sim::soft_capture`]); empty: none.
    body_wrenches: Vec<ExternalWrench>,
    /// A loop closure: the forward dynamics are then the constrained ones
    /// ([`crate::sim::closed_chain`]); `None`: ABA.
    pub(crate) closure: Option<Box<crate::sim::closed_chain::ClosureState>>,
    /// An orbital run's track of `O` and whether the tidal wrenches act ([`OrbitOptions`]).
    pub(crate) orbit: Option<(OrbitTrack, bool)>,
    /// `O`'s ECI position and velocity at the last evaluation.
    pub(crate) orbit_state: (Vector3<f64>, Vector3<f64>),
    /// The total tidal wrench of the last evaluation, `[force; torque about O]`.
    pub(crate) gravity_wrench: Vector6<f64>,
    /// The wrenches of the last evaluation: [`Plant::set_body_wrenches`]'s and the tidal ones.
    wrench_buf: Vec<ExternalWrench>,
}

impl<'a> Plant<'a> {
    /// Check the options (wheels, limits) and set the controller up against the model.
    pub fn new(model: &'a Model, opts: &SimOptions, controller: &'a mut dyn Controller) -> Result<Self> {
        Plant::build(Cow::Borrowed(model), opts, Box::new(controller))
    }

    /// A plant that owns its model and controller.
    pub fn owned(model: Model, opts: &SimOptions, controller: Box<dyn Controller>) -> Result<Plant<'static>> {
        Plant::build(Cow::Owned(model), opts, controller)
    }

    fn build(model: Cow<'a, Model>, opts: &SimOptions, mut controller: Box<dyn Controller + 'a>) -> Result<Self> {
        let n = model.n_dof();
        let wheels = match &opts.wheels {
            Some(w) => {
                check_wheels(&model, w)?;
                w.clone()
            }
            None => detect_reaction_wheels(&model),
        };
        let arm = arm_dofs(n, &wheels);
        let actuators = Actuators::new(&model, opts.joint_limits, opts.thrusters);
        let ctx = ControlContext { plant: &model, mode: opts.mode, wheel_dofs: &wheels, arm_dofs: &arm, actuators: &actuators };
        controller.setup(&ctx)?;
        let n_ref = controller.reference_len();
        let orbit = match &opts.orbit {
            Some(o) => Some((OrbitTrack::new(&o.orbit, opts.duration)?, o.gravity_gradient)),
            None => None,
        };
        let orbit_state = opts.orbit.map(|o| (o.orbit.r0, o.orbit.v0)).unwrap_or_default();
        Ok(Plant {
            data: Data::new(&model),
            nx: model.nx(),
            model,
            mode: opts.mode,
            actuators,
            cmd: Command::new(n, n_ref),
            held_input: None,
            controller,
            tau_applied: vec![0.0; n],
            wrench_applied: Vector6::zeros(),
            f: vec![0.0; 6 + n],
            flags_eval: vec![0; n + 6],
            flags_step: vec![0; n + 6],
            n_evals: 0,
            dropped_max: 0.0,
            dropped_count: 0,
            wheels,
            nonfinite_stage: false,
            body_wrenches: Vec::new(),
            closure: None,
            orbit,
            orbit_state,
            gravity_wrench: Vector6::zeros(),
            wrench_buf: Vec::new(),
        })
    }

    /// The plant's model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Apply `wrenches` (checked here against the model) at every evaluation from now on, in
    /// the forward dynamics with the commanded forces; an empty slice removes them. Reuses its
    /// buffer: no allocation once it has held as many wrenches.
    pub fn set_body_wrenches(&mut self, wrenches: &[ExternalWrench]) -> Result<()> {
        for w in wrenches {
            w.check(&self.model)?;
        }
        self.body_wrenches.clear();
        self.body_wrenches.extend_from_slice(wrenches);
        Ok(())
    }

    /// The workspace of the last evaluation (kinematics at its `x`, body velocities at its `u`).
    pub fn data(&self) -> &Data {
        &self.data
    }

    /// Add `tau` (N) and `base_wrench` (`[F0; N0]` in 𝒥 at the base CM) to every command of the
    /// controller from now on (then the mode's mask and the actuator limits apply as usual);
    /// `None` stops adding. The caller checks lengths and finiteness.
    pub fn set_held_input(&mut self, input: Option<(&[f64], Vector6<f64>)>) {
        match input {
            Some((tau, wrench)) => match &mut self.held_input {
                Some((t, w)) => {
                    t.copy_from_slice(tau);
                    *w = wrench;
                }
                None => self.held_input = Some((tau.to_vec(), wrench)),
            },
            None => self.held_input = None,
        }
    }
}

impl Plant<'_> {
    /// An orbital run: read `O`'s state at `t` and, with the gravity gradient, fill the wrench
    /// buffer with [`Plant::set_body_wrenches`]'s wrenches and each body's tidal wrench (the
    /// kinematics are current). Returns whether the buffer is to be used.
    fn tidal_wrenches(&mut self, t: f64) -> Result<bool> {
        let Some((track, gg)) = &mut self.orbit else {
            return Ok(false);
        };
        track.extend_to(t)?;
        self.orbit_state = track.state(t);
        if !*gg {
            return Ok(false);
        }
        let g = gravity_gradient_tensor(track.orbit().body.mu, &self.orbit_state.0);
        self.wrench_buf.clear();
        self.wrench_buf.extend_from_slice(&self.body_wrenches);
        let first = self.wrench_buf.len();
        tidal_wrenches_into(&self.model, &self.data, &g, &mut self.wrench_buf);
        let mut total = Vector6::zeros();
        for w in &self.wrench_buf[first..] {
            let about_o = self.data.com_in_world[w.body].cross(&w.force) + w.torque;
            total += Vector6::new(w.force.x, w.force.y, w.force.z, about_o.x, about_o.y, about_o.z);
        }
        self.gravity_wrench = total;
        Ok(true)
    }

    /// Whether the plant runs in orbit with the tidal wrenches.
    pub fn has_gravity_gradient(&self) -> bool {
        matches!(self.orbit, Some((_, true)))
    }
}

impl OdeSystem for Plant<'_> {
    fn dim(&self) -> usize {
        self.nx + self.model.nu()
    }

    fn project(&self, y: &mut [f64]) {
        let q = &mut y[3..7];
        let norm = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
        if norm > 0.0 && norm.is_finite() {
            for v in q.iter_mut() {
                *v /= norm;
            }
        }
    }

    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
        self.n_evals += 1;
        if let Some(i) = y.iter().position(|v| !v.is_finite()) {
            self.nonfinite_stage = true;
            return Err(SpacearmError::Simulation(format!(
                "the state became non-finite at t = {t} s (entry {i} of [x; u]): the motion diverged — reduce dt, tighten \
                 rtol/atol or lower the controller gains"
            )));
        }
        let n = self.model.n_dof();
        let (x, u) = y.split_at(self.nx);
        self.cmd.clear();
        self.controller.command(t, x, u, &mut self.cmd)?;
        if let Some((tau, wrench)) = &self.held_input {
            for (c, h) in self.cmd.tau.iter_mut().zip(tau) {
                *c += h;
            }
            self.cmd.base_wrench += wrench;
        }
        if self.cmd.tau.iter().chain(self.cmd.base_wrench.iter()).any(|v| !v.is_finite()) {
            return Err(SpacearmError::Simulation(format!("controller '{}' returned a non-finite torque or base wrench at t = {t} s", self.controller.name())));
        }
        forward_kinematics(&self.model, &mut self.data, x)?;
        self.flags_eval.fill(0);
        self.tau_applied.copy_from_slice(&self.cmd.tau);
        self.actuators.saturate_joints(&mut self.tau_applied, &u[6..], &mut self.flags_eval[..n]);
        let (mut kept, dropped) = self.mode.mask(&self.cmd.base_wrench);
        let dropped_norm = dropped.norm();
        if dropped_norm > 0.0 {
            self.dropped_count += 1;
            self.dropped_max = self.dropped_max.max(dropped_norm);
        }
        self.actuators.saturate_thrusters(&mut kept, &mut self.flags_eval[n..]);
        let base_to_com =
            if self.mode == Mode::TranslationFlying { center_of_mass_from_data(&self.model, &self.data) - self.data.base_position } else { Vector3::zeros() };
        self.wrench_applied = self.mode.wrench_at_base(&kept, &base_to_com);
        self.f[..6].copy_from_slice(self.wrench_applied.as_slice());
        self.f[6..].copy_from_slice(&self.tau_applied);
        let tidal = self.tidal_wrenches(t)?;
        if let Some(c) = &mut self.closure {
            if tidal {
                return Err(SpacearmError::argument("a closed chain in orbit with the gravity gradient is not implemented yet (use gravity_gradient=False)"));
            }
            c.evaluate(&self.model, &mut self.data, x, u, &self.f)?;
        } else if tidal {
            aba_with_wrenches_after_kinematics(&self.model, &mut self.data, &x[7..], u, &self.f, &self.wrench_buf)?;
        } else if self.body_wrenches.is_empty() {
            aba_after_kinematics(&self.model, &mut self.data, &x[7..], u, &self.f)?;
        } else {
            aba_with_wrenches_after_kinematics(&self.model, &mut self.data, &x[7..], u, &self.f, &self.body_wrenches)?;
        }
        // ṙ0 = v0; quaṫ = ½ [ω0; 0] ⊗ quat (Hamilton, [x, y, z, w], ω0 in 𝒥); q̇; u̇.
        dy[0..3].copy_from_slice(&u[0..3]);
        dy[3..7].copy_from_slice(&quaternion_rate(&x[3..7], &Vector3::new(u[3], u[4], u[5])));
        dy[7..self.nx].copy_from_slice(&u[6..]);
        dy[self.nx..].copy_from_slice(self.data.accel.as_slice());
        for (s, e) in self.flags_step.iter_mut().zip(&self.flags_eval) {
            *s |= *e;
        }
        Ok(())
    }
}

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

/// Run a plant set up for `opts` from `(x0, u0)` (checked by the caller): admission of the
/// records, then the RK4 or DOPRI5 loop.
///
/// Stop conditions ([`crate::sim::events`]): a time condition within the duration makes the run
/// the run of that duration (its last step lands on it); gap conditions are watched at every
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
    let gaps = watch.has_gaps().then_some(&watch);
    let mut result = match opts.integrator {
        IntegratorKind::Rk4 => simulate_rk4(plant, x0, u0, opts, gaps, progress)?,
        IntegratorKind::Dopri5 => simulate_dopri5(plant, x0, u0, opts, gaps, progress)?,
    };
    if result.stop.is_none() {
        result.stop = watch.time.map(|(condition, t)| StopEvent { condition, t, value: t });
    }
    check_divergence(&result)?;
    Ok(result)
}

/// Admission control of recorded samples ([`crate::admission`]), the one check of every entry
/// point that records ([`simulate`], [`crate::sim::rollout::rollout`], a recording
/// [`Rk4Stepper`]): `samples` samples of `values` values in all, in `f64`, counted twice (the
/// records and the copy a caller converts them into), refused before any buffer is reserved,
/// with the way out for `integrator`.
pub fn admit_records(integrator: IntegratorKind, samples: f64, values: f64) -> Result<()> {
    let remedy = match integrator {
        IntegratorKind::Rk4 => "record fewer samples (record_every > 1 keeps every k-th step), or simulate a shorter duration",
        IntegratorKind::Dopri5 => {
            "use a coarser output grid (dt is DOPRI5's output interval; the step size adapts on its own), or simulate a shorter duration"
        }
    };
    crate::admission::admit(
        format_args!("recording {samples} samples ({values:.3e} values)"),
        2.0 * crate::admission::bytes_of::<f64>(values),
        remedy,
    )
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
/// one landing on the duration. With gap conditions (`gaps`), `f` is evaluated at every step's
/// end for their values, and the step in which one first holds is re-taken from its start with
/// shorter steps to locate the event ([`crate::sim::events`]); the run ends there.
fn simulate_rk4(plant: Plant<'_>, x0: &[f64], u0: &[f64], opts: &SimOptions, gaps: Option<&StopWatch>, progress: Progress<'_>) -> Result<SimResult> {
    let n_steps = rk4_step_count(opts);
    let mut stepper = Rk4Stepper::new(plant, x0, u0, Some((sample_count(opts), opts.record_every)))?;
    // A step longer than the fastest mode allows is refused before the first step.
    let y0 = stepper.state().to_vec();
    crate::sim::step_limit::check_rk4_step(stepper.plant_mut(), 0.0, &y0, opts.dt.min(opts.duration))?;
    let progress_every = opts.duration / 1000.0;
    let mut next_progress = 0.0;
    // The event watch's workspaces: the state at the step's start, a stage, f, an RK4 for re-taking it.
    let dim = y0.len();
    let (mut y_prev, mut y_try, mut dy) = (y0.clone(), vec![0.0; dim], vec![0.0; dim]);
    let mut rk = Rk4::new(dim);
    let mut stop = None;
    let mut g_prev = vec![0.0; opts.stop.len()];
    if let Some(w) = gaps {
        stepper.plant_mut().rhs(0.0, &y0, &mut dy)?;
        if let Some((condition, _, gap)) = w.holding(stepper.plant_mut()) {
            stop = Some(StopEvent { condition, t: 0.0, value: gap });
        }
        w.values_into(stepper.plant_mut(), &mut g_prev);
    }
    let mut t_prev = 0.0;
    for i in 0..n_steps {
        if stop.is_some() {
            break;
        }
        let t_next = if i + 1 == n_steps { opts.duration } else { (i + 1) as f64 * opts.dt };
        if gaps.is_some() {
            y_prev.copy_from_slice(stepper.state());
        }
        stepper.step_to(t_next)?;
        if let Some(w) = gaps {
            y_try.copy_from_slice(stepper.state());
            let plant = stepper.plant_mut();
            plant.rhs(t_next, &y_try, &mut dy)?;
            let g_start = g_prev.clone();
            w.values_into(plant, &mut g_prev);
            let mut found: Option<(usize, f64, f64)> = None;
            for condition in w.gap_conditions() {
                if g_prev[condition] > 0.0 {
                    continue;
                }
                // g(t_prev) > 0: no condition held at the previous step's end.
                let mut g_at = |t: f64| -> Result<f64> {
                    y_try.copy_from_slice(&y_prev);
                    rk.step(&mut *plant, t_prev, t - t_prev, &mut y_try, false)?;
                    plant.rhs(t, &y_try, &mut dy)?;
                    Ok(w.value(plant, condition))
                };
                let (t_s, g_s) = locate_root(&mut g_at, (t_prev, g_start[condition]), (t_next, g_prev[condition]))?;
                if found.is_none_or(|f| t_s < f.1) {
                    found = Some((condition, t_s, g_s));
                }
            }
            if let Some((condition, t_s, g_s)) = found {
                // The state at the event: the step re-taken to it (or the step's own end).
                if t_s < t_next {
                    y_try.copy_from_slice(&y_prev);
                    rk.step(&mut *plant, t_prev, t_s - t_prev, &mut y_try, false)?;
                } else {
                    y_try.copy_from_slice(stepper.state());
                }
                stepper.land(t_s, &y_try);
                stop = Some(StopEvent { condition, t: t_s, value: g_s + w.tolerance(condition) });
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
fn simulate_dopri5(mut plant: Plant<'_>, x0: &[f64], u0: &[f64], opts: &SimOptions, gaps: Option<&StopWatch>, progress: Progress<'_>) -> Result<SimResult> {
    let mut y: Vec<f64> = x0.iter().chain(u0).copied().collect();
    plant.project(&mut y);
    let mut rec = Recorder::for_plant(&plant, sample_count(opts));
    let words = DopriWords {
        of_run: "",
        budget_remedy: " (loosen rtol/atol, raise max_steps, or use rk4)",
        stiff_remedy: "the dynamics are too stiff or discontinuous there (a saturating actuator switching, a very high gain); loosen \
                       rtol/atol or use rk4",
    };
    let run = dopri5_loop(&mut plant, &mut y, opts, &words, gaps, &mut *progress, &mut |p, t, y, dy| rec.record(p, t, y, dy))?;
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
/// With gap conditions (`gaps`), their values are read at every accepted step's end from the
/// last stage's evaluation (at the new point: first same as last) and at every sample's
/// evaluation; at the first of these where one holds, the event is located on the dense output ([`crate::sim::events`]), the samples before
/// it are recorded, the last sample is the event's and `y` ends there.
pub(crate) fn dopri5_loop<S: StepWatch>(
    sys: &mut S,
    y: &mut [f64],
    opts: &SimOptions,
    words: &DopriWords,
    gaps: Option<&StopWatch>,
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
    sys.rhs(0.0, y, &mut dy)?;
    record(sys, 0.0, y, &dy);
    if let Some((condition, _, gap)) = gaps.and_then(|w| w.holding(sys.watched_plant())) {
        return Ok(DopriRun { n_steps, n_rejected, events, stop: Some(StopEvent { condition, t: 0.0, value: gap }) });
    }
    let mut g_prev = vec![0.0; opts.stop.len()];
    let (mut g_end, mut g_sample) = (g_prev.clone(), g_prev.clone());
    if let Some(w) = gaps {
        w.values_into(sys.watched_plant(), &mut g_prev);
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
            if let Some(w) = gaps {
                w.values_into(sys.watched_plant(), &mut g_end);
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
                if let Some(w) = gaps {
                    w.values_into(sys.watched_plant(), &mut g_sample);
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
            if let (None, Some(w)) = (stop, gaps) {
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

/// The earliest event of the gap conditions that hold at `b` (values `gb`), none holding at `a`
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
    for condition in w.gap_conditions() {
        if gb[condition] > 0.0 {
            continue;
        }
        let mut g_at = |tc: f64| -> Result<f64> {
            dp.dense_output(tc, y_try);
            sys.project(y_try);
            sys.rhs(tc, y_try, dy)?;
            Ok(w.value(sys.watched_plant(), condition))
        };
        let (t_s, g_s) = locate_root(&mut g_at, (a, ga[condition]), (b, gb[condition]))?;
        if stop.is_none_or(|s| t_s < s.t) {
            stop = Some(StopEvent { condition, t: t_s, value: g_s + w.tolerance(condition) });
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

/// The result of a run from its plant (counters, controller) and records.
pub(crate) fn finish_result(plant: &Plant<'_>, rec: Recorder, events: Vec<SaturationEvent>, n_steps: usize, n_rejected: usize) -> SimResult {
    // The mechanical energy (kinetic plus springs) is conserved without joint torques, base
    // wrench or joint dampers.
    let undamped = plant.model().dof_dynamics().iter().all(|d| d.damping == 0.0);
    let mut conserved = plant.mode.conserved(plant.controller.is_torque_free() && undamped);
    if plant.has_gravity_gradient() {
        // The tidal wrenches do work on the system: only the momentum balances are monitored.
        conserved.retain(|c| *c != Conserved::Energy);
    }
    let drift = rec.drift(&conserved);
    let drift_scales = conserved.iter().map(|&c| (c, rec.scale(c))).collect();
    let balance = rec.balance;
    SimResult {
        balance,
        reference_width: plant.controller.reference_len(),
        records: rec.rec,
        events,
        drift,
        drift_scales,
        n_steps,
        n_rejected,
        n_rhs_evals: plant.n_evals,
        actuator_names: Actuators::names(plant.model()),
        tracking: plant.controller.tracking(),
        controller: plant.controller.name().to_string(),
        dropped_wrench_max: plant.dropped_max,
        dropped_wrench_count: plant.dropped_count,
        wheel_dofs: plant.wheels.clone(),
        goal: plant.controller.goal_report(),
        stop: None,
    }
}
