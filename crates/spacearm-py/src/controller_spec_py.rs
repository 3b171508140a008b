//! The controllers of the simulation entry points as typed, frozen, keyword-only classes: the
//! references (`JointReference`, `CartesianReference`) and one spec per core controller
//! (`JointPdSpec`, `ComputedTorqueSpec`, `RmrcSpec`, `CoordinatedFlyingSpec`,
//! `BaseThrustersSpec`, `AttitudeSpec`, `CombinedSpec`, `CallbackSpec`, `ZeroTorqueSpec`).
//! `spacearm.control` builds them; each value is checked when the spec is built, and a spec
//! builds a fresh core controller for every run ([`build_controller`]: controllers keep
//! workspaces, so each rollout and each `Simulator.reset` gets its own).

use std::sync::{Arc, Mutex};

use nalgebra::Vector3;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use spacearm_core::control::{
    AttitudeControl, BaseThrusterControl, Combined, LvlhReference, Command, ComputedTorque, ControlContext, Controller, CoordinatedFlying, CoordinatedGains, JointPd,
    JointTorqueLimit, MomentumDamping, PassiveTreatment, ResolvedMotionRate, ZeroTorque,
};
use spacearm_core::analysis::redundancy::Strategy;
use spacearm_core::control::shaping::{InputShaper, ShaperKind};
use spacearm_core::analysis::Task;
use spacearm_core::sim::free_body::FreeBody;
use spacearm_core::sim::reference::{CartesianLine, JointReference, PointReference};
use numpy::{PyArray2, PyArrayMethods};
use spacearm_core::{Model, SpacearmError};

use crate::convert::*;
use crate::model_py::PyModel;
use crate::sim_options_py::{refuse_unknown, type_name};

type CoreResult<T> = spacearm_core::Result<T>;

fn bad(msg: String) -> SpacearmError {
    SpacearmError::InvalidArgument(msg)
}

fn vector(v: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    Ok(vec_arg(v, what)?.as_slice().to_vec())
}

fn quat(v: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; 4]> {
    let q = vec_arg_n(v, what, 4)?;
    let q = q.as_slice();
    Ok([q[0], q[1], q[2], q[3]])
}

fn array<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v)
}

// ---- references ------------------------------------------------------------------------------

/// A joint-space reference of the arm joints (`spacearm_core::sim::reference::JointReference`):
/// built by `JointReference.quintic(...)` (rest-to-rest quintic) or `JointReference.constant(q=...)`.
#[pyclass(module = "spacearm._core", name = "JointReference", frozen)]
pub struct PyJointReference {
    inner: JointReference,
}

#[pymethods]
impl PyJointReference {
    /// From `q_start` to `q_goal` (rad or m per arm joint) over `[t_start, t_end]` (s).
    #[staticmethod]
    #[pyo3(signature = (*, q_start, q_goal, t_start, t_end))]
    fn quintic(py: Python<'_>, q_start: &Bound<'_, PyAny>, q_goal: &Bound<'_, PyAny>, t_start: f64, t_end: f64) -> PyResult<Self> {
        let w = "joint reference";
        let inner = JointReference::quintic(vector(q_start, &format!("{w} 'q_start'"))?, vector(q_goal, &format!("{w} 'q_goal'"))?, t_start, t_end).or_raise(py)?;
        Ok(PyJointReference { inner })
    }

    /// The piecewise quintic Hermite interpolant of knots: times `t` (K ≥ 2, strictly
    /// increasing, s) and positions `q`, velocities `qd`, accelerations `qdd` at the knots, each
    /// of shape (K, n) (real numbers, any layout).
    #[staticmethod]
    #[pyo3(signature = (*, t, q, qd, qdd))]
    fn sampled(py: Python<'_>, t: &Bound<'_, PyAny>, q: &Bound<'_, PyAny>, qd: &Bound<'_, PyAny>, qdd: &Bound<'_, PyAny>) -> PyResult<Self> {
        let t = vector(t, "sampled reference 't'")?;
        let mut parts = Vec::with_capacity(3);
        let mut n = None;
        for (what, v) in [("q", q), ("qd", qd), ("qdd", qdd)] {
            let a = array_values(v, &format!("sampled reference '{what}'"))?;
            let shape = a.shape;
            if shape.len() != 2 || shape[0] != t.len() || n.is_some_and(|n| n != shape[1]) {
                return Err(shape_error(py, format!("sampled reference '{what}' has shape {shape:?}; expected ({}, n) with the same n for q, qd and qdd", t.len())));
            }
            n = Some(shape[1]);
            parts.push(a.values);
        }
        let qdd = parts.pop().expect("three arrays");
        let qd = parts.pop().expect("three arrays");
        let q = parts.pop().expect("three arrays");
        let inner = JointReference::sampled(t, q, qd, qdd, n.unwrap_or(0)).or_raise(py)?;
        Ok(PyJointReference { inner })
    }

    /// Hold `q` (rad or m per arm joint).
    #[staticmethod]
    #[pyo3(signature = (*, q))]
    fn constant(py: Python<'_>, q: &Bound<'_, PyAny>) -> PyResult<Self> {
        Ok(PyJointReference { inner: JointReference::constant(vector(q, "joint reference 'q'")?).or_raise(py)? })
    }

