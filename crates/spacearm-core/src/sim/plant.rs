//! The plant as an ODE for the integrators ([`Plant`]): at every evaluation the controller's
//! command, the joint motor limits, the mode's base-wrench mask, the thruster limits, the tidal
//! wrenches of an orbit and the forward dynamics (ABA, or the constrained dynamics of a loop
//! closure); the sequence is in the docs of [`crate::sim::simulate`].

use std::borrow::Cow;

use nalgebra::{Vector3, Vector6};

use crate::algorithms::aba::{aba_after_kinematics, aba_with_wrenches_after_kinematics};
use crate::algorithms::kinematics::forward_kinematics;
use crate::algorithms::momentum::center_of_mass_from_data;
use crate::algorithms::wrench::ExternalWrench;
use crate::control::{arm_dofs, Command, ControlContext, Controller};
use crate::error::{Result, SpacearmError};
use crate::math::integrate::OdeSystem;
use crate::math::rotations::quaternion_rate;
use crate::model::data::Data;
use crate::model::Model;
use crate::scenario::actuators::{check_wheels, detect_reaction_wheels, Actuators};
use crate::scenario::modes::Mode;
use crate::scenario::orbit::{gravity_gradient_tensor, tidal_wrenches_into, OrbitTrack};
use crate::sim::contact::PlantContact;
use crate::sim::free_target::FreeTarget;
use crate::sim::options::SimOptions;

/// The plant as an ODE `ẏ = f(t, y)` for the integrators: model, mode, actuators and controller
/// (public so that single steps can be timed; [`simulate`](crate::sim::simulate::simulate) is the way to run a simulation).
///
/// It borrows or owns its model and controller (`Plant<'static>` owns both: a plant that can
/// live in a Python object or move to another thread).
pub struct Plant<'a> {
    pub(crate) model: Cow<'a, Model>,
    pub(crate) data: Data,
    pub(crate) mode: Mode,
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
    pub(crate) closure: Option<Box<crate::sim::closure::ClosureState>>,
    /// An orbital run's track of `O` and whether the tidal wrenches act ([`OrbitOptions`](crate::sim::options::OrbitOptions)).
    pub(crate) orbit: Option<(OrbitTrack, bool)>,
    /// `O`'s ECI position and velocity at the last evaluation.
    pub(crate) orbit_state: (Vector3<f64>, Vector3<f64>),
    /// The total tidal wrench of the last evaluation, `[force; torque about O]`.
    pub(crate) gravity_wrench: Vector6<f64>,
    /// The wrenches of the last evaluation: [`Plant::set_body_wrenches`]'s, the tidal ones and
    /// the contacts'.
    wrench_buf: Vec<ExternalWrench>,
    /// Compliant contact between the system's bodies ([`crate::sim::contact`]); `None`: none.
    pub(crate) contact: Option<Box<PlantContact>>,
}

impl<'a> Plant<'a> {
    /// Check the options (wheels, limits) and set the controller up against the model.
    pub fn new(model: &'a Model, opts: &SimOptions, controller: &'a mut dyn Controller) -> Result<Self> {
        Plant::build(Cow::Borrowed(model), opts, Box::new(controller), None)
    }

    /// [`Plant::new`] with a free target in the loop of contact ([`crate::sim::free_target`]):
    /// `target` (one rigid body with collision shapes) at the 13-state `state`, its state
    /// integrated after `[x; u; W]`, touching the robot by the run's contact (`opts.contact`,
    /// required).
    pub fn with_target(model: &'a Model, opts: &SimOptions, controller: &'a mut dyn Controller, target: &Model, state: &[f64]) -> Result<Self> {
        Plant::build(Cow::Borrowed(model), opts, Box::new(controller), Some((target, state)))
    }

