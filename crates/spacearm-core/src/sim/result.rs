//! What a run returns ([`SimResult`]): the recorded samples ([`Records`]), the saturation
//! onsets ([`SaturationEvent`]), the drift of the conserved quantities and the counters; the
//! quantities are defined in the docs of [`crate::sim::simulate`].

use crate::control::TrackingKind;
use crate::scenario::actuators::SaturationKind;
use crate::scenario::modes::Conserved;
use crate::sim::stop::StopEvent;

/// A saturation onset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SaturationEvent {
    /// Start time of the step in which the actuator started saturating, s.
    pub t: f64,
    /// Actuator index: dof `0..N`, then the six thruster channels `N..N+6`.
    pub actuator: usize,
    /// Which limit it reached.
    pub kind: SaturationKind,
}

/// Recorded samples, each field row-major with one row per sample.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Records {
    /// Number of samples (rows).
    pub n_samples: usize,
    /// Sample times, s.
    pub t: Vec<f64>,
    /// Configurations `x = [r0, quat0, q]` (width `7 + N`).
    pub x: Vec<f64>,
    /// Generalized velocities `u = [v0, ω0, q̇]` (width `6 + N`).
    pub u: Vec<f64>,
    /// Generalized accelerations `u̇` (width `6 + N`).
    pub du: Vec<f64>,
    /// Joint torques applied, after the actuator limits (width `N`).
    pub tau: Vec<f64>,
    /// Joint torques commanded by the controller, before the limits (width `N`).
    pub tau_cmd: Vec<f64>,
    /// Base wrench `[F0; N0]` applied, in 𝒥 at the base CM (width 6).
    pub base_wrench: Vec<f64>,
    /// Linear momentum `P`, N·s (width 3).
    pub linear_momentum: Vec<f64>,
    /// Angular momentum about the origin of 𝒥, N·m·s (width 3).
    pub angular_momentum_origin: Vec<f64>,
    /// Angular momentum about the system CM, N·m·s (width 3).
    pub angular_momentum_com: Vec<f64>,
    /// Mechanical energy: kinetic energy plus the joint springs' potential energy, J (width 1).
    pub energy: Vec<f64>,
    /// System CM in 𝒥, m (width 3).
    pub com: Vec<f64>,
    /// End-effector position (if the model has an end effector).
    pub ee_position: Option<Vec<f64>>,
    /// End-effector body orientation `[x, y, z, w]`, sign kept continuous.
    pub ee_quat: Option<Vec<f64>>,
    /// Controller reference (width [`SimResult::reference_width`]).
    pub reference: Option<Vec<f64>>,
    /// The controller's tracking error (see [`SimResult::tracking`]), if it reports one.
    pub tracking_error: Option<Vec<f64>>,
    /// With a joint-space tracking controller on a plant with compliant joints: the error of the
    /// links, `|q_ref − (θ + δ)|` over the same joints, the compliant joints' deflection `δ`
    /// added to their motor angle `θ` ([`crate::model::appendage::compliant_pairs`]; a rigid
    /// joint's link angle is its own); the motor's is [`Self::tracking_error`]. `None` otherwise
    /// (no compliant joint tracked, or a Cartesian controller, whose point already moves with the
    /// links).
    pub link_tracking_error: Option<Vec<f64>>,
    /// The controller's base attitude error angle, rad, if it reports one.
    pub attitude_error: Option<Vec<f64>>,
    /// Wheel rates relative to the base, rad/s.
    pub wheel_speed: Option<Vec<f64>>,
    /// An optimizing law's ([`crate::control::Controller::reports_solve`]) solve that gave the
    /// held command, per sample: wall-clock time, s (it differs from run to run).
    pub solve_time: Option<Vec<f64>>,
    /// Its iterations.
    pub solve_iterations: Option<Vec<f64>>,
    /// Its cost.
    pub solve_cost: Option<Vec<f64>>,
    /// 1 if it converged, 0 if it stopped at a limit.
    pub solve_converged: Option<Vec<f64>>,
    /// A plant with control-moment gyros on its base: the cluster's singularity measure
    /// `m = det(A Aᵀ) / h̄⁶` (control/cmg_jacobian.rs; 0 at a singular state), per sample.
    pub cmg_measure: Option<Vec<f64>>,
    /// A plant with control-moment gyros on its base: the fraction of the momentum envelope the
    /// cluster uses, `|H| / σ(Ĥ)` (analysis/cmg_envelope.rs; 1 at saturation), per sample.
    pub cmg_envelope_fraction: Option<Vec<f64>>,
    /// An orbital run's system CM in ECI, `r_O + r_g`, m (width 3).
    pub r_cm_eci: Option<Vec<f64>>,
    /// An orbital run's system CM velocity in ECI, `v_O + P/M`, m/s (width 3).
    pub v_cm_eci: Option<Vec<f64>>,
    /// An orbital run's total tidal wrench `[Σ fᵢ; Σ (ρᵢ × fᵢ + Nᵢ)]` (the torque about `O`),
    /// N and N·m (width 6; zeros without the gravity gradient).
    pub gravity_wrench: Option<Vec<f64>>,
    /// With contact ([`crate::sim::contact`]): the number of contacts in interpenetration
    /// (rigid contact, [`crate::sim::rigid_contact`]: the points that took a normal impulse in
    /// the last step before the sample) (width 1).
    pub contact_count: Option<Vec<f64>>,
    /// With contact: the sum of their normal forces `Σ f_n`, N (rigid: the last step's
    /// `Σ λ_n / h`, the mean normal force over it) (width 1).
    pub contact_normal_force: Option<Vec<f64>>,
    /// With rigid contact: the sum since `t = 0` of the impulses `Rᵢ λᵢ` received by the second
    /// body of each contact point (the first received the opposite), in 𝒥, N·s (width 3).
    pub contact_impulse: Option<Vec<f64>>,
    /// With contact: the work done on the system by the contact forces since `t = 0`, J: their
    /// power `Σ f · (v₂ − v₁)` integrated by the run's integrator with the motion (one more
    /// entry of the ODE's state; width 1). The energy ledger `energy − contact_work` is then
    /// what is conserved (its drift is the energy's).
    pub contact_work: Option<Vec<f64>>,
    /// With contact: one row per contact that exerts a force at a sample (a ragged record: the
    /// rows of sample `k` are those whose first entry is `k`; their number is its
    /// `contact_count`), `CONTACT_FORCE_WIDTH` = 13 values
    /// `[k, body_a, body_b, p (3), n̂ (3), f_n, f (3)]`: the sample's index, the first and second
    /// body (a free target is body `nb`, one past the robot's), the point where the forces act
    /// and the unit normal from the first body towards the second, in 𝒥, the normal force (N)
    /// and the total force on the second body (normal `f_n n̂` plus friction; N, in 𝒥); the
    /// first body feels `−f` at the same point (docs/contact.md, "Contact dynamics").
    pub contact_forces: Option<Vec<f64>>,
    /// With a free target in the loop ([`crate::sim::free_target`]): its 13-state
    /// `[r, quat xyzw, v, ω]` (width 13).
    pub target_state: Option<Vec<f64>>,
    /// With a free target: robot + target `[P; L_origin]` (width 6), what contact conserves.
    pub ledger_momentum: Option<Vec<f64>>,
    /// With a free target: robot + target mechanical energy, J (width 1); minus
    /// `contact_work` it is conserved.
    pub ledger_energy: Option<Vec<f64>>,
    /// A closed chain's constraint wrench `λ` on frame b at its origin, `[force; torque]` in 𝒥
    /// (width 6; [`crate::sim::closed_chain`]).
    pub constraint_wrench: Option<Vec<f64>>,
    /// A closed chain's pose error `e = [position (m); rotation (rad)]` (width 6).
    pub constraint_error: Option<Vec<f64>>,
}