    /// `"quintic"`, `"constant"`, `"sampled"` or `"shaped"`.
    #[getter]
    fn kind(&self) -> &'static str {
        match self.inner {
            JointReference::Quintic { .. } => "quintic",
            JointReference::Constant(_) => "constant",
            JointReference::Sampled { .. } => "sampled",
            JointReference::Shaped { .. } => "shaped",
        }
    }

    /// The joint coordinates at and before `t_start`, shape (n,) (the set point of a constant;
    /// the first knot of a sampled reference).
    #[getter]
    fn q_start<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.inner.end_values().0)
    }

    /// The joint coordinates at and after `t_end`, shape (n,) (the set point of a constant; the
    /// last knot of a sampled reference).
    #[getter]
    fn q_goal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.inner.end_values().1)
    }

    /// Start of the motion, s (None for a constant; the first knot time of a sampled reference).
    #[getter]
    fn t_start(&self) -> Option<f64> {
        self.inner.time_span().map(|s| s.0)
    }

    /// End of the motion, s (None for a constant; the last knot time of a sampled reference; a
    /// shaped reference ends the shaper's length after its base).
    #[getter]
    fn t_end(&self) -> Option<f64> {
        self.inner.time_span().map(|s| s.1)
    }

    /// `(q, qd, qdd)` at each time of `t`, each of shape (T, n): the values the controllers
    /// follow.
    fn evaluate<'py>(&self, py: Python<'py>, t: &Bound<'_, PyAny>) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let times = vector(t, "joint reference evaluation times")?;
        let n = self.inner.len();
        let (mut q, mut qd, mut qdd) = (vec![0.0; times.len() * n], vec![0.0; times.len() * n], vec![0.0; times.len() * n]);
        for (i, &ti) in times.iter().enumerate() {
            let r = i * n..(i + 1) * n;
            self.inner.eval(ti, &mut q[r.clone()], &mut qd[r.clone()], &mut qdd[r]);
        }
        let shape = |v: Vec<f64>| PyArray1::from_vec(py, v).reshape([times.len(), n]);
        Ok((shape(q)?, shape(qd)?, shape(qdd)?))
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.JointReference {} of {} joints>", self.kind(), self.inner.len())
    }
}

/// An input shaper (ZV or ZVD) designed for one mode (`spacearm_core::control::shaping`).
#[pyclass(module = "spacearm._core", name = "InputShaper", frozen)]
pub struct PyInputShaper {
    inner: InputShaper,
}

#[pymethods]
impl PyInputShaper {
    /// `kind` `"zv"` or `"zvd"` for the mode of natural frequency `frequency` (rad/s) and damping
    /// ratio `damping` (0 ≤ ζ < 1).
    #[new]
    #[pyo3(signature = (kind, *, frequency, damping=0.0, **unknown))]
    fn new(py: Python<'_>, kind: &str, frequency: f64, damping: f64, unknown: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        let k = ShaperKind::from_name(kind)
            .ok_or_else(|| bad(format!("an input shaper's kind must be one of {:?}, got {kind:?}", ShaperKind::NAMES)))
            .or_raise(py)?;
        Ok(PyInputShaper { inner: InputShaper::new(k, frequency, damping).or_raise(py)? })
    }

    /// `"zv"` or `"zvd"`.
    #[getter]
    fn kind(&self) -> &'static str {
        self.inner.kind.name()
    }

    /// The design natural frequency, rad/s.
    #[getter]
    fn frequency(&self) -> f64 {
        self.inner.frequency
    }

    /// The design damping ratio.
    #[getter]
    fn damping(&self) -> f64 {
        self.inner.damping
    }

    /// Impulse amplitudes (sum 1), shape (n,).
    #[getter]
    fn amplitudes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, &self.inner.amplitudes)
    }

    /// Impulse times, s, shape (n,).
    #[getter]
    fn times<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, &self.inner.times)
    }

    /// The residual vibration of the mode `(frequency, damping)` relative to an unshaped move.
    #[pyo3(signature = (frequency, damping=0.0))]
    fn residual_vibration(&self, frequency: f64, damping: f64) -> f64 {
        self.inner.residual_vibration(frequency, damping)
    }

    /// The shaped reference `sum_i A_i r(t - t_i)`.
    fn shape(&self, reference: &PyJointReference) -> PyJointReference {
        PyJointReference { inner: self.inner.shape(reference.inner.clone()) }
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.InputShaper {} at {} rad/s, damping {}>", self.inner.kind.name(), self.inner.frequency, self.inner.damping)
    }
}

/// A straight line of a point in 𝒥 with quintic timing (`spacearm_core::sim::reference::CartesianLine`).
#[pyclass(module = "spacearm._core", name = "CartesianReference", frozen)]
pub struct PyCartesianReference {
    inner: CartesianLine,
}

#[pymethods]
impl PyCartesianReference {
    /// From `p_start` to `p_goal` (m, in 𝒥) over `[t_start, t_end]` (s).
    #[new]
    #[pyo3(signature = (*, p_start, p_goal, t_start, t_end, **unknown))]
    fn new(py: Python<'_>, p_start: &Bound<'_, PyAny>, p_goal: &Bound<'_, PyAny>, t_start: f64, t_end: f64, unknown: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        let w = "Cartesian reference";
        let line = CartesianLine::new(vec3(p_start, &format!("{w} 'p_start'"))?, vec3(p_goal, &format!("{w} 'p_goal'"))?, t_start, t_end).or_raise(py)?;
        Ok(PyCartesianReference { inner: line })
    }

    /// Start point, shape (3,), m, in 𝒥.
    #[getter]
    fn p_start<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.inner.p_start.as_slice())
    }

    /// End point, shape (3,), m, in 𝒥.
    #[getter]
    fn p_goal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.inner.p_goal.as_slice())
    }

    /// Start of the motion, s.
    #[getter]
    fn t_start(&self) -> f64 {
        self.inner.t_start
    }

    /// End of the motion, s.
    #[getter]
    fn t_end(&self) -> f64 {
        self.inner.t_end
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.CartesianReference t_start={} s, t_end={} s>", self.inner.t_start, self.inner.t_end)
    }
}

