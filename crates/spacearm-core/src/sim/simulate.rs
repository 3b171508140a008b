//! The simulation loop: integrate `y = [x; u]` under a controller in a maneuvering mode, with
//! actuator limits, recording every quantity into buffers allocated before the first step.
//!
//! Per right-hand-side evaluation (every integrator stage): the controller's [`Command`] →
//! joint motor limits → the mode's base-wrench mask → thruster limits → the wrench at the base
//! CM (through the system CM in translation-flying) → forward dynamics by the articulated-body
//! algorithm with `f = [F0; N0; τ]` → `ẏ = [v0; ½ [ω0; 0] ⊗ quat; q̇; u̇]`.
//!
//! Recorded per sample: the state, `u̇`, applied and commanded torques, the applied base
//! wrench, `P`, `L_origin`, `L_com`, kinetic energy, system CM, end-effector pose, the
//! controller's reference and tracking error, wheel speeds. Saturation events mark the accepted
//! step in which an actuator starts saturating (its onset; the per-sample `tau` against
//! `tau_cmd` shows how long it lasts). The drift of each conserved quantity is its largest
//! deviation from the initial value over the recorded samples, relative to
//! `max(|initial|, scale)` with the scale the largest over the samples of the sum of the
//! magnitudes of the bodies' contributions (`Σ mᵢ|vᵢ|` for `P`, `Σ |rᵢ × mᵢvᵢ| + |Iᵢωᵢ|` about
//! the point for `L`, the energy itself for the energy): the size of the terms whose
//! cancellation the conservation is.

use nalgebra::{Rotation3, UnitQuaternion, Vector3, Vector6};

use crate::algorithms::aba::aba_after_kinematics;
use crate::sim::actuators::{check_wheels, detect_reaction_wheels, Actuators, SaturationKind, ThrusterLimits};
use crate::control::{arm_dofs, Command, ControlContext, Controller, TrackingKind};
use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::sim::integrate::{Dopri5, IntegratorKind, OdeSystem, Rk4, StepOutcome};
use crate::algorithms::kinematics::{check_velocity, forward_kinematics, point_position, split_configuration};
use crate::model::Model;
use crate::sim::modes::{Conserved, Mode};
use crate::algorithms::momentum::{center_of_mass_from_data, momentum_from_data};
use crate::math::rotations::quaternion_rate;
use crate::math::spatial::{angular, linear};

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
}

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
            max_steps: 10_000_000,
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
        Ok(())
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
    /// Kinetic energy, J (width 1).
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
    /// The controller's base attitude error angle, rad, if it reports one.
    pub attitude_error: Option<Vec<f64>>,
    /// Wheel rates relative to the base, rad/s.
    pub wheel_speed: Option<Vec<f64>>,
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
}

/// The plant as an ODE `ẏ = f(t, y)` for the integrators: model, mode, actuators and controller
/// (public so that single steps can be timed; [`simulate`] is the way to run a simulation).
pub struct Plant<'a> {
    model: &'a Model,
    data: Data,
    mode: Mode,
    actuators: Actuators,
    controller: &'a mut dyn Controller,
    cmd: Command,
    tau_applied: Vec<f64>,
    wrench_applied: Vector6<f64>,
    f: Vec<f64>,
    /// Saturation bits of the last evaluation, and OR-ed over the current step.
    flags_eval: Vec<u8>,
    flags_step: Vec<u8>,
    nx: usize,
    n_evals: usize,
    dropped_max: f64,
    dropped_count: usize,
    wheels: Vec<usize>,
    /// Set when a stage value was not finite (an adaptive step that was far too long).
    nonfinite_stage: bool,
}

