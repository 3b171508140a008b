//! The Generalized Jacobian Matrix formulation: `H*`, `c*`, `J*`, the momentum map and the
//! reduced joint-space dynamics (paper §4–5, eqs. 39–50 and 104–111; docs/physics.md).
//!
//! All functions here take their inertia blocks from the CRBA mass matrix and invert `H0` by
//! the closed-form Schur complement; nothing inverts a 6×6 matrix numerically.
//!
//! Implementation: with `H0m = [A; B]` (rows 0–2 and 3–5), `C = B − r̃_0g A` (the coupling
//! about the system CM) and `Y = S⁻¹ C`, the closed form of `H0⁻¹` (eqs. 52–53) gives
//! `H0⁻¹ H0m = [A/M + r̃_0g Y; Y]`, hence
//! - `H* = H_m − AᵀA/M − Cᵀ S⁻¹ C` (symmetric by construction),
//! - `J* = J_mX − [A/M + (r_0g − r_0X) × Y; Y]`,
//! - `H0mᵀ H0⁻¹ w = Aᵀ w_lin / M + Cᵀ S⁻¹ (w_ang − r_0g × w_lin)`,
//!
//! all column by column in O(N) or O(N²) with no dense 6×N or N×N temporaries. The `compute_*`
//! functions leave their result in [`Data`] and allocate nothing; the functions returning owned
//! matrices are thin copies of them.
//!
//! Imports: `math`, `model` and `algorithms`.

use nalgebra::{DMatrix, DVector, Matrix6, Vector3, Vector6};

use crate::algorithms::crba::crba_after_kinematics;
use crate::model::data::{Data, DataT};
use crate::error::{Result, SpacearmError};
use crate::algorithms::inertia::BaseInverse;
use crate::model::joint::JointType;
use crate::algorithms::kinematics::{check_body, check_joint_vector, check_velocity, forward_kinematics, point_position};
use crate::model::Model;
use crate::math::scalar::Real;
use crate::algorithms::passive::add_joint_passive_forces;
use crate::algorithms::rnea::rnea_after_kinematics;
use crate::math::spatial::spatial;

/// The blocks `H0` (6×6), `H0m` (6×N), `H_m` (N×N) of a mass matrix.
pub fn split_mass_matrix(h: &DMatrix<f64>) -> (Matrix6<f64>, DMatrix<f64>, DMatrix<f64>) {
    let n = h.nrows() - 6;
    (
        h.fixed_view::<6, 6>(0, 0).into_owned(),
        h.view((0, 6), (6, n)).into_owned(),
        h.view((6, 6), (n, n)).into_owned(),
    )
}

/// Forward kinematics, CRBA (the joint block only if `joint_block`) and the factored `H0⁻¹`.
fn reduce(model: &Model, data: &mut Data, x: &[f64], joint_block: bool) -> Result<BaseInverse<f64>> {
    forward_kinematics(model, data, x)?;
    reduce_after_kinematics(model, data, joint_block)
}

/// CRBA (the joint block only if `joint_block`) and the factored `H0⁻¹` on the kinematics
/// already in `data`, any scalar.
pub(crate) fn reduce_after_kinematics<T: Real>(model: &Model, data: &mut DataT<T>, joint_block: bool) -> Result<BaseInverse<T>> {
    crba_after_kinematics(model, data, joint_block)?;
    BaseInverse::new(&data.subtree_inertia[0])
}

/// Column `j` of `H0m` as `(A_j, B_j)`. Requires CRBA.
#[inline]
fn h0m_column<T: Real>(data: &DataT<T>, j: usize) -> (Vector3<T>, Vector3<T>) {
    let c = data.mass_matrix.column(6 + j);
    (Vector3::new(c[0], c[1], c[2]), Vector3::new(c[3], c[4], c[5]))
}

/// Fill `data.work_lin[j] = A_j`, `data.work_ang[j] = C_j = B_j − r_0g × A_j`,
/// `data.work_y[j] = S⁻¹ C_j` for every dof. Requires CRBA.
pub(crate) fn reduction_columns<T: Real>(model: &Model, data: &mut DataT<T>, inv: &BaseInverse<T>) {
    for j in 0..model.n_dof() {
        let (a, b) = h0m_column(data, j);
        let c = b - inv.base_to_com.cross(&a);
        data.work_lin[j] = a;
        data.work_ang[j] = c;
        data.work_y[j] = inv.schur_inverse * c;
    }
}