/// A point on a torque-free rigid body (`spacearm_core::sim::free_body::FreeBody`): the grasp
/// point of a tumbling capture target, as a reference for `RmrcSpec`, and the body's motion.
#[pyclass(module = "spacearm._core", name = "FreeBodyReference", frozen)]
pub struct PyFreeBodyReference {
    inner: FreeBody,
}

#[pymethods]
impl PyFreeBodyReference {
    /// A body of `inertia` (3×3 about its CM in its axes, kg·m², symmetric positive definite;
    /// 9 numbers row-major) in `state` (13: `[r, quat xyzw, v, w]` in 𝒥, at simulation time 0),
    /// the point at `offset` (m, body axes, from the CM); attitude grid `step` (s). `orbit`: the
    /// run's `Orbit` (the state relative to its point at time 0, ECI axes): the body then moves
    /// under gravity's tidal part and turns under its gravity-gradient torque (docs/orbit.md).
    #[new]
    #[pyo3(signature = (*, inertia, state, offset, step, orbit=None, **unknown))]
    fn new(
        py: Python<'_>,
        inertia: &Bound<'_, PyAny>,
        state: &Bound<'_, PyAny>,
        offset: &Bound<'_, PyAny>,
        step: f64,
        orbit: Option<PyRef<'_, crate::orbit_py::PyOrbit>>,
        unknown: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        let i = vec_arg_n(inertia, "free-body 'inertia' (9 numbers, row-major 3×3)", 9)?;
        let i = nalgebra::Matrix3::from_row_slice(i.as_slice());
        let s = vec_arg_n(state, "free-body 'state' ([r, quat xyzw, v, w])", 13)?;
        let mut inner = FreeBody::new(i, s.as_slice(), vec3(offset, "free-body 'offset'")?, step).or_raise(py)?;
        if let Some(o) = orbit {
            inner = inner.in_orbit(&o.inner).or_raise(py)?;
        }
        Ok(PyFreeBodyReference { inner })
    }

    /// The body's 13-states at the times `t` (s ≥ 0), shape (T, 13).
    fn states<'py>(&self, py: Python<'py>, t: &Bound<'_, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let times = vector(t, "free-body times")?;
        let mut body = self.inner.clone();
        let mut out = Vec::with_capacity(times.len() * 13);
        for &ti in &times {
            out.extend_from_slice(&body.state(ti).or_raise(py)?);
        }
        Ok(PyArray1::from_vec(py, out).reshape([times.len(), 13])?)
    }

    /// The point's positions and velocities (in 𝒥) at the times `t`, each of shape (T, 3).
    fn points<'py>(&self, py: Python<'py>, t: &Bound<'_, PyAny>) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let times = vector(t, "free-body times")?;
        let mut body = self.inner.clone();
        let (mut p, mut v) = (Vec::with_capacity(times.len() * 3), Vec::with_capacity(times.len() * 3));
        for &ti in &times {
            let (pi, vi, _) = body.point(ti).or_raise(py)?;
            p.extend_from_slice(pi.as_slice());
            v.extend_from_slice(vi.as_slice());
        }
        Ok((PyArray1::from_vec(py, p).reshape([times.len(), 3])?, PyArray1::from_vec(py, v).reshape([times.len(), 3])?))
    }

    /// The external wrench on the body (mass `mass`, kg) at the times `t`, (T, 6): in orbit the
    /// tidal force (N) and its moment about the run's origin (N·m, with the gravity-gradient
    /// torque about the CM); zeros for a torque-free body.
    fn external_wrenches<'py>(&self, py: Python<'py>, t: &Bound<'_, PyAny>, mass: f64) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let times = vector(t, "free-body times")?;
        if !(mass.is_finite() && mass > 0.0) {
            return Err(to_py_err(py, bad(format!("free-body mass must be finite and > 0 kg, got {mass}"))));
        }
        let mut body = self.inner.clone();
        let mut out = Vec::with_capacity(times.len() * 6);
        for &ti in &times {
            let (f, n) = body.external_wrench(ti, mass).or_raise(py)?;
            out.extend_from_slice(f.as_slice());
            out.extend_from_slice(n.as_slice());
        }
        Ok(PyArray1::from_vec(py, out).reshape([times.len(), 6])?)
    }

    /// Whether the body moves in orbit (built with `orbit=`).
    #[getter]
    fn in_orbit(&self) -> bool {
        self.inner.is_in_orbit()
    }

    fn __repr__(&self) -> String {
        "<spacearm._core.FreeBodyReference>".to_string()
    }
}

/// A point reference of `RmrcSpec`: a `CartesianReference` or a `FreeBodyReference`.
fn point_reference(obj: &Bound<'_, PyAny>) -> PyResult<PointReference> {
    if let Ok(r) = obj.cast::<PyCartesianReference>() {
        return Ok(PointReference::Line(r.get().inner));
    }
    if let Ok(r) = obj.cast::<PyFreeBodyReference>() {
        return Ok(PointReference::FreeBody(Box::new(r.get().inner.clone())));
    }
    if let Ok(r) = obj.cast::<PyJointReference>() {
        let inner = &r.get().inner;
        if matches!(inner, JointReference::Sampled { n: 3, .. }) {
            return Ok(PointReference::Sampled(inner.clone()));
        }
        return Err(to_py_err(obj.py(), bad("a JointReference as a point path must be a sampled one of 3 coordinates (the point in 𝒥)".into())));
    }
    Err(to_py_err(
        obj.py(),
        bad(format!("a point reference must be a CartesianReference, a FreeBodyReference or a sampled JointReference of 3 coordinates, got {}", type_name(obj))),
    ))
}

/// A point of the robot: a body index and an offset (m, in that body's frame).
fn point(py: Python<'_>, what: &str, body: &Bound<'_, PyAny>, offset: &Bound<'_, PyAny>) -> PyResult<(usize, Vector3<f64>)> {
    let b: usize = body.extract().map_err(|_| to_py_err(py, bad(format!("{what}: 'body' must be a body index"))))?;
    Ok((b, vec3(offset, &format!("{what} 'offset'"))?))
}

