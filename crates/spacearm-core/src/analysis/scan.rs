//! Batch scan over joint space: for each sample `q`, with the base at the origin of 𝒥 and
//! aligned with it (which loses nothing: see [`crate::analysis::singularity`]), the singular
//! values of the task rows of `J*` and `J_m` and the positions that the workspace analysis needs.
//!
//! Samples run in parallel (rayon), each on a workspace of its own thread and from its own
//! input only, and results are stored at the sample's index: the output is identical for any
//! number of threads.

use nalgebra::{DMatrix, Vector3};
use rayon::prelude::*;

use super::singularity::{check_has_dofs, task_jacobians};
use super::{Svd, Task};
use crate::model::data::Data;
use crate::error::{Result, SpacearmError};
use crate::algorithms::kinematics::{check_body, point_position};
use crate::model::Model;
use crate::algorithms::momentum::center_of_mass_from_data;

/// The results of one joint-space sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanSample {
    /// Smallest singular value of the task rows of `J*`.
    pub sigma_min_generalized: f64,
    /// Largest singular value of the task rows of `J*`.
    pub sigma_max_generalized: f64,
    /// Manipulability `Π σᵢ` of the task rows of `J*`.
    pub manipulability_generalized: f64,
    /// Determinant of the task rows of `J*` when they are square (m = N), else NaN. Its sign
    /// changes across a dynamic singularity, which locates the singular surfaces on a grid.
    pub det_generalized: f64,
    /// Smallest singular value of the task rows of the fixed-base `J_m`.
    pub sigma_min_fixed: f64,
    /// Manipulability of the task rows of `J_m`.
    pub manipulability_fixed: f64,
    /// Determinant of the task rows of `J_m` when square, else NaN.
    pub det_fixed: f64,
    /// The point's position from the base CM, in the base frame: the fixed-base workspace.
    pub point_from_base: Vector3<f64>,
    /// The point's position from the system CM, in the base frame: the free-floating
    /// workspace (Vafa & Dubowsky's virtual manipulator; its norm is the barycentric distance).
    pub point_from_com: Vector3<f64>,
}

fn det_if_square(j: &DMatrix<f64>) -> f64 {
    if j.is_square() { j.clone().determinant() } else { f64::NAN }
}

/// One sample (the base at the origin, aligned with 𝒥).
pub fn scan_one(model: &Model, data: &mut Data, x: &mut [f64], q: &[f64], body: usize, offset: &Vector3<f64>, task: &Task) -> Result<ScanSample> {
    x[7..].copy_from_slice(q);
    let (jstar, jm) = task_jacobians(model, data, x, body, offset, task)?;
    let point = point_position(data, body, offset);
    let com = center_of_mass_from_data(model, data);
    let s_star = Svd::new(&jstar)?;
    let s_fixed = Svd::new(&jm)?;
    Ok(ScanSample {
        sigma_min_generalized: s_star.sigma_min(),
        sigma_max_generalized: s_star.sigma_max(),
        manipulability_generalized: s_star.singular_values.iter().product(),
        det_generalized: det_if_square(&jstar),
        sigma_min_fixed: s_fixed.sigma_min(),
        manipulability_fixed: s_fixed.singular_values.iter().product(),
        det_fixed: det_if_square(&jm),
        point_from_base: point,
        point_from_com: point - com,
    })
}

/// Scan `samples` (row-major, M×N: one joint vector per row) in parallel.
pub fn scan(model: &Model, samples: &[f64], body: usize, offset: &Vector3<f64>, task: &Task) -> Result<Vec<ScanSample>> {
    check_has_dofs(model)?;
    check_body(model, body)?;
    crate::error::check_finite("point offset", offset.as_slice())?;
    let n = model.n_dof();
    if !samples.len().is_multiple_of(n) {
        return Err(SpacearmError::Dimension {
            what: "joint samples".into(),
            expected: format!("a multiple of N = {n} (one row of N joint coordinates per sample)"),
            got: samples.len(),
        });
    }
    crate::error::check_finite("joint samples", samples)?;
    let mut x0 = vec![0.0; 7 + n];
    x0[6] = 1.0;
    samples
        .par_chunks(n)
        .map_init(|| (Data::new(model), x0.clone()), |(data, x), q| scan_one(model, data, x, q, body, offset, task))
        .collect()
}

/// A regular grid over the joints: `resolution` values per joint between `lower[i]` and
/// `upper[i]` inclusive, the last joint varying fastest (row-major M×N, M = resolutionᴺ).
pub fn joint_grid(lower: &[f64], upper: &[f64], resolution: usize) -> Result<Vec<f64>> {
    let n = lower.len();
    if upper.len() != n {
        return Err(SpacearmError::Dimension { what: "upper joint bounds".into(), expected: n.to_string(), got: upper.len() });
    }
    if resolution < 2 {
        return Err(SpacearmError::InvalidArgument(format!("the grid resolution must be at least 2 values per joint, got {resolution}")));
    }
    crate::error::check_finite("lower joint bounds", lower)?;
    crate::error::check_finite("upper joint bounds", upper)?;
    if let Some(i) = (0..n).find(|&i| lower[i] > upper[i]) {
        return Err(SpacearmError::InvalidArgument(format!("joint {i}: the grid needs lower <= upper, got [{}, {}]", lower[i], upper[i])));
    }
    // Admission: the grid (N values per sample) and the scan's results (one ScanSample each).
    let total = (resolution as f64).powi(n as i32);
    crate::admission::admit(
        format_args!("a joint grid of {resolution}^{n} = {total:.3e} samples and its scan"),
        total * (crate::admission::bytes_of::<f64>(n as f64) + std::mem::size_of::<ScanSample>() as f64),
        "lower the resolution, or scan random samples instead",
    )?;
    let m = resolution.pow(n as u32);
    let mut out = vec![0.0; m * n];
    for s in 0..m {
        let mut rem = s;
        for i in (0..n).rev() {
            let k = rem % resolution;
            rem /= resolution;
            out[s * n + i] = lower[i] + (upper[i] - lower[i]) * k as f64 / (resolution - 1) as f64;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    #[test]
    fn grid_order_and_limits() {
        let g = joint_grid(&[0.0, -1.0], &[1.0, 1.0], 3).unwrap();
        assert_eq!(g.len(), 18);
        assert_eq!(&g[0..2], &[0.0, -1.0]);
        assert_eq!(&g[2..4], &[0.0, 0.0]);
        assert_eq!(&g[16..18], &[1.0, 1.0]);
        assert!(joint_grid(&[0.0], &[1.0], 1).is_err());
        assert!(joint_grid(&[1.0], &[0.0], 3).is_err());
        assert!(joint_grid(&[0.0; 6], &[1.0; 6], 100).is_err());
    }

    #[test]
    fn parallel_scan_equals_serial() {
        let m = presets::planar4();
        let ee = m.points()[m.end_effector().unwrap()].clone();
        let g = joint_grid(&[-1.0; 4], &[1.0; 4], 4).unwrap();
        let par = scan(&m, &g, ee.body, &ee.offset, &Task::planar()).unwrap();
        let mut d = Data::new(&m);
        let mut x = vec![0.0; 11];
        x[6] = 1.0;
        for (k, q) in g.chunks(4).enumerate() {
            let s = scan_one(&m, &mut d, &mut x, q, ee.body, &ee.offset, &Task::planar()).unwrap();
            // Debug strings compare NaN determinants (non-square task) too.
            assert_eq!(format!("{s:?}"), format!("{:?}", par[k]));
        }
        assert!(scan(&m, &g[..5], ee.body, &ee.offset, &Task::planar()).is_err());
    }
}
