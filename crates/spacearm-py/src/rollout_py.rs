//! `spacearm._core.rollout`: many simulations on native threads without the GIL
//! (`spacearm_core::sim::rollout`), their records stacked into arrays with a leading rollout
//! axis. Wrapped by `spacearm.rollout`.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyList;
use rayon::prelude::*;
use spacearm_core::control::{Controller, ZeroTorque};
use spacearm_core::sim::rollout::{rollout_cancellable as core_rollout, RolloutSpec};
use spacearm_core::sim::simulate::{check_initial_state, sample_count, SimResult};
use spacearm_core::{Model, SpacearmError};

use crate::convert::*;
use crate::model_py::PyModel;
use crate::controller_spec_py::{build_controller, error_slot};
use crate::records_py::{take_fields, Field, Record, PyRolloutBatch, PyRunEvents, PyRunMeta, PyRunRecords};
use crate::sim_options_py::PyRunOptions;

/// Run `B` rollouts; returns a `RolloutBatch`: every record with a leading rollout axis
/// (`(B, K, ...)`, NaN rows for a failed rollout), and each rollout's status, description and
/// saturation onsets.
#[pyfunction]
#[pyo3(signature = (models, x0, u0, duration, options, controllers=None, threads=None, stop=None))]
#[allow(clippy::too_many_arguments)]
pub fn rollout<'py>(
    py: Python<'py>,
    models: &Bound<'py, PyList>,
    x0: &Bound<'py, PyAny>,
    u0: &Bound<'py, PyAny>,
    duration: f64,
    options: PyRef<'py, PyRunOptions>,
    controllers: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
    stop: Option<&Bound<'py, PyAny>>,
) -> PyResult<PyRolloutBatch> {
    let stop = stop.filter(|s| !s.is_none()).map(|s| s.clone().unbind());
    let bad = |msg: String| to_py_err(py, bad(msg));
    let plants: Vec<Model> = models
        .iter()
        .map(|m| m.cast::<PyModel>().map(|m| m.borrow().model.clone()).map_err(|_| bad("rollout: models must be spacearm core models".into())))
        .collect::<PyResult<_>>()?;
    let first = plants.first().ok_or_else(|| bad("rollout: no model given".into()))?;
    let (nx, nu, n) = (first.nx(), first.nu(), first.n_dof());
    let (x0, b) = rows_arg(x0, "x0", nx)?;
    let (u0, b_u) = rows_arg(u0, "u0", nu)?;
    if b_u != b {
        return Err(bad(format!("x0 has {b} rows but u0 has {b_u}; give one initial velocity per rollout")));
    }
    if plants.len() != 1 && plants.len() != b {
        return Err(bad(format!("plants: got {} models for {b} rollouts; give one per rollout", plants.len())));
    }
    let plant = |i: usize| if plants.len() == 1 { &plants[0] } else { &plants[i] };
    for (i, m) in plants.iter().enumerate() {
        same_joints("plant", i, m, n).or_raise(py)?;
    }
    for i in 0..b {
        check_initial_state(plant(i), &x0[i * nx..(i + 1) * nx], &u0[i * nu..(i + 1) * nu]).map_err(|e| to_py_err_in(py, &format!("rollout {i}"), e))?;
    }
    let (opts, float32) = (options.sim_options(duration), options.records_float32());
    // One controller instance per rollout (controllers keep workspaces): a shared spec builds
    // one per rollout.
    let slot = error_slot();
    let mut boxed: Vec<Box<dyn Controller>> = Vec::with_capacity(b);
    match controllers {
        None => boxed.extend((0..b).map(|_| Box::new(ZeroTorque) as Box<dyn Controller>)),
        Some(c) if c.is_none() => boxed.extend((0..b).map(|_| Box::new(ZeroTorque) as Box<dyn Controller>)),
        Some(c) => match c.cast::<PyList>() {
            Ok(list) => {
                if list.len() != b {
                    return Err(bad(format!("controllers: got {} for {b} rollouts; give one controller, or one per rollout", list.len())));
                }
                for (i, spec) in list.iter().enumerate() {
                    boxed.push(build_controller(&spec, plant(i), &slot)?);
                }
            }
            Err(_) => {
                for i in 0..b {
                    boxed.push(build_controller(c, plant(i), &slot)?);
                }
            }
        },
    }
    let specs: Vec<RolloutSpec<'_>> = boxed
        .into_iter()
        .enumerate()
        .map(|(i, controller)| RolloutSpec { model: plant(i), x0: &x0[i * nx..(i + 1) * nx], u0: &u0[i * nu..(i + 1) * nu], controller })
        .collect();
    // Ctrl-C stops the rollouts within 0.1 s (crate::interrupt).
    let results = crate::interrupt::run_until(py, stop, |cancel| core_rollout(specs, &opts, threads, cancel))?.or_raise(py)?;
    stack(py, results, &opts, float32, (nx, nu, n))
}

