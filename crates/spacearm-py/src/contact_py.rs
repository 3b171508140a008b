//! Bindings of the core's contact dynamics: `spacearm_core::algorithms::impulse` (impulse
//! dynamics and the two-body grasp impact), the soft-capture plant (`sim::soft_capture`) and the
//! closed chain (`sim::closed_chain`, `algorithms::constrained`, `derivatives::loop_closure_bias`). Arrays in, a typed frozen result out; the Python
//! package `spacearm.capture` is the face users see (docs/capture.md).

use nalgebra::DMatrix;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use spacearm_core::algorithms::impulse::{self, BodyPoint, GraspContact, JointsAtImpact};
use spacearm_core::sim::simulate::{SimOptions, SimResult};
use spacearm_core::{Model, SpacearmError};

use crate::convert::*;
use crate::model_py::PyModel;
use crate::records_py::PyRunResult;
use crate::sim_options_py::PyRunOptions;
use crate::simulate_py::{run_controlled, RunArgs};
use spacearm_core::sim::soft_capture::{self as soft, ImpedanceSpec};
use spacearm_core::algorithms::constrained::LoopClosure;
use spacearm_core::derivatives::{loop_closure_bias, ClosureBiasWork};
use spacearm_core::sim::closed_chain::simulate_closed_chain as core_closed_chain;

result_class! {
    /// The result of `impulse_dynamics` (`spacearm_core::algorithms::impulse::ImpulseDynamics`).
    PyImpulseDynamics as "ImpulseDynamics", fn of(py: Python<'_>, r: &impulse::ImpulseDynamics) {
        /// (6+N,) the generalized velocity after the impact.
        u_after: Py<PyArray1<f64>> = dvec(py, &r.u_after).unbind(),
        /// (6+N,) the jump Δu = H⁻¹ Jᵀ Λ (zero on locked coordinates).
        du: Py<PyArray1<f64>> = dvec(py, &r.du).unbind(),
        /// (m,) the contact impulse Λ.
        impulse: Py<PyArray1<f64>> = dvec(py, &r.impulse).unbind(),
        /// (m, m) the Delassus operator J H⁻¹ Jᵀ over the mobile coordinates.
        delassus: Py<PyArray2<f64>> = dmat(py, &r.delassus).unbind(),
        /// (N,) the impulsive joint torques that hold locked joints (zeros with free joints).
        locking_impulse: Py<PyArray1<f64>> = dvec(py, &r.locking_impulse).unbind(),
    }
}

#[pymethods]
impl PyImpulseDynamics {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("<spacearm._core.ImpulseDynamics impulse={:?}>", self.impulse.bind(py).to_vec().unwrap_or_default())
    }
}

result_class! {
    /// Where an impulse's momentum goes, about the base CM (`[P; L_base]`, eq. 42):
    /// `spacearm_core::algorithms::impulse::MomentumSplit`, the public
    /// `spacearm.capture.MomentumSplit` (`capture.impulse_momentum_split` returns it). Read-only arrays.
    PyMomentumSplit as "MomentumSplit", fn of(py: Python<'_>, s: &impulse::MomentumSplit) [
        let ro = |v: &[f64]| read_only(array1(py, v));
    ] {
        /// (6,) H0 Δẋ0: the momentum the base's own jump carries.
        base: Py<PyArray1<f64>> = ro(s.base.as_slice()),
        /// (6,) H0m Δq̇: the coupling momentum the joints take up.
        arm: Py<PyArray1<f64>> = ro(s.arm.as_slice()),
        /// (6,) J_0Xᵀ Λ: the impulse's momentum about the base CM (base + arm).
        total: Py<PyArray1<f64>> = ro(s.total.as_slice()),
        /// (6, 6) B with Δẋ0 = B Λ: impulses in its null space leave the base still.
        base_jump_map: Py<PyArray2<f64>> = read_only(matrix(py, &s.base_jump_map)),
        /// (6,) the singular values of B, largest first: a zero one means a reaction-null impulse
        /// direction exists.
        base_jump_singular_values: Py<PyArray1<f64>> = ro(s.base_jump_singular_values.as_slice()),
    }
}

