//! The contact Jacobian and the Delassus operator of a set of point contacts between bodies of a
//! model (docs/contact.md, "Rigid frictional impacts").
//!
//! Point `i` joins body `a` and body `b` at the point `pᵢ` (in 𝒥) with the unit normal `nᵢ` from
//! `a` towards `b`. Its contact frame `Rᵢ = [t₁, t₂, n]` (columns; [`contact_frame`]) orders its
//! three rows tangents first, as the cone of coulomb_cone.rs does. Its rows of the contact
//! Jacobian give the velocity of the material point of `b` at `pᵢ` relative to that of `a`, in
//! the contact frame:
//!
//! `Jᵢ = Rᵢᵀ (J_v,b(pᵢ) − J_v,a(pᵢ))`,  `J_v,k(p) = [E, −(p − r₀)~, J_T,k(p)]`
//!
//! (3 × (6+N); the translational rows of the point Jacobians `[J_0X, J_mX]` of docs/equations.md,
//! eqs. 104–108). The **Delassus operator** is the inverse inertia the contacts see,
//!
//! `G = J H⁻¹ Jᵀ`
//!
//! (3k × 3k, `H` the system's (6+N)² mass matrix — the floating base's, in every maneuvering mode:
//! during an impact the finite base wrench a mode allows does no work, so all five share `H`);
//! `Δu = H⁻¹ Jᵀ λ` is the velocity jump of the impulses `λ`. Both bodies are in the system, so
//! the base's columns of `J` cancel (`J_v,b − J_v,a` has only joint columns) and
//! `G = J_m H*⁻¹ J_mᵀ` with the generalized inertia matrix `H*` (eq. 49): the base's free motion is
//! what makes the contacts feel `H*` rather than the joints' block of `H`.
//!
//! Imports: [`crate::algorithms`] (kinematics, impulse: the Cholesky factorisation of `H`).

use nalgebra::{DMatrix, Matrix3, Vector3};

use crate::algorithms::impulse::{contact_response, JointsAtImpact};
use crate::algorithms::kinematics::{check_body, forward_kinematics, point_jacobians};
use crate::error::{check_finite, Result, SpacearmError};
use crate::model::data::Data;
use crate::model::Model;

/// A point contact between two bodies of a model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint {
    /// The first and second body (indices, 0 = base).
    pub body: [usize; 2],
    /// The contact point in 𝒥, m.
    pub point: Vector3<f64>,
    /// The unit normal from the first body towards the second, in 𝒥.
    pub normal: Vector3<f64>,
    /// Coulomb's `μ` (≥ 0).
    pub friction: f64,
}

/// The contact frame of the unit normal `n`: the columns `[t₁, t₂, n]`, right-handed, with
/// `t₁ = n × e / ‖n × e‖` for `e` the axis of 𝒥 least aligned with `n` (the first of x, y, z
/// on ties) and `t₂ = n × t₁`.
pub fn contact_frame(normal: &Vector3<f64>) -> Matrix3<f64> {
    let n = normal;
    let k = (0..3).min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs())).unwrap_or(0);
    let t1 = n.cross(&Vector3::ith(k, 1.0)).normalize();
    let t2 = n.cross(&t1);
    Matrix3::from_columns(&[t1, t2, *n])
}

/// Check the points against `model`: bodies that exist and differ, finite points, unit normals
/// (to 1e-9), friction ≥ 0.
pub fn check_points(model: &Model, points: &[ContactPoint]) -> Result<()> {
    if points.is_empty() {
        return Err(SpacearmError::argument("no contact point: give at least one"));
    }
    for (i, p) in points.iter().enumerate() {
        check_body(model, p.body[0])?;
        check_body(model, p.body[1])?;
        if p.body[0] == p.body[1] {
            return Err(SpacearmError::argument(format!("contact {i} joins body {} to itself (a body does not touch itself)", p.body[0])));
        }
        check_finite(&format!("the point of contact {i}"), p.point.as_slice())?;
        check_finite(&format!("the normal of contact {i}"), p.normal.as_slice())?;
        if (p.normal.norm() - 1.0).abs() > 1e-9 {
            return Err(SpacearmError::argument(format!("the normal of contact {i} must be a unit vector, got norm {}", p.normal.norm())));
        }
        if !(p.friction.is_finite() && p.friction >= 0.0) {
            return Err(SpacearmError::argument(format!("the friction coefficient of contact {i} must be finite and >= 0, got {}", p.friction)));
        }
    }
    Ok(())
}

/// The contact Jacobian (3k × (6+N), module docs) of `points` on the kinematics in `data`
/// (forward kinematics done). Points checked by the caller ([`check_points`]).
pub fn contact_jacobian(model: &Model, data: &Data, points: &[ContactPoint]) -> Result<DMatrix<f64>> {
    let mut j = DMatrix::zeros(3 * points.len(), model.nu());
    for (i, p) in points.iter().enumerate() {
        let frame = contact_frame(&p.normal);
        let mut rel = DMatrix::zeros(3, model.nu());
        for (side, sign) in [(1, 1.0), (0, -1.0)] {
            let body = p.body[side];
            // The offset from the body's CM, in its frame, of the world point p.
            let offset = data.body_to_world[body].transpose() * (p.point - data.com_in_world[body]);
            let (j0, jm) = point_jacobians(model, data, body, &offset)?;
            let mut base = rel.view_mut((0, 0), (3, 6));
            base += j0.fixed_view::<3, 6>(0, 0) * sign;
            let mut joints = rel.view_mut((0, 6), (3, model.n_dof()));
            joints += jm.rows(0, 3) * sign;
        }
        j.view_mut((3 * i, 0), (3, model.nu())).copy_from(&(frame.transpose() * rel));
    }
    Ok(j)
}

/// The contact Jacobian, the Delassus operator and the velocity map of a set of contacts.
#[derive(Debug, Clone, PartialEq)]
pub struct Delassus {
    /// The contact frames `[t₁, t₂, n]` of the points (columns, in 𝒥).
    pub frames: Vec<Matrix3<f64>>,
    /// `J` (3k × (6+N)).
    pub jacobian: DMatrix<f64>,
    /// `G = J H⁻¹ Jᵀ` (3k × 3k).
    pub delassus: DMatrix<f64>,
    /// `H⁻¹ Jᵀ` ((6+N) × 3k): `Δu = response · λ`.
    pub response: DMatrix<f64>,
    /// `H` at the configuration.
    pub mass_matrix: DMatrix<f64>,
}

/// The Delassus operator of `points` at the configuration `x` (module docs).
pub fn delassus(model: &Model, data: &mut Data, x: &[f64], points: &[ContactPoint]) -> Result<Delassus> {
    check_points(model, points)?;
    forward_kinematics(model, data, x)?;
    let jacobian = contact_jacobian(model, data, points)?;
    let r = contact_response(model, data, x, &jacobian, JointsAtImpact::Free)?;
    Ok(Delassus { frames: points.iter().map(|p| contact_frame(&p.normal)).collect(), jacobian, delassus: r.delassus, response: r.response, mass_matrix: r.mass_matrix })
}