/// One record of every rollout, stacked.
enum Stacked {
    F64(Vec<f64>),
    F32(Vec<f32>),
}

/// The rollouts' records stacked along a leading axis, with their status and descriptions.
fn stack<'py>(
    py: Python<'py>,
    results: Vec<spacearm_core::Result<SimResult>>,
    opts: &spacearm_core::sim::simulate::SimOptions,
    float32: bool,
    (nx, nu, n): (usize, usize, usize),
) -> PyResult<PyRolloutBatch> {
    let b = results.len();
    let k = sample_count(opts);
    let ok: Vec<bool> = results.iter().map(|r| r.is_ok()).collect();
    let mut reason = Vec::with_capacity(b);
    let mut error_class = Vec::with_capacity(b);
    let mut metas = Vec::with_capacity(b);
    let mut event_list = Vec::with_capacity(b);
    let mut fields: Vec<Option<Vec<Field>>> = Vec::with_capacity(b);
    for r in results {
        match r {
            Ok(mut res) => {
                reason.push(None);
                error_class.push(None);
                metas.push(Some(Py::new(py, PyRunMeta::of_run(py, &res, opts, float32)?)?));
                event_list.push(Some(Py::new(py, PyRunEvents::of_run(py, &res))?));
                fields.push(Some(take_fields(&mut res, nx, nu, n)));
            }
            Err(e) => {
                reason.push(Some(e.to_string()));
                error_class.push(Some(to_py_err(py, e).get_type(py).name()?.to_string()));
                metas.push(None);
                event_list.push(None);
                fields.push(None);
            }
        }
    }
    // The layout of a record: that of the first successful rollout (or the three always recorded).
    let layout: Vec<(Record, usize, bool)> = match fields.iter().flatten().next() {
        Some(f) => f.iter().map(|f| (f.record, f.width, f.scalar)).collect(),
        None => vec![(Record::T, 1, true), (Record::X, nx, false), (Record::U, nu, false)],
    };
    // Regroup by record (moving the buffers, no copy): columns[j][i] is record j of rollout i.
    let mut columns: Vec<Vec<Option<Vec<f64>>>> = layout.iter().map(|_| Vec::with_capacity(b)).collect();
    for (i, f) in fields.into_iter().enumerate() {
        match f {
            Some(f) => {
                let same = f.len() == layout.len()
                    && f.iter().zip(&layout).all(|(f, &(name, width, _))| f.record == name && f.width == width && f.values.len() == k * width);
                if !same {
                    let msg = format!("rollout {i} records differently from rollout 0 (another kind of controller?); give every rollout the same kind of controller");
                    return Err(to_py_err(py, SpacearmError::InvalidArgument(msg)));
                }
                for (column, field) in columns.iter_mut().zip(f) {
                    column.push(Some(field.values));
                }
            }
            None => columns.iter_mut().for_each(|c| c.push(None)),
        }
    }
    // Stack each record on its own thread (a copy into the batch buffer, page faults included,
    // is most of this work), freeing each rollout's buffer once copied.
    let stacked: Vec<Stacked> = py.detach(|| {
        columns
            .into_par_iter()
            .zip(layout.par_iter())
            .map(|(column, &(name, width, _))| {
                let mut values = Vec::with_capacity(b * k * width);
                for v in column {
                    match v {
                        Some(mut v) => values.append(&mut v),
                        None => values.resize(values.len() + k * width, f64::NAN),
                    }
                }
                if float32 && !name.stays_float64() {
                    Stacked::F32(values.iter().map(|&v| v as f32).collect())
                } else {
                    Stacked::F64(values)
                }
            })
            .collect()
    });
    let mut arrays = Vec::with_capacity(layout.len());
    for (values, &(name, width, scalar)) in stacked.into_iter().zip(&layout) {
        let shape: Vec<usize> = if scalar { vec![b, k] } else { vec![b, k, width] };
        let array = match values {
            Stacked::F64(v) => PyArray1::from_vec(py, v).into_any(),
            Stacked::F32(v) => PyArray1::from_vec(py, v).into_any(),
        };
        arrays.push((name, array.call_method1("reshape", (shape,))?));
    }
    Ok(PyRolloutBatch {
        records: Py::new(py, PyRunRecords::from_arrays(arrays)?)?,
        ok: PyArray1::from_vec(py, ok).unbind(),
        reason,
        error_class,
        meta: metas,
        events: event_list,
    })
}