#[pymethods]
impl PyMomentumSplit {
    fn __repr__(&self, py: Python<'_>) -> String {
        let norm = |a: &Py<PyArray1<f64>>| a.bind(py).to_vec().unwrap_or_default().iter().map(|v| v * v).sum::<f64>().sqrt();
        format!("<spacearm._core.MomentumSplit |base| {:.4e}, |arm| {:.4e}, |total| {:.4e}>", norm(&self.base), norm(&self.arm), norm(&self.total))
    }
}

/// The inverse inertia G (6×6) at the point `(body, offset)` of `model` at `x`: an impulse
/// [f̂; n̂] there changes the point's twist by G Λ; `arm` "free" (J H⁻¹ Jᵀ) or "locked"
/// (J_0X H0⁻¹ J_0Xᵀ).
#[pyfunction]
#[pyo3(signature = (model, x, body, offset, arm = "free"))]
pub fn point_inverse_inertia<'py>(
    py: Python<'py>,
    model: PyRef<'_, PyModel>,
    x: &Bound<'_, PyAny>,
    body: usize,
    offset: &Bound<'_, PyAny>,
    arm: &str,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let joints = joints(py, arm)?;
    let point = body_point(body, offset, "offset")?;
    let x = vec_arg(x, "x")?;
    let g = model.with_data(|m, d| impulse::point_inverse_inertia(m, d, x.as_slice(), point, joints)).or_raise(py)?;
    Ok(matrix(py, &g))
}

/// Yoshida's virtual mass (kg) at the point `(body, offset)` along `direction` (any non-zero
/// length, in 𝒥): 1 / (nᵀ G_vv n).
#[pyfunction]
#[pyo3(signature = (model, x, body, offset, direction, arm = "free"))]
pub fn virtual_mass(
    py: Python<'_>,
    model: PyRef<'_, PyModel>,
    x: &Bound<'_, PyAny>,
    body: usize,
    offset: &Bound<'_, PyAny>,
    direction: &Bound<'_, PyAny>,
    arm: &str,
) -> PyResult<f64> {
    let joints = joints(py, arm)?;
    let point = body_point(body, offset, "offset")?;
    let n = vec3(direction, "direction")?;
    let x = vec_arg(x, "x")?;
    model.with_data(|m, d| impulse::virtual_mass(m, d, x.as_slice(), point, &n, joints)).or_raise(py)
}

/// How the impulse Λ (6, [f̂; n̂] in 𝒥) at the point `(body, offset)` divides between the base
/// and the arm (joints free).
#[pyfunction]
#[pyo3(signature = (model, x, body, offset, impulse))]
pub fn impulse_momentum_split(
    py: Python<'_>,
    model: PyRef<'_, PyModel>,
    x: &Bound<'_, PyAny>,
    body: usize,
    offset: &Bound<'_, PyAny>,
    impulse: &Bound<'_, PyAny>,
) -> PyResult<PyMomentumSplit> {
    let point = body_point(body, offset, "offset")?;
    let lam = vec6(impulse, "impulse")?;
    let x = vec_arg(x, "x")?;
    let s = model.with_data(|m, d| impulse::impulse_momentum_split(m, d, x.as_slice(), point, &lam)).or_raise(py)?;
    Ok(PyMomentumSplit::of(py, &s))
}

