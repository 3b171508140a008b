//! `spacearm._core.simulate`: the whole simulation loop in Rust (`spacearm_core::sim::simulate`),
//! options and controller specifications parsed from Python dicts (unknown keys and bad values
//! are errors naming them), records returned as numpy arrays. Wrapped by
//! `spacearm.sim.simulation.simulate`, which builds the dicts from the user-facing classes of
//! `spacearm.control`.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use nalgebra::Vector3;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use spacearm_core::sim::actuators::ThrusterLimits;
use spacearm_core::control::mismatch::{perturbed_model, Slosh};
use spacearm_core::control::{
    AttitudeControl, BaseThrusterControl, Combined, Command, ComputedTorque, ControlContext, Controller, CoordinatedFlying, CoordinatedGains, JointPd,
    ResolvedMotionRate, ZeroTorque,
};
use spacearm_core::sim::integrate::IntegratorKind;
use spacearm_core::sim::modes::Mode;
use spacearm_core::sim::reference::{CartesianLine, JointReference};
use spacearm_core::sim::simulate::{simulate as core_simulate, SimOptions};
use spacearm_core::{Model, SpacearmError};

use crate::convert::*;
use crate::model_py::PyModel;
use crate::records_py::RunResult;

type CoreResult<T> = spacearm_core::Result<T>;

/// How often a run without a progress callable checks for Ctrl-C.
const SIGNAL_CHECK_INTERVAL: Duration = Duration::from_millis(100);

fn bad(msg: String) -> SpacearmError {
    SpacearmError::InvalidArgument(msg)
}

/// Reject keys of `d` not in `allowed`; `what` names the dict in the message.
fn check_keys(d: &Bound<'_, PyDict>, allowed: &[&str], what: &str) -> PyResult<()> {
    for key in d.keys() {
        let k: String = key.extract().map_err(|_| to_py_err(d.py(), bad(format!("{what}: keys must be strings, got {key}"))))?;
        if !allowed.contains(&k.as_str()) {
            return Err(to_py_err(d.py(), bad(format!("{what}: unknown key '{k}'; expected one of {allowed:?}"))));
        }
    }
    Ok(())
}

fn get<'py>(d: &Bound<'py, PyDict>, key: &str, what: &str) -> PyResult<Bound<'py, PyAny>> {
    d.get_item(key)?.ok_or_else(|| to_py_err(d.py(), bad(format!("{what}: missing '{key}'"))))
}

fn get_opt<'py>(d: &Bound<'py, PyDict>, key: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
    Ok(d.get_item(key)?.filter(|v| !v.is_none()))
}

fn get_f64(d: &Bound<'_, PyDict>, key: &str, what: &str) -> PyResult<f64> {
    get(d, key, what)?.extract::<f64>().map_err(|_| to_py_err(d.py(), bad(format!("{what}: '{key}' must be a number"))))
}

fn get_vec(d: &Bound<'_, PyDict>, key: &str, what: &str) -> PyResult<Vec<f64>> {
    let v = get(d, key, what)?;
    Ok(vec_arg(&v, &format!("{what} '{key}'"))?.as_slice().to_vec())
}

fn get_vec3(d: &Bound<'_, PyDict>, key: &str, what: &str) -> PyResult<Vector3<f64>> {
    let v = get(d, key, what)?;
    vec3(&v, &format!("{what} '{key}'"))
}

fn get_str(d: &Bound<'_, PyDict>, key: &str, what: &str) -> PyResult<String> {
    get(d, key, what)?.extract::<String>().map_err(|_| to_py_err(d.py(), bad(format!("{what}: '{key}' must be a string"))))
}

/// The options of a run, parsed.
pub struct RunOptions {
    pub sim: SimOptions,
    /// The progress callable, if any.
    pub progress: Option<Py<PyAny>>,
    /// Whether the records are returned as float32 (`"record_dtype": "float32"`).
    pub float32: bool,
}