// ---- controller specs ------------------------------------------------------------------------

/// No control: zero joint torques and no base wrench.
#[pyclass(module = "spacearm._core", name = "ZeroTorqueSpec", frozen)]
pub struct PyZeroTorqueSpec;

#[pymethods]
impl PyZeroTorqueSpec {
    #[new]
    fn new() -> Self {
        PyZeroTorqueSpec
    }

    fn __repr__(&self) -> &'static str {
        "<spacearm._core.ZeroTorqueSpec>"
    }
}

/// Joint PD on the arm joints (`spacearm_core::control::JointPd`).
#[pyclass(module = "spacearm._core", name = "JointPdSpec", frozen)]
pub struct PyJointPdSpec {
    /// Proportional gains, one or one per arm joint, N·m/rad.
    #[pyo3(get)]
    kp: Vec<f64>,
    /// Derivative gains, one or one per arm joint, N·m·s/rad.
    #[pyo3(get)]
    kd: Vec<f64>,
    reference: Py<PyJointReference>,
}

#[pymethods]
impl PyJointPdSpec {
    #[new]
    #[pyo3(signature = (*, kp, kd, reference, **unknown))]
    fn new(py: Python<'_>, kp: &Bound<'_, PyAny>, kd: &Bound<'_, PyAny>, reference: Py<PyJointReference>, unknown: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        Ok(PyJointPdSpec { kp: vector(kp, "joint_pd 'kp'")?, kd: vector(kd, "joint_pd 'kd'")?, reference })
    }

    /// The joint reference.
    #[getter]
    fn reference(&self, py: Python<'_>) -> Py<PyJointReference> {
        self.reference.clone_ref(py)
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.JointPdSpec kp: {} gains, kd: {} gains>", self.kp.len(), self.kd.len())
    }
}

/// Computed torque on the reduced equations of motion (`spacearm_core::control::ComputedTorque`,
/// paper eqs. 112–115).
#[pyclass(module = "spacearm._core", name = "ComputedTorqueSpec", frozen)]
pub struct PyComputedTorqueSpec {
    /// Proportional gains, one or one per arm joint, 1/s².
    #[pyo3(get)]
    kp: Vec<f64>,
    /// Derivative gains, one or one per arm joint, 1/s.
    #[pyo3(get)]
    kd: Vec<f64>,
    reference: Py<PyJointReference>,
    /// The controller's model (None: the plant's).
    model: Option<Model>,
    passive: PassiveTreatment,
}

#[pymethods]
impl PyComputedTorqueSpec {
    #[new]
    #[pyo3(signature = (*, kp, kd, reference, model=None, passive="drift", **unknown))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        kp: &Bound<'_, PyAny>,
        kd: &Bound<'_, PyAny>,
        reference: Py<PyJointReference>,
        model: Option<&Bound<'_, PyAny>>,
        passive: &str,
        unknown: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        let model = controller_model(py, model)?;
        let passive = PassiveTreatment::from_name(passive).ok_or_else(|| {
            bad(format!("computed_torque 'passive' must be one of {:?}, got {passive:?}", PassiveTreatment::NAMES))
        }).or_raise(py)?;
        Ok(PyComputedTorqueSpec { kp: vector(kp, "computed_torque 'kp'")?, kd: vector(kd, "computed_torque 'kd'")?, reference, model, passive })
    }

    /// How the passive joints are treated: ``"drift"`` (measured) or ``"frozen"`` (a rigid model).
    #[getter]
    fn passive(&self) -> &'static str {
        self.passive.name()
    }

    /// The joint reference.
    #[getter]
    fn reference(&self, py: Python<'_>) -> Py<PyJointReference> {
        self.reference.clone_ref(py)
    }

    /// Whether the controller has a model of its own (else it uses the plant's).
    #[getter]
    fn has_model(&self) -> bool {
        self.model.is_some()
    }

    fn __repr__(&self) -> String {
        let model = if self.model.is_some() { "its own" } else { "the plant's" };
        format!("<spacearm._core.ComputedTorqueSpec kp: {} gains, kd: {} gains, model: {model}>", self.kp.len(), self.kd.len())
    }
}

/// Resolved-motion-rate control of a point through `J*` (`spacearm_core::control::ResolvedMotionRate`,
/// paper eq. 110) with damped least squares.
#[pyclass(module = "spacearm._core", name = "RmrcSpec", frozen)]
pub struct PyRmrcSpec {
    reference: Py<PyAny>,
    /// The cap on the joint-rate command (rad/s or m/s; inf: none): the command is scaled as a
    /// whole.
    #[pyo3(get)]
    max_joint_rate: f64,
    /// Position feedback gain, 1/s.
    #[pyo3(get)]
    gain: f64,
    /// The largest damping λ_max, m (`max_damping` everywhere in Python: one name for λ_max).
    #[pyo3(get)]
    max_damping: f64,
    /// The singular value below which damping starts, m.
    #[pyo3(get)]
    threshold: f64,
    /// Joint-rate tracking gain, 1/s.
    #[pyo3(get)]
    velocity_gain: f64,
    /// The body of the controlled point.
    #[pyo3(get)]
    body: usize,
    offset: Vector3<f64>,
    task: Task,
    strategy: Strategy,
}

