//! `spacearm._core.simulate`: the whole simulation loop in Rust (`spacearm_core::sim::simulate`),
//! its options a `RunOptions` (sim_options_py.rs) and its controller a spec (controller_spec_py.rs),
//! records returned as numpy arrays. Wrapped by `spacearm.sim.simulation.simulate`, which builds
//! the options and the spec from the user-facing classes of `spacearm.control`.

use pyo3::prelude::*;
use spacearm_core::control::mismatch::{perturbed_cmgs, perturbed_model, Slosh};
use spacearm_core::control::{Controller, ZeroTorque};
use spacearm_core::sim::run::{run, RunInput, RunOutput};
use spacearm_core::sim::simulate::{Progress, SimOptions, SimResult};
use spacearm_core::sim::topology::TopologyEvent;
use spacearm_core::Model;
use spacearm_core::SpacearmError;

use crate::controller_spec_py::{build_controller, error_slot, from_data, take_error, ErrorSlot};
use crate::convert::*;
use crate::events_py::topology_dict;
use crate::interrupt::run_reporting;
use crate::model_py::PyModel;
use crate::records_py::PyRunResult;
use crate::sim_options_py::PyRunOptions;

type CoreResult<T> = spacearm_core::Result<T>;

/// Run a simulation, without the GIL: the core's one entry (`spacearm_core::sim::run::run`),
/// which decides the loop from what is given — the robot alone, a free target (13-state
/// `target_state`) in the loop of the options' contact, topology `events` (a list of plain-data
/// events, the core's `TopologyEvent`), or both; returns its records, saturation onsets and
/// description as a `RunResult`, with a second system its rows as `RunResult.topology`
/// (events_py.rs; see `spacearm.sim.simulation`).
#[pyfunction]
#[pyo3(signature = (model, x0, u0, duration, options, controller_spec=None, events=None, target=None, target_state=None))]
#[allow(clippy::too_many_arguments)]
pub fn simulate<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyModel>,
    x0: &Bound<'py, PyAny>,
    u0: &Bound<'py, PyAny>,
    duration: f64,
    options: PyRef<'py, PyRunOptions>,
    controller_spec: Option<&Bound<'py, PyAny>>,
    events: Option<&Bound<'py, PyAny>>,
    target: Option<&Bound<'py, PyModel>>,
    target_state: Option<&Bound<'py, PyAny>>,
) -> PyResult<PyRunResult> {
    let args = RunArgs::read(model.borrow().model.clone(), x0, u0, duration, &options, py)?;
    let events: Vec<TopologyEvent> = match events.filter(|e| !e.is_none()) {
        Some(e) => from_data(e, "events")?,
        None => Vec::new(),
    };
    let target: Option<Model> = target.map(|t| t.borrow().model.clone());
    let state: Option<Vec<f64>> = target_state.filter(|s| !s.is_none()).map(|s| vec_arg(s, "target_state").map(|v| v.as_slice().to_vec())).transpose()?;
    let pair = match (&target, &state) {
        (Some(t), Some(s)) => Some((t, s.as_slice())),
        (None, None) => None,
        _ => return Err(to_py_err(py, SpacearmError::InvalidArgument("target and target_state go together: give both (a rigid model and its 13-state) or neither".into()))),
    };
    let slot = error_slot();
    let spec: Option<Py<PyAny>> = controller_spec.filter(|s| !s.is_none()).map(|s| s.clone().unbind());
    let (result, interrupted) = run_reporting(py, args.progress_fn.as_ref(), |progress| {
        // The controller of the spec on each segment's model (the robot's alone: once).
        let mut factory = |m: &Model| -> CoreResult<Box<dyn Controller>> {
            match &spec {
                Some(s) => Python::attach(|py| build_controller(s.bind(py), m, &slot)).map_err(|e| {
                    let msg = Python::attach(|py| e.value(py).to_string());
                    slot.lock().expect("the error slot").get_or_insert(e);
                    SpacearmError::InvalidArgument(msg)
                }),
                None => Ok(Box::new(ZeroTorque)),
            }
        };
        let input = RunInput { robot: &args.plant, x0: &args.x0, u0: &args.u0, opts: &args.opts, target: pair, events: &events };
        run(input, &mut factory, progress)
    });
    match result.map_err(|e| run_error(py, e, &slot, interrupted))? {
        RunOutput::Plain(res) => args.result(py, res),
        RunOutput::WithTarget(mut run) => {
            let d = topology_dict(py, &mut run)?;
            Ok(args.result(py, run.result)?.with_topology(d))
        }
    }
}

