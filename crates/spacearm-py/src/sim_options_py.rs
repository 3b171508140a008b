//! The options of the simulation entry points (`simulate`, `rollout`, `Simulator`) as typed,
//! frozen, keyword-only classes: `RunOptions` and the `ThrusterLimits` it may carry. Every option
//! left out (or given as None) keeps the core's default (`SimOptions::default()`, exported as
//! `SIM_DEFAULTS`); each value is checked when the object is built, and an unknown keyword is an
//! `ArgumentError` naming it and the keywords the class takes.

use nalgebra::Vector3;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyType};
use pyo3::PyTypeInfo;
use spacearm_core::sim::actuators::ThrusterLimits;
use spacearm_core::sim::options::RunSpec;
use spacearm_core::sim::simulate::SimOptions;

use crate::convert::*;

/// Refuse the keywords collected in `unknown` (the `**unknown` of a class's constructor) with an
/// `ArgumentError` naming the first and the keywords `T` takes (read from its signature, so the
/// list is never restated).
pub fn refuse_unknown<T: PyTypeInfo>(py: Python<'_>, unknown: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
    let Some(key) = unknown.and_then(|d| d.keys().iter().next()) else {
        return Ok(());
    };
    let cls: Bound<'_, PyType> = T::type_object(py);
    let name = cls.qualname().map(|n| n.to_string()).unwrap_or_else(|_| T::NAME.to_string());
    let expected: Vec<String> = py
        .import("inspect")
        .and_then(|inspect| inspect.call_method1("signature", (&cls,)))
        .and_then(|sig| sig.getattr("parameters"))
        .and_then(|params| params.call_method0("values"))
        .and_then(|values| {
            values
                .try_iter()?
                .filter_map(|p| p.ok())
                // Keyword-only parameters (kind 3), not the `**unknown` catch-all (kind 4).
                .filter(|p| p.getattr("kind").and_then(|k| k.extract::<i64>()).ok() == Some(3))
                .map(|p| p.getattr("name")?.extract::<String>())
                .collect::<PyResult<Vec<String>>>()
        })
        .unwrap_or_default();
    Err(to_py_err(py, bad(format!("{name}: unknown key '{key}'; expected one of {expected:?}"))))
}

/// Thruster limits per axis of 𝒥 (`spacearm_core::sim::actuators::ThrusterLimits`): a force
/// through the base CM and a torque are each clamped per component. Checked when built (every
/// limit > 0; infinity for none).
#[pyclass(module = "spacearm._core", name = "ThrusterLimits", frozen)]
pub struct PyThrusterLimits {
    pub inner: ThrusterLimits,
}

#[pymethods]
impl PyThrusterLimits {
    /// From the data of a `ThrusterLimitsSpec` (`{max_force, max_torque}`: one number for the three
    /// axes, or three; absent or inf: no limit).
    #[staticmethod]
    fn from_spec(data: &Bound<'_, PyAny>) -> PyResult<Self> {
        Ok(PyThrusterLimits { inner: crate::controller_spec_py::thruster_limits(data)? })
    }

    /// Largest base force per axis of 𝒥, shape (3,), N (inf: no limit).
    #[getter]
    fn max_force<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.inner.max_force.as_slice())
    }

    /// Largest base torque per axis of 𝒥, shape (3,), N·m (inf: no limit).
    #[getter]
    fn max_torque<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.inner.max_torque.as_slice())
    }

    fn __repr__(&self) -> String {
        let v = |v: &Vector3<f64>| format!("[{}, {}, {}]", v.x, v.y, v.z);
        format!("<spacearm._core.ThrusterLimits max_force={} N, max_torque={} N·m>", v(&self.inner.max_force), v(&self.inner.max_torque))
    }
}

/// The options of a run, checked: everything of `SimOptions` but the duration (an argument of
/// each entry point), the progress callable and the dtype of the records.
#[pyclass(module = "spacearm._core", name = "RunOptions", frozen)]
pub struct PyRunOptions {
    /// The core's options; `duration` is a placeholder, replaced by [`PyRunOptions::sim_options`].
    sim: SimOptions,
    progress: Option<Py<PyAny>>,
    float32: bool,
}

