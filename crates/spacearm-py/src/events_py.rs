//! The rows of a run with a second system (`spacearm_core::sim::run::RunOutput::WithTarget`: a
//! free target in the loop of contact, topology events, or both; docs/contact.md, docs/events.md)
//! as the dict `RunResult.topology` of `spacearm._core.simulate` (simulate_py.rs). Read by
//! `spacearm.sim.simulation.simulate(..., contact=, events=, target=, target_state=)`.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use spacearm_core::sim::topology::TopologyRun;

use crate::convert::*;
use crate::model_py::PyModel;

/// `run`'s rows as a dict of numpy arrays: `target` (K, 13), `attached` (K,), `phase` (K,: the
/// events that have happened), `ledger_momentum` (K, 6), `ledger_energy` (K,), `event_index`,
/// `event_kind` (0 attach, 1 detach), `event_t`, `event_gap`, `event_energy_before/after` (E,),
/// `event_impulse`, `event_momentum_before/after` (E, 6), `event_point` (E, 3), `event_body`
/// (names) and `final_model`. Moves the rows out of `run`.
pub(crate) fn topology_dict<'py>(py: Python<'py>, run: &mut TopologyRun) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("target", rows(py, std::mem::take(&mut run.target), 13)?)?;
    d.set_item("attached", PyArray1::from_vec(py, std::mem::take(&mut run.attached)))?;
    d.set_item("phase", PyArray1::from_vec(py, run.phase.iter().map(|&p| p as i64).collect()))?;
    d.set_item("ledger_momentum", rows(py, std::mem::take(&mut run.ledger_momentum), 6)?)?;
    d.set_item("ledger_energy", PyArray1::from_vec(py, std::mem::take(&mut run.ledger_energy)))?;
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
    d.set_item("final_model", Py::new(py, PyModel::new(run.final_model.clone()))?)?;
    Ok(d)
}
