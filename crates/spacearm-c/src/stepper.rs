//! The stepper handle: the core's fixed-step RK4 loop (`spacearm_core::sim::stepper`, the loop
//! of `spacearm.simulate` and `spacearm.Simulator`) with a native controller, stepped from C
//! with a joint torque and base wrench held over each step (docs/c-api.md, "Stepping").
//!
//! The options are TOML text, so that new options never change the ABI; the `[controller]`
//! table is the core's controller spec (`spacearm_core::control::spec::ControllerSpec`, the
//! same data `spacearm.simulate` runs; docs/c-api.md, "Controllers"):
//!
//! ```toml
//! mode = "floating"        # or rotation-floating, rotation-flying, translation-flying, flying
//! dt = 0.001               # the RK4 step, s, within [SPACEARM_MIN_DT, SPACEARM_MAX_DT]
//! joint_limits = true      # the joints' effort and velocity limits apply
//! wheels = [6, 7, 8]       # optional: the reaction-wheel dofs (default: detected)
//! thrusters = { max_force = 50.0, max_torque = [5.0, 5.0, 2.0] }  # optional, per axis of 𝒥
//! [controller]             # optional; default: kind = "none" (only the held torque acts)
//! kind = "joint_pd"        # any native kind of CONTROLLER_KINDS but "external"
//! kp = 100.0               # one gain or one per actuated arm joint
//! kd = [20.0, 20.0]
//! reference = [0.1, 0.2]   # a list: a constant set point; or a table, e.g. kind = "quintic"
//! ```
//!
//! With `[contact]`, the options may name a free target in the loop of contact (docs/contact.md,
//! "Contact with a free target"): `target = "rock.toml"` (its model TOML file) and
//! `target_state = [r, quat xyzw, v, ω]` (13); a relative path is read from the working
//! directory (`spacearm_stepper_new` takes the options as text; `spacearm_stepper_new_from_file`
//! reads it from the options file's folder). `spacearm_stepper_target_state` gives its state.
//! An FMU refuses a target (its variables carry the robot's state only).

use std::ffi::c_char;
use std::path::Path;

use nalgebra::{DVectorView, Vector6};
use spacearm_core::control::spec::{no_external, ControllerSpec};
use spacearm_core::control::Controller;
use spacearm_core::sim::integrate::IntegratorKind;
use spacearm_core::sim::options::RunSpec;
use spacearm_core::sim::simulate::{check_initial_state, Plant, SimOptions};
use spacearm_core::sim::stepper::Rk4Stepper;
use spacearm_core::Model;

use crate::model::{model_ref, SpacearmModel};
use crate::status::{free_handle, give, guard, guard_value, handle, input, optional_input, output, put, put_optional, text, write_text, Failure, Outcome, SpacearmStatus};

/// The most RK4 steps one call may take: `n` of `spacearm_stepper_step`, and `h / dt` of one
/// communication step `h` of an FMU (`fmi3DoStep`, `fmi2DoStep`). A call asking for more is
/// refused with `SPACEARM_STATUS_INVALID_ARGUMENT` (an FMU: `fmi3Error`/`fmi2Error` with a logged
/// message) before any step is taken, so no call runs unbounded (10⁵ steps of the 6-joint
/// spatial6 take about 0.5 s; split a longer run into several calls).
pub const SPACEARM_MAX_STEPS_PER_CALL: usize = 1_000_000;

/// The smallest RK4 step `dt` a stepper or an FMU accepts, s: with it, one call of
/// `SPACEARM_MAX_STEPS_PER_CALL` steps still covers 1 s.
pub const SPACEARM_MIN_DT: f64 = 1e-6;

/// The largest RK4 step `dt` a stepper or an FMU accepts, s (far beyond where a fixed-step RK4 of
/// an arm's dynamics is accurate; `1e300` is refused rather than overflowing the state).
pub const SPACEARM_MAX_DT: f64 = 10.0;

