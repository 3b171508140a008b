//! `spacearm._core.run_capture`: the capture mission as one core run
//! (`spacearm_core::sim::capture::run_capture`), its description a `CaptureSpec` read from plain
//! data (as the controller specs are), its result the `CaptureRun` class (the arrays of every
//! phase end to end, the impact, the captured system, the momentum ledger). Wrapped by
//! `spacearm.capture.capture`, whose `CaptureResult` adds the figures and the files.

use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use spacearm_core::sim::capture::{check_capture as core_check_capture, run_capture as core_run_capture, CaptureRun};
use spacearm_core::sim::capture_spec::CaptureSpec;

use crate::contact_py::PyGraspImpulse;
use crate::controller_spec_py::from_data;
use crate::convert::*;
use crate::model_py::PyModel;

result_class! {
    /// A capture mission's records (`spacearm_core::sim::capture::CaptureRun`): every array has one
    /// row per sample `t`, the phases end to end.
    PyCaptureRun as "CaptureRun", fn of(py: Python<'_>, run: CaptureRun, kind: &str) -> PyResult [
        let (nx, nu, n) = run.dims;
        let count = run.t.len();
        let tau = if n == 0 { PyArray2::zeros(py, [count, 0], false).unbind() } else { rows(py, run.tau, n)?.unbind() };
        let approach_end = run.approach_stop.map_or(f64::NAN, |s| s.t);
        let (captured, captured_state, captured_names) = match run.captured {
            Some(c) => (
                Some(Py::new(py, PyModel::new(c.model))?),
                Some((PyArray1::from_vec(py, c.x).unbind(), PyArray1::from_vec(py, c.u).unbind())),
                Some((c.payload, c.gripper)),
            ),
            None => (None, None, None),
        };
        let (mut ew, mut ei, mut rc, mut vc, mut tl) = (None, None, None, None, None);
        let ledger = match run.orbit {
            Some(o) => {
                ew = Some(rows(py, o.external_wrench, 6)?.unbind());
                ei = Some(rows(py, o.external_impulse, 6)?.unbind());
                rc = Some(rows(py, o.r_cm_eci, 3)?.unbind());
                vc = Some(rows(py, o.v_cm_eci, 3)?.unbind());
                tl = Some(rows(py, o.target_lvlh, 6)?.unbind());
                "balance"
            }
            None => "conservation",
        };
    ] {
        /// (T,) sample times, s.
        t: Py<PyArray1<f64>> = PyArray1::from_vec(py, run.t).unbind(),
        /// (T,) phase index (0 approach, 1 capture, 2 post-capture, 3 detumble).
        phase: Py<PyArray1<i64>> = PyArray1::from_vec(py, run.phase).unbind(),
        /// (T, 7+N) robot configurations.
        x: Py<PyArray2<f64>> = rows(py, run.x, nx)?.unbind(),
        /// (T, 6+N) robot velocities.
        u: Py<PyArray2<f64>> = rows(py, run.u, nu)?.unbind(),
        /// (T, N) joint torques applied.
        tau: Py<PyArray2<f64>> = tau,
        /// (T, 6) base wrench applied.
        base_wrench: Py<PyArray2<f64>> = rows(py, run.base_wrench, 6)?.unbind(),
        /// (T, 13) target states.
        target: Py<PyArray2<f64>> = rows(py, run.target, 13)?.unbind(),
        /// (T, 3) robot + target linear momentum.
        #[pyo3(name = "P")]
        p: Py<PyArray2<f64>> = rows(py, run.ledger.p, 3)?.unbind(),
        /// (T, 3) robot + target angular momentum about the origin.
        #[pyo3(name = "L")]
        l: Py<PyArray2<f64>> = rows(py, run.ledger.l, 3)?.unbind(),
        /// (T, 6) the wrench holding the target (moment about its CM).
        grasp_wrench: Py<PyArray2<f64>> = rows(py, run.grasp_wrench, 6)?.unbind(),
        /// The grasp impact (soft: the lock after the impedance phase).
        impact: Py<PyGraspImpulse> = Py::new(py, PyGraspImpulse::of(py, if kind == "point" { "point" } else { "rigid" }, &run.impact, &run.impact_target_x))?,
        /// The combined model (None for a point contact).
        captured: Option<Py<PyModel>> = captured,
        /// The combined system's state at the grasp, `(x, u)` (None for a point contact).
        captured_state: Option<(Py<PyArray1<f64>>, Py<PyArray1<f64>>)> = captured_state,
        /// The target's link name and the body it rides on (None for a point contact).
        captured_names: Option<(String, String)> = captured_names,
        /// s after the detumble phase starts (inf: never).
        time_to_detumble: f64 = run.time_to_detumble,
        /// |ω0| at the end, rad/s.
        residual_spin: f64 = run.residual_spin,
        /// Relative drift of P.
        drift_p: f64 = run.ledger.drift_p,
        /// Relative drift of L.
        drift_l: f64 = run.ledger.drift_l,
        /// The scales of the drifts, (P, L).
        drift_scales: (f64, f64) = (run.ledger.scale_p, run.ledger.scale_l),
        /// When the approach ended (the grasp event), s.
        approach_end: f64 = approach_end,
        /// `"conservation"` (empty space: the drifts are the momenta's changes) or `"balance"` (in
        /// orbit: the residuals of change = integral of the external wrenches).
        ledger: &'static str = ledger,
        /// In orbit: (T, 6) the external wrench about the origin (tidal + thrusters); else None.
        external_wrench: Option<Py<PyArray2<f64>>> = ew,
        /// In orbit: (T, 6) its trapezoid integral from 0.
        external_impulse: Option<Py<PyArray2<f64>>> = ei,
        /// In orbit: (T, 3) the chaser's system CM in ECI.
        r_cm_eci: Option<Py<PyArray2<f64>>> = rc,
        /// In orbit: (T, 3) its velocity in ECI.
        v_cm_eci: Option<Py<PyArray2<f64>>> = vc,
        /// In orbit: (T, 6) the target's CM relative to the robot's own CM in the robot's LVLH.
        target_lvlh: Option<Py<PyArray2<f64>>> = tl,
    }
}

