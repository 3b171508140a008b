//! The FMI co-simulation unit (docs/fmi.md): one [`Instance`] per instantiated FMU, shared by
//! the FMI 2 ([`fmi2`]) and FMI 3 ([`fmi3`]) entry points, and the model description
//! ([`variables`]) that `spacearm.fmi.export` asks this library for.
//!
//! An FMU's `resources/` holds `model.toml` (the model, docs/model-format.md),
//! `options.toml` (the stepper options of [`crate::stepper`]: mode, RK4 step, actuators and the
//! controller as the core's `ControllerSpec`, whose numbers are the FMU's parameters,
//! [`parameters`]) and
//! `token.txt` (the instantiation token, checked at instantiation). A
//! communication step of `h` is `h / dt` RK4 steps of the core's loop with the inputs held
//! (the loop of `spacearm.simulate`), so an FMU run equals `spacearm.simulate` of the same model
//! and inputs (tests/fmi/test_fmu.py).

pub mod fmi2;
pub mod fmi3;
pub mod parameters;
pub mod variables;

use std::ffi::{c_char, c_int, c_void, CStr};
use std::path::{Path, PathBuf};

use nalgebra::{Rotation3, UnitQuaternion, Vector3};
use spacearm_core::algorithms::{kinematics, momentum};
use spacearm_core::{Data, Model};

use crate::status::{caught, guard, put, text, write_text, Failure, Outcome, SpacearmStatus};
use crate::stepper::{check_steps_per_call, SpacearmStepper, StepperOptions};
use variables::{Causality, FmiVersion, Layout};

/// Where an instance is in the FMI state machine (the states both versions share).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Phase {
    Instantiated,
    Initialization,
    Stepping,
    Terminated,
    /// A step failed: only reset or free may follow.
    Failed,
}

/// How an instance reports: `(is_error, message)`.
pub(crate) type Logger = Box<dyn Fn(bool, &str)>;

/// One FMU instance: its model, the variable table, the values (indexed by value reference)
/// and the stepper.
pub(crate) struct Instance {
    pub name: String,
    model: Model,
    data: Data,
    layout: Layout,
    options: StepperOptions,
    stepper: Option<SpacearmStepper>,
    values: Vec<f64>,
    last_quat: Option<UnitQuaternion<f64>>,
    pub phase: Phase,
    pub logger: Logger,
    pub logging_on: bool,
}

fn read(dir: &Path, file: &str) -> Outcome<String> {
    let p = dir.join(file);
    std::fs::read_to_string(&p).map_err(|e| Failure::new(SpacearmStatus::Io, format!("cannot read the FMU resource '{}': {e}", p.display())))
}

/// The file of `resources/` that holds the FMU's instantiation token (FMI 3
/// `instantiationToken`, FMI 2 `guid`), the same text as in its `modelDescription.xml`; written
/// by `spacearm.fmi.export`. (The folder above `resources/` is not read: importers such as FMPy
/// extract only `binaries/` and `resources/` to run an FMU.)
pub(crate) const TOKEN_FILE: &str = "token.txt";

/// Check the instantiation token an importer passed (FMI 3 `instantiationToken`, FMI 2 `guid`)
/// against the FMU's own ([`TOKEN_FILE`]): a binary instantiated with another FMU's token (or
/// with none) is refused, as FMI 3 §2.3.1 and FMI 2 §2.1.5 ask.
pub(crate) fn check_token(resources: &Path, version: FmiVersion, given: Option<&str>) -> Outcome {
    let attribute = match version {
        FmiVersion::Fmi3 => "instantiationToken",
        FmiVersion::Fmi2 => "guid",
    };
    let expected = read(resources, TOKEN_FILE)?;
    let expected = expected.trim_end_matches(['\n', '\r']);
    match given {
        Some(g) if g == expected => Ok(()),
        Some(g) => Err(Failure::argument(format!(
            "the {attribute} '{g}' passed to instantiate is not this FMU's '{expected}' (its modelDescription.xml): \
             the importer took the token of another FMU or of another export of this one"
        ))),
        None => Err(Failure::argument(format!("the {attribute} passed to instantiate is NULL; this FMU's is '{expected}'"))),
    }
}