/// Options dict → [`RunOptions`].
pub fn parse_options(py: Python<'_>, duration: f64, o: &Bound<'_, PyDict>) -> PyResult<RunOptions> {
    const KEYS: [&str; 12] =
        ["mode", "integrator", "dt", "rtol", "atol", "record_every", "wheels", "thrusters", "joint_limits", "max_steps", "progress", "record_dtype"];
    check_keys(o, &KEYS, "simulation options")?;
    let mut opts = SimOptions { duration, ..SimOptions::default() };
    let w = "simulation options";
    if let Some(m) = get_opt(o, "mode")? {
        let name: String = m.extract().map_err(|_| to_py_err(py, bad("mode must be a string".into())))?;
        opts.mode = Mode::from_name(&name).or_raise(py)?;
    }
    if let Some(m) = get_opt(o, "integrator")? {
        let name: String = m.extract().map_err(|_| to_py_err(py, bad("integrator must be a string".into())))?;
        opts.integrator = IntegratorKind::from_name(&name).or_raise(py)?;
    }
    for (key, slot) in [("dt", &mut opts.dt), ("rtol", &mut opts.rtol), ("atol", &mut opts.atol)] {
        if get_opt(o, key)?.is_some() {
            *slot = get_f64(o, key, w)?;
        }
    }
    for (key, slot) in [("record_every", &mut opts.record_every), ("max_steps", &mut opts.max_steps)] {
        if let Some(v) = get_opt(o, key)? {
            let i: i64 = v.extract().map_err(|_| to_py_err(py, bad(format!("{key} must be an integer >= 1, got {v}"))))?;
            if i < 1 {
                return Err(to_py_err(py, bad(format!("{key} must be an integer >= 1, got {i}"))));
            }
            *slot = i as usize;
        }
    }
    if let Some(v) = get_opt(o, "wheels")? {
        let dofs: Vec<i64> = v.extract().map_err(|_| to_py_err(py, bad("wheels must be a list of dof indices".into())))?;
        if let Some(d) = dofs.iter().find(|d| **d < 0) {
            return Err(to_py_err(py, SpacearmError::NotFound(format!("wheel dof {d} does not exist"))));
        }
        opts.wheels = Some(dofs.into_iter().map(|d| d as usize).collect());
    }
    if let Some(v) = get_opt(o, "thrusters")? {
        let d = v.cast::<PyDict>().map_err(|_| to_py_err(py, bad("thrusters must be a dict with max_force and max_torque".into())))?;
        check_keys(d, &["max_force", "max_torque"], "thrusters")?;
        let f = get_vec3(d, "max_force", "thrusters")?;
        let t = get_vec3(d, "max_torque", "thrusters")?;
        opts.thrusters = Some(ThrusterLimits::new(f, t).or_raise(py)?);
    }
    if let Some(v) = get_opt(o, "joint_limits")? {
        opts.joint_limits = v.extract().map_err(|_| to_py_err(py, bad("joint_limits must be True or False".into())))?;
    }
    let float32 = match get_opt(o, "record_dtype")? {
        None => false,
        Some(v) => match v.extract::<String>().ok().as_deref() {
            Some("float64") => false,
            Some("float32") => true,
            _ => return Err(to_py_err(py, bad(format!("record_dtype must be 'float64' or 'float32', got {v}")))),
        },
    };
    Ok(RunOptions { sim: opts, progress: get_opt(o, "progress")?.map(Bound::unbind), float32 })
}

/// A joint reference spec: `{"type": "quintic_joint", q_start, q_goal, t_start, t_end}` or
/// `{"type": "constant_joint", "q"}`.
fn parse_joint_reference(spec: &Bound<'_, PyAny>) -> PyResult<JointReference> {
    let py = spec.py();
    let d = spec.cast::<PyDict>().map_err(|_| to_py_err(py, bad("a joint reference must be a dict".into())))?;
    let kind = get_str(d, "type", "joint reference")?;
    let w = "joint reference";
    match kind.as_str() {
        "quintic_joint" => {
            check_keys(d, &["type", "q_start", "q_goal", "t_start", "t_end"], w)?;
            JointReference::quintic(get_vec(d, "q_start", w)?, get_vec(d, "q_goal", w)?, get_f64(d, "t_start", w)?, get_f64(d, "t_end", w)?).or_raise(py)
        }
        "constant_joint" => {
            check_keys(d, &["type", "q"], w)?;
            JointReference::constant(get_vec(d, "q", w)?).or_raise(py)
        }
        other => Err(to_py_err(py, bad(format!("joint reference type must be 'quintic_joint' or 'constant_joint', got '{other}'")))),
    }
}