/// The one check of a number of RK4 steps asked of one call (see
/// [`SPACEARM_MAX_STEPS_PER_CALL`]); `steps` is a float so that an FMU's `h / dt` is checked
/// before it is converted (a cast of `1e300` would saturate to `usize::MAX`).
pub(crate) fn check_steps_per_call(steps: f64, what: &str) -> Outcome<usize> {
    if !(steps >= 0.0 && steps <= SPACEARM_MAX_STEPS_PER_CALL as f64) {
        return Err(Failure::argument(format!(
            "{what} needs {steps:e} RK4 steps in one call, more than the {SPACEARM_MAX_STEPS_PER_CALL} allowed \
             (SPACEARM_MAX_STEPS_PER_CALL); split it into several calls"
        )));
    }
    Ok(steps as usize)
}

/// Checked stepper options: the core's simulation options (as `spacearm.simulate` builds them
/// for an RK4 run of step `dt`) and the controller, as the core's spec.
#[derive(Debug, Clone)]
pub(crate) struct StepperOptions {
    pub sim: SimOptions,
    pub controller: ControllerSpec,
    /// A free target in the loop of contact: its model and 13-state.
    pub target: Option<(Model, Vec<f64>)>,
}

impl StepperOptions {
    /// Parse and check the options TOML against `model`: a TOML or serde error (an unknown key,
    /// an unknown controller kind, a value of the wrong type) is `Parse`; a value the core's
    /// checks refuse has the core's status (`InvalidArgument`, `Dimension`, `NotFound`, ...).
    pub(crate) fn parse(model: &Model, text: &str) -> Outcome<Self> {
        Self::parse_in(model, text, None)
    }

    /// [`StepperOptions::parse`] of an options file in the folder `base` (a relative `target`
    /// path is read from there; `None`: from the working directory).
    pub(crate) fn parse_in(model: &Model, text: &str, base: Option<&Path>) -> Outcome<Self> {
        // The core's run description (sim/options.rs RunSpec): the same names, defaults and
        // checks as spacearm.simulate's; the stepper adds its step bounds and steps RK4 only.
        let mut o: RunSpec = toml::from_str(text).map_err(|e| Failure::new(SpacearmStatus::Parse, format!("stepper options: {e}")))?;
        let target = o.free_target(base)?;
        if !(SPACEARM_MIN_DT..=SPACEARM_MAX_DT).contains(&o.dt) {
            return Err(Failure::argument(format!(
                "dt must be between {SPACEARM_MIN_DT:e} s and {SPACEARM_MAX_DT} s (SPACEARM_MIN_DT, SPACEARM_MAX_DT), got {:e} s",
                o.dt
            )));
        }
        if o.integrator != IntegratorKind::Rk4 {
            return Err(Failure::argument(format!(
                "integrator = \"{}\": the stepper and an FMU step with fixed RK4 steps of dt (integrator = \"rk4\")",
                o.integrator.name()
            )));
        }
        let sim = o.options(o.dt)?;
        sim.refuse_stop("the stepper")?;
        StepperOptions { sim, controller: ControllerSpec::None {}, target }.with_controller(model, o.controller.unwrap_or(ControllerSpec::None {}))
    }

    /// These options with the controller `spec`, checked against `model`: the spec's own checks,
    /// its construction on the plant (points, tasks) and the controller's setup (dimensions, the
    /// mode), as a run would do them.
    pub(crate) fn with_controller(&self, model: &Model, spec: ControllerSpec) -> Outcome<Self> {
        let options = StepperOptions { sim: self.sim.clone(), controller: spec, target: self.target.clone() };
        options.plant(model)?;
        Ok(options)
    }

    /// The plant of a run on `model` with a fresh controller (and the free target, if any).
    pub(crate) fn plant(&self, model: &Model) -> Outcome<Plant<'static>> {
        let controller = self.build_controller(model)?;
        Ok(match &self.target {
            Some((t, s)) => Plant::owned_with_target(model.clone(), &self.sim, controller, t, s)?,
            None => Plant::owned(model.clone(), &self.sim, controller)?,
        })
    }

    /// A fresh controller for a run on `model`.
    pub(crate) fn build_controller(&self, model: &Model) -> Outcome<Box<dyn Controller>> {
        Ok(self.controller.build(model, &mut no_external)?)
    }
}