/// What every single-plant run entry point (`simulate`, `simulate_closed_chain`) reads of its `(model, x0, u0, duration, options)` arguments, the
/// same way: a copy of the model (the run holds no borrow of the Python object, so a callback
/// controller may call the robot's methods), the initial state, the options of a run of
/// `duration`, the records' precision and the progress callable.
pub(crate) struct RunArgs {
    pub plant: Model,
    pub x0: Vec<f64>,
    pub u0: Vec<f64>,
    pub opts: SimOptions,
    pub float32: bool,
    pub progress_fn: Option<Py<PyAny>>,
}

impl RunArgs {
    pub(crate) fn read(plant: Model, x0: &Bound<'_, PyAny>, u0: &Bound<'_, PyAny>, duration: f64, options: &PyRunOptions, py: Python<'_>) -> PyResult<Self> {
        Ok(RunArgs {
            plant,
            x0: owned_vec(x0, "x0")?,
            u0: owned_vec(u0, "u0")?,
            opts: options.sim_options(duration),
            float32: options.records_float32(),
            progress_fn: options.progress_fn(py),
        })
    }

    /// The records of the finished run as a `RunResult`.
    pub(crate) fn result(&self, py: Python<'_>, res: SimResult) -> PyResult<PyRunResult> {
        PyRunResult::of_run(py, res, &self.opts, self.float32, (self.plant.nx(), self.plant.nu(), self.plant.n_dof()))
    }
}

/// Run `work(controller, progress)` without the GIL ([`run_reporting`]: `progress_fn` and Ctrl-C
/// at the progress reports), the controller that of `controller_spec` on `plant` (None: zero
/// torques); a failed run raises as [`run_error`] says.
pub(crate) fn run_controlled<R: Send>(
    py: Python<'_>,
    plant: &Model,
    controller_spec: Option<&Bound<'_, PyAny>>,
    progress_fn: Option<&Py<PyAny>>,
    work: impl FnOnce(&mut dyn Controller, Progress<'_>) -> CoreResult<R> + Send,
) -> PyResult<R> {
    let slot = error_slot();
    let mut controller: Box<dyn Controller> = match controller_spec {
        Some(s) if !s.is_none() => build_controller(s, plant, &slot)?,
        _ => Box::new(ZeroTorque),
    };
    let (result, interrupted) = run_reporting(py, progress_fn, |progress| work(controller.as_mut(), progress));
    result.map_err(|e| run_error(py, e, &slot, interrupted))
}

/// The Python error of a failed run: a callback controller's, else the progress callable's
/// (or Ctrl-C), else the core's.
pub(crate) fn run_error(py: Python<'_>, e: SpacearmError, slot: &ErrorSlot, interrupted: Option<PyErr>) -> PyErr {
    take_error(slot).or(interrupted).unwrap_or_else(|| to_py_err(py, e))
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

/// A copy of `model` with its CMGs' rotor inertias scaled and each unit turned by a rotation
/// vector (see `spacearm_core::control::mismatch::perturbed_cmgs`).
#[pyfunction]
#[pyo3(name = "perturbed_cmgs", signature = (model, rotor_inertia_scale, tilts))]
pub fn perturbed_cmgs_py(py: Python<'_>, model: &Bound<'_, PyModel>, rotor_inertia_scale: f64, tilts: Vec<[f64; 3]>) -> PyResult<PyModel> {
    let m = perturbed_cmgs(&model.borrow().model, rotor_inertia_scale, &tilts).or_raise(py)?;
    Ok(PyModel::new(m))
}

/// Degrees of freedom the simulator treats as reaction wheels by default.
#[pyfunction]
pub fn default_wheel_dofs(model: &Bound<'_, PyModel>) -> Vec<usize> {
    spacearm_core::sim::actuators::detect_reaction_wheels(&model.borrow().model)
}

/// The drift of a conserved quantity over samples (`spacearm_core::algorithms::momentum::conserved_drift`):
/// `max_k |v_k − v_0| / max(|v_0|, scale)` for `values` (T, d) or (T,).
#[pyfunction]
pub fn conserved_drift(values: &Bound<'_, PyAny>, scale: f64) -> PyResult<f64> {
    let a = array_values(values, "values")?;
    let dim = if a.shape.len() <= 1 { 1 } else { a.shape[1..].iter().product() };
    Ok(spacearm_core::algorithms::momentum::conserved_drift(&a.values, dim, scale))
}
