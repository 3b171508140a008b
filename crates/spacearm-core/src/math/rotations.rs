//! Rotations and quaternions, in one place: the unit-quaternion check applied to every
//! quaternion given as input, conversions between spacearm's `[x, y, z, w]` storage order and
//! nalgebra, roll-pitch-yaw angles, Rodrigues' rotation, `R A Rᵀ`, the quaternion
//! kinematics `quaṫ = ½ [ω; 0] ⊗ quat` shared by every integrator of the base attitude, and the
//! rotation helpers on `[x, y, z, w]` that every binding exports (Hamilton product, quaternion ↔
//! matrix, exponential and logarithm, the rotation vector of a matrix): `spacearm.rotations`
//! computes with these.
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

/// Hamilton product `a ⊗ b` of quaternions `[x, y, z, w]` (any norm): for unit ones the
/// rotation `R(a) R(b)`. The configuration rate `½ [ω; 0] ⊗ q` is one too ([`quaternion_rate`]).
#[inline]
pub fn xyzw_multiply(a: &[f64; 4], b: &[f64; 4]) -> [f64; 4] {
    let ([ax, ay, az, aw], [bx, by, bz, bw]) = (*a, *b);
    [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
}

/// Norm of the quaternion `[x, y, z, w]`.
#[inline]
fn norm4(q: &[f64; 4]) -> f64 {
    (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt()
}

/// Rotation matrix of the quaternion `[x, y, z, w]` divided by its norm (callers check the
/// norm first: [`unit_quaternion_from_xyzw`]), by the closed form
/// `E + 2 w ṽ + 2 ṽ ṽ` written entry by entry (`1 − 2(y² + z²)`, `2(xy − zw)`, ...).
#[inline]
pub fn matrix_from_xyzw(q: &[f64; 4]) -> Matrix3<f64> {
    let n = norm4(q);
    let (x, y, z, w) = (q[0] / n, q[1] / n, q[2] / n, q[3] / n);
    Matrix3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - z * w),
        2.0 * (x * z + y * w),
        2.0 * (x * y + z * w),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - x * w),
        2.0 * (x * z - y * w),
        2.0 * (y * z + x * w),
        1.0 - 2.0 * (x * x + y * y),
    )
}

/// Unit quaternion `[x, y, z, w]` with `w ≥ 0` of a rotation matrix (callers check that it is
/// one), by Shepperd's method: the largest of `tr R` and the diagonal picks the component
/// computed from a square root, stable for every rotation; normalized at the end.
pub fn xyzw_from_matrix(r: &Matrix3<f64>) -> [f64; 4] {
    let tr = r[(0, 0)] + r[(1, 1)] + r[(2, 2)];
    let diag = [r[(0, 0)], r[(1, 1)], r[(2, 2)], tr];
    // The first largest, as numpy's argmax.
    let mut k = 0;
    for (idx, &d) in diag.iter().enumerate().skip(1) {
        if d > diag[k] {
            k = idx;
        }
    }
    let mut q = [0.0; 4];
    if k == 3 {
        let w = (1.0 + tr).sqrt() / 2.0;
        q = [(r[(2, 1)] - r[(1, 2)]) / (4.0 * w), (r[(0, 2)] - r[(2, 0)]) / (4.0 * w), (r[(1, 0)] - r[(0, 1)]) / (4.0 * w), w];
    } else {
        let (i, j, l) = (k, (k + 1) % 3, (k + 2) % 3);
        let s = (1.0 + r[(i, i)] - r[(j, j)] - r[(l, l)]).sqrt() * 2.0;
        q[i] = s / 4.0;
        q[j] = (r[(j, i)] + r[(i, j)]) / s;
        q[l] = (r[(l, i)] + r[(i, l)]) / s;
        q[3] = (r[(l, j)] - r[(j, l)]) / s;
    }
    if q[3] < 0.0 {
        q = q.map(|v| -v);
    }
    let n = norm4(&q);
    q.map(|v| v / n)
}

/// Unit quaternion `[x, y, z, w]` of the rotation vector `θ` (a rotation by `|θ|` about
/// `θ / |θ|`), `exp(θ / 2)`: `[θ sin(|θ|/2) / |θ|, cos(|θ|/2)]`, the ratio by its Taylor series
/// `½ − |θ|²/48` below `|θ| = 1e-8` (exact there in f64).
#[inline]
pub fn xyzw_exp(theta: &Vector3<f64>) -> [f64; 4] {
    let angle = theta.norm();
    let half = 0.5 * angle;
    let k = if angle > 1e-8 { half.sin() / angle } else { 0.5 - angle * angle / 48.0 };
    [theta.x * k, theta.y * k, theta.z * k, half.cos()]
}

