//! The core's rules and defaults, read by the Python package instead of restating them:
//! the mode and integrator names, the simulation defaults, the damped-least-squares defaults and
//! the quintic time scaling of the references (docs/simulation-core.md).

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use spacearm_core::math::dls::DampingLaw;
use spacearm_core::sim::integrate::IntegratorKind;
use spacearm_core::sim::modes::Mode;
use spacearm_core::sim::reference::quintic_scaling as core_quintic_scaling;
use spacearm_core::sim::simulate::SimOptions;

/// Rest-to-rest quintic time scaling `(s, ṡ, s̈)` at each time of `t` (1-D array).
#[pyfunction]
fn quintic_scaling<'py>(
    py: Python<'py>,
    t: PyReadonlyArray1<'py, f64>,
    t_start: f64,
    t_end: f64,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
    let t = t.as_slice()?;
    let (mut s, mut sd, mut sdd) = (Vec::with_capacity(t.len()), Vec::with_capacity(t.len()), Vec::with_capacity(t.len()));
    for &ti in t {
        let (a, b, c) = core_quintic_scaling(ti, t_start, t_end);
        s.push(a);
        sd.push(b);
        sdd.push(c);
    }
    Ok((PyArray1::from_vec(py, s), PyArray1::from_vec(py, sd), PyArray1::from_vec(py, sdd)))
}

/// Register the rules on the extension module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("MODES", Mode::NAMES.to_vec())?;
    m.add("INTEGRATORS", IntegratorKind::NAMES.to_vec())?;
    let d = SimOptions::default();
    let defaults = PyDict::new(py);
    defaults.set_item("mode", d.mode.name())?;
    defaults.set_item("integrator", d.integrator.name())?;
    defaults.set_item("dt", d.dt)?;
    defaults.set_item("rtol", d.rtol)?;
    defaults.set_item("atol", d.atol)?;
    defaults.set_item("record_every", d.record_every)?;
    defaults.set_item("joint_limits", d.joint_limits)?;
    defaults.set_item("max_steps", d.max_steps)?;
    m.add("SIM_DEFAULTS", defaults)?;
    let law = DampingLaw::default();
    let dls = PyDict::new(py);
    dls.set_item("threshold", law.threshold)?;
    dls.set_item("max_damping", law.max_damping)?;
    m.add("DLS_DEFAULTS", dls)?;
    m.add_function(wrap_pyfunction!(quintic_scaling, m)?)?;
    Ok(())
}