impl Instance {
    /// An instance from the FMU's `resources/` folder, after [`check_token`].
    pub(crate) fn from_resources(dir: &Path, version: FmiVersion, token: Option<&str>, name: String, logger: Logger, logging_on: bool) -> Outcome<Instance> {
        check_token(dir, version, token)?;
        let model = crate::model::model_from_toml(&read(dir, "model.toml")?, "resources/model.toml")?;
        let text = read(dir, "options.toml")?;
        crate::stepper::refuse_target(&text, "an FMU")?;
        let options = StepperOptions::parse(&model, &text)?;
        let layout = Layout::new(&model, &options)?;
        let values = layout.vars.iter().map(|v| v.start).collect();
        Ok(Instance { name, data: Data::new(&model), model, layout, options, stepper: None, values, last_quat: None, phase: Phase::Instantiated, logger, logging_on })
    }

    pub(crate) fn log_info(&self, msg: &str) {
        if self.logging_on {
            (self.logger)(false, msg);
        }
    }

    fn variable(&self, vr: u32) -> Result<usize, String> {
        let i = vr as usize;
        if i < self.values.len() {
            Ok(i)
        } else {
            Err(format!("value reference {vr} does not exist (this FMU has 0..{})", self.values.len() - 1))
        }
    }

    /// Set the variables `vrs` to `values`.
    pub(crate) fn set(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String> {
        if vrs.len() != values.len() {
            return Err(format!("{} value references but {} values", vrs.len(), values.len()));
        }
        for (&vr, &v) in vrs.iter().zip(values) {
            let i = self.variable(vr)?;
            let var = &self.layout.vars[i];
            match var.causality {
                Causality::Input => {}
                Causality::Parameter if matches!(self.phase, Phase::Instantiated | Phase::Initialization) => {}
                Causality::Parameter => return Err(format!("parameter '{}' is fixed: it can be set only before the end of initialization", var.name)),
                _ => return Err(format!("variable '{}' is an {}; only inputs and parameters can be set", var.name, if var.causality == Causality::Output { "output" } else { "independent variable" })),
            }
            if !v.is_finite() {
                return Err(format!("variable '{}' must be finite, got {v}", var.name));
            }
            self.values[i] = v;
        }
        Ok(())
    }

    /// The values of the variables `vrs` into `out`.
    pub(crate) fn get(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), String> {
        if vrs.len() != out.len() {
            return Err(format!("{} value references but room for {} values", vrs.len(), out.len()));
        }
        if self.phase == Phase::Initialization {
            // The outputs of the initial state as the parameters now give it.
            let (x0, u0) = (self.values[self.layout.x0.clone()].to_vec(), self.values[self.layout.u0.clone()].to_vec());
            self.last_quat = None;
            self.outputs(&x0, &u0).map_err(|f| f.message)?;
        }
        for (&vr, o) in vrs.iter().zip(out.iter_mut()) {
            *o = self.values[self.variable(vr)?];
        }
        Ok(())
    }

    /// Compute the outputs of the state `(x, u)` into the values.
    fn outputs(&mut self, x: &[f64], u: &[f64]) -> Outcome {
        let l = &self.layout;
        put("the output x", x, &mut self.values[l.x.clone()])?;
        put("the output u", u, &mut self.values[l.u.clone()])?;
        let p = momentum::momentum(&self.model, &mut self.data, x, u)?;
        let m = l.momentum.start;
        put("the output P", p.linear.as_slice(), &mut self.values[m..m + 3])?;
        put("the output L", p.angular_about_origin.as_slice(), &mut self.values[m + 3..m + 6])?;
        if let (Some(pos), Some(quat), Some(ee)) = (l.ee_position.clone(), l.ee_quat.clone(), self.model.end_effector()) {
            let point = &self.model.points()[ee];
            kinematics::forward_kinematics(&self.model, &mut self.data, x)?;
            let r: Vector3<f64> = kinematics::point_position(&self.data, point.body, &point.offset);
            put("the output ee_position", r.as_slice(), &mut self.values[pos])?;
            // As the simulation records it (sim::record): the body's attitude, sign continuous.
            let mut q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(self.data.body_to_world[point.body]));
            if let Some(last) = self.last_quat {
                if last.coords.dot(&q.coords) < 0.0 {
                    q = UnitQuaternion::new_unchecked(-q.into_inner());
                }
            }
            self.last_quat = Some(q);
            put("the output ee_quat", q.coords.as_slice(), &mut self.values[quat])?;
        }
        Ok(())
    }

