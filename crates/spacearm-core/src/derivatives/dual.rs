//! The dual-number evaluation the derivatives share (module docs of [`crate::derivatives`]):
//! the directions of the tangent space ([`Direction`]), the dual workspace and its seeding along
//! a chunk of directions or along the velocity, [`DerivativeData`] (the workspace of every
//! derivative), and the loop closure's bias `J̇_c u` ([`loop_closure_bias`]).

use nalgebra::{Const, DMatrix, Matrix3, Matrix6, SVector, Vector3, Vector6, U1};
use num_dual::{Derivative, Dual64, DualSVec64};

use crate::model::data::{Data, DataT};
use crate::error::Result;
use crate::algorithms::kinematics::{check_velocity, forward_kinematics, forward_kinematics_at, split_configuration};
use crate::model::Model;
use crate::math::scalar::Real;
use crate::math::spatial::{cross_motion, skew};

/// Number of directions differentiated together in one dual-number pass.
pub const CHUNK: usize = 8;

/// A dual number carrying [`CHUNK`] directional derivatives.
pub type DualChunk = DualSVec64<CHUNK>;

/// One direction of differentiation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Direction {
    /// Rotation increment of the base about axis `i` of 𝒥 (tangent coordinate `3 + i`).
    Attitude(usize),
    /// Joint coordinate `q_j` (tangent coordinate `6 + j`).
    Joint(usize),
    /// Generalized velocity component `u_k`.
    Velocity(usize),
}

impl Direction {
    /// Index in the tangent space of the configuration (`None` for a velocity direction).
    pub(crate) fn tangent_index(self) -> Option<usize> {
        match self {
            Direction::Attitude(i) => Some(3 + i),
            Direction::Joint(j) => Some(6 + j),
            Direction::Velocity(_) => None,
        }
    }
}

/// The configuration directions that matter: attitude then joints (`3 + N`; `δr0` has none).
pub(crate) fn configuration_directions(n_dof: usize) -> impl Iterator<Item = Direction> {
    (0..3).map(Direction::Attitude).chain((0..n_dof).map(Direction::Joint))
}

/// Dual-number inputs and workspace for one scalar type.
#[derive(Debug, Clone)]
pub(crate) struct DualWork<T: Real> {
    pub data: DataT<T>,
    pub q: Vec<T>,
    pub u: Vec<T>,
    pub du: Vec<T>,
}

impl<T: Real> DualWork<T> {
    fn new(model: &Model) -> Self {
        DualWork {
            data: DataT::new(model),
            q: vec![T::zero(); model.n_dof()],
            u: vec![T::zero(); model.nu()],
            du: vec![T::zero(); model.nu()],
        }
    }
}

/// The f64 base pose and joint coordinates of a validated configuration.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Pose<'a> {
    pub r0: Vector3<f64>,
    pub base_to_world: Matrix3<f64>,
    pub q: &'a [f64],
}

impl<'a> Pose<'a> {
    /// Validate `x` (length, finite, unit quaternion) and split it.
    pub(crate) fn new(model: &Model, x: &'a [f64]) -> Result<Self> {
        let (r0, quat0, q) = split_configuration(model, x)?;
        Ok(Pose { r0, base_to_world: quat0.to_rotation_matrix().into_inner(), q })
    }
}

/// Forward kinematics on dual numbers: `R0 ← (E + θ̃) R0` with the dual rotation increment
/// `theta` (zero real part), `q` already in `work.q`.
fn dual_kinematics<T: Real>(model: &Model, work: &mut DualWork<T>, pose: &Pose, r0: Vector3<T>, theta: Vector3<T>) {
    let rot: Matrix3<T> = pose.base_to_world.map(T::c);
    let rot = rot + skew(&theta) * rot;
    forward_kinematics_at(model, &mut work.data, &r0, &rot, &work.q);
}