/// The wrench `[f; n]` (𝒥, the moment about the body's CM) that the joint of `body` transmits to
/// the subtree it carries, at each row of `x` (B, 7+N), `u` and `du` (B, 6+N): RNEA's joint force
/// (`spacearm_core::algorithms::rnea::joint_wrench`); for a captured payload, the wrench that
/// holds it on its motion. Returns (B, 6).
#[pyfunction]
#[pyo3(signature = (model, x, u, du, body))]
pub fn joint_wrenches<'py>(
    py: Python<'py>,
    model: PyRef<'_, PyModel>,
    x: &Bound<'py, PyAny>,
    u: &Bound<'py, PyAny>,
    du: &Bound<'py, PyAny>,
    body: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (xs, rows, nx) = matrix_arg(x, "x")?;
    let (us, urows, nu) = matrix_arg(u, "u")?;
    let (dus, durows, ndu) = matrix_arg(du, "du")?;
    if urows != rows || durows != rows {
        return Err(to_py_err(
            py,
            SpacearmError::InvalidArgument(format!("x, u and du must have one row per sample, got {rows}, {urows} and {durows} rows")),
        ));
    }
    let mut out = DMatrix::<f64>::zeros(6, rows);
    model
        .with_data(|m, d| {
            for k in 0..rows {
                let w = spacearm_core::algorithms::rnea::joint_wrench(m, d, &xs[k * nx..(k + 1) * nx], &us[k * nu..(k + 1) * nu], &dus[k * ndu..(k + 1) * ndu], body)?;
                out.column_mut(k).copy_from(&w);
            }
            Ok::<(), SpacearmError>(())
        })
        .or_raise(py)?;
    Ok(matrix(py, &out.transpose()))
}

result_class! {
    /// The result of `grasp_impact` (`spacearm_core::algorithms::impulse::GraspImpact`), every
    /// vector in 𝒥: the public `spacearm.capture.GraspImpulse` (`capture.grasp_impulse` returns it;
    /// no Python copy of its fields). Built once; the arrays are read-only.
    PyGraspImpulse as "GraspImpulse", fn of(py: Python<'_>, kind: &str, g: &impulse::GraspImpact, x_target: &[f64]) [
        let ro1 = |v: &[f64]| read_only(array1(py, v));
        let target_state_after = x_target.iter().chain(g.target_u_after.iter()).copied().collect::<Vec<f64>>();
    ] {
        /// "rigid" or "point".
        kind: String = kind.to_owned(),
        /// (6+N,) the robot's velocity jump [Δv0, Δω0, Δq̇].
        du: Py<PyArray1<f64>> = ro1(g.du.as_slice()),
        /// The target's jump of its model's u: [v; ω] (CM velocity, angular velocity, 6) of a rigid target.
        target_dtwist: Py<PyArray1<f64>> = ro1(g.target_du.as_slice()),
        /// (6,) Λ = [f̂; n̂] on the robot at the grasp point (N·s, N·m·s); the target gets −Λ.
        impulse: Py<PyArray1<f64>> = ro1(g.impulse.as_slice()),
        /// (3,) the grasp point X (the robot's point), m.
        point: Py<PyArray1<f64>> = ro1(g.point.as_slice()),
        /// Distance from X to the target's grasp point, m: zero for a perfect approach.
        gap: f64 = g.gap,
        /// (6+N,) the robot's velocity after the impact.
        u_after: Py<PyArray1<f64>> = ro1(g.u_after.as_slice()),
        /// The target's state after the impact: its x followed by its u after.
        target_state_after: Py<PyArray1<f64>> = ro1(&target_state_after),
        /// (6,) the relative twist at X (gripper minus target) before the impact.
        relative_twist_before: Py<PyArray1<f64>> = ro1(g.relative_twist_before.as_slice()),
        /// (6,) the relative twist at X after the impact.
        relative_twist_after: Py<PyArray1<f64>> = ro1(g.relative_twist_after.as_slice()),
        /// (6, 6) the robot's inverse inertia at X.
        #[pyo3(name = "G_robot")]
        g_robot: Py<PyArray2<f64>> = read_only(matrix(py, &g.g_robot)),
        /// (6, 6) the target's inverse inertia at X.
        #[pyo3(name = "G_target")]
        g_target: Py<PyArray2<f64>> = read_only(matrix(py, &g.g_target)),
        /// Energy the grasp dissipates, −Λᵀ(v_rel⁻ + v_rel⁺)/2, J (>= 0 to rounding; excludes locking_work).
        energy_lost: f64 = g.energy_lost,
        /// Work of the locking joint impulses τ̂ᵀq̇, J (either sign; 0 with the arm free).
        locking_work: f64 = g.locking_work,
        /// The target's velocity after the impact (of its model's u).
        target_u_after: Py<PyArray1<f64>> = ro1(g.target_u_after.as_slice()),
        /// (3,) the unit contact normal of a point contact, or None.
        normal: Option<Py<PyArray1<f64>>> = g.normal.map(|n| ro1(n.as_slice())),
        /// (N,) the locking joint impulses τ̂ (zeros with the arm free).
        locking_impulse: Py<PyArray1<f64>> = ro1(g.locking_impulse.as_slice()),
    }
}

