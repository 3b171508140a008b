//! The typed results of the analysis bindings (`analysis_py.rs`): one frozen class per result
//! type of `spacearm_core::analysis`, with the same name and fields, so the schema of what
//! crosses the boundary is written here and in `_core.pyi`, not in dictionary keys. They are
//! the public types too: `spacearm.analysis` returns them as they are (no Python copy of their
//! fields); `spacearm.analysis.Motion` subclasses `RmrcMotion` to add the figure only.
//!
//! Each class only carries what the core computed: the arrays are built once, when the result
//! is converted, and every read of an attribute hands out that same numpy array (no copy).
//! Frames and units follow docs/conventions.md: vectors in the inertial frame 𝒥 unless the
//! name says otherwise; a task Jacobian's rows are the task rows of the point twist `[v; ω]`
//! (m/s, rad/s) and its columns the joint rates (rad/s, or m/s for a prismatic joint).

use nalgebra::{DMatrix, Vector3};
use numpy::{Element, PyArray, PyArray1, PyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use spacearm_core::analysis::{reaction_null_space as rns, redundancy, scan, singularity, workspace};

use spacearm_core::SpacearmError;

use crate::convert::{array1, dmat, dvec, matrix_arg, result_class, summary, to_py_err, vec3, vec_arg, OrRaise};

/// A numpy array's shape as Python writes it: `(3, 6)`, `(3,)`.
fn shape_of<T: Element, D: numpy::ndarray::Dimension>(py: Python<'_>, a: &Py<PyArray<T, D>>) -> String {
    let s = a.bind(py).shape().iter().map(|n| n.to_string()).collect::<Vec<_>>();
    if s.len() == 1 {
        format!("({},)", s[0])
    } else {
        format!("({})", s.join(", "))
    }
}

/// A row-major `rows × cols` buffer of the core as a numpy array of that shape.
pub(crate) fn row_major<'py>(py: Python<'py>, v: &[f64], rows: usize, cols: usize) -> Bound<'py, PyArray2<f64>> {
    dmat(py, &DMatrix::from_row_slice(rows, cols, v))
}

result_class! {
    repr;
    /// Measures of one task Jacobian (`spacearm_core::analysis::singularity::JacobianMeasures`):
    /// its singular value decomposition and the numbers derived from it.
    PyJacobianMeasures as "JacobianMeasures", fn new(py: Python<'_>, m: &singularity::JacobianMeasures) {
        /// (m, N) float64: the task rows of the Jacobian analysed (rows of the point twist in 𝒥 per
        /// joint rate).
        jacobian: Py<PyArray2<f64>> = dmat(py, &m.jacobian).unbind(),
        /// (min(m, N),) float64: its singular values, decreasing; units of the Jacobian's rows.
        singular_values: Py<PyArray1<f64>> = dvec(py, &m.singular_values).unbind(),
        /// σ_min, the smallest singular value (the last of `singular_values`; NaN when there are none).
        sigma_min: f64 = m.singular_values.iter().next_back().copied().unwrap_or(f64::NAN),
        /// σ_max / σ_min, dimensionless (inf at a singularity).
        condition: f64 = m.condition,
        /// Yoshikawa's manipulability Π σᵢ.
        manipulability: f64 = m.manipulability,
        /// (m, min(m, N)) float64: left singular vectors, unit columns in task space (𝒥); the last
        /// is the worst task direction.
        task_directions: Py<PyArray2<f64>> = dmat(py, &m.task_directions).unbind(),
        /// (N, N) float64: right singular vectors, unit columns in joint space; the columns beyond
        /// the rank span the null space (self-motions).
        joint_directions: Py<PyArray2<f64>> = dmat(py, &m.joint_directions).unbind(),
    }
}