#[pymethods]
impl PyRmrcSpec {
    #[new]
    #[pyo3(signature = (*, reference, gain, max_damping, threshold, velocity_gain, body, offset, max_joint_rate=f64::INFINITY, task=vec![0, 1, 2], strategy="naive", **unknown))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        reference: &Bound<'_, PyAny>,
        gain: f64,
        max_damping: f64,
        threshold: f64,
        velocity_gain: f64,
        body: &Bound<'_, PyAny>,
        offset: &Bound<'_, PyAny>,
        max_joint_rate: f64,
        task: Vec<usize>,
        strategy: &str,
        unknown: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        point_reference(reference)?;
        let task = crate::analysis_py::task(py, task)?;
        let strategy = crate::analysis_py::strategy(py, strategy)?;
        if !(max_joint_rate > 0.0) {
            return Err(to_py_err(py, bad(format!("rmrc 'max_joint_rate' must be > 0 (inf: no cap), got {max_joint_rate}"))));
        }
        let (body, offset) = point(py, "rmrc", body, offset)?;
        Ok(PyRmrcSpec { reference: reference.clone().unbind(), max_joint_rate, gain, max_damping, threshold, velocity_gain, body, offset, task, strategy })
    }

    /// The point reference (a CartesianReference or a FreeBodyReference).
    #[getter]
    fn reference(&self, py: Python<'_>) -> Py<PyAny> {
        self.reference.clone_ref(py)
    }

    /// The point's offset in its body's frame, shape (3,), m.
    #[getter]
    fn offset<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.offset.as_slice())
    }

    /// The rows of the point twist the controller drives (0-2 linear, 3-5 angular velocity).
    #[getter]
    fn task(&self) -> Vec<usize> {
        self.task.rows().to_vec()
    }

    /// The treatment of the base: "naive", "reactionless" or "minimum_disturbance".
    #[getter]
    fn strategy(&self) -> &'static str {
        self.strategy.name()
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.RmrcSpec body={} gain={} 1/s task={:?} strategy={}>", self.body, self.gain, self.task.rows(), self.strategy.name())
    }
}

/// Coordinated base-and-arm control in the flying mode (`spacearm_core::control::CoordinatedFlying`).
#[pyclass(module = "spacearm._core", name = "CoordinatedFlyingSpec", frozen)]
pub struct PyCoordinatedFlyingSpec {
    reference: Py<PyCartesianReference>,
    /// The body of the controlled point.
    #[pyo3(get)]
    body: usize,
    offset: Vector3<f64>,
    /// The base pose held: position (m, in 𝒥) and quaternion [x, y, z, w]; None: the initial pose.
    base_ref: Option<(Vector3<f64>, [f64; 4])>,
    gains: CoordinatedGains,
    /// The largest damping λ_max, m (`max_damping` everywhere in Python: one name for λ_max).
    #[pyo3(get)]
    max_damping: f64,
    /// The singular value below which damping starts, m.
    #[pyo3(get)]
    threshold: f64,
}

#[pymethods]
impl PyCoordinatedFlyingSpec {
    #[new]
    #[pyo3(signature = (*, reference, body, offset, kp_ee, kd_ee, kp_base, kd_base, max_damping, threshold, base_position=None, base_quat=None, **unknown))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        reference: Py<PyCartesianReference>,
        body: &Bound<'_, PyAny>,
        offset: &Bound<'_, PyAny>,
        kp_ee: f64,
        kd_ee: f64,
        kp_base: f64,
        kd_base: f64,
        max_damping: f64,
        threshold: f64,
        base_position: Option<&Bound<'_, PyAny>>,
        base_quat: Option<&Bound<'_, PyAny>>,
        unknown: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        let (body, offset) = point(py, "coordinated_flying", body, offset)?;
        let base_ref = match (base_position, base_quat) {
            (None, None) => None,
            (Some(p), Some(q)) => Some((vec3(p, "coordinated flying base_position")?, quat(q, "coordinated flying base_quat")?)),
            _ => return Err(to_py_err(py, bad("coordinated_flying: give both base_position and base_quat, or neither".into()))),
        };
        let gains = CoordinatedGains { kp_ee, kd_ee, kp_base, kd_base };
        Ok(PyCoordinatedFlyingSpec { reference, body, offset, base_ref, gains, max_damping, threshold })
    }

    /// The end effector's Cartesian reference.
    #[getter]
    fn reference(&self, py: Python<'_>) -> Py<PyCartesianReference> {
        self.reference.clone_ref(py)
    }

    /// The point's offset in its body's frame, shape (3,), m.
    #[getter]
    fn offset<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, self.offset.as_slice())
    }

    /// The base position held, shape (3,), m, in 𝒥 (None: the initial one).
    #[getter]
    fn base_position<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.base_ref.as_ref().map(|(p, _)| array(py, p.as_slice()))
    }

    /// The base attitude held, quaternion [x, y, z, w], shape (4,) (None: the initial one).
    #[getter]
    fn base_quat<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.base_ref.as_ref().map(|(_, q)| array(py, q))
    }

    /// End-effector stiffness, 1/s².
    #[getter]
    fn kp_ee(&self) -> f64 {
        self.gains.kp_ee
    }

    /// End-effector damping, 1/s.
    #[getter]
    fn kd_ee(&self) -> f64 {
        self.gains.kd_ee
    }

    /// Base stiffness, 1/s².
    #[getter]
    fn kp_base(&self) -> f64 {
        self.gains.kp_base
    }

    /// Base damping, 1/s.
    #[getter]
    fn kd_base(&self) -> f64 {
        self.gains.kd_base
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.CoordinatedFlyingSpec body={} base_ref={}>", self.body, if self.base_ref.is_some() { "given" } else { "initial pose" })
    }
}

