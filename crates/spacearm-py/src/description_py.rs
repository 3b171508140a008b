//! The typed description of a model that `Model.describe()` hands to Python: `ModelInfo` with
//! its `BaseInfo`, `LinkInfo` (each with its `JointLimitsInfo`) and `PointInfo`. Frozen
//! snapshots of the immutable core `Model`, read by `spacearm.model.description`; they carry
//! only what the core holds (frames and units: docs/conventions.md, "A model's frames,
//! concretely"). Every array attribute is a new numpy array at each access, so no caller can
//! change what another reads.

use nalgebra::{Matrix3, Vector3};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use spacearm_core as core;

use crate::convert::{array1, matrix};

/// The spacecraft base (body 0); its frame has its origin at the base CM.
#[pyclass(module = "spacearm._core", name = "BaseInfo", frozen)]
#[derive(Clone)]
pub struct PyBaseInfo {
    /// The base's name.
    #[pyo3(get)]
    name: String,
    /// Mass, kg.
    #[pyo3(get)]
    mass: f64,
    inertia: Matrix3<f64>,
}

#[pymethods]
impl PyBaseInfo {
    /// (3, 3) kg·m²: inertia about the base CM, in base-frame axes.
    #[getter]
    fn inertia<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.inertia)
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.BaseInfo '{}': mass {} kg, inertia (3, 3)>", self.name, self.mass)
    }
}

/// A joint's limits; an absent bound is infinite (`-inf` for `lower`, `inf` for the others).
#[pyclass(module = "spacearm._core", name = "JointLimitsInfo", frozen)]
#[derive(Clone)]
pub struct PyJointLimitsInfo {
    /// Lower position bound: rad (revolute) or m (prismatic).
    #[pyo3(get)]
    lower: f64,
    /// Upper position bound: rad (revolute) or m (prismatic).
    #[pyo3(get)]
    upper: f64,
    /// Speed bound: rad/s or m/s.
    #[pyo3(get)]
    velocity: f64,
    /// Effort bound: N·m (revolute) or N (prismatic).
    #[pyo3(get)]
    effort: f64,
}

#[pymethods]
impl PyJointLimitsInfo {
    fn __repr__(&self) -> String {
        format!(
            "<spacearm._core.JointLimitsInfo lower={} upper={} velocity={} effort={}>",
            self.lower, self.upper, self.velocity, self.effort
        )
    }
}

/// One link (body `k + 1` for the `k`-th link) and the joint connecting it to its parent. The
/// link frame has its origin at the link CM; at `q = 0` its axes are the parent's rotated by
/// `rotation`.
#[pyclass(module = "spacearm._core", name = "LinkInfo", frozen)]
#[derive(Clone)]
pub struct PyLinkInfo {
    /// The link's name.
    #[pyo3(get)]
    name: String,
    /// Name of the parent body (the base's name for a link on the base).
    #[pyo3(get)]
    parent: String,
    /// Body index of the parent (0 = base).
    #[pyo3(get)]
    parent_index: usize,
    /// Name of the joint.
    #[pyo3(get)]
    joint: String,
    /// Joint type: "revolute", "prismatic" or "fixed".
    #[pyo3(get, name = "type")]
    kind: &'static str,
    origin: Vector3<f64>,
    rotation: [f64; 4],
    axis: Vector3<f64>,
    com: Vector3<f64>,
    /// Mass, kg.
    #[pyo3(get)]
    mass: f64,
    inertia: Matrix3<f64>,
    /// The joint's limits.
    #[pyo3(get)]
    limits: PyJointLimitsInfo,
    /// Index of the joint's coordinate in `q`; None for a fixed joint.
    #[pyo3(get)]
    dof: Option<usize>,
}

#[pymethods]
impl PyLinkInfo {
    /// (3,) m: joint position in the parent frame, measured from the parent's CM.
    #[getter]
    fn origin<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.origin.as_slice())
    }

    /// (4,) unit quaternion `[x, y, z, w]`: the link frame in the parent frame at `q = 0`.
    #[getter]
    fn rotation<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, &self.rotation)
    }

    /// (3,) unit joint axis in the link frame (unused by a fixed joint).
    #[getter]
    fn axis<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.axis.as_slice())
    }

    /// (3,) m: the link's CM measured from its joint, in the link frame.
    #[getter]
    fn com<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.com.as_slice())
    }

    /// (3, 3) kg·m²: inertia about the link's CM, in link-frame axes.
    #[getter]
    fn inertia<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.inertia)
    }

    fn __repr__(&self) -> String {
        format!(
            "<spacearm._core.LinkInfo '{}' ({} joint '{}' on '{}'): origin (3,), rotation (4,), axis (3,), com (3,), inertia (3, 3)>",
            self.name, self.kind, self.joint, self.parent
        )
    }
}

