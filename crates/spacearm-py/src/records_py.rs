//! Records of a run as numpy arrays, without a second copy: each record `Vec` is handed to numpy
//! (`PyArray1::from_vec` keeps the allocation; the reshape is a view), or converted to float32
//! field by field, freeing each float64 buffer as soon as its float32 copy exists. The run's
//! description (`meta`) as a dict.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use spacearm_core::sim::simulate::{SimOptions, SimResult};

/// One recorded quantity of a run, row-major with `width` values per sample; `scalar`: one value
/// per sample, returned 1-D.
pub struct Field {
    pub name: &'static str,
    pub values: Vec<f64>,
    pub width: usize,
    pub scalar: bool,
}

/// Take every recorded quantity out of `res` (leaving its records empty), with the names the
/// Python `Trajectory` uses.
pub fn take_fields(res: &mut SimResult, nx: usize, nu: usize, n: usize) -> Vec<Field> {
    let n_ref = res.reference_width;
    let n_wheels = res.wheel_dofs.len();
    let r = &mut res.records;
    let take = std::mem::take::<Vec<f64>>;
    let f = |name, values, width, scalar| Field { name, values, width, scalar };
    let mut out = vec![
        f("t", take(&mut r.t), 1, true),
        f("x", take(&mut r.x), nx, false),
        f("u", take(&mut r.u), nu, false),
        f("du", take(&mut r.du), nu, false),
        f("tau", take(&mut r.tau), n, false),
        f("tau_cmd", take(&mut r.tau_cmd), n, false),
        f("base_wrench", take(&mut r.base_wrench), 6, false),
        f("P", take(&mut r.linear_momentum), 3, false),
        f("L_origin", take(&mut r.angular_momentum_origin), 3, false),
        f("L_com", take(&mut r.angular_momentum_com), 3, false),
        f("energy", take(&mut r.energy), 1, true),
        f("com", take(&mut r.com), 3, false),
    ];
    if let (Some(p), Some(q)) = (r.ee_position.take(), r.ee_quat.take()) {
        out.push(f("ee_position", p, 3, false));
        out.push(f("ee_quat", q, 4, false));
    }
    if let Some(v) = r.reference.take() {
        out.push(f("reference", v, n_ref, false));
    }
    if let Some(v) = r.tracking_error.take() {
        out.push(f("tracking_error", v, 1, true));
    }
    if let Some(v) = r.attitude_error.take() {
        out.push(f("attitude_error", v, 1, true));
    }
    if let Some(v) = r.wheel_speed.take() {
        out.push(f("wheel_speed", v, n_wheels, false));
    }
    out
}

/// `values` as a numpy array of `shape` (row-major), float32 if asked (the time stays float64:
/// float32 cannot tell apart the steps of a long run). No copy for float64.
pub fn to_numpy<'py>(py: Python<'py>, name: &str, values: Vec<f64>, shape: &[usize], float32: bool) -> PyResult<Bound<'py, PyAny>> {
    let array = if float32 && name != "t" {
        let narrow: Vec<f32> = values.iter().map(|&v| v as f32).collect();
        drop(values);
        PyArray1::from_vec(py, narrow).into_any()
    } else {
        PyArray1::from_vec(py, values).into_any()
    };
    if shape.len() == 1 {
        return Ok(array);
    }
    array.call_method1("reshape", (shape.to_vec(),))
}

/// The saturation onsets as three arrays: time, actuator index, kind code.
pub fn events<'py>(py: Python<'py>, res: &SimResult, out: &Bound<'py, PyDict>) -> PyResult<()> {
    let ev_t: Vec<f64> = res.events.iter().map(|e| e.t).collect();
    let ev_a: Vec<i64> = res.events.iter().map(|e| e.actuator as i64).collect();
    let ev_k: Vec<i64> = res.events.iter().map(|e| e.kind as i64).collect();
    out.set_item("saturation_t", PyArray1::from_vec(py, ev_t))?;
    out.set_item("saturation_actuator", PyArray1::from_vec(py, ev_a))?;
    out.set_item("saturation_kind", PyArray1::from_vec(py, ev_k))?;
    Ok(())
}

/// The description of a run (what `Trajectory.meta` holds, less what Python adds).
pub fn meta<'py>(py: Python<'py>, res: &SimResult, opts: &SimOptions, float32: bool) -> PyResult<Bound<'py, PyDict>> {
    let meta = PyDict::new(py);
    meta.set_item("mode", opts.mode.name())?;
    meta.set_item("integrator", opts.integrator.name())?;
    meta.set_item("dt", opts.dt)?;
    meta.set_item("rtol", opts.rtol)?;
    meta.set_item("atol", opts.atol)?;
    meta.set_item("controller", &res.controller)?;
    meta.set_item("conserved", PyList::new(py, res.drift.iter().map(|(c, _)| c.name()))?)?;
    let drift = PyDict::new(py);
    for (c, v) in &res.drift {
        drift.set_item(c.name(), *v)?;
    }
    meta.set_item("drift", drift)?;
    let drift_scales = PyDict::new(py);
    for (c, v) in &res.drift_scales {
        drift_scales.set_item(c.name(), *v)?;
    }
    meta.set_item("drift_scales", drift_scales)?;
    meta.set_item("n_steps", res.n_steps)?;
    meta.set_item("n_rejected", res.n_rejected)?;
    meta.set_item("n_rhs_evals", res.n_rhs_evals)?;
    meta.set_item("actuator_names", res.actuator_names.clone())?;
    meta.set_item("wheel_dofs", res.wheel_dofs.clone())?;
    meta.set_item("tracking_error_kind", res.tracking.map(|t| t.name()))?;
    meta.set_item("record_every", opts.record_every)?;
    meta.set_item("record_dtype", if float32 { "float32" } else { "float64" })?;
    meta.set_item("joint_limits", opts.joint_limits)?;
    let dropped = PyDict::new(py);
    dropped.set_item("max_norm", res.dropped_wrench_max)?;
    dropped.set_item("count", res.dropped_wrench_count)?;
    meta.set_item("dropped_base_wrench", dropped)?;
    Ok(meta)
}

/// One run's records, events and `"_meta"` as the dict `spacearm.Trajectory` is made from.
pub fn run_dict<'py>(py: Python<'py>, mut res: SimResult, opts: &SimOptions, float32: bool, nx: usize, nu: usize, n: usize) -> PyResult<Bound<'py, PyDict>> {
    let k = res.records.n_samples;
    let out = PyDict::new(py);
    for field in take_fields(&mut res, nx, nu, n) {
        let shape: Vec<usize> = if field.scalar { vec![k] } else { vec![k, field.width] };
        out.set_item(field.name, to_numpy(py, field.name, field.values, &shape, float32)?)?;
    }
    events(py, &res, &out)?;
    out.set_item("_meta", meta(py, &res, opts, float32)?)?;
    Ok(out)
}
