//! Impulse dynamics: the velocity jump of an impact (docs/capture.md, "The grasp impact").
//!
//! During an impact the configuration is fixed, the velocities jump and finite forces contribute
//! nothing. An impulse `Λ` (m components) acting through a contact Jacobian `J` (m × (6+N): six
//! rows `[v; ω]` of a welded frame, one row `nᵀ J_v` for a frictionless point) changes the
//! generalized velocity by `Δu = H⁻¹ Jᵀ Λ`, so the contact's velocity `J u` jumps by
//! `G Λ` with the **Delassus operator** (the inverse inertia at the contact)
//! `G = J H⁻¹ Jᵀ` (Yoshida et al. 2004; Pinocchio's `impulseDynamics` solves the same KKT system
//! `[H  Jᵀ; J  0] [u⁺; −Λ] = [H u⁻; −e J u⁻]`). Newton's restitution law `J u⁺ = −e J u⁻` gives
//!
//! `Λ = −(1 + e) G⁻¹ J u⁻`, `u⁺ = u⁻ + H⁻¹ Jᵀ Λ`
//!
//! (`e = 0`: a plastic lock). With the joints **locked** ([`JointsAtImpact::Locked`]) the joint
//! rates are held through the impact, `Δq̇ = 0`: only the base coordinates jump, and `H`, `J` are
//! their blocks `H0`, `J_0` (the joints' rows of `H Δu = Jᵀ Λ + [0; τ̂]` give the impulsive joint
//! torques `τ̂` that do the holding, the *locking impulses*).
//!
//! [`grasp_impact`] is the two-body case: the robot's grasp point `X` against the material point
//! of a target model at `X`, an impulse `Λ` on the robot and `−Λ` on the target. The contact
//! Jacobian over `[u_robot; u_target]` is `[J_r, −J_t]` on a block-diagonal mass matrix, so the
//! Delassus operator is the sum `G_r + G_t` of the two [`contact_response`]s.
//!
//! Imports: [`crate::math`], [`crate::model`] and the algorithms of this folder.

use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Vector3, Vector6};

use crate::algorithms::crba::crba;
pub use crate::algorithms::kinematics::BodyPoint;
use crate::algorithms::kinematics::{check_body, check_velocity, point_jacobians, point_position};
use crate::error::{by_name, check_finite, Result, SpacearmError};
use crate::model::data::Data;
use crate::model::Model;

/// What the joints do during an impact.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointsAtImpact {
    /// The joint rates jump with the base's (all of `u` is mobile).
    Free,
    /// The joint rates are held (`Δq̇ = 0`) by impulsive joint torques: only the base jumps.
    Locked,
}

crate::error::named_by!(JointsAtImpact, "arm", [Free = "free", Locked = "locked"]);

impl JointsAtImpact {
    /// Number of coordinates that may jump in a model with `nu` velocity coordinates.
    fn mobile(self, nu: usize) -> usize {
        match self {
            JointsAtImpact::Free => nu,
            JointsAtImpact::Locked => 6,
        }
    }
}

/// How a model answers impulses through a contact Jacobian `J` (m × (6+N)).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactResponse {
    /// `G = J_m H_m⁻¹ J_mᵀ` (m × m) over the mobile coordinates `m` (all of `u`, or the base's
    /// six with the joints locked): the contact velocity jumps by `G Λ`.
    pub delassus: DMatrix<f64>,
    /// `H_m⁻¹ J_mᵀ` ((6+N) × m; zero rows for locked coordinates): `Δu = response · Λ`.
    pub response: DMatrix<f64>,
    /// The mass matrix `H` at the configuration (full, (6+N)²).
    pub mass_matrix: DMatrix<f64>,
}

fn check_jacobian(model: &Model, jacobian: &DMatrix<f64>) -> Result<()> {
    if jacobian.ncols() != model.nu() {
        return Err(SpacearmError::Dimension { what: "contact Jacobian (columns)".into(), expected: format!("6+N = {}", model.nu()), got: jacobian.ncols() });
    }
    if jacobian.nrows() == 0 {
        return Err(SpacearmError::argument("the contact Jacobian has no rows"));
    }
    check_finite("contact Jacobian", jacobian.as_slice())
}

/// The response of `model` at `x` to impulses through `jacobian` (m × (6+N)): the Delassus
/// operator `G` and the map `Λ ↦ Δu` (module docs). `SingularError` when the mobile block of `H`
/// is not positive definite.
pub fn contact_response(model: &Model, data: &mut Data, x: &[f64], jacobian: &DMatrix<f64>, joints: JointsAtImpact) -> Result<ContactResponse> {
    check_jacobian(model, jacobian)?;
    let h = crba(model, data, x)?.clone();
    response_from(&h, jacobian, joints)
}

fn response_from(h: &DMatrix<f64>, jacobian: &DMatrix<f64>, joints: JointsAtImpact) -> Result<ContactResponse> {
    let nu = h.nrows();
    let k = joints.mobile(nu);
    let hm = h.view((0, 0), (k, k)).into_owned();
    let jm = jacobian.columns(0, k).into_owned();
    let chol = hm.cholesky().ok_or_else(|| SpacearmError::Singular("the mass matrix".into()))?;
    let part = chol.solve(&jm.transpose()); // H_m⁻¹ J_mᵀ (k × m)
    let delassus = &jm * &part;
    let mut response = DMatrix::zeros(nu, jacobian.nrows());
    response.rows_mut(0, k).copy_from(&part);
    Ok(ContactResponse { delassus, response, mass_matrix: h.clone() })
}

/// Solve `G Λ = rhs` (LU with partial pivoting); `SingularError` naming `what` when `G` is.
fn solve_delassus(g: &DMatrix<f64>, rhs: &DVector<f64>, what: &str) -> Result<DVector<f64>> {
    let singular = || SpacearmError::Singular(what.to_string());
    let sol = g.clone().lu().solve(rhs).ok_or_else(singular)?;
    if sol.iter().all(|v| v.is_finite()) {
        Ok(sol)
    } else {
        Err(singular())
    }
}

