//! The results of a run as frozen classes: the recorded arrays (`RunRecords`), the saturation
//! onsets (`RunEvents`), the run's description (`RunMeta`, one `ConservedDrift` per conserved
//! quantity), the three together (`RunResult`: what `simulate` and `Simulator.result` return).
//!
//! Records go to numpy without a second copy: each record `Vec` is handed over as it is
//! (`PyArray1::from_vec` keeps the allocation; the reshape is a view), or converted to float32
//! field by field, freeing each float64 buffer as soon as its float32 copy exists.

use numpy::{PyArray1, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use spacearm_core::sim::result::CONTACT_FORCE_WIDTH;
use spacearm_core::sim::simulate::{SimOptions, SimResult};

/// The quantities a run may record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Record {
    T,
    X,
    U,
    Du,
    Tau,
    TauCmd,
    BaseWrench,
    LinearMomentum,
    AngularMomentumOrigin,
    AngularMomentumCom,
    Energy,
    Com,
    EePosition,
    EeQuat,
    Reference,
    TrackingError,
    LinkTrackingError,
    AttitudeError,
    WheelSpeed,
    SolveTime,
    SolveIterations,
    SolveCost,
    SolveConverged,
    CmgMeasure,
    CmgEnvelopeFraction,
    RCmEci,
    VCmEci,
    GravityWrench,
    ContactCount,
    ContactNormalForce,
    ContactWork,
    ContactForces,
    ContactImpulse,
}

impl Record {
    /// The name the Python `Trajectory` uses, and the attribute of [`PyRunRecords`].
    pub fn name(self) -> &'static str {
        match self {
            Record::T => "t",
            Record::X => "x",
            Record::U => "u",
            Record::Du => "du",
            Record::Tau => "tau",
            Record::TauCmd => "tau_cmd",
            Record::BaseWrench => "base_wrench",
            Record::LinearMomentum => "P",
            Record::AngularMomentumOrigin => "L_origin",
            Record::AngularMomentumCom => "L_com",
            Record::Energy => "energy",
            Record::Com => "com",
            Record::EePosition => "ee_position",
            Record::EeQuat => "ee_quat",
            Record::Reference => "reference",
            Record::TrackingError => "tracking_error",
            Record::LinkTrackingError => "link_tracking_error",
            Record::AttitudeError => "attitude_error",
            Record::WheelSpeed => "wheel_speed",
            Record::SolveTime => "solve_time",
            Record::SolveIterations => "solve_iterations",
            Record::SolveCost => "solve_cost",
            Record::SolveConverged => "solve_converged",
            Record::CmgMeasure => "cmg_measure",
            Record::CmgEnvelopeFraction => "cmg_envelope_fraction",
            Record::RCmEci => "r_cm_eci",
            Record::VCmEci => "v_cm_eci",
            Record::GravityWrench => "gravity_wrench",
            Record::ContactCount => "contact_count",
            Record::ContactNormalForce => "contact_normal_force",
            Record::ContactWork => "contact_work",
            Record::ContactForces => "contact_forces",
            Record::ContactImpulse => "contact_impulse",
        }
    }

    /// The rows of a record of `values` with `width` per row: one per sample (`k`), but for the
    /// ragged `contact_forces` (one per acting contact per sample; its first column says which).
    pub fn rows(self, k: usize, values: &[f64], width: usize) -> usize {
        match self {
            Record::ContactForces => values.len() / width,
            _ => k,
        }
    }

    /// Whether the record stays float64 when the run asks for float32 records: the time does
    /// (float32 cannot tell apart the steps of a long run).
    pub fn stays_float64(self) -> bool {
        // The ECI position of an orbit needs float64 (float32 resolves ~0.5 m at 7000 km).
        matches!(self, Record::T | Record::RCmEci | Record::VCmEci)
    }
}

/// One recorded quantity of a run, row-major with `width` values per sample; `scalar`: one value
/// per sample, returned 1-D.
pub struct Field {
    pub record: Record,
    pub values: Vec<f64>,
    pub width: usize,
    pub scalar: bool,
}