/// Refuse options TOML `text` that names a free target where it cannot run: an FMU's variables
/// carry the robot's state only (docs/fmi.md), so no FMU is made of, nor instantiated from,
/// options with `target` or `target_state`.
pub(crate) fn refuse_target(text: &str, what: &str) -> Outcome {
    let doc: toml::Table = toml::from_str(text).map_err(|e| Failure::new(SpacearmStatus::Parse, format!("stepper options: {e}")))?;
    if doc.contains_key("target") || doc.contains_key("target_state") {
        return Err(Failure::argument(format!(
            "{what} with a free target (the options' target, target_state) is not implemented: an FMU's variables carry the robot's \
             state only; run the target with the C stepper (spacearm_stepper_target_state) or spacearm.simulate(target=...)"
        )));
    }
    Ok(())
}

/// `options` (stepper options TOML without a `[controller]` table) with the controller spec
/// TOML `controller` (a `ControllerSpec` document, as `ControllerSpec.to_toml()` of the Python
/// binding writes it) as its `[controller]` table: the one document the stepper and an FMU read.
/// Both are parsed and the result written by the TOML serializer (numbers in shortest
/// round-trip form, so the spec is carried bit for bit); nothing is checked against a model.
pub(crate) fn options_with_controller(options: &str, controller: &str) -> Outcome<String> {
    let mut doc: toml::Table = toml::from_str(options).map_err(|e| Failure::new(SpacearmStatus::Parse, format!("options_toml: {e}")))?;
    if doc.contains_key("controller") {
        return Err(Failure::argument("options_toml already has a [controller] table; pass the options without it"));
    }
    let spec: ControllerSpec = toml::from_str(controller).map_err(|e| Failure::new(SpacearmStatus::Parse, format!("controller_toml: {e}")))?;
    let table = toml::Value::try_from(&spec).map_err(|e| Failure::new(SpacearmStatus::Internal, format!("the controller spec as TOML: {e}")))?;
    doc.insert("controller".into(), table);
    toml::to_string(&doc).map_err(|e| Failure::new(SpacearmStatus::Internal, format!("the options as TOML: {e}")))
}

/// The stepper options TOML `options_toml` (without a `[controller]` table; NULL: the
/// defaults) with the controller spec TOML `controller_toml` (the fields of a `[controller]`
/// table as a document of their own: `kind = ...`, nested tables as `[reference]`) as its
/// `[controller]` table, written NUL-terminated into `buf` (`len` bytes, `*needed` the size
/// needed; `len = 0` asks for it). Used by `spacearm.fmi.export` to write an FMU's
/// `options.toml` from the spec `spacearm.simulate` runs.
///
/// # Safety
/// `options_toml` NULL or NUL-terminated; `controller_toml` NUL-terminated; `buf` NULL or `len`
/// writable bytes; `needed` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn spacearm_options_with_controller(
    options_toml: *const c_char,
    controller_toml: *const c_char,
    buf: *mut c_char,
    len: usize,
    needed: *mut usize,
) -> SpacearmStatus {
    guard(|| {
        // SAFETY (this block and below): the caller's contract, documented above.
        let options = if options_toml.is_null() { "" } else { unsafe { text(options_toml, "options_toml") }? };
        let controller = unsafe { text(controller_toml, "controller_toml") }?;
        let out = options_with_controller(options, controller)?;
        unsafe { write_text(&out, buf, len, needed) }
    })
}

/// A stepping simulation of its own copy of a model: RK4 at a fixed step with a native
/// controller; free it with `spacearm_stepper_free`. Not for use by two threads at once.
pub struct SpacearmStepper {
    pub(crate) model: Model,
    pub(crate) options: StepperOptions,
    pub(crate) stepper: Option<Rk4Stepper<'static>>,
    tau: Vec<f64>,
}