#[pymethods]
impl PyGraspImpulse {
    fn __repr__(&self, py: Python<'_>) -> String {
        let lam = self.impulse.bind(py).to_vec().unwrap_or_default();
        let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
        let (f, n) = if lam.len() == 6 { (norm(&lam[..3]), norm(&lam[3..])) } else { (f64::NAN, f64::NAN) };
        format!(
            "<spacearm._core.GraspImpulse {}: |f̂| {:.4e} N s, |n̂| {:.4e} N m s, energy_lost {:.4e} J, locking_work {:.4e} J, gap {:.3e} m>",
            self.kind, f, n, self.energy_lost, self.locking_work, self.gap
        )
    }
}

fn joints(py: Python<'_>, arm: &str) -> PyResult<JointsAtImpact> {
    JointsAtImpact::from_name(arm).or_raise(py)
}

/// The point `offset` (m, from the CM of `body`, in its axes; finite, named `what`) of a body.
fn body_point(body: usize, offset: &Bound<'_, PyAny>, what: &str) -> PyResult<BodyPoint> {
    Ok(BodyPoint { body, offset: finite3(offset, what)? })
}

/// Impulse dynamics of one model: the velocity after an impact through the contact Jacobian
/// `jacobian` (m × (6+N)) from `u_before`, restitution `e` in [0, 1], `arm` "free" or "locked".
#[pyfunction]
#[pyo3(signature = (model, x, u_before, jacobian, restitution = 0.0, arm = "free"))]
pub fn impulse_dynamics(
    py: Python<'_>,
    model: PyRef<'_, PyModel>,
    x: &Bound<'_, PyAny>,
    u_before: &Bound<'_, PyAny>,
    jacobian: &Bound<'_, PyAny>,
    restitution: f64,
    arm: &str,
) -> PyResult<PyImpulseDynamics> {
    let joints = joints(py, arm)?;
    let (x, u) = (vec_arg(x, "x")?, vec_arg(u_before, "u_before")?);
    let (j, rows, cols) = matrix_arg(jacobian, "jacobian")?;
    let j = DMatrix::from_row_slice(rows, cols, &j);
    let r = model.with_data(|m, d| impulse::impulse_dynamics(m, d, x.as_slice(), u.as_slice(), &j, restitution, joints)).or_raise(py)?;
    Ok(PyImpulseDynamics::of(py, &r))
}

/// Refuse a target grasp point `offset` (m, from the CM of `body`, in its axes) farther from the
/// CM than `MAX_HANDLE_RATIO` times the body's size (`spacearm_core::algorithms::impulse::check_grasp_handle`).
#[pyfunction]
pub fn check_grasp_handle(py: Python<'_>, model: PyRef<'_, PyModel>, body: usize, offset: &Bound<'_, PyAny>) -> PyResult<()> {
    let offset = finite3(offset, "offset")?;
    impulse::check_grasp_handle(&model.model, body, &offset).or_raise(py)
}

