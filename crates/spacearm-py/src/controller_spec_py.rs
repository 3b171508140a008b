//! The run's description crossing from Python: one class, `ControllerSpec`, holding the core's
//! [`spacearm_core::control::spec::ControllerSpec`] (deserialized from the plain data that
//! `spacearm._util.spec` makes of a `spacearm.control` object, with `pythonize`) and the Python
//! callables of its `external` controllers; and the evaluators of references and shapers
//! (`JointReference`, `InputShaper`, `FreeBodyReference`), each built from its spec. No field is
//! copied or checked here: the core's serde types name the fields, `validate` checks them, and
//! `build` makes a fresh controller for every run (controllers keep workspaces, so each rollout
//! and each `Simulator.reset` gets its own).

use std::sync::{Arc, Mutex};

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use serde::de::DeserializeOwned;
use spacearm_core::control::spec::{ControllerSpec, JointReferenceSpec, PointReferenceSpec, ShaperSpec, ThrusterLimitsSpec};
use spacearm_core::control::shaping::InputShaper;
use spacearm_core::control::{Command, Controller};
use spacearm_core::sim::free_body::FreeBody;
use spacearm_core::sim::reference::JointReference;
use spacearm_core::{Model, SpacearmError};

use crate::convert::*;
use crate::sim_options_py::type_name;

type CoreResult<T> = spacearm_core::Result<T>;

/// A core spec type from the plain data (dicts, lists, numbers, strings) of `data`: an
/// `ArgumentError` naming `what` and serde's words (the field, what it expected) if it is not one.
pub fn from_data<T: DeserializeOwned>(data: &Bound<'_, PyAny>, what: &str) -> PyResult<T> {
    let mut de = pythonize::Depythonizer::from_object(data);
    serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = e.path().to_string();
        let at = if path == "." { String::new() } else { format!(" '{path}'") };
        to_py_err(data.py(), bad(format!("{what}{at}: {}", e.inner())))
    })
}

/// The plain data of a core spec (the inverse of [`from_data`]).
pub fn to_data<'py, T: serde::Serialize>(py: Python<'py>, value: &T) -> PyResult<Bound<'py, PyAny>> {
    pythonize::pythonize(py, value).map_err(|e| to_py_err(py, bad(format!("spec to data: {e}"))))
}

// ---- the controller spec ---------------------------------------------------------------------

/// A native control law as the core's data (`spacearm_core::control::spec::ControllerSpec`),
/// checked when made; `externals`: the Python callables of its `kind = "external"` controllers,
/// by index (`fn(t, x, u) -> tau` or `(tau, base_wrench)`).
#[pyclass(module = "spacearm._core", name = "ControllerSpec", frozen)]
pub struct PyControllerSpec {
    pub spec: ControllerSpec,
    externals: Vec<Py<PyAny>>,
}

#[pymethods]
impl PyControllerSpec {
    #[new]
    #[pyo3(signature = (data, externals = Vec::new()))]
    fn new(py: Python<'_>, data: &Bound<'_, PyAny>, externals: Vec<Bound<'_, PyAny>>) -> PyResult<Self> {
        let spec: ControllerSpec = from_data(data, "controller")?;
        spec.validate().or_raise(py)?;
        for s in spec.walk() {
            if let ControllerSpec::External { index } = s {
                match externals.get(*index) {
                    Some(f) if f.is_callable() => {}
                    Some(f) => return Err(to_py_err(py, bad(format!("the callback controller needs a callable fn(t, x, u), got {}", type_name(f))))),
                    None => return Err(to_py_err(py, bad(format!("controller kind 'external' index {index}: {} callables given", externals.len())))),
                }
            }
        }
        Ok(PyControllerSpec { spec, externals: externals.into_iter().map(|e| e.unbind()).collect() })
    }

    /// The controller's kind (`"joint_pd"`, ...): the core's table `CONTROLLER_KINDS`.
    #[getter]
    fn kind(&self) -> &'static str {
        self.spec.kind()
    }

    /// The spec as plain data (dicts, lists, numbers): what the core reads.
    fn to_data<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_data(py, &self.spec)
    }

    /// The spec as the TOML text of a `[controller]` table (the C stepper's and the FMUs' options).
    fn to_toml(&self, py: Python<'_>) -> PyResult<String> {
        self.spec.to_toml().or_raise(py)
    }

    fn __repr__(&self) -> String {
        let kinds: Vec<&str> = self.spec.walk().iter().map(|s| s.kind()).collect();
        format!("<spacearm._core.ControllerSpec {}>", kinds.join(" > "))
    }
}

