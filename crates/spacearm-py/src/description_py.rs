//! The typed description of a model, the public `spacearm.ModelDescription` (what
//! `Model.describe()` and `Robot.description` return) with its `BaseDescription`,
//! `LinkDescription` (each with its `JointLimits`) and `PointDescription`: frozen snapshots of
//! the immutable core `Model`, carrying only what the core holds (frames and units:
//! docs/conventions.md, "A model's frames, concretely"). These classes are the public types
//! (`spacearm.model.description` re-exports them); there is no Python copy of their fields.
//!
//! Everything is built once, when the model is described: every attribute read hands out the
//! same object, and the arrays are read-only, so no caller can change what another reads.
//! `to_dict` is the plain-data form of `Robot.describe()`; `link`/`point` look items up by name.

use nalgebra::{Matrix, Vector3};
use numpy::{PyArray, PyArray1, PyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use spacearm_core as core;

use crate::convert::{array1, matrix, read_only, result_class};
use crate::errors_py::{new_error, ErrorClass};

fn vector<'py>(py: Python<'py>, v: &[f64]) -> Py<PyArray1<f64>> {
    read_only(array1(py, v))
}

fn matrix3(py: Python<'_>, m: &nalgebra::Matrix3<f64>) -> Py<PyArray2<f64>> {
    read_only(matrix(py, m))
}

fn vector3(py: Python<'_>, v: &Vector3<f64>) -> Py<PyArray1<f64>> {
    vector(py, Matrix::as_slice(v))
}

/// `array.tolist()`: nested lists of Python floats.
fn to_list<'py, D>(py: Python<'py>, a: &Py<PyArray<f64, D>>) -> PyResult<Bound<'py, PyAny>> {
    a.bind(py).call_method0("tolist")
}

result_class! {
    /// The spacecraft base (body 0). Its frame has its origin at the base CM.
    PyBaseDescription as "BaseDescription", fn of(py: Python<'_>, m: &core::Model) {
        /// The base's name.
        name: String = m.base_name().to_string(),
        /// Mass, kg.
        mass: f64 = m.base().mass,
        /// (3, 3) kg·m², read-only: inertia about the base CM, in base-frame axes.
        inertia: Py<PyArray2<f64>> = matrix3(py, &m.base().inertia),
    }
}

#[pymethods]
impl PyBaseDescription {
    fn __repr__(&self) -> String {
        format!("<spacearm.BaseDescription '{}': mass {} kg, inertia (3, 3)>", self.name, self.mass)
    }
}

result_class! {
    /// A joint's limits. `lower`/`upper`: position bounds (rad for a revolute joint, m for a
    /// prismatic one); `velocity`: speed bound (rad/s or m/s); `effort`: torque (N·m) or force (N)
    /// bound. An absent bound is infinite (`-inf` for `lower`, `inf` for the others).
    PyJointLimits as "JointLimits", fn of(l: &core::JointLimits) {
        /// Lower position bound: rad (revolute) or m (prismatic); `-inf` when unbounded.
        lower: f64 = l.lower,
        /// Upper position bound: rad (revolute) or m (prismatic); `inf` when unbounded.
        upper: f64 = l.upper,
        /// Speed bound: rad/s or m/s; `inf` when unbounded.
        velocity: f64 = l.velocity,
        /// Effort bound: N·m (revolute) or N (prismatic); `inf` when unbounded.
        effort: f64 = l.effort,
    }
}

#[pymethods]
impl PyJointLimits {
    /// `[lower, upper, velocity, effort]`, the order of `Robot.describe()`.
    fn to_list(&self) -> [f64; 4] {
        [self.lower, self.upper, self.velocity, self.effort]
    }

    fn __repr__(&self) -> String {
        format!("JointLimits(lower={:?}, upper={:?}, velocity={:?}, effort={:?})", self.lower, self.upper, self.velocity, self.effort)
    }
}

