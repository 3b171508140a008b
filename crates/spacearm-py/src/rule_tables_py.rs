//! The core's rule tables as typed frozen classes: `SimDefaults` (`_core.SIM_DEFAULTS`),
//! `ModelBounds` (`_core.MODEL_BOUNDS`) and `DlsDefaults` (`_core.DLS_DEFAULTS`), one instance
//! each, built from the core's constants and defaults. Each field is a documented attribute (the
//! schema is in `_core.pyi`); each table is also a read-only mapping of its field names (`keys`,
//! `t[name]`, `dict(t)`, `**t`, equality with a dict), the form the Python package has always
//! read.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyIterator, PyList};
use pyo3::IntoPyObjectExt;
use spacearm_core::math::dls::DampingLaw;
use spacearm_core::model::{body, validate};
use spacearm_core::sim::simulate::SimOptions;
use spacearm_core::SpacearmError;

use crate::convert::{to_py_err, OrRaise};

/// A frozen class of documented, typed fields with the read-only mapping view of the module doc.
macro_rules! rule_table {
    ($(#[doc = $doc:expr])* $rust:ident, $py:literal { $( $(#[doc = $fdoc:expr])* $field:ident : $ty:ty ),+ $(,)? }) => {
        $(#[doc = $doc])*
        #[pyclass(module = "spacearm._core", name = $py, frozen)]
        pub struct $rust {
            $( $(#[doc = $fdoc])* #[pyo3(get)] pub $field: $ty, )+
        }

        impl $rust {
            const KEYS: &'static [&'static str] = &[$(stringify!($field)),+];

            fn as_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
                let d = PyDict::new(py);
                $( d.set_item(stringify!($field), self.$field.clone())?; )+
                Ok(d)
            }
        }

        #[pymethods]
        impl $rust {
            /// The field names, in order.
            fn keys(&self) -> Vec<&'static str> {
                Self::KEYS.to_vec()
            }

            fn __getitem__<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
                match key {
                    $( stringify!($field) => self.$field.clone().into_bound_py_any(py), )+
                    _ => Err(to_py_err(py, SpacearmError::NotFound(format!("{}: no field '{key}'; fields are {:?}", $py, Self::KEYS)))),
                }
            }

            fn __len__(&self) -> usize {
                Self::KEYS.len()
            }

            fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyIterator>> {
                PyList::new(py, Self::KEYS)?.try_iter()
            }

            fn __contains__(&self, key: &str) -> bool {
                Self::KEYS.contains(&key)
            }

            /// Equal to a dict (or a table) with the same fields and values.
            fn __eq__<'py>(&self, py: Python<'py>, other: &Bound<'py, PyAny>) -> PyResult<bool> {
                if let Ok(other) = other.cast::<$rust>() {
                    return self.as_dict(py)?.eq(other.get().as_dict(py)?);
                }
                if other.is_instance_of::<PyDict>() {
                    return self.as_dict(py)?.eq(other);
                }
                Ok(false)
            }

            fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
                let mut fields = Vec::new();
                $( fields.push(format!("{}={}", stringify!($field), self.$field.clone().into_bound_py_any(py)?.repr()?)); )+
                Ok(format!("{}({})", $py, fields.join(", ")))
            }
        }
    };
}

rule_table! {
    /// The simulation defaults (`SimOptions::default()`), read by `spacearm.simulate` and the
    /// other simulation entry points for their signatures.
    PySimDefaults, "SimDefaults" {
        /// Maneuvering mode name (one of `_core.MODES`).
        mode: &'static str,
        /// Integrator name (one of `_core.INTEGRATORS`).
        integrator: &'static str,
        /// RK4 step; DOPRI5 output interval, s.
        dt: f64,
        /// DOPRI5 relative tolerance.
        rtol: f64,
        /// DOPRI5 absolute tolerance.
        atol: f64,
        /// RK4: keep every k-th step.
        record_every: usize,
        /// Whether the joints' effort and velocity limits apply.
        joint_limits: bool,
        /// Largest number of attempted DOPRI5 steps.
        max_steps: usize,
    }
}

rule_table! {
    /// The physical bounds of every model (docs/model-format.md, rule 10 and 11), the same at
    /// every door that makes a model.
    PyModelBounds, "ModelBounds" {
        /// Smallest non-zero mass of a body, kg (`MIN_MASS` in `model/body.rs`).
        min_mass: f64,
        /// Largest mass of a body, kg (`MAX_MASS`).
        max_mass: f64,
        /// Largest magnitude of a component of a joint origin, a CM or a point offset, m
        /// (`MAX_LENGTH` in `model/validate.rs`).
        max_length: f64,
        /// Largest magnitude of an inertia entry, kg·m² (`MAX_INERTIA_ENTRY`).
        max_inertia_entry: f64,
    }
}

rule_table! {
    /// The default damped-least-squares law (`math/dls.rs`, `DampingLaw::default()`), taken by
    /// every controller and analysis that damps unless told otherwise.
    PyDlsDefaults, "DlsDefaults" {
        /// Size ε of the singular region, in the units of σ (m/rad for position rows).
        threshold: f64,
        /// Damping λ_max at the singularity itself, in the units of σ.
        max_damping: f64,
    }
}

/// Add the three tables to the extension module (their classes are registered in `lib.rs`).
pub fn add_tables(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let d = SimOptions::default();
    let sim = PySimDefaults {
        mode: d.mode.name(),
        integrator: d.integrator.name(),
        dt: d.dt,
        rtol: d.rtol,
        atol: d.atol,
        record_every: d.record_every,
        joint_limits: d.joint_limits,
        max_steps: d.max_steps,
    };
    m.add("SIM_DEFAULTS", sim)?;
    let bounds = PyModelBounds {
        min_mass: body::MIN_MASS,
        max_mass: body::MAX_MASS,
        max_length: validate::MAX_LENGTH,
        max_inertia_entry: body::MAX_INERTIA_ENTRY,
    };
    m.add("MODEL_BOUNDS", bounds)?;
    let law = DampingLaw::default();
    m.add("DLS_DEFAULTS", PyDlsDefaults { threshold: law.threshold, max_damping: law.max_damping })?;
    // The run's names (control/spec.rs): the controller kinds, the CLI's aliases, the tasks.
    use spacearm_core::control::spec;
    m.add("CONTROLLER_KINDS", spec::CONTROLLER_KINDS.to_vec())?;
    m.add("CONTROLLER_ALIASES", spec::CONTROLLER_ALIASES.iter().map(|(a, k)| (*a, *k)).collect::<std::collections::BTreeMap<_, _>>())?;
    m.add("TASKS", spec::TASK_NAMES.iter().map(|(k, r)| (*k, r.to_vec())).collect::<Vec<_>>())?;
    m.add_function(pyo3::wrap_pyfunction!(controller_kind, m)?)?;
    Ok(())
}

/// The controller kind a user's name means (a kind, its hyphenated spelling, or an alias of
/// `CONTROLLER_ALIASES`): the core's `control::spec::controller_kind`.
#[pyfunction]
fn controller_kind(py: Python<'_>, name: &str) -> PyResult<&'static str> {
    spacearm_core::control::spec::controller_kind(name).or_raise(py)
}