/// A fresh core controller for a run on `plant` from a `ControllerSpec`; callback controllers
/// share `slot`.
pub fn build_controller(obj: &Bound<'_, PyAny>, plant: &Model, slot: &ErrorSlot) -> PyResult<Box<dyn Controller>> {
    let py = obj.py();
    let s = obj
        .cast::<PyControllerSpec>()
        .map_err(|_| to_py_err(py, bad(format!("a controller must be a spacearm.control controller (a _core.ControllerSpec), got {}", type_name(obj)))))?
        .get();
    let mut external = |i: usize| -> CoreResult<Box<dyn Controller>> {
        Ok(Box::new(PyCallback { func: s.externals[i].clone_ref(py), error: slot.clone() }) as Box<dyn Controller>)
    };
    s.spec.build(plant, &mut external).or_raise(py)
}

/// Check the data of a spec of `family` (`"controller"`, `"joint_reference"`,
/// `"point_reference"`, `"shaper"`, `"thrusters"`, `"stop"`, `"mpc_problem"`, `"mpc_options"`) without running anything: what the
/// `spacearm.control` classes call when they are made, so that a wrong value is refused there,
/// by the core's checks.
#[pyfunction]
pub fn check_spec(py: Python<'_>, family: &str, data: &Bound<'_, PyAny>) -> PyResult<()> {
    match family {
        "controller" => from_data::<ControllerSpec>(data, "controller")?.validate(),
        "joint_reference" => from_data::<JointReferenceSpec>(data, "joint reference")?.build().map(drop),
        "point_reference" => from_data::<PointReferenceSpec>(data, "point reference")?.build().map(drop),
        "shaper" => from_data::<ShaperSpec>(data, "input shaper")?.build().map(drop),
        "thrusters" => from_data::<ThrusterLimitsSpec>(data, "thrusters")?.build().map(drop),
        "stop" => spacearm_core::sim::events::validate(&[from_data(data, "stop")?]),
        "mpc_problem" => from_data::<spacearm_core::optimal::ProblemSpec>(data, "mpc problem")?.validate(),
        "mpc_options" => from_data::<spacearm_core::optimal::SolverOptions>(data, "mpc solver options")?.validate(),
        other => return Err(to_py_err(py, bad(format!("unknown spec family {other:?}")))),
    }
    .or_raise(py)
}

/// Thruster limits from their spec data (`spacearm_core::control::spec::ThrusterLimitsSpec`).
pub fn thruster_limits(data: &Bound<'_, PyAny>) -> PyResult<spacearm_core::sim::actuators::ThrusterLimits> {
    let spec: ThrusterLimitsSpec = from_data(data, "thrusters")?;
    spec.build().or_raise(data.py())
}

// ---- evaluators of references and shapers ----------------------------------------------------

/// A joint-space reference of the arm joints (`spacearm_core::sim::reference::JointReference`),
/// built from its spec data (`JointReference.from_spec`).
#[pyclass(module = "spacearm._core", name = "JointReference", frozen)]
pub struct PyJointReference {
    inner: JointReference,
}

pymethods_with_getters! {
#[pymethods]
impl PyJointReference {
    getters(self) {
        /// Start of the motion, s (None for a constant; the first knot time of a sampled reference).
        t_start: Option<f64> = self.inner.time_span().map(|s| s.0);
        /// End of the motion, s (None for a constant; the last knot time of a sampled reference; a
        /// shaped reference ends the shaper's length after its base).
        t_end: Option<f64> = self.inner.time_span().map(|s| s.1);
    }

    /// From the data of a `JointReferenceSpec` (a list: a constant set point).
    #[staticmethod]
    fn from_spec(py: Python<'_>, data: &Bound<'_, PyAny>) -> PyResult<Self> {
        let spec: JointReferenceSpec = from_data(data, "joint reference")?;
        Ok(PyJointReference { inner: spec.build().or_raise(py)? })
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
        array1(py, self.inner.end_values().0)
    }

    /// The joint coordinates at and after `t_end`, shape (n,) (the set point of a constant; the
    /// last knot of a sampled reference).
    #[getter]
    fn q_goal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.inner.end_values().1)
    }

    /// `(q, qd, qdd)` at each time of `t`, each of shape (T, n): the values the controllers
    /// follow.
    fn evaluate<'py>(&self, py: Python<'py>, t: &Bound<'_, PyAny>) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let times = owned_vec(t, "joint reference evaluation times")?;
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
}