/// `spacearm.analysis.SingularityReport`: J* (free-floating, zero momentum) and J_m (base held
/// fixed) at one configuration (`spacearm_core::analysis::singularity::SingularityAnalysis`,
/// with the task rows analysed).
#[pyclass(module = "spacearm._core", name = "SingularityReport", frozen, get_all)]
pub struct PySingularityReport {
    /// Measures of the task rows of J* (free-floating, zero momentum; paper eq. 110).
    generalized: Py<PyJacobianMeasures>,
    /// Measures of the task rows of J_m (base held fixed; paper eq. 106).
    fixed_base: Py<PyJacobianMeasures>,
    /// The twist rows analysed (0-5 of [v; ω]), a tuple.
    task: Py<PyTuple>,
}

impl PySingularityReport {
    pub fn new(py: Python<'_>, a: &singularity::SingularityAnalysis, rows: &[usize]) -> PyResult<Self> {
        Ok(PySingularityReport {
            generalized: Py::new(py, PyJacobianMeasures::new(py, &a.generalized))?,
            fixed_base: Py::new(py, PyJacobianMeasures::new(py, &a.fixed_base))?,
            task: PyTuple::new(py, rows)?.unbind(),
        })
    }
}

#[pymethods]
impl PySingularityReport {
    fn __repr__(&self, py: Python<'_>) -> String {
        let j = |m: &Py<PyJacobianMeasures>| shape_of(py, &m.get().jacobian);
        format!("<spacearm.analysis.SingularityReport generalized=JacobianMeasures(jacobian={}) fixed_base=JacobianMeasures(jacobian={}) task={}>", j(&self.generalized), j(&self.fixed_base), self.task.bind(py))
    }
}

result_class! {
    repr;
    /// What the singularity detector tells a resolved-motion-rate controller
    /// (`spacearm_core::analysis::singularity::Detection`).
    PyDetection as "Detection", fn of(d: singularity::Detection) {
        /// Smallest singular value of the task rows of J*.
        sigma_min: f64 = d.sigma_min,
        /// Condition number σ_max / σ_min, dimensionless.
        condition: f64 = d.condition,
        /// Recommended damping λ(σ_min) of the damped least-squares inverse (units of σ).
        damping: f64 = d.damping,
        /// σ_min < ε: inside the singular region.
        near_singular: bool = d.near_singular,
    }
}

result_class! {
    /// A joint-space scan of M samples, one entry per sample in each column (the columns of
    /// `spacearm_core::analysis::scan::ScanSample`).
    PyScanResult as "ScanResult", fn new(py: Python<'_>, s: &[scan::ScanSample]) [
        let column = |f: fn(&scan::ScanSample) -> f64| array1(py, &s.iter().map(f).collect::<Vec<f64>>()).unbind();
        let points = |f: fn(&scan::ScanSample) -> Vector3<f64>| {
            let v: Vec<f64> = s.iter().flat_map(|r| f(r).iter().copied().collect::<Vec<_>>()).collect();
            row_major(py, &v, s.len(), 3).unbind()
        };
    ] {
        /// (M,) float64: smallest singular value of the task rows of J*.
        sigma_min_generalized: Py<PyArray1<f64>> = column(|r| r.sigma_min_generalized),
        /// (M,) float64: largest singular value of the task rows of J*.
        sigma_max_generalized: Py<PyArray1<f64>> = column(|r| r.sigma_max_generalized),
        /// (M,) float64: manipulability Π σᵢ of the task rows of J*.
        manipulability_generalized: Py<PyArray1<f64>> = column(|r| r.manipulability_generalized),
        /// (M,) float64: determinant of the task rows of J* when square, else NaN.
        det_generalized: Py<PyArray1<f64>> = column(|r| r.det_generalized),
        /// (M,) float64: smallest singular value of the task rows of J_m (base held fixed).
        sigma_min_fixed: Py<PyArray1<f64>> = column(|r| r.sigma_min_fixed),
        /// (M,) float64: manipulability of the task rows of J_m.
        manipulability_fixed: Py<PyArray1<f64>> = column(|r| r.manipulability_fixed),
        /// (M,) float64: determinant of the task rows of J_m when square, else NaN.
        det_fixed: Py<PyArray1<f64>> = column(|r| r.det_fixed),
        /// (M, 3) float64: the point from the base CM, base frame, m (the fixed-base workspace).
        point_from_base: Py<PyArray2<f64>> = points(|r| r.point_from_base),
        /// (M, 3) float64: the point from the system CM, base frame, m (the free-floating workspace).
        point_from_com: Py<PyArray2<f64>> = points(|r| r.point_from_com),
    }
}