/// Rotation vector (`|θ| ≤ π`) of the quaternion `[x, y, z, w]`, normalized first, `2 log q`:
/// with `[v; w]` the unit quaternion of the same rotation with `w ≥ 0`,
/// `θ = 2 atan2(|v|, w) v / |v|` (`2 v / w` for `|v| ≤ 1e-12`).
#[inline]
pub fn xyzw_log(q: &[f64; 4]) -> Vector3<f64> {
    let n = norm4(q);
    let mut u = q.map(|v| v / n);
    if u[3] < 0.0 {
        u = u.map(|v| -v);
    }
    let v = Vector3::new(u[0], u[1], u[2]);
    let s = v.norm();
    let angle = 2.0 * s.atan2(u[3]);
    let k = if s > 1e-12 { angle / s } else { 2.0 / u[3] };
    v * k
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

    /// A random-ish set of rotation vectors: small, generic, near and at π.
    fn sample_vectors() -> Vec<Vector3<f64>> {
        let mut out = vec![Vector3::zeros(), Vector3::new(1e-10, -3e-10, 2e-10), Vector3::new(0.0, 0.0, std::f64::consts::PI)];
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..200 {
            let v = Vector3::new(next(), next(), next());
            out.push(v * (3.1 * (next() + 1.0) / 2.0) / v.norm().max(1e-300));
        }
        out
    }

    #[test]
    fn xyzw_multiply_is_the_hamilton_product() {
        // i j = k, j i = −k, i i = −1 and nalgebra's product of generic quaternions.
        let (i, j, k) = ([1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]);
        assert_eq!(xyzw_multiply(&i, &j), k);
        assert_eq!(xyzw_multiply(&j, &i), [0.0, 0.0, -1.0, 0.0]);
        assert_eq!(xyzw_multiply(&i, &i), [0.0, 0.0, 0.0, -1.0]);
        let (a, b) = ([0.3, -1.2, 0.5, 2.0], [-0.7, 0.1, 0.9, -0.4]);
        let theirs = quaternion_from_xyzw(&a) * quaternion_from_xyzw(&b);
        let ours = xyzw_multiply(&a, &b);
        for (o, t) in ours.iter().zip([theirs.i, theirs.j, theirs.k, theirs.w]) {
            assert!((o - t).abs() < 1e-15);
        }
        // ½ [ω; 0] ⊗ q is the quaternion rate.
        let (q, w) = ([0.1, 0.2, -0.3, 0.9], Vector3::new(0.4, -0.5, 0.6));
        let rate = xyzw_multiply(&[0.5 * w.x, 0.5 * w.y, 0.5 * w.z, 0.0], &q);
        let expected = quaternion_rate(&q, &w);
        for k in 0..4 {
            assert!((rate[k] - expected[k]).abs() < 1e-16);
        }
    }

    #[test]
    fn matrix_from_xyzw_is_rodrigues() {
        for theta in sample_vectors() {
            let q = xyzw_exp(&theta);
            let r = matrix_from_xyzw(&q);
            let angle = theta.norm();
            let expected = if angle == 0.0 { Matrix3::identity() } else { axis_angle_rotation(&(theta / angle), angle) };
            assert!((r - expected).abs().max() < 1e-15, "{theta:?}");
            // Any norm: the quaternion is normalized first.
            assert!((matrix_from_xyzw(&q.map(|v| 3.0 * v)) - r).abs().max() < 1e-15);
        }
        // 90° about z: [0, 0, √½, √½].
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let r = matrix_from_xyzw(&[0.0, 0.0, s, s]);
        assert!((r - Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0)).abs().max() < 1e-15);
    }

    #[test]
    fn xyzw_from_matrix_inverts_matrix_from_xyzw_with_w_nonnegative() {
        for theta in sample_vectors() {
            let mut q = xyzw_exp(&theta);
            if q[3] < 0.0 {
                q = q.map(|v| -v);
            }
            let back = xyzw_from_matrix(&matrix_from_xyzw(&q));
            assert!(back[3] >= 0.0);
            // At w = 0 (a half turn) q and −q are both w ≥ 0: compare rotations there.
            let same = (0..4).all(|k| (back[k] - q[k]).abs() < 1e-15);
            let flipped = q[3].abs() < 1e-15 && (0..4).all(|k| (back[k] + q[k]).abs() < 1e-15);
            assert!(same || flipped, "{theta:?}: {q:?} -> {back:?}");
            assert!((norm4(&back) - 1.0).abs() < 1e-15);
        }
        // Half turns about each axis take the diagonal branches.
        for (axis, expected) in [(0, [1.0, 0.0, 0.0, 0.0]), (1, [0.0, 1.0, 0.0, 0.0]), (2, [0.0, 0.0, 1.0, 0.0])] {
            let mut d = Vector3::from_element(-1.0);
            d[axis] = 1.0;
            assert_eq!(xyzw_from_matrix(&Matrix3::from_diagonal(&d)), expected);
        }
    }

    #[test]
    fn xyzw_exp_and_log_are_closed_forms_and_inverse() {
        for theta in sample_vectors() {
            let q = xyzw_exp(&theta);
            let angle = theta.norm();
            assert!((q[3] - (0.5 * angle).cos()).abs() < 4e-16);
            let (axis, s) = if angle == 0.0 { (Vector3::zeros(), 0.0) } else { (theta / angle, (0.5 * angle).sin()) };
            for k in 0..3 {
                assert!((q[k] - axis[k] * s).abs() < 4e-16, "{theta:?}");
            }
            let back = xyzw_log(&q);
            assert!((back - theta).norm() <= 4e-15 * angle.max(1e-300) + 1e-300, "{theta:?} -> {back:?}: {}", (back - theta).norm());
            // log and the matrix route agree.
            assert!((back - rotation_vector(&matrix_from_xyzw(&q))).norm() < 1e-14);
        }
        // Taylor branch: exact to f64 near zero, log(−q) = log(q).
        let tiny = Vector3::new(1e-9, 0.0, 0.0);
        assert_eq!(xyzw_exp(&tiny), [5e-10, 0.0, 0.0, 1.0]);
        let q = [0.1, -0.2, 0.3, -0.9];
        assert!((xyzw_log(&q) - xyzw_log(&q.map(|v| -v))).norm() < 1e-16);
    }

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