/// An input shaper (ZV or ZVD) designed for one mode (`spacearm_core::control::shaping`),
/// built from its spec data (`InputShaper.from_spec`).
#[pyclass(module = "spacearm._core", name = "InputShaper", frozen)]
pub struct PyInputShaper {
    inner: InputShaper,
}

pymethods_with_getters! {
#[pymethods]
impl PyInputShaper {
    getters(self) {
        /// `"zv"` or `"zvd"`.
        kind: &'static str = self.inner.kind.name();
        /// The design natural frequency, rad/s.
        frequency: f64 = self.inner.frequency;
        /// The design damping ratio.
        damping: f64 = self.inner.damping;
    }

    /// From the data of a `ShaperSpec`: `{kind: "zv" | "zvd", frequency (rad/s), damping}`.
    #[staticmethod]
    fn from_spec(py: Python<'_>, data: &Bound<'_, PyAny>) -> PyResult<Self> {
        let spec: ShaperSpec = from_data(data, "input shaper")?;
        Ok(PyInputShaper { inner: spec.build().or_raise(py)? })
    }

    /// Impulse amplitudes (sum 1), shape (n,).
    #[getter]
    fn amplitudes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, &self.inner.amplitudes)
    }

    /// Impulse times, s, shape (n,).
    #[getter]
    fn times<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, &self.inner.times)
    }

    /// The residual vibration of the mode `(frequency, damping)` relative to an unshaped move.
    #[pyo3(signature = (frequency, damping=0.0))]
    fn residual_vibration(&self, frequency: f64, damping: f64) -> f64 {
        self.inner.residual_vibration(frequency, damping)
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.InputShaper {} at {} rad/s, damping {}>", self.inner.kind.name(), self.inner.frequency, self.inner.damping)
    }
}
}

/// A point on a rigid body moving freely (`spacearm_core::sim::free_body::FreeBody`): the grasp
/// point of a tumbling capture target and the body's motion, built from the data of a
/// `PointReferenceSpec` of kind `"free_body"` (`FreeBodyReference.from_spec`).
#[pyclass(module = "spacearm._core", name = "FreeBodyReference", frozen)]
pub struct PyFreeBodyReference {
    inner: FreeBody,
}

#[pymethods]
impl PyFreeBodyReference {
    /// From the data of a free-body point reference.
    #[staticmethod]
    fn from_spec(py: Python<'_>, data: &Bound<'_, PyAny>) -> PyResult<Self> {
        let spec: PointReferenceSpec = from_data(data, "free-body reference")?;
        Ok(PyFreeBodyReference { inner: spec.free_body().or_raise(py)? })
    }

    /// The body's 13-states at the times `t` (s ≥ 0), shape (T, 13).
    fn states<'py>(&self, py: Python<'py>, t: &Bound<'_, PyAny>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let times = owned_vec(t, "free-body times")?;
        let mut body = self.inner.clone();
        let mut out = Vec::with_capacity(times.len() * 13);
        for &ti in &times {
            out.extend_from_slice(&body.state(ti).or_raise(py)?);
        }
        rows(py, out, 13)
    }

    /// The point's positions and velocities (in 𝒥) at the times `t`, each of shape (T, 3).
    fn points<'py>(&self, py: Python<'py>, t: &Bound<'_, PyAny>) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let times = owned_vec(t, "free-body times")?;
        let mut body = self.inner.clone();
        let (mut p, mut v) = (Vec::with_capacity(times.len() * 3), Vec::with_capacity(times.len() * 3));
        for &ti in &times {
            let (pi, vi, _) = body.point(ti).or_raise(py)?;
            p.extend_from_slice(pi.as_slice());
            v.extend_from_slice(vi.as_slice());
        }
        Ok((rows(py, p, 3)?, rows(py, v, 3)?))
    }

    /// The external wrench on the body (mass `mass`, kg) at the times `t`, (T, 6): in orbit the
    /// tidal force (N) and its moment about the run's origin (N·m, with the gravity-gradient
    /// torque about the CM); zeros for a torque-free body.
    fn external_wrenches<'py>(&self, py: Python<'py>, t: &Bound<'_, PyAny>, mass: f64) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let times = owned_vec(t, "free-body times")?;
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
        rows(py, out, 6)
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

// ---- the Python callback controller ----------------------------------------------------------

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