/// Seed a chunk of directions (at most [`CHUNK`]): lane `l` of the ε part carries direction
/// `dirs[l]`. Sets `work.q` and `work.u` (from `u`, if given) and runs forward kinematics.
pub(crate) fn seed_chunk(model: &Model, work: &mut DualWork<DualChunk>, pose: &Pose, u: Option<&[f64]>, dirs: &[Direction]) {
    debug_assert!(dirs.len() <= CHUNK);
    let mut theta = Vector3::<DualChunk>::zeros();
    for (j, q) in work.q.iter_mut().enumerate() {
        *q = DualChunk::from_re(pose.q[j]);
    }
    if let Some(u) = u {
        for (k, v) in work.u.iter_mut().enumerate() {
            *v = DualChunk::from_re(u[k]);
        }
    }
    for (lane, dir) in dirs.iter().enumerate() {
        match *dir {
            Direction::Attitude(i) => theta[i] = DualChunk::from_re(0.0).derivative(lane),
            Direction::Joint(j) => work.q[j] = DualChunk::from_re(pose.q[j]).derivative(lane),
            Direction::Velocity(k) => work.u[k] = DualChunk::from_re(u.expect("velocity directions need u")[k]).derivative(lane),
        }
    }
    dual_kinematics(model, work, pose, pose.r0.map(DualChunk::from_re), theta);
}

/// Seed a chunk of directions from the `f64` kinematics already in `kin` (current for the
/// configuration of `pose`), without running forward kinematics on dual numbers: the ε parts
/// of the two fields that CRBA and RNEA read — the motion subspaces `Sᵢ` and the spatial
/// inertias `Iᵢ` at the base CM — are their exact first-order changes, which have a closed
/// form. A direction moves rigidly every body it carries with the twist `S_d` at the base CM
/// (the base CM itself never moves under `δθ` or `δq`): `[0; e_i]` for the attitude increment
/// `δθ_i` (every body), the joint's motion subspace `S_j` for `δq_j` (the bodies of its
/// subtree). Then (Featherstone §2.9–2.12) `δSᵢ = S_d ×ₘ Sᵢ`, and `Iᵢ` follows from its CM and
/// world inertia moving as `δc = S_d,lin + S_d,ang × c`, `δI_c = ω̃ I_c − I_c ω̃` — evaluated
/// by [`spatial_inertia_change`]. Sets `work.q` and
/// `work.u` as [`seed_chunk`] does; the other kinematic fields of `work.data` are left stale.
///
/// Cost O(bodies × depth × lanes) flops, a fraction of forward kinematics on dual numbers
/// (which the tests use as the reference for this seeding).
pub(crate) fn seed_chunk_from_kinematics(model: &Model, kin: &Data, work: &mut DualWork<DualChunk>, pose: &Pose, u: Option<&[f64]>, dirs: &[Direction]) {
    debug_assert!(dirs.len() <= CHUNK);
    for (j, q) in work.q.iter_mut().enumerate() {
        *q = DualChunk::from_re(pose.q[j]);
    }
    if let Some(u) = u {
        for (k, v) in work.u.iter_mut().enumerate() {
            *v = DualChunk::from_re(u[k]);
        }
    }
    for (lane, dir) in dirs.iter().enumerate() {
        if let Direction::Velocity(k) = *dir {
            work.u[k] = DualChunk::from_re(u.expect("velocity directions need u")[k]).derivative(lane);
        }
    }
    let r0 = kin.base_position;
    for b in 0..model.n_bodies() {
        let s = kin.motion_subspace[b];
        let inertia = &kin.spatial_inertia[b];
        if !dirs.iter().any(|d| moves(model, *d, b)) {
            work.data.motion_subspace[b] = s.map(DualChunk::from_re);
            work.data.spatial_inertia[b] = inertia.map(DualChunk::from_re);
            continue;
        }
        let mass = model.mass_properties(b).mass;
        let c = kin.com_in_world[b] - r0;
        let ic = kin.inertia_in_world[b];
        let mut ds = [[0.0; CHUNK]; 6];
        let mut di = [[0.0; CHUNK]; 36];
        for (lane, dir) in dirs.iter().enumerate() {
            if !moves(model, *dir, b) {
                continue;
            }
            let twist = match *dir {
                Direction::Attitude(i) => {
                    let mut t = Vector6::zeros();
                    t[3 + i] = 1.0;
                    t
                }
                Direction::Joint(j) => kin.motion_subspace[model.body_of_dof(j)],
                Direction::Velocity(_) => unreachable!("velocity directions move no body"),
            };
            let d_s = cross_motion(&twist, &s);
            for r in 0..6 {
                ds[r][lane] = d_s[r];
            }
            let (v, w) = (twist.fixed_rows::<3>(0).into_owned(), twist.fixed_rows::<3>(3).into_owned());
            let dc = v + w.cross(&c);
            let d_i = spatial_inertia_change(mass, &c, &ic, &dc, &w);
            for (k, e) in d_i.iter().enumerate() {
                di[k][lane] = *e;
            }
        }
        let dual = |re: f64, eps: &[f64; CHUNK]| DualChunk::new(re, Derivative::some(SVector::from(*eps)));
        work.data.motion_subspace[b] = Vector6::from_fn(|r, _| dual(s[r], &ds[r]));
        work.data.spatial_inertia[b] = Matrix6::from_iterator(inertia.iter().zip(di.iter()).map(|(re, eps)| dual(*re, eps)));
    }
}