/// Take every recorded quantity out of `res` (leaving its records empty); `t`, `x` and `u` always.
pub fn take_fields(res: &mut SimResult, nx: usize, nu: usize, n: usize) -> Vec<Field> {
    let n_ref = res.reference_width;
    let n_wheels = res.wheel_dofs.len();
    let r = &mut res.records;
    let take = std::mem::take::<Vec<f64>>;
    let f = |record, values, width, scalar| Field { record, values, width, scalar };
    let mut out = vec![
        f(Record::T, take(&mut r.t), 1, true),
        f(Record::X, take(&mut r.x), nx, false),
        f(Record::U, take(&mut r.u), nu, false),
        f(Record::Du, take(&mut r.du), nu, false),
        f(Record::Tau, take(&mut r.tau), n, false),
        f(Record::TauCmd, take(&mut r.tau_cmd), n, false),
        f(Record::BaseWrench, take(&mut r.base_wrench), 6, false),
        f(Record::LinearMomentum, take(&mut r.linear_momentum), 3, false),
        f(Record::AngularMomentumOrigin, take(&mut r.angular_momentum_origin), 3, false),
        f(Record::AngularMomentumCom, take(&mut r.angular_momentum_com), 3, false),
        f(Record::Energy, take(&mut r.energy), 1, true),
        f(Record::Com, take(&mut r.com), 3, false),
    ];
    // The records a run keeps only when it has them, in order: each group (record, values, width,
    // scalar) kept whole when every one of its records is present (taken either way).
    let optional: Vec<Vec<(Record, Option<Vec<f64>>, usize, bool)>> = vec![
        vec![(Record::EePosition, r.ee_position.take(), 3, false), (Record::EeQuat, r.ee_quat.take(), 4, false)],
        vec![(Record::Reference, r.reference.take(), n_ref, false)],
        vec![(Record::TrackingError, r.tracking_error.take(), 1, true)],
        vec![(Record::LinkTrackingError, r.link_tracking_error.take(), 1, true)],
        vec![(Record::AttitudeError, r.attitude_error.take(), 1, true)],
        vec![(Record::WheelSpeed, r.wheel_speed.take(), n_wheels, false)],
        vec![(Record::SolveTime, r.solve_time.take(), 1, true)],
        vec![(Record::SolveIterations, r.solve_iterations.take(), 1, true)],
        vec![(Record::SolveCost, r.solve_cost.take(), 1, true)],
        vec![(Record::SolveConverged, r.solve_converged.take(), 1, true)],
        vec![(Record::CmgMeasure, r.cmg_measure.take(), 1, true), (Record::CmgEnvelopeFraction, r.cmg_envelope_fraction.take(), 1, true)],
        vec![(Record::RCmEci, r.r_cm_eci.take(), 3, false), (Record::VCmEci, r.v_cm_eci.take(), 3, false), (Record::GravityWrench, r.gravity_wrench.take(), 6, false)],
        vec![
            (Record::ContactCount, r.contact_count.take(), 1, true),
            (Record::ContactNormalForce, r.contact_normal_force.take(), 1, true),
            (Record::ContactWork, r.contact_work.take(), 1, true),
        ],
        // Ragged: one row per acting contact per sample, not one per sample ([`Record::rows`]).
        vec![(Record::ContactForces, r.contact_forces.take(), CONTACT_FORCE_WIDTH, false)],
        vec![(Record::ContactImpulse, r.contact_impulse.take(), 3, false)],
    ];
    for group in optional {
        if group.iter().all(|(_, v, _, _)| v.is_some()) {
            out.extend(group.into_iter().filter_map(|(record, v, width, scalar)| v.map(|v| f(record, v, width, scalar))));
        }
    }
    out
}

/// `values` as a numpy array of `shape` (row-major), float32 if asked (except the records that
/// stay float64). No copy for float64.
pub fn to_numpy<'py>(py: Python<'py>, record: Record, values: Vec<f64>, shape: &[usize], float32: bool) -> PyResult<Bound<'py, PyAny>> {
    let array = if float32 && !record.stays_float64() {
        let narrow: Vec<f32> = values.iter().map(|&v| v as f32).collect();
        drop(values);
        PyArray1::from_vec(py, narrow).into_any()
    } else {
        PyArray1::from_vec(py, values).into_any()
    };
    if shape.len() == 1 {
        return Ok(array);
    }
    array.call_method1("reshape", (shape.to_vec(),))
}

