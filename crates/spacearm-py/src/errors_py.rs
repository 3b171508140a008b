//! The exception classes of spacearm, defined here, in the extension, so that the extension
//! never imports the Python package that wraps it; `spacearm.errors` re-exports them (and adds
//! the few classes only Python code raises).
//!
//! Each class derives from `SpacearmError` and from the builtin a Python programmer expects
//! (the table is in `spacearm.errors`' docstring). The classes are built once, at module
//! initialisation, with `type(name, bases, namespace)` because PyO3's `create_exception!`
//! allows one base only. Their `__module__` is `spacearm.errors`, where users import them
//! from and where pickle finds them.

use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};
use spacearm_core::ErrorKind;

/// One exception class of the extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorClass {
    Spacearm,
    Model,
    ModelFile,
    Shape,
    NonFinite,
    Quaternion,
    NotFound,
    Singular,
    Argument,
    Type,
    Simulation,
    ResourceLimit,
}

impl ErrorClass {
    const ALL: [ErrorClass; 12] = [
        ErrorClass::Spacearm,
        ErrorClass::Model,
        ErrorClass::ModelFile,
        ErrorClass::Shape,
        ErrorClass::NonFinite,
        ErrorClass::Quaternion,
        ErrorClass::NotFound,
        ErrorClass::Singular,
        ErrorClass::Argument,
        ErrorClass::Type,
        ErrorClass::Simulation,
        ErrorClass::ResourceLimit,
    ];

    /// The class name in `spacearm.errors`.
    pub fn name(self) -> &'static str {
        match self {
            ErrorClass::Spacearm => "SpacearmError",
            ErrorClass::Model => "ModelError",
            ErrorClass::ModelFile => "ModelFileError",
            ErrorClass::Shape => "ShapeError",
            ErrorClass::NonFinite => "NonFiniteError",
            ErrorClass::Quaternion => "QuaternionError",
            ErrorClass::NotFound => "NotFoundError",
            ErrorClass::Singular => "SingularError",
            ErrorClass::Argument => "ArgumentError",
            ErrorClass::Type => "SpacearmTypeError",
            ErrorClass::Simulation => "SimulationError",
            ErrorClass::ResourceLimit => "ResourceLimitError",
        }
    }

    /// The class of an error kind of the core: the one named by the core's table
    /// ([`ErrorKind::exception`]).
    pub fn of_kind(kind: ErrorKind) -> ErrorClass {
        ErrorClass::ALL.into_iter().find(|c| c.name() == kind.exception()).unwrap_or(ErrorClass::Spacearm)
    }

    /// The spacearm class it derives from (`None`: the root) and its builtin bases.
    fn bases(self) -> (Option<ErrorClass>, &'static [&'static str]) {
        match self {
            ErrorClass::Spacearm => (None, &["Exception"]),
            ErrorClass::Model => (Some(ErrorClass::Spacearm), &["ValueError"]),
            ErrorClass::ModelFile => (Some(ErrorClass::Model), &[]),
            ErrorClass::Shape | ErrorClass::NonFinite | ErrorClass::Quaternion | ErrorClass::Argument => {
                (Some(ErrorClass::Spacearm), &["ValueError"])
            }
            ErrorClass::NotFound => (Some(ErrorClass::Spacearm), &["KeyError", "ValueError"]),
            ErrorClass::Singular => (Some(ErrorClass::Spacearm), &["ArithmeticError"]),
            ErrorClass::Type => (Some(ErrorClass::Spacearm), &["TypeError"]),
            ErrorClass::Simulation => (Some(ErrorClass::Spacearm), &["RuntimeError"]),
            ErrorClass::ResourceLimit => (Some(ErrorClass::Spacearm), &["MemoryError"]),
        }
    }
}

static CLASSES: PyOnceLock<Vec<Py<PyType>>> = PyOnceLock::new();

fn build_classes(py: Python<'_>) -> PyResult<Vec<Py<PyType>>> {
    let builtins = py.import("builtins")?;
    let type_ = builtins.getattr("type")?;
    let mut built: Vec<Py<PyType>> = Vec::with_capacity(ErrorClass::ALL.len());
    for class in ErrorClass::ALL {
        let (parent, builtin_bases) = class.bases();
        let mut bases: Vec<Bound<'_, PyAny>> = Vec::new();
        if let Some(p) = parent {
            bases.push(built[p as usize].bind(py).clone().into_any());
        }
        for b in builtin_bases {
            bases.push(builtins.getattr(*b)?);
        }
        let namespace = PyDict::new(py);
        namespace.set_item("__module__", "spacearm.errors")?;
        if class == ErrorClass::NotFound {
            // KeyError's str() is the repr of its argument (quotes around the message): print
            // the message as written, like every other spacearm error.
            namespace.set_item("__str__", builtins.getattr("BaseException")?.getattr("__str__")?)?;
        }
        let cls = type_.call1((class.name(), PyTuple::new(py, bases)?, namespace))?;
        built.push(cls.cast_into::<PyType>()?.unbind());
    }
    Ok(built)
}

/// The class object of `class` (built on first use).
pub fn class_of(py: Python<'_>, class: ErrorClass) -> PyResult<Bound<'_, PyType>> {
    let classes = CLASSES.get_or_try_init(py, || build_classes(py))?;
    Ok(classes[class as usize].bind(py).clone())
}

/// A new exception of `class` with `message`.
pub fn new_error(py: Python<'_>, class: ErrorClass, message: String) -> PyErr {
    match class_of(py, class) {
        Ok(cls) => PyErr::from_type(cls, message),
        Err(e) => e,
    }
}

/// Add every class to the extension module, and `ERROR_KINDS`: the core's error kinds, each
/// as its name, its C status code and the class it is raised as (the core's table).
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    for class in ErrorClass::ALL {
        m.add(class.name(), class_of(m.py(), class)?)?;
    }
    let kinds: Vec<(&str, i32, Bound<'_, PyType>)> =
        ErrorKind::ALL.into_iter().map(|k| Ok((k.name(), k.status_code(), class_of(m.py(), ErrorClass::of_kind(k))?))).collect::<PyResult<_>>()?;
    m.add("ERROR_KINDS", kinds)?;
    Ok(())
}