/// `H0mᵀ H0⁻¹ w` added with factor `sign` into `out` (length N), any scalar. Requires
/// [`reduction_columns`].
pub(crate) fn add_h0m_t_h0_inv<T: Real>(model: &Model, data: &DataT<T>, inv: &BaseInverse<T>, w: &Vector6<T>, sign: f64, out: &mut DVector<T>) {
    let (w_lin, w_ang) = (w.fixed_rows::<3>(0).into_owned(), w.fixed_rows::<3>(3).into_owned());
    let y = inv.angular(&w_lin, &w_ang);
    let w_lin_m = w_lin / inv.total_mass;
    let sign = T::c(sign);
    for j in 0..model.n_dof() {
        out[j] += sign * (data.work_lin[j].dot(&w_lin_m) + data.work_ang[j].dot(&y));
    }
}

/// Generalized inertia matrix `H* = H_m − H0mᵀ H0⁻¹ H0m` (N×N, paper eq. 45), left in
/// `data.generalized_inertia`.
pub fn compute_generalized_inertia<'d>(model: &Model, data: &'d mut Data, x: &[f64]) -> Result<&'d DMatrix<f64>> {
    let inv = reduce(model, data, x, true)?;
    reduction_columns(model, data, &inv);
    fill_generalized_inertia(model, data, &inv, false)?;
    Ok(&data.generalized_inertia)
}

/// `H*` from the CRBA matrix and [`reduction_columns`] into `data.generalized_inertia`, or into
/// `data.factor_n` if `into_factor`; any scalar.
pub(crate) fn fill_generalized_inertia<T: Real>(model: &Model, data: &mut DataT<T>, inv: &BaseInverse<T>, into_factor: bool) -> Result<()> {
    data.ensure_generalized_inertia(into_factor)?;
    let n = model.n_dof();
    let m = inv.total_mass;
    let (h, a, c, y) = (&data.mass_matrix, &data.work_lin, &data.work_ang, &data.work_y);
    let out = if into_factor { &mut data.factor_n } else { &mut data.generalized_inertia };
    for j in 0..n {
        let a_j = a[j] / m;
        for i in 0..=j {
            let v = h[(6 + i, 6 + j)] - a[i].dot(&a_j) - c[i].dot(&y[j]);
            out[(i, j)] = v;
            out[(j, i)] = v;
        }
    }
    Ok(())
}

/// Generalized inertia matrix `H* = H_m − H0mᵀ H0⁻¹ H0m` (N×N, paper eq. 45).
pub fn generalized_inertia(model: &Model, data: &mut Data, x: &[f64]) -> Result<DMatrix<f64>> {
    Ok(compute_generalized_inertia(model, data, x)?.clone())
}

/// Generalized bias `c* = c_m − H0mᵀ H0⁻¹ c0` (N, paper eq. 46 with the base velocity `u[0..6]`
/// taken as given), left in `data.generalized_bias`.
pub fn compute_generalized_bias<'d>(model: &Model, data: &'d mut Data, x: &[f64], u: &[f64]) -> Result<&'d DVector<f64>> {
    let inv = reduce(model, data, x, false)?;
    check_velocity(model, "u", u)?;
    generalized_bias_after_reduction(model, data, &inv, u);
    Ok(&data.generalized_bias)
}

/// `c*` into `data.generalized_bias` from the base rows of the CRBA matrix and `H0⁻¹` (`u`
/// checked), any scalar: RNEA at `u̇ = 0`, then `c_m − H0mᵀ H0⁻¹ c0`.
pub(crate) fn generalized_bias_after_reduction<T: Real>(model: &Model, data: &mut DataT<T>, inv: &BaseInverse<T>, u: &[T]) {
    rnea_after_kinematics(model, data, u, None, &[]);
    reduction_columns(model, data, inv);
    let n = model.n_dof();
    let c0 = data.tau.fixed_rows::<6>(0).into_owned();
    let mut out = std::mem::take(&mut data.generalized_bias);
    out.copy_from(&data.tau.rows(6, n));
    add_h0m_t_h0_inv(model, data, inv, &c0, -1.0, &mut out);
    data.generalized_bias = out;
}

/// Generalized bias `c* = c_m − H0mᵀ H0⁻¹ c0` (N, paper eq. 46 with the base velocity `u[0..6]`
/// taken as given).
pub fn generalized_bias(model: &Model, data: &mut Data, x: &[f64], u: &[f64]) -> Result<DVector<f64>> {
    Ok(compute_generalized_bias(model, data, x, u)?.clone())
}

/// Generalized Jacobian `J* = J_mX − J_0X H0⁻¹ H0m` (6×N, paper eq. 110) of a point fixed to
/// `body` at `offset` (body frame, from its CM), left in `data.generalized_jacobian`. Needs only
/// the base rows of `H` (O(N)), and `J_mX` only on the path from the base to `body`.
pub fn compute_generalized_jacobian<'d>(
    model: &Model,
    data: &'d mut Data,
    x: &[f64],
    body: usize,
    offset: &Vector3<f64>,
) -> Result<&'d DMatrix<f64>> {
    let inv = reduce(model, data, x, false)?;
    check_body(model, body)?;
    generalized_jacobian_after_reduction(model, data, &inv, body, offset)?;
    Ok(&data.generalized_jacobian)
}