impl<'a> Plant<'a> {
    /// Check the options (wheels, limits) and set the controller up against the model.
    pub fn new(model: &'a Model, opts: &SimOptions, controller: &'a mut dyn Controller) -> Result<Self> {
        let n = model.n_dof();
        let wheels = match &opts.wheels {
            Some(w) => {
                check_wheels(model, w)?;
                w.clone()
            }
            None => detect_reaction_wheels(model),
        };
        let arm = arm_dofs(n, &wheels);
        let actuators = Actuators::new(model, opts.joint_limits, opts.thrusters);
        let ctx = ControlContext { plant: model, mode: opts.mode, wheel_dofs: &wheels, arm_dofs: &arm, actuators: &actuators };
        controller.setup(&ctx)?;
        let n_ref = controller.reference_len();
        Ok(Plant {
            model,
            data: Data::new(model),
            mode: opts.mode,
            actuators,
            cmd: Command::new(n, n_ref),
            controller,
            tau_applied: vec![0.0; n],
            wrench_applied: Vector6::zeros(),
            f: vec![0.0; 6 + n],
            flags_eval: vec![0; n + 6],
            flags_step: vec![0; n + 6],
            nx: model.nx(),
            n_evals: 0,
            dropped_max: 0.0,
            dropped_count: 0,
            wheels,
            nonfinite_stage: false,
        })
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
        if self.cmd.tau.iter().chain(self.cmd.base_wrench.iter()).any(|v| !v.is_finite()) {
            return Err(SpacearmError::Simulation(format!(
                "controller '{}' returned a non-finite torque or base wrench at t = {t} s",
                self.controller.name()
            )));
        }
        forward_kinematics(self.model, &mut self.data, x)?;
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
        let base_to_com = if self.mode == Mode::TranslationFlying {
            center_of_mass_from_data(self.model, &self.data) - self.data.base_position
        } else {
            Vector3::zeros()
        };
        self.wrench_applied = self.mode.wrench_at_base(&kept, &base_to_com);
        self.f[..6].copy_from_slice(self.wrench_applied.as_slice());
        self.f[6..].copy_from_slice(&self.tau_applied);
        aba_after_kinematics(self.model, &mut self.data, u, &self.f)?;
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

/// Running maxima of the drift scales.
#[derive(Debug, Default, Clone, Copy)]
struct Scales {
    p: f64,
    l_origin: f64,
    l_com: f64,
    energy: f64,
}

struct Recorder {
    rec: Records,
    ee: Option<(usize, Vector3<f64>)>,
    wheels: Vec<usize>,
    n_ref: usize,
    scales: Scales,
    last_quat: Option<UnitQuaternion<f64>>,
}

impl Recorder {
    /// Values recorded per sample: the sum of the widths that [`Recorder::new`] reserves.
    fn sample_width(model: &Model, n_wheels: usize, n_ref: usize, tracking: bool, attitude: bool) -> usize {
        let (nx, nu, n) = (model.nx(), model.nu(), model.n_dof());
        let ee = if model.end_effector().is_some() { 3 + 4 } else { 0 };
        1 + nx + 2 * nu + 2 * n + 6 + 3 + 3 + 3 + 1 + 3 + ee + n_ref + usize::from(tracking) + usize::from(attitude) + n_wheels
    }

    fn new(model: &Model, capacity: usize, wheels: &[usize], n_ref: usize, tracking: bool, attitude: bool) -> Self {
        let (nx, nu, n) = (model.nx(), model.nu(), model.n_dof());
        let v = |w: usize| Vec::with_capacity(capacity * w);
        let ee = model.end_effector().map(|i| (model.points()[i].body, model.points()[i].offset));
        Recorder {
            rec: Records {
                n_samples: 0,
                t: v(1),
                x: v(nx),
                u: v(nu),
                du: v(nu),
                tau: v(n),
                tau_cmd: v(n),
                base_wrench: v(6),
                linear_momentum: v(3),
                angular_momentum_origin: v(3),
                angular_momentum_com: v(3),
                energy: v(1),
                com: v(3),
                ee_position: ee.map(|_| v(3)),
                ee_quat: ee.map(|_| v(4)),
                reference: (n_ref > 0).then(|| v(n_ref)),
                tracking_error: tracking.then(|| v(1)),
                attitude_error: attitude.then(|| v(1)),
                wheel_speed: (!wheels.is_empty()).then(|| v(wheels.len())),
            },
            ee,
            wheels: wheels.to_vec(),
            n_ref,
            scales: Scales::default(),
            last_quat: None,
        }
    }

    /// Record the sample at `(t, y)`; the plant has just evaluated `dy = f(t, y)`, so its
    /// workspace holds the kinematics at `x` and the body velocities at `u`.
    fn record(&mut self, plant: &Plant<'_>, t: f64, y: &[f64], dy: &[f64]) {
        let (model, data) = (plant.model, &plant.data);
        let nx = plant.nx;
        let r = &mut self.rec;
        r.n_samples += 1;
        r.t.push(t);
        r.x.extend_from_slice(&y[..nx]);
        r.u.extend_from_slice(&y[nx..]);
        r.du.extend_from_slice(&dy[nx..]);
        r.tau.extend_from_slice(&plant.tau_applied);
        r.tau_cmd.extend_from_slice(&plant.cmd.tau);
        r.base_wrench.extend_from_slice(plant.wrench_applied.as_slice());
        // Momentum and energy from the body velocities (spatial, at the base CM), body by body,
        // with the scale of each sum's terms for the drift (module docs).
        let momentum = momentum_from_data(model, data);
        let r0 = data.base_position;
        let rg = center_of_mass_from_data(model, data);
        let mut energy = 0.0;
        let (mut sp, mut slo, mut slc) = (0.0, 0.0, 0.0);
        for b in 0..model.n_bodies() {
            let v = data.body_velocity[b];
            energy += 0.5 * v.dot(&(data.spatial_inertia[b] * v));
            let w = angular(&v);
            let rb = data.com_in_world[b];
            let p_b = (linear(&v) + w.cross(&(rb - r0))) * model.mass_properties(b).mass;
            let spin = (data.inertia_in_world[b] * w).norm();
            sp += p_b.norm();
            slo += rb.cross(&p_b).norm() + spin;
            slc += (rb - rg).cross(&p_b).norm() + spin;
        }
        r.linear_momentum.extend_from_slice(momentum.linear.as_slice());
        r.angular_momentum_origin.extend_from_slice(momentum.angular_about_origin.as_slice());
        r.angular_momentum_com.extend_from_slice(momentum.angular_about_com.as_slice());
        r.energy.push(energy);
        r.com.extend_from_slice(rg.as_slice());
        let s = &mut self.scales;
        s.p = s.p.max(sp);
        s.l_origin = s.l_origin.max(slo);
        s.l_com = s.l_com.max(slc);
        s.energy = s.energy.max(energy);
        if let Some((body, offset)) = self.ee {
            let pos = point_position(data, body, &offset);
            r.ee_position.as_mut().expect("allocated with ee").extend_from_slice(pos.as_slice());
            let mut q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(data.body_to_world[body]));
            if let Some(last) = self.last_quat {
                if last.coords.dot(&q.coords) < 0.0 {
                    q = UnitQuaternion::new_unchecked(-q.into_inner());
                }
            }
            self.last_quat = Some(q);
            let c = q.coords; // [i, j, k, w]
            r.ee_quat.as_mut().expect("allocated with ee").extend_from_slice(&[c[0], c[1], c[2], c[3]]);
        }
        if let Some(rf) = r.reference.as_mut() {
            rf.extend_from_slice(&plant.cmd.reference[..self.n_ref]);
        }
        if let Some(te) = r.tracking_error.as_mut() {
            te.push(plant.cmd.tracking_error);
        }
        if let Some(ae) = r.attitude_error.as_mut() {
            ae.push(plant.cmd.attitude_error);
        }
        if let Some(ws) = r.wheel_speed.as_mut() {
            for &d in &self.wheels {
                ws.push(y[nx + 6 + d]);
            }
        }
    }

    /// The scale of a conserved quantity's drift: the running maximum of its magnitude scale.
    fn scale(&self, c: Conserved) -> f64 {
        match c {
            Conserved::LinearMomentum => self.scales.p,
            Conserved::AngularMomentumOrigin => self.scales.l_origin,
            Conserved::AngularMomentumCom => self.scales.l_com,
            Conserved::Energy => self.scales.energy,
        }
    }

    /// Drift of each conserved quantity over the recorded samples (see the module docs).
    fn drift(&self, conserved: &[Conserved]) -> Vec<(Conserved, f64)> {
        let r = &self.rec;
        let vec_drift = |data: &[f64], scale: f64| {
            let first = Vector3::new(data[0], data[1], data[2]);
            let denom = first.norm().max(scale).max(f64::MIN_POSITIVE);
            data.chunks_exact(3).map(|c| (Vector3::new(c[0], c[1], c[2]) - first).norm()).fold(0.0, f64::max) / denom
        };
        conserved
            .iter()
            .map(|&c| {
                let d = match c {
                    Conserved::LinearMomentum => vec_drift(&r.linear_momentum, self.scales.p),
                    Conserved::AngularMomentumOrigin => vec_drift(&r.angular_momentum_origin, self.scales.l_origin),
                    Conserved::AngularMomentumCom => vec_drift(&r.angular_momentum_com, self.scales.l_com),
                    Conserved::Energy => {
                        let e0 = r.energy[0];
                        let denom = e0.abs().max(self.scales.energy).max(f64::MIN_POSITIVE);
                        r.energy.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max) / denom
                    }
                };
                (c, d)
            })
            .collect()
    }
}

