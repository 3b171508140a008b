//! The core's rules and defaults, read by the Python package instead of restating them:
//! the mode and integrator names, the simulation defaults, the damped-least-squares defaults
//! (those tables and the model bounds are typed classes: `rule_tables_py.rs`), the quintic time scaling of the references (docs/simulation-core.md), the tolerance on input
//! quaternions, the physical bounds of a model, the rule of one body's mass properties, the
//! memory limit of one request and the box drawn for a body of given moments.

use nalgebra::Matrix3;
use numpy::PyArray1;
use pyo3::prelude::*;
use spacearm_core::error::{ModelItem, SpacearmError};
use spacearm_core::model::body::{MassProperties, TriangleInequality};
use spacearm_core::sim::integrate::IntegratorKind;
use spacearm_core::sim::modes::Mode;
use spacearm_core::sim::reference::quintic_scaling as core_quintic_scaling;

/// Rest-to-rest quintic time scaling `(s, ṡ, s̈)` at each time of `t` (1-D array).
#[pyfunction]
fn quintic_scaling<'py>(
    py: Python<'py>,
    t: &Bound<'py, PyAny>,
    t_start: f64,
    t_end: f64,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
    let t = crate::convert::vec_arg(t, "t")?;
    let t = t.as_slice();
    let (mut s, mut sd, mut sdd) = (Vec::with_capacity(t.len()), Vec::with_capacity(t.len()), Vec::with_capacity(t.len()));
    for &ti in t {
        let (a, b, c) = core_quintic_scaling(ti, t_start, t_end);
        s.push(a);
        sd.push(b);
        sdd.push(c);
    }
    Ok((PyArray1::from_vec(py, s), PyArray1::from_vec(py, sd), PyArray1::from_vec(py, sdd)))
}

/// The core's verdict on one body's mass properties (`MassProperties::checked` in
/// `model/body.rs`, the rule every body of every model obeys): `None` when `mass` (kg) and
/// `inertia` ((3, 3) kg·m², about the CM) pass, else `(field, message)` with `field` `"mass"` or
/// `"inertia"` and the message of the `ModelError` the builder would raise (`invalid model: `
/// and the rule's text, which names the body as `who`). With
/// `triangle_inequality=False` that one rule is not applied (it is the only one a model may
/// relax; the URDF reader checks each link's own inertial this way before fixed links are merged,
/// and the merged bodies meet the whole rule when the model is built). A link may be massless,
/// so zero mass passes.
#[pyfunction]
#[pyo3(signature = (who, mass, inertia, *, triangle_inequality = true))]
fn body_mass_properties_error(who: &str, mass: f64, inertia: [[f64; 3]; 3], triangle_inequality: bool) -> Option<(String, String)> {
    let rule = if triangle_inequality { TriangleInequality::Enforce } else { TriangleInequality::Warn };
    let inertia = Matrix3::from_fn(|i, j| inertia[i][j]);
    match MassProperties::checked(ModelItem::Model, who, mass, inertia, false, rule) {
        Ok(_) => None,
        Err(e) => Some((format!("{:?}", e.field).to_lowercase(), SpacearmError::from(e).to_string())),
    }
}

/// Side lengths (m) of the uniform box whose principal moments about its centre are
/// `moments` (kg·m²) for `mass` (kg): the default shape of a body whose shape the data do not
/// give (model/geometry.rs, `box_of_moments`).
#[pyfunction]
fn box_of_moments(mass: f64, moments: [f64; 3]) -> [f64; 3] {
    spacearm_core::model::geometry::box_of_moments(mass, moments)
}

/// Register the rules on the extension module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("MODES", Mode::NAMES.to_vec())?;
    m.add("INTEGRATORS", IntegratorKind::NAMES.to_vec())?;
    m.add("PASSIVE_TREATMENTS", spacearm_core::control::PassiveTreatment::NAMES.to_vec())?;
    m.add("CONTROLLER_LABELS", spacearm_core::control::CONTROLLER_LABELS.iter().copied().collect::<std::collections::HashMap<_, _>>())?;
    m.add("QUATERNION_TOLERANCE", spacearm_core::math::rotations::QUATERNION_TOLERANCE)?;
    m.add("MEMORY_LIMIT_BYTES", spacearm_core::admission::MEMORY_LIMIT_BYTES)?;
    m.add("GOAL_TOLERANCE", spacearm_core::control::GOAL_TOLERANCE)?;
    m.add("MAX_HANDLE_RATIO", spacearm_core::algorithms::impulse::MAX_HANDLE_RATIO)?;
    crate::rule_tables_py::add_tables(m)?;
    crate::convert::add_to_module!(m, functions: [quintic_scaling, body_mass_properties_error, box_of_moments]);
    Ok(())
}