    fn state_outputs(&mut self) -> Outcome {
        let s = self.stepper.as_ref().and_then(|s| s.state()).ok_or_else(|| Failure::argument("the FMU has no state"))?.to_vec();
        let nx = self.model.nx();
        self.values[0] = self.stepper.as_ref().and_then(|s| s.stepper.as_ref()).map(|s| s.time()).unwrap_or(0.0);
        self.outputs(&s[..nx], &s[nx..])
    }

    pub(crate) fn enter_initialization(&mut self) -> Result<(), String> {
        if self.phase != Phase::Instantiated {
            return Err(format!("initialization mode can be entered only once after instantiation or reset (the FMU is {:?})", self.phase));
        }
        self.phase = Phase::Initialization;
        Ok(())
    }

    /// Start the simulation from the parameters' initial state, gains and set point.
    pub(crate) fn exit_initialization(&mut self) -> Result<(), String> {
        if self.phase != Phase::Initialization {
            return Err(format!("exit initialization mode called outside initialization mode (the FMU is {:?})", self.phase));
        }
        let l = &self.layout;
        let spec = l.parameters.spec(&self.values[l.controller.clone()]).map_err(|f| f.message)?;
        let options = self.options.with_controller(&self.model, spec).map_err(|f| format!("the controller's parameters: {}", f.message))?;
        let (x0, u0) = (self.values[l.x0.clone()].to_vec(), self.values[l.u0.clone()].to_vec());
        let mut stepper = SpacearmStepper::new(self.model.clone(), options);
        stepper.reset(&x0, &u0).map_err(|f| f.message)?;
        self.stepper = Some(stepper);
        self.last_quat = None;
        self.state_outputs().map_err(|f| f.message)?;
        self.phase = Phase::Stepping;
        self.log_info(&format!("{}: initialized at t = 0 with {} RK4 steps of {} s per second", self.name, (1.0 / self.options.sim.dt).round(), self.options.sim.dt));
        Ok(())
    }

    /// One communication step from `t` to `t + h`: `h / dt` RK4 steps with the inputs held, at
    /// most [`crate::stepper::SPACEARM_MAX_STEPS_PER_CALL`] (a longer step is refused before any
    /// RK4 step is taken).
    pub(crate) fn do_step(&mut self, t: f64, h: f64) -> Result<(), String> {
        if self.phase != Phase::Stepping {
            return Err(format!("doStep needs an initialized FMU (the FMU is {:?})", self.phase));
        }
        let dt = self.options.sim.dt;
        let now = self.values[0];
        if (t - now).abs() > 1e-9 * dt.max(now.abs()) {
            return Err(format!("the communication point {t} s is not the FMU's time {now} s"));
        }
        let steps = (h / dt).round();
        if !h.is_finite() || h <= 0.0 || steps < 1.0 || (steps * dt - h).abs() > 1e-6 * dt {
            return Err(format!("the communication step {h} s must be a positive multiple of the FMU's RK4 step {dt} s (set when the FMU was exported)"));
        }
        let steps = check_steps_per_call(steps, &format!("the communication step {h} s (RK4 steps of {dt} s)")).map_err(|f| f.message)?;
        let l = &self.layout;
        let tau = self.values[l.tau.clone()].to_vec();
        let wrench = l.base_wrench.clone().map(|r| self.values[r].to_vec());
        let stepper = self.stepper.as_mut().ok_or("the FMU has no state")?;
        if let Err(f) = stepper.step(Some(&tau), wrench.as_deref(), steps) {
            self.phase = Phase::Failed;
            return Err(format!("the step from t = {t} s failed: {}", f.message));
        }
        match self.state_outputs() {
            Ok(()) => Ok(()),
            Err(f) => {
                // An output that is not finite (a state beyond double precision): no going on.
                self.phase = Phase::Failed;
                Err(format!("after the step from t = {t} s: {}", f.message))
            }
        }
    }

    /// `fmi2SetDebugLogging`, `fmi3SetDebugLogging`: log the informational messages or not.
    pub(crate) fn set_logging(&mut self, on: bool) -> Result<(), String> {
        self.logging_on = on;
        Ok(())
    }

