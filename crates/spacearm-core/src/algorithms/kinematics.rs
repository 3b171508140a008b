//! Forward kinematics, point positions and point/link Jacobians (paper §2–3, eqs. 104–108).

use nalgebra::{DMatrix, Matrix3, Matrix6, UnitQuaternion, Vector3, Vector6};

use crate::model::data::{Data, DataT};
use crate::error::{check_finite, Result, SpacearmError};
use crate::model::joint::JointType;
use crate::math::rotations::{axis_angle_rotation, quaternion_from_xyzw, rotate_symmetric, QUATERNION_TOLERANCE};
use crate::model::Model;
use crate::math::scalar::{matrix3, vector3, Real};
use crate::math::spatial::{point_twist_transform, spatial, spatial_inertia};

/// The configuration `x = [r0 (3), quat0 (4, [x, y, z, w]), q (N)]` split into its parts,
/// validated (length, finite values, unit quaternion within [`QUATERNION_TOLERANCE`]); the
/// quaternion is normalized exactly before use.
pub fn split_configuration<'a>(model: &Model, x: &'a [f64]) -> Result<(Vector3<f64>, UnitQuaternion<f64>, &'a [f64])> {
    let n = model.n_dof();
    if x.len() != 7 + n {
        return Err(SpacearmError::Dimension {
            what: "x".into(),
            expected: format!("7+N = {}", 7 + n),
            got: x.len(),
        });
    }
    check_finite("x", x)?;
    let quat = base_quaternion(x)?;
    Ok((Vector3::new(x[0], x[1], x[2]), UnitQuaternion::from_quaternion(quat), &x[7..]))
}

/// The base quaternion `x[3:7]` of a configuration of at least 7 entries, or
/// `NotUnitQuaternion` when its norm is off 1 by more than [`QUATERNION_TOLERANCE`]: the one
/// check of a configuration's quaternion (also what a door applies to a one-state `x` shared
/// by an empty batch, which runs no kernel).
pub fn base_quaternion(x: &[f64]) -> Result<nalgebra::Quaternion<f64>> {
    let quat = quaternion_from_xyzw(&x[3..7]);
    let norm = quat.norm();
    if (norm - 1.0).abs() > QUATERNION_TOLERANCE || norm.is_nan() {
        return Err(SpacearmError::NotUnitQuaternion {
            what: "the base quaternion x[3:7]".into(),
            norm,
            tolerance: QUATERNION_TOLERANCE,
        });
    }
    Ok(quat)
}

/// Check a generalized velocity `u = [v0, ω0, q̇]` (length `6+N`, finite).
pub fn check_velocity(model: &Model, what: &str, u: &[f64]) -> Result<()> {
    if u.len() != model.nu() {
        return Err(SpacearmError::Dimension {
            what: what.into(),
            expected: format!("6+N = {}", model.nu()),
            got: u.len(),
        });
    }
    check_finite(what, u)
}

/// Check a joint-space vector (length `N`, finite).
pub fn check_joint_vector(model: &Model, what: &str, v: &[f64]) -> Result<()> {
    if v.len() != model.n_dof() {
        return Err(SpacearmError::Dimension { what: what.into(), expected: format!("N = {}", model.n_dof()), got: v.len() });
    }
    check_finite(what, v)
}

/// Forward kinematics: fills the poses, joint positions and axes, motion subspaces and world
/// inertias of `data` (paper §2.2: `rᵢ`, `pᵢ`, `kᵢ`, `Rᵢ`).
pub fn forward_kinematics(model: &Model, data: &mut Data, x: &[f64]) -> Result<()> {
    let (r0, quat0, q) = split_configuration(model, x)?;
    forward_kinematics_at(model, data, &r0, &quat0.to_rotation_matrix().into_inner(), q);
    Ok(())
}