impl SpacearmStepper {
    pub(crate) fn new(model: Model, options: StepperOptions) -> Self {
        let n = model.n_dof();
        SpacearmStepper { model, options, stepper: None, tau: vec![0.0; n] }
    }

    /// Start again at `t = 0` from `(x0, u0)` with a fresh controller.
    pub(crate) fn reset(&mut self, x0: &[f64], u0: &[f64]) -> Outcome {
        check_initial_state(&self.model, x0, u0)?;
        let plant = self.options.plant(&self.model)?;
        self.stepper = Some(Rk4Stepper::new(plant, x0, u0, None)?);
        Ok(())
    }

    /// The running loop, or the failure of a stepper not yet reset.
    fn running(&self) -> Outcome<&Rk4Stepper<'static>> {
        self.stepper.as_ref().ok_or_else(not_reset)
    }

    fn running_mut(&mut self) -> Outcome<&mut Rk4Stepper<'static>> {
        self.stepper.as_mut().ok_or_else(not_reset)
    }

    /// `n` steps of `dt` with `tau` (N) and `base_wrench` (6) held, landing on `t = i·dt`; at
    /// most [`SPACEARM_MAX_STEPS_PER_CALL`].
    pub(crate) fn step(&mut self, tau: Option<&[f64]>, base_wrench: Option<&[f64]>, n: usize) -> Outcome {
        check_steps_per_call(n as f64, &format!("n = {n}"))?;
        if let Some(t) = tau {
            crate::status::finite("tau", t)?;
        }
        if let Some(w) = base_wrench {
            crate::status::finite("base_wrench", w)?;
        }
        let dt = self.options.sim.dt;
        match tau {
            Some(t) => self.tau.copy_from_slice(t),
            None => self.tau.fill(0.0),
        }
        let w = base_wrench.map(Vector6::from_column_slice).unwrap_or_else(Vector6::zeros);
        let held = (tau.is_some() || base_wrench.is_some()).then_some(w);
        let tau_buf = std::mem::take(&mut self.tau);
        let result = (|| {
            let s = self.running_mut()?;
            s.plant_mut().set_held_input(held.map(|w| (tau_buf.as_slice(), w)));
            for _ in 0..n {
                let t_next = (s.n_steps() + 1) as f64 * dt;
                s.step_to(t_next)?;
            }
            Ok(())
        })();
        self.tau = tau_buf;
        result
    }

    pub(crate) fn state(&self) -> Option<&[f64]> {
        self.stepper.as_ref().map(|s| s.state())
    }
}

fn not_reset() -> Failure {
    Failure::argument("the stepper has no state yet; call spacearm_stepper_reset first")
}

/// The stepper behind a handle, or a NullPointer failure.
///
/// # Safety
/// `s` NULL or a live stepper handle.
unsafe fn stepper_ref<'a>(s: *const SpacearmStepper) -> Outcome<&'a SpacearmStepper> {
    // SAFETY: the caller's contract.
    unsafe { handle(s, "stepper", "a handle from spacearm_stepper_new") }
}

/// [`stepper_ref`], to change it.
///
/// # Safety
/// `s` NULL or a live stepper handle, not in use elsewhere.
unsafe fn stepper_mut<'a>(s: *mut SpacearmStepper) -> Outcome<&'a mut SpacearmStepper> {
    // SAFETY: the caller's contract (`stepper_ref` refuses NULL).
    unsafe {
        stepper_ref(s)?;
        Ok(&mut *s)
    }
}

/// The entry points that make a stepper: `*out` receives a stepper of a copy of `model` with
/// the options `parse` reads (from the model) under [`guard`].
///
/// # Safety
/// `model` NULL or a live handle; `out` NULL or writable; `parse` reads its pointers under the
/// caller's contract.
unsafe fn new_stepper(model: *const SpacearmModel, out: *mut *mut SpacearmStepper, parse: impl FnOnce(&Model) -> Outcome<StepperOptions>) -> SpacearmStatus {
    guard(|| {
        // SAFETY (this block and below): the caller's contract.
        let m = unsafe { model_ref(model) }?;
        let opts = parse(&m.model)?;
        unsafe { give(SpacearmStepper::new(m.model.clone(), opts), out, "SpacearmStepper") }
    })
}

