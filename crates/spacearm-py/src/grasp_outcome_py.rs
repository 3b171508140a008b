//! Binding of the core's grasp outcome (`spacearm_core::sim::grasp_outcome`; docs/contact.md,
//! "The grasp's outcome"): a run's records in, a frozen `GraspOutcome` out
//! (`spacearm.contact.grasp_outcome` is the face users see); the Wilson interval of a success
//! rate (`spacearm_core::math::wilson`) for the campaigns that count grasps.

use pyo3::prelude::*;
use spacearm_core::math::wilson::wilson_interval;
use spacearm_core::sim::grasp_outcome::{grasp_outcome as core_grasp_outcome, GraspOutcome, GraspThresholds};

use crate::convert::*;
use crate::model_py::PyModel;

result_class! {
    /// Whether a gripper held, slipped or missed a target's handle, with the numbers that decided
    /// it (`spacearm_core::sim::grasp_outcome::GraspOutcome`).
    PyGraspOutcome as "GraspOutcome", fn of(o: &GraspOutcome) {
        /// "held", "slipped" or "missed".
        outcome: String = o.verdict.name().to_string(),
        /// Why, in words.
        reason: String = o.reason.clone(),
        /// The final window's largest relative angular speed of handle and palm, rad/s.
        relative_spin: f64 = o.relative_spin,
        /// The final window's largest speed of the handle's origin relative to the grasp centre, m/s.
        relative_speed: f64 = o.relative_speed,
        /// The final window's largest distance of the handle's origin from the grasp centre, m.
        offset: f64 = o.offset,
        /// The fewest fingers on the handle at a sample of the window.
        fingers_touching: usize = o.fingers_touching,
        /// The gripper's finger count.
        fingers: usize = o.fingers,
        /// The first sample time with a finger on the handle, s (None: never).
        first_touch: Option<f64> = o.first_touch,
        /// The samples of the run with a finger on the handle.
        touching_samples: usize = o.touching_samples,
        /// The window's first sample time, s.
        window_start: f64 = o.window_start,
        /// The window's sample count.
        window_samples: usize = o.window_samples,
        /// The thresholds used: window (s), max_relative_spin (rad/s), max_relative_speed (m/s), max_offset (m), touch_margin (m).
        window: f64 = o.thresholds.window,
        max_relative_spin: f64 = o.thresholds.max_relative_spin,
        max_relative_speed: f64 = o.thresholds.max_relative_speed,
        max_offset: f64 = o.thresholds.max_offset,
        touch_margin: f64 = o.thresholds.touch_margin,
    }
}

#[pymethods]
impl PyGraspOutcome {
    /// Whether the grasp held.
    #[getter]
    fn held(&self) -> bool {
        self.outcome == "held"
    }

    fn __repr__(&self) -> String {
        format!(
            "<GraspOutcome {}: relative spin {:.3e} rad/s, relative speed {:.3e} m/s, offset {:.3e} m, {} of {} fingers>",
            self.outcome, self.relative_spin, self.relative_speed, self.offset, self.fingers_touching, self.fingers
        )
    }
}

/// The outcome of the grasp of `target`'s collision geometry `handle` by `robot`'s gripper
/// `gripper` over the records `t` (n,), `x` (n, nx), `u` (n, nu), `target_state` (n, 13).
#[pyfunction]
#[pyo3(signature = (robot, target, gripper, handle, t, x, u, target_state, *, window = 0.5, max_relative_spin = 0.005, max_relative_speed = 0.005, max_offset = 0.005, touch_margin = 0.001))]
#[allow(clippy::too_many_arguments)]
fn grasp_outcome(
    py: Python<'_>,
    robot: PyRef<'_, PyModel>,
    target: PyRef<'_, PyModel>,
    gripper: &str,
    handle: &str,
    t: &Bound<'_, PyAny>,
    x: &Bound<'_, PyAny>,
    u: &Bound<'_, PyAny>,
    target_state: &Bound<'_, PyAny>,
    window: f64,
    max_relative_spin: f64,
    max_relative_speed: f64,
    max_offset: f64,
    touch_margin: f64,
) -> PyResult<PyGraspOutcome> {
    let (r, tm) = (&robot.model, &target.model);
    let t = owned_vec(t, "t")?;
    let (x, _) = rows_arg(x, "x", r.nx())?;
    let (u, _) = rows_arg(u, "u", r.nu())?;
    let (s, _) = rows_arg(target_state, "target_state", 13)?;
    let th = GraspThresholds { window, max_relative_spin, max_relative_speed, max_offset, touch_margin };
    let o = py.detach(|| core_grasp_outcome(r, tm, gripper, handle, &t, &x, &u, &s, &th)).or_raise(py)?;
    Ok(PyGraspOutcome::of(&o))
}

/// `(rate, low, high)`: the success rate `successes / trials` and its Wilson score interval at
/// `z` (default the two-sided 95 % quantile `spacearm_core::math::wilson::Z95`).
#[pyfunction]
#[pyo3(signature = (successes, trials, z = 1.959963984540054))]
fn success_rate(py: Python<'_>, successes: usize, trials: usize, z: f64) -> PyResult<(f64, f64, f64)> {
    let r = wilson_interval(successes, trials, z).or_raise(py)?;
    Ok((r.rate, r.low, r.high))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    add_to_module!(m, functions: [grasp_outcome, success_rate], classes: [PyGraspOutcome],);
    Ok(())
}
