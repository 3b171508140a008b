//! `spacearm._core.simulate`: the whole simulation loop in Rust (`spacearm_core::sim::simulate`),
//! its options a `RunOptions` (sim_options_py.rs) and its controller a spec (controller_spec_py.rs),
//! records returned as numpy arrays. Wrapped by `spacearm.sim.simulation.simulate`, which builds
//! the options and the spec from the user-facing classes of `spacearm.control`.

use std::time::{Duration, Instant};

use pyo3::prelude::*;
use spacearm_core::control::mismatch::{perturbed_cmgs, perturbed_model, Slosh};
use spacearm_core::control::{Controller, ZeroTorque};
use spacearm_core::sim::simulate::simulate as core_simulate;
use spacearm_core::SpacearmError;

use crate::controller_spec_py::{build_controller, error_slot, take_error, ErrorSlot};
use crate::convert::*;
use crate::model_py::PyModel;
use crate::records_py::PyRunResult;
use crate::sim_options_py::PyRunOptions;

type CoreResult<T> = spacearm_core::Result<T>;

/// How often a run without a progress callable checks for Ctrl-C.
const SIGNAL_CHECK_INTERVAL: Duration = Duration::from_millis(100);

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
    options: PyRef<'py, PyRunOptions>,
    controller_spec: Option<&Bound<'py, PyAny>>,
) -> PyResult<PyRunResult> {
    // A copy of the model: the run holds no borrow of the Python object, so a callback
    // controller may call the robot's methods.
    let plant = model.borrow().model.clone();
    let x0 = vec_arg(x0, "x0")?.as_slice().to_vec();
    let u0 = vec_arg(u0, "u0")?.as_slice().to_vec();
    let (opts, progress_fn, float32) = (options.sim_options(duration), options.progress_fn(py), options.records_float32());
    let slot = error_slot();
    let mut controller: Box<dyn Controller> = match controller_spec {
        Some(s) if !s.is_none() => build_controller(s, &plant, &slot)?,
        _ => Box::new(ZeroTorque),
    };
    let mut progress_error: Option<PyErr> = None;
    let result = py.detach(|| {
        let mut progress = progress_reporter(&progress_fn, &mut progress_error);
        core_simulate(&plant, &x0, &u0, &opts, controller.as_mut(), &mut progress)
    });
    let res = result.map_err(|e| run_error(py, e, &slot, progress_error))?;
    PyRunResult::of_run(py, res, &opts, float32, (plant.nx(), plant.nu(), plant.n_dof()))
}

/// The progress report of a run without the GIL: the progress callable and Ctrl-C checked with
/// the GIL taken back, at every report (at most ~1000 a run) if there is a callable, else every
/// 0.1 s of wall time (taking the GIL back waits for the other Python threads, so not more often
/// than that); the first Python error is kept in `progress_error` and stops the run.
pub(crate) fn progress_reporter<'a>(progress_fn: &'a Option<Py<PyAny>>, progress_error: &'a mut Option<PyErr>) -> impl FnMut(f64) -> CoreResult<()> + 'a {
    let mut last_check = Instant::now();
    move |fraction: f64| -> CoreResult<()> {
        if progress_fn.is_none() && fraction < 1.0 && last_check.elapsed() < SIGNAL_CHECK_INTERVAL {
            return Ok(());
        }
        last_check = Instant::now();
        Python::attach(|py| {
            py.check_signals()?;
            match progress_fn {
                Some(f) => f.call1(py, (fraction,)).map(|_| ()),
                None => Ok(()),
            }
        })
        .map_err(|e| {
            progress_error.get_or_insert(e);
            SpacearmError::Simulation("interrupted".into())
        })
    }
}

/// The Python error of a failed run: a callback controller's, else the progress callable's
/// (or Ctrl-C), else the core's.
pub(crate) fn run_error(py: Python<'_>, e: SpacearmError, slot: &ErrorSlot, progress_error: Option<PyErr>) -> PyErr {
    take_error(slot).or(progress_error).unwrap_or_else(|| to_py_err(py, e))
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
