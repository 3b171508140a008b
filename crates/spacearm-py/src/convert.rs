//! Conversions between numpy arrays / Python values and the core's types, and the mapping of
//! core errors onto the exception classes of [`crate::errors_py`] (re-exported by
//! `spacearm.errors`). This is the one place where arguments cross the boundary: only real
//! numbers (bool, int, float) are accepted, under the argument's name. The extension imports
//! numpy here, never the `spacearm` package.

use nalgebra::{DMatrix, DVector, Dim, IsContiguous, Matrix, RawStorage, Vector3, Vector6};
use std::os::raw::c_int;

use numpy::npyffi::flags::{NPY_ARRAY_ALIGNED, NPY_ARRAY_C_CONTIGUOUS, NPY_ARRAY_WRITEABLE};
use numpy::npyffi::NPY_TYPES;
use numpy::{PyArray, PyArray1, PyArray2, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use spacearm_core::SpacearmError;

use crate::errors_py::{new_error, ErrorClass};

/// The exception class of a core error: its kind's (the core's table, [`ErrorKind::exception`]).
pub fn class_of_error(err: &SpacearmError) -> ErrorClass {
    ErrorClass::of_kind(err.kind())
}

/// Raise the `spacearm.errors` class that corresponds to a core error.
pub fn to_py_err(py: Python<'_>, err: SpacearmError) -> PyErr {
    new_error(py, class_of_error(&err), err.to_string())
}

/// [`to_py_err`] with `context: ` before the message (`rollout 3: ...`, `copy 0: ...`).
pub fn to_py_err_in(py: Python<'_>, context: &str, err: SpacearmError) -> PyErr {
    new_error(py, class_of_error(&err), format!("{context}: {err}"))
}

/// The core's `InvalidArgument` with `msg` (raised as `ArgumentError`): the one form of the
/// binding's own refusals of an argument (its wording is the binding's; the class the core's).
pub fn bad(msg: String) -> SpacearmError {
    SpacearmError::InvalidArgument(msg)
}

/// Refuse plant `i` of a list (`what`: "plant", "model") whose joints differ from plant 0's
/// (`n_dof` of them): the rule of every door that runs several plants side by side (their
/// records and states stack row by row), the one the core's `BatchStepper` keeps for its copies.
pub fn same_joints(what: &str, i: usize, model: &spacearm_core::Model, n_dof: usize) -> spacearm_core::Result<()> {
    if model.n_dof() == n_dof {
        return Ok(());
    }
    Err(bad(format!("{what} {i} has {} joints, {what} 0 has {n_dof}; every {what} needs the same joints", model.n_dof())))
}

/// A `ShapeError` with `message`.
pub fn shape_error(py: Python<'_>, message: String) -> PyErr {
    new_error(py, ErrorClass::Shape, message)
}

/// A `SpacearmTypeError` with `message`.
pub fn type_error(py: Python<'_>, message: String) -> PyErr {
    new_error(py, ErrorClass::Type, message)
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

/// A model rule's refusal (`ModelError`, which says where the rule is broken) raises as the
/// core error it converts into.
impl<T> OrRaise<T> for Result<T, spacearm_core::error::ModelError> {
    fn or_raise(self, py: Python<'_>) -> PyResult<T> {
        self.map_err(|e| to_py_err(py, e.into()))
    }
}

/// A float64 vector argument of a binding. An argument that already is a 1-D, C-contiguous,
/// aligned, native float64 numpy array is used in place (no copy, no borrow bookkeeping: the
/// call holds the GIL throughout and runs no Python code between taking the slice and
/// returning); anything else is converted by numpy under the rules of [`real_array`].
pub struct VecArg<'py>(Bound<'py, PyArray1<f64>>);

impl VecArg<'_> {
    /// The values. Take slices only after every argument of the call has been converted (a
    /// conversion may run Python code).
    pub fn as_slice(&self) -> &[f64] {
        // SAFETY: contiguity and alignment were checked on construction; the array is kept
        // alive by `self`, and no Python code runs while the slice is in use (see above).
        unsafe { self.0.as_slice().unwrap_or(&[]) }
    }
}