result_class! {
    /// One link (body `k + 1` for the `k`-th link) and the joint connecting it to its parent. The
    /// link frame has its origin at the link CM; at `q = 0` its axes are the parent's rotated by
    /// `rotation`.
    PyLinkDescription as "LinkDescription", fn of(py: Python<'_>, m: &core::Model, k: usize) -> PyResult [
        let l = &m.links()[k];
        let j = &l.joint;
        let q = j.rotation_in_parent;
    ] {
        /// The link's name.
        name: String = l.name.clone(),
        /// Name of the parent body (the base's name for a link on the base).
        parent: String = m.body_name(l.parent).to_string(),
        /// Body index of the parent (0 = base).
        parent_index: usize = l.parent,
        /// Name of the joint.
        joint: String = j.name.clone(),
        /// Joint type: "revolute", "prismatic" or "fixed".
        #[pyo3(name = "type")]
        kind: &'static str = j.kind.as_str(),
        /// (3,) m, read-only: joint position in the parent frame, measured from the parent's CM.
        origin: Py<PyArray1<f64>> = vector3(py, &j.origin_in_parent),
        /// (4,) unit quaternion `[x, y, z, w]`, read-only: the link frame in the parent frame at `q = 0`.
        rotation: Py<PyArray1<f64>> = vector(py, &[q.i, q.j, q.k, q.w]),
        /// (3,) read-only: unit joint axis in the link frame (unused by a fixed joint: as given, or
        /// z if given zero).
        axis: Py<PyArray1<f64>> = vector3(py, &j.axis.into_inner()),
        /// (3,) m, read-only: the link's CM measured from its joint, in the link frame.
        com: Py<PyArray1<f64>> = vector3(py, &l.com_from_joint),
        /// Mass, kg.
        mass: f64 = l.mass.mass,
        /// (3, 3) kg·m², read-only: inertia about the link's CM, in link-frame axes.
        inertia: Py<PyArray2<f64>> = matrix3(py, &l.mass.inertia),
        /// The joint's limits.
        limits: Py<PyJointLimits> = Py::new(py, PyJointLimits::of(&j.limits))?,
        /// Index of the joint's coordinate in `q`; None for a fixed joint.
        dof: Option<usize> = m.dof_of_body(k + 1),
        /// Whether a motor drives the joint (False: a passive joint, docs/flexibility.md).
        actuated: bool = j.dynamics.actuated,
        /// Joint spring stiffness, N·m/rad (revolute) or N/m (prismatic); 0: none.
        stiffness: f64 = j.dynamics.stiffness,
        /// Joint damping, N·m·s/rad (revolute) or N·s/m (prismatic); 0: none.
        damping: f64 = j.dynamics.damping,
        /// The spring's rest coordinate, rad or m.
        rest: f64 = j.dynamics.rest,
    }
}

#[pymethods]
impl PyLinkDescription {
    fn __repr__(&self) -> String {
        format!(
            "<spacearm.LinkDescription '{}' ({} joint '{}' on '{}'): origin (3,), rotation (4,), axis (3,), com (3,), inertia (3, 3)>",
            self.name, self.kind, self.joint, self.parent
        )
    }
}

result_class! {
    /// A named point fixed to a body (an end effector, a grasp point).
    PyPointDescription as "PointDescription", fn of(py: Python<'_>, m: &core::Model, p: &core::model::Point) {
        /// The point's name.
        name: String = p.name.clone(),
        /// Name of the body carrying the point.
        body: String = m.body_name(p.body).to_string(),
        /// Index of the body carrying the point (0 = base).
        body_index: usize = p.body,
        /// (3,) m, read-only: the point from the body's CM, in the body frame.
        offset: Py<PyArray1<f64>> = vector3(py, &p.offset),
    }
}

#[pymethods]
impl PyPointDescription {
    fn __repr__(&self) -> String {
        format!("<spacearm.PointDescription '{}' on '{}': offset (3,)>", self.name, self.body)
    }
}

