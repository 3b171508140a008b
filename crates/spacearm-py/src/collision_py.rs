//! Binding of the core's collision detection (`spacearm_core::collision`, docs/contact.md): the
//! contacts of a state between a model's collision shapes, as frozen `Contact` objects (the
//! public type; `spacearm.contact.contacts` is the face users see).

use numpy::PyArray1;
use pyo3::prelude::*;
use spacearm_core::collision::{self, CollisionShapes, PairFilter};
use spacearm_core::SpacearmError;

use crate::convert::*;
use crate::model_py::PyModel;

/// A contact between two collision shapes at one state, in the inertial frame 𝒥
/// (`spacearm_core::collision::Contact`).
#[pyclass(module = "spacearm._core", name = "Contact", frozen, get_all)]
pub struct PyContact {
    /// The two geometries' names.
    geometries: (String, String),
    /// Their bodies' names.
    bodies: (String, String),
    /// (3,) the closest (deepest) point of the first shape's surface, m.
    point_a: Py<PyArray1<f64>>,
    /// (3,) the closest (deepest) point of the second shape's surface, m.
    point_b: Py<PyArray1<f64>>,
    /// (3,) the unit normal from the first shape towards the second.
    normal: Py<PyArray1<f64>>,
    /// Signed distance, m: > 0 apart, < 0 interpenetrating (the depth is −distance).
    distance: f64,
}

#[pymethods]
impl PyContact {
    fn __repr__(&self) -> String {
        format!("<Contact {} ({}) ~ {} ({}): distance {:.6e} m>", self.geometries.0, self.bodies.0, self.geometries.1, self.bodies.1, self.distance)
    }
}

/// The contacts of the state `x` between `model`'s collision shapes (docs/contact.md): every pair
/// of bodies but a body and its parent, or the body-name pairs `pairs`; those at most `margin`
/// apart (m).
#[pyfunction]
#[pyo3(signature = (model, x, pairs=None, margin=0.0))]
fn contacts(py: Python<'_>, model: PyRef<'_, PyModel>, x: &Bound<'_, PyAny>, pairs: Option<Vec<(String, String)>>, margin: f64) -> PyResult<Vec<PyContact>> {
    let x = vec_arg(x, "x")?;
    let m = &model.model;
    let names = m.body_names();
    let index = |name: &str| {
        names.iter().position(|n| n == name).ok_or_else(|| SpacearmError::NotFound(format!("no body named '{name}' in '{}'; the bodies are {names:?}", m.name())))
    };
    let filter = match pairs {
        None => PairFilter::AllButAdjacent,
        Some(list) => PairFilter::Bodies(list.iter().map(|(a, b)| Ok((index(a)?, index(b)?))).collect::<Result<Vec<_>, SpacearmError>>().or_raise(py)?),
    };
    let shapes = CollisionShapes::from_model(m).or_raise(py)?;
    let found = model.with_data(|m, d| collision::contacts(m, d, &shapes, x.as_slice(), &filter, margin)).or_raise(py)?;
    let geometry = |k: usize| m.geometries()[k].name.clone();
    Ok(found
        .into_iter()
        .map(|c| PyContact {
            geometries: (geometry(c.geometry[0]), geometry(c.geometry[1])),
            bodies: (names[c.body[0]].clone(), names[c.body[1]].clone()),
            point_a: PyArray1::from_slice(py, c.point[0].as_slice()).unbind(),
            point_b: PyArray1::from_slice(py, c.point[1].as_slice()).unbind(),
            normal: PyArray1::from_slice(py, c.normal.as_slice()).unbind(),
            distance: c.distance,
        })
        .collect())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    add_to_module!(m, functions: [contacts], classes: [PyContact],);
    Ok(())
}
