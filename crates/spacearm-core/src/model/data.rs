//! Preallocated workspace and results for one [`Model`] (Pinocchio's Model/Data split).
//!
//! Every algorithm fills the fields it documents; vectors are indexed by body (0 = base).
//! Spatial quantities use world (𝒥) axes and the base CM at the current instant as reference
//! point (see [`crate::math::spatial`]).
//!
//! The workspace is generic over the scalar ([`Real`]): users and the `f64` algorithms use
//! [`Data`] `= DataT<T>`; [`crate::derivatives`] runs the same algorithms on a `DataT` of dual
//! numbers.
//!
//! Memory: everything indexed by body or degree of freedom is allocated with the workspace
//! (O(N)); the dense matrices (`mass_matrix`, `generalized_inertia`, `generalized_jacobian`
//! and the factorization scratch) start empty and are sized by the first algorithm that needs
//! them, after [`crate::admission`] has admitted their size. So a model of 10⁵ links builds and
//! runs kinematics, RNEA and ABA in O(N) memory, and a dense request too large for the machine
//! is refused with a clear error instead of aborting.

use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Vector3, Vector6};

use crate::admission::{admit, bytes_of};
use crate::error::Result;
use crate::model::Model;
use crate::math::scalar::Real;

/// Workspace and results of the algorithms for one model, in `f64`.
pub type Data = DataT<f64>;

/// Workspace and results of the algorithms for one model, with scalar `T`.
#[derive(Debug, Clone)]
pub struct DataT<T: Real> {
    /// Base CM position `r0` in 𝒥 (filled by forward kinematics).
    pub base_position: Vector3<T>,
    /// Rotation of each body frame to 𝒥 (`R0` for the base).
    pub body_to_world: Vec<Matrix3<T>>,
    /// CM position `rᵢ` of each body in 𝒥.
    pub com_in_world: Vec<Vector3<T>>,
    /// Position `pᵢ` in 𝒥 of the joint moving each body (the base entry is `r0`).
    pub joint_position_in_world: Vec<Vector3<T>>,
    /// Unit axis `kᵢ` in 𝒥 of the joint moving each body (zero for the base).
    pub joint_axis_in_world: Vec<Vector3<T>>,
    /// Motion subspace `Sᵢ` of each joint at the base CM (zero for the base and fixed joints):
    /// `[(pᵢ − r0) × kᵢ; kᵢ]` revolute, `[kᵢ; 0]` prismatic.
    pub motion_subspace: Vec<Vector6<T>>,
    /// Inertia of each body about its CM in 𝒥 axes, `Rᵢ Iᵢ Rᵢᵀ`.
    pub inertia_in_world: Vec<Matrix3<T>>,
    /// Spatial inertia of each body at the base CM (𝒥 axes).
    pub spatial_inertia: Vec<Matrix6<T>>,
    /// Spatial velocity of each body at the base CM.
    pub body_velocity: Vec<Vector6<T>>,
    /// Spatial acceleration of each body at the base CM.
    pub body_acceleration: Vec<Vector6<T>>,
    /// Velocity-product acceleration `Vᵢ ×ₘ Sᵢ q̇ᵢ` of each joint.
    pub velocity_product: Vec<Vector6<T>>,
    /// Spatial force transmitted across each joint (RNEA) or articulated bias force (ABA).
    pub body_force: Vec<Vector6<T>>,
    /// Composite (CRBA) or articulated (ABA) inertia of each subtree.
    pub subtree_inertia: Vec<Matrix6<T>>,
    /// ABA: `Uᵢ = Iᴬᵢ Sᵢ`.
    pub(crate) aba_u: Vec<Vector6<T>>,
    /// ABA: `Dᵢ = Sᵢᵀ Uᵢ` and `uᵢ = τᵢ − Sᵢᵀ pᴬᵢ`.
    pub(crate) aba_d: Vec<T>,
    pub(crate) aba_small_u: Vec<T>,
    /// Joint-space mass matrix `H` (6+N square; empty until the first CRBA), filled by CRBA. The routines that need only
    /// the base rows (`J*`, `c*`, the momentum map) refresh `[H0, H0m]` and leave `H_m` stale.
    pub mass_matrix: DMatrix<T>,
    /// Generalized force or acceleration result (6+N), filled by RNEA / ABA.
    pub tau: DVector<T>,
    /// Generalized acceleration `u̇` (6+N), filled by the forward-dynamics routines.
    pub accel: DVector<T>,
    /// Generalized inertia matrix `H*` (N×N; empty until first filled), filled by [`crate::gjm::compute_generalized_inertia`].
    pub generalized_inertia: DMatrix<T>,
    /// Generalized Jacobian `J*` (6×N; empty until first filled), filled by [`crate::gjm::compute_generalized_jacobian`].
    pub generalized_jacobian: DMatrix<T>,
    /// Generalized bias `c*` (N), filled by [`crate::gjm::compute_generalized_bias`].
    pub generalized_bias: DVector<T>,
    /// Scratch: a (6+N)² or N² matrix factorized in place by the dense forward-dynamics routes.
    pub(crate) factor: DMatrix<T>,
    /// Scratch: an N-vector.
    pub(crate) work_n: DVector<T>,
    /// Scratch: per-dof 3-vectors (joint-side columns, reduction intermediates).
    pub(crate) work_lin: Vec<Vector3<T>>,
    pub(crate) work_ang: Vec<Vector3<T>>,
    pub(crate) work_y: Vec<Vector3<T>>,
    /// Scratch: degree-of-freedom indices along a path to the base.
    pub(crate) work_dofs: Vec<usize>,
    /// Scratch: an N² matrix factorized in place by the reduced dynamics.
    pub(crate) factor_n: DMatrix<T>,
}

