//! Bindings of `spacearm_core::analysis`: dynamic singularities, joint-space scans,
//! workspaces, reaction null space, free-floating kinematics and resolved-motion-rate control.
//! Thin wrappers: arrays in, a typed result out (the classes of `analysis_results_py.rs`); the
//! Python package `spacearm.analysis` is the face users see. Scans release the GIL while rayon runs.

use nalgebra::{Vector3, Vector6};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use spacearm_core::analysis::{
    free_floating_kinematics as ffk, reach, reaction_null_space as rns, redundancy, scan, singularity, Task,
};
use spacearm_core::SpacearmError;

use crate::analysis_results_py::*;
use crate::convert::*;
use crate::model_py::PyModel;

pub(crate) fn task(py: Python<'_>, rows: Vec<usize>) -> PyResult<Task> {
    Task::new(&rows).or_raise(py)
}


/// Singular values, condition, manipulability, singular directions of J* and J_m.
#[pyfunction]
pub fn analysis_singularity<'py>(py: Python<'py>, m: PyRef<'_, PyModel>, x: &Bound<'py, PyAny>, body: usize, offset: &Bound<'py, PyAny>, rows: Vec<usize>) -> PyResult<PySingularityReport> {
    let off = vec3(offset, "offset")?;
    let x = vec_arg(x, "x")?;
    let t = task(py, rows.clone())?;
    let a = m.with_data(|model, data| singularity::analyze(model, data, x.as_slice(), body, &off, &t)).or_raise(py)?;
    PySingularityReport::new(py, &a, &rows)
}

/// The singularity detector on the task rows of J* at x: σ_min, condition, damping, near_singular.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn analysis_detect(py: Python<'_>, m: PyRef<'_, PyModel>, x: &Bound<'_, PyAny>, body: usize, offset: &Bound<'_, PyAny>, rows: Vec<usize>, threshold: f64, max_damping: f64) -> PyResult<PyDetection> {
    let off = vec3(offset, "offset")?;
    let x = vec_arg(x, "x")?;
    let t = task(py, rows)?;
    let law = singularity::DampingLaw::new(threshold, max_damping).or_raise(py)?;
    let d = m.with_data(|model, data| singularity::detect_at(model, data, x.as_slice(), body, &off, &t, &law)).or_raise(py)?;
    Ok(PyDetection::of(d))
}

/// The damping λ(σ_min) of the law λ² = λ_max² (1 − (σ/ε)²) for σ < ε.
#[pyfunction]
pub fn analysis_damping(py: Python<'_>, sigma_min: f64, threshold: f64, max_damping: f64) -> PyResult<f64> {
    Ok(singularity::DampingLaw::new(threshold, max_damping).or_raise(py)?.damping(sigma_min))
}

/// Regular joint grid (row-major M×N).
#[pyfunction]
pub fn analysis_joint_grid<'py>(py: Python<'py>, lower: Vec<f64>, upper: Vec<f64>, resolution: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = lower.len();
    let g = scan::joint_grid(&lower, &upper, resolution).or_raise(py)?;
    Ok(row_major(py, &g, g.len() / n.max(1), n))
}

fn run_scan(py: Python<'_>, m: &PyModel, samples: &Bound<'_, PyAny>, body: usize, off: &Vector3<f64>, t: &Task) -> PyResult<Vec<scan::ScanSample>> {
    let (v, _, cols) = matrix_arg(samples, "samples")?;
    let n = m.model.n_dof();
    if cols != n {
        return Err(to_py_err(py, SpacearmError::Dimension { what: "joint samples (columns)".into(), expected: format!("N = {n}"), got: cols }));
    }
    let model = &m.model;
    py.detach(|| scan::scan(model, &v, body, off, t)).or_raise(py)
}

/// Parallel scan of joint samples (M×N): σ, manipulability, det of J* and J_m, positions.
#[pyfunction]
pub fn analysis_scan<'py>(py: Python<'py>, m: PyRef<'_, PyModel>, samples: &Bound<'py, PyAny>, body: usize, offset: &Bound<'py, PyAny>, rows: Vec<usize>) -> PyResult<PyScanResult> {
    let off = vec3(offset, "offset")?;
    let t = task(py, rows)?;
    let s = run_scan(py, &m, samples, body, &off, &t)?;
    Ok(PyScanResult::new(py, &s))
}