/// First-order change of [`spatial_inertia`]`(m, c, I_c)` when the CM moves by `dc` and the
/// body turns at `w` (so `dI_c = w̃ I_c − I_c w̃`): with `c̃ᵀ c̃ = |c|² E − c cᵀ`,
/// `[[0, −m dc̃], [m dc̃, dI_c + m (2 (c·dc) E − dc cᵀ − c dcᵀ)]]`.
fn spatial_inertia_change(m: f64, c: &Vector3<f64>, ic: &Matrix3<f64>, dc: &Vector3<f64>, w: &Vector3<f64>) -> Matrix6<f64> {
    // w̃ I_c − I_c w̃ = W + Wᵀ with W = w̃ I_c (I_c symmetric, w̃ᵀ = −w̃).
    let wi = skew(w) * ic;
    let cdc = 2.0 * c.dot(dc);
    let mut out = Matrix6::zeros();
    let mdc = skew(&(dc * m));
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-mdc));
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&mdc);
    for i in 0..3 {
        for j in 0..3 {
            let diag = if i == j { cdc } else { 0.0 };
            out[(3 + i, 3 + j)] = wi[(i, j)] + wi[(j, i)] + m * (diag - dc[i] * c[j] - c[i] * dc[j]);
        }
    }
    out
}

/// `true` if a change of the configuration along `dir` moves `body`.
#[inline]
fn moves(model: &Model, dir: Direction, body: usize) -> bool {
    match dir {
        Direction::Attitude(_) => true,
        Direction::Joint(j) => is_ancestor_or_self(model, model.body_of_dof(j), body),
        Direction::Velocity(_) => false,
    }
}

/// `true` if `ancestor` is `body` or on its path to the base.
fn is_ancestor_or_self(model: &Model, ancestor: usize, body: usize) -> bool {
    let mut b = body;
    loop {
        if b == ancestor {
            return true;
        }
        if b == 0 || b < ancestor {
            // Parents are listed before their children: below `ancestor`'s index it cannot appear.
            return false;
        }
        b = model.links()[b - 1].parent;
    }
}

/// Seed the single direction `(ẋ, u̇_dir)` = the tangent velocity `u` itself: `r0` moves at
/// `v0`, the attitude at `ω0`, the joints at `q̇`. Sets `work.q`, `work.u` (real, no ε) and runs
/// forward kinematics.
pub(crate) fn seed_along_velocity(model: &Model, work: &mut DualWork<Dual64>, pose: &Pose, u: &[f64]) {
    let n = model.n_dof();
    for j in 0..n {
        work.q[j] = Dual64::new(pose.q[j], u[6 + j]);
    }
    for (k, v) in work.u.iter_mut().enumerate() {
        *v = Dual64::from_re(u[k]);
    }
    let r0 = Vector3::new(Dual64::new(pose.r0.x, u[0]), Dual64::new(pose.r0.y, u[1]), Dual64::new(pose.r0.z, u[2]));
    let theta = Vector3::new(Dual64::new(0.0, u[3]), Dual64::new(0.0, u[4]), Dual64::new(0.0, u[5]));
    dual_kinematics(model, work, pose, r0, theta);
}

/// Workspace of [`loop_closure_bias`]: forward kinematics on one-lane dual numbers.
#[derive(Debug, Clone)]
pub struct ClosureBiasWork(DualWork<Dual64>);