#[pymethods]
impl PyScanResult {
    fn __repr__(&self, py: Python<'_>) -> String {
        // Seven columns of shape (M,) and the two positions (M, 3).
        format!("<spacearm._core.ScanResult samples={} point_from_base={} point_from_com={}>", self.sigma_min_generalized.bind(py).len(), shape_of(py, &self.point_from_base), shape_of(py, &self.point_from_com))
    }
}

result_class! {
    /// Radial description of the workspaces (`spacearm_core::analysis::workspace::WorkspaceShells`).
    /// Constructing one computes the shells of a scan (`analysis_py::shells`);
    /// `spacearm.analysis.Workspace` is its Python subclass (the samples, timing and figure).
    PyWorkspaceShells as "WorkspaceShells" (subclass), fn of(py: Python<'_>, w: &workspace::WorkspaceShells) [
        let pairs = |v: &[[f64; 2]]| v.iter().map(|[a, b]| (*a, *b)).collect();
    ] {
        /// (R_min, R_max) of the free-floating reachable workspace about the system CM, m.
        reachable: (f64, f64) = (w.reachable[0], w.reachable[1]),
        /// (min, max) distance of the point from the base CM with the base held fixed, m.
        fixed_base: (f64, f64) = (w.fixed_base[0], w.fixed_base[1]),
        /// (K,) float64: barycentric radii of the singular samples and crossings found, sorted, m.
        singular_radii: Py<PyArray1<f64>> = array1(py, &w.singular_radii).unbind(),
        /// Path-dependent shells [(a, b), ...], m.
        path_dependent: Vec<(f64, f64)> = pairs(&w.path_dependent),
        /// Path-independent shells [(a, b), ...]: the reachable shell minus the path-dependent ones, m.
        path_independent: Vec<(f64, f64)> = pairs(&w.path_independent),
        /// The radial resolution that merged the singular radii into shells, m.
        radial_resolution: f64 = w.radial_resolution,
    }
}

