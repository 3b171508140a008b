//! The core's rotation helpers (`spacearm_core::math::rotations`, `math::spatial::skew`) over
//! float64 arrays: one item (`(4,)` quaternion, `(3,)` vector, `(3, 3)` matrix) or `(B, …)` rows
//! of them, computed row by row by the core's functions. `spacearm.rotations` checks the input
//! (finite values, unit norm, proper rotation matrices) and calls these; here only the shape is
//! checked (a `ShapeError`), so any float64 array of the right shape is computed.


use nalgebra::{Matrix3, Vector3};
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{IntoPyArray, PyArrayDyn};
use pyo3::prelude::*;
use spacearm_core::math::rotations as core;
use spacearm_core::math::spatial::skew as core_skew;

use crate::convert::{array_values, shape_error};

/// `arr`'s rows of `item` shape: `(None, values)` for one item, `(Some(B), values)` for `(B, …)`
/// rows; values in C order (borrowed when the array is C-contiguous).
fn items(py: Python<'_>, arr: &Bound<'_, PyAny>, what: &str, item: &[usize]) -> PyResult<(Option<usize>, Vec<f64>)> {
    let read = array_values(arr, what)?;
    let shape = &read.shape[..];
    let count = if shape == item {
        None
    } else if shape.len() == item.len() + 1 && &shape[1..] == item {
        Some(shape[0])
    } else {
        let item_text = item.iter().map(|d| d.to_string()).collect::<Vec<_>>().join(", ");
        let one = if item.len() == 1 { format!("({item_text},)") } else { format!("({item_text})") };
        let got = shape.iter().map(|d| d.to_string()).collect::<Vec<_>>().join(", ");
        let got = if shape.len() == 1 { format!("({got},)") } else { format!("({got})") };
        return Err(shape_error(py, format!("{what} must have shape {one} or (B, {item_text}), got {got}")));
    };
    Ok((count, read.values))
}

/// `values` as an array of shape `item` (one) or `(B, …item)` (rows).
fn output<'py>(py: Python<'py>, count: Option<usize>, item: &[usize], values: Vec<f64>) -> Bound<'py, PyArrayDyn<f64>> {
    let mut shape: Vec<usize> = count.into_iter().collect();
    shape.extend_from_slice(item);
    ArrayD::from_shape_vec(IxDyn(&shape), values).expect("shape of the rows").into_pyarray(py)
}

/// Apply `f` to each item of `width` values, each giving `out` values.
fn map_rows(values: &[f64], width: usize, out: usize, mut f: impl FnMut(&[f64], &mut [f64])) -> Vec<f64> {
    let n = values.len() / width;
    let mut result = vec![0.0; n * out];
    for (row, dst) in values.chunks_exact(width).zip(result.chunks_exact_mut(out)) {
        f(row, dst);
    }
    result
}

fn quat(row: &[f64]) -> [f64; 4] {
    [row[0], row[1], row[2], row[3]]
}

/// A row-major 3×3 matrix.
fn mat3(row: &[f64]) -> Matrix3<f64> {
    Matrix3::from_row_slice(row)
}

/// Write `m` row-major into `dst`.
fn put_mat3(m: &Matrix3<f64>, dst: &mut [f64]) {
    for i in 0..3 {
        for j in 0..3 {
            dst[3 * i + j] = m[(i, j)];
        }
    }
}

/// Hamilton product `a ⊗ b` (`math::rotations::xyzw_multiply`) of `(4,)` or `(B, 4)`
/// quaternions `[x, y, z, w]`, row by row; one quaternion (or one row) pairs with every row of
/// the other.
#[pyfunction]
pub fn quat_multiply<'py>(py: Python<'py>, a: &Bound<'py, PyAny>, b: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (na, va) = items(py, &a, "a", &[4])?;
    let (nb, vb) = items(py, &b, "b", &[4])?;
    let (ra, rb) = (na.unwrap_or(1), nb.unwrap_or(1));
    let rows = match (ra, rb) {
        _ if ra == rb => ra,
        (1, _) => rb,
        (_, 1) => ra,
        _ => return Err(shape_error(py, format!("a and b must have the same number of rows (or one of them one), got {ra} and {rb}"))),
    };
    let count = if na.is_none() && nb.is_none() { None } else { Some(rows) };
    let mut out = vec![0.0; rows * 4];
    for (k, dst) in out.chunks_exact_mut(4).enumerate() {
        let (ia, ib) = (if ra == 1 { 0 } else { k }, if rb == 1 { 0 } else { k });
        dst.copy_from_slice(&core::xyzw_multiply(&quat(&va[4 * ia..]), &quat(&vb[4 * ib..])));
    }
    Ok(output(py, count, &[4], out))
}