type Array = Py<PyUntypedArray>;

/// A shape as Python writes it: `(3,)`, `(51, 13)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", shape.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(", ")),
    }
}

/// The recorded samples of a run: one numpy array per record, one row per sample (`K` samples;
/// a batch of rollouts adds a leading rollout axis, `(B, K, ...)`). float64, or float32 when the
/// run asked for it (`t` stays float64). Every vector is in the inertial frame 𝒥; SI units.
///
/// `t`, `x` and `u` are always there; a record the run did not make is `None`, and `fields`
/// names, in order, those it made; `to_dict` maps each of those names to its array (the arrays
/// themselves, no copy): the data dict of `Trajectory` and `Rollouts`.
#[pyclass(module = "spacearm._core", name = "RunRecords", frozen)]
#[derive(Default)]
pub struct PyRunRecords {
    /// `(K,)` sample times, s (always float64).
    #[pyo3(get)]
    t: Option<Array>,
    /// `(K, 7+N)` configurations `[r0, quat0 (x, y, z, w), q]`: base CM in 𝒥 (m), base attitude, joint coordinates (rad or m).
    #[pyo3(get)]
    x: Option<Array>,
    /// `(K, 6+N)` velocities `[v0, w0, qd]`: base CM velocity and angular velocity in 𝒥 (m/s, rad/s), joint rates.
    #[pyo3(get)]
    u: Option<Array>,
    /// `(K, 6+N)` accelerations `du/dt` (m/s², rad/s²), or None.
    #[pyo3(get)]
    du: Option<Array>,
    /// `(K, N)` applied joint torques (N·m; N for prismatic joints), after the actuator limits, or None.
    #[pyo3(get)]
    tau: Option<Array>,
    /// `(K, N)` joint torques the controller commanded, before the limits (N·m or N), or None.
    #[pyo3(get)]
    tau_cmd: Option<Array>,
    /// `(K, 6)` applied base wrench `[F0, N0]` at the base CM in 𝒥 (N, N·m), or None.
    #[pyo3(get)]
    base_wrench: Option<Array>,
    /// `(K, 3)` linear momentum `P` of the system in 𝒥 (kg·m/s), or None.
    #[pyo3(get, name = "P")]
    linear_momentum: Option<Array>,
    /// `(K, 3)` angular momentum about the origin of 𝒥, in 𝒥 (kg·m²/s), or None.
    #[pyo3(get, name = "L_origin")]
    angular_momentum_origin: Option<Array>,
    /// `(K, 3)` angular momentum about the system CM, in 𝒥 (kg·m²/s), or None.
    #[pyo3(get, name = "L_com")]
    angular_momentum_com: Option<Array>,
    /// `(K,)` kinetic energy (J), or None.
    #[pyo3(get)]
    energy: Option<Array>,
    /// `(K, 3)` system CM position in 𝒥 (m), or None.
    #[pyo3(get)]
    com: Option<Array>,
    /// `(K, 3)` end-effector position in 𝒥 (m); None if the robot has no end effector.
    #[pyo3(get)]
    ee_position: Option<Array>,
    /// `(K, 4)` end-effector attitude, quaternion `[x, y, z, w]` (body to 𝒥); None if the robot has no end effector.
    #[pyo3(get)]
    ee_quat: Option<Array>,
    /// `(K, R)` the controller's reference (its own layout and units); None if it has none.
    #[pyo3(get)]
    reference: Option<Array>,
    /// `(K,)` `|reference − actual|` (rad or m: `RunMeta.tracking_error_kind`); None if the controller tracks nothing.
    #[pyo3(get)]
    tracking_error: Option<Array>,
    /// `(K,)` with compliant joints under a joint-space controller: `|q_ref − (θ + δ)|`, the links'
    /// error (motor angle plus deflection; `tracking_error` is the motors'); None otherwise.
    #[pyo3(get)]
    link_tracking_error: Option<Array>,
    /// `(K,)` base attitude error angle (rad) of an attitude controller; None otherwise.
    #[pyo3(get)]
    attitude_error: Option<Array>,
    /// `(K, W)` reaction-wheel speeds (rad/s), one column per wheel of `RunMeta.wheel_dofs`; None without wheels.
    #[pyo3(get)]
    wheel_speed: Option<Array>,
    /// `(K,)` an optimizing law's (`spacearm.control.MPC`) wall-clock time of the solve that gave the held command, s; None otherwise.
    #[pyo3(get)]
    solve_time: Option<Array>,
    /// `(K,)` that solve's iterations; None otherwise.
    #[pyo3(get)]
    solve_iterations: Option<Array>,
    /// `(K,)` that solve's optimal cost; None otherwise.
    #[pyo3(get)]
    solve_cost: Option<Array>,
    /// `(K,)` 1 if that solve converged, 0 if it stopped at a limit; None otherwise.
    #[pyo3(get)]
    solve_converged: Option<Array>,
    /// `(K,)` with CMGs on the base: the cluster's singularity measure `det(A Aᵀ)/h̄⁶`; None otherwise.
    #[pyo3(get)]
    cmg_measure: Option<Array>,
    /// `(K,)` with CMGs on the base: the fraction of the momentum envelope used, `|H|/σ(Ĥ)`; None otherwise.
    #[pyo3(get)]
    cmg_envelope_fraction: Option<Array>,
    /// `(K, 3)` an orbital run's system CM in ECI (m, always float64), or None.
    #[pyo3(get)]
    r_cm_eci: Option<Array>,
    /// `(K, 3)` an orbital run's system CM velocity in ECI (m/s, always float64), or None.
    #[pyo3(get)]
    v_cm_eci: Option<Array>,
    /// `(K, 6)` an orbital run's total tidal wrench `[force; torque about the origin]` in 𝒥 (N, N·m), or None.
    #[pyo3(get)]
    gravity_wrench: Option<Array>,
    /// `(K,)` with contact: the number of contacts in interpenetration, or None.
    #[pyo3(get)]
    contact_count: Option<Array>,
    /// `(K,)` with contact: the sum of the contacts' normal forces, N, or None.
    #[pyo3(get)]
    contact_normal_force: Option<Array>,
    /// `(K,)` with contact: the work of the contact forces on the system since t = 0 (their
    /// power integrated with the motion), J, or None.
    #[pyo3(get)]
    contact_work: Option<Array>,
    /// `(R, 13)` with contact: one row per contact that exerts a force at a sample,
    /// `[k, body_a, body_b, point (3), normal (3), f_n, force on body_b (3)]` (sample index, the
    /// bodies, a free target being body nb; in 𝒥, m and N; body_a feels −force), or None.
    #[pyo3(get)]
    contact_forces: Option<Array>,
    /// `(K, 3)` with rigid contact: the sum since t = 0 of the impulses received by the second
    /// body of each contact point, in 𝒥, N·s, or None.
    #[pyo3(get)]
    contact_impulse: Option<Array>,
    /// The records made, in the order of [`take_fields`].
    made: Vec<Record>,
}

