//! Conversions between numpy arrays / Python values and the core's types, and the mapping of
//! core errors onto the Python exception classes defined in `spacearm.errors`.

use nalgebra::{DMatrix, DVector, Dim, IsContiguous, Matrix, Matrix3, Matrix6, RawStorage, Vector3, Vector6};
use std::os::raw::c_int;

use numpy::npyffi::flags::{NPY_ARRAY_ALIGNED, NPY_ARRAY_C_CONTIGUOUS};
use numpy::npyffi::NPY_TYPES;
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
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
        SpacearmError::InvalidArgument(_) => "ArgumentError",
        SpacearmError::Simulation(_) => "SimulationError",
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

/// A float64 vector argument of a binding. An argument that already is a 1-D, C-contiguous,
/// aligned, native float64 numpy array is used in place (no copy, no borrow bookkeeping: the
/// call holds the GIL throughout and runs no Python code between taking the slice and
/// returning); anything else goes through `spacearm._arrays.vector`, the Python layer's own
/// converter, so that conversion errors read exactly as they do there.
pub struct VecArg<'py>(Bound<'py, PyArray1<f64>>);

impl VecArg<'_> {
    /// The values. Take slices only after every argument of the call has been converted (the
    /// fallback conversion runs Python code).
    pub fn as_slice(&self) -> &[f64] {
        // SAFETY: contiguity and alignment were checked on construction; the array is kept
        // alive by `self`, and no Python code runs while the slice is in use (see above).
        unsafe { self.0.as_slice().unwrap_or(&[]) }
    }
}

fn usable_in_place<'py>(obj: &Bound<'py, PyAny>) -> Option<Bound<'py, PyArray1<f64>>> {
    // Cheaper than `cast::<PyArray1<f64>>()`, whose dtype test goes through numpy's casting
    // tables: an ndarray (or subclass), 1-D, dtype float64 in native byte order, C-contiguous
    // and aligned.
    let arr = obj.cast::<PyUntypedArray>().ok()?;
    if arr.ndim() != 1 {
        return None;
    }
    let dtype = arr.dtype();
    let native = matches!(dtype.byteorder(), b'=' | b'|') || (cfg!(target_endian = "little") && dtype.byteorder() == b'<');
    if dtype.num() != NPY_TYPES::NPY_DOUBLE as c_int || !native {
        return None;
    }
    // SAFETY: `arr` is a live numpy array; reading its flags field is what PyArray_FLAGS does.
    let flags = unsafe { (*arr.as_array_ptr()).flags };
    let wanted = NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED;
    if flags & wanted != wanted {
        return None;
    }
    // SAFETY: dimensionality and element type were checked above.
    Some(unsafe { arr.cast_unchecked::<PyArray1<f64>>() }.clone())
}

/// Convert a vector argument named `what` (see [`VecArg`]).
pub fn vec_arg<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<VecArg<'py>> {
    if let Some(arr) = usable_in_place(obj) {
        return Ok(VecArg(arr));
    }
    static VECTOR: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    let py = obj.py();
    let convert = VECTOR.get_or_try_init(py, || py.import("spacearm._util.arrays")?.getattr("vector").map(Bound::unbind))?;
    let converted = convert.bind(py).call1((obj, what))?;
    if let Some(arr) = usable_in_place(&converted) {
        return Ok(VecArg(arr));
    }
    // `vector` returns contiguous float64; a misaligned buffer still needs a fresh copy.
    let arr = converted.cast_into::<PyArray1<f64>>().map_err(PyErr::from)?;
    let copy = PyArray1::from_vec(py, arr.to_vec().map_err(PyErr::from)?);
    Ok(VecArg(copy))
}

/// A fixed-length argument (`offset`, momenta): [`vec_arg`] plus a length check that raises
/// `ShapeError` naming `what`.
pub fn vec_arg_n<'py>(obj: &Bound<'py, PyAny>, what: &str, n: usize) -> PyResult<VecArg<'py>> {
    let v = vec_arg(obj, what)?;
    let len = v.0.len();
    if len != n {
        return Err(to_py_err(obj.py(), SpacearmError::Dimension { what: what.into(), expected: n.to_string(), got: len }));
    }
    Ok(v)
}

/// Raise `NonFiniteError` naming `what` and its first non-finite entry, if any.
pub fn check_finite(py: Python<'_>, what: &str, values: &[f64]) -> PyResult<()> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(to_py_err(py, SpacearmError::NonFinite { what: what.into(), index, value: values[index] })),
        None => Ok(()),
    }
}

