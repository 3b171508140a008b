//! Rotations and quaternions, in one place: the unit-quaternion check applied to every
//! quaternion given as input, conversions between spacearm's `[x, y, z, w]` storage order and
//! nalgebra, roll-pitch-yaw angles, Rodrigues' rotation, `R A Rᵀ`, and the quaternion
//! kinematics `quaṫ = ½ [ω; 0] ⊗ quat` shared by every integrator of the base attitude.
//!
//! Convention (docs/conventions.md): Hamilton quaternions stored `[x, y, z, w]`, rotating
//! body axes into the inertial frame 𝒥; angular velocities in 𝒥.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

use crate::error::{check_finite, Result, SpacearmError};
use crate::math::scalar::Real;

/// Tolerance on the norm of a quaternion given as input (`| |q| - 1 | <= this`).
pub const QUATERNION_TOLERANCE: f64 = 1e-6;

/// The nalgebra quaternion of `[x, y, z, w]` (the first four entries of `xyzw`), as stored.
#[inline]
pub fn quaternion_from_xyzw(xyzw: &[f64]) -> Quaternion<f64> {
    Quaternion::new(xyzw[3], xyzw[0], xyzw[1], xyzw[2])
}

/// `[x, y, z, w]` of a unit quaternion.
#[inline]
pub fn xyzw(q: &UnitQuaternion<f64>) -> [f64; 4] {
    [q.i, q.j, q.k, q.w]
}

/// Validate a quaternion `[x, y, z, w]` given as input (finite, unit within
/// [`QUATERNION_TOLERANCE`]) and return it normalized.
pub fn unit_quaternion_from_xyzw(what: &str, q: &[f64; 4]) -> Result<UnitQuaternion<f64>> {
    check_finite(what, q)?;
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if (norm - 1.0).abs() > QUATERNION_TOLERANCE {
        return Err(SpacearmError::NotUnitQuaternion { what: what.into(), norm, tolerance: QUATERNION_TOLERANCE });
    }
    Ok(UnitQuaternion::from_quaternion(quaternion_from_xyzw(q)))
}

/// `[x, y, z, w]` of URDF roll-pitch-yaw angles: `Rz(yaw) Ry(pitch) Rx(roll)`.
pub fn xyzw_from_rpy(rpy: &[f64; 3]) -> [f64; 4] {
    xyzw(&UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]))
}

/// Rotation by `angle` about the unit `axis` (Rodrigues: `E cos θ + (1 − cos θ) k kᵀ + sin θ k̃`).
///
/// The same entries as nalgebra's `Rotation3::from_axis_angle`, without its shortcut to the
/// identity at `θ = 0`, which would drop the derivative part of a dual-number angle.
#[inline]
pub fn axis_angle_rotation<T: Real>(axis: &Vector3<T>, angle: T) -> Matrix3<T> {
    let (ux, uy, uz) = (axis.x, axis.y, axis.z);
    let (sqx, sqy, sqz) = (ux * ux, uy * uy, uz * uz);
    let (sin, cos) = angle.sin_cos();
    let one_m_cos = T::one() - cos;
    Matrix3::new(
        sqx + (T::one() - sqx) * cos,
        ux * uy * one_m_cos - uz * sin,
        ux * uz * one_m_cos + uy * sin,
        ux * uy * one_m_cos + uz * sin,
        sqy + (T::one() - sqy) * cos,
        uy * uz * one_m_cos - ux * sin,
        ux * uz * one_m_cos - uy * sin,
        uy * uz * one_m_cos + ux * sin,
        sqz + (T::one() - sqz) * cos,
    )
}

/// `R A Rᵀ` for a symmetric 3×3 `A` (an inertia tensor changing axes), computed from its upper
/// triangle so that the result is exactly symmetric.
#[inline]
pub fn rotate_symmetric<T: Real>(r: &Matrix3<T>, a: &Matrix3<T>) -> Matrix3<T> {
    let mut out = r * a * r.transpose();
    out[(1, 0)] = out[(0, 1)];
    out[(2, 0)] = out[(0, 2)];
    out[(2, 1)] = out[(1, 2)];
    out
}

/// Quaternion kinematics `quaṫ = ½ [ω; 0] ⊗ quat` for `quat = [x, y, z, w]` and the angular
/// velocity `ω` in 𝒥 (the body's attitude rate; Hamilton product, `ω` on the left because it
/// is expressed in the inertial frame). Returns `quaṫ` as `[x, y, z, w]`. Any scalar (the
/// simulator's `f64`, the recorded state derivative of [`crate::taped`]).
#[inline]
pub fn quaternion_rate<T: Real>(quat_xyzw: &[T], omega_world: &Vector3<T>) -> [T; 4] {
    let vector = Vector3::new(quat_xyzw[0], quat_xyzw[1], quat_xyzw[2]);
    let scalar = quat_xyzw[3];
    // ½ [ω; 0] ⊗ [v; s]: vector part ½(s ω + ω × v), scalar part −½ ω·v.
    let dv = (omega_world * scalar + omega_world.cross(&vector)) * T::c(0.5);
    [dv.x, dv.y, dv.z, T::c(-0.5) * omega_world.dot(&vector)]
}

