//! Workspaces of a free-floating manipulator (zero momentum).
//!
//! Vafa & Dubowsky (1987, 1990, "The kinematics and dynamics of space manipulators: the virtual
//! manipulator approach", IJRR 9(4)): with no external force the system CM stays fixed, and the
//! end effector's position from it is `r_E − r_g = R0 f(q)` with `f(q)` the end effector from
//! the system CM in the base frame (the virtual manipulator). The base attitude `R0` can be
//! turned to any value by cyclic joint motion, so the *reachable workspace* `W_R` is the
//! spherical shell about the system CM with radii `R_min = min |f(q)|`, `R_max = max |f(q)|`.
//!
//! Papadopoulos & Dubowsky (1991, "On the nature of control algorithms for free-floating space
//! manipulators", IEEE T-RA 7(6); 1993, "Dynamic singularities in free-floating space
//! manipulators", ASME JDSMC 115(1)): dynamic singularities are configurations `q_s` with
//! `rank J*(q_s) <` task dimension; as the attitude is path dependent, each singular
//! configuration can occur anywhere on the sphere of radius `|f(q_s)|`. Each singular surface
//! `Q_s,i` in joint space therefore sweeps a shell `[R_min,i, R_max,i]`; their union is the
//! *path-dependent workspace* (PDW: points reachable by some paths but where other paths meet a
//! dynamic singularity) and the rest of `W_R` is the *path-independent workspace* (PIW: points
//! reached by any path, free of dynamic singularities).
//!
//! Computation (by sampling, at a stated resolution): the samples of
//! [`crate::analysis::scan`] give `|f(q)|`; singular samples are those with
//! `σ_min(J*) < threshold`, and on a grid with a square task also every grid edge across which
//! `det J*` changes sign (the radius linearly interpolated at the zero). Singular radii closer
//! than `radial_resolution` are merged into one PDW interval. The fixed-base workspace
//! (radii of the point from the base CM, base held still) is reported for comparison.

use super::scan::ScanSample;
use crate::error::{Result, SpacearmError};

/// Radial description of the workspaces.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkspaceShells {
    /// `[R_min, R_max]` of the free-floating reachable workspace about the system CM, m.
    pub reachable: [f64; 2],
    /// `[min, max]` distance of the point from the base CM with the base held fixed, m.
    pub fixed_base: [f64; 2],
    /// Barycentric radii `|f(q)|` of the singular samples and crossings found, sorted.
    pub singular_radii: Vec<f64>,
    /// Path-dependent shells `[a, b]` (union of the singular radii, merged at the resolution).
    pub path_dependent: Vec<[f64; 2]>,
    /// Path-independent shells: `W_R` minus the path-dependent ones.
    pub path_independent: Vec<[f64; 2]>,
    /// The radial resolution used to merge singular radii, m.
    pub radial_resolution: f64,
}

/// Grid structure of the samples, when they form a full grid (see [`crate::analysis::scan::joint_grid`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GridShape {
    /// Values per joint.
    pub resolution: usize,
    /// Number of joints varied (all joints of the model).
    pub n_joints: usize,
}

/// Barycentric radii of the singular crossings between grid neighbours (sign changes of `det J*`).
fn grid_crossings(samples: &[ScanSample], grid: GridShape) -> Vec<f64> {
    let (r, n) = (grid.resolution, grid.n_joints);
    let mut out = Vec::new();
    for (s, a) in samples.iter().enumerate() {
        let da = a.det_generalized;
        if !da.is_finite() {
            return Vec::new();
        }
        let mut stride = 1;
        let mut rem = s;
        for _axis in (0..n).rev() {
            let idx = rem % r;
            rem /= r;
            if idx + 1 < r {
                let b = &samples[s + stride];
                let db = b.det_generalized;
                if da * db < 0.0 {
                    let t = da / (da - db);
                    let (ra, rb) = (a.point_from_com.norm(), b.point_from_com.norm());
                    out.push(ra + t * (rb - ra));
                }
            }
            stride *= r;
        }
    }
    out
}

/// The workspaces from a scan of joint space.
pub fn workspace_shells(samples: &[ScanSample], singular_threshold: f64, radial_resolution: f64, grid: Option<GridShape>) -> Result<WorkspaceShells> {
    if samples.is_empty() {
        return Err(SpacearmError::Dimension { what: "workspace samples".into(), expected: "at least one".into(), got: 0 });
    }
    if !(singular_threshold.is_finite() && singular_threshold >= 0.0) {
        return Err(SpacearmError::InvalidArgument(format!("the singularity threshold must be finite and >= 0, got {singular_threshold}")));
    }
    if !(radial_resolution.is_finite() && radial_resolution > 0.0) {
        return Err(SpacearmError::InvalidArgument(format!("the radial resolution must be finite and > 0, got {radial_resolution}")));
    }
    if let Some(g) = grid {
        if g.resolution < 2 || g.resolution.checked_pow(g.n_joints as u32) != Some(samples.len()) {
            return Err(SpacearmError::Dimension {
                what: "grid samples".into(),
                expected: format!("resolution^n_joints = {}^{}", g.resolution, g.n_joints),
                got: samples.len(),
            });
        }
    }
    let radii: Vec<f64> = samples.iter().map(|s| s.point_from_com.norm()).collect();
    let fixed: Vec<f64> = samples.iter().map(|s| s.point_from_base.norm()).collect();
    let minmax = |v: &[f64]| [v.iter().copied().fold(f64::INFINITY, f64::min), v.iter().copied().fold(f64::NEG_INFINITY, f64::max)];
    let reachable = minmax(&radii);
    let mut singular: Vec<f64> = samples.iter().zip(&radii).filter(|(s, _)| s.sigma_min_generalized < singular_threshold).map(|(_, &r)| r).collect();
    if let Some(g) = grid {
        singular.extend(grid_crossings(samples, g));
    }
    singular.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    let mut path_dependent: Vec<[f64; 2]> = Vec::new();
    for &r in &singular {
        match path_dependent.last_mut() {
            Some(last) if r - last[1] <= radial_resolution => last[1] = r,
            _ => path_dependent.push([r, r]),
        }
    }
    let mut path_independent = Vec::new();
    let mut lo = reachable[0];
    for iv in &path_dependent {
        if iv[0] > lo {
            path_independent.push([lo, iv[0]]);
        }
        lo = lo.max(iv[1]);
    }
    if reachable[1] > lo {
        path_independent.push([lo, reachable[1]]);
    }
    Ok(WorkspaceShells { reachable, fixed_base: minmax(&fixed), singular_radii: singular, path_dependent, path_independent, radial_resolution })
}