impl ClosureBiasWork {
    /// A workspace for `model`.
    pub fn new(model: &Model) -> Self {
        ClosureBiasWork(DualWork::new(model))
    }
}

/// `J̇_c u` of a loop closure ([`crate::algorithms::constrained::LoopClosure`]) at `(x, u)`,
/// exactly: the time derivative along `u` of `J_c(x) = J_b − J_a` (both at b's origin `p_b(x)`,
/// so the moving point is differentiated too) times `u` — the frames' relative acceleration at
/// `u̇ = 0`. Forward kinematics on dual numbers seeded with `u` (`seed_along_velocity`), then
/// the joint-side point Jacobians of the same generic code (`J_c`'s base columns are zero).
pub fn loop_closure_bias(
    model: &Model,
    work: &mut ClosureBiasWork,
    x: &[f64],
    u: &[f64],
    closure: &crate::algorithms::constrained::LoopClosure,
) -> Result<Vector6<f64>> {
    use crate::algorithms::kinematics::{joint_jacobian_of_point, point_position};
    let pose = pose_and_velocity(model, x, u)?;
    seed_along_velocity(model, &mut work.0, &pose, u);
    let data = &work.0.data;
    let pb = point_position(data, closure.b.body, &closure.b.offset);
    let jb = joint_jacobian_of_point(model, data, closure.b.body, &pb);
    let ja = joint_jacobian_of_point(model, data, closure.a.body, &pb);
    let mut out = Vector6::zeros();
    for j in 0..model.n_dof() {
        for r in 0..6 {
            out[r] += (jb[(r, j)].eps - ja[(r, j)].eps) * u[6 + j];
        }
    }
    Ok(out)
}

/// The ε lanes of a chunk dual number (zeros when it carries none).
#[inline]
pub(crate) fn lanes(v: &DualChunk) -> [f64; CHUNK] {
    let e = v.eps.unwrap_generic(Const::<CHUNK>, U1);
    let mut out = [0.0; CHUNK];
    out.copy_from_slice(e.as_slice());
    out
}