/// The grasp impact between the robot's point `(body, offset)` at `(x, u)` and the target
/// model at `(x_target, u_target)`, hit on the body of its grasp point `(target_body,
/// target_offset)` at its material point at the robot's point. `kind` "rigid" or "point"
/// (`normal` in 𝒥, None: from the grasped body's CM to the grasp point), `restitution` in [0, 1],
/// `arm` "free" or "locked"; `capture_tolerance` (m): the largest gap between the grasp points.
#[pyfunction]
#[pyo3(signature = (robot, x, u, body, offset, target, x_target, u_target, target_body, target_offset, *, kind = "rigid",
                    restitution = 0.0, normal = None, arm = "free", capture_tolerance = 0.01))]
#[allow(clippy::too_many_arguments)]
pub fn grasp_impact(
    py: Python<'_>,
    robot: PyRef<'_, PyModel>,
    x: &Bound<'_, PyAny>,
    u: &Bound<'_, PyAny>,
    body: usize,
    offset: &Bound<'_, PyAny>,
    target: PyRef<'_, PyModel>,
    x_target: &Bound<'_, PyAny>,
    u_target: &Bound<'_, PyAny>,
    target_body: usize,
    target_offset: &Bound<'_, PyAny>,
    kind: &str,
    restitution: f64,
    normal: Option<&Bound<'_, PyAny>>,
    arm: &str,
    capture_tolerance: f64,
) -> PyResult<PyGraspImpulse> {
    let joints = joints(py, arm)?;
    // The name first (the core's table), then the normal a point contact takes (a rigid grasp ignores it).
    let contact = match GraspContact::from_name(kind, None).or_raise(py)? {
        GraspContact::Point { .. } => GraspContact::Point { normal: normal.map(|n| finite3(n, "normal")).transpose()? },
        rigid => rigid,
    };
    let robot_point = body_point(body, offset, "offset")?;
    let target_grasp = body_point(target_body, target_offset, "target_offset")?;
    let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
    let (xt, ut) = (vec_arg(x_target, "x_target")?, vec_arg(u_target, "u_target")?);
    let g = robot
        .with_data(|rm, rd| {
            target.with_data(|tm, td| {
                impulse::grasp_impact(
                    rm, rd, x.as_slice(), u.as_slice(), robot_point, tm, td, xt.as_slice(), ut.as_slice(), target_grasp, contact, restitution, joints, capture_tolerance,
                )
            })
        })
        .or_raise(py)?;
    Ok(PyGraspImpulse::of(py, kind, &g, xt.as_slice()))
}

result_class! {
    /// The result of `soft_capture` (`spacearm_core::sim::soft_capture::SoftCaptureResult`).
    PySoftCaptureResult as "SoftCaptureResult", fn of(py: Python<'_>, res: soft::SoftCaptureResult, (rm, tm): (&Model, &Model), opts: &SimOptions, float32: bool) -> PyResult [
        let g = res.gains;
        let target_opts = SimOptions { wheels: Some(Vec::new()), ..opts.clone() };
    ] {
        /// The robot's run (its records, onsets, description).
        robot: Py<PyRunResult> = Py::new(py, PyRunResult::of_run(py, res.robot, opts, float32, (rm.nx(), rm.nu(), rm.n_dof()))?)?,
        /// The target's run (zero torques).
        target: Py<PyRunResult> = Py::new(py, PyRunResult::of_run(py, res.target, &target_opts, float32, (tm.nx(), tm.nu(), tm.n_dof()))?)?,
        /// (K, 6) the impedance's wrench [f; n] on the robot at its grasp point, in the inertial frame.
        wrench: Py<PyArray2<f64>> = rows(py, res.wrench, 6)?.unbind(),
        /// K, N/m.
        stiffness: f64 = g.stiffness,
        /// D, N s/m.
        damping: f64 = g.damping,
        /// K_r, N m/rad.
        rotational_stiffness: f64 = g.rotational_stiffness,
        /// D_r, N m s/rad.
        rotational_damping: f64 = g.rotational_damping,
        /// Drift of robot + target P over the samples (relative, the core's definition).
        drift_linear: f64 = res.drift[0],
        /// Drift of robot + target L about the origin over the samples.
        drift_angular: f64 = res.drift[1],
    }
}