result_class! {
    /// A visual or collision shape fixed to a body (docs/geometry.md): `shape` is "box" (`size`:
    /// full side lengths), "cylinder" or "capsule" (`radius`, `length`, along the geometry's z),
    /// "sphere" (`radius`) or "mesh" (`file` as the model states it, `scale`); the keys of other
    /// kinds are None. Placed in the body frame (origin at the body's CM) by `origin` and `rotation`.
    PyGeometryDescription as "GeometryDescription", fn of(py: Python<'_>, m: &core::Model, g: &core::Geometry) [
        let (size, radius, length, file, scale) = match &g.shape {
            core::Shape::Box { size: s } => (Some(vector(py, s)), None, None, None, None),
            core::Shape::Sphere { radius: r } => (None, Some(*r), None, None, None),
            core::Shape::Cylinder { radius: r, length: l } | core::Shape::Capsule { radius: r, length: l } => (None, Some(*r), Some(*l), None, None),
            core::Shape::Mesh { file: f, scale: s } => (None, None, None, Some(f.clone()), Some(vector(py, s))),
        };
        let q = g.rotation;
    ] {
        /// The geometry's name.
        name: String = g.name.clone(),
        /// Name of the body it is fixed to.
        body: String = m.body_name(g.body).to_string(),
        /// Index of that body (0 = base).
        body_index: usize = g.body,
        /// "visual" or "collision".
        role: &'static str = g.role.as_str(),
        /// "box", "cylinder", "sphere", "capsule" or "mesh".
        shape: &'static str = g.shape.kind(),
        /// (3,) m, read-only: a box's full side lengths; None for other shapes.
        size: Option<Py<PyArray1<f64>>> = size,
        /// m: the radius of a sphere, cylinder or capsule; None for other shapes.
        radius: Option<f64> = radius,
        /// m: the length of a cylinder or of a capsule's cylinder part; None for other shapes.
        length: Option<f64> = length,
        /// A mesh's file, as the model states it; None for other shapes.
        file: Option<String> = file,
        /// (3,) read-only: a mesh's scale along its x, y, z; None for other shapes.
        scale: Option<Py<PyArray1<f64>>> = scale,
        /// (3,) m, read-only: the geometry frame's origin in the body frame, from its CM.
        origin: Py<PyArray1<f64>> = vector3(py, &g.origin),
        /// (4,) unit quaternion `[x, y, z, w]`, read-only: the geometry frame in the body frame.
        rotation: Py<PyArray1<f64>> = vector(py, &[q.i, q.j, q.k, q.w]),
        /// (4,) read-only: red, green, blue, alpha in [0, 1].
        rgba: Py<PyArray1<f64>> = vector(py, &g.rgba),
    }
}

#[pymethods]
impl PyGeometryDescription {
    fn __repr__(&self) -> String {
        format!("<spacearm.GeometryDescription '{}': {} {} on '{}'>", self.name, self.role, self.shape, self.body)
    }
}

/// A whole model: base, links in tree order (a parent before its children; link `i` is body
/// `i + 1`), named points, end effector and initial joint coordinates.
#[pyclass(module = "spacearm._core", name = "ModelDescription", frozen, get_all)]
pub struct PyModelDescription {
    /// The model's name.
    name: String,
    /// The base (body 0).
    base: Py<PyBaseDescription>,
    /// The links in tree order (link `k` is body `k + 1`), a tuple of `LinkDescription`.
    links: Py<PyTuple>,
    /// The named points in the order they were added, a tuple of `PointDescription`.
    points: Py<PyTuple>,
    /// The visual and collision shapes in the order they were added, a tuple of
    /// `GeometryDescription` (docs/geometry.md).
    geometries: Py<PyTuple>,
    /// Name of the end-effector point, or None.
    end_effector: Option<String>,
    /// (N,) read-only: initial joint coordinates, rad (revolute) or m (prismatic), in `q` order.
    initial_q: Py<PyArray1<f64>>,
}