/// Whether `arr` holds native-order float64 (in any layout).
fn is_native_float64(arr: &Bound<'_, PyUntypedArray>) -> bool {
    // Cheaper than `cast::<PyArray1<f64>>()`, whose dtype test goes through numpy's casting
    // tables.
    let dtype = arr.dtype();
    let native = matches!(dtype.byteorder(), b'=' | b'|') || (cfg!(target_endian = "little") && dtype.byteorder() == b'<');
    dtype.num() == NPY_TYPES::NPY_DOUBLE as c_int && native
}

/// Whether `arr` is native-order float64, C-contiguous and aligned: usable as a slice.
fn is_plain_float64(arr: &Bound<'_, PyUntypedArray>) -> bool {
    if !is_native_float64(arr) {
        return false;
    }
    // SAFETY: `arr` is a live numpy array; reading its flags field is what PyArray_FLAGS does.
    let flags = unsafe { (*arr.as_array_ptr()).flags };
    let wanted = NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED;
    flags & wanted == wanted
}

fn usable_in_place<'py>(obj: &Bound<'py, PyAny>) -> Option<Bound<'py, PyArray1<f64>>> {
    let arr = obj.cast::<PyUntypedArray>().ok()?;
    if arr.ndim() != 1 || !is_plain_float64(arr) {
        return None;
    }
    // SAFETY: dimensionality and element type were checked above.
    Some(unsafe { arr.cast_unchecked::<PyArray1<f64>>() }.clone())
}

fn numpy_function<'py>(py: Python<'py>, cell: &'static PyOnceLock<Py<PyAny>>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    Ok(cell.get_or_try_init(py, || py.import("numpy")?.getattr(name).map(Bound::unbind))?.bind(py).clone())
}

/// `obj` as a C-contiguous, aligned float64 numpy array, refusing anything that is not real
/// numbers: numpy's `asarray` reads it, then its dtype must be bool, integer or float (complex
/// would lose its imaginary part, and object, datetime, timedelta, string and void arrays are
/// not numbers) — else a `SpacearmTypeError` naming `what` and the dtype; a ragged sequence is a
/// `ShapeError`. An array in any other layout (Fortran order, transposed, sliced, negative or
/// zero strides, unaligned, byte-swapped, read-only) is copied once into a new C-ordered array
/// holding the same values at the same indices (docs/conventions.md, "Arrays").
pub fn real_array<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyUntypedArray>> {
    let arr = real_array_as_given(obj, what)?;
    if is_plain_float64(&arr) {
        return Ok(arr);
    }
    contiguous_float64(arr)
}

/// `arr` copied into a new C-ordered, aligned, native float64 array with the same values at the
/// same indices. A native float64 array of any strides and alignment is read by
/// [`read_c_order`]; any other real dtype is converted by numpy (`np.require(arr, float64,
/// ["C", "A"])`: C order and alignment both demanded; `np.ascontiguousarray` alone leaves an
/// unaligned array unaligned).
fn contiguous_float64<'py>(arr: Bound<'py, PyUntypedArray>) -> PyResult<Bound<'py, PyUntypedArray>> {
    let py = arr.py();
    if is_native_float64(&arr) {
        let mut values = Vec::new();
        read_c_order(&arr, &mut values)?;
        let shape = arr.shape().to_vec();
        let out = numpy::ndarray::ArrayD::from_shape_vec(numpy::ndarray::IxDyn(&shape), values).expect("values of the array's shape");
        return Ok(numpy::IntoPyArray::into_pyarray(out, py).into_any().cast_into::<PyUntypedArray>().map_err(PyErr::from)?);
    }
    static REQUIRE: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    let converted = numpy_function(py, &REQUIRE, "require")?.call1((arr, "float64", ["C", "A"]))?;
    converted.cast_into::<PyUntypedArray>().map_err(PyErr::from)
}

/// Values read between two checks for Ctrl-C while an array is read (reading a large batch,
/// e.g. a broadcast view of millions of rows, takes seconds; a pending SIGINT is answered
/// within one chunk, docs/simulation-core.md, "Errors").
const CHUNK_VALUES: usize = 1 << 20;