/// The result of [`impulse_dynamics`].
#[derive(Debug, Clone, PartialEq)]
pub struct ImpulseDynamics {
    /// The generalized velocity after the impact, `u⁺ = u⁻ + Δu`.
    pub u_after: DVector<f64>,
    /// The velocity jump `Δu = H⁻¹ Jᵀ Λ` (zero on locked coordinates).
    pub du: DVector<f64>,
    /// The contact impulse `Λ` (m; the units of `J`'s rows times N·s per m/s).
    pub impulse: DVector<f64>,
    /// The Delassus operator `G = J H⁻¹ Jᵀ` over the mobile coordinates (m × m).
    pub delassus: DMatrix<f64>,
    /// The impulsive joint torques that hold the joints with [`JointsAtImpact::Locked`]: the joint
    /// rows of `H Δu − Jᵀ Λ` (N; zeros with free joints, to rounding).
    pub locking_impulse: DVector<f64>,
}

/// Impulse dynamics of one model (Pinocchio's `impulseDynamics`): the velocity after an impact
/// through the contact Jacobian `jacobian` (m × (6+N)) from `u_before`, with Newton's
/// restitution `e` in [0, 1] (`J u⁺ = −e J u⁻`) and the joints free or locked. An impulse that
/// does not meet that law to within [`GRASP_RESIDUAL_TOLERANCE`] (an ill-conditioned `J H⁻¹ Jᵀ`)
/// is a `Singular` error, an overflow a `NonFinite` one.
pub fn impulse_dynamics(
    model: &Model,
    data: &mut Data,
    x: &[f64],
    u_before: &[f64],
    jacobian: &DMatrix<f64>,
    restitution: f64,
    joints: JointsAtImpact,
) -> Result<ImpulseDynamics> {
    check_velocity(model, "u_before", u_before)?;
    check_restitution(restitution)?;
    let r = contact_response(model, data, x, jacobian, joints)?;
    let u = DVector::from_column_slice(u_before);
    let rhs = -(1.0 + restitution) * (jacobian * &u);
    let impulse = solve_delassus(&r.delassus, &rhs, "the Delassus operator J H⁻¹ Jᵀ (the contact rows are dependent)")?;
    let du = &r.response * &impulse;
    let locking_impulse = (&r.mass_matrix * &du - jacobian.transpose() * &impulse).rows(6, model.n_dof()).into_owned();
    let u_after = &u + &du;
    // The contact law the impulse was solved from, checked as the grasp's is.
    check_rows_law(&r.delassus, &impulse, &(jacobian * &u), &(jacobian * &u_after), restitution)?;
    Ok(ImpulseDynamics { u_after, du, impulse, delassus: r.delassus, locking_impulse })
}

/// The inverse inertia at a point of `model` (docs/capture.md, "The grasp impact"): an impulse
/// `Λ = [f̂; n̂]` (in 𝒥) at the body point `point` changes the point's twist `[v; ω]` by `G Λ`,
/// `G = J_m H_m⁻¹ J_mᵀ` (6×6) with `J = [J_0X, J_mX]` the point's Jacobian (eqs. 104–108) over
/// the coordinates that may jump (all of `u`, or the base's six with the joints locked:
/// `J_0X H0⁻¹ J_0Xᵀ`). The contact response of the point's six rows ([`contact_response`]).
pub fn point_inverse_inertia(model: &Model, data: &mut Data, x: &[f64], point: BodyPoint, joints: JointsAtImpact) -> Result<Matrix6<f64>> {
    Ok(matrix6(&point_response(model, data, x, point, joints)?.1.delassus))
}

/// The point's Jacobian `[J_0X, J_mX]` (6 × (6+N)) at `x` and the model's response through it.
fn point_response(model: &Model, data: &mut Data, x: &[f64], point: BodyPoint, joints: JointsAtImpact) -> Result<(DMatrix<f64>, ContactResponse)> {
    check_body(model, point.body)?;
    check_finite("the point's offset", point.offset.as_slice())?;
    let h = crba(model, data, x)?.clone(); // (runs the forward kinematics the Jacobian needs)
    let j = jacobian_of(model, data, point.body, &point.offset)?;
    let r = response_from(&h, &j, joints)?;
    Ok((j, r))
}

/// Yoshida's virtual mass at `point` along `direction` (kg; Yoshida et al. 2004):
/// `1 / (nᵀ G_vv n)`, `n` the unit `direction` (in 𝒥) and `G_vv` the translational block of
/// [`point_inverse_inertia`]: the mass a collision along `n` at the point feels.
pub fn virtual_mass(model: &Model, data: &mut Data, x: &[f64], point: BodyPoint, direction: &Vector3<f64>, joints: JointsAtImpact) -> Result<f64> {
    let norm = direction.norm();
    if !(norm.is_finite() && norm >= 1e-12) {
        return Err(SpacearmError::argument(format!("direction must be a non-zero finite 3-vector, got {:?}", direction.as_slice())));
    }
    let n = direction / norm;
    let g = point_inverse_inertia(model, data, x, point, joints)?;
    let g_vv: Matrix3<f64> = g.fixed_view::<3, 3>(0, 0).into_owned();
    Ok(1.0 / n.dot(&(g_vv * n)))
}

/// What [`impulse_momentum_split`] returns: where an impulse's momentum goes, about the base CM
/// (`[P; L_base]`, eq. 42), `base + arm == total == J_0Xᵀ Λ`.
#[derive(Debug, Clone, PartialEq)]
pub struct MomentumSplit {
    /// `H0 Δẋ0`: the momentum the base's own jump carries.
    pub base: Vector6<f64>,
    /// `H0m Δq̇`: the coupling momentum the joints take up.
    pub arm: Vector6<f64>,
    /// `J_0Xᵀ Λ`: the impulse's momentum about the base CM.
    pub total: Vector6<f64>,
    /// `B` with `Δẋ0 = B Λ` (the base rows of `H⁻¹ Jᵀ`): impulses in its null space leave the
    /// base still (the reaction null space at impact, Nenchev & Yoshida 1999).
    pub base_jump_map: Matrix6<f64>,
    /// The singular values of `B`, largest first: a zero one means a reaction-null impulse
    /// direction exists.
    pub base_jump_singular_values: Vector6<f64>,
}

