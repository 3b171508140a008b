//! `spacearm._core.simulate_target`: a run with a free target in the loop of contact
//! (`spacearm_core::sim::simulate::simulate_with_target`, docs/contact.md, "Contact with a free
//! target"); its records a `RunResult` like `simulate`'s and the target's rows and the ledger as
//! a dict of numpy arrays (the names a run with topology events uses). Wrapped by
//! `spacearm.sim.simulation.simulate(..., contact=, target=, target_state=)`.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use spacearm_core::sim::simulate::simulate_with_target;

use crate::convert::*;
use crate::model_py::PyModel;
use crate::records_py::PyRunResult;
use crate::sim_options_py::PyRunOptions;
use crate::simulate_py::{run_controlled, RunArgs};

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
    let run = RunArgs::read(model.borrow().model.clone(), x0, u0, duration, &options, py)?;
    let target = target.borrow().model.clone();
    let state = vec_arg(target_state, "target_state")?.as_slice().to_vec();
    let mut res = run_controlled(py, &run.plant, controller_spec, run.progress_fn.as_ref(), |controller, progress| {
        simulate_with_target(&run.plant, &run.x0, &run.u0, &run.opts, controller, &target, &state, progress)
    })?;
    let r = &mut res.records;
    let d = PyDict::new(py);
    d.set_item("target", rows(py, r.target_state.take().unwrap_or_default(), 13)?)?;
    d.set_item("ledger_momentum", rows(py, r.ledger_momentum.take().unwrap_or_default(), 6)?)?;
    d.set_item("ledger_energy", PyArray1::from_vec(py, r.ledger_energy.take().unwrap_or_default()))?;
    Ok((run.result(py, res)?, d))
}