/// Append the values of `arr`, a native-order float64 array, to `out` in C (row-major) order:
/// element `(i0, i1, …)` is read at `data + Σ ik·stride_k` bytes, so every layout reads right —
/// C or Fortran order, transposed and sliced views, negative and zero (broadcast) strides — and
/// each element is read unaligned, so an array at an odd byte offset reads right too. This is
/// the one place where the extension reads an array's memory; everything else goes through it
/// or through a C-contiguous aligned array it checked ([`usable_in_place`]).
fn read_c_order(arr: &Bound<'_, PyUntypedArray>, out: &mut Vec<f64>) -> PyResult<()> {
    debug_assert!(is_native_float64(arr));
    let py = arr.py();
    let shape = arr.shape();
    let strides = arr.strides();
    let total: usize = shape.iter().product();
    if total == 0 {
        return Ok(());
    }
    out.reserve(total);
    // SAFETY: `arr` is a live numpy array; `data` is what PyArray_DATA returns.
    let base = unsafe { (*arr.as_array_ptr()).data } as *const u8;
    // SAFETY: as in `is_plain_float64`.
    let flags = unsafe { (*arr.as_array_ptr()).flags };
    if flags & (NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED) == NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED {
        // SAFETY: a C-contiguous aligned float64 array holds `total` values in order from `data`.
        let values = unsafe { std::slice::from_raw_parts(base as *const f64, total) };
        for chunk in values.chunks(CHUNK_VALUES) {
            py.check_signals()?;
            out.extend_from_slice(chunk);
        }
        return Ok(());
    }
    let nd = shape.len();
    let (inner, inner_stride) = (shape[nd - 1], strides[nd - 1]);
    let outer = total / inner;
    let rows_per_check = (CHUNK_VALUES / inner).max(1);
    // The index of the current row over the leading axes, and its byte offset.
    let mut index = vec![0usize; nd - 1];
    let mut offset: isize = 0;
    for k in 0..outer {
        if k % rows_per_check == 0 {
            py.check_signals()?;
        }
        for j in 0..inner {
            // SAFETY: every index is within the array's shape, so the offset is within the
            // memory numpy holds for it (strides may be negative or zero); read unaligned.
            out.push(unsafe { std::ptr::read_unaligned(base.offset(offset + j as isize * inner_stride) as *const f64) });
        }
        // The next row: the last leading axis advances, carrying into the ones before it.
        let mut d = nd - 1;
        while d > 0 {
            d -= 1;
            index[d] += 1;
            offset += strides[d];
            if index[d] < shape[d] {
                break;
            }
            offset -= strides[d] * shape[d] as isize;
            index[d] = 0;
        }
    }
    Ok(())
}

/// The values of an array argument in C order, with its shape: what every door reads an array
/// through (docs/conventions.md, "Arrays").
pub struct ArrayValues {
    pub values: Vec<f64>,
    pub shape: Vec<usize>,
}

