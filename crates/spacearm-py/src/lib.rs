//! PyO3 bindings of `spacearm-core`, built as the private extension `spacearm._core`.
//!
//! Thin by design: each method converts numpy arrays to slices, calls one core function and
//! converts the result back; errors map onto `spacearm.errors`. The Python package
//! (`python/spacearm`) is the face users see.

mod builder_py;
mod convert;
mod model_py;

use pyo3::prelude::*;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<model_py::PyModel>()?;
    m.add_class::<builder_py::PyModelBuilder>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