/// Base regulation by thrusters (`spacearm_core::control::BaseThrusterControl`).
#[pyclass(module = "spacearm._core", name = "BaseThrustersSpec", frozen)]
pub struct PyBaseThrustersSpec {
    com_ref: Option<Vector3<f64>>,
    quat_ref: Option<[f64; 4]>,
    /// System-CM stiffness, 1/s².
    #[pyo3(get)]
    kp_position: f64,
    /// System-CM damping, 1/s.
    #[pyo3(get)]
    kd_position: f64,
    /// Attitude stiffness, N·m/rad.
    #[pyo3(get)]
    kp_attitude: f64,
    /// Attitude damping, N·m·s/rad.
    #[pyo3(get)]
    kd_attitude: f64,
    /// In orbit: hold the attitude relative to this orbit's LVLH (quat_ref then relative to LVLH).
    orbit: Option<spacearm_core::sim::orbit::Orbit>,
}

#[pymethods]
impl PyBaseThrustersSpec {
    #[new]
    #[pyo3(signature = (*, kp_position, kd_position, kp_attitude, kd_attitude, com_ref=None, quat_ref=None, orbit=None, **unknown))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        kp_position: f64,
        kd_position: f64,
        kp_attitude: f64,
        kd_attitude: f64,
        com_ref: Option<&Bound<'_, PyAny>>,
        quat_ref: Option<&Bound<'_, PyAny>>,
        orbit: Option<PyRef<'_, crate::orbit_py::PyOrbit>>,
        unknown: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        let com_ref = com_ref.map(|v| vec3(v, "thruster control com_ref")).transpose()?;
        let quat_ref = quat_ref.map(|v| quat(v, "thruster control quat_ref")).transpose()?;
        Ok(PyBaseThrustersSpec { com_ref, quat_ref, kp_position, kd_position, kp_attitude, kd_attitude, orbit: orbit.map(|o| o.inner) })
    }

    /// The system CM position held, shape (3,), m, in 𝒥 (None: the initial one).
    #[getter]
    fn com_ref<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.com_ref.as_ref().map(|p| array(py, p.as_slice()))
    }

    /// The base attitude held, quaternion [x, y, z, w], shape (4,) (None: the initial one).
    #[getter]
    fn quat_ref<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.quat_ref.as_ref().map(|q| array(py, q))
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.BaseThrustersSpec kp_position={} kd_position={} kp_attitude={} kd_attitude={}>", self.kp_position, self.kd_position, self.kp_attitude, self.kd_attitude)
    }
}

/// Base attitude control with reaction wheels (`spacearm_core::control::AttitudeControl`).
#[pyclass(module = "spacearm._core", name = "AttitudeSpec", frozen)]
pub struct PyAttitudeSpec {
    quat_ref: [f64; 4],
    /// In orbit: hold `quat_ref` relative to this orbit's LVLH.
    orbit: Option<spacearm_core::sim::orbit::Orbit>,
    /// Attitude stiffness, N·m/rad.
    #[pyo3(get)]
    kp: f64,
    /// Attitude damping, N·m·s/rad.
    #[pyo3(get)]
    kd: f64,
}

#[pymethods]
impl PyAttitudeSpec {
    #[new]
    #[pyo3(signature = (*, quat_ref, kp, kd, orbit=None, **unknown))]
    fn new(py: Python<'_>, quat_ref: &Bound<'_, PyAny>, kp: f64, kd: f64, orbit: Option<PyRef<'_, crate::orbit_py::PyOrbit>>, unknown: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        Ok(PyAttitudeSpec { quat_ref: quat(quat_ref, "attitude quat_ref")?, kp, kd, orbit: orbit.map(|o| o.inner) })
    }

    /// The base attitude held, quaternion [x, y, z, w] of 𝒥, shape (4,).
    #[getter]
    fn quat_ref<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, &self.quat_ref)
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.AttitudeSpec kp={} kd={}>", self.kp, self.kd)
    }
}

/// An arm controller and a base controller together (`spacearm_core::control::Combined`): the
/// base runs first.
#[pyclass(module = "spacearm._core", name = "CombinedSpec", frozen)]
pub struct PyCombinedSpec {
    /// The arm controller's spec.
    #[pyo3(get)]
    arm: Py<PyAny>,
    /// The base controller's spec.
    #[pyo3(get)]
    base: Py<PyAny>,
}

#[pymethods]
impl PyCombinedSpec {
    #[new]
    #[pyo3(signature = (*, arm, base, **unknown))]
    fn new(py: Python<'_>, arm: &Bound<'_, PyAny>, base: &Bound<'_, PyAny>, unknown: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        spec_of(arm)?;
        spec_of(base)?;
        Ok(PyCombinedSpec { arm: arm.clone().unbind(), base: base.clone().unbind() })
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let name = |v: &Py<PyAny>| type_name(v.bind(py));
        format!("<spacearm._core.CombinedSpec arm={} base={}>", name(&self.arm), name(&self.base))
    }
}

/// Thruster damping of the system momentum (`spacearm_core::control::MomentumDamping`): the
/// flying-mode detumbling law, `F0 = −P/τ`, `N0 = −L_G/τ − (r0 − r_g) × F0`, each norm-limited.
#[pyclass(module = "spacearm._core", name = "MomentumDampingSpec", frozen)]
pub struct PyMomentumDampingSpec {
    /// Time constant τ, s.
    #[pyo3(get)]
    time_constant: f64,
    /// Norm limit of the force, N (inf: none).
    #[pyo3(get)]
    max_force: f64,
    /// Norm limit of the torque, N·m (inf: none).
    #[pyo3(get)]
    max_torque: f64,
    model: Option<Model>,
}

