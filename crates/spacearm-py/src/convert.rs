//! Conversions between numpy arrays / Python values and the core's types, and the mapping of
//! core errors onto the Python exception classes defined in `spacearm.errors`.

use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Vector3, Vector6};
use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray1};
use pyo3::prelude::*;
use spacearm_core::SpacearmError;

/// Raise the `spacearm.errors` class that corresponds to a core error.
pub fn to_py_err(py: Python<'_>, err: SpacearmError) -> PyErr {
    let class = match &err {
        SpacearmError::InvalidModel(_) => "ModelError",
        SpacearmError::Dimension { .. } => "ShapeError",
        SpacearmError::NonFinite { .. } => "NonFiniteError",
        SpacearmError::NotUnitQuaternion { .. } => "QuaternionError",
        SpacearmError::NotFound(_) => "NotFoundError",
        SpacearmError::Singular(_) => "SingularError",
        SpacearmError::Parse(_) => "ModelFileError",
    };
    let message = err.to_string();
    match py.import("spacearm.errors").and_then(|m| m.getattr(class)).and_then(|c| c.call1((message.clone(),))) {
        Ok(instance) => PyErr::from_value(instance),
        Err(e) => e,
    }
}

/// `core::Result<T>` → `PyResult<T>` with the right exception class.
pub trait OrRaise<T> {
    fn or_raise(self, py: Python<'_>) -> PyResult<T>;
}

impl<T> OrRaise<T> for spacearm_core::Result<T> {
    fn or_raise(self, py: Python<'_>) -> PyResult<T> {
        self.map_err(|e| to_py_err(py, e))
    }
}

/// Borrow a 1-D float64 array as a slice (the Python layer makes arrays contiguous).
pub fn slice<'a>(py: Python<'_>, what: &str, a: &'a PyReadonlyArray1<'_, f64>) -> PyResult<&'a [f64]> {
    a.as_slice().map_err(|_| {
        to_py_err(py, SpacearmError::Dimension { what: format!("{what} (as a contiguous 1-D float array)"), expected: "contiguous".into(), got: 0 })
    })
}

pub fn vec3(py: Python<'_>, what: &str, a: &PyReadonlyArray1<'_, f64>) -> PyResult<Vector3<f64>> {
    let s = slice(py, what, a)?;
    if s.len() != 3 {
        return Err(to_py_err(py, SpacearmError::Dimension { what: what.into(), expected: "3".into(), got: s.len() }));
    }
    Ok(Vector3::from_column_slice(s))
}

pub fn vec6(py: Python<'_>, what: &str, a: &PyReadonlyArray1<'_, f64>) -> PyResult<Vector6<f64>> {
    let s = slice(py, what, a)?;
    if s.len() != 6 {
        return Err(to_py_err(py, SpacearmError::Dimension { what: what.into(), expected: "6".into(), got: s.len() }));
    }
    Ok(Vector6::from_column_slice(s))
}

pub fn array1<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v)
}

pub fn dvec<'py>(py: Python<'py>, v: &DVector<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v.as_slice())
}

pub fn dmat<'py>(py: Python<'py>, m: &DMatrix<f64>) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_fn((m.nrows(), m.ncols()), |(i, j)| m[(i, j)]).into_pyarray(py)
}

pub fn mat6<'py>(py: Python<'py>, m: &Matrix6<f64>) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_fn((6, 6), |(i, j)| m[(i, j)]).into_pyarray(py)
}

pub fn mat3<'py>(py: Python<'py>, m: &Matrix3<f64>) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_fn((3, 3), |(i, j)| m[(i, j)]).into_pyarray(py)
}

pub fn stack_mat3<'py>(py: Python<'py>, ms: &[Matrix3<f64>]) -> Bound<'py, PyArray3<f64>> {
    Array3::from_shape_fn((ms.len(), 3, 3), |(k, i, j)| ms[k][(i, j)]).into_pyarray(py)
}

pub fn stack_vec3<'py>(py: Python<'py>, vs: &[Vector3<f64>]) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_fn((vs.len(), 3), |(k, i)| vs[k][i]).into_pyarray(py)
}

pub fn rows3(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    [[m[(0, 0)], m[(0, 1)], m[(0, 2)]], [m[(1, 0)], m[(1, 1)], m[(1, 2)]], [m[(2, 0)], m[(2, 1)], m[(2, 2)]]]
}