#[pymethods]
impl PyWorkspaceShells {
    /// The shells of a scan of M samples: `sigma_min_generalized` and `det_generalized` (M,),
    /// `point_from_com` and `point_from_base` (M, 3); a sample is singular below
    /// `singular_threshold` (or, on a grid `(resolution, n_joints)` with a square task, at a sign
    /// change of det between neighbours); singular radii closer than `radial_resolution` merge.
    #[new]
    #[pyo3(signature = (sigma_min_generalized, det_generalized, point_from_com, point_from_base, singular_threshold, radial_resolution, grid=None))]
    #[allow(clippy::too_many_arguments)]
    fn new<'py>(
        py: Python<'py>,
        sigma_min_generalized: Vec<f64>,
        det_generalized: Vec<f64>,
        point_from_com: &Bound<'py, PyAny>,
        point_from_base: &Bound<'py, PyAny>,
        singular_threshold: f64,
        radial_resolution: f64,
        grid: Option<(usize, usize)>,
    ) -> PyResult<Self> {
        let (com, m1, c1) = matrix_arg(point_from_com, "point_from_com")?;
        let (base, m2, c2) = matrix_arg(point_from_base, "point_from_base")?;
        let m = sigma_min_generalized.len();
        if det_generalized.len() != m || m1 != m || m2 != m || c1 != 3 || c2 != 3 {
            return Err(to_py_err(py, SpacearmError::Dimension { what: "scan arrays".into(), expected: format!("{m} samples (positions M×3)"), got: det_generalized.len() }));
        }
        let samples: Vec<scan::ScanSample> = (0..m)
            .map(|i| scan::ScanSample {
                sigma_min_generalized: sigma_min_generalized[i],
                sigma_max_generalized: f64::NAN,
                manipulability_generalized: f64::NAN,
                det_generalized: det_generalized[i],
                sigma_min_fixed: f64::NAN,
                manipulability_fixed: f64::NAN,
                det_fixed: f64::NAN,
                point_from_base: Vector3::new(base[3 * i], base[3 * i + 1], base[3 * i + 2]),
                point_from_com: Vector3::new(com[3 * i], com[3 * i + 1], com[3 * i + 2]),
            })
            .collect();
        let grid = grid.map(|(resolution, n_joints)| workspace::GridShape { resolution, n_joints });
        let w = workspace::workspace_shells(&samples, singular_threshold, radial_resolution, grid).or_raise(py)?;
        Ok(Self::of(py, &w))
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "<spacearm._core.WorkspaceShells reachable={:?} fixed_base={:?} singular_radii={} path_dependent={} shells path_independent={} shells radial_resolution={:?}>",
            self.reachable,
            self.fixed_base,
            shape_of(py, &self.singular_radii),
            self.path_dependent.len(),
            self.path_independent.len(),
            self.radial_resolution
        )
    }
}

result_class! {
    repr;
    /// The reaction null space at one configuration
    /// (`spacearm_core::analysis::reaction_null_space::ReactionNullSpace`).
    PyReactionNullSpace as "ReactionNullSpace", fn new(py: Python<'_>, r: &rns::ReactionNullSpace) {
        /// (3, N) or (6, N) float64: rows of −H0⁻¹ H0m (zero momentum), joint rates → base angular
        /// velocity ω0 (rad/s) or base twist [v0; ω0] (m/s, rad/s), in 𝒥.
        base_motion_map: Py<PyArray2<f64>> = dmat(py, &r.base_motion_map).unbind(),
        /// (min(rows, N),) float64: singular values of the map, decreasing.
        singular_values: Py<PyArray1<f64>> = dvec(py, &r.singular_values).unbind(),
        /// Numerical rank of the map (singular values above tolerance · σ_max).
        rank: usize = r.rank,
        /// (N, N − rank) float64: orthonormal basis of the null space, in joint space.
        basis: Py<PyArray2<f64>> = dmat(py, &r.basis).unbind(),
        /// Dimension of the null space, N − rank (the columns of `basis`).
        dimension: usize = r.basis.ncols(),
        /// (N, N) float64: orthogonal projector onto the null space.
        projector: Py<PyArray2<f64>> = dmat(py, &r.projector).unbind(),
    }
}

result_class! {
    repr;
    /// One evaluation of the resolved-motion-rate law (`spacearm_core::analysis::redundancy::RmrcRates`).
    PyRmrcRates as "RmrcRates", fn new(py: Python<'_>, r: &redundancy::RmrcRates) {
        /// (N,) float64: joint rates q̇, rad/s (m/s for a prismatic joint).
        qd: Py<PyArray1<f64>> = dvec(py, &r.qd).unbind(),
        /// σ_min of the (projected) task Jacobian.
        sigma_min: f64 = r.sigma_min,
        /// Damping λ of the damped least-squares inverse used (units of σ).
        damping: f64 = r.damping,
        /// (3,) float64: base angular velocity ω0 these rates produce (zero momentum), rad/s, in 𝒥.
        base_angular_velocity: Py<PyArray1<f64>> = array1(py, r.base_angular_velocity.as_slice()).unbind(),
    }
}

