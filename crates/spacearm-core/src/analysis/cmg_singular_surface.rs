//! The singular surfaces of a CMG cluster's momentum space (docs/cmg.md, "The singular
//! surfaces"; Margulies & Aubrun, "Geometric theory of single-gimbal control moment gyro
//! systems", J. Astronaut. Sci. 26(2), 1978; Wie, *Space Vehicle Dynamics and Control*, 2nd ed.,
//! 2008, §7.6; Bedrossian, Paradiso & Bergmann, "Steering law design for redundant single-gimbal
//! control moment gyros", JGCD 13(6), 1990).
//!
//! The cluster is singular where its Jacobian `A = [h_i (ĝ_i × ŝ_i)]` (control/cmg_jacobian.rs)
//! has rank < 3: a unit direction `u` with `Aᵀ u = 0`, i.e. `u · (ĝ_i × ŝ_i) = 0` for every CMG —
//! each spin axis lies in the plane of `ĝ_i` and `u`. With `ŝ_i ⊥ ĝ_i` that leaves two choices
//! per CMG, the signs `ε_i = ±1`:
//!
//! `ŝ_i = ε_i (ĝ_i × u) × ĝ_i / |ĝ_i × u| = ε_i (u − (u·ĝ_i) ĝ_i) / |u − (u·ĝ_i) ĝ_i|`,
//! `H(u, ε) = Σ_i h_i ŝ_i`.
//!
//! For one sign pattern `ε`, `u` over the unit sphere sweeps one singular surface; `ε` and `−ε`
//! sweep the same surface (`H(u, −ε) = H(−u, ε)`), so `2^(n−1)` patterns, `ε_1 = +1`, give them
//! all. Every `ε_i = +1` is the outer surface, the momentum envelope (analysis/cmg_envelope.rs);
//! patterns with negative signs are the internal singular surfaces. A direction along a gimbal
//! axis (`u ∥ ĝ_i`) leaves `ŝ_i` undetermined (every spin axis of that CMG is singular there):
//! it has no point here.

use nalgebra::Vector3;

use crate::error::{Result, SpacearmError};

/// The most CMGs of a cluster whose sign patterns [`sign_patterns`] lists (`2^(n−1)` of them).
pub const MAX_CMGS: usize = 16;

/// `|u − (u·ĝ) ĝ|` below which `u` is taken as along `ĝ` (no singular spin axis is determined).
const ALONG_AXIS: f64 = 1e-9;

/// One point of a singular surface: the cluster's momentum and the spin axes that hold it.
#[derive(Debug, Clone, PartialEq)]
pub struct SingularState {
    /// `H = Σ h_i ŝ_i` (N·m·s, in the frame of the gimbal axes).
    pub momentum: Vector3<f64>,
    /// The unit spin axes `ŝ_i`, one per CMG.
    pub spin: Vec<Vector3<f64>>,
}

/// The `2^(n−1)` sign patterns with `ε_1 = +1`, ordered by their number of negative signs (the
/// outer surface first), then as binary numbers of the signs `ε_2 … ε_n` (`−1` a set bit, `ε_n`
/// the lowest). One per distinct singular surface (module docs).
pub fn sign_patterns(n: usize) -> Result<Vec<Vec<f64>>> {
    if n == 0 || n > MAX_CMGS {
        return Err(SpacearmError::argument(format!(
            "cmg singular surfaces: a cluster of 1 to {MAX_CMGS} CMGs, got {n}"
        )));
    }
    let mut masks: Vec<u32> = (0..1u32 << (n - 1)).collect();
    masks.sort_by_key(|m| (m.count_ones(), *m));
    Ok(masks
        .into_iter()
        .map(|m| (0..n).map(|i| if i > 0 && m >> (n - 1 - i) & 1 == 1 { -1.0 } else { 1.0 }).collect())
        .collect())
}