/// A 3-vector argument (length checked, `ShapeError` naming `what`).
pub fn vec3(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vector3<f64>> {
    Ok(Vector3::from_column_slice(vec_arg_n(obj, what, 3)?.as_slice()))
}

/// A 6-vector argument (length checked, `ShapeError` naming `what`).
pub fn vec6(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vector6<f64>> {
    Ok(Vector6::from_column_slice(vec_arg_n(obj, what, 6)?.as_slice()))
}

pub fn array1<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v)
}

pub fn dvec<'py>(py: Python<'py>, v: &DVector<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v.as_slice())
}

/// A column-major `rows × cols` buffer as a new C-ordered numpy array (filled in place, no
/// intermediate).
fn column_major_to_py<'py>(py: Python<'py>, src: &[f64], rows: usize, cols: usize) -> Bound<'py, PyArray2<f64>> {
    assert_eq!(src.len(), rows * cols, "column-major buffer of the stated shape");
    // SAFETY: a fresh array owned by nobody else; every element is written below.
    let out = unsafe { PyArray2::<f64>::new(py, [rows, cols], false) };
    let dst = unsafe { out.as_slice_mut().expect("a new array is contiguous") };
    assert_eq!(dst.len(), rows * cols);
    // Walk the output in order, reading the source with a stride of `rows`.
    let (mut d, s0) = (dst.as_mut_ptr(), src.as_ptr());
    for i in 0..rows {
        // SAFETY: element (i, j) is at i + j·rows < rows·cols in `src`; `d` advances through
        // the rows·cols elements of `dst` exactly once.
        unsafe {
            let mut s = s0.add(i);
            for _ in 0..cols {
                *d = *s;
                d = d.add(1);
                s = s.wrapping_add(rows);
            }
        }
    }
    out
}

/// Any nalgebra matrix with contiguous storage as a new C-ordered numpy array.
pub fn matrix<'py, R: Dim, C: Dim, S: RawStorage<f64, R, C> + IsContiguous>(py: Python<'py>, m: &Matrix<f64, R, C, S>) -> Bound<'py, PyArray2<f64>> {
    let (rows, cols) = m.shape();
    column_major_to_py(py, m.as_slice(), rows, cols)
}

pub fn dmat<'py>(py: Python<'py>, m: &DMatrix<f64>) -> Bound<'py, PyArray2<f64>> {
    matrix(py, m)
}

pub fn mat6<'py>(py: Python<'py>, m: &Matrix6<f64>) -> Bound<'py, PyArray2<f64>> {
    matrix(py, m)
}

pub fn mat3<'py>(py: Python<'py>, m: &Matrix3<f64>) -> Bound<'py, PyArray2<f64>> {
    matrix(py, m)
}

pub fn stack_mat3<'py>(py: Python<'py>, ms: &[Matrix3<f64>]) -> Bound<'py, PyArray3<f64>> {
    // SAFETY: a fresh array owned by nobody else; every element is written below.
    let out = unsafe { PyArray3::<f64>::new(py, [ms.len(), 3, 3], false) };
    let dst = unsafe { out.as_slice_mut().expect("a new array is contiguous") };
    for (k, m) in ms.iter().enumerate() {
        for i in 0..3 {
            for j in 0..3 {
                dst[9 * k + 3 * i + j] = m[(i, j)];
            }
        }
    }
    out
}

pub fn stack_vec3<'py>(py: Python<'py>, vs: &[Vector3<f64>]) -> Bound<'py, PyArray2<f64>> {
    // SAFETY: a fresh array owned by nobody else; every element is written below.
    let out = unsafe { PyArray2::<f64>::new(py, [vs.len(), 3], false) };
    let dst = unsafe { out.as_slice_mut().expect("a new array is contiguous") };
    for (k, v) in vs.iter().enumerate() {
        dst[3 * k..3 * k + 3].copy_from_slice(v.as_slice());
    }
    out
}

pub fn rows3(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    [[m[(0, 0)], m[(0, 1)], m[(0, 2)]], [m[(1, 0)], m[(1, 1)], m[(1, 2)]], [m[(2, 0)], m[(2, 1)], m[(2, 2)]]]
}

/// The core's triangle-inequality rule for the Python option `allow_nonphysical_inertia`.
pub fn triangle_inequality(allow_nonphysical_inertia: bool) -> spacearm_core::model::TriangleInequality {
    if allow_nonphysical_inertia {
        spacearm_core::model::TriangleInequality::Warn
    } else {
        spacearm_core::model::TriangleInequality::Enforce
    }
}