/// Divide the quaternion `[x, y, z, w]` stored in `quat_xyzw` by its norm.
#[inline]
pub fn normalize_xyzw(quat_xyzw: &mut [f64]) {
    let n = quat_xyzw.iter().take(4).map(|v| v * v).sum::<f64>().sqrt();
    for v in &mut quat_xyzw[..4] {
        *v /= n;
    }
}

/// The rotation vector `θ` (`|θ| ≤ π`) with `exp(θ̃) = R` of a rotation matrix, `log(R)`: through
/// its unit quaternion `[v; w]` (`w ≥ 0`), `θ = 2 atan2(|v|, w) v / |v|` — accurate for small
/// rotations too (an `acos` of the trace or of `w` loses half the digits there).
pub fn rotation_vector(r: &Matrix3<f64>) -> Vector3<f64> {
    let q = UnitQuaternion::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(*r));
    let (mut v, mut w) = (q.imag(), q.scalar());
    if w < 0.0 {
        v = -v;
        w = -w;
    }
    let s = v.norm();
    if s == 0.0 {
        return Vector3::zeros();
    }
    v * (2.0 * s.atan2(w) / s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_vector_inverts_the_exponential() {
        for theta in [Vector3::new(0.3, -1.2, 0.8), Vector3::new(1e-9, 2e-9, -1e-9), Vector3::new(0.0, 3.1, 0.0), Vector3::zeros()] {
            let r = nalgebra::Rotation3::from_scaled_axis(theta).into_inner();
            let back = rotation_vector(&r);
            assert!((back - theta).norm() <= 1e-14 * theta.norm().max(1e-300) + 1e-300, "{theta:?} -> {back:?}");
        }
    }

    #[test]
    fn axis_angle_rotation_matches_nalgebra() {
        let axis = nalgebra::Unit::new_normalize(Vector3::new(0.3, -0.5, 0.8));
        for angle in [0.0, 0.7, -2.9] {
            let ours = axis_angle_rotation(&axis.into_inner(), angle);
            let theirs = nalgebra::Rotation3::from_axis_angle(&axis, angle).into_inner();
            assert!((ours - theirs).abs().max() < 1e-15);
        }
    }

    #[test]
    fn rotate_symmetric_is_r_a_rt() {
        let a = Matrix3::new(0.4, 0.01, 0.02, 0.01, 0.5, -0.03, 0.02, -0.03, 0.6);
        let r = nalgebra::Rotation3::from_euler_angles(0.3, -1.1, 2.0).into_inner();
        let out = rotate_symmetric(&r, &a);
        assert!((out - r * a * r.transpose()).abs().max() < 1e-15);
        assert_eq!(out, out.transpose());
    }

    #[test]
    fn quaternion_rate_is_the_derivative_of_a_rotation_about_a_fixed_axis() {
        // quat(t) = exp(t ω / 2) ⊗ quat(0) for constant ω in 𝒥: compare with a central
        // difference of nalgebra's rotation composition.
        let q0 = UnitQuaternion::from_euler_angles(0.4, -0.2, 1.1);
        let w = Vector3::new(0.3, -0.7, 0.5);
        let at = |t: f64| xyzw(&(UnitQuaternion::from_scaled_axis(w * t) * q0));
        let h = 1e-6;
        let (a, b) = (at(h), at(-h));
        let rate = quaternion_rate(&xyzw(&q0), &w);
        for k in 0..4 {
            assert!((rate[k] - (a[k] - b[k]) / (2.0 * h)).abs() < 1e-9, "{k}: {rate:?}");
        }
    }

    #[test]
    fn input_quaternions_are_checked() {
        assert!(unit_quaternion_from_xyzw("q", &[0.0, 0.0, 0.0, 1.0]).is_ok());
        assert!(matches!(unit_quaternion_from_xyzw("q", &[0.0, 0.0, 0.0, 2.0]), Err(SpacearmError::NotUnitQuaternion { .. })));
        assert!(matches!(unit_quaternion_from_xyzw("q", &[f64::NAN, 0.0, 0.0, 1.0]), Err(SpacearmError::NonFinite { .. })));
        let rpy = xyzw_from_rpy(&[0.0, 0.0, std::f64::consts::FRAC_PI_2]);
        assert!((rpy[2] - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15 && (rpy[3] - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15);
    }
}