/// Preallocated workspace and results of the derivative functions for one [`Model`].
///
/// Holds an `f64` [`Data`], two dual-number workspaces (one with [`CHUNK`] lanes for partial
/// derivatives, one with a single lane for time derivatives) and every result matrix, so that
/// repeated calls allocate nothing.
#[derive(Debug, Clone)]
pub struct DerivativeData {
    /// The `f64` workspace (forward dynamics, mass matrix and its factorization).
    pub data: Data,
    pub(crate) chunk: DualWork<DualChunk>,
    pub(crate) single: DualWork<Dual64>,
    /// `∂H/∂x_k` for the `6+N` tangent coordinates `k` (each `(6+N)²`), filled by
    /// [`mass_matrix_partials`](crate::derivatives::mass_matrix_partials).
    pub mass_matrix_partials: Vec<DMatrix<f64>>,
    /// `Ḣ` (`(6+N)²`), filled by [`mass_matrix_derivative`](crate::derivatives::mass_matrix_derivative).
    pub mass_matrix_derivative: DMatrix<f64>,
    /// `∂H*/∂q_k` for the `N` joint coordinates (each N×N), filled by
    /// [`generalized_inertia_partials`](crate::derivatives::generalized_inertia_partials).
    pub generalized_inertia_partials: Vec<DMatrix<f64>>,
    /// `Ḣ*` (N×N), filled by [`generalized_inertia_derivative`](crate::derivatives::generalized_inertia_derivative).
    pub generalized_inertia_derivative: DMatrix<f64>,
    /// `∂J*/∂x_k` for the `6+N` tangent coordinates (each 6×N), filled by
    /// [`generalized_jacobian_partials`](crate::derivatives::generalized_jacobian_partials).
    pub generalized_jacobian_partials: Vec<DMatrix<f64>>,
    /// `J̇*` (6×N), filled by [`generalized_jacobian_derivative`](crate::derivatives::generalized_jacobian_derivative).
    pub generalized_jacobian_derivative: DMatrix<f64>,
    /// `∂u̇/∂x` ((6+N)², tangent coordinates), filled by [`forward_dynamics_derivatives`](crate::derivatives::forward_dynamics_derivatives).
    pub accel_wrt_configuration: DMatrix<f64>,
    /// `∂u̇/∂u` ((6+N)²), filled by [`forward_dynamics_derivatives`](crate::derivatives::forward_dynamics_derivatives).
    pub accel_wrt_velocity: DMatrix<f64>,
    /// `∂u̇/∂f = H⁻¹` ((6+N)²), filled by [`forward_dynamics_derivatives`](crate::derivatives::forward_dynamics_derivatives).
    pub accel_wrt_force: DMatrix<f64>,
    /// `A` of the linearized state equation (2(6+N) square), filled by [`linearize`](crate::derivatives::linearize).
    pub state_matrix: DMatrix<f64>,
    /// `B` of the linearized state equation (2(6+N) × (6+N) or × N), filled by [`linearize`](crate::derivatives::linearize).
    pub input_matrix: DMatrix<f64>,
    /// `∂ID/∂x` ((6+N)², tangent coordinates), filled by [`inverse_dynamics_partials`](crate::derivatives::inverse_dynamics_partials).
    pub id_wrt_configuration: DMatrix<f64>,
    /// `∂ID/∂u` ((6+N)²), filled by [`inverse_dynamics_partials`](crate::derivatives::inverse_dynamics_partials).
    pub id_wrt_velocity: DMatrix<f64>,
    /// Scratch: derivatives of the inverse dynamics, (6+N) × (9+2N), columns `[δθ, δq, δu]`.
    pub(crate) id_partials: DMatrix<f64>,
    /// Scratch: the acceleration `u̇` at which inverse dynamics is differentiated.
    pub(crate) du_scratch: nalgebra::DVector<f64>,
    /// Scratch: `L⁻¹` while inverting `H` ((6+N)²).
    pub(crate) dense_scratch: DMatrix<f64>,
    /// Scratch of the analytic RNEA partials (O(N)).
    pub(crate) rnea: super::rnea_partials::RneaPartialsWork,
    /// The directions of each function: attitude + joints; joints; attitude + joints + velocity.
    pub(crate) config_dirs: Vec<Direction>,
    pub(crate) joint_dirs: Vec<Direction>,
    pub(crate) dynamics_dirs: Vec<Direction>,
}

impl DerivativeData {
    /// Admit the workspace of [`DerivativeData::new`] for `model` (its dense matrices take
    /// about 13 (6+N)² values; the two tensors of partials, (6+N)³ and N³ values, are sized by
    /// their functions on first use and admitted there), or refuse it with
    /// [`crate::SpacearmError::ResourceLimit`].
    pub fn admit(model: &Model) -> Result<()> {
        let nu = model.nu() as f64;
        crate::admission::admit(
            format_args!("the derivative workspace of a model with N = {}", model.n_dof()),
            crate::admission::bytes_of::<f64>(13.0 * nu * nu + 6.0 * nu * nu),
            "use finite differences of forward_dynamics (O(N) per call with ABA) or a smaller model",
        )
    }