impl PyRunOptions {
    /// The core's options of a run of `duration` seconds.
    pub fn sim_options(&self, duration: f64) -> SimOptions {
        SimOptions { duration, ..self.sim.clone() }
    }

    /// The progress callable, if any.
    pub fn progress_fn(&self, py: Python<'_>) -> Option<Py<PyAny>> {
        self.progress.as_ref().map(|f| f.clone_ref(py))
    }

    /// Whether the records are returned as float32.
    pub fn records_float32(&self) -> bool {
        self.float32
    }
}

/// `v` as plain data for the core's reader: a numpy scalar as its Python number (`item()`),
/// a `ThrusterLimits` as its limits, a `spacearm.Orbit` as its data; anything else as it is.
fn plain<'py>(py: Python<'py>, key: &str, v: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    if let Ok(limits) = v.cast::<PyThrusterLimits>() {
        let t = &limits.get().inner;
        use spacearm_core::control::spec::{PerAxis, ThrusterLimitsSpec};
        let spec = ThrusterLimitsSpec { max_force: PerAxis(t.max_force.into()), max_torque: PerAxis(t.max_torque.into()) };
        return crate::controller_spec_py::to_data(py, &spec);
    }
    if let Ok(orbit) = v.cast::<crate::orbit_py::PyOrbit>() {
        return crate::controller_spec_py::to_data(py, &orbit.get().inner);
    }
    match key {
        "thrusters" => return Err(to_py_err(py, bad(format!("thrusters must be a ThrusterLimits, got {}", type_name(v))))),
        "orbit" => return Err(to_py_err(py, bad(format!("orbit must be a spacearm.Orbit, got {}", type_name(v))))),
        _ => {}
    }
    if v.is_instance(&py.import("numpy")?.getattr("generic")?)? {
        return v.call_method0("item");
    }
    Ok(v.clone())
}

