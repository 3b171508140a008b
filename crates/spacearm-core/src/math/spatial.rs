//! 3-vectors, cross-product matrices and spatial (6-D) vectors and inertias.
//!
//! Spatial vectors are ordered `[linear (3), angular (3)]`, linear first, as in the paper
//! (docs/conventions.md). The recursive algorithms (Featherstone, *Rigid Body Dynamics Algorithms*,
//! 2008, ch. 2) work with spatial vectors whose axes are those of the inertial frame 𝒥 and whose
//! reference point is the base centre of mass `r0` at the current instant. With that choice the
//! base's spatial velocity is exactly the paper's `ẋ0 = [v0; ω0]` and a spatial force on the
//! base is exactly `[F0; N0]`, so no convention transform is ever needed for the base.
//!
//! Every function is generic over the scalar ([`Real`]: `f64` or a dual number).

use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

use crate::math::scalar::Real;

/// Cross-product matrix `ã` with `ã b = a × b` (the paper's `a^×`).
#[inline]
pub fn skew<T: Real>(a: &Vector3<T>) -> Matrix3<T> {
    let z = T::zero();
    Matrix3::new(z, -a.z, a.y, a.z, z, -a.x, -a.y, a.x, z)
}

/// Linear part `[0..3]` of a spatial vector.
#[inline]
pub fn linear<T: Real>(v: &Vector6<T>) -> Vector3<T> {
    v.fixed_rows::<3>(0).into_owned()
}

/// Angular part `[3..6]` of a spatial vector.
#[inline]
pub fn angular<T: Real>(v: &Vector6<T>) -> Vector3<T> {
    v.fixed_rows::<3>(3).into_owned()
}

/// Build a spatial vector from its linear and angular parts.
#[inline]
pub fn spatial<T: Real>(lin: &Vector3<T>, ang: &Vector3<T>) -> Vector6<T> {
    Vector6::new(lin.x, lin.y, lin.z, ang.x, ang.y, ang.z)
}

/// Motion cross product `v ×ₘ m` (Featherstone eq. 2.31, reordered linear-first):
/// `[ω × m_lin + v × m_ang; ω × m_ang]` for `v = [v; ω]`.
#[inline]
pub fn cross_motion<T: Real>(v: &Vector6<T>, m: &Vector6<T>) -> Vector6<T> {
    let (lin, ang) = (linear(v), angular(v));
    let (m_lin, m_ang) = (linear(m), angular(m));
    spatial(&(ang.cross(&m_lin) + lin.cross(&m_ang)), &ang.cross(&m_ang))
}

/// Force cross product `v ×* f` (Featherstone eq. 2.32, reordered linear-first):
/// `[ω × f_lin; ω × f_ang + v × f_lin]` for `v = [v; ω]`, `f = [f_lin; f_ang]`.
#[inline]
pub fn cross_force<T: Real>(v: &Vector6<T>, f: &Vector6<T>) -> Vector6<T> {
    let (lin, ang) = (linear(v), angular(v));
    let (f_lin, f_ang) = (linear(f), angular(f));
    spatial(&ang.cross(&f_lin), &(ang.cross(&f_ang) + lin.cross(&f_lin)))
}

/// Spatial inertia of a body of mass `m`, centre of mass at `c` from the reference point and
/// inertia `inertia_about_com` about its CM (all in the same axes):
/// `[[m E, −m c̃], [m c̃, I_c + m c̃ᵀ c̃]]` (paper eq. 29's per-link term; Featherstone eq. 2.63),
/// with `c̃ᵀ c̃ = |c|² E − c cᵀ`. The rotational block is symmetrized from its upper triangle.
#[inline]
pub fn spatial_inertia<T: Real>(m: T, c: &Vector3<T>, inertia_about_com: &Matrix3<T>) -> Matrix6<T> {
    let (x, y, z) = (c.x, c.y, c.z);
    let o = T::zero();
    let (mx, my, mz) = (m * x, m * y, m * z);
    let ic = inertia_about_com;
    let i00 = ic[(0, 0)] + (my * y + mz * z);
    let i11 = ic[(1, 1)] + (mx * x + mz * z);
    let i22 = ic[(2, 2)] + (mx * x + my * y);
    let i01 = ic[(0, 1)] - mx * y;
    let i02 = ic[(0, 2)] - mx * z;
    let i12 = ic[(1, 2)] - my * z;
    #[rustfmt::skip]
    let out = Matrix6::new(
        m,   o,   o,   o,   mz,  -my,
        o,   m,   o,   -mz, o,   mx,
        o,   o,   m,   my,  -mx, o,
        o,   -mz, my,  i00, i01, i02,
        mz,  o,   -mx, i01, i11, i12,
        -my, mx,  o,   i02, i12, i22,
    );
    out
}