/// A named point fixed to a body (an end effector, a grasp point).
#[pyclass(module = "spacearm._core", name = "PointInfo", frozen)]
#[derive(Clone)]
pub struct PyPointInfo {
    /// The point's name.
    #[pyo3(get)]
    name: String,
    /// Name of the body carrying the point.
    #[pyo3(get)]
    body: String,
    /// Index of the body carrying the point (0 = base).
    #[pyo3(get)]
    body_index: usize,
    offset: Vector3<f64>,
}

#[pymethods]
impl PyPointInfo {
    /// (3,) m: the point from the body's CM, in the body frame.
    #[getter]
    fn offset<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.offset.as_slice())
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.PointInfo '{}' on '{}': offset (3,)>", self.name, self.body)
    }
}

/// A whole model: base, links in tree order (a parent before its children), named points, end
/// effector and initial joint coordinates.
#[pyclass(module = "spacearm._core", name = "ModelInfo", frozen)]
pub struct PyModelInfo {
    /// The model's name.
    #[pyo3(get)]
    name: String,
    /// The base (body 0).
    #[pyo3(get)]
    base: PyBaseInfo,
    links: Vec<PyLinkInfo>,
    points: Vec<PyPointInfo>,
    /// Name of the end-effector point, or None.
    #[pyo3(get)]
    end_effector: Option<String>,
    initial_q: Vec<f64>,
}

#[pymethods]
impl PyModelInfo {
    /// The links in tree order (link `k` is body `k + 1`), a tuple of `LinkInfo`.
    #[getter]
    fn links<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.links.iter().cloned())
    }

    /// The named points in the order they were added, a tuple of `PointInfo`.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.points.iter().cloned())
    }

    /// (N,) initial joint coordinates: rad (revolute) or m (prismatic), in `q` order.
    #[getter]
    fn initial_q<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, &self.initial_q)
    }

    fn __repr__(&self) -> String {
        format!(
            "<spacearm._core.ModelInfo '{}': base, {} links, {} points, initial_q ({},)>",
            self.name,
            self.links.len(),
            self.points.len(),
            self.initial_q.len()
        )
    }
}

impl PyModelInfo {
    /// The description of `m`, field by field as the core holds it.
    pub fn of(m: &core::Model) -> PyModelInfo {
        let base = PyBaseInfo { name: m.base_name().to_string(), mass: m.base().mass, inertia: m.base().inertia };
        let links = m
            .links()
            .iter()
            .enumerate()
            .map(|(k, l)| {
                let j = &l.joint;
                let q = j.rotation_in_parent;
                PyLinkInfo {
                    name: l.name.clone(),
                    parent: m.body_name(l.parent).to_string(),
                    parent_index: l.parent,
                    joint: j.name.clone(),
                    kind: j.kind.as_str(),
                    origin: j.origin_in_parent,
                    rotation: [q.i, q.j, q.k, q.w],
                    axis: j.axis.into_inner(),
                    com: l.com_from_joint,
                    mass: l.mass.mass,
                    inertia: l.mass.inertia,
                    limits: PyJointLimitsInfo {
                        lower: j.limits.lower,
                        upper: j.limits.upper,
                        velocity: j.limits.velocity,
                        effort: j.limits.effort,
                    },
                    dof: m.dof_of_body(k + 1),
                }
            })
            .collect();
        let points = m
            .points()
            .iter()
            .map(|p| PyPointInfo { name: p.name.clone(), body: m.body_name(p.body).to_string(), body_index: p.body, offset: p.offset })
            .collect();
        PyModelInfo {
            name: m.name().to_string(),
            base,
            links,
            points,
            end_effector: m.end_effector().map(|i| m.points()[i].name.clone()),
            initial_q: m.initial_q().to_vec(),
        }
    }
}