/// `J*` into `data.generalized_jacobian` from the base rows of the CRBA matrix and `H0⁻¹`
/// (`body` checked), any scalar.
pub(crate) fn generalized_jacobian_after_reduction<T: Real>(
    model: &Model,
    data: &mut DataT<T>,
    inv: &BaseInverse<T>,
    body: usize,
    offset: &Vector3<f64>,
) -> Result<()> {
    data.ensure_generalized_jacobian()?;
    let point = point_position(data, body, offset);
    // J_0X H0⁻¹ H0m, column j: [A_j/M + (r_0g − r_0X) × Y_j; Y_j].
    let e = inv.base_to_com - (point - data.base_position);
    let m = inv.total_mass;
    for j in 0..model.n_dof() {
        let (a, b) = h0m_column(data, j);
        let y = inv.schur_inverse * (b - inv.base_to_com.cross(&a));
        let lin = a / m + e.cross(&y);
        let mut col = data.generalized_jacobian.column_mut(j);
        col[0] = -lin.x;
        col[1] = -lin.y;
        col[2] = -lin.z;
        col[3] = -y.x;
        col[4] = -y.y;
        col[5] = -y.z;
    }
    // + J_mX on the path (paper eq. 106).
    let mut b = body;
    while b != 0 {
        if let Some(d) = model.dof_of_body(b) {
            let k = data.joint_axis_in_world[b];
            let mut col = data.generalized_jacobian.column_mut(d);
            match model.links()[b - 1].joint.kind {
                JointType::Revolute => {
                    let lin = k.cross(&(point - data.joint_position_in_world[b]));
                    col[0] += lin.x;
                    col[1] += lin.y;
                    col[2] += lin.z;
                    col[3] += k.x;
                    col[4] += k.y;
                    col[5] += k.z;
                }
                _ => {
                    col[0] += k.x;
                    col[1] += k.y;
                    col[2] += k.z;
                }
            }
        }
        b = model.links()[b - 1].parent;
    }
    Ok(())
}

/// Generalized Jacobian `J* = J_mX − J_0X H0⁻¹ H0m` (6×N, paper eq. 110) of a point fixed to
/// `body` at `offset` (body frame, from its CM): with zero system momentum, the point's twist
/// `[v_X; ω]` in 𝒥 is `J* q̇`.
pub fn generalized_jacobian(model: &Model, data: &mut Data, x: &[f64], body: usize, offset: &Vector3<f64>) -> Result<DMatrix<f64>> {
    Ok(compute_generalized_jacobian(model, data, x, body, offset)?.clone())
}

/// Base momentum vector `M0 = [P; L_base]` from the linear momentum and the angular momentum
/// about the origin of 𝒥: `L_base = L_origin − r0 × P`.
fn momentum_about_base<T: Real>(data: &DataT<T>, linear: &Vector3<T>, angular_about_origin: &Vector3<T>) -> Vector6<T> {
    spatial(linear, &(angular_about_origin - data.base_position.cross(linear)))
}

fn check3(what: &str, v: &Vector3<f64>) -> Result<()> {
    crate::error::check_finite(what, v.as_slice())
}

/// Base velocity `ẋ0 = H0⁻¹ (M0 − H0m q̇)` (paper eq. 43/109) that gives the system the
/// linear momentum `P` and the angular momentum `L_origin` (about the origin of 𝒥) while the
/// joints move at `q̇`.
pub fn base_velocity_from_momentum(
    model: &Model,
    data: &mut Data,
    x: &[f64],
    qd: &[f64],
    linear_momentum: &Vector3<f64>,
    angular_momentum_origin: &Vector3<f64>,
) -> Result<Vector6<f64>> {
    check_joint_vector(model, "qd", qd)?;
    check3("linear momentum", linear_momentum)?;
    check3("angular momentum", angular_momentum_origin)?;
    let inv = reduce(model, data, x, false)?;
    Ok(base_velocity_after_reduction(data, &inv, qd, linear_momentum, angular_momentum_origin))
}

/// `H0⁻¹ (M0 − H0m q̇)` from the base rows of the CRBA matrix and `H0⁻¹`, any scalar.
pub(crate) fn base_velocity_after_reduction<T: Real>(
    data: &DataT<T>,
    inv: &BaseInverse<T>,
    qd: &[T],
    linear_momentum: &Vector3<T>,
    angular_momentum_origin: &Vector3<T>,
) -> Vector6<T> {
    let mut w = momentum_about_base(data, linear_momentum, angular_momentum_origin);
    for (j, &qdj) in qd.iter().enumerate() {
        w -= data.mass_matrix.fixed_view::<6, 1>(0, 6 + j) * qdj;
    }
    inv.apply(&w)
}