/// Reaction null space at x: `which` is "angular" or "full".
#[pyfunction]
pub fn analysis_reaction_null_space<'py>(py: Python<'py>, m: PyRef<'_, PyModel>, x: &Bound<'py, PyAny>, which: &str, tolerance: f64) -> PyResult<PyReactionNullSpace> {
    let which = rns::BaseMotion::from_name(which).or_raise(py)?;
    let x = vec_arg(x, "x")?;
    let r = m.with_data(|model, data| rns::reaction_null_space(model, data, x.as_slice(), which, tolerance)).or_raise(py)?;
    Ok(PyReactionNullSpace::new(py, &r))
}

/// Base motion under prescribed joint motion at the RK4 half steps; returns (K+1)×(7+N).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn analysis_integrate_prescribed<'py>(
    py: Python<'py>,
    m: PyRef<'_, PyModel>,
    x0: &Bound<'py, PyAny>,
    dt: f64,
    q_half: &Bound<'py, PyAny>,
    qd_half: &Bound<'py, PyAny>,
    linear_momentum: &Bound<'py, PyAny>,
    angular_momentum: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let p = vec3(linear_momentum, "linear momentum")?;
    let l = vec3(angular_momentum, "angular momentum")?;
    let x0 = vec_arg(x0, "x0")?;
    let n = m.model.n_dof();
    let (q, _, qc) = matrix_arg(q_half, "prescribed q")?;
    let (qd, _, qdc) = matrix_arg(qd_half, "prescribed qd")?;
    for (what, c) in [("prescribed q (columns)", qc), ("prescribed qd (columns)", qdc)] {
        if c != n {
            return Err(to_py_err(py, SpacearmError::Dimension { what: what.into(), expected: format!("N = {n}"), got: c }));
        }
    }
    let mom = ffk::ConservedMomentum { linear: p, angular_about_origin: l };
    let xs = m.with_data(|model, data| ffk::integrate_prescribed(model, data, x0.as_slice(), dt, &q, &qd, &mom)).or_raise(py)?;
    Ok(row_major(py, &xs, xs.len() / (7 + n), 7 + n))
}

pub(crate) fn strategy(py: Python<'_>, s: &str) -> PyResult<redundancy::Strategy> {
    redundancy::Strategy::from_name(s).or_raise(py)
}

/// The options of the resolved-motion-rate law (`spacearm_core::analysis::redundancy::RmrcOptions`)
/// as one typed, keyword-only object: the task rows of the point twist, the damping law
/// (`threshold` ε and `max_damping` λ_max), the feedback gain (1/s; used by the `RmrcMotion` constructor),
/// the strategy (`"naive"`, `"reactionless"`, `"minimum_disturbance"`) and the null-space
/// gains. Checked when built.
#[pyclass(module = "spacearm._core", name = "RmrcOptions", frozen)]
pub struct PyRmrcOptions {
    pub(crate) inner: redundancy::RmrcOptions,
}

#[pymethods]
impl PyRmrcOptions {
    #[new]
    #[pyo3(signature = (*, rows, threshold, max_damping, gain=0.0, strategy="naive", manipulability_gain=0.0, joint_limit_gain=0.0))]
    #[allow(clippy::too_many_arguments)]
    fn new(py: Python<'_>, rows: Vec<usize>, threshold: f64, max_damping: f64, gain: f64, strategy: &str, manipulability_gain: f64, joint_limit_gain: f64) -> PyResult<Self> {
        Ok(PyRmrcOptions {
            inner: redundancy::RmrcOptions {
                task: task(py, rows)?,
                damping: singularity::DampingLaw::new(threshold, max_damping).or_raise(py)?,
                feedback_gain: gain,
                strategy: self::strategy(py, strategy)?,
                manipulability_gain,
                joint_limit_gain,
            },
        })
    }

    fn __repr__(&self) -> String {
        format!("<spacearm._core.RmrcOptions {:?}>", self.inner)
    }
}

/// One evaluation of the RMRC law: joint rates, σ_min, damping, base angular velocity.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn analysis_rmrc_rates<'py>(
    py: Python<'py>,
    m: PyRef<'_, PyModel>,
    x: &Bound<'py, PyAny>,
    body: usize,
    offset: &Bound<'py, PyAny>,
    desired_twist: &Bound<'py, PyAny>,
    options: PyRef<'_, PyRmrcOptions>,
) -> PyResult<PyRmrcRates> {
    let off = vec3(offset, "offset")?;
    let v: Vector6<f64> = vec6(desired_twist, "desired twist")?;
    let x = vec_arg(x, "x")?;
    let o = &options.inner;
    let r = m.with_data(|model, data| redundancy::rmrc_rates(model, data, x.as_slice(), body, &off, &v, o)).or_raise(py)?;
    Ok(PyRmrcRates::new(py, &r))
}