impl PyRunRecords {
    /// The records `arrays` (which record, numpy array), each under its name. Every caller gives
    /// `t`, `x` and `u` ([`take_fields`] always makes them).
    pub fn from_arrays(arrays: Vec<(Record, Bound<'_, PyAny>)>) -> PyResult<Self> {
        let mut r = PyRunRecords::default();
        for (record, array) in arrays {
            let slot = match record {
                Record::T => &mut r.t,
                Record::X => &mut r.x,
                Record::U => &mut r.u,
                Record::Du => &mut r.du,
                Record::Tau => &mut r.tau,
                Record::TauCmd => &mut r.tau_cmd,
                Record::BaseWrench => &mut r.base_wrench,
                Record::LinearMomentum => &mut r.linear_momentum,
                Record::AngularMomentumOrigin => &mut r.angular_momentum_origin,
                Record::AngularMomentumCom => &mut r.angular_momentum_com,
                Record::Energy => &mut r.energy,
                Record::Com => &mut r.com,
                Record::EePosition => &mut r.ee_position,
                Record::EeQuat => &mut r.ee_quat,
                Record::Reference => &mut r.reference,
                Record::TrackingError => &mut r.tracking_error,
                Record::LinkTrackingError => &mut r.link_tracking_error,
                Record::AttitudeError => &mut r.attitude_error,
                Record::WheelSpeed => &mut r.wheel_speed,
                Record::SolveTime => &mut r.solve_time,
                Record::SolveIterations => &mut r.solve_iterations,
                Record::SolveCost => &mut r.solve_cost,
                Record::SolveConverged => &mut r.solve_converged,
                Record::CmgMeasure => &mut r.cmg_measure,
                Record::CmgEnvelopeFraction => &mut r.cmg_envelope_fraction,
                Record::RCmEci => &mut r.r_cm_eci,
                Record::VCmEci => &mut r.v_cm_eci,
                Record::GravityWrench => &mut r.gravity_wrench,
                Record::ContactCount => &mut r.contact_count,
                Record::ContactNormalForce => &mut r.contact_normal_force,
                Record::ContactWork => &mut r.contact_work,
                Record::ContactForces => &mut r.contact_forces,
                Record::ContactImpulse => &mut r.contact_impulse,
            };
            *slot = Some(array.cast_into::<PyUntypedArray>()?.unbind());
            r.made.push(record);
        }
        Ok(r)
    }

    /// One run's records (`(K, ...)` arrays), moved out of `res`.
    pub fn of_run(py: Python<'_>, res: &mut SimResult, float32: bool, (nx, nu, n): (usize, usize, usize)) -> PyResult<Self> {
        let k = res.records.n_samples;
        let mut arrays = Vec::new();
        for field in take_fields(res, nx, nu, n) {
            let rows = field.record.rows(k, &field.values, field.width);
            let shape: Vec<usize> = if field.scalar { vec![rows] } else { vec![rows, field.width] };
            arrays.push((field.record, to_numpy(py, field.record, field.values, &shape, float32)?));
        }
        Self::from_arrays(arrays)
    }
}

#[pymethods]
impl PyRunRecords {
    /// The names of the records made (the attributes that are not None), in a fixed order.
    #[getter]
    fn fields<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, self.made.iter().map(|r| r.name()))
    }

    /// `{name: array}` for every record made, in the order of `fields` (the arrays themselves,
    /// no copy; a new dict at each call).
    fn to_dict<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(slf.py());
        for name in slf.get().made.iter().map(|r| r.name()) {
            d.set_item(name, slf.getattr(name)?)?;
        }
        Ok(d)
    }

    fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
        let mut parts = Vec::new();
        for name in slf.get().made.iter().map(|r| r.name()) {
            let array = slf.getattr(name)?.cast_into::<PyUntypedArray>()?;
            parts.push(format!("{name}: {} {}", shape_text(array.shape()), array.dtype()));
        }
        Ok(format!("RunRecords({})", parts.join(", ")))
    }
}