/// `{"type": "cartesian_line", p_start, p_goal, t_start, t_end}`.
fn parse_cartesian_line(spec: &Bound<'_, PyAny>) -> PyResult<CartesianLine> {
    let py = spec.py();
    let d = spec.cast::<PyDict>().map_err(|_| to_py_err(py, bad("a Cartesian reference must be a dict".into())))?;
    let w = "Cartesian reference";
    check_keys(d, &["type", "p_start", "p_goal", "t_start", "t_end"], w)?;
    let kind = get_str(d, "type", w)?;
    if kind != "cartesian_line" {
        return Err(to_py_err(py, bad(format!("Cartesian reference type must be 'cartesian_line', got '{kind}'"))));
    }
    CartesianLine::new(get_vec3(d, "p_start", w)?, get_vec3(d, "p_goal", w)?, get_f64(d, "t_start", w)?, get_f64(d, "t_end", w)?).or_raise(py)
}

fn model_of(v: &Bound<'_, PyAny>) -> PyResult<Model> {
    let m = v.cast::<PyModel>().map_err(|_| to_py_err(v.py(), bad("a controller's model must be a spacearm Robot's core model".into())))?;
    Ok(m.borrow().model.clone())
}

/// Where a callback controller keeps the first Python exception it raised, for [`simulate`]
/// to re-raise unchanged (a mutex: the run may be on another thread, without the GIL).
pub type ErrorSlot = Arc<Mutex<Option<PyErr>>>;

/// A new, empty [`ErrorSlot`].
pub fn error_slot() -> ErrorSlot {
    Arc::new(Mutex::new(None))
}

/// The Python exception a callback stored in `slot`, if any.
pub fn take_error(slot: &ErrorSlot) -> Option<PyErr> {
    slot.lock().map(|mut e| e.take()).unwrap_or(None)
}

/// A Python callable as a controller: `fn(t, x, u) -> tau` or `(tau, base_wrench)`.
struct PyCallback {
    func: Py<PyAny>,
    error: ErrorSlot,
}

impl PyCallback {
    fn call(&self, py: Python<'_>, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> PyResult<()> {
        let result = self.func.bind(py).call1((t, PyArray1::from_slice(py, x), PyArray1::from_slice(py, u)))?;
        let (tau_obj, wrench_obj) = match result.cast::<PyTuple>() {
            Ok(tup) if tup.len() == 2 => (tup.get_item(0)?, Some(tup.get_item(1)?)),
            _ => (result, None),
        };
        let n = out.tau.len();
        let tau = vec_arg_n(&tau_obj, "the callback controller's tau", n)?;
        out.tau.copy_from_slice(tau.as_slice());
        if let Some(w) = wrench_obj {
            out.base_wrench = vec6(&w, "the callback controller's base_wrench")?;
        }
        Ok(())
    }
}

impl Controller for PyCallback {
    fn name(&self) -> &str {
        "callback"
    }
    fn setup(&mut self, _ctx: &ControlContext<'_>) -> CoreResult<()> {
        Ok(())
    }
    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> CoreResult<()> {
        let res = Python::attach(|py| self.call(py, t, x, u, out));
        res.map_err(|e| {
            let msg = format!("the controller callback raised at t = {t} s: {e}");
            if let Ok(mut slot) = self.error.lock() {
                slot.get_or_insert(e);
            }
            SpacearmError::Simulation(msg)
        })
    }
}