#[pymethods]
impl PyMomentumDampingSpec {
    #[new]
    #[pyo3(signature = (*, time_constant, max_force=f64::INFINITY, max_torque=f64::INFINITY, model=None, **unknown))]
    fn new(py: Python<'_>, time_constant: f64, max_force: f64, max_torque: f64, model: Option<&Bound<'_, PyAny>>, unknown: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        if !(time_constant.is_finite() && time_constant > 0.0) {
            return Err(to_py_err(py, bad(format!("momentum damping 'time_constant' must be finite and > 0, got {time_constant}"))));
        }
        for (what, v) in [("max_force", max_force), ("max_torque", max_torque)] {
            if !(v > 0.0) {
                return Err(to_py_err(py, bad(format!("momentum damping '{what}' must be > 0 (inf: no limit), got {v}"))));
            }
        }
        Ok(PyMomentumDampingSpec { time_constant, max_force, max_torque, model: controller_model(py, model)? })
    }

    /// Whether the law has a model of its own (else it uses the plant's).
    #[getter]
    fn has_model(&self) -> bool {
        self.model.is_some()
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.MomentumDampingSpec time_constant={} s>", self.time_constant)
    }
}

/// Another controller's joint torques clamped to `±limit` on every joint
/// (`spacearm_core::control::JointTorqueLimit`).
#[pyclass(module = "spacearm._core", name = "JointTorqueLimitSpec", frozen)]
pub struct PyJointTorqueLimitSpec {
    /// The clamped controller's spec.
    #[pyo3(get)]
    controller: Py<PyAny>,
    /// The limit, N·m (N for prismatic joints).
    #[pyo3(get)]
    limit: f64,
}

#[pymethods]
impl PyJointTorqueLimitSpec {
    #[new]
    #[pyo3(signature = (*, controller, limit, **unknown))]
    fn new(py: Python<'_>, controller: &Bound<'_, PyAny>, limit: f64, unknown: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        spec_of(controller)?;
        if !(limit > 0.0) {
            return Err(to_py_err(py, bad(format!("a joint torque 'limit' must be > 0 (inf: no limit), got {limit}"))));
        }
        Ok(PyJointTorqueLimitSpec { controller: controller.clone().unbind(), limit })
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!("<spacearm._core.JointTorqueLimitSpec {} within ±{}>", type_name(self.controller.bind(py)), self.limit)
    }
}

/// A controller's own model from its Python argument (a Robot's core model), or `None`.
fn controller_model(py: Python<'_>, model: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Model>> {
    match model {
        Some(m) => {
            let m = m.cast::<PyModel>().map_err(|_| to_py_err(py, bad("a controller's model must be a spacearm Robot's core model".into())))?;
            Ok(Some(m.borrow().model.clone()))
        }
        None => Ok(None),
    }
}

/// A Python callable as the controller: `fn(t, x, u) -> tau` or `(tau, base_wrench)`, called at
/// every integrator stage.
#[pyclass(module = "spacearm._core", name = "CallbackSpec", frozen)]
pub struct PyCallbackSpec {
    /// The callable.
    #[pyo3(get)]
    r#fn: Py<PyAny>,
}

#[pymethods]
impl PyCallbackSpec {
    #[new]
    #[pyo3(signature = (*, r#fn, **unknown))]
    fn new(py: Python<'_>, r#fn: &Bound<'_, PyAny>, unknown: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        if !r#fn.is_callable() {
            return Err(to_py_err(py, bad("the callback controller needs a callable fn(t, x, u)".into())));
        }
        Ok(PyCallbackSpec { r#fn: r#fn.clone().unbind() })
    }

    fn __repr__(&self) -> &'static str {
        "<spacearm._core.CallbackSpec>"
    }
}

// ---- from a spec to a controller -------------------------------------------------------------

/// The spec classes, as the message of a wrong object names them.
const SPEC_CLASSES: [&str; 11] = [
    "ZeroTorqueSpec",
    "JointPdSpec",
    "ComputedTorqueSpec",
    "RmrcSpec",
    "AttitudeSpec",
    "BaseThrustersSpec",
    "CoordinatedFlyingSpec",
    "MomentumDampingSpec",
    "CombinedSpec",
    "JointTorqueLimitSpec",
    "CallbackSpec",
];