pymethods_with_getters! {
#[pymethods]
impl PyRunOptions {
    getters(self) {
        /// The maneuvering mode (paper Table 1), one of `MODES`.
        mode: &'static str = self.sim.mode.name();
        /// The integrator, one of `INTEGRATORS`.
        integrator: &'static str = self.sim.integrator.name();
        /// RK4: the step; DOPRI5: the output interval; s.
        dt: f64 = self.sim.dt;
        /// DOPRI5 relative tolerance.
        rtol: f64 = self.sim.rtol;
        /// DOPRI5 absolute tolerance.
        atol: f64 = self.sim.atol;
        /// RK4: every how many steps a sample is recorded.
        record_every: usize = self.sim.record_every;
        /// The reaction-wheel dofs, or None: those the model's structure shows.
        wheels: Option<Vec<usize>> = self.sim.wheels.clone();
        /// The thruster limits, or None: unlimited.
        thrusters: Option<PyThrusterLimits> = self.sim.thrusters.map(|inner| PyThrusterLimits { inner });
        /// Whether the joints' effort and velocity limits apply.
        joint_limits: bool = self.sim.joint_limits;
        /// DOPRI5: the most steps attempted before giving up.
        max_steps: usize = self.sim.max_steps;
        /// The orbit of the run's origin (the system CM's reference point), or None: empty space.
        orbit: Option<crate::orbit_py::PyOrbit> = self.sim.orbit.map(|o| crate::orbit_py::PyOrbit { inner: o.orbit });
        /// Whether the tidal (gravity-gradient) wrenches act on every body (orbital runs).
        gravity_gradient: bool = self.sim.orbit.is_some_and(|o| o.gravity_gradient);
    }

    /// Every keyword is optional; None keeps the core's default.
    #[new]
    #[pyo3(signature = (*, mode=None, integrator=None, dt=None, rtol=None, atol=None, record_every=None, wheels=None, thrusters=None,
                        joint_limits=None, max_steps=None, progress=None, record_dtype=None, orbit=None, gravity_gradient=None, stop=None, contact=None, **unknown))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        mode: Option<&Bound<'_, PyAny>>,
        integrator: Option<&Bound<'_, PyAny>>,
        dt: Option<&Bound<'_, PyAny>>,
        rtol: Option<&Bound<'_, PyAny>>,
        atol: Option<&Bound<'_, PyAny>>,
        record_every: Option<&Bound<'_, PyAny>>,
        wheels: Option<&Bound<'_, PyAny>>,
        thrusters: Option<&Bound<'_, PyAny>>,
        joint_limits: Option<&Bound<'_, PyAny>>,
        max_steps: Option<&Bound<'_, PyAny>>,
        progress: Option<&Bound<'_, PyAny>>,
        record_dtype: Option<&Bound<'_, PyAny>>,
        orbit: Option<&Bound<'_, PyAny>>,
        gravity_gradient: Option<&Bound<'_, PyAny>>,
        stop: Option<&Bound<'_, PyAny>>,
        contact: Option<&Bound<'_, PyAny>>,
        unknown: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        refuse_unknown::<Self>(py, unknown)?;
        // The given options as the core's run description (sim/options.rs RunSpec: its names,
        // defaults and one validation); the progress callable and the records' dtype are the
        // binding's own.
        let data = PyDict::new(py);
        let given = [
            ("mode", mode), ("integrator", integrator), ("dt", dt), ("rtol", rtol), ("atol", atol), ("record_every", record_every),
            ("wheels", wheels), ("thrusters", thrusters), ("joint_limits", joint_limits), ("max_steps", max_steps), ("orbit", orbit),
            ("gravity_gradient", gravity_gradient), ("stop", stop), ("contact", contact),
        ];
        for (key, value) in given {
            if let Some(v) = value {
                data.set_item(key, plain(py, key, v)?)?;
            }
        }
        let spec: RunSpec = crate::controller_spec_py::from_data(data.as_any(), "simulation options")?;
        // The duration is each entry point's argument: any positive placeholder checks the rest.
        let opts = spec.options(1.0).or_raise(py)?;
        let float32 = match record_dtype {
            None => false,
            Some(v) => match v.extract::<String>().ok().as_deref() {
                Some("float64") => false,
                Some("float32") => true,
                _ => return Err(to_py_err(py, bad(format!("record_dtype must be 'float64' or 'float32', got {v}")))),
            },
        };
        if let Some(f) = progress {
            if !f.is_callable() {
                return Err(to_py_err(py, bad(format!("progress must be a callable(fraction) or None, got {}", type_name(f)))));
            }
        }
        Ok(PyRunOptions { sim: opts, progress: progress.map(|f| f.clone().unbind()), float32 })
    }

    /// The callable given the fraction done (0..1) during the run, or None.
    #[getter]
    fn progress(&self, py: Python<'_>) -> Option<Py<PyAny>> {
        self.progress_fn(py)
    }

    /// The stop conditions of the run (empty: it runs its duration).
    #[getter]
    fn stop<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::controller_spec_py::to_data(py, &self.sim.stop)
    }

    /// The contact of the run as data (sim/contact.rs ContactSpec), or None.
    #[getter]
    fn contact<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        match &self.sim.contact {
            Some(c) => crate::controller_spec_py::to_data(py, c),
            None => Ok(py.None().into_bound(py)),
        }
    }

    /// The dtype of the records but the time: "float64" or "float32".
    #[getter]
    fn record_dtype(&self) -> &'static str {
        if self.float32 {
            "float32"
        } else {
            "float64"
        }
    }

    fn __repr__(&self) -> String {
        let o = &self.sim;
        format!(
            "<spacearm._core.RunOptions mode={:?} integrator={:?} dt={:?} s rtol={:?} atol={:?} record_every={} wheels={:?} thrusters={} joint_limits={} max_steps={} progress={} record_dtype={:?}>",
            o.mode.name(),
            o.integrator.name(),
            o.dt,
            o.rtol,
            o.atol,
            o.record_every,
            o.wheels,
            if o.thrusters.is_some() { "limited" } else { "None" },
            o.joint_limits,
            o.max_steps,
            if self.progress.is_some() { "callable" } else { "None" },
            self.record_dtype(),
        )
    }
}
}

/// The name of `v`'s type, for messages.
pub fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into())
}