    /// `fmi2Terminate`, `fmi3Terminate`.
    pub(crate) fn terminate(&mut self) -> Result<(), String> {
        self.phase = Phase::Terminated;
        Ok(())
    }

    /// Back to the state just after instantiation (start values, no simulation): `fmi2Reset`,
    /// `fmi3Reset` (it cannot fail).
    pub(crate) fn reset(&mut self) -> Result<(), String> {
        self.values = self.layout.vars.iter().map(|v| v.start).collect();
        self.stepper = None;
        self.last_quat = None;
        self.phase = Phase::Instantiated;
        Ok(())
    }
}

/// `fmi2OK` / `fmi3OK` (the status codes are the same in both versions).
pub(crate) const FMI_OK: c_int = 0;
/// `fmi2Error` / `fmi3Error`.
pub(crate) const FMI_ERROR: c_int = 3;

/// The instance of the importer's handle `c` (FMI 2's component, FMI 3's instance) running
/// `body` through [`run_fmi`], as the entry point's status; a NULL handle is an error.
///
/// # Safety
/// `c` NULL or an instance from [`instantiate`].
pub(crate) unsafe fn with(c: *mut c_void, body: impl FnOnce(&mut Instance) -> Result<(), String>) -> c_int {
    // SAFETY: the importer's contract: `c` is an instance of this library.
    let done = match unsafe { c.cast::<Instance>().as_mut() } {
        None => Err(()),
        Some(inst) => run_fmi(inst, body),
    };
    if done.is_ok() { FMI_OK } else { FMI_ERROR }
}

/// Entry points `fn name(c: Handle) -> Status` of FMI 2 or 3 that are one call on the instance
/// (`name => Instance::method`): the state-machine steps both versions share.
macro_rules! instance_entry_points {
    ($handle:ty, $status:ty; $($name:ident => $body:expr),* $(,)?) => {
        $(
            /// # Safety
            /// The FMI contract: `c` NULL or an instance of this library.
            #[no_mangle]
            pub unsafe extern "C" fn $name(c: $handle) -> $status {
                // SAFETY: the FMI contract.
                unsafe { super::with(c, $body) }
            }
        )*
    };
}
pub(crate) use instance_entry_points;

/// The instance name the importer gave (`"spacearm"` for NULL).
///
/// # Safety
/// `name` NULL or a NUL-terminated string.
pub(crate) unsafe fn instance_name(name: *const c_char) -> String {
    // SAFETY: the caller's contract.
    if name.is_null() { String::from("spacearm") } else { unsafe { CStr::from_ptr(name) }.to_string_lossy().into_owned() }
}

/// A new instance as the importer's handle, or NULL (the body of `fmi2Instantiate` and
/// `fmi3InstantiateCoSimulation`, a panic caught): `resources` checks the version's own
/// arguments and gives the `resources/` folder; the instance made from there is checked against
/// the importer's `token` (GUID / instantiation token). A failure is logged through
/// `logger(instance name)`, or `logger("spacearm")` once that went into the failed attempt.
///
/// # Safety
/// `name` and `token` NULL or NUL-terminated strings; `resources` reads its pointers under the
/// importer's contract.
pub(crate) unsafe fn instantiate(
    version: FmiVersion,
    name: *const c_char,
    token: *const c_char,
    logging_on: bool,
    logger: impl Fn(&str) -> Logger,
    resources: impl FnOnce() -> Result<PathBuf, String>,
) -> *mut c_void {
    let made = caught(|| {
        // SAFETY (this block and below): the caller's contract.
        let name = unsafe { instance_name(name) };
        let log = logger(&name);
        match resources() {
            Err(m) => log(true, &m),
            Ok(dir) => {
                let token = if token.is_null() { None } else { Some(unsafe { CStr::from_ptr(token) }.to_string_lossy().into_owned()) };
                match Instance::from_resources(&dir, version, token.as_deref(), name, log, logging_on) {
                    Ok(inst) => return Ok(Box::into_raw(Box::new(inst)).cast::<c_void>()),
                    Err(f) => logger("spacearm")(true, &f.message),
                }
            }
        }
        Ok(std::ptr::null_mut())
    });
    made.unwrap_or(std::ptr::null_mut())
}