/// Check a cluster: unit gimbal axes (finite, nonzero: normalized here), one finite rotor
/// momentum each, and (when given) sign patterns of ±1, one sign per CMG.
fn check(gimbals: &[Vector3<f64>], h: &[f64], signs: &[Vec<f64>]) -> Result<Vec<Vector3<f64>>> {
    if gimbals.len() != h.len() {
        return Err(SpacearmError::argument(format!(
            "cmg singular surfaces: {} gimbal axes but {} rotor momenta",
            gimbals.len(),
            h.len()
        )));
    }
    if gimbals.is_empty() || gimbals.len() > MAX_CMGS {
        return Err(SpacearmError::argument(format!(
            "cmg singular surfaces: a cluster of 1 to {MAX_CMGS} CMGs, got {}",
            gimbals.len()
        )));
    }
    if let Some(i) = h.iter().position(|v| !v.is_finite()) {
        return Err(SpacearmError::argument(format!("cmg singular surfaces: rotor momentum {i} must be finite, got {}", h[i])));
    }
    for (k, s) in signs.iter().enumerate() {
        if s.len() != gimbals.len() || s.iter().any(|e| *e != 1.0 && *e != -1.0) {
            return Err(SpacearmError::argument(format!(
                "cmg singular surfaces: sign pattern {k} must have {} entries, each +1 or -1, got {s:?}",
                gimbals.len()
            )));
        }
    }
    gimbals
        .iter()
        .enumerate()
        .map(|(i, g)| {
            g.iter()
                .all(|v| v.is_finite())
                .then(|| g.try_normalize(1e-300))
                .flatten()
                .ok_or_else(|| SpacearmError::argument(format!("cmg singular surfaces: gimbal axis {i} must be finite and nonzero, got {g:?}")))
        })
        .collect()
}

/// The singular state of sign pattern `signs` in direction `u` (unit): `None` where `u` lies
/// along a gimbal axis (module docs). `gimbals` unit, `h` the rotor momenta.
pub fn singular_state(gimbals: &[Vector3<f64>], h: &[f64], signs: &[f64], u: &Vector3<f64>) -> Option<SingularState> {
    let spin = gimbals
        .iter()
        .zip(signs)
        .map(|(g, e)| (u - g * g.dot(u)).try_normalize(ALONG_AXIS).map(|s| s * *e))
        .collect::<Option<Vec<_>>>()?;
    let momentum = spin.iter().zip(h).map(|(s, h)| s * *h).sum();
    Some(SingularState { momentum, spin })
}