    /// A plant that owns its model and controller.
    pub fn owned(model: Model, opts: &SimOptions, controller: Box<dyn Controller>) -> Result<Plant<'static>> {
        Plant::build(Cow::Owned(model), opts, controller, None)
    }

    /// [`Plant::owned`] with a free target in the loop of contact ([`Plant::with_target`]; the
    /// C stepper's and an FMU's run of an options TOML that names one).
    pub fn owned_with_target(model: Model, opts: &SimOptions, controller: Box<dyn Controller>, target: &Model, state: &[f64]) -> Result<Plant<'static>> {
        Plant::build(Cow::Owned(model), opts, controller, Some((target, state)))
    }

    /// The free target's 13-state in the integrator's state `y`, if the plant has one.
    pub fn target_state<'y>(&self, y: &'y [f64]) -> Option<&'y [f64]> {
        self.target().map(|t| t.state(y))
    }

    fn build(model: Cow<'a, Model>, opts: &SimOptions, mut controller: Box<dyn Controller + 'a>, target: Option<(&Model, &[f64])>) -> Result<Self> {
        let n = model.n_dof();
        let wheels = match &opts.wheels {
            Some(w) => {
                check_wheels(&model, w)?;
                w.clone()
            }
            None => detect_reaction_wheels(&model),
        };
        // The CMGs' gimbals and rotors are momentum devices, not arm joints (docs/cmg.md): an arm
        // law's reference leaves them out, CMG steering drives them.
        let devices: Vec<usize> = wheels.iter().copied().chain(crate::model::cmg::detect_cmgs(&model).iter().flat_map(|c| [c.gimbal_dof, c.rotor_dof])).collect();
        let arm = arm_dofs(n, &devices);
        let actuators = Actuators::new(&model, opts.joint_limits, opts.thrusters);
        let ctx = ControlContext { plant: &model, mode: opts.mode, wheel_dofs: &wheels, arm_dofs: &arm, actuators: &actuators };
        controller.setup(&ctx)?;
        let n_ref = controller.reference_len();
        let orbit = match &opts.orbit {
            Some(o) => Some((OrbitTrack::new(&o.orbit, opts.duration)?, o.gravity_gradient)),
            None => None,
        };
        let orbit_state = opts.orbit.map(|o| (o.orbit.r0, o.orbit.v0)).unwrap_or_default();
        let target = match target {
            Some((t, s)) => {
                if opts.contact.is_none() {
                    return Err(SpacearmError::argument(
                        "a free target without topology events takes part in a run by contact: give contact=ContactModel(...) too (or events=[...] for a target that is attached)",
                    ));
                }
                if opts.orbit.is_some() {
                    return Err(SpacearmError::argument("contact with a free target in an orbit is not implemented yet (docs/contact.md, \"What is not handled\")"));
                }
                let mut t = FreeTarget::new(&model, t, s)?;
                t.offset = model.nx() + model.nu() + 1;
                Some(t)
            }
            None => None,
        };
        let contact = opts.contact.as_ref().map(|c| PlantContact::new(&model, c, target).map(Box::new)).transpose()?;
        Ok(Plant {
            contact,
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

    /// The integrator's initial state: `[x0; u0]`, with contact the contact work (0), with a free
    /// target its 13-state.
    pub(crate) fn initial_state(&self, x0: &[f64], u0: &[f64]) -> Vec<f64> {
        let mut y: Vec<f64> = x0.iter().chain(u0).copied().collect();
        if let Some(c) = &self.contact {
            y.push(0.0);
            if let Some(t) = &c.target {
                y.extend_from_slice(&t.state0);
            }
        }
        y
    }

    /// Whether the run's contact is rigid (its impulses applied by [`Plant::rigid_jump`]).
    pub(crate) fn is_rigid(&self) -> bool {
        self.contact.as_ref().is_some_and(|c| c.rigid.is_some())
    }

    /// Rigid contact: the velocity jump of the step of length `h` from `(t, y)`, `dy = f(t, y)`
    /// just evaluated ([`crate::sim::rigid_contact`]); whether one was applied.
    pub(crate) fn rigid_jump(&mut self, t: f64, h: f64, y: &mut [f64], dy: &[f64]) -> Result<bool> {
        let (nx, nu) = (self.nx, self.model.nu());
        match self.contact.as_deref_mut() {
            Some(c) => c.rigid_step(&self.model, &mut self.data, t, h, y, &dy[nx..nx + nu]),
            _ => Ok(false),
        }
    }

    /// The free target of the run, if it has one.
    pub(crate) fn target(&self) -> Option<&FreeTarget> {
        self.contact.as_ref().and_then(|c| c.target.as_ref())
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

    /// A sampled controller's sample at the start of a step from `(t, y)` ([`Controller::sample`](crate::control::Controller::sample)):
    /// what every loop does before the step's first evaluation.
    pub fn sample(&mut self, t: f64, y: &[f64]) -> Result<()> {
        let (x, u) = y.split_at(self.nx);
        self.controller.sample(t, x, u)
    }

    /// The forces the plant applies at `(t, x, u)`: the controller's command (plus the held
    /// input), through the actuator limits and the mode's mask (docs/modes.md), into
    /// [`Plant::applied`]; the kinematics of `x` are left in [`Plant::data`]. What every
    /// evaluation of the dynamics does first; also called alone to read a controller's command
    /// at a state measured elsewhere (a flight-software module, `spacearm.basilisk`).
    pub fn apply_command(&mut self, t: f64, x: &[f64], u: &[f64]) -> Result<()> {
        let n = self.model.n_dof();
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
        Ok(())
    }

    /// The joint torques (N) and the base wrench (`[F0; N0]` at the base CM, in 𝒥) of the last
    /// evaluation, after the limits and the mode's mask.
    pub fn applied(&self) -> (&[f64], &Vector6<f64>) {
        (&self.tau_applied, &self.wrench_applied)
    }

    /// Whether the plant runs in orbit with the tidal wrenches.
    pub fn has_gravity_gradient(&self) -> bool {
        matches!(self.orbit, Some((_, true)))
    }
}

impl OdeSystem for Plant<'_> {
    fn dim(&self) -> usize {
        // With contact, one more: the work of the contact forces, integrated with the motion;
        // with a free target its 13-state.
        self.nx + self.model.nu() + usize::from(self.contact.is_some()) + if self.target().is_some() { 13 } else { 0 }
    }

    fn project(&self, y: &mut [f64]) {
        let q = &mut y[3..7];
        let norm = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
        if norm > 0.0 && norm.is_finite() {
            for v in q.iter_mut() {
                *v /= norm;
            }
        }
        if let Some(t) = self.target() {
            t.project(y);
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
        let (x, u) = y.split_at(self.nx);
        let u = &u[..self.model.nu()];
        self.apply_command(t, x, u)?;
        self.f[..6].copy_from_slice(self.wrench_applied.as_slice());
        self.f[6..].copy_from_slice(&self.tau_applied);
        let tidal = self.tidal_wrenches(t)?;
        // Contact: its pairs of wrenches join the others in the buffer (sim/contact.rs).
        let contact = self.contact.is_some();
        if let Some(c) = &mut self.contact {
            if !tidal {
                self.wrench_buf.clear();
                self.wrench_buf.extend_from_slice(&self.body_wrenches);
            }
            c.wrenches_into(&self.model, &mut self.data, y, &mut self.wrench_buf)?;
        }
        if let Some(c) = &mut self.closure {
            if tidal {
                return Err(SpacearmError::argument("a closed chain in orbit with the gravity gradient is not implemented yet (use gravity_gradient=False)"));
            }
            if contact {
                return Err(SpacearmError::argument("contact in a closed chain is not implemented yet (leave contact out of a closed-chain run)"));
            }
            c.evaluate(&self.model, &mut self.data, x, u, &self.f)?;
        } else if tidal || contact {
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
        let nu = self.model.nu();
        dy[self.nx..self.nx + nu].copy_from_slice(self.data.accel.as_slice());
        if let Some(c) = &self.contact {
            dy[self.nx + nu] = c.power;
            if let Some(t) = &c.target {
                t.derivative(t.state(y), &mut dy[t.offset..t.offset + 13]);
            }
        }
        for (s, e) in self.flags_step.iter_mut().zip(&self.flags_eval) {
            *s |= *e;
        }
        Ok(())
    }
}