/// How the impulse `Λ` (`[f̂; n̂]` in 𝒥) at `point` divides between the base and the arm, the
/// joints free (impedance matching, Yoshida et al. 2004): `Δu = H⁻¹ Jᵀ Λ`, the base's jump
/// `Δẋ0` carries `H0 Δẋ0`, the joints' jump `Δq̇` the coupling momentum `H0m Δq̇`.
pub fn impulse_momentum_split(model: &Model, data: &mut Data, x: &[f64], point: BodyPoint, impulse: &Vector6<f64>) -> Result<MomentumSplit> {
    check_finite("impulse", impulse.as_slice())?;
    let (j, r) = point_response(model, data, x, point, JointsAtImpact::Free)?;
    let lam = DVector::from_column_slice(impulse.as_slice());
    let du = &r.response * &lam;
    let h = &r.mass_matrix;
    let n = model.n_dof();
    let base = h.view((0, 0), (6, 6)) * du.rows(0, 6);
    let arm = h.view((0, 6), (6, n)) * du.rows(6, n);
    let total = j.columns(0, 6).transpose() * &lam;
    let b = Matrix6::from_fn(|i, k| r.response[(i, k)]);
    let mut sv = b.singular_values();
    sv.as_mut_slice().sort_by(|a, c| c.total_cmp(a));
    Ok(MomentumSplit {
        base: Vector6::from_column_slice(base.as_slice()),
        arm: Vector6::from_column_slice(arm.as_slice()),
        total: Vector6::from_column_slice(total.as_slice()),
        base_jump_map: b,
        base_jump_singular_values: sv,
    })
}

fn check_restitution(e: f64) -> Result<()> {
    if !(0.0..=1.0).contains(&e) {
        return Err(SpacearmError::argument(format!("restitution must be in [0, 1], got {e}")));
    }
    Ok(())
}

/// The contact of a grasp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GraspContact {
    /// A 6-D weld of the two frames (six contact rows).
    Rigid,
    /// A frictionless point contact along `normal` (from the target into the robot, in 𝒥; `None`:
    /// from the grasped body's CM to the target's grasp point). One contact row; unilateral: no
    /// impulse when the bodies separate along the normal.
    Point {
        /// Contact normal in 𝒥 (normalized here), or `None` for the default.
        normal: Option<Vector3<f64>>,
    },
}

impl GraspContact {
    /// The names of [`GraspContact::from_name`], the one table every door reads.
    pub const NAMES: [&'static str; 2] = ["rigid", "point"];

    /// The contact called `kind`, `"rigid"` or `"point"` (the latter along `normal`, `None`: the
    /// default normal; a rigid grasp ignores it); any other name is refused naming the table.
    pub fn from_name(kind: &str, normal: Option<Vector3<f64>>) -> Result<Self> {
        by_name("kind", &Self::NAMES, &[GraspContact::Rigid, GraspContact::Point { normal }], kind)
    }
}

/// The result of [`grasp_impact`] (every vector in 𝒥).
#[derive(Debug, Clone, PartialEq)]
pub struct GraspImpact {
    /// `Λ = [f̂; n̂]` on the robot at the grasp point (N·s, N·m·s); the target gets `−Λ`.
    pub impulse: Vector6<f64>,
    /// The robot's velocity jump `Δu`.
    pub du: DVector<f64>,
    /// The target's velocity jump (of its model's `u`).
    pub target_du: DVector<f64>,
    /// The robot's velocity after the impact.
    pub u_after: DVector<f64>,
    /// The target's velocity after the impact.
    pub target_u_after: DVector<f64>,
    /// The grasp point `X` in 𝒥 (the robot's point).
    pub point: Vector3<f64>,
    /// Distance from `X` to the target's grasp point, m.
    pub gap: f64,
    /// The unit contact normal (point contact), or `None` (rigid).
    pub normal: Option<Vector3<f64>>,
    /// Twist of the robot at `X` minus the target's material point's twist at `X`, before.
    pub relative_twist_before: Vector6<f64>,
    /// The same after the impact.
    pub relative_twist_after: Vector6<f64>,
    /// The robot's inverse inertia at `X`, `G_r = J H⁻¹ Jᵀ` (over its mobile coordinates).
    pub g_robot: Matrix6<f64>,
    /// The target's inverse inertia at `X`, `G_t`.
    pub g_target: Matrix6<f64>,
    /// Energy the contact impulses take out, `−Λᵀ (v_rel⁻ + v_rel⁺) / 2` (J, ≥ 0 to rounding).
    pub energy_lost: f64,
    /// Work of the locking joint impulses, `τ̂ᵀ q̇` (J, either sign; 0 with free joints).
    pub locking_work: f64,
    /// The locking joint impulses `τ̂` (N; zeros with free joints).
    pub locking_impulse: DVector<f64>,
}

fn jacobian_of(model: &Model, data: &Data, body: usize, offset: &Vector3<f64>) -> Result<DMatrix<f64>> {
    let (j0, jm) = point_jacobians(model, data, body, offset)?;
    let mut j = DMatrix::zeros(6, model.nu());
    j.view_mut((0, 0), (6, 6)).copy_from(&j0);
    j.view_mut((0, 6), (6, model.n_dof())).copy_from(&jm);
    Ok(j)
}

fn matrix6(m: &DMatrix<f64>) -> Matrix6<f64> {
    Matrix6::from_fn(|i, j| m[(i, j)])
}

/// The farthest a target's grasp point may lie from the CM of the body it is on, in units of
/// that body's size ([`body_size`]): a handle longer than this is no grasp the rigid-lock and
/// impulse models describe (docs/capture.md, "Grasps that are refused").
pub const MAX_HANDLE_RATIO: f64 = 2.0;

/// The size of a body from its mass properties: the half-diagonal of the uniform box with the
/// same mass and principal moments, `√(1.5 tr(I) / m)` m (for a box of sides `a, b, c`,
/// `tr(I) = m (a² + b² + c²) / 6`); a point mass has size 0.
pub fn body_size(model: &Model, body: usize) -> f64 {
    let mp = model.mass_properties(body);
    if mp.mass > 0.0 {
        (1.5 * mp.inertia.trace() / mp.mass).max(0.0).sqrt()
    } else {
        0.0
    }
}

/// Refuse a grasp point `offset` (from the CM of `body`, in its axes) farther from the CM than
/// [`MAX_HANDLE_RATIO`] times the body's size: an `InvalidArgument` naming both lengths.
pub fn check_grasp_handle(model: &Model, body: usize, offset: &Vector3<f64>) -> Result<()> {
    check_body(model, body)?;
    check_finite("the target's grasp offset", offset.as_slice())?;
    let size = body_size(model, body);
    let length = offset.norm();
    if length > MAX_HANDLE_RATIO * size {
        return Err(SpacearmError::argument(format!(
            "the grasp point is {length:.4} m from the CM of body {body} of '{}', more than {MAX_HANDLE_RATIO} × its size \
             {size:.4} m (the half-diagonal of the uniform box of its mass and inertia): no handle that long is a rigid \
             grasp; put the grasp point on the body",
            model.name()
        )));
    }
    Ok(())
}

/// The largest relative residual of the contact law a grasp impact may leave and still be
/// returned (docs/capture.md, "Grasps that are refused"): after the solve, the relative twist on
/// the contact rows must meet Newton's law `J v⁺ = −e J v⁻` to within this fraction of
/// `|J v⁻|` (rigid: all six rows; point: the normal row). Beyond it the system
/// `(G_r + G_t) Λ = −(1 + e) v⁻` was too ill-conditioned for double precision (masses or
/// inertias many orders of magnitude apart) and the impulse is not the impact's.
pub const GRASP_RESIDUAL_TOLERANCE: f64 = 1e-6;

/// The condition number (2-norm) of the symmetric positive semi-definite `g`: the ratio of its
/// largest to its smallest eigenvalue (infinite when the smallest is not positive).
fn spd_condition(g: &DMatrix<f64>) -> f64 {
    let ev = g.clone().symmetric_eigenvalues();
    let (lo, hi) = ev.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &v| (lo.min(v), hi.max(v.abs())));
    if lo > 0.0 {
        hi / lo
    } else {
        f64::INFINITY
    }
}