/// The saturation onsets of a run, in time order (`E` events): the accepted step in which an
/// actuator started saturating.
#[pyclass(module = "spacearm._core", name = "RunEvents", frozen, get_all)]
pub struct PyRunEvents {
    /// `(E,)` float64: start time of the step in which each saturation began, s.
    saturation_t: Py<PyArray1<f64>>,
    /// `(E,)` int64: the actuator, dof `0..N` then the six thruster channels `N..N+6` (named by `RunMeta.actuator_names`).
    saturation_actuator: Py<PyArray1<i64>>,
    /// `(E,)` int64: the limit reached, 0 joint torque, 1 joint speed, 2 thruster.
    saturation_kind: Py<PyArray1<i64>>,
}

impl PyRunEvents {
    pub fn of_run(py: Python<'_>, res: &SimResult) -> Self {
        let ev_t: Vec<f64> = res.events.iter().map(|e| e.t).collect();
        let ev_a: Vec<i64> = res.events.iter().map(|e| e.actuator as i64).collect();
        let ev_k: Vec<i64> = res.events.iter().map(|e| e.kind as i64).collect();
        PyRunEvents {
            saturation_t: PyArray1::from_vec(py, ev_t).unbind(),
            saturation_actuator: PyArray1::from_vec(py, ev_a).unbind(),
            saturation_kind: PyArray1::from_vec(py, ev_k).unbind(),
        }
    }
}