    /// The prologue of the tensors of partials of a kinematic quantity (`H`,
    /// [`super::mass_matrix_partials`]; `H*`, [`super::generalized_inertia_partials`]): the pose
    /// of `x` checked, forward kinematics in `f64` into `self.data`, and the tensor (`n`
    /// matrices of `n×n`, `n = 6 + N` for `H`, `N` for `H*`) sized by [`Self::size_partials`].
    /// Returns the pose and `n`.
    pub(crate) fn prepare_partials<'a>(&mut self, model: &Model, x: &'a [f64], tensor: PartialsTensor) -> Result<(Pose<'a>, usize)> {
        let pose = Pose::new(model, x)?;
        forward_kinematics(model, &mut self.data, x)?;
        let n = match tensor {
            PartialsTensor::MassMatrix => {
                let nu = model.nu();
                let remedy = "use mass_matrix_derivative (Ḣ along one velocity, (6+N)² values) or a smaller model";
                Self::size_partials(&mut self.mass_matrix_partials, nu, format_args!("mass_matrix_partials ((6+N)³ = {nu}³ values)"), remedy)?;
                nu
            }
            PartialsTensor::GeneralizedInertia => {
                let n = model.n_dof();
                let remedy = "use generalized_inertia_derivative (Ḣ* along one velocity, N² values) or a smaller model";
                Self::size_partials(&mut self.generalized_inertia_partials, n, format_args!("generalized_inertia_partials (N³ = {n}³ values)"), remedy)?;
                n
            }
        };
        Ok((pose, n))
    }

    /// Size a tensor of partials (`tensor`, `n` matrices of `n×n`) on its function's first use,
    /// admitting its `n³` values first: `what` names the function and the size, `remedy` the
    /// way out ([`crate::admission::admit`]).
    fn size_partials(tensor: &mut Vec<DMatrix<f64>>, n: usize, what: impl std::fmt::Display, remedy: &str) -> Result<()> {
        if tensor.len() != n {
            crate::admission::admit(what, crate::admission::bytes_of::<f64>((n as f64).powi(3)), remedy)?;
            *tensor = vec![DMatrix::zeros(n, n); n];
        }
        Ok(())
    }

    /// Allocate the workspace and results for `model` (see [`DerivativeData::admit`]).
    pub fn new(model: &Model) -> Self {
        let n = model.n_dof();
        let nu = model.nu();
        DerivativeData {
            data: Data::new(model),
            chunk: DualWork::new(model),
            single: DualWork::new(model),
            mass_matrix_partials: Vec::new(),
            mass_matrix_derivative: DMatrix::zeros(nu, nu),
            generalized_inertia_partials: Vec::new(),
            generalized_inertia_derivative: DMatrix::zeros(n, n),
            generalized_jacobian_partials: vec![DMatrix::zeros(6, n); nu],
            generalized_jacobian_derivative: DMatrix::zeros(6, n),
            accel_wrt_configuration: DMatrix::zeros(nu, nu),
            accel_wrt_velocity: DMatrix::zeros(nu, nu),
            accel_wrt_force: DMatrix::zeros(nu, nu),
            state_matrix: DMatrix::zeros(2 * nu, 2 * nu),
            input_matrix: DMatrix::zeros(2 * nu, nu),
            id_wrt_configuration: DMatrix::zeros(nu, nu),
            id_wrt_velocity: DMatrix::zeros(nu, nu),
            id_partials: DMatrix::zeros(nu, 9 + 2 * n),
            du_scratch: nalgebra::DVector::zeros(nu),
            dense_scratch: DMatrix::zeros(nu, nu),
            rnea: super::rnea_partials::RneaPartialsWork::new(model),
            config_dirs: configuration_directions(n).collect(),
            joint_dirs: (0..n).map(Direction::Joint).collect(),
            dynamics_dirs: configuration_directions(n).chain((0..nu).map(Direction::Velocity)).collect(),
        }
    }
}

/// The tensors of partials that [`DerivativeData::prepare_partials`] sizes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PartialsTensor {
    /// `∂H/∂x_k`, `work.mass_matrix_partials`.
    MassMatrix,
    /// `∂H*/∂q_k`, `work.generalized_inertia_partials`.
    GeneralizedInertia,
}