/// A `NonFinite` error for the first value of `parts` that is not finite (velocities so large
/// that the impact's arithmetic overflows; `v_before` is the contact velocity before).
fn check_impact_finite(parts: &[(&str, &[f64])], v_before: &DVector<f64>) -> Result<()> {
    for (what, values) in parts {
        if let Some(index) = values.iter().position(|v| !v.is_finite()) {
            return Err(SpacearmError::NonFinite {
                what: format!(
                    "{what} (from a contact velocity of norm {:.3e} before the impact: velocities that large overflow the impact's \
                     arithmetic)",
                    v_before.norm()
                ),
                index,
                value: values[index],
            });
        }
    }
    Ok(())
}

/// A `Singular` error naming `system` (`g`, with its condition number) when the solved impulse
/// leaves the `residual` of the contact law against the contact velocity `scale` before the
/// impact, more than [`GRASP_RESIDUAL_TOLERANCE`] of it.
fn check_residual(system: &str, g: &DMatrix<f64>, residual: f64, scale: f64) -> Result<()> {
    if residual > GRASP_RESIDUAL_TOLERANCE * scale {
        return Err(SpacearmError::Singular(format!(
            "{system} (condition number {}): the solved impulse leaves a contact velocity of {residual:.3e} against {scale:.3e} \
             before the impact, more than the {GRASP_RESIDUAL_TOLERANCE:e} allowed (masses or inertias too many orders of \
             magnitude apart for double precision)",
            condition_words(spd_condition(g))
        )));
    }
    Ok(())
}

/// Refuse a grasp impact whose numbers are not finite or whose impulse does not meet the
/// contact law it was solved from (module docs; [`GRASP_RESIDUAL_TOLERANCE`]): rigid, all six
/// rows `v⁺ = −e v⁻`; point, the normal row (nothing to meet when the contact separates).
#[allow(clippy::too_many_arguments)]
fn check_contact_law(
    g: &DMatrix<f64>,
    lam: &DVector<f64>,
    v_before: &DVector<f64>,
    v_after: &DVector<f64>,
    contact: GraspContact,
    normal: Option<&Vector3<f64>>,
    restitution: f64,
    energy_lost: f64,
) -> Result<()> {
    let parts: [(&str, &[f64]); 3] =
        [("the grasp impulse", lam.as_slice()), ("the relative twist after the grasp", v_after.as_slice()), ("the grasp's energy lost", &[energy_lost])];
    check_impact_finite(&parts, v_before)?;
    let (residual, scale) = match (contact, normal) {
        (GraspContact::Point { .. }, Some(n)) => {
            let (vb, va) = (n.dot(&v_before.fixed_rows::<3>(0)), n.dot(&v_after.fixed_rows::<3>(0)));
            if vb >= 0.0 {
                return Ok(());
            }
            ((va + restitution * vb).abs(), vb.abs())
        }
        _ => ((v_after + restitution * v_before).norm(), v_before.norm()),
    };
    check_residual("the grasp's inverse inertia G_robot + G_target", g, residual, scale)
}