/// Rotation matrices (`math::rotations::matrix_from_xyzw`, each quaternion divided by its
/// norm) of `(4,)` or `(B, 4)` quaternions: `(3, 3)` or `(B, 3, 3)`.
#[pyfunction]
pub fn quat_to_matrix<'py>(py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (n, v) = items(py, &q, "q", &[4])?;
    let out = map_rows(&v, 4, 9, |row, dst| put_mat3(&core::matrix_from_xyzw(&quat(row)), dst));
    Ok(output(py, n, &[3, 3], out))
}

/// Unit quaternions `[x, y, z, w]` with `w ≥ 0` (`math::rotations::xyzw_from_matrix`,
/// Shepperd's method) of `(3, 3)` or `(B, 3, 3)` rotation matrices: `(4,)` or `(B, 4)`.
#[pyfunction]
pub fn quat_from_matrix<'py>(py: Python<'py>, r: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (n, v) = items(py, &r, "r", &[3, 3])?;
    let out = map_rows(&v, 9, 4, |row, dst| dst.copy_from_slice(&core::xyzw_from_matrix(&mat3(row))));
    Ok(output(py, n, &[4], out))
}

/// Rotation vectors `log(R)` (`math::rotations::rotation_vector`, `|θ| ≤ π`) of `(3, 3)` or
/// `(B, 3, 3)` rotation matrices: `(3,)` or `(B, 3)`.
#[pyfunction]
pub fn rotation_vector<'py>(py: Python<'py>, r: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (n, v) = items(py, &r, "r", &[3, 3])?;
    let out = map_rows(&v, 9, 3, |row, dst| dst.copy_from_slice(core::rotation_vector(&mat3(row)).as_slice()));
    Ok(output(py, n, &[3], out))
}

/// Unit quaternions `[x, y, z, w]` of `(3,)` or `(B, 3)` rotation vectors
/// (`math::rotations::xyzw_exp`): `(4,)` or `(B, 4)`.
#[pyfunction]
pub fn quat_exp<'py>(py: Python<'py>, theta: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (n, v) = items(py, &theta, "theta", &[3])?;
    let out = map_rows(&v, 3, 4, |row, dst| dst.copy_from_slice(&core::xyzw_exp(&Vector3::from_row_slice(row))));
    Ok(output(py, n, &[4], out))
}

/// Rotation vectors (`|θ| ≤ π`, `math::rotations::xyzw_log`, each quaternion normalized first)
/// of `(4,)` or `(B, 4)` quaternions: `(3,)` or `(B, 3)`.
#[pyfunction]
pub fn quat_log<'py>(py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (n, v) = items(py, &q, "q", &[4])?;
    let out = map_rows(&v, 4, 3, |row, dst| dst.copy_from_slice(core::xyzw_log(&quat(row)).as_slice()));
    Ok(output(py, n, &[3], out))
}

/// Cross-product matrices `[v]×` (`math::spatial::skew`) of `(3,)` or `(B, 3)` vectors:
/// `(3, 3)` or `(B, 3, 3)`.
#[pyfunction]
pub fn skew<'py>(py: Python<'py>, v: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (n, vals) = items(py, &v, "v", &[3])?;
    let out = map_rows(&vals, 3, 9, |row, dst| put_mat3(&core_skew(&Vector3::from_row_slice(row)), dst));
    Ok(output(py, n, &[3, 3], out))
}

/// `[x, y, z, w]` of URDF roll-pitch-yaw angles, `Rz(yaw) Ry(pitch) Rx(roll)`
/// (`math::rotations::xyzw_from_rpy`).
#[pyfunction]
pub fn quat_from_rpy<'py>(py: Python<'py>, roll: f64, pitch: f64, yaw: f64) -> Bound<'py, PyArrayDyn<f64>> {
    output(py, None, &[4], core::xyzw_from_rpy(&[roll, pitch, yaw]).to_vec())
}

/// Register the rotation helpers on the extension module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    crate::convert::add_to_module!(
        m,
        functions: [quat_multiply, quat_to_matrix, quat_from_matrix, rotation_vector, quat_exp, quat_log, skew, quat_from_rpy],
    );
    Ok(())
}