/// Free the instance of the importer's handle `c` (NULL: nothing), a panic caught.
///
/// # Safety
/// `c` NULL or an instance from [`instantiate`], freed once.
pub(crate) unsafe fn free_handle(c: *mut c_void) {
    // SAFETY: the caller's contract.
    unsafe { crate::status::free_handle(c.cast::<Instance>()) }
}

/// Call the importer's logger (its code: a panic there must not unwind through the FMI
/// boundary either; it is caught and dropped).
pub(crate) fn log_caught(log: impl FnOnce()) {
    let _ = caught(|| {
        log();
        Ok(())
    });
}

/// The unit starts at `t = 0` (the experiment's start time the importer passes).
pub(crate) fn check_start_time(start_time: f64) -> Result<(), String> {
    if start_time != 0.0 {
        return Err(format!("the FMU starts at t = 0 s; got startTime {start_time}"));
    }
    Ok(())
}

/// The importer's array `p` of `n` elements as a slice (FMI 2 and 3 alike): empty for `n = 0`,
/// an error for a NULL pointer with a non-zero length.
///
/// # Safety
/// `p` NULL or `n` readable elements (the importer's contract).
pub(crate) unsafe fn slice<'a, T>(p: *const T, n: usize) -> Result<&'a [T], String> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err("a NULL array was passed with a non-zero length".into());
    }
    // SAFETY: the importer's contract: `n` readable elements.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// [`slice`] for an output array.
///
/// # Safety
/// `p` NULL or `n` writable elements (the importer's contract).
pub(crate) unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Result<&'a mut [T], String> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err("a NULL array was passed with a non-zero length".into());
    }
    // SAFETY: the importer's contract: `n` writable elements.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// Run an FMI entry point's body under [`caught`]: a failure is logged through the instance's
/// logger and returned as `Err`; a panic is caught and reported the same way.
pub(crate) fn run_fmi(inst: &mut Instance, body: impl FnOnce(&mut Instance) -> Result<(), String>) -> Result<(), ()> {
    let failure = match caught(|| body(inst).map_err(Failure::argument)) {
        Ok(()) => return Ok(()),
        Err(f) => f,
    };
    log_caught(|| (inst.logger)(true, &failure.message));
    Err(())
}

/// The `modelDescription.xml` of an FMU of the model TOML `model_toml` with the stepper options
/// TOML `options_toml`, for FMI `fmi_version` (2 or 3), with the binary's `model_identifier`,
/// the `token` (GUID / instantiation token) and the default experiment's `stop_time`; written
/// NUL-terminated into `buf` (`len` bytes, `*needed` the size needed). Used by
/// `spacearm.fmi.export`; the FMU's binary reads the same variable table.
///
/// # Safety
/// The strings NUL-terminated; `buf` NULL or `len` writable bytes; `needed` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn spacearm_fmu_model_description(
    model_toml: *const c_char,
    options_toml: *const c_char,
    fmi_version: u32,
    model_identifier: *const c_char,
    token: *const c_char,
    stop_time: f64,
    buf: *mut c_char,
    len: usize,
    needed: *mut usize,
) -> SpacearmStatus {
    guard(|| {
        // SAFETY (this block and below): the caller's contract, documented above.
        let (m, o, id, tok) = unsafe { (text(model_toml, "model_toml")?, text(options_toml, "options_toml")?, text(model_identifier, "model_identifier")?, text(token, "token")?) };
        let version = match fmi_version {
            2 => FmiVersion::Fmi2,
            3 => FmiVersion::Fmi3,
            v => return Err(Failure::argument(format!("fmi_version must be 2 or 3, got {v}"))),
        };
        if !(stop_time.is_finite() && stop_time > 0.0) {
            return Err(Failure::argument(format!("stop_time must be finite and > 0, got {stop_time}")));
        }
        let model = crate::model::model_from_toml(m, "<model TOML>")?;
        crate::stepper::refuse_target(o, "an FMU")?;
        let options = StepperOptions::parse(&model, o)?;
        let xml = variables::model_description(&model, &options, version, id, tok, stop_time)?;
        unsafe { write_text(&xml, buf, len, needed) }
    })
}