/// `m v` for a 6×6 matrix, column by column (the small fixed-size product, written out so that
/// it compiles to straight-line code in the recursions).
#[inline(always)]
pub fn mul6<T: Real>(m: &Matrix6<T>, v: &Vector6<T>) -> Vector6<T> {
    let a = m.as_slice();
    let mut out = [T::zero(); 6];
    for j in 0..6 {
        let vj = v[j];
        let col = &a[6 * j..6 * j + 6];
        for i in 0..6 {
            out[i] += col[i] * vj;
        }
    }
    Vector6::from(out)
}

/// `a · b` for spatial vectors.
#[inline(always)]
pub fn dot6<T: Real>(a: &Vector6<T>, b: &Vector6<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] + a[4] * b[4] + a[5] * b[5]
}

/// `dst += src` for 6×6 matrices.
#[inline(always)]
pub fn add6_assign<T: Real>(dst: &mut Matrix6<T>, src: &Matrix6<T>) {
    for (d, s) in dst.as_mut_slice().iter_mut().zip(src.as_slice()) {
        *d += *s;
    }
}

/// Twist transform of a point offset `d` from the reference point: `[[E, −d̃], [0, E]]`, the
/// paper's `J_0X` (eq. 105) — maps `[v_ref; ω]` to `[v_point; ω]`.
pub fn point_twist_transform<T: Real>(d: &Vector3<T>) -> Matrix6<T> {
    let mut out = Matrix6::identity();
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-skew(d)));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skew_is_cross_product() {
        let a = Vector3::new(0.3, -1.2, 2.0);
        let b = Vector3::new(-0.7, 0.1, 0.4);
        assert!((skew(&a) * b - a.cross(&b)).norm() < 1e-15);
    }

    #[test]
    fn force_cross_is_dual_of_motion_cross() {
        // Featherstone eq. 2.34: (v×*) = −(v×ₘ)ᵀ, checked through ⟨v ×ₘ m, f⟩ = −⟨m, v ×* f⟩.
        let v = Vector6::new(0.1, -0.4, 0.3, 1.2, -0.5, 0.7);
        let m = Vector6::new(-0.2, 0.8, 0.6, -0.3, 0.9, 0.4);
        let f = Vector6::new(0.5, 0.2, -1.1, 0.3, -0.6, 0.8);
        let lhs = cross_motion(&v, &m).dot(&f);
        let rhs = -m.dot(&cross_force(&v, &f));
        assert!((lhs - rhs).abs() < 1e-14);
        assert!(lhs.abs() > 1e-3);
    }

    #[test]
    fn spatial_inertia_gives_momentum_of_rigid_body() {
        // Momentum of a body moving with twist [v_ref; ω] computed from point-mass sums.
        let m = 2.5;
        let c = Vector3::new(0.3, -0.2, 0.5);
        let ic = Matrix3::new(0.4, 0.01, 0.02, 0.01, 0.5, -0.03, 0.02, -0.03, 0.6);
        let v_ref = Vector3::new(0.2, 0.1, -0.4);
        let w = Vector3::new(0.5, -0.7, 0.3);
        let h = spatial_inertia(m, &c, &ic) * spatial(&v_ref, &w);
        let v_com = v_ref + w.cross(&c);
        let p = m * v_com;
        let l = c.cross(&p) + ic * w;
        assert!((linear(&h) - p).norm() < 1e-14);
        assert!((angular(&h) - l).norm() < 1e-14);
        // Same as the block formula with explicit cross-product matrices.
        let cx = skew(&c);
        let mut blocks = Matrix6::zeros();
        blocks.fixed_view_mut::<3, 3>(0, 0).copy_from(&(Matrix3::identity() * m));
        blocks.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-m * cx));
        blocks.fixed_view_mut::<3, 3>(3, 0).copy_from(&(m * cx));
        blocks.fixed_view_mut::<3, 3>(3, 3).copy_from(&(ic + m * cx.transpose() * cx));
        assert!((spatial_inertia(m, &c, &ic) - blocks).abs().max() < 1e-14);
    }
}

/// The unit vector along `v` as an array, or `None` for a zero, tiny (< 1e-9) or non-finite `v`
/// (model geometry given as `[f64; 3]`: slosh mounts, appendages).
pub fn unit3(v: &[f64; 3]) -> Option<[f64; 3]> {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (n.is_finite() && n > 1e-9).then(|| [v[0] / n, v[1] / n, v[2] / n])
}

/// `a × b` of two arrays.
pub fn cross3(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// `a · b` of two arrays.
pub fn dot3(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
