//! The core's rule tables as frozen classes: `SimDefaults` (`_core.SIM_DEFAULTS`),
//! `ModelBounds` (`_core.MODEL_BOUNDS`) and `DlsDefaults` (`_core.DLS_DEFAULTS`), one instance
//! each, built from the core's constants and defaults (the simulation defaults from the core's
//! data, so that a run option is declared in the core only). Each field is an attribute (the
//! schema is in `_core.pyi`); each table is also a read-only mapping of its field names (`keys`,
//! `t[name]`, `dict(t)`, `**t`, equality with a dict), the form the Python package has always
//! read.

use pyo3::exceptions::PyAttributeError;
use pyo3::prelude::*;
use pyo3::types::{IntoPyDict, PyDict, PyIterator, PyList};
use spacearm_core::math::dls::DampingLaw;
use spacearm_core::model::{body, validate};
use spacearm_core::sim::options::RunSpec;
use spacearm_core::SpacearmError;

use crate::controller_spec_py::to_data;
use crate::convert::{to_py_err, OrRaise};

/// A frozen class over the ordered fields `fields` (a dict, names to values) with the read-only
/// mapping view of the module doc; each field is also an attribute (`t.dt`). The fields, their
/// types and docs are the core's (and the stub's, `_core.pyi`); the class only shows them.
macro_rules! rule_table {
    ($(#[doc = $doc:expr])* $rust:ident, $py:literal) => {
        $(#[doc = $doc])*
        #[pyclass(module = "spacearm._core", name = $py, frozen)]
        pub struct $rust {
            fields: Py<PyDict>,
        }

        #[pymethods]
        impl $rust {
            /// The field names, in order.
            fn keys(&self, py: Python<'_>) -> PyResult<Vec<String>> {
                self.fields.bind(py).keys().extract()
            }

            fn __getattr__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
                self.fields.bind(py).get_item(name)?.ok_or_else(|| PyAttributeError::new_err(format!("'{}' has no field '{name}'", $py)))
            }

            fn __getitem__<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
                self.fields.bind(py).get_item(key)?.ok_or_else(|| {
                    to_py_err(py, SpacearmError::NotFound(format!("{}: no field '{key}'; fields are {:?}", $py, self.keys(py).unwrap_or_default())))
                })
            }

            fn __len__(&self, py: Python<'_>) -> usize {
                self.fields.bind(py).len()
            }

            fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyIterator>> {
                self.fields.bind(py).keys().try_iter()
            }

            fn __contains__(&self, py: Python<'_>, key: &str) -> PyResult<bool> {
                self.fields.bind(py).contains(key)
            }

            /// Equal to a dict (or a table) with the same fields and values.
            fn __eq__<'py>(&self, py: Python<'py>, other: &Bound<'py, PyAny>) -> PyResult<bool> {
                if let Ok(other) = other.cast::<$rust>() {
                    return self.fields.bind(py).eq(other.get().fields.bind(py));
                }
                if other.is_instance_of::<PyDict>() {
                    return self.fields.bind(py).eq(other);
                }
                Ok(false)
            }

            fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
                let fields = self.fields.bind(py).iter().map(|(k, v)| Ok(format!("{k}={}", v.repr()?))).collect::<PyResult<Vec<_>>>()?;
                Ok(format!("{}({})", $py, fields.join(", ")))
            }
        }
    };
}

rule_table! {
    /// The simulation defaults, read by `spacearm.simulate` and the other simulation entry points
    /// for their signatures: the run options the core declares once (`run_options!` in
    /// sim/options.rs) whose default is a value, as `RunSpec::default()` writes them.
    PySimDefaults, "SimDefaults"
}

rule_table! {
    /// The physical bounds of every model (docs/model-format.md, rule 10 and 11), the same at
    /// every door that makes a model.
    PyModelBounds, "ModelBounds"
}

rule_table! {
    /// The default damped-least-squares law (`math/dls.rs`, `DampingLaw::default()`), taken by
    /// every controller and analysis that damps unless told otherwise.
    PyDlsDefaults, "DlsDefaults"
}

/// The run options of `RunSpec::default()` (the core's data, in its order) that default to a
/// value; those that default to nothing (`None` or an empty list: the wheels, stop conditions,
/// contact, thrusters, orbit and controller) have no default to show.
fn sim_defaults(py: Python<'_>) -> PyResult<PySimDefaults> {
    let all = to_data(py, &RunSpec::default())?.cast_into::<PyDict>()?;
    let fields = PyDict::new(py);
    for (key, value) in all.iter() {
        let empty = value.is_none() || value.cast::<PyList>().is_ok_and(|l| l.is_empty());
        if !empty {
            fields.set_item(key, value)?;
        }
    }
    Ok(PySimDefaults { fields: fields.unbind() })
}

/// Add the three tables to the extension module (their classes are registered in `lib.rs`).
pub fn add_tables(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SIM_DEFAULTS", sim_defaults(m.py())?)?;
    let py = m.py();
    // kg, the smallest non-zero and the largest body mass (`model/body.rs`); m, the largest
    // |component| of a joint origin, a CM or a point offset (`model/validate.rs`); kg·m², the
    // largest |inertia entry|.
    let bounds = [("min_mass", body::MIN_MASS), ("max_mass", body::MAX_MASS), ("max_length", validate::MAX_LENGTH), ("max_inertia_entry", body::MAX_INERTIA_ENTRY)];
    m.add("MODEL_BOUNDS", PyModelBounds { fields: bounds.into_py_dict(py)?.unbind() })?;
    // ε, the size of the singular region, and λ_max, the damping at the singularity (units of σ).
    let law = DampingLaw::default();
    let law = [("threshold", law.threshold), ("max_damping", law.max_damping)];
    m.add("DLS_DEFAULTS", PyDlsDefaults { fields: law.into_py_dict(py)?.unbind() })?;
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