/// The momentum term of the point twist with non-zero system momentum:
/// `[v_X; ω] = J* q̇ + J_0X H0⁻¹ M0` — this returns `J_0X H0⁻¹ M0`.
pub fn momentum_twist(
    model: &Model,
    data: &mut Data,
    x: &[f64],
    body: usize,
    offset: &Vector3<f64>,
    linear_momentum: &Vector3<f64>,
    angular_momentum_origin: &Vector3<f64>,
) -> Result<Vector6<f64>> {
    check3("linear momentum", linear_momentum)?;
    check3("angular momentum", angular_momentum_origin)?;
    let inv = reduce(model, data, x, false)?;
    check_body(model, body)?;
    let d = point_position(data, body, offset) - data.base_position;
    let t = inv.apply(&momentum_about_base(data, linear_momentum, angular_momentum_origin));
    let (t_lin, t_ang) = (t.fixed_rows::<3>(0).into_owned(), t.fixed_rows::<3>(3).into_owned());
    Ok(spatial(&(t_lin - d.cross(&t_ang)), &t_ang))
}

/// Reduced joint-space forward dynamics (docs/physics.md): with base wrench `F_b = [F0; N0]`,
/// `q̈ = H*⁻¹ (τ − c* − H0mᵀ H0⁻¹ F_b)` and `ẍ0 = H0⁻¹ (F_b − H0m q̈ − c0)`, left in
/// `data.accel`. See [`reduced_forward_dynamics`].
pub fn compute_reduced_forward_dynamics<'d>(
    model: &Model,
    data: &'d mut Data,
    x: &[f64],
    u: &[f64],
    tau: &[f64],
    base_wrench: &Vector6<f64>,
) -> Result<&'d DVector<f64>> {
    check_velocity(model, "u", u)?;
    check_joint_vector(model, "tau", tau)?;
    crate::error::check_finite("base wrench", base_wrench.as_slice())?;
    let inv = reduce(model, data, x, true)?;
    rnea_after_kinematics(model, data, u, None, &[]);
    reduction_columns(model, data, &inv);
    fill_generalized_inertia(model, data, &inv, true)?;
    let n = model.n_dof();
    // τ − c* − H0mᵀ H0⁻¹ F_b = τ − c_m − H0mᵀ H0⁻¹ (F_b − c0).
    let w = base_wrench - data.tau.fixed_rows::<6>(0);
    let mut rhs = std::mem::take(&mut data.work_n);
    for j in 0..n {
        rhs[j] = tau[j] - data.tau[6 + j];
    }
    // The joints' springs and dampers act as a joint force (docs/flexibility.md).
    add_joint_passive_forces(model, &x[7..], &u[6..], rhs.as_mut_slice());
    add_h0m_t_h0_inv(model, data, &inv, &w, -1.0, &mut rhs);
    let factor = std::mem::take(&mut data.factor_n);
    let Some(chol) = factor.cholesky() else {
        data.factor_n = DMatrix::zeros(n, n);
        data.work_n = rhs;
        return Err(SpacearmError::Singular("the generalized inertia matrix H*".into()));
    };
    chol.solve_mut(&mut rhs);
    data.factor_n = chol.unpack_dirty();
    // ẍ0 = H0⁻¹ (F_b − c0 − H0m q̈).
    let mut g = w;
    for (j, &qdd) in rhs.iter().enumerate() {
        g -= data.mass_matrix.fixed_view::<6, 1>(0, 6 + j) * qdd;
    }
    let base_acc = inv.apply(&g);
    data.accel.fixed_rows_mut::<6>(0).copy_from(&base_acc);
    data.accel.rows_mut(6, n).copy_from(&rhs);
    data.work_n = rhs;
    Ok(&data.accel)
}

/// Reduced joint-space forward dynamics (docs/physics.md): with base wrench `F_b = [F0; N0]`,
/// `q̈ = H*⁻¹ (τ − c* − H0mᵀ H0⁻¹ F_b)` and `ẍ0 = H0⁻¹ (F_b − H0m q̈ − c0)`. `F_b = 0` is the
/// floating case (eq. 50 generalized to a moving base). Returns the full `u̇ = [ẍ0; q̈]`, which
/// equals the ABA result for `f = [F_b; τ]`.
pub fn reduced_forward_dynamics(
    model: &Model,
    data: &mut Data,
    x: &[f64],
    u: &[f64],
    tau: &[f64],
    base_wrench: &Vector6<f64>,
) -> Result<DVector<f64>> {
    Ok(compute_reduced_forward_dynamics(model, data, x, u, tau, base_wrench)?.clone())
}