/// Validate a configuration and a velocity for the derivative functions.
pub(crate) fn pose_and_velocity<'a>(model: &Model, x: &'a [f64], u: &[f64]) -> Result<Pose<'a>> {
    let pose = Pose::new(model, x)?;
    check_velocity(model, "u", u)?;
    Ok(pose)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::joint::{JointLimits, JointType};
    use crate::algorithms::kinematics::forward_kinematics;
    use crate::model::{LinkSpec, ModelBuilder};

    /// A tree with a rotated revolute chain, a prismatic branch and a fixed link carrying a
    /// revolute child.
    fn tree() -> Model {
        let mut b = ModelBuilder::new("t", "base", 120.0, [[20.0, 0.5, -0.3], [0.5, 25.0, 0.2], [-0.3, 0.2, 30.0]]).unwrap();
        let mut add = |name: &str, parent: &str, kind: JointType, rot: [f64; 4], axis: [f64; 3]| {
            b.add_link(LinkSpec {
                name: name.into(),
                parent: parent.into(),
                joint_name: None,
                kind,
                origin_in_parent: [0.4, -0.2, 0.3],
                rotation_in_parent: rot,
                axis,
                com_from_joint: [0.2, 0.1, -0.05],
                mass: 3.0,
                inertia: [[0.05, 0.001, 0.0], [0.001, 0.06, 0.002], [0.0, 0.002, 0.07]],
                limits: JointLimits::unlimited(),
            })
            .unwrap();
        };
        let r = [0.1, -0.2, 0.3, (1.0f64 - 0.14).sqrt()];
        add("a", "base", JointType::Revolute, r, [0.0, 0.6, 0.8]);
        add("b", "a", JointType::Revolute, [0.0, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        add("p", "a", JointType::Prismatic, r, [0.0, 0.0, 1.0]);
        add("f", "b", JointType::Fixed, r, [1.0, 0.0, 0.0]);
        add("c", "f", JointType::Revolute, [0.0, 0.0, 0.0, 1.0], [0.3, 0.4, 0.0]);
        b.build().unwrap()
    }

    #[test]
    fn spatial_inertia_change_is_the_derivative_of_spatial_inertia() {
        use crate::math::rotations::rotate_symmetric;
        use crate::math::spatial::spatial_inertia;
        let (m, c) = (2.5, Vector3::new(0.3, -0.2, 0.5));
        let ic = Matrix3::new(0.4, 0.01, 0.02, 0.01, 0.5, -0.03, 0.02, -0.03, 0.6);
        let (dc, w) = (Vector3::new(-0.7, 0.1, 0.4), Vector3::new(0.2, 0.9, -0.3));
        // Dual-number evaluation of spatial_inertia(m, c + dc ε, (E + w̃ ε) I_c (E + w̃ ε)ᵀ).
        let c_dual = Vector3::from_fn(|r, _| Dual64::new(c[r], dc[r]));
        let turn = Matrix3::from_fn(|r, k| Dual64::from_re(if r == k { 1.0 } else { 0.0 })) + skew(&w.map(|e| Dual64::new(0.0, e)));
        let reference = spatial_inertia(Dual64::from_re(m), &c_dual, &rotate_symmetric(&turn, &ic.map(Dual64::from_re))).map(|e| e.eps);
        let ours = spatial_inertia_change(m, &c, &ic, &dc, &w);
        assert!(reference.norm() > 1.0);
        assert!((ours - reference).abs().max() < 1e-14);
    }

    #[test]
    fn closed_form_seeding_equals_forward_kinematics_on_dual_numbers() {
        let model = tree();
        let mut work = DerivativeData::new(&model);
        let x = [0.3, -1.2, 2.0, 0.2, -0.4, 0.1, (1.0f64 - 0.21).sqrt(), 0.7, -0.3, 0.25, 1.1];
        let u: Vec<f64> = (0..model.nu()).map(|k| 0.1 * k as f64 - 0.3).collect();
        let pose = Pose::new(&model, &x).unwrap();
        forward_kinematics(&model, &mut work.data, &x).unwrap();
        let dirs: Vec<Direction> = work.dynamics_dirs.clone();
        let mut reference = DualWork::<DualChunk>::new(&model);
        let mut checked = 0;
        for chunk in dirs.chunks(CHUNK) {
            seed_chunk(&model, &mut reference, &pose, Some(&u), chunk);
            seed_chunk_from_kinematics(&model, &work.data, &mut work.chunk, &pose, Some(&u), chunk);
            for b in 0..model.n_bodies() {
                let pairs = work.chunk.data.motion_subspace[b]
                    .iter()
                    .zip(reference.data.motion_subspace[b].iter())
                    .chain(work.chunk.data.spatial_inertia[b].iter().zip(reference.data.spatial_inertia[b].iter()));
                for (ours, theirs) in pairs {
                    assert!((ours.re - theirs.re).abs() < 1e-13);
                    let (a, r) = (lanes(ours), lanes(theirs));
                    for l in 0..CHUNK {
                        assert!((a[l] - r[l]).abs() < 1e-12 * (1.0 + r[l].abs()), "body {b}: {} vs {}", a[l], r[l]);
                        checked += (r[l] != 0.0) as usize;
                    }
                }
            }
            assert_eq!(work.chunk.u, reference.u);
            assert_eq!(work.chunk.q, reference.q);
        }
        assert!(checked > 500, "the comparison covered {checked} non-zero derivatives");
    }
}