#[pymethods]
impl PyRunEvents {
    /// `{"saturation_t", "saturation_actuator", "saturation_kind"}`: the three arrays under their
    /// record names (no copy; a new dict at each call).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("saturation_t", &self.saturation_t)?;
        d.set_item("saturation_actuator", &self.saturation_actuator)?;
        d.set_item("saturation_kind", &self.saturation_kind)?;
        Ok(d)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!("RunEvents({} saturation onsets)", self.saturation_t.bind(py).len())
    }
}

/// The drift of one quantity the run's mode conserves.
#[pyclass(module = "spacearm._core", name = "ConservedDrift", frozen, get_all)]
pub struct PyConservedDrift {
    /// The quantity, by its record name: `"P"`, `"L_origin"`, `"L_com"` or `"energy"`.
    quantity: String,
    /// Largest deviation from the initial value over the recorded samples, relative to
    /// `max(|initial|, scale)` (dimensionless).
    drift: f64,
    /// The magnitude the drift is measured against when the initial value is smaller: the largest
    /// over the samples of the sum of the bodies' contributions, in the quantity's unit
    /// (kg·m/s, kg·m²/s or J).
    scale: f64,
}

#[pymethods]
impl PyConservedDrift {
    fn __repr__(&self) -> String {
        format!("ConservedDrift(quantity={:?}, drift={:e}, scale={:e})", self.quantity, self.drift, self.scale)
    }
}