#[pymethods]
impl PySoftCaptureResult {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("<spacearm._core.SoftCaptureResult {} samples, drift P {:e}, L {:e}>", self.wrench.bind(py).shape()[0], self.drift_linear, self.drift_angular)
    }
}

/// The soft capture of the target model (state `(x_target, u_target)`, grasp point
/// `(target_body, target_offset)`) by the robot (state `(x, u)`, grasp point `(body, offset)`,
/// joint law `controller_spec`, None: zero torques) for `duration` s under `options` (floating
/// mode); gains given or from `frequency` and `damping_ratio`.
#[pyfunction]
#[pyo3(signature = (robot, x, u, body, offset, target, x_target, u_target, target_body, target_offset, duration, options,
                    controller_spec = None, *, frequency = 3.0, damping_ratio = 0.7, stiffness = None, damping = None,
                    rotational_stiffness = None, rotational_damping = None))]
#[allow(clippy::too_many_arguments)]
pub fn soft_capture(
    py: Python<'_>,
    robot: PyRef<'_, PyModel>,
    x: &Bound<'_, PyAny>,
    u: &Bound<'_, PyAny>,
    body: usize,
    offset: &Bound<'_, PyAny>,
    target: PyRef<'_, PyModel>,
    x_target: &Bound<'_, PyAny>,
    u_target: &Bound<'_, PyAny>,
    target_body: usize,
    target_offset: &Bound<'_, PyAny>,
    duration: f64,
    options: PyRef<'_, PyRunOptions>,
    controller_spec: Option<&Bound<'_, PyAny>>,
    frequency: f64,
    damping_ratio: f64,
    stiffness: Option<f64>,
    damping: Option<f64>,
    rotational_stiffness: Option<f64>,
    rotational_damping: Option<f64>,
) -> PyResult<PySoftCaptureResult> {
    let robot_point = body_point(body, offset, "offset")?;
    let target_point = body_point(target_body, target_offset, "target_offset")?;
    let x = owned_vec(x, "x")?;
    let u = owned_vec(u, "u")?;
    let xt = owned_vec(x_target, "x_target")?;
    let ut = owned_vec(u_target, "u_target")?;
    let (opts, float32) = (options.sim_options(duration), options.records_float32());
    let spec = ImpedanceSpec { frequency, damping_ratio, stiffness, damping, rotational_stiffness, rotational_damping };
    // Copies of the models: the run holds no borrow of the Python objects.
    let (rm, tm) = (robot.model.clone(), target.model.clone());
    let res = run_controlled(py, &rm, controller_spec, None, |controller, progress| {
        soft::soft_capture(&rm, &x, &u, robot_point, &tm, &xt, &ut, target_point, &spec, &opts, controller, progress)
    })?;
    PySoftCaptureResult::of(py, res, (&rm, &tm), &opts, float32)
}

result_class! {
    /// A closed chain's run (`spacearm_core::sim::closed_chain`).
    PyClosedChainResult as "ClosedChainResult", fn of(py: Python<'_>, mut res: SimResult, m: &Model, opts: &SimOptions, float32: bool) -> PyResult [
        let constraint_wrench = rows(py, res.records.constraint_wrench.take().unwrap_or_default(), 6)?.unbind();
        let pose_error = rows(py, res.records.constraint_error.take().unwrap_or_default(), 6)?.unbind();
    ] {
        /// The run (records, onsets, description).
        run: Py<PyRunResult> = Py::new(py, PyRunResult::of_run(py, res, opts, float32, (m.nx(), m.nu(), m.n_dof()))?)?,
        /// (K, 6) λ: the wrench on frame b at its origin, [force; torque] in the inertial frame (body a gets −λ).
        constraint_wrench: Py<PyArray2<f64>> = constraint_wrench,
        /// (K, 6) e = [position error (m); rotation error (rad)].
        pose_error: Py<PyArray2<f64>> = pose_error,
    }
}

#[pymethods]
impl PyClosedChainResult {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("<spacearm._core.ClosedChainResult {} samples>", self.pose_error.bind(py).shape()[0])
    }
}