/// The singular surfaces of a cluster (module docs): for each sign pattern of `signs` (all of
/// [`sign_patterns`] when `None`) and each direction of `directions` (normalized here; a zero
/// direction has no point), the singular state, `None` where it is undetermined. Returns the
/// patterns used and, per pattern, one entry per direction.
#[allow(clippy::type_complexity)]
pub fn cmg_singular_surfaces(
    gimbals: &[Vector3<f64>],
    h: &[f64],
    signs: Option<Vec<Vec<f64>>>,
    directions: &[Vector3<f64>],
) -> Result<(Vec<Vec<f64>>, Vec<Vec<Option<SingularState>>>)> {
    if signs.as_ref().is_some_and(Vec::is_empty) {
        return Err(SpacearmError::argument("cmg singular surfaces: give at least one sign pattern (or none for all of them)"));
    }
    let g = check(gimbals, h, signs.as_deref().unwrap_or_default())?;
    let signs = match signs {
        Some(s) => s,
        None => sign_patterns(g.len())?,
    };
    let surfaces = signs
        .iter()
        .map(|e| {
            directions
                .iter()
                .map(|d| d.try_normalize(1e-300).and_then(|u| singular_state(&g, h, e, &u)))
                .collect()
        })
        .collect();
    Ok((signs, surfaces))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::cmg_envelope::cmg_envelope;
    use nalgebra::Matrix3xX;

    fn pyramid(beta: f64) -> Vec<Vector3<f64>> {
        let (sb, cb) = beta.sin_cos();
        vec![Vector3::new(sb, 0.0, cb), Vector3::new(0.0, sb, cb), Vector3::new(-sb, 0.0, cb), Vector3::new(0.0, -sb, cb)]
    }

    /// Directions over the sphere (a Fibonacci lattice).
    fn sphere(n: usize) -> Vec<Vector3<f64>> {
        let golden = std::f64::consts::PI * (3.0 - 5.0f64.sqrt());
        (0..n)
            .map(|k| {
                let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
                let r = (1.0 - z * z).sqrt();
                let a = golden * k as f64;
                Vector3::new(r * a.cos(), r * a.sin(), z)
            })
            .collect()
    }

    #[test]
    fn the_sign_patterns_are_the_distinct_surfaces_outer_first() {
        let p = sign_patterns(4).unwrap();
        assert_eq!(p.len(), 8);
        assert_eq!(p[0], vec![1.0; 4]);
        assert_eq!(p[1], vec![1.0, 1.0, 1.0, -1.0]);
        assert!(p.iter().all(|e| e[0] == 1.0));
        let negatives: Vec<usize> = p.iter().map(|e| e.iter().filter(|v| **v < 0.0).count()).collect();
        assert_eq!(negatives, vec![0, 1, 1, 1, 2, 2, 2, 3]);
        assert!(sign_patterns(0).is_err() && sign_patterns(MAX_CMGS + 1).is_err());
    }

    #[test]
    fn every_singular_state_has_a_rank_deficient_jacobian_and_the_outer_one_is_the_envelope() {
        for (name, g) in [
            ("pyramid", pyramid((1.0f64 / 3.0f64.sqrt()).acos())),
            // A roof: two pairs of parallel gimbal axes, the pairs' planes at ±30° from z.
            ("roof", {
                let (s, c) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
                vec![Vector3::new(0.0, s, c), Vector3::new(0.0, s, c), Vector3::new(0.0, -s, c), Vector3::new(0.0, -s, c)]
            }),
        ] {
            let h = [1.0, 1.2, 0.9, 1.1];
            let dirs = sphere(400);
            let (signs, surfaces) = cmg_singular_surfaces(&g, &h, None, &dirs).unwrap();
            let env = cmg_envelope(&g, &h, &dirs);
            let mut worst = 0.0f64;
            for (e, surface) in signs.iter().zip(&surfaces) {
                for (u, state) in dirs.iter().zip(surface) {
                    let st = state.as_ref().unwrap();
                    // The Jacobian's columns h_i (ĝ_i × ŝ_i), its singular values from A Aᵀ.
                    let a = Matrix3xX::from_columns(&g.iter().zip(&st.spin).zip(&h).map(|((g, s), h)| g.cross(s) * *h).collect::<Vec<_>>());
                    // The singularity measure m = det(A Aᵀ)/h̄⁶ (docs/cmg.md): 0 up to rounding.
                    let hbar = h.iter().map(|v| v.abs()).sum::<f64>() / h.len() as f64;
                    worst = worst.max((&a * a.transpose()).determinant().abs() / hbar.powi(6));
                    assert!((a.transpose() * u).norm() < 1e-13, "{name} {e:?}: Aᵀu != 0");
                    for (s, gi) in st.spin.iter().zip(&g) {
                        assert!((s.norm() - 1.0).abs() < 1e-14 && s.dot(gi).abs() < 1e-14);
                    }
                    let sum: Vector3<f64> = st.spin.iter().zip(&h).map(|(s, h)| s * *h).sum();
                    assert!((sum - st.momentum).norm() < 1e-14);
                }
                if e.iter().all(|v| *v == 1.0) {
                    for (p, q) in surface.iter().zip(&env) {
                        assert!((p.as_ref().unwrap().momentum - q).norm() < 1e-13, "{name}: outer != envelope");
                    }
                }
            }
            assert!(worst < 1e-13, "{name}: measure up to {worst:e}");
            // The same measure away from the surface: spin axis i turned 0.3 (i + 1) rad about its gimbal.
            let st = surfaces[0][7].as_ref().unwrap();
            let turn = |i: usize| 0.3 * (i + 1) as f64;
            let turned: Vec<Vector3<f64>> =
                st.spin.iter().zip(&g).enumerate().map(|(i, (s, g))| s * turn(i).cos() + g.cross(s) * turn(i).sin()).collect();
            let a = Matrix3xX::from_columns(&g.iter().zip(&turned).zip(&h).map(|((g, s), h)| g.cross(s) * *h).collect::<Vec<_>>());
            assert!((&a * a.transpose()).determinant() > 1e-3, "{name}: the turned state is singular too");
        }
    }

    #[test]
    fn the_pyramid_has_its_known_singular_states() {
        // Wie (2008) §7.6: the pyramid of β = 54.74° is saturated at 4h sin β = 3.27h along its
        // axis (z) and 2h(1 + cos β) = 3.15h along a gimbal plane (x); the internal elliptic
        // singular state δ = (−90°, 0, 90°, 0) holds H = 2h cos β x̂ = 1.15h x̂ with spin axes
        // (cos β, 0, −sin β), −x̂, (cos β, 0, sin β), x̂ (gimbal angles from ŝ_0 = ŷ, −x̂, −ŷ, x̂).
        let beta = (1.0f64 / 3.0f64.sqrt()).acos();
        let (sb, cb) = beta.sin_cos();
        let g = pyramid(beta);
        let h = [1.0; 4];
        let (_, s) = cmg_singular_surfaces(&g, &h, Some(vec![vec![1.0; 4]]), &[Vector3::z(), Vector3::x()]).unwrap();
        assert!((s[0][0].as_ref().unwrap().momentum - Vector3::z() * 4.0 * sb).norm() < 1e-14);
        assert!((s[0][1].as_ref().unwrap().momentum.x - 3.1547005383792515).abs() < 1e-14);
        let (_, s) = cmg_singular_surfaces(&g, &h, Some(vec![vec![1.0, -1.0, 1.0, 1.0]]), &[Vector3::x()]).unwrap();
        let st = s[0][0].as_ref().unwrap();
        assert!((st.momentum - Vector3::x() * 2.0 * cb).norm() < 1e-14, "{}", st.momentum);
        let want = [Vector3::new(cb, 0.0, -sb), -Vector3::x(), Vector3::new(cb, 0.0, sb), Vector3::x()];
        for (a, b) in st.spin.iter().zip(&want) {
            assert!((a - b).norm() < 1e-14, "{a} {b}");
        }
        // Along a gimbal axis the state is undetermined; a zero direction has none.
        let (_, s) = cmg_singular_surfaces(&g, &h, None, &[g[0], Vector3::zeros()]).unwrap();
        assert!(s.iter().all(|surface| surface.iter().all(Option::is_none)));
    }

    #[test]
    fn bad_clusters_and_signs_are_refused() {
        let g = pyramid(0.9);
        let d = [Vector3::x()];
        assert!(cmg_singular_surfaces(&g, &[1.0; 3], None, &d).is_err());
        assert!(cmg_singular_surfaces(&[Vector3::zeros()], &[1.0], None, &d).is_err());
        assert!(cmg_singular_surfaces(&g, &[1.0, 1.0, f64::NAN, 1.0], None, &d).is_err());
        assert!(cmg_singular_surfaces(&g, &[1.0; 4], Some(vec![vec![1.0, 0.5, 1.0, 1.0]]), &d).is_err());
        assert!(cmg_singular_surfaces(&g, &[1.0; 4], Some(vec![vec![1.0; 3]]), &d).is_err());
        assert!(cmg_singular_surfaces(&g, &[1.0; 4], Some(vec![]), &d).is_err());
    }
}