/// The description of a run (what `Trajectory.meta` holds, less what Python adds).
#[pyclass(module = "spacearm._core", name = "RunMeta", frozen, get_all)]
pub struct PyRunMeta {
    /// The maneuvering mode (`"floating"`, `"rotation-floating"`, ...).
    mode: &'static str,
    /// `"rk4"` or `"dopri5"`.
    integrator: &'static str,
    /// Step (RK4) or output interval (DOPRI5), s.
    dt: f64,
    /// DOPRI5 relative tolerance.
    rtol: f64,
    /// DOPRI5 absolute tolerance.
    atol: f64,
    /// The name of the controller that ran.
    controller: String,
    /// One entry per quantity the mode conserves, in the mode's order (in an orbital run with the
    /// gravity gradient: per quantity whose balance was checked, see `balance`).
    drift: Vec<Py<PyConservedDrift>>,
    /// Whether `drift` holds balance residuals (an orbital run with the gravity gradient: the
    /// quantities are not conserved) rather than drifts of conserved quantities.
    balance: bool,
    /// Accepted integration steps.
    n_steps: usize,
    /// Rejected steps (DOPRI5 only).
    n_rejected: usize,
    /// Evaluations of the right-hand side (each a forward-dynamics solve).
    n_rhs_evals: usize,
    /// The name of each actuator index of `RunEvents.saturation_actuator`.
    actuator_names: Vec<String>,
    /// The degrees of freedom (indices into q) that are reaction wheels.
    wheel_dofs: Vec<usize>,
    /// What `RunRecords.tracking_error` measures, or None.
    tracking_error_kind: Option<&'static str>,
    /// RK4: every how many steps a sample was kept.
    record_every: usize,
    /// `"float64"` or `"float32"`: the dtype of the records.
    record_dtype: &'static str,
    /// Whether the joints' effort and velocity limits applied.
    joint_limits: bool,
    /// Largest norm of a commanded base-wrench part the mode does not allow (N or N·m; 0 if none).
    dropped_base_wrench_max_norm: f64,
    /// Number of evaluations that commanded such a part (dropped).
    dropped_base_wrench_count: usize,
    /// A point controller (RMRC) at the final sample: `|p_ref − p|` (m), None for other controllers.
    goal_distance: Option<f64>,
    /// ... the smallest singular value of its task Jacobian there.
    goal_sigma_min: Option<f64>,
    /// ... whether it stopped short of an unreachable goal (farther than `GOAL_TOLERANCE` with
    /// its damping active: the arm stretched into a singularity).
    goal_unreachable: Option<bool>,
    /// The stop condition that ended the run: `(index, kind, t, value)`; None: it ran its duration.
    stop: Option<(usize, &'static str, f64, f64)>,
}

impl PyRunMeta {
    pub fn of_run(py: Python<'_>, res: &SimResult, opts: &SimOptions, float32: bool) -> PyResult<Self> {
        // The core makes `drift` and `drift_scales` from one list of conserved quantities, in its
        // order: the two pair up entry by entry.
        let drift = res
            .drift
            .iter()
            .zip(&res.drift_scales)
            .map(|(&(c, drift), &(c_scale, scale))| {
                debug_assert_eq!(c, c_scale);
                Py::new(py, PyConservedDrift { quantity: c.name().to_string(), drift, scale })
            })
            .collect::<PyResult<_>>()?;
        Ok(PyRunMeta {
            mode: opts.mode.name(),
            integrator: opts.integrator.name(),
            dt: opts.dt,
            rtol: opts.rtol,
            atol: opts.atol,
            controller: res.controller.clone(),
            drift,
            balance: res.balance,
            n_steps: res.n_steps,
            n_rejected: res.n_rejected,
            n_rhs_evals: res.n_rhs_evals,
            actuator_names: res.actuator_names.clone(),
            wheel_dofs: res.wheel_dofs.clone(),
            tracking_error_kind: res.tracking.map(|t| t.name()),
            record_every: opts.record_every,
            record_dtype: if float32 { "float32" } else { "float64" },
            joint_limits: opts.joint_limits,
            dropped_base_wrench_max_norm: res.dropped_wrench_max,
            dropped_base_wrench_count: res.dropped_wrench_count,
            goal_distance: res.goal.map(|g| g.distance),
            goal_sigma_min: res.goal.map(|g| g.sigma_min),
            goal_unreachable: res.goal_unreachable(),
            stop: res.stop.map(|s| (s.condition, opts.stop[s.condition].kind(), s.t, s.value)),
        })
    }
}

#[pymethods]
impl PyRunMeta {
    /// The run-description dict of docs/simulation.md (`Trajectory.meta` less `duration` and
    /// `robot`, which the caller adds): plain Python values, a new dict at each call. The drift
    /// entries become `conserved` (the quantities in order), `drift` and `drift_scales` (by
    /// quantity); the dropped base wrench becomes `{"max_norm", "count"}`.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("mode", self.mode)?;
        d.set_item("integrator", self.integrator)?;
        d.set_item("dt", self.dt)?;
        d.set_item("rtol", self.rtol)?;
        d.set_item("atol", self.atol)?;
        d.set_item("controller", &self.controller)?;
        let drift: Vec<&PyConservedDrift> = self.drift.iter().map(|c| c.get()).collect();
        // In an orbital run with the gravity gradient the monitored quantities are not conserved:
        // their drift is the residual of their balance (`SimResult::balance`, docs/orbit.md).
        let names = drift.iter().map(|c| c.quantity.as_str()).collect::<Vec<_>>();
        let none: Vec<&str> = Vec::new();
        d.set_item("conserved", if self.balance { &none } else { &names })?;
        d.set_item("balanced", if self.balance { &names } else { &none })?;
        let (values, scales) = (PyDict::new(py), PyDict::new(py));
        for c in &drift {
            values.set_item(&c.quantity, c.drift)?;
            scales.set_item(&c.quantity, c.scale)?;
        }
        d.set_item("drift", values)?;
        d.set_item("drift_scales", scales)?;
        d.set_item("n_steps", self.n_steps)?;
        d.set_item("n_rejected", self.n_rejected)?;
        d.set_item("n_rhs_evals", self.n_rhs_evals)?;
        d.set_item("actuator_names", &self.actuator_names)?;
        d.set_item("wheel_dofs", &self.wheel_dofs)?;
        d.set_item("tracking_error_kind", self.tracking_error_kind)?;
        d.set_item("record_every", self.record_every)?;
        d.set_item("record_dtype", self.record_dtype)?;
        d.set_item("joint_limits", self.joint_limits)?;
        let dropped = PyDict::new(py);
        dropped.set_item("max_norm", self.dropped_base_wrench_max_norm)?;
        dropped.set_item("count", self.dropped_base_wrench_count)?;
        d.set_item("dropped_base_wrench", dropped)?;
        if let (Some(distance), Some(sigma_min), Some(unreachable)) = (self.goal_distance, self.goal_sigma_min, self.goal_unreachable) {
            let goal = PyDict::new(py);
            goal.set_item("distance", distance)?;
            goal.set_item("sigma_min", sigma_min)?;
            goal.set_item("unreachable", unreachable)?;
            d.set_item("goal", goal)?;
        }
        match self.stop {
            Some((condition, kind, t, value)) => {
                let stop = PyDict::new(py);
                stop.set_item("condition", condition)?;
                stop.set_item("kind", kind)?;
                stop.set_item("t", t)?;
                stop.set_item("value", value)?;
                d.set_item("stop", stop)?;
            }
            None => d.set_item("stop", py.None())?,
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "RunMeta(mode={:?}, integrator={:?}, controller={:?}, n_steps={}, {} conserved)",
            self.mode,
            self.integrator,
            self.controller,
            self.n_steps,
            self.drift.len()
        )
    }
}