#[pymethods]
impl PyCaptureRun {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("<spacearm._core.CaptureRun {} samples, drift P {:e}, L {:e}>", self.t.bind(py).len().unwrap_or(0), self.drift_p, self.drift_l)
    }
}

/// Every check of the capture mission `spec` (the data of a `CaptureSpec`) of `target` by
/// `model` from `(x0, u0)` before anything runs (`spacearm_core::sim::capture::check_capture`).
#[pyfunction]
#[pyo3(signature = (model, x0, u0, target, spec))]
pub fn check_capture(py: Python<'_>, model: PyRef<'_, PyModel>, x0: &Bound<'_, PyAny>, u0: &Bound<'_, PyAny>, target: PyRef<'_, PyModel>, spec: &Bound<'_, PyAny>) -> PyResult<()> {
    let spec: CaptureSpec = from_data(spec, "capture")?;
    let (x0, u0) = (vec_arg(x0, "x0")?, vec_arg(u0, "u0")?);
    core_check_capture(&model.model, x0.as_slice(), u0.as_slice(), &target.model, &spec).map(drop).or_raise(py)
}

/// Run the capture mission `spec` (the data of a `CaptureSpec`) of the rigid `target` model by
/// `model` from `(x0, u0)`, without the GIL (Ctrl-C checked between steps).
#[pyfunction]
#[pyo3(signature = (model, x0, u0, target, spec))]
pub fn run_capture(py: Python<'_>, model: PyRef<'_, PyModel>, x0: &Bound<'_, PyAny>, u0: &Bound<'_, PyAny>, target: PyRef<'_, PyModel>, spec: &Bound<'_, PyAny>) -> PyResult<PyCaptureRun> {
    let spec: CaptureSpec = from_data(spec, "capture")?;
    let x0 = owned_vec(x0, "x0")?;
    let u0 = owned_vec(u0, "u0")?;
    // Copies of the models: the run holds no borrow of the Python objects.
    let (rm, tm) = (model.model.clone(), target.model.clone());
    let (result, interrupted) = crate::interrupt::run_reporting(py, None, |progress| core_run_capture(&rm, &x0, &u0, &tm, &spec, progress));
    let run = result.map_err(|e| interrupted.unwrap_or_else(|| to_py_err(py, e)))?;
    PyCaptureRun::of(py, run, &spec.kind)
}

/// Add the capture mission to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    add_to_module!(m, functions: [run_capture, check_capture], classes: [PyCaptureRun],);
    m.add("MAX_CAPTURE_SAMPLES", spacearm_core::sim::capture_spec::MAX_CAPTURE_SAMPLES as u64)?;
    m.add("MAX_TURN_PER_SAMPLE", spacearm_core::sim::capture_spec::MAX_TURN_PER_SAMPLE)?;
    m.add("CAPTURE_KINDS", spacearm_core::sim::capture_spec::CAPTURE_KINDS.to_vec())?;
    Ok(())
}