/// The values per row of [`Records::contact_forces`].
pub const CONTACT_FORCE_WIDTH: usize = 13;

/// Everything a simulation returns.
#[derive(Debug, Clone)]
pub struct SimResult {
    /// The recorded samples.
    pub records: Records,
    /// Number of reference values per sample in [`Records::reference`].
    pub reference_width: usize,
    /// Saturation onsets, in time order.
    pub events: Vec<SaturationEvent>,
    /// Quantities the mode conserves, with their drift.
    pub drift: Vec<(Conserved, f64)>,
    /// The scale each drift was measured against when the initial value is smaller (see the
    /// module docs), so that a recomputation from the records gives the same number.
    pub drift_scales: Vec<(Conserved, f64)>,
    /// `true` in an orbital run with the gravity gradient: the quantities of [`Self::drift`] are
    /// not conserved (the tidal wrenches change them), and each drift is the residual of the
    /// quantity's balance — its change less the time integral of the recorded tidal wrench
    /// (docs/orbit.md); `false`: they are conserved and each drift is their change.
    pub balance: bool,
    /// Accepted integration steps.
    pub n_steps: usize,
    /// Rejected steps (adaptive integrator only).
    pub n_rejected: usize,
    /// Evaluations of the right-hand side (each one forward-dynamics solve).
    pub n_rhs_evals: usize,
    /// Name of each actuator index of [`SaturationEvent::actuator`].
    pub actuator_names: Vec<String>,
    /// Degrees of freedom that are reaction wheels.
    pub wheel_dofs: Vec<usize>,
    /// What [`Records::tracking_error`] measures, if recorded.
    pub tracking: Option<TrackingKind>,
    /// Name of the controller that ran.
    pub controller: String,
    /// Largest norm of a commanded base-wrench part the mode does not allow, and the number of
    /// evaluations in which one was commanded.
    pub dropped_wrench_max: f64,
    /// Number of evaluations that commanded such a part.
    pub dropped_wrench_count: usize,
    /// A point controller's report on its goal at the final sample ([`Controller::goal_report`](crate::control::Controller::goal_report)).
    pub goal: Option<crate::control::GoalReport>,
    /// The stop condition that ended the run ([`SimOptions::stop`](crate::sim::options::SimOptions::stop)); `None`: it ran its duration.
    pub stop: Option<StopEvent>,
}

impl SimResult {
    /// Whether the point controller's goal was out of reach ([`crate::control::GoalReport::unreachable`]),
    /// judged at the natural end of a run only: a run stopped by an event ended before its
    /// goal's time, so its last distance says nothing about reach (`Some(false)`); `None`
    /// without a point controller.
    pub fn goal_unreachable(&self) -> Option<bool> {
        self.goal.map(|g| self.stop.is_none() && g.unreachable())
    }
}
