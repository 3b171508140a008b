//! `spacearm._core.simulate_events`: a run with topology events (`spacearm_core::sim::topology`,
//! the events the core's serde type `TopologyEvent` read from plain data), its records a
//! `RunResult` like `simulate`'s and the second system's rows, the ledger and the events as a
//! dict of numpy arrays. Wrapped by `spacearm.sim.simulation.simulate(..., events=[...])`.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use spacearm_core::control::{Controller, ZeroTorque};
use spacearm_core::model::Model;
use spacearm_core::sim::topology::{simulate_with_events, TopologyEvent};
use spacearm_core::SpacearmError;

use crate::controller_spec_py::{build_controller, error_slot, from_data};
use crate::convert::*;
use crate::model_py::PyModel;
use crate::records_py::PyRunResult;
use crate::sim_options_py::PyRunOptions;
use crate::interrupt::run_reporting;
use crate::simulate_py::{run_error, RunArgs};

/// Run `model` with the topology `events` (a list of plain-data events, the core's
/// `TopologyEvent`), the free `target` model at `target_state` (13) if given; returns
/// `(RunResult, topology)` with `topology` a dict: `target` (K, 13), `attached` (K,),
/// `ledger_momentum` (K, 6), `ledger_energy` (K,), `event_index`, `event_kind` (0 attach,
/// 1 detach), `event_t`, `event_gap`, `event_energy_before/after` (E,), `event_impulse`,
/// `event_momentum_before/after` (E, 6), `event_point` (E, 3), `event_body` (names) and
/// `final_model`.
#[pyfunction]
#[pyo3(signature = (model, x0, u0, duration, options, controller_spec, events, target=None, target_state=None))]
#[allow(clippy::too_many_arguments)]
pub fn simulate_events<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyModel>,
    x0: &Bound<'py, PyAny>,
    u0: &Bound<'py, PyAny>,
    duration: f64,
    options: PyRef<'py, PyRunOptions>,
    controller_spec: Option<&Bound<'py, PyAny>>,
    events: &Bound<'py, PyAny>,
    target: Option<&Bound<'py, PyModel>>,
    target_state: Option<&Bound<'py, PyAny>>,
) -> PyResult<(PyRunResult, Bound<'py, PyDict>)> {
    let args = RunArgs::read(model.borrow().model.clone(), x0, u0, duration, &options, py)?;
    let events: Vec<TopologyEvent> = from_data(events, "events")?;
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
        let mut factory = |m: &Model| -> spacearm_core::Result<Box<dyn Controller>> {
            match &spec {
                Some(s) => Python::attach(|py| build_controller(s.bind(py), m, &slot)).map_err(|e| {
                    let msg = Python::attach(|py| e.value(py).to_string());
                    slot.lock().expect("the error slot").get_or_insert(e);
                    SpacearmError::InvalidArgument(msg)
                }),
                None => Ok(Box::new(ZeroTorque)),
            }
        };
        simulate_with_events(&args.plant, &args.x0, &args.u0, &args.opts, &mut factory, pair, &events, progress)
    });
    let run = result.map_err(|e| run_error(py, e, &slot, interrupted))?;
    let d = PyDict::new(py);
    d.set_item("target", rows(py, run.target, 13)?)?;
    d.set_item("attached", PyArray1::from_vec(py, run.attached))?;
    d.set_item("ledger_momentum", rows(py, run.ledger_momentum, 6)?)?;
    d.set_item("ledger_energy", PyArray1::from_vec(py, run.ledger_energy))?;
    let ev = &run.events;
    d.set_item("event_index", PyArray1::from_vec(py, ev.iter().map(|e| e.event as i64).collect()))?;
    d.set_item("event_kind", PyArray1::from_vec(py, ev.iter().map(|e| i64::from(e.kind == "detach")).collect()))?;
    d.set_item("event_t", PyArray1::from_vec(py, ev.iter().map(|e| e.t).collect()))?;
    d.set_item("event_gap", PyArray1::from_vec(py, ev.iter().map(|e| e.gap).collect()))?;
    d.set_item("event_energy_before", PyArray1::from_vec(py, ev.iter().map(|e| e.energy_before).collect()))?;
    d.set_item("event_energy_after", PyArray1::from_vec(py, ev.iter().map(|e| e.energy_after).collect()))?;
    d.set_item("event_impulse", rows(py, ev.iter().flat_map(|e| e.impulse).collect(), 6)?)?;
    d.set_item("event_momentum_before", rows(py, ev.iter().flat_map(|e| e.momentum_before).collect(), 6)?)?;
    d.set_item("event_momentum_after", rows(py, ev.iter().flat_map(|e| e.momentum_after).collect(), 6)?)?;
    d.set_item("event_point", rows(py, ev.iter().flat_map(|e| e.point).collect(), 3)?)?;
    d.set_item("event_body", ev.iter().map(|e| e.body.clone()).collect::<Vec<_>>())?;
    d.set_item("final_model", Py::new(py, PyModel::new(run.final_model))?)?;
    Ok((args.result(py, run.result)?, d))
}