/// One run: its records, saturation onsets and description (what `simulate` and
/// `Simulator.result` return).
#[pyclass(module = "spacearm._core", name = "RunResult", frozen, get_all)]
pub struct PyRunResult {
    /// The recorded samples, `(K, ...)` arrays.
    records: Py<PyRunRecords>,
    /// The saturation onsets.
    events: Py<PyRunEvents>,
    /// The run's description.
    meta: Py<PyRunMeta>,
    /// A run with a free target or topology events: the second system's rows, the ledger and
    /// the events that happened (events_py.rs); None for a run of the robot alone.
    topology: Option<Py<PyDict>>,
}

impl PyRunResult {
    /// One run's result, its records moved out of `res` (no second copy).
    pub fn of_run(py: Python<'_>, mut res: SimResult, opts: &SimOptions, float32: bool, dims: (usize, usize, usize)) -> PyResult<Self> {
        let events = Py::new(py, PyRunEvents::of_run(py, &res))?;
        let meta = Py::new(py, PyRunMeta::of_run(py, &res, opts, float32)?)?;
        let records = Py::new(py, PyRunRecords::of_run(py, &mut res, float32, dims)?)?;
        Ok(PyRunResult { records, events, meta, topology: None })
    }

    /// This result with the rows of its second system (`topology`).
    pub fn with_topology(self, topology: Bound<'_, PyDict>) -> Self {
        PyRunResult { topology: Some(topology.unbind()), ..self }
    }
}

#[pymethods]
impl PyRunResult {
    fn __repr__(&self, py: Python<'_>) -> String {
        let k = self.records.get().t.as_ref().map_or(0, |t| t.bind(py).shape()[0]);
        format!("RunResult({k} samples)")
    }
}

/// The results of `B` rollouts (what `rollout` returns): the records stacked along a leading
/// rollout axis, and each rollout's status, description and saturation onsets.
#[pyclass(module = "spacearm._core", name = "RolloutBatch", frozen, get_all)]
pub struct PyRolloutBatch {
    /// The records, `(B, K, ...)` arrays: row `i` is rollout `i`'s, NaN for a failed rollout.
    /// When every rollout failed, only `t`, `x` and `u` are there.
    pub records: Py<PyRunRecords>,
    /// `(B,)` bool: whether each rollout ran to the end.
    pub ok: Py<PyArray1<bool>>,
    /// The error message of each failed rollout, None for the others.
    pub reason: Vec<Option<String>>,
    /// The `spacearm.errors` class name of each failure (`"SimulationError"`, ...), None for the others.
    pub error_class: Vec<Option<String>>,
    /// Each rollout's description, None for a failed one.
    pub meta: Vec<Option<Py<PyRunMeta>>>,
    /// Each rollout's saturation onsets, None for a failed one.
    pub events: Vec<Option<Py<PyRunEvents>>>,
}

#[pymethods]
impl PyRolloutBatch {
    fn __repr__(&self, py: Python<'_>) -> String {
        let ok = self.reason.iter().filter(|r| r.is_none()).count();
        let k = self.records.get().t.as_ref().map_or(0, |t| t.bind(py).shape().get(1).copied().unwrap_or(0));
        format!("RolloutBatch({} rollouts of {k} samples, {ok} ok)", self.reason.len())
    }
}