impl<T: Real> DataT<T> {
    /// Allocate a workspace for `model`.
    pub fn new(model: &Model) -> Self {
        let nb = model.n_bodies();
        let nu = model.nu();
        DataT {
            base_position: Vector3::zeros(),
            body_to_world: vec![Matrix3::identity(); nb],
            com_in_world: vec![Vector3::zeros(); nb],
            joint_position_in_world: vec![Vector3::zeros(); nb],
            joint_axis_in_world: vec![Vector3::zeros(); nb],
            motion_subspace: vec![Vector6::zeros(); nb],
            inertia_in_world: vec![Matrix3::zeros(); nb],
            spatial_inertia: vec![Matrix6::zeros(); nb],
            body_velocity: vec![Vector6::zeros(); nb],
            body_acceleration: vec![Vector6::zeros(); nb],
            velocity_product: vec![Vector6::zeros(); nb],
            body_force: vec![Vector6::zeros(); nb],
            subtree_inertia: vec![Matrix6::zeros(); nb],
            aba_u: vec![Vector6::zeros(); nb],
            aba_d: vec![T::zero(); nb],
            aba_small_u: vec![T::zero(); nb],
            mass_matrix: DMatrix::zeros(0, 0),
            tau: DVector::zeros(nu),
            accel: DVector::zeros(nu),
            generalized_inertia: DMatrix::zeros(0, 0),
            generalized_jacobian: DMatrix::zeros(0, 0),
            generalized_bias: DVector::zeros(nu - 6),
            factor: DMatrix::zeros(0, 0),
            work_n: DVector::zeros(nu - 6),
            work_lin: vec![Vector3::zeros(); nu - 6],
            work_ang: vec![Vector3::zeros(); nu - 6],
            work_y: vec![Vector3::zeros(); nu - 6],
            work_dofs: Vec::with_capacity(nu - 6),
            factor_n: DMatrix::zeros(0, 0),
        }
    }

    /// The dimension `6+N` of the velocity space.
    #[inline]
    fn nu(&self) -> usize {
        self.tau.len()
    }

    /// Size `data.mass_matrix` to `(6+N)²` (once; admitted first).
    #[inline]
    pub(crate) fn ensure_mass_matrix(&mut self) -> Result<()> {
        let nu = self.nu();
        ensure_dense::<T>(&mut self.mass_matrix, nu, nu, "the mass matrix H")
    }

    /// Size the `(6+N)²` factorization scratch (once; admitted first).
    #[inline]
    pub(crate) fn ensure_factor(&mut self) -> Result<()> {
        let nu = self.nu();
        ensure_dense::<T>(&mut self.factor, nu, nu, "the factorization of the mass matrix H")
    }

    /// Size `generalized_inertia` (or, with `into_factor`, its N² factorization scratch).
    #[inline]
    pub(crate) fn ensure_generalized_inertia(&mut self, into_factor: bool) -> Result<()> {
        let n = self.nu() - 6;
        let m = if into_factor { &mut self.factor_n } else { &mut self.generalized_inertia };
        ensure_dense::<T>(m, n, n, "the generalized inertia matrix H*")
    }

    /// Size `generalized_jacobian` to 6×N (once).
    #[inline]
    pub(crate) fn ensure_generalized_jacobian(&mut self) -> Result<()> {
        let n = self.nu() - 6;
        ensure_dense::<T>(&mut self.generalized_jacobian, 6, n, "the generalized Jacobian J*")
    }
}

/// Give `m` the shape `rows × cols` (zeros) unless it has it already, after admitting its size.
/// Every call of an algorithm that fills a dense matrix passes here: the test of the shape is
/// inlined, the sizing (once per workspace) is not.
#[inline(always)]
fn ensure_dense<T: Real>(m: &mut DMatrix<T>, rows: usize, cols: usize, what: &str) -> Result<()> {
    if m.shape() == (rows, cols) {
        return Ok(());
    }
    resize_dense(m, rows, cols, what)
}

#[cold]
#[inline(never)]
fn resize_dense<T: Real>(m: &mut DMatrix<T>, rows: usize, cols: usize, what: &str) -> Result<()> {
    admit(
        format_args!("{what} ({rows}×{cols})"),
        bytes_of::<T>(rows as f64 * cols as f64),
        "use the O(N) algorithms instead (ABA forward dynamics, RNEA, kinematics) or a smaller model",
    )?;
    *m = DMatrix::zeros(rows, cols);
    Ok(())
}