/// A controller spec dict → a core controller; callback controllers share `slot`.
pub fn parse_controller(spec: &Bound<'_, PyAny>, slot: &ErrorSlot) -> PyResult<Box<dyn Controller>> {
    let py = spec.py();
    let d = spec.cast::<PyDict>().map_err(|_| to_py_err(py, bad("a controller spec must be a dict".into())))?;
    let kind = get_str(d, "type", "controller")?;
    let w = kind.as_str();
    Ok(match w {
        "none" => {
            check_keys(d, &["type"], w)?;
            Box::new(ZeroTorque)
        }
        "joint_pd" => {
            check_keys(d, &["type", "kp", "kd", "reference"], w)?;
            Box::new(JointPd::new(get_vec(d, "kp", w)?, get_vec(d, "kd", w)?, parse_joint_reference(&get(d, "reference", w)?)?))
        }
        "computed_torque" => {
            check_keys(d, &["type", "kp", "kd", "reference", "model"], w)?;
            let model = match get_opt(d, "model")? {
                Some(m) => Some(model_of(&m)?),
                None => None,
            };
            Box::new(ComputedTorque::new(get_vec(d, "kp", w)?, get_vec(d, "kd", w)?, parse_joint_reference(&get(d, "reference", w)?)?, model))
        }
        "rmrc" => {
            check_keys(d, &["type", "reference", "gain", "damping", "threshold", "velocity_gain", "body", "offset"], w)?;
            let line = parse_cartesian_line(&get(d, "reference", w)?)?;
            let body: usize = get(d, "body", w)?.extract().map_err(|_| to_py_err(py, bad("rmrc: 'body' must be a body index".into())))?;
            Box::new(ResolvedMotionRate::new(
                line,
                get_f64(d, "gain", w)?,
                get_f64(d, "damping", w)?,
                get_f64(d, "threshold", w)?,
                get_f64(d, "velocity_gain", w)?,
                body,
                get_vec3(d, "offset", w)?,
            ))
        }
        "coordinated_flying" => {
            const KEYS: [&str; 13] =
                ["type", "reference", "body", "offset", "base_position", "base_quat", "kp_ee", "kd_ee", "kp_base", "kd_base", "damping", "threshold", "point"];
            check_keys(d, &KEYS, w)?;
            let line = parse_cartesian_line(&get(d, "reference", w)?)?;
            let body: usize = get(d, "body", w)?.extract().map_err(|_| to_py_err(py, bad("coordinated_flying: 'body' must be a body index".into())))?;
            let base_ref = match (get_opt(d, "base_position")?, get_opt(d, "base_quat")?) {
                (None, None) => None,
                (Some(p), Some(q)) => {
                    let q = vec_arg_n(&q, "coordinated flying base_quat", 4)?;
                    let q = q.as_slice();
                    Some((vec3(&p, "coordinated flying base_position")?, [q[0], q[1], q[2], q[3]]))
                }
                _ => return Err(to_py_err(py, bad("coordinated_flying: give both base_position and base_quat, or neither".into()))),
            };
            let gains = CoordinatedGains {
                kp_ee: get_f64(d, "kp_ee", w)?,
                kd_ee: get_f64(d, "kd_ee", w)?,
                kp_base: get_f64(d, "kp_base", w)?,
                kd_base: get_f64(d, "kd_base", w)?,
            };
            Box::new(CoordinatedFlying::new(line, body, get_vec3(d, "offset", w)?, base_ref, gains, get_f64(d, "damping", w)?, get_f64(d, "threshold", w)?))
        }
        "base_thrusters" => {
            check_keys(d, &["type", "com_ref", "quat_ref", "kp_position", "kd_position", "kp_attitude", "kd_attitude"], w)?;
            let com_ref = match get_opt(d, "com_ref")? {
                Some(v) => Some(vec3(&v, "thruster control com_ref")?),
                None => None,
            };
            let quat_ref = match get_opt(d, "quat_ref")? {
                Some(v) => {
                    let q = vec_arg_n(&v, "thruster control quat_ref", 4)?;
                    let q = q.as_slice();
                    Some([q[0], q[1], q[2], q[3]])
                }
                None => None,
            };
            Box::new(BaseThrusterControl::new(
                com_ref,
                quat_ref,
                get_f64(d, "kp_position", w)?,
                get_f64(d, "kd_position", w)?,
                get_f64(d, "kp_attitude", w)?,
                get_f64(d, "kd_attitude", w)?,
            ))
        }
        "attitude" => {
            check_keys(d, &["type", "quat_ref", "kp", "kd"], w)?;
            let q = get(d, "quat_ref", w)?;
            let q = vec_arg_n(&q, "attitude quat_ref", 4)?;
            let q = q.as_slice();
            Box::new(AttitudeControl::new([q[0], q[1], q[2], q[3]], get_f64(d, "kp", w)?, get_f64(d, "kd", w)?))
        }
        "combined" => {
            check_keys(d, &["type", "arm", "base"], w)?;
            Box::new(Combined::new(parse_controller(&get(d, "arm", w)?, slot)?, parse_controller(&get(d, "base", w)?, slot)?))
        }
        "callback" => {
            check_keys(d, &["type", "fn"], w)?;
            let f = get(d, "fn", w)?;
            if !f.is_callable() {
                return Err(to_py_err(py, bad("the callback controller needs a callable fn(t, x, u)".into())));
            }
            Box::new(PyCallback { func: f.unbind(), error: slot.clone() })
        }
        other => {
            return Err(to_py_err(
                py,
                bad(format!(
                    "controller type must be one of ['none', 'joint_pd', 'computed_torque', 'rmrc', 'attitude', 'base_thrusters', 'coordinated_flying', 'combined', 'callback'], got '{other}'"
                )),
            ))
        }
    })
}