#[pymethods]
impl PyModelDescription {
    /// The link called `name` (raises `spacearm.NotFoundError` if there is none).
    fn link<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        find(py, &self.links, name, "link", |l: &PyLinkDescription| &l.name)
    }

    /// The point called `name` (raises `spacearm.NotFoundError` if there is none).
    fn point<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        find(py, &self.points, name, "point", |p: &PyPointDescription| &p.name)
    }

    /// The plain-data form (dicts, lists, tuples of Python numbers and strings), exactly as
    /// `Robot.describe()` returns it: a new object at each call.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let base = self.base.get();
        let b = PyDict::new(py);
        b.set_item("name", &base.name)?;
        b.set_item("mass", base.mass)?;
        b.set_item("inertia", to_list(py, &base.inertia)?)?;
        let links = PyList::empty(py);
        for link in self.links.bind(py).iter() {
            let link = link.cast::<PyLinkDescription>()?.get();
            let d = PyDict::new(py);
            d.set_item("name", &link.name)?;
            d.set_item("parent", &link.parent)?;
            d.set_item("parent_index", link.parent_index)?;
            d.set_item("joint", &link.joint)?;
            d.set_item("type", link.kind)?;
            d.set_item("origin", to_list(py, &link.origin)?)?;
            d.set_item("rotation", to_list(py, &link.rotation)?)?;
            d.set_item("axis", to_list(py, &link.axis)?)?;
            d.set_item("com", to_list(py, &link.com)?)?;
            d.set_item("mass", link.mass)?;
            d.set_item("inertia", to_list(py, &link.inertia)?)?;
            d.set_item("limits", link.limits.get().to_list().to_vec())?;
            d.set_item("dof", link.dof)?;
            d.set_item("actuated", link.actuated)?;
            d.set_item("stiffness", link.stiffness)?;
            d.set_item("damping", link.damping)?;
            d.set_item("rest", link.rest)?;
            links.append(d)?;
        }
        let points = PyList::empty(py);
        for p in self.points.bind(py).iter() {
            let p = p.cast::<PyPointDescription>()?.get();
            points.append((&p.name, &p.body, to_list(py, &p.offset)?))?;
        }
        let out = PyDict::new(py);
        out.set_item("name", &self.name)?;
        out.set_item("base", b)?;
        out.set_item("links", links)?;
        out.set_item("points", points)?;
        out.set_item("end_effector", &self.end_effector)?;
        out.set_item("initial_q", to_list(py, &self.initial_q)?)?;
        Ok(out)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "<spacearm.ModelDescription '{}': base, {} links, {} points, initial_q ({},)>",
            self.name,
            self.links.bind(py).len(),
            self.points.bind(py).len(),
            self.initial_q.bind(py).len()
        )
    }
}

/// The item of `items` (a tuple of `T`) called `name`, else a `NotFoundError` listing the names.
fn find<'py, T: pyo3::PyClass<Frozen = pyo3::pyclass::boolean_struct::True> + Sync>(
    py: Python<'py>,
    items: &Py<PyTuple>,
    name: &str,
    what: &str,
    name_of: fn(&T) -> &String,
) -> PyResult<Bound<'py, PyAny>> {
    let items = items.bind(py);
    let mut names = Vec::with_capacity(items.len());
    for item in items.iter() {
        let n = name_of(item.cast::<T>()?.get());
        if n == name {
            return Ok(item);
        }
        names.push(n.clone());
    }
    let listed = if names.is_empty() { "none".to_string() } else { names.join(", ") };
    Err(new_error(py, ErrorClass::NotFound, format!("no {what} named '{name}' ({what}s: {listed})")))
}

impl PyModelDescription {
    /// The description of `m`, field by field as the core holds it.
    pub fn of(py: Python<'_>, m: &core::Model) -> PyResult<PyModelDescription> {
        let links = (0..m.links().len()).map(|k| PyLinkDescription::of(py, m, k)).collect::<PyResult<Vec<_>>>()?;
        Ok(PyModelDescription {
            name: m.name().to_string(),
            base: Py::new(py, PyBaseDescription::of(py, m))?,
            links: PyTuple::new(py, links)?.unbind(),
            points: PyTuple::new(py, m.points().iter().map(|p| PyPointDescription::of(py, m, p)))?.unbind(),
            geometries: PyTuple::new(py, m.geometries().iter().map(|g| PyGeometryDescription::of(py, m, g)))?.unbind(),
            end_effector: m.end_effector().map(|i| m.points()[i].name.clone()),
            initial_q: vector(py, m.initial_q()),
        })
    }
}