/// A controller spec, borrowed from its Python object.
enum Spec<'a> {
    ZeroTorque,
    JointPd(&'a PyJointPdSpec),
    ComputedTorque(&'a PyComputedTorqueSpec),
    Rmrc(&'a PyRmrcSpec),
    Attitude(&'a PyAttitudeSpec),
    BaseThrusters(&'a PyBaseThrustersSpec),
    CoordinatedFlying(&'a PyCoordinatedFlyingSpec),
    MomentumDamping(&'a PyMomentumDampingSpec),
    Combined(&'a PyCombinedSpec),
    TorqueLimit(&'a PyJointTorqueLimitSpec),
    Callback(&'a PyCallbackSpec),
}

/// Which spec `obj` is; an `ArgumentError` naming the spec classes if none.
fn spec_of<'a>(obj: &'a Bound<'_, PyAny>) -> PyResult<Spec<'a>> {
    if obj.cast::<PyZeroTorqueSpec>().is_ok() {
        return Ok(Spec::ZeroTorque);
    }
    if let Ok(s) = obj.cast::<PyJointPdSpec>() {
        return Ok(Spec::JointPd(s.get()));
    }
    if let Ok(s) = obj.cast::<PyComputedTorqueSpec>() {
        return Ok(Spec::ComputedTorque(s.get()));
    }
    if let Ok(s) = obj.cast::<PyRmrcSpec>() {
        return Ok(Spec::Rmrc(s.get()));
    }
    if let Ok(s) = obj.cast::<PyAttitudeSpec>() {
        return Ok(Spec::Attitude(s.get()));
    }
    if let Ok(s) = obj.cast::<PyBaseThrustersSpec>() {
        return Ok(Spec::BaseThrusters(s.get()));
    }
    if let Ok(s) = obj.cast::<PyCoordinatedFlyingSpec>() {
        return Ok(Spec::CoordinatedFlying(s.get()));
    }
    if let Ok(s) = obj.cast::<PyMomentumDampingSpec>() {
        return Ok(Spec::MomentumDamping(s.get()));
    }
    if let Ok(s) = obj.cast::<PyCombinedSpec>() {
        return Ok(Spec::Combined(s.get()));
    }
    if let Ok(s) = obj.cast::<PyJointTorqueLimitSpec>() {
        return Ok(Spec::TorqueLimit(s.get()));
    }
    if let Ok(s) = obj.cast::<PyCallbackSpec>() {
        return Ok(Spec::Callback(s.get()));
    }
    Err(to_py_err(obj.py(), bad(format!("controller type must be one of {SPEC_CLASSES:?}, got {}", type_name(obj)))))
}

/// A fresh core controller from a controller spec; callback controllers share `slot`.
pub fn build_controller(obj: &Bound<'_, PyAny>, slot: &ErrorSlot) -> PyResult<Box<dyn Controller>> {
    let py = obj.py();
    let joint_ref = |r: &Py<PyJointReference>| r.get().inner.clone();
    let line = |r: &Py<PyCartesianReference>| r.get().inner;
    Ok(match spec_of(obj)? {
        Spec::ZeroTorque => Box::new(ZeroTorque),
        Spec::JointPd(s) => Box::new(JointPd::new(s.kp.clone(), s.kd.clone(), joint_ref(&s.reference))),
        Spec::ComputedTorque(s) => Box::new(ComputedTorque::new(s.kp.clone(), s.kd.clone(), joint_ref(&s.reference), s.model.clone()).with_passive(s.passive)),
        Spec::Rmrc(s) => Box::new(
            ResolvedMotionRate::new(point_reference(s.reference.bind(py))?, s.gain, s.max_damping, s.threshold, s.velocity_gain, s.body, s.offset)
                .with_max_joint_rate(s.max_joint_rate)
                .with_task(s.task.clone())
                .with_strategy(s.strategy),
        ),
        Spec::Attitude(s) => {
            let c = AttitudeControl::new(s.quat_ref, s.kp, s.kd);
            match &s.orbit {
                Some(o) => Box::new(c.with_lvlh(LvlhReference::new(o, Some(s.quat_ref)).map_err(|e| to_py_err(py, e))?)),
                None => Box::new(c),
            }
        }
        Spec::BaseThrusters(s) => {
            let c = BaseThrusterControl::new(s.com_ref, s.quat_ref, s.kp_position, s.kd_position, s.kp_attitude, s.kd_attitude);
            match &s.orbit {
                Some(o) => Box::new(c.with_lvlh(LvlhReference::new(o, s.quat_ref).map_err(|e| to_py_err(py, e))?)),
                None => Box::new(c),
            }
        }
        Spec::CoordinatedFlying(s) => {
            Box::new(CoordinatedFlying::new(line(&s.reference), s.body, s.offset, s.base_ref, s.gains, s.max_damping, s.threshold))
        }
        Spec::MomentumDamping(s) => Box::new(MomentumDamping::new(s.time_constant, s.max_force, s.max_torque, s.model.clone())),
        Spec::Combined(s) => Box::new(Combined::new(build_controller(s.arm.bind(py), slot)?, build_controller(s.base.bind(py), slot)?)),
        Spec::TorqueLimit(s) => Box::new(JointTorqueLimit::new(build_controller(s.controller.bind(py), slot)?, s.limit)),
        Spec::Callback(s) => Box::new(PyCallback { func: s.r#fn.clone_ref(py), error: slot.clone() }),
    })
}

/// Where a callback controller keeps the first Python exception it raised, for the entry point
/// to re-raise unchanged (a mutex: the run may be on another thread, without the GIL).
pub type ErrorSlot = Arc<Mutex<Option<PyErr>>>;

/// A new, empty [`ErrorSlot`].
pub fn error_slot() -> ErrorSlot {
    Arc::new(Mutex::new(None))
}

/// The Python exception a callback stored in `slot`, if any.
pub fn take_error(slot: &ErrorSlot) -> Option<PyErr> {
    slot.lock().map(|mut e| e.take()).unwrap_or(None)
}

/// A Python callable as a controller: `fn(t, x, u) -> tau` or `(tau, base_wrench)`.
struct PyCallback {
    func: Py<PyAny>,
    error: ErrorSlot,
}

impl PyCallback {
    fn call(&self, py: Python<'_>, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> PyResult<()> {
        let result = self.func.bind(py).call1((t, PyArray1::from_slice(py, x), PyArray1::from_slice(py, u)))?;
        let (tau_obj, wrench_obj) = match result.cast::<PyTuple>() {
            Ok(tup) if tup.len() == 2 => (tup.get_item(0)?, Some(tup.get_item(1)?)),
            _ => (result, None),
        };
        let n = out.tau.len();
        let tau = vec_arg_n(&tau_obj, "the callback controller's tau", n)?;
        out.tau.copy_from_slice(tau.as_slice());
        if let Some(w) = wrench_obj {
            out.base_wrench = vec6(&w, "the callback controller's base_wrench")?;
        }
        Ok(())
    }
}

impl Controller for PyCallback {
    fn name(&self) -> &str {
        "callback"
    }
    fn setup(&mut self, _ctx: &ControlContext<'_>) -> CoreResult<()> {
        Ok(())
    }
    fn command(&mut self, t: f64, x: &[f64], u: &[f64], out: &mut Command) -> CoreResult<()> {
        let res = Python::attach(|py| self.call(py, t, x, u, out));
        res.map_err(|e| {
            let msg = format!("the controller callback raised at t = {t} s: {e}");
            if let Ok(mut slot) = self.error.lock() {
                slot.get_or_insert(e);
            }
            SpacearmError::Simulation(msg)
        })
    }
}