/// Forward kinematics from the base pose (`r0`, `R0` = `base_to_world`) and the joint
/// coordinates `q` (length N, unchecked), for any scalar: the one implementation behind
/// [`forward_kinematics`] and the dual-number derivatives of [`crate::derivatives`].
///
/// Always inlined: it has several `f64` callers, and out of line it costs instructions on the
/// path of every per-state call (the measurement: benchmarks/README.md, "Profiler history").
#[inline(always)]
pub fn forward_kinematics_at<T: Real>(model: &Model, data: &mut DataT<T>, r0: &Vector3<T>, base_to_world: &Matrix3<T>, q: &[T]) {
    let r0 = *r0;
    let r0_mat = *base_to_world;
    data.base_position = r0;
    data.body_to_world[0] = r0_mat;
    data.com_in_world[0] = r0;
    data.joint_position_in_world[0] = r0;
    data.joint_axis_in_world[0] = Vector3::zeros();
    data.motion_subspace[0] = Vector6::zeros();
    let base = &model.base();
    let base_inertia = rotate_symmetric(&r0_mat, &matrix3(&base.inertia));
    data.inertia_in_world[0] = base_inertia;
    data.spatial_inertia[0] = spatial_inertia(T::c(base.mass), &Vector3::zeros(), &base_inertia);

    for (k, link) in model.links().iter().enumerate() {
        let b = k + 1;
        let p = link.parent;
        let parent_rot = data.body_to_world[p];
        let joint = &link.joint;
        let joint_pos = data.com_in_world[p] + parent_rot * vector3(&joint.origin_in_parent);
        let rq = &joint.rotation_in_parent;
        // Most models attach joints without a fixed rotation: skip the product then.
        let joint_rot = if rq.i == 0.0 && rq.j == 0.0 && rq.k == 0.0 {
            parent_rot
        } else {
            parent_rot * matrix3(&rq.to_rotation_matrix().into_inner())
        };
        let axis = vector3(&joint.axis.into_inner());
        let axis_world = joint_rot * axis;
        let (rot, com_local, axis_out, subspace) = match joint.kind {
            JointType::Revolute => {
                let angle = q[model.dof_of_body(b).expect("revolute joint has a dof")];
                // A joint at exactly zero (with no derivative part) adds no rotation.
                let rot = if angle.is_exactly_zero() { joint_rot } else { joint_rot * axis_angle_rotation(&axis, angle) };
                (rot, vector3(&link.com_from_joint), axis_world, spatial(&(joint_pos - r0).cross(&axis_world), &axis_world))
            }
            JointType::Prismatic => {
                let d = q[model.dof_of_body(b).expect("prismatic joint has a dof")];
                (joint_rot, vector3(&link.com_from_joint) + axis * d, axis_world, spatial(&axis_world, &Vector3::zeros()))
            }
            JointType::Fixed => (joint_rot, vector3(&link.com_from_joint), Vector3::zeros(), Vector6::zeros()),
        };
        let com = joint_pos + rot * com_local;
        data.body_to_world[b] = rot;
        data.com_in_world[b] = com;
        data.joint_position_in_world[b] = joint_pos;
        data.joint_axis_in_world[b] = axis_out;
        data.motion_subspace[b] = subspace;
        let inertia_world = rotate_symmetric(&rot, &matrix3(&link.mass.inertia));
        data.inertia_in_world[b] = inertia_world;
        data.spatial_inertia[b] = spatial_inertia(T::c(link.mass.mass), &(com - r0), &inertia_world);
    }
}

/// Position in 𝒥 of a point fixed to `body` at `offset` (body frame, from its CM). Requires
/// forward kinematics.
pub fn point_position<T: Real>(data: &DataT<T>, body: usize, offset: &Vector3<f64>) -> Vector3<T> {
    data.com_in_world[body] + data.body_to_world[body] * vector3(offset)
}

/// A point fixed to a body: body index and offset from its CM in its frame (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyPoint {
    /// Body index (0 = base).
    pub body: usize,
    /// Offset from the body's CM, in its frame, m.
    pub offset: Vector3<f64>,
}

/// Check a body index against the model.
pub fn check_body(model: &Model, body: usize) -> Result<()> {
    if body >= model.n_bodies() {
        return Err(SpacearmError::NotFound(format!(
            "body index {body} does not exist (the model has bodies 0..={})",
            model.n_bodies() - 1
        )));
    }
    Ok(())
}

/// Joint-side point Jacobian `J_mX` (6×N, paper eq. 106) of the point at world position
/// `point` fixed to `body`: column `j` is `[kⱼ × (x − pⱼ); kⱼ]` (revolute) or `[kⱼ; 0]`
/// (prismatic) for every joint on the path from the base to `body`, zero elsewhere.
/// Requires forward kinematics.
pub fn joint_jacobian_of_point<T: Real>(model: &Model, data: &DataT<T>, body: usize, point: &Vector3<T>) -> DMatrix<T> {
    let mut jm = DMatrix::zeros(6, model.n_dof());
    let mut b = body;
    while b != 0 {
        if let Some(d) = model.dof_of_body(b) {
            let k = data.joint_axis_in_world[b];
            let lin = match model.links()[b - 1].joint.kind {
                JointType::Revolute => k.cross(&(point - data.joint_position_in_world[b])),
                _ => k,
            };
            let ang = if model.links()[b - 1].joint.kind == JointType::Revolute { k } else { Vector3::zeros() };
            jm.fixed_view_mut::<3, 1>(0, d).copy_from(&lin);
            jm.fixed_view_mut::<3, 1>(3, d).copy_from(&ang);
        }
        b = model.links()[b - 1].parent;
    }
    jm
}

/// Both point Jacobians of a point fixed to `body` at `offset` (paper eqs. 104–108):
/// `J_0X = [[E, −r̃_0X], [0, E]]` (6×6) and `J_mX` (6×N), so that the point's twist
/// `[v_X; ω]` is `J_0X ẋ0 + J_mX q̇`. Requires forward kinematics.
pub fn point_jacobians(model: &Model, data: &Data, body: usize, offset: &Vector3<f64>) -> Result<(Matrix6<f64>, DMatrix<f64>)> {
    check_body(model, body)?;
    let x = point_position(data, body, offset);
    let j0 = point_twist_transform(&(x - data.base_position));
    Ok((j0, joint_jacobian_of_point(model, data, body, &x)))
}

/// Translational and rotational Jacobians `J_Ti`, `J_Ri` (3×N each) of the CM of `body`
/// (paper eqs. 20–21). Requires forward kinematics.
pub fn link_jacobians(model: &Model, data: &Data, body: usize) -> (DMatrix<f64>, DMatrix<f64>) {
    let jm = joint_jacobian_of_point(model, data, body, &data.com_in_world[body]);
    (jm.rows(0, 3).into_owned(), jm.rows(3, 3).into_owned())
}

/// Pose of every body's CM frame: rotation to 𝒥 and CM position. Requires forward kinematics.
pub fn body_poses(data: &Data) -> Vec<(Matrix3<f64>, Vector3<f64>)> {
    data.body_to_world.iter().copied().zip(data.com_in_world.iter().copied()).collect()
}