/// Saturation onsets: actuator kinds flagged in this step and not in the previous one.
fn onsets(t: f64, prev: &mut [u8], now: &[u8], events: &mut Vec<SaturationEvent>) {
    for (a, (p, &n)) in prev.iter_mut().zip(now).enumerate() {
        let new = n & !*p;
        if new != 0 {
            for kind in SaturationKind::ALL {
                if new & kind.bit() != 0 {
                    events.push(SaturationEvent { t, actuator: a, kind });
                }
            }
        }
        *p = n;
    }
}

/// Reports progress as a fraction of the simulated time, at most ~1000 times per run; an error
/// it returns (an interrupted run) stops the simulation.
pub type Progress<'a> = &'a mut dyn FnMut(f64) -> Result<()>;

/// Admission control of a simulation's records ([`crate::admission`]): `capacity` samples of
/// `width` values each, recorded in `f64` and copied once more by the caller that converts
/// them (so twice the records' size is counted).
fn admit_records(opts: &SimOptions, capacity: usize, width: usize) -> Result<()> {
    let remedy = match opts.integrator {
        IntegratorKind::Rk4 => "record fewer samples (record_every > 1 keeps every k-th step), or simulate a shorter duration",
        IntegratorKind::Dopri5 => "use a coarser output grid (dt is DOPRI5's output interval; the step size adapts on its own), or simulate a shorter duration",
    };
    crate::admission::admit(
        &format!("a simulation recording {capacity} samples of {width} values"),
        2.0 * crate::admission::bytes_of::<f64>(capacity as f64 * width as f64),
        remedy,
    )
}