/// Run a simulation, without the GIL; returns its records, saturation onsets and description as
/// a `RunResult` (see `spacearm.sim.simulation`).
#[pyfunction]
#[pyo3(signature = (model, x0, u0, duration, options, controller_spec=None))]
pub fn simulate<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyModel>,
    x0: &Bound<'py, PyAny>,
    u0: &Bound<'py, PyAny>,
    duration: f64,
    options: &Bound<'py, PyDict>,
    controller_spec: Option<&Bound<'py, PyAny>>,
) -> PyResult<RunResult> {
    // A copy of the model: the run holds no borrow of the Python object, so a callback
    // controller may call the robot's methods.
    let plant = model.borrow().model.clone();
    let x0 = vec_arg(x0, "x0")?.as_slice().to_vec();
    let u0 = vec_arg(u0, "u0")?.as_slice().to_vec();
    let RunOptions { sim: opts, progress: progress_fn, float32 } = parse_options(py, duration, options)?;
    let slot = error_slot();
    let mut controller: Box<dyn Controller> = match controller_spec {
        Some(s) if !s.is_none() => parse_controller(s, &slot)?,
        _ => Box::new(ZeroTorque),
    };
    let mut progress_error: Option<PyErr> = None;
    let mut last_check = Instant::now();
    let result = py.detach(|| {
        // The progress callable and Ctrl-C are checked with the GIL taken back: at every report
        // (at most ~1000 a run) if there is a callable, else every 0.1 s of wall time (taking
        // the GIL back waits for the other Python threads, so not more often than that).
        let mut progress = |fraction: f64| -> CoreResult<()> {
            if progress_fn.is_none() && fraction < 1.0 && last_check.elapsed() < SIGNAL_CHECK_INTERVAL {
                return Ok(());
            }
            last_check = Instant::now();
            Python::attach(|py| {
                py.check_signals()?;
                match &progress_fn {
                    Some(f) => f.call1(py, (fraction,)).map(|_| ()),
                    None => Ok(()),
                }
            })
            .map_err(|e| {
                progress_error.get_or_insert(e);
                SpacearmError::Simulation("interrupted".into())
            })
        };
        core_simulate(&plant, &x0, &u0, &opts, controller.as_mut(), &mut progress)
    });
    let res = match result {
        Ok(r) => r,
        Err(e) => {
            if let Some(err) = take_error(&slot) {
                return Err(err);
            }
            if let Some(err) = progress_error {
                return Err(err);
            }
            return Err(to_py_err(py, e));
        }
    };
    RunResult::of_run(py, res, &opts, float32, (plant.nx(), plant.nu(), plant.n_dof()))
}

/// A copy of `model` with mass-property errors and fuel slosh (see
/// `spacearm_core::control::mismatch::perturbed_model`). `slosh_offset = None` with a non-zero
/// fraction removes the slosh mass instead of moving it.
#[pyfunction]
#[pyo3(signature = (model, base_mass_scale, base_inertia_scale, link_mass_scale, slosh_fraction, slosh_offset, slosh_removed))]
#[allow(clippy::too_many_arguments)]
pub fn perturbed(
    py: Python<'_>,
    model: &Bound<'_, PyModel>,
    base_mass_scale: f64,
    base_inertia_scale: f64,
    link_mass_scale: f64,
    slosh_fraction: f64,
    slosh_offset: &Bound<'_, PyAny>,
    slosh_removed: bool,
) -> PyResult<PyModel> {
    let offset = vec3(slosh_offset, "slosh_offset")?;
    let slosh = if slosh_fraction == 0.0 {
        Slosh::None
    } else if slosh_removed {
        Slosh::Removed { fraction: slosh_fraction }
    } else {
        Slosh::Moved { fraction: slosh_fraction, offset }
    };
    let m = perturbed_model(&model.borrow().model, base_mass_scale, base_inertia_scale, link_mass_scale, slosh).or_raise(py)?;
    Ok(PyModel::new(m))
}

/// Degrees of freedom the simulator treats as reaction wheels by default.
#[pyfunction]
pub fn default_wheel_dofs(model: &Bound<'_, PyModel>) -> Vec<usize> {
    spacearm_core::sim::actuators::detect_reaction_wheels(&model.borrow().model)
}