/// Read argument `obj` named `what` as real numbers in C order, whatever its layout, alignment,
/// byte order or real dtype (the rules of [`real_array`]). The copy is admitted first
/// ([`spacearm_core::admission`]), counting one copy for a native float64 array (read through
/// its strides) and two for any other dtype (numpy's conversion, then the read).
pub fn array_values(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<ArrayValues> {
    let arr = real_array_as_given(obj, what)?;
    let shape = arr.shape().to_vec();
    let float64 = is_native_float64(&arr);
    let count: f64 = shape.iter().map(|d| *d as f64).product();
    let copies = if float64 { 1.0 } else { 2.0 };
    let bytes = copies * spacearm_core::admission::bytes_of::<f64>(count);
    spacearm_core::admission::admit(
        format_args!(
            "reading {what} ({}, {} cop{})",
            match shape[..] {
                [rows, width] => format!("{rows} rows of {width}"),
                _ => format!("shape {shape:?}"),
            },
            copies,
            if float64 { "y" } else { "ies" }
        ),
        bytes,
        "pass a smaller batch (split it into chunks), as a float64 array",
    )
    .map_err(|e| to_py_err(obj.py(), e))?;
    let arr = if float64 { arr } else { contiguous_float64(arr)? };
    let mut values = Vec::new();
    read_c_order(&arr, &mut values)?;
    Ok(ArrayValues { values, shape })
}

/// [`array_values`] of a 2-D argument with rows of `width`: `(values, rows)`, or a
/// `ShapeError` naming `what` and the expected shape.
pub fn rows_arg(obj: &Bound<'_, PyAny>, what: &str, width: usize) -> PyResult<(Vec<f64>, usize)> {
    let a = array_values(obj, what)?;
    if a.shape.len() != 2 || a.shape[1] != width {
        return Err(shape_error(obj.py(), format!("{what} must have shape (B, {width}), got an array of shape {:?}", a.shape)));
    }
    Ok((a.values, a.shape[0]))
}

/// [`array_values`] of a 2-D argument of any width: `(values, rows, cols)`, or a `ShapeError`.
pub fn matrix_arg(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<(Vec<f64>, usize, usize)> {
    let a = array_values(obj, what)?;
    if a.shape.len() != 2 {
        return Err(shape_error(obj.py(), format!("{what} must be a 2-D array, got an array of shape {:?}", a.shape)));
    }
    Ok((a.values, a.shape[0], a.shape[1]))
}

/// [`real_array`]'s reading and checks without its conversion: `obj` as a numpy array of real
/// numbers in whatever layout and real dtype it has (a numpy array is not copied).
fn real_array_as_given<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyUntypedArray>> {
    static ASARRAY: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    let py = obj.py();
    let type_name = || obj.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "object".into());
    let arr = match obj.cast::<PyUntypedArray>() {
        Ok(a) => a.clone(),
        Err(_) => {
            let converted = numpy_function(py, &ASARRAY, "asarray")?.call1((obj,)).map_err(|e| {
                // numpy refuses a ragged or unreadable sequence with ValueError or TypeError;
                // anything that is not an Exception (KeyboardInterrupt) goes through.
                if e.is_instance_of::<pyo3::exceptions::PyException>(py) {
                    shape_error(py, format!("{what} must be an array of numbers (a 1-D array, or a 2-D array with one state per row), got a {} that numpy cannot read as one: {}", type_name(), e.value(py)))
                } else {
                    e
                }
            })?;
            converted.cast_into::<PyUntypedArray>().map_err(PyErr::from)?
        }
    };
    let dtype = arr.dtype();
    if !matches!(dtype.kind(), b'b' | b'i' | b'u' | b'f') {
        let described = dtype.str().map(|s| s.to_string()).unwrap_or_else(|_| "?".into());
        let got = if arr.ndim() == 0 && dtype.kind() == b'O' { format!("a {}", type_name()) } else { format!("an array of dtype {described}") };
        return Err(type_error(py, format!("{what} must hold real numbers (bool, int or float), got {got}")));
    }
    Ok(arr)
}

/// Convert a vector argument named `what` (see [`VecArg`]): one state, 1-D. A 1-D array in any
/// other layout or dtype is copied once into a C-contiguous aligned float64 array.
pub fn vec_arg<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<VecArg<'py>> {
    if let Some(arr) = usable_in_place(obj) {
        return Ok(VecArg(arr));
    }
    let arr = real_array_as_given(obj, what)?;
    if arr.ndim() != 1 {
        return Err(shape_error(obj.py(), format!("{what} must be a 1-D array, got an array of shape {:?}", arr.shape())));
    }
    one_vector(obj.py(), arr, what)
}

/// A 1-D real array as a [`VecArg`]: used in place when it is plain float64, else copied once.
fn one_vector<'py>(py: Python<'py>, arr: Bound<'py, PyUntypedArray>, what: &str) -> PyResult<VecArg<'py>> {
    let arr = if is_plain_float64(&arr) { arr } else { contiguous_float64(arr)? };
    match usable_in_place(arr.as_any()) {
        Some(a) => Ok(VecArg(a)),
        // Not reached: `contiguous_float64` returns a C-contiguous aligned float64 array.
        None => Err(shape_error(py, format!("{what} could not be read as a float64 vector"))),
    }
}

/// A vector argument that may also be a batch: `One` 1-D vector, or `Many` rows of a 2-D
/// array (copied, row-major, so that the values may be read without the GIL).
pub enum ArgValue<'py> {
    /// One vector, used in place.
    One(VecArg<'py>),
    /// A batch of `rows` vectors of length `width`, row after row.
    Many { values: Vec<f64>, rows: usize, width: usize },
}

/// Convert an argument that may be one vector (1-D) or a batch of them (2-D, one per row).
pub fn batch_arg<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<ArgValue<'py>> {
    match usable_in_place(obj) {
        Some(arr) => Ok(ArgValue::One(VecArg(arr))),
        None => converted_batch_arg(obj, what),
    }
}