/// The reach of a point from the state (x, u) after `duration` s: (system CM then, R_max or
/// None, (plane normal, plane point) or None) — `spacearm_core::analysis::reach`.
#[pyfunction]
#[allow(clippy::type_complexity)]
pub fn analysis_reach<'py>(
    py: Python<'py>,
    m: PyRef<'_, PyModel>,
    x: &Bound<'py, PyAny>,
    u: &Bound<'py, PyAny>,
    body: usize,
    offset: &Bound<'py, PyAny>,
    duration: f64,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Option<f64>, Option<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)>)> {
    let off = vec3(offset, "offset")?;
    let x = vec_arg(x, "x")?;
    let u = vec_arg(u, "u")?;
    let r = m.with_data(|model, data| reach::reach(model, data, x.as_slice(), u.as_slice(), body, &off, duration)).or_raise(py)?;
    let plane = r.plane.map(|p| (array1(py, p.normal.as_slice()), array1(py, p.point.as_slice())));
    Ok((array1(py, r.center.as_slice()), r.radius, plane))
}

/// Register the analysis functions on the extension module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    add_to_module!(
        m,
        functions: [analysis_singularity, analysis_detect, analysis_damping, analysis_joint_grid, analysis_scan, analysis_reaction_null_space, analysis_integrate_prescribed, analysis_rmrc_rates, analysis_reach, analysis_cmg_envelope, analysis_cmg_singular_surfaces],
    );
    Ok(())
}

/// The momentum envelope of a CMG cluster (core `analysis::cmg_envelope`): for each direction,
/// the envelope's point `Σ h_i ŝ_i(u)`; `gimbals` the unit gimbal axes, `h` the rotor momenta.
#[pyfunction]
pub fn analysis_cmg_envelope(py: Python<'_>, gimbals: Vec<[f64; 3]>, h: Vec<f64>, directions: Vec<[f64; 3]>) -> PyResult<Vec<[f64; 3]>> {
    if gimbals.len() != h.len() {
        return Err(to_py_err(py, SpacearmError::InvalidArgument(format!("cmg_envelope: {} gimbal axes but {} rotor momenta", gimbals.len(), h.len()))));
    }
    let g: Vec<Vector3<f64>> = gimbals.iter().map(|v| Vector3::from(*v).normalize()).collect();
    let d: Vec<Vector3<f64>> = directions.iter().map(|v| Vector3::from(*v)).collect();
    Ok(spacearm_core::analysis::cmg_envelope::cmg_envelope(&g, &h, &d).iter().map(|p| [p.x, p.y, p.z]).collect())
}

/// The singular surfaces of a CMG cluster (core `analysis::cmg_singular_surface`): the sign
/// patterns used (all `2^(n-1)` when `signs` is None) and, per pattern and direction, the
/// singular momentum and the `n` spin axes (NaN where the direction lies along a gimbal axis).
#[pyfunction]
#[pyo3(signature = (gimbals, h, signs, directions))]
#[allow(clippy::type_complexity)]
pub fn analysis_cmg_singular_surfaces(
    py: Python<'_>,
    gimbals: Vec<[f64; 3]>,
    h: Vec<f64>,
    signs: Option<Vec<Vec<f64>>>,
    directions: Vec<[f64; 3]>,
) -> PyResult<(Vec<Vec<f64>>, Vec<[f64; 3]>, Vec<[f64; 3]>)> {
    use spacearm_core::analysis::cmg_singular_surface::cmg_singular_surfaces;
    let g: Vec<Vector3<f64>> = gimbals.iter().map(|v| Vector3::from(*v)).collect();
    let d: Vec<Vector3<f64>> = directions.iter().map(|v| Vector3::from(*v)).collect();
    let n = g.len();
    let (signs, surfaces) = py.detach(|| cmg_singular_surfaces(&g, &h, signs, &d)).or_raise(py)?;
    let nan = [f64::NAN; 3];
    let (mut points, mut spins) = (Vec::with_capacity(signs.len() * d.len()), Vec::with_capacity(signs.len() * d.len() * n));
    for state in surfaces.iter().flatten() {
        match state {
            Some(st) => {
                points.push([st.momentum.x, st.momentum.y, st.momentum.z]);
                spins.extend(st.spin.iter().map(|s| [s.x, s.y, s.z]));
            }
            None => {
                points.push(nan);
                spins.extend(std::iter::repeat_n(nan, n));
            }
        }
    }
    Ok((signs, points, spins))
}