result_class! {
    /// A closed-loop point-to-point motion of a free-floating system (zero momentum), recorded at
    /// its K+1 time nodes (`spacearm_core::analysis::redundancy::RmrcMotion`, with the model's name,
    /// the strategy and the target). Constructing one runs the motion (`analysis_py::move_to`);
    /// `spacearm.analysis.Motion` is its Python subclass, which adds the figure and nothing else.
    PyRmrcMotion as "RmrcMotion" (subclass), fn of(py: Python<'_>, r: &redundancy::RmrcMotion, n_dof: usize, robot_name: String, strategy: &'static str, target: &Vector3<f64>) [
        let k = r.times.len();
    ] {
        /// Name of the model moved.
        robot_name: String = robot_name,
        /// The strategy: "naive", "reactionless" or "minimum_disturbance".
        strategy: &'static str = strategy,
        /// (3,) float64: the point's target in 𝒥, m.
        target: Py<PyArray1<f64>> = array1(py, target.as_slice()).unbind(),
        /// (K+1,) float64: times k·dt, s.
        times: Py<PyArray1<f64>> = array1(py, &r.times).unbind(),
        /// (K+1, 7+N) float64: configurations [r0, quat [x, y, z, w], q].
        x: Py<PyArray2<f64>> = row_major(py, &r.x, k, 7 + n_dof).unbind(),
        /// (K+1, N) float64: joint rates, rad/s (m/s for a prismatic joint).
        qd: Py<PyArray2<f64>> = row_major(py, &r.qd, k, n_dof).unbind(),
        /// (K+1, 3) float64: the point's position in 𝒥, m.
        point_position: Py<PyArray2<f64>> = row_major(py, &r.point_position, k, 3).unbind(),
        /// (K+1,) float64: σ_min of the (projected) task Jacobian.
        sigma_min: Py<PyArray1<f64>> = array1(py, &r.sigma_min).unbind(),
        /// (K+1,) float64: damping λ used.
        damping: Py<PyArray1<f64>> = array1(py, &r.damping).unbind(),
        /// (K+1,) float64: base rotation angle from the start, rad.
        attitude_change: Py<PyArray1<f64>> = array1(py, &r.attitude_change).unbind(),
        /// The largest base rotation from the start over the motion (max of `attitude_change`), rad.
        max_attitude_change: f64 = r.attitude_change.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        /// Distance of the point from the target at the end (linear task rows only), m.
        final_position_error: f64 = r.final_position_error,
    }
}

#[pymethods]
impl PyRmrcMotion {
    /// Move a point of `model` to `target` by resolved-motion-rate control (what
    /// `spacearm.analysis.move_to` documents; its arguments, checked, in the same order).
    #[new]
    #[pyo3(signature = (model, x0, body, offset, target, duration, settle, dt, options))]
    #[allow(clippy::too_many_arguments)]
    fn new<'py>(
        py: Python<'py>,
        model: PyRef<'_, crate::model_py::PyModel>,
        x0: &Bound<'py, PyAny>,
        body: usize,
        offset: &Bound<'py, PyAny>,
        target: &Bound<'py, PyAny>,
        duration: f64,
        settle: f64,
        dt: f64,
        options: PyRef<'_, crate::analysis_py::PyRmrcOptions>,
    ) -> PyResult<Self> {
        let off = vec3(offset, "offset")?;
        let target = vec3(target, "target")?;
        let x0 = vec_arg(x0, "x0")?;
        let o = &options.inner;
        let r = model.with_data(|m, data| redundancy::move_to(m, data, x0.as_slice(), body, &off, &target, duration, settle, dt, o)).or_raise(py)?;
        Ok(Self::of(py, &r, model.model.n_dof(), model.model.name().to_string(), o.strategy.name(), &target))
    }

    fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
        summary(slf.as_any(), &["robot_name", "strategy", "times", "x", "qd", "point_position", "sigma_min", "damping", "attitude_change", "final_position_error"])
    }
}