/// [`check_contact_law`] for contact rows of any number: every row meets `J u⁺ = −e J u⁻`.
fn check_rows_law(g: &DMatrix<f64>, lam: &DVector<f64>, v_before: &DVector<f64>, v_after: &DVector<f64>, restitution: f64) -> Result<()> {
    check_impact_finite(&[("the contact impulse", lam.as_slice()), ("the contact velocity after the impact", v_after.as_slice())], v_before)?;
    check_residual("the Delassus operator J H⁻¹ Jᵀ", g, (v_after + restitution * v_before).norm(), v_before.norm())
}

/// A condition number for a message: `1.2e17`, or "beyond double precision" when infinite.
fn condition_words(c: f64) -> String {
    if c.is_finite() {
        format!("{c:.2e}")
    } else {
        "beyond double precision".to_string()
    }
}

/// The impact between the robot's grasp point and a target model (module docs): the robot at
/// `(x, u)` grasps at `robot_point`; the target at `(x_target, u_target)` is hit on the body of
/// its grasp point `target_grasp`, at its material point that coincides with the robot's point
/// `X`. `restitution` `e` in [0, 1] (`J v⁺ = −e J v⁻` on the contact rows); `joints`: the
/// robot's joints free or locked (the target's are always free). Refused: a target grasp point
/// beyond [`check_grasp_handle`]'s bound, and grasp points more than `gap_tolerance` (m) apart
/// (the gripper does not touch the handle: no impact). An impulse that does not meet the
/// contact law to within [`GRASP_RESIDUAL_TOLERANCE`] (an ill-conditioned `G_r + G_t`) is a
/// `SingularError`, numbers that overflow a `NonFinite` error: no residual twist, no NaN energy.
///
/// Rigid: `Λ = −(1 + e) (G_r + G_t)⁻¹ v_rel⁻`. Point: `Λ = [λ n; 0]`,
/// `λ = −(1 + e) nᵀv_rel⁻ / (nᵀ (G_r + G_t)_vv n)` when `nᵀv_rel⁻ < 0`, else no impulse.
#[allow(clippy::too_many_arguments)]
pub fn grasp_impact(
    robot: &Model,
    robot_data: &mut Data,
    x: &[f64],
    u: &[f64],
    robot_point: BodyPoint,
    target: &Model,
    target_data: &mut Data,
    x_target: &[f64],
    u_target: &[f64],
    target_grasp: BodyPoint,
    contact: GraspContact,
    restitution: f64,
    joints: JointsAtImpact,
    gap_tolerance: f64,
) -> Result<GraspImpact> {
    check_restitution(restitution)?;
    if !(gap_tolerance >= 0.0) {
        return Err(SpacearmError::argument(format!("the capture tolerance must be >= 0 m, got {gap_tolerance}")));
    }
    check_velocity(robot, "u", u)?;
    check_velocity(target, "the target's u", u_target)?;
    check_body(robot, robot_point.body)?;
    check_body(target, target_grasp.body)?;
    check_finite("the robot's grasp offset", robot_point.offset.as_slice())?;
    check_finite("the target's grasp offset", target_grasp.offset.as_slice())?;

    // The robot's side: H, the point's Jacobian (crba runs forward kinematics).
    let h_r = crba(robot, robot_data, x)?.clone();
    let point = point_position(robot_data, robot_point.body, &robot_point.offset);
    let j_r = jacobian_of(robot, robot_data, robot_point.body, &robot_point.offset)?;
    // The target's side: its material point at X on the grasped body.
    let h_t = crba(target, target_data, x_target)?.clone();
    let tb = target_grasp.body;
    let grasp_world = point_position(target_data, tb, &target_grasp.offset);
    let body_cm = target_data.com_in_world[tb];
    let rot_t: Matrix3<f64> = target_data.body_to_world[tb];
    let t_offset = rot_t.transpose() * (point - body_cm);
    check_grasp_handle(target, tb, &target_grasp.offset)?;
    let gap = (point - grasp_world).norm();
    if gap > gap_tolerance {
        return Err(SpacearmError::argument(format!(
            "the grasp points are {gap:.4} m apart at the impact, more than the capture tolerance {gap_tolerance} m: the \
             gripper does not touch the target's grasp point, so there is no impact to compute"
        )));
    }
    let j_t = jacobian_of(target, target_data, tb, &t_offset)?;

    let resp_r = response_from(&h_r, &j_r, joints)?;
    let resp_t = response_from(&h_t, &j_t, JointsAtImpact::Free)
        .map_err(|_| SpacearmError::Singular("the target's mass matrix".into()))?;
    let u_r = DVector::from_column_slice(u);
    let u_t = DVector::from_column_slice(u_target);
    let v_rel = &j_r * &u_r - &j_t * &u_t;
    let g = &resp_r.delassus + &resp_t.delassus;

    let (lam, normal) = match contact {
        GraspContact::Rigid => {
            let lam = solve_delassus(&g, &(-(1.0 + restitution) * &v_rel), "the grasp's inverse inertia G_robot + G_target")?;
            (lam, None)
        }
        GraspContact::Point { normal } => {
            let (raw, what) = match normal {
                Some(n) => (n, "normal"),
                None => (grasp_world - body_cm, "the default normal (the grasped body's CM to the grasp point)"),
            };
            let norm = raw.norm();
            if !(norm.is_finite() && norm >= 1e-12) {
                return Err(SpacearmError::argument(format!("{what} must be a non-zero finite 3-vector, got {raw:?}")));
            }
            let n = raw / norm;
            let vn = n.dot(&v_rel.fixed_rows::<3>(0));
            let mut lam = DVector::zeros(6);
            if vn < 0.0 {
                let g_vv: Matrix3<f64> = g.fixed_view::<3, 3>(0, 0).into_owned();
                let l = -(1.0 + restitution) * vn / n.dot(&(g_vv * n));
                lam.fixed_rows_mut::<3>(0).copy_from(&(n * l));
            }
            (lam, Some(n))
        }
    };

    let du = &resp_r.response * &lam;
    let target_du = -(&resp_t.response * &lam);
    let u_after = &u_r + &du;
    let target_u_after = &u_t + &target_du;
    let v_rel_after = &j_r * &u_after - &j_t * &target_u_after;
    // The contact pair's work over the impact (velocities jump linearly in the impulse, so the
    // work is the impulse times the mean of the velocities before and after).
    let energy_lost = -lam.dot(&(&v_rel + &v_rel_after)) / 2.0;
    check_contact_law(&g, &lam, &v_rel, &v_rel_after, contact, normal.as_ref(), restitution, energy_lost)?;
    let n = robot.n_dof();
    let (locking_impulse, locking_work) = if joints == JointsAtImpact::Locked && n > 0 {
        let tau = (&h_r * &du - j_r.transpose() * &lam).rows(6, n).into_owned();
        let work = tau.dot(&u_r.rows(6, n));
        (tau, work)
    } else {
        (DVector::zeros(n), 0.0)
    };
    Ok(GraspImpact {
        impulse: Vector6::from_column_slice(lam.as_slice()),
        du,
        target_du,
        u_after,
        target_u_after,
        point,
        gap,
        normal,
        relative_twist_before: Vector6::from_column_slice(v_rel.as_slice()),
        relative_twist_after: Vector6::from_column_slice(v_rel_after.as_slice()),
        g_robot: matrix6(&resp_r.delassus),
        g_target: matrix6(&resp_t.delassus),
        energy_lost,
        locking_work,
        locking_impulse,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithms::momentum::{kinetic_energy, momentum};
    use crate::model::presets::{initial_configuration, spatial6};
    use crate::model::ModelBuilder;

    fn state(model: &Model) -> (Vec<f64>, Vec<f64>) {
        let mut x = initial_configuration(model);
        for (j, q) in x[7..].iter_mut().enumerate() {
            *q += 0.3 * (j as f64 + 1.0).sin();
        }
        let u: Vec<f64> = (0..model.nu()).map(|k| 0.05 * ((k as f64) * 1.7 + 0.3).cos()).collect();
        (x, u)
    }

    fn target() -> Model {
        ModelBuilder::new("t", "t", 50.0, [[4.0, 0.1, 0.0], [0.1, 5.0, 0.0], [0.0, 0.0, 6.0]]).unwrap().build().unwrap()
    }

    fn ee(model: &Model) -> BodyPoint {
        let p = &model.points()[model.end_effector().unwrap()];
        BodyPoint { body: p.body, offset: p.offset }
    }

    /// The target with its grasp point (offset (-0.5, 0, 0)) at the robot's end effector, tumbling.
    fn target_state(robot: &Model, x: &[f64]) -> (Vec<f64>, Vec<f64>, BodyPoint) {
        let mut data = Data::new(robot);
        crate::algorithms::kinematics::forward_kinematics(robot, &mut data, x).unwrap();
        let p = ee(robot);
        let xp = point_position(&data, p.body, &p.offset);
        let xt = vec![xp.x + 0.5, xp.y + 0.01, xp.z - 0.02, 0.0, 0.0, 0.0, 1.0];
        let ut = vec![-0.02, 0.01, 0.03, 0.05, -0.02, 0.2];
        (xt, ut, BodyPoint { body: 0, offset: Vector3::new(-0.5, 0.0, 0.0) })
    }

    #[test]
    fn a_gap_beyond_the_tolerance_and_a_long_handle_are_refused() {
        let (robot, tgt) = (spatial6(), target());
        let (x, u) = state(&robot);
        let (xt, ut, grasp) = target_state(&robot, &x); // grasp points 0.0224 m apart
        let run = |tol: f64, grasp: BodyPoint| {
            grasp_impact(&robot, &mut Data::new(&robot), &x, &u, ee(&robot), &tgt, &mut Data::new(&tgt), &xt, &ut, grasp,
                         GraspContact::Rigid, 0.0, JointsAtImpact::Free, tol)
        };
        assert!(run(0.03, grasp).is_ok());
        let err = run(0.02, grasp).unwrap_err().to_string();
        assert!(err.contains("0.0224 m apart") && err.contains("capture tolerance 0.02 m"), "{err}");
        // The target's size: tr(I) = 15 kg m², 50 kg → √(1.5·15/50) = 0.6708 m; the bound 1.3416 m.
        assert!((body_size(&tgt, 0) - (1.5f64 * 15.0 / 50.0).sqrt()).abs() < 1e-15);
        assert!(check_grasp_handle(&tgt, 0, &Vector3::new(1.34, 0.0, 0.0)).is_ok());
        let err = check_grasp_handle(&tgt, 0, &Vector3::new(0.0, 1.35, 0.0)).unwrap_err().to_string();
        assert!(err.contains("1.3500 m from the CM") && err.contains("0.6708 m"), "{err}");
        let far = BodyPoint { offset: Vector3::new(-2.0, 0.0, 0.0), ..grasp };
        assert!(run(f64::INFINITY, far).unwrap_err().to_string().contains("no handle that long"));
    }

    fn total(robot: &Model, x: &[f64], u: &[f64], target: &Model, xt: &[f64], ut: &[f64]) -> (Vector3<f64>, Vector3<f64>, f64) {
        let (mut dr, mut dt) = (Data::new(robot), Data::new(target));
        let (a, b) = (momentum(robot, &mut dr, x, u).unwrap(), momentum(target, &mut dt, xt, ut).unwrap());
        let e = kinetic_energy(robot, &mut dr, x, u).unwrap() + kinetic_energy(target, &mut dt, xt, ut).unwrap();
        (a.linear + b.linear, a.angular_about_origin + b.angular_about_origin, e)
    }

    fn impact(contact: GraspContact, e: f64, joints: JointsAtImpact) -> (GraspImpact, [(Vector3<f64>, Vector3<f64>, f64); 2]) {
        let (robot, tgt) = (spatial6(), target());
        let (x, u) = state(&robot);
        let (xt, ut, grasp) = target_state(&robot, &x);
        let (mut dr, mut dt) = (Data::new(&robot), Data::new(&tgt));
        let g = grasp_impact(&robot, &mut dr, &x, &u, ee(&robot), &tgt, &mut dt, &xt, &ut, grasp, contact, e, joints, f64::INFINITY).unwrap();
        let before = total(&robot, &x, &u, &tgt, &xt, &ut);
        let after = total(&robot, &x, g.u_after.as_slice(), &tgt, &xt, g.target_u_after.as_slice());
        (g, [before, after])
    }

    #[test]
    fn the_inverse_inertia_at_a_point_is_the_point_acceleration_aba_gives_an_impulse_from_rest() {
        // Independent of CRBA + Cholesky: from rest (no bias forces in space) the generalized
        // impulse Jᵀ Λ gives Δu = ABA(x, 0, Jᵀ Λ), and the point's twist jumps by J Δu = G Λ.
        let robot = spatial6();
        let (x, _) = state(&robot);
        let p = ee(&robot);
        let mut d = Data::new(&robot);
        let g = point_inverse_inertia(&robot, &mut d, &x, p, JointsAtImpact::Free).unwrap();
        let j = jacobian_of(&robot, &d, p.body, &p.offset).unwrap();
        let zero = vec![0.0; robot.nu()];
        for k in 0..6 {
            let mut lam = DVector::zeros(6);
            lam[k] = 1.0 + 0.3 * k as f64;
            let f = j.transpose() * &lam;
            let du = crate::algorithms::aba::aba(&robot, &mut Data::new(&robot), &x, &zero, f.as_slice(), &[]).unwrap().clone();
            let want = &j * du;
            let got = g * Vector6::from_column_slice(lam.as_slice());
            assert!((got - Vector6::from_column_slice(want.as_slice())).norm() < 1e-12 * want.norm(), "column {k}");
        }
        // G is symmetric positive definite; the locked arm is stiffer (G_locked ≤ G_free).
        assert!((g - g.transpose()).norm() < 1e-14 * g.norm());
        let gl = point_inverse_inertia(&robot, &mut d, &x, p, JointsAtImpact::Locked).unwrap();
        assert!((g - gl).symmetric_eigenvalues().min() > -1e-12 * g.norm());
        // Yoshida's virtual mass along n: 1 / (nᵀ G_vv n), any length of n.
        let n = Vector3::new(0.3, -0.5, 0.8);
        let m = virtual_mass(&robot, &mut d, &x, p, &(2.0 * n), JointsAtImpact::Free).unwrap();
        let u = n.normalize();
        assert!((m * u.dot(&(g.fixed_view::<3, 3>(0, 0) * u)) - 1.0).abs() < 1e-13);
        assert!(virtual_mass(&robot, &mut d, &x, p, &Vector3::zeros(), JointsAtImpact::Free).is_err());
    }

    #[test]
    fn a_rigid_body_s_inverse_inertia_is_the_closed_form() {
        // One rigid body (mass m, inertia I about its CM, identity attitude), point r from the CM:
        // Δv_X = f / m + (I⁻¹ (n + r × f)) × r, Δω = I⁻¹ (n + r × f).
        let body = target();
        let x = [0.2, -0.1, 0.4, 0.0, 0.0, 0.0, 1.0];
        let r = Vector3::new(-0.5, 0.2, 0.1);
        let i_inv = Matrix3::new(4.0, 0.1, 0.0, 0.1, 5.0, 0.0, 0.0, 0.0, 6.0).try_inverse().unwrap();
        for joints in [JointsAtImpact::Free, JointsAtImpact::Locked] {
            let g = point_inverse_inertia(&body, &mut Data::new(&body), &x, BodyPoint { body: 0, offset: r }, joints).unwrap();
            for k in 0..6 {
                let mut lam = Vector6::zeros();
                lam[k] = 1.0;
                let (f, n) = (lam.fixed_rows::<3>(0).into_owned(), lam.fixed_rows::<3>(3).into_owned());
                let dw = i_inv * (n + r.cross(&f));
                let dv = f / 50.0 + dw.cross(&r);
                let want = Vector6::new(dv.x, dv.y, dv.z, dw.x, dw.y, dw.z);
                assert!((g * lam - want).norm() < 1e-14, "column {k}: {:?} vs {want:?}", g * lam);
            }
        }
    }

    #[test]
    fn an_impulse_s_momentum_splits_into_the_base_s_and_the_arm_s_shares() {
        let robot = spatial6();
        let (x, _) = state(&robot);
        let p = ee(&robot);
        let lam = Vector6::new(1.0, -2.0, 0.5, 0.1, 0.3, -0.2);
        let mut d = Data::new(&robot);
        let s = impulse_momentum_split(&robot, &mut d, &x, p, &lam).unwrap();
        assert!((s.base + s.arm - s.total).norm() < 1e-12 * s.total.norm());
        assert!(s.arm.norm() > 1e-3 * s.total.norm(), "the arm takes a share");
        // B Λ is the base's jump that ABA gives the generalized impulse Jᵀ Λ from rest.
        let j = jacobian_of(&robot, &d, p.body, &p.offset).unwrap();
        let f = j.transpose() * DVector::from_column_slice(lam.as_slice());
        let du = crate::algorithms::aba::aba(&robot, &mut Data::new(&robot), &x, &vec![0.0; robot.nu()], f.as_slice(), &[]).unwrap().clone();
        let want = Vector6::from_column_slice(&du.as_slice()[..6]);
        assert!((s.base_jump_map * lam - want).norm() < 1e-12 * want.norm());
        let sv = s.base_jump_singular_values;
        assert!(sv.iter().zip(sv.iter().skip(1)).all(|(a, b)| a >= b) && sv[5] >= 0.0);
        assert!(impulse_momentum_split(&robot, &mut d, &x, p, &Vector6::repeat(f64::NAN)).is_err());
    }

    #[test]
    fn a_rigid_grasp_locks_the_frames_and_conserves_momentum() {
        for joints in [JointsAtImpact::Free, JointsAtImpact::Locked] {
            let (g, [b, a]) = impact(GraspContact::Rigid, 0.0, joints);
            let scale = g.relative_twist_before.norm();
            assert!(g.relative_twist_after.norm() < 1e-12 * scale.max(1.0), "{:e}", g.relative_twist_after.norm());
            assert!((a.0 - b.0).norm() < 1e-12 * b.0.norm().max(1.0));
            assert!((a.1 - b.1).norm() < 1e-11 * b.1.norm().max(1.0));
            // ½ v Gᵀ⁻¹ v, and the energy ledger with the locking work.
            let gsum = g.g_robot + g.g_target;
            let closed = 0.5 * g.relative_twist_before.dot(&(gsum.try_inverse().unwrap() * g.relative_twist_before));
            assert!((g.energy_lost - closed).abs() < 1e-10 * closed, "{} vs {closed}", g.energy_lost);
            assert!(((b.2 - a.2) - (g.energy_lost - g.locking_work)).abs() < 1e-10 * b.2);
            if joints == JointsAtImpact::Locked {
                assert!(g.du.rows(6, 6).norm() == 0.0);
                assert!(g.locking_work != 0.0);
            } else {
                assert_eq!(g.locking_work, 0.0);
            }
        }
    }

    #[test]
    fn a_point_contact_follows_newtons_restitution() {
        for e in [0.0, 0.4, 1.0] {
            let (g, [b, a]) = impact(GraspContact::Point { normal: None }, e, JointsAtImpact::Free);
            let n = g.normal.unwrap();
            let (vb, va) = (n.dot(&g.relative_twist_before.fixed_rows::<3>(0)), n.dot(&g.relative_twist_after.fixed_rows::<3>(0)));
            assert!(vb < 0.0, "the fixture must approach");
            assert!((va + e * vb).abs() < 1e-12 * vb.abs(), "{va} vs {}", -e * vb);
            let m_eff = 1.0 / n.dot(&((g.g_robot + g.g_target).fixed_view::<3, 3>(0, 0) * n));
            let closed = 0.5 * m_eff * (1.0 - e * e) * vb * vb;
            assert!((g.energy_lost - closed).abs() < 1e-10 * b.2);
            assert!(((b.2 - a.2) - g.energy_lost).abs() < 1e-10 * b.2);
            assert!((a.0 - b.0).norm() < 1e-12 * b.0.norm().max(1.0));
            assert!(g.impulse.fixed_rows::<3>(3).norm() == 0.0);
        }
        // Separating along the normal given: no impulse; a zero normal is refused.
        let (g0, _) = impact(GraspContact::Point { normal: None }, 0.0, JointsAtImpact::Free);
        let away = -g0.normal.unwrap();
        let (g, _) = impact(GraspContact::Point { normal: Some(away) }, 0.0, JointsAtImpact::Free);
        assert!(g.impulse.norm() == 0.0 && g.du.norm() == 0.0 && g.energy_lost == 0.0);
        let (robot, tgt) = (spatial6(), target());
        let (x, u) = state(&robot);
        let (xt, ut, grasp) = target_state(&robot, &x);
        let err = grasp_impact(&robot, &mut Data::new(&robot), &x, &u, ee(&robot), &tgt, &mut Data::new(&tgt), &xt, &ut, grasp,
                               GraspContact::Point { normal: Some(Vector3::zeros()) }, 0.0, JointsAtImpact::Free, f64::INFINITY)
            .unwrap_err();
        assert!(matches!(err, SpacearmError::InvalidArgument(_)), "{err}");
    }

    #[test]
    fn impulse_dynamics_meets_the_restitution_law_and_matches_a_grasp_of_a_heavy_body() {
        let robot = spatial6();
        let (x, u) = state(&robot);
        let mut data = Data::new(&robot);
        crate::algorithms::kinematics::forward_kinematics(&robot, &mut data, &x).unwrap();
        let p = ee(&robot);
        let j = jacobian_of(&robot, &data, p.body, &p.offset).unwrap();
        let uv = DVector::from_column_slice(&u);
        for e in [0.0, 0.6] {
            for joints in [JointsAtImpact::Free, JointsAtImpact::Locked] {
                let r = impulse_dynamics(&robot, &mut data, &x, &u, &j, e, joints).unwrap();
                let (vb, va) = (&j * &uv, &j * &r.u_after);
                assert!((&va + e * &vb).norm() < 1e-12 * vb.norm());
                let ke = |v: &DVector<f64>| kinetic_energy(&robot, &mut Data::new(&robot), &x, v.as_slice()).unwrap();
                let lost = ke(&uv) - ke(&r.u_after);
                if joints == JointsAtImpact::Free {
                    assert!(lost >= 0.0 && r.locking_impulse.norm() < 1e-10);
                } else {
                    assert!(r.du.rows(6, 6).norm() == 0.0);
                    assert!(((lost + r.locking_impulse.dot(&uv.rows(6, 6))) - (-r.impulse.dot(&(&va + &vb)) / 2.0)).abs() < 1e-10 * ke(&uv));
                }
            }
        }
        // A target of 1e12 kg at rest: a fixed contact to about 1e-10.
        let heavy = ModelBuilder::new("t", "t", 1e12, [[1e12, 0.0, 0.0], [0.0, 1e12, 0.0], [0.0, 0.0, 1e12]]).unwrap().build().unwrap();
        let (mut xt, _, grasp) = target_state(&robot, &x);
        xt[0] -= 0.5;
        let grasp = BodyPoint { offset: Vector3::zeros(), ..grasp };
        let g = grasp_impact(&robot, &mut data, &x, &u, p, &heavy, &mut Data::new(&heavy), &xt, &[0.0; 6], grasp, GraspContact::Rigid, 0.0,
                             JointsAtImpact::Free, f64::INFINITY)
            .unwrap();
        let r = impulse_dynamics(&robot, &mut data, &x, &u, &j, 0.0, JointsAtImpact::Free).unwrap();
        assert!((&g.du - &r.du).norm() < 1e-9 * r.du.norm(), "{:e}", (&g.du - &r.du).norm() / r.du.norm());
    }
}
