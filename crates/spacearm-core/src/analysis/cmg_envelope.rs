//! The momentum envelope of a CMG cluster (docs/cmg.md; Wie, *Space Vehicle Dynamics and
//! Control*, 2nd ed., 2008, §7.6; Margulies & Aubrun, "Geometric theory of single-gimbal control
//! moment gyro systems", J. Astronaut. Sci. 26(2), 1978).
//!
//! The largest momentum a cluster holds along a unit direction `u` has every spin axis as close
//! to `u` as its gimbal plane allows: `ŝ_i = (u − (u·ĝ_i) ĝ_i) / |u − (u·ĝ_i) ĝ_i|`, so the
//! envelope's point in that direction is `H(u) = Σ h_i ŝ_i` (the outer singular surface, every
//! sign `ε_i = +1`); a gimbal axis along `u` (`u ∥ ĝ_i`) contributes nothing there.

use nalgebra::Vector3;

/// The envelope's point `H(u) = Σ h_i ŝ_i(u)` (module docs) for each direction of `directions`
/// (normalized here; a zero direction gives a zero point), with `gimbals` the unit gimbal axes
/// and `h` the rotor momenta.
pub fn cmg_envelope(gimbals: &[Vector3<f64>], h: &[f64], directions: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    directions
        .iter()
        .map(|d| {
            let Some(u) = d.try_normalize(1e-300) else { return Vector3::zeros() };
            gimbals
                .iter()
                .zip(h)
                .map(|(g, h)| {
                    let p = u - g * g.dot(&u);
                    p.try_normalize(1e-12).map_or_else(Vector3::zeros, |s| s * *h)
                })
                .sum()
        })
        .collect()
}

/// The fraction of the momentum envelope a cluster uses: `|H| / σ(Ĥ)` with `H = Σ h_i ŝ_i`
/// (`spin` the current spin axes) and `σ(u) = H(u) · u` the envelope's extent along `u`, the
/// largest `H · u` of any gimbal angles (module docs, with `|h_i|`). 1 on the envelope (saturation), 0 at zero
/// momentum; it can exceed 1 only by rounding.
pub fn envelope_fraction(gimbals: &[Vector3<f64>], spin: &[Vector3<f64>], h: &[f64]) -> f64 {
    let momentum: Vector3<f64> = spin.iter().zip(h).map(|(s, h)| s * *h).sum();
    let Some(u) = momentum.try_normalize(1e-300) else { return 0.0 };
    // A rotor spinning backwards (h_i < 0) reaches the same extent with its spin axis reversed.
    let size: Vec<f64> = h.iter().map(|v| v.abs()).collect();
    let extent = cmg_envelope(gimbals, &size, &[u])[0].dot(&u);
    if extent > 0.0 {
        momentum.norm() / extent
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pyramid(beta: f64) -> Vec<Vector3<f64>> {
        let (sb, cb) = beta.sin_cos();
        vec![Vector3::new(sb, 0.0, cb), Vector3::new(0.0, sb, cb), Vector3::new(-sb, 0.0, cb), Vector3::new(0.0, -sb, cb)]
    }

    #[test]
    fn the_pyramid_envelope_has_its_closed_forms_and_bounds_every_gimbal_state() {
        let beta = (1.0f64 / 3.0f64.sqrt()).acos();
        let g = pyramid(beta);
        let h = [1.0; 4];
        let e = cmg_envelope(&g, &h, &[Vector3::z(), Vector3::x(), -Vector3::z()]);
        // Along z: each rotor gives sin β; along x: the two gimbals in the xz plane give cos β,
        // the two perpendicular to x give 1.
        assert!((e[0] - Vector3::z() * 4.0 * beta.sin()).norm() < 1e-14, "{}", e[0]);
        assert!((e[1] - Vector3::x() * (2.0 + 2.0 * beta.cos())).norm() < 1e-14, "{}", e[1]);
        assert!((e[2] + e[0]).norm() < 1e-14);
        // Sampled gimbal states: the momentum along u never exceeds the envelope's, and some
        // come within 1 % of it.
        let s0 = [Vector3::y(), -Vector3::x(), -Vector3::y(), Vector3::x()];
        let u = Vector3::new(0.3, -0.5, 0.8).normalize();
        let hu = cmg_envelope(&g, &h, &[u])[0].dot(&u);
        let mut best = 0.0f64;
        let mut seed = 12345u64;
        for _ in 0..20000 {
            let mut hs = Vector3::zeros();
            for i in 0..4 {
                seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                let d = (seed >> 11) as f64 / (1u64 << 53) as f64 * std::f64::consts::TAU;
                hs += s0[i] * d.cos() + g[i].cross(&s0[i]) * d.sin();
            }
            best = best.max(hs.dot(&u));
        }
        assert!(best <= hu + 1e-12 && best > 0.99 * hu, "{best} {hu}");
    }
}