/// Simulate `model` from `(x0, u0)` for `opts.duration` seconds under `controller`.
///
/// `x0` must be a valid configuration (unit quaternion within
/// [`crate::math::rotations::QUATERNION_TOLERANCE`]; it is normalized exactly); `u0` any finite
/// velocity (non-zero momentum is allowed). Deterministic: the same inputs give bit-identical
/// records.
pub fn simulate(model: &Model, x0: &[f64], u0: &[f64], opts: &SimOptions, controller: &mut dyn Controller, progress: Progress<'_>) -> Result<SimResult> {
    opts.validate()?;
    crate::error::check_vector("x0", x0, model.nx()).map_err(|e| match e {
        SpacearmError::Dimension { got, .. } => SpacearmError::Dimension { what: "x0".into(), expected: format!("7+N = {}", model.nx()), got },
        other => other,
    })?;
    split_configuration(model, x0)?;
    check_velocity(model, "u0", u0)?;
    let n = model.n_dof();
    let mut plant = Plant::new(model, opts, controller)?;
    let n_ref = plant.controller.reference_len();
    let tracking = plant.controller.tracking();
    let conserved = opts.mode.conserved(plant.controller.is_torque_free());
    let wheels = plant.wheels.clone();
    let mut y: Vec<f64> = x0.iter().chain(u0).copied().collect();
    let dim = y.len();
    plant.project(&mut y);

    // Sample times: RK4 every `record_every` steps of dt (plus the end); DOPRI5 every dt (plus
    // the end). Steps are at t_i = i·dt (computed by multiplication, not accumulation).
    let n_steps_rk4 = ((opts.duration / opts.dt) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
    let capacity = match opts.integrator {
        IntegratorKind::Rk4 => n_steps_rk4 / opts.record_every + 2,
        IntegratorKind::Dopri5 => n_steps_rk4 + 2,
    };
    let attitude = plant.controller.reports_attitude_error();
    admit_records(opts, capacity, Recorder::sample_width(model, wheels.len(), n_ref, tracking.is_some(), attitude))?;
    let mut rec = Recorder::new(model, capacity, &wheels, n_ref, tracking.is_some(), attitude);
    let mut events = Vec::new();
    let mut prev_flags = vec![0u8; n + 6];
    let mut dy = vec![0.0; dim];
    let mut n_steps = 0;
    let mut n_rejected = 0;
    let progress_every = opts.duration / 1000.0;
    let mut next_progress = 0.0;

    match opts.integrator {
        IntegratorKind::Rk4 => {
            let mut rk = Rk4::new(dim);
            for i in 0..n_steps_rk4 {
                let t = i as f64 * opts.dt;
                let t_next = if i + 1 == n_steps_rk4 { opts.duration } else { (i + 1) as f64 * opts.dt };
                plant.flags_step.fill(0);
                let record_now = i % opts.record_every == 0;
                if record_now {
                    plant.rhs(t, &y, rk.k1_mut())?;
                    rec.record(&plant, t, &y, rk.k1());
                }
                rk.step(&mut plant, t, t_next - t, &mut y, record_now)?;
                n_steps += 1;
                onsets(t, &mut prev_flags, &plant.flags_step, &mut events);
                if t_next >= next_progress {
                    progress(t_next / opts.duration)?;
                    next_progress = t_next + progress_every;
                }
            }
        }
        IntegratorKind::Dopri5 => {
            let mut dp = Dopri5::new(dim, opts.rtol, opts.atol);
            plant.rhs(0.0, &y, &mut dy)?;
            rec.record(&plant, 0.0, &y, &dy);
            let n_out = n_steps_rk4;
            let mut k_out = 1;
            let out_time = |k: usize| if k == n_out { opts.duration } else { k as f64 * opts.dt };
            let mut t = 0.0;
            let mut h = dp.initial_step(&mut plant, t, &y, opts.duration)?;
            let mut y_out = vec![0.0; dim];
            while t < opts.duration {
                if n_steps + n_rejected >= opts.max_steps {
                    return Err(SpacearmError::Simulation(format!(
                        "DOPRI5 used its budget of {} steps and reached only t = {t} s of {} s (loosen rtol/atol, raise \
                         max_steps, or use rk4)",
                        opts.max_steps, opts.duration
                    )));
                }
                let remaining = opts.duration - t;
                // Land exactly on the end; avoid a sliver of a last step.
                if h >= remaining || remaining - h < 1e-10 * opts.duration {
                    h = remaining;
                }
                plant.flags_step.fill(0);
                let outcome = match dp.try_step(&mut plant, t, h, &mut y) {
                    Ok(o) => o,
                    // A trial step so long that a stage left the finite numbers: reject it and
                    // retry shorter (y and f(t, y) are untouched by a failed attempt).
                    Err(SpacearmError::Simulation(_)) if plant.nonfinite_stage => {
                        plant.nonfinite_stage = false;
                        StepOutcome { accepted: false, error: f64::INFINITY, next_h: 0.25 * h }
                    }
                    Err(e) => return Err(e),
                };
                if outcome.accepted {
                    n_steps += 1;
                    onsets(t, &mut prev_flags, &plant.flags_step, &mut events);
                    let t_new = if h == remaining { opts.duration } else { t + h };
                    while k_out <= n_out && out_time(k_out) <= t_new {
                        let t_o = out_time(k_out);
                        if t_o == t_new {
                            y_out.copy_from_slice(&y);
                        } else {
                            dp.dense_output(t_o, &mut y_out);
                            plant.project(&mut y_out);
                        }
                        plant.rhs(t_o, &y_out, &mut dy)?;
                        rec.record(&plant, t_o, &y_out, &dy);
                        k_out += 1;
                        // A dense output grid can put many samples in one step: report (and
                        // let the caller interrupt) between them too.
                        if t_o >= next_progress {
                            progress(t_o / opts.duration)?;
                            next_progress = t_o + progress_every;
                        }
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
                    return Err(SpacearmError::Simulation(format!(
                        "DOPRI5 step size fell to {h:e} s at t = {t} s: the dynamics are too stiff or discontinuous there \
                         (a saturating actuator switching, a very high gain); loosen rtol/atol or use rk4"
                    )));
                }
            }
        }
    }
    if opts.integrator == IntegratorKind::Rk4 {
        plant.rhs(opts.duration, &y, &mut dy)?;
        rec.record(&plant, opts.duration, &y, &dy);
    }
    progress(1.0)?;
    let drift = rec.drift(&conserved);
    let drift_scales = conserved.iter().map(|&c| (c, rec.scale(c))).collect();
    Ok(SimResult {
        reference_width: n_ref,
        records: rec.rec,
        events,
        drift,
        drift_scales,
        n_steps,
        n_rejected,
        n_rhs_evals: plant.n_evals,
        actuator_names: Actuators::names(model),
        wheel_dofs: wheels,
        tracking,
        controller: plant.controller.name().to_string(),
        dropped_wrench_max: plant.dropped_max,
        dropped_wrench_count: plant.dropped_count,
    })
}