/// A stepper for a copy of `model` with the options TOML `options` (NULL: the defaults,
/// floating mode, dt = 1 ms, no controller; see docs/c-api.md). Call `spacearm_stepper_reset`
/// before stepping.
///
/// # Safety
/// `model` a live handle; `options` NULL or a NUL-terminated string; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn spacearm_stepper_new(model: *const SpacearmModel, options: *const c_char, out: *mut *mut SpacearmStepper) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe { new_stepper(model, out, |m| StepperOptions::parse(m, if options.is_null() { "" } else { text(options, "options")? })) }
}

/// A stepper for a copy of `model` with the options read from the TOML file `path` (a relative
/// `target` path in it is read from the file's folder; see `spacearm_stepper_new`).
///
/// # Safety
/// `model` a live handle; `path` a NUL-terminated string; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn spacearm_stepper_new_from_file(model: *const SpacearmModel, path: *const c_char, out: *mut *mut SpacearmStepper) -> SpacearmStatus {
    // SAFETY (this block and below): the caller's contract, documented above.
    unsafe {
        new_stepper(model, out, |m| {
            let path = Path::new(text(path, "path")?);
            let text = std::fs::read_to_string(path).map_err(|e| Failure::new(SpacearmStatus::Io, format!("{}: cannot read the options file: {e}", path.display())))?;
            StepperOptions::parse_in(m, &text, Some(path.parent().unwrap_or(Path::new(""))))
        })
    }
}

/// Free a stepper (NULL is ignored).
///
/// # Safety
/// `stepper` NULL or a handle not yet freed; not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn spacearm_stepper_free(stepper: *mut SpacearmStepper) {
    // SAFETY: a handle from `spacearm_stepper_new*`, freed once (caller's contract).
    unsafe { free_handle(stepper) }
}

/// Start at `t = 0` from `x0` (7+N) and `u0` (6+N) with a fresh controller.
///
/// # Safety
/// `stepper` a live handle; `x0` 7+N and `u0` 6+N doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_stepper_reset(stepper: *mut SpacearmStepper, x0: *const f64, u0: *const f64) -> SpacearmStatus {
    guard(|| {
        // SAFETY (this block and below): the caller's contract, documented above.
        let s = unsafe { stepper_mut(stepper) }?;
        let (nx, nu) = (s.model.nx(), s.model.nu());
        let (x0, u0) = unsafe { (input(x0, nx, "x0")?, input(u0, nu, "u0")?) };
        s.reset(x0, u0)
    })
}

/// Advance `n` RK4 steps of `dt` with the joint torque `tau` (N, NULL: zero) and the base wrench
/// `base_wrench` (`[F0, N0]` in 𝒥 at the base CM, 6, NULL: zero) added to the controller's
/// command and held over the steps; the mode's mask and the actuator limits apply as in
/// `spacearm.simulate`. `n` is at most `SPACEARM_MAX_STEPS_PER_CALL` (more is refused with
/// `SPACEARM_STATUS_INVALID_ARGUMENT` before any step). A failed step leaves the stepper needing
/// a reset.
///
/// # Safety
/// `stepper` a live handle; `tau` NULL or N doubles; `base_wrench` NULL or 6 doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_stepper_step(stepper: *mut SpacearmStepper, tau: *const f64, base_wrench: *const f64, n: usize) -> SpacearmStatus {
    guard(|| {
        // SAFETY (this block and below): the caller's contract, documented above.
        let s = unsafe { stepper_mut(stepper) }?;
        let nd = s.model.n_dof();
        let (tau, w) = unsafe { (optional_input(tau, nd, "tau")?, optional_input(base_wrench, 6, "base_wrench")?) };
        s.step(tau, w, n)
    })
}

