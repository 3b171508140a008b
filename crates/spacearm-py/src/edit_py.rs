//! The core's model edits (`spacearm_core::model::edit`): attach a body, attach a model,
//! remove a subtree, each a new validated `_core.Model` (wrapped by `spacearm.Robot.attach_body`,
//! `Robot.attach` and `Robot.remove_subtree`). Conversion only: the rules are the core's.

use pyo3::prelude::*;
use spacearm_core::{Model, ModelBuilder, Mount};

use crate::builder_py::add_link_to;

use crate::convert::*;
use crate::model_py::PyModel;

/// Build the edited model `b`, renamed to `name` when given.
fn finish(py: Python<'_>, mut b: ModelBuilder, name: Option<&str>) -> PyResult<PyModel> {
    if let Some(n) = name {
        b.set_name(n).or_raise(py)?;
    }
    Ok(PyModel::new(b.build().or_raise(py)?))
}

/// `model` with a body `name` attached to `parent` (core `Model::attach_body`): on a fixed joint
/// (a payload, its CM at `origin`) or on a revolute or prismatic joint at `origin` about `axis`,
/// its CM at `com` from the joint; `dynamics = (actuated, stiffness, damping, rest)`.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (model, name, parent, origin, rotation, mass, inertia, joint_type="fixed", axis=[0.0, 0.0, 1.0], com=[0.0; 3], joint_name=None, limits=None, dynamics=None, model_name=None))]
pub fn model_attach_body(
    py: Python<'_>,
    model: &PyModel,
    name: &str,
    parent: &str,
    origin: [f64; 3],
    rotation: [f64; 4],
    mass: f64,
    inertia: [[f64; 3]; 3],
    joint_type: &str,
    axis: [f64; 3],
    com: [f64; 3],
    joint_name: Option<String>,
    limits: Option<[f64; 4]>,
    dynamics: Option<(bool, f64, f64, f64)>,
    model_name: Option<&str>,
) -> PyResult<PyModel> {
    let mut b = model.model.to_builder();
    add_link_to(py, &mut b, (name.into(), parent.into(), joint_type.into(), origin, rotation, axis, com, mass, inertia, joint_name, limits), dynamics)?;
    finish(py, b, model_name)
}

/// `model` with `other` attached to `parent` at `origin`/`rotation` (core
/// `ModelBuilder::attach_model`): its base the link `base_link` (default `<prefix><base>`),
/// every other name prefixed.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (model, other, parent, origin, rotation, prefix, base_link=None, model_name=None))]
pub fn model_attach_model(
    py: Python<'_>,
    model: &PyModel,
    other: &PyModel,
    parent: &str,
    origin: [f64; 3],
    rotation: [f64; 4],
    prefix: &str,
    base_link: Option<&str>,
    model_name: Option<&str>,
) -> PyResult<PyModel> {
    let other: &Model = &other.model;
    let mut b = model.model.to_builder();
    b.attach_model(other, &Mount::new(parent, origin, rotation), prefix, base_link).or_raise(py)?;
    finish(py, b, model_name)
}

/// `model` without the link `body` and everything below it (core `ModelBuilder::remove_subtree`).
#[pyfunction]
#[pyo3(signature = (model, body, model_name=None))]
pub fn model_remove_subtree(py: Python<'_>, model: &PyModel, body: &str, model_name: Option<&str>) -> PyResult<PyModel> {
    let mut b = model.model.to_builder();
    b.remove_subtree(body).or_raise(py)?;
    finish(py, b, model_name)
}
