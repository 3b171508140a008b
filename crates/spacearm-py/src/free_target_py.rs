//! `spacearm._core.simulate_target`: a run with a free target in the loop of contact
//! (`spacearm_core::sim::simulate::simulate_with_target`, docs/contact.md, "Contact with a free
//! target"); its records a `RunResult` like `simulate`'s and the target's rows and the ledger as
//! a dict of numpy arrays (the names a run with topology events uses). Wrapped by
//! `spacearm.sim.simulation.simulate(..., contact=, target=, target_state=)`.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use spacearm_core::control::{Controller, ZeroTorque};
use spacearm_core::sim::simulate::simulate_with_target;

use crate::controller_spec_py::{build_controller, error_slot};
use crate::events_py::rows;
use crate::convert::*;
use crate::model_py::PyModel;
use crate::records_py::PyRunResult;
use crate::sim_options_py::PyRunOptions;
use crate::simulate_py::{progress_reporter, run_error};

/// Run `model` with the free `target` model at `target_state` (13) touching it by the options'
/// contact; returns `(RunResult, dict)` with `target` (K, 13), `ledger_momentum` (K, 6) and
/// `ledger_energy` (K,).
#[pyfunction]
#[pyo3(signature = (model, x0, u0, duration, options, controller_spec, target, target_state))]
#[allow(clippy::too_many_arguments)]
pub fn simulate_target<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyModel>,
    x0: &Bound<'py, PyAny>,
    u0: &Bound<'py, PyAny>,
    duration: f64,
    options: PyRef<'py, PyRunOptions>,
    controller_spec: Option<&Bound<'py, PyAny>>,
    target: &Bound<'py, PyModel>,
    target_state: &Bound<'py, PyAny>,
) -> PyResult<(PyRunResult, Bound<'py, PyDict>)> {
    let plant = model.borrow().model.clone();
    let target = target.borrow().model.clone();
    let x0 = vec_arg(x0, "x0")?.as_slice().to_vec();
    let u0 = vec_arg(u0, "u0")?.as_slice().to_vec();
    let state = vec_arg(target_state, "target_state")?.as_slice().to_vec();
    let (opts, progress_fn, float32) = (options.sim_options(duration), options.progress_fn(py), options.records_float32());
    let slot = error_slot();
    let mut controller: Box<dyn Controller> = match controller_spec {
        Some(s) if !s.is_none() => build_controller(s, &plant, &slot)?,
        _ => Box::new(ZeroTorque),
    };
    let mut progress_error: Option<PyErr> = None;
    let result = py.detach(|| {
        let mut progress = progress_reporter(&progress_fn, &mut progress_error);
        simulate_with_target(&plant, &x0, &u0, &opts, controller.as_mut(), &target, &state, &mut progress)
    });
    let mut res = result.map_err(|e| run_error(py, e, &slot, progress_error))?;
    let r = &mut res.records;
    let d = PyDict::new(py);
    d.set_item("target", rows(py, r.target_state.take().unwrap_or_default(), 13)?)?;
    d.set_item("ledger_momentum", rows(py, r.ledger_momentum.take().unwrap_or_default(), 6)?)?;
    d.set_item("ledger_energy", PyArray1::from_vec(py, r.ledger_energy.take().unwrap_or_default()))?;
    let result = PyRunResult::of_run(py, res, &opts, float32, (plant.nx(), plant.nu(), plant.n_dof()))?;
    Ok((result, d))
}