/// [`batch_arg`] of anything that is not a float64 vector usable in place (lists, other dtypes,
/// layouts, batches): out of line, so that the common case stays a few instructions in its
/// caller. A batch is read by [`array_values`] (admitted first, read through its strides).
#[inline(never)]
fn converted_batch_arg<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<ArgValue<'py>> {
    let arr = real_array_as_given(obj, what)?;
    match arr.ndim() {
        1 => Ok(ArgValue::One(one_vector(obj.py(), arr, what)?)),
        2 => {
            let a = array_values(arr.as_any(), what)?;
            Ok(ArgValue::Many { values: a.values, rows: a.shape[0], width: a.shape[1] })
        }
        _ => Err(shape_error(
            obj.py(),
            format!("{what} must be a 1-D array (one state) or a 2-D array (a batch, one state per row), got an array of shape {:?}", arr.shape()),
        )),
    }
}

/// A vector argument (see [`vec_arg`]) copied out: for a run that holds no borrow of Python
/// objects while it works.
pub fn owned_vec(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    Ok(vec_arg(obj, what)?.as_slice().to_vec())
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

/// A finite 3-vector argument (a point offset): [`vec3`] plus `NonFiniteError` naming `what`.
pub fn finite3(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vector3<f64>> {
    let v = vec3(obj, what)?;
    check_finite(obj.py(), what, v.as_slice())?;
    Ok(v)
}

/// A 6-vector argument (length checked, `ShapeError` naming `what`).
pub fn vec6(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vector6<f64>> {
    Ok(Vector6::from_column_slice(vec_arg_n(obj, what, 6)?.as_slice()))
}

/// `a`, made read-only (numpy's `setflags(write=False)`): a result class hands out the same
/// array on every read, so no caller can change what another reads.
pub fn read_only<'py, D>(a: Bound<'py, PyArray<f64, D>>) -> Py<PyArray<f64, D>> {
    // SAFETY: a fresh array that nothing else references yet; clearing WRITEABLE is what
    // `ndarray.setflags(write=False)` does.
    unsafe { (*a.as_array_ptr()).flags &= !NPY_ARRAY_WRITEABLE };
    a.unbind()
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

/// The core's triangle-inequality rule for the Python option `allow_nonphysical_inertia`.
pub fn triangle_inequality(allow_nonphysical_inertia: bool) -> spacearm_core::model::TriangleInequality {
    if allow_nonphysical_inertia {
        spacearm_core::model::TriangleInequality::Warn
    } else {
        spacearm_core::model::TriangleInequality::Enforce
    }
}

/// The row-major `values` as a `(len / width, width)` array (the buffer moved, not copied; no
/// rows when `width` is 0).
pub fn rows<'py>(py: Python<'py>, values: Vec<f64>, width: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let k = if width == 0 { 0 } else { values.len() / width };
    Ok(PyArray1::from_vec(py, values).reshape([k, width])?)
}

/// Add the `#[pyfunction]`s `functions` and the `#[pyclass]`es `classes` to the module `m`: a
/// door's `register` as two lists (`add_to_module!(m, functions: [f, g], classes: [A, B])`).
macro_rules! add_to_module {
    ($m:expr, functions: [$($f:path),* $(,)?] $(, classes: [$($c:ty),* $(,)?])? $(,)?) => {{
        $($m.add_function(pyo3::wrap_pyfunction!($f, $m)?)?;)*
        $($($m.add_class::<$c>()?;)*)?
    }};
    ($m:expr, classes: [$($c:ty),* $(,)?] $(,)?) => {{
        $($m.add_class::<$c>()?;)*
    }};
}
pub(crate) use add_to_module;

/// A `#[pymethods] impl` block whose read-only properties that need no `py` are written one a
/// line, `name: Type = expression;` (its doc comment above it, the expression reading `self`),
/// ahead of the class's other methods: a property in one line instead of a `#[getter]` method
/// of four. The attribute and the receiver come from the call (`#[pymethods] impl Class {
/// getters(self) { … } … }`) so that PyO3's generated code and the expressions' `self` resolve
/// at the call site.
macro_rules! pymethods_with_getters {
    ($pound:tt $attr:tt impl $class:ty { getters($s:ident) { $($(#[$doc:meta])* $name:ident: $ty:ty = $value:expr;)* } $($methods:tt)* }) => {
        $pound $attr
        impl $class {
            $(
                $(#[$doc])*
                #[getter]
                fn $name(&$s) -> $ty {
                    $value
                }
            )*
            $($methods)*
        }
    };
}
pub(crate) use pymethods_with_getters;

/// The one-line repr of a result (tests/test_reprs.py: short, no array's numbers):
/// `<module.Class name=value …>` over the attributes `fields` of `obj`, an array shown by its
/// shape (`(3, 6)`), anything else by its repr. The class is `obj`'s own, so a Python subclass
/// (`spacearm.analysis.Motion`) reads as itself.
pub fn summary(obj: &Bound<'_, PyAny>, fields: &[&str]) -> PyResult<String> {
    let cls = obj.get_type();
    let mut text = format!("<{}.{}", cls.module()?, cls.qualname()?);
    for field in fields {
        let value = obj.getattr(*field)?;
        let shown = match value.cast::<PyUntypedArray>() {
            Ok(a) if a.ndim() == 1 => format!("({},)", a.shape()[0]),
            Ok(a) => format!("({})", a.shape().iter().map(|n| n.to_string()).collect::<Vec<_>>().join(", ")),
            Err(_) => value.repr()?.to_string(),
        };
        text += &format!(" {field}={shown}");
    }
    Ok(text + ">")
}

/// A frozen class of a core result with its fields written once: each field's doc (and
/// attributes), type and value — an expression of the constructor's arguments and of the
/// `let`s in brackets before the fields. Writes the struct (`get_all`: each field a read-only
/// attribute; more `#[pyclass]` options in parentheses after the name, `(subclass)`) and the
/// constructor `$ctor` (`-> PyResult`: a fallible one, the values may use `?`); with `repr`
/// first, also a `__repr__` of every field ([`summary`]). The field-by-field copy of a core
/// result into Python stands in one list.
macro_rules! result_class {
    (@class [$($repr:ident)?]
        $(#[$attr:meta])*
        $rust:ident as $name:literal $(($($opt:ident),*))?, fn $ctor:ident($($args:tt)*) $(-> $ret:ident)? $([$(let $local:pat = $init:expr;)*])? {
            $($(#[$fattr:meta])* $field:ident: $fty:ty = $value:expr,)+
        }
    ) => {
        $(#[$attr])*
        #[pyclass(module = "spacearm._core", name = $name, frozen, $($($opt,)*)? get_all)]
        pub struct $rust {
            $($(#[$fattr])* $field: $fty,)+
        }

        impl $rust {
            /// The attributes, in order.
            #[allow(dead_code)]
            const FIELDS: &'static [&'static str] = &[$(stringify!($field)),+];

            crate::convert::result_class!(@ctor [$($ret)?] $rust, $ctor, ($($args)*), { $($(let $local = $init;)*)? }, { $($field: $value),+ });
        }

        $(
            #[pymethods]
            impl $rust {
                fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
                    let _ = stringify!($repr);
                    crate::convert::summary(slf.as_any(), Self::FIELDS)
                }
            }
        )?
    };
    (@ctor [] $rust:ident, $ctor:ident, ($($args:tt)*), { $($pre:tt)* }, { $($field:ident: $value:expr),+ }) => {
        pub(crate) fn $ctor($($args)*) -> Self {
            $($pre)*
            $rust { $($field: $value,)+ }
        }
    };
    (@ctor [PyResult] $rust:ident, $ctor:ident, ($($args:tt)*), { $($pre:tt)* }, { $($field:ident: $value:expr),+ }) => {
        pub(crate) fn $ctor($($args)*) -> PyResult<Self> {
            $($pre)*
            Ok($rust { $($field: $value,)+ })
        }
    };
    (@ $($rest:tt)*) => {
        compile_error!("result_class!: expected `[repr;] docs Class as \"Name\", fn ctor(args) [-> PyResult] [lets] { fields }`");
    };
    (repr; $($rest:tt)*) => {
        crate::convert::result_class!(@class [repr] $($rest)*);
    };
    ($($rest:tt)*) => {
        crate::convert::result_class!(@class [] $($rest)*);
    };
}
pub(crate) use result_class;
