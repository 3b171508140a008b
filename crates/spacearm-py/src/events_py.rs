//! `spacearm._core.StopCondition`: a condition that stops a run early
//! (`spacearm_core::sim::events::StopCondition`), built by its two constructors and checked by
//! the core (when built, and against the plant when the run starts).

use pyo3::prelude::*;
use spacearm_core::sim::events::{validate, StopCondition};

use crate::convert::*;

/// A stop condition of a run (`RunOptions(stop=[...])`): `StopCondition.time(t)` or
/// `StopCondition.gap(body, offset, tolerance)` (docs/simulation-core.md, "Events").
#[pyclass(module = "spacearm._core", name = "StopCondition", frozen)]
#[derive(Clone)]
pub struct PyStopCondition {
    pub inner: StopCondition,
}

impl PyStopCondition {
    fn checked(py: Python<'_>, inner: StopCondition) -> PyResult<Self> {
        validate(std::slice::from_ref(&inner)).or_raise(py)?;
        Ok(PyStopCondition { inner })
    }
}

#[pymethods]
impl PyStopCondition {
    /// Stop at time `t` (s, > 0), if the run gets there.
    #[staticmethod]
    fn time(py: Python<'_>, t: f64) -> PyResult<Self> {
        Self::checked(py, StopCondition::Time { t })
    }

    /// Stop when the robot point (`body`, `offset` from its CM in its frame, m) is within
    /// `tolerance` (m, > 0) of the controller's point reference.
    #[staticmethod]
    fn gap(py: Python<'_>, body: usize, offset: &Bound<'_, PyAny>, tolerance: f64) -> PyResult<Self> {
        let o = vec3(offset, "offset")?;
        Self::checked(py, StopCondition::Gap { body, offset: [o.x, o.y, o.z], tolerance })
    }

    /// `"time"` or `"gap"`.
    #[getter]
    fn kind(&self) -> &'static str {
        self.inner.kind()
    }

    fn __repr__(&self) -> String {
        match &self.inner {
            StopCondition::Time { t } => format!("<spacearm._core.StopCondition time t={t} s>"),
            StopCondition::Gap { body, offset, tolerance } => {
                format!("<spacearm._core.StopCondition gap body={body} offset={offset:?} m tolerance={tolerance} m>")
            }
        }
    }
}