/// The current time, s (NaN for a NULL or not yet reset stepper).
///
/// # Safety
/// `stepper` NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn spacearm_stepper_time(stepper: *const SpacearmStepper) -> f64 {
    guard_value(f64::NAN, || {
        // SAFETY: the caller's contract.
        Ok(unsafe { stepper_ref(stepper) }?.running()?.time())
    })
}

/// The current state: `x_out` (7+N) and `u_out` (6+N); either may be NULL.
///
/// # Safety
/// `stepper` a live handle; `x_out` NULL or 7+N, `u_out` NULL or 6+N writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_stepper_state(stepper: *const SpacearmStepper, x_out: *mut f64, u_out: *mut f64) -> SpacearmStatus {
    guard(|| {
        // SAFETY (this block and below): the caller's contract, documented above.
        let s = unsafe { stepper_ref(stepper) }?;
        let nx = s.model.nx();
        let y = s.running()?.state();
        let (x, u) = (DVectorView::from_slice(&y[..nx], nx), DVectorView::from_slice(&y[nx..], y.len() - nx));
        unsafe {
            put_optional("the state x_out", &x, x_out)?;
            put_optional("the state u_out", &u, u_out)
        }
    })
}

/// The free target's 13-state `[r, quat xyzw, v, ω]` (in 𝒥) into `out` (13 doubles), for a
/// stepper whose options name a target; `SPACEARM_STATUS_INVALID_ARGUMENT` without one.
///
/// # Safety
/// `stepper` a live handle; `out` 13 writable doubles.
#[no_mangle]
pub unsafe extern "C" fn spacearm_stepper_target_state(stepper: *const SpacearmStepper, out: *mut f64) -> SpacearmStatus {
    guard(|| {
        // SAFETY (this block and below): the caller's contract, documented above.
        let t = unsafe { stepper_ref(stepper) }?.running()?.target_state().ok_or_else(|| Failure::argument("the stepper has no free target (its options name none: target = \"...toml\", target_state = [...])"))?;
        put("the target's state", t, unsafe { output(out, 13, "out") }?)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use spacearm_core::model::builder::{LinkSpec, ModelBuilder};
    use spacearm_core::model::joint::{JointDynamics, JointLimits, JointType};

    /// Two actuated links and a passive sprung panel between them in dof order.
    fn arm_with_panel() -> Model {
        let mut b = ModelBuilder::new("p", "base", 100.0, [[10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]]).unwrap();
        let link = |name: &str, parent: &str, origin: [f64; 3]| LinkSpec {
            name: name.into(),
            parent: parent.into(),
            joint_name: None,
            kind: JointType::Revolute,
            origin_in_parent: origin,
            rotation_in_parent: [0.0, 0.0, 0.0, 1.0],
            axis: [0.0, 1.0, 0.0],
            com_from_joint: [0.4, 0.0, 0.0],
            mass: 3.0,
            inertia: [[0.05, 0.0, 0.0], [0.0, 0.3, 0.0], [0.0, 0.0, 0.3]],
            limits: JointLimits::unlimited(),
        };
        b.add_link(link("l1", "base", [0.6, 0.0, 0.0])).unwrap();
        b.add_link(link("panel", "base", [-0.6, 0.0, 0.0])).unwrap();
        b.set_joint_dynamics("panel", JointDynamics { actuated: false, stiffness: 20.0, damping: 0.1, rest: 0.0 }).unwrap();
        b.add_link(link("l2", "l1", [0.8, 0.0, 0.0])).unwrap();
        b.build().unwrap()
    }

    #[test]
    fn the_steps_of_one_call_and_dt_are_bounded() {
        assert_eq!(check_steps_per_call(SPACEARM_MAX_STEPS_PER_CALL as f64, "n").unwrap(), SPACEARM_MAX_STEPS_PER_CALL);
        for steps in [SPACEARM_MAX_STEPS_PER_CALL as f64 + 1.0, 1e303, f64::INFINITY, f64::NAN, usize::MAX as f64] {
            assert_eq!(check_steps_per_call(steps, "n").unwrap_err().status, SpacearmStatus::InvalidArgument, "{steps}");
        }
        let m = arm_with_panel();
        for dt in ["1e-300", "1e300", "9.99e-7", "10.01", "nan", "-inf", "0.0"] {
            let e = StepperOptions::parse(&m, &format!("dt = {dt}\n")).unwrap_err();
            assert!(e.status == SpacearmStatus::InvalidArgument && e.message.starts_with("dt must be between"), "{dt}: {}", e.message);
        }
        for dt in [SPACEARM_MIN_DT, SPACEARM_MAX_DT] {
            assert!(StepperOptions::parse(&m, &format!("dt = {dt:?}\n")).is_ok());
        }
        let mut s = SpacearmStepper::new(m.clone(), StepperOptions::parse(&m, "").unwrap());
        let (x0, u0) = (spacearm_core::model::presets::initial_configuration(&m), vec![0.0; m.nu()]);
        s.reset(&x0, &u0).unwrap();
        assert_eq!(s.step(None, None, usize::MAX).unwrap_err().status, SpacearmStatus::InvalidArgument);
        assert_eq!(s.stepper.as_ref().unwrap().n_steps(), 0);
    }

    #[test]
    fn the_set_point_has_one_entry_per_actuated_arm_joint() {
        let m = arm_with_panel();
        let pd = |reference: &str| StepperOptions::parse(&m, &format!("[controller]\nkind = \"joint_pd\"\nkp = [2.0]\nkd = [0.5]\nreference = {reference}\n"));
        assert!(pd("[0.1, 0.2]").is_ok());
        // The passive panel takes no reference: three entries are refused at parse, by the
        // controller's setup on the plant.
        let e = pd("[0.1, 0.0, 0.2]").unwrap_err();
        assert_eq!(e.status, SpacearmStatus::Dimension, "{}", e.message);
        // The old key of the schema the core's spec replaced is an unknown field.
        let e = StepperOptions::parse(&m, "[controller]\nkind = \"joint_pd\"\nkp = 2.0\nkd = 0.5\nq_ref = [0.1, 0.2]\n").unwrap_err();
        assert!(e.status == SpacearmStatus::Parse && e.message.contains("q_ref"), "{}", e.message);
    }

    #[test]
    fn a_controller_document_becomes_the_options_controller_table() {
        let spec = "kind = \"combined\"\n\n[arm]\nkind = \"joint_pd\"\nkp = [60.0]\nkd = [20.0]\nreference = [0.1, 0.2]\n\n[base]\nkind = \"none\"\n";
        let text = options_with_controller("mode = \"floating\"\ndt = 0.002\n", spec).unwrap();
        let m = arm_with_panel();
        let o = StepperOptions::parse(&m, &text).unwrap();
        assert_eq!(o.sim.dt, 0.002);
        assert_eq!(o.controller, toml::from_str::<ControllerSpec>(spec).unwrap());
        // A number keeps its last bit through the text.
        let third = 1.0 / 3.0;
        let text = options_with_controller("", &format!("kind = \"joint_pd\"\nkp = {third:?}\nkd = 1.0\nreference = [{third:?}, 0.0]\n")).unwrap();
        match StepperOptions::parse(&m, &text).unwrap().controller {
            ControllerSpec::JointPd { kp, .. } => assert_eq!(kp.0, vec![third]),
            other => panic!("{other:?}"),
        }
        let e = options_with_controller("[controller]\nkind = \"none\"\n", "kind = \"none\"").unwrap_err();
        assert_eq!(e.status, SpacearmStatus::InvalidArgument);
        let e = options_with_controller("", "kind = \"pid\"").unwrap_err();
        assert!(e.status == SpacearmStatus::Parse && e.message.contains("pid"), "{}", e.message);
    }
}