result_class! {
    /// The loop-closure terms at one state (`LoopClosure::jacobian`, `derivatives::loop_closure_bias`).
    PyLoopClosureTerms as "LoopClosureTerms", fn of(py: Python<'_>, j: &DMatrix<f64>, jd: &[f64]) {
        /// (6, 6+N) J_c = J_b − J_a at b's origin.
        jacobian: Py<PyArray2<f64>> = dmat(py, j).unbind(),
        /// (6,) the exact J̇_c u.
        jdot_u: Py<PyArray1<f64>> = array1(py, jd).unbind(),
    }
}

/// `J_c` and the exact `J̇_c u` of the loop closing frames a and b at `(x, u)`.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn loop_closure(
    py: Python<'_>,
    model: PyRef<'_, PyModel>,
    x: &Bound<'_, PyAny>,
    u: &Bound<'_, PyAny>,
    body_a: usize,
    offset_a: &Bound<'_, PyAny>,
    body_b: usize,
    offset_b: &Bound<'_, PyAny>,
) -> PyResult<PyLoopClosureTerms> {
    let (a, b) = (body_point(body_a, offset_a, "offset_a")?, body_point(body_b, offset_b, "offset_b")?);
    let (x, u) = (vec_arg(x, "x")?, vec_arg(u, "u")?);
    let (j, jd) = model
        .with_data(|m, d| -> spacearm_core::Result<_> {
            let c = LoopClosure::at(m, d, x.as_slice(), a, b)?;
            let jd = loop_closure_bias(m, &mut ClosureBiasWork::new(m), x.as_slice(), u.as_slice(), &c)?;
            Ok((c.jacobian(m, d), jd))
        })
        .or_raise(py)?;
    Ok(PyLoopClosureTerms::of(py, &j, jd.as_slice()))
}

/// Simulate `model` with the frames at `(body_a, offset_a)` and `(body_b, offset_b)` welded at
/// their relative pose at `x0`, under `controller_spec` (None: zero torques) and `options`;
/// `stabilization`: Baumgarte's rate (1/s).
#[pyfunction]
#[pyo3(signature = (model, x0, u0, duration, body_a, offset_a, body_b, offset_b, options, controller_spec = None, *, stabilization = 20.0))]
#[allow(clippy::too_many_arguments)]
pub fn simulate_closed_chain(
    py: Python<'_>,
    model: PyRef<'_, PyModel>,
    x0: &Bound<'_, PyAny>,
    u0: &Bound<'_, PyAny>,
    duration: f64,
    body_a: usize,
    offset_a: &Bound<'_, PyAny>,
    body_b: usize,
    offset_b: &Bound<'_, PyAny>,
    options: PyRef<'_, PyRunOptions>,
    controller_spec: Option<&Bound<'_, PyAny>>,
    stabilization: f64,
) -> PyResult<PyClosedChainResult> {
    let (a, b) = (body_point(body_a, offset_a, "offset_a")?, body_point(body_b, offset_b, "offset_b")?);
    let run = RunArgs::read(model.model.clone(), x0, u0, duration, &options, py)?;
    let res = run_controlled(py, &run.plant, controller_spec, run.progress_fn.as_ref(), |controller, progress| {
        core_closed_chain(&run.plant, &run.x0, &run.u0, a, b, stabilization, &run.opts, controller, progress)
    })?;
    PyClosedChainResult::of(py, res, &run.plant, &run.opts, run.float32)
}

/// Add the contact functions and classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    add_to_module!(
        m,
        functions: [impulse_dynamics, grasp_impact, point_inverse_inertia, virtual_mass, impulse_momentum_split, joint_wrenches, check_grasp_handle, soft_capture, simulate_closed_chain, loop_closure],
        classes: [PyImpulseDynamics, PyGraspImpulse, PyMomentumSplit, PySoftCaptureResult, PyClosedChainResult, PyLoopClosureTerms],
    );
    Ok(())
}
