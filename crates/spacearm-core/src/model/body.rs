//! Mass properties of one rigid body and their validation (DESIGN.md §4).

use nalgebra::{Matrix3, SymmetricEigen};

use crate::error::{Result, SpacearmError};

/// Relative tolerance on the symmetry, positive semi-definiteness and triangle inequality of
/// an inertia tensor, scaled by its largest principal moment.
pub const INERTIA_TOLERANCE: f64 = 1e-9;

/// Mass and rotational inertia of a rigid body, the inertia taken about its centre of mass and
/// expressed in the body frame.
#[derive(Debug, Clone, PartialEq)]
pub struct MassProperties {
    /// Mass, kg.
    pub mass: f64,
    /// Inertia tensor about the CM in body axes, kg·m².
    pub inertia: Matrix3<f64>,
}

impl MassProperties {
    /// Build and validate. `who` names the body in error messages; `require_positive_mass`
    /// is true for the base (whose CM defines the base frame) and false for links.
    pub fn new(who: &str, mass: f64, inertia: Matrix3<f64>, require_positive_mass: bool) -> Result<Self> {
        if !mass.is_finite() {
            return Err(SpacearmError::model(format!("{who}: mass must be finite, got {mass}")));
        }
        if require_positive_mass && mass <= 0.0 {
            return Err(SpacearmError::model(format!("{who}: mass must be > 0 kg, got {mass}")));
        }
        if mass < 0.0 {
            return Err(SpacearmError::model(format!("{who}: mass must be >= 0 kg, got {mass}")));
        }
        if let Some(v) = inertia.iter().find(|v| !v.is_finite()) {
            return Err(SpacearmError::model(format!("{who}: inertia must be finite, found {v}")));
        }
        let scale = inertia.abs().max().max(f64::MIN_POSITIVE);
        let asym = (inertia - inertia.transpose()).abs().max();
        if asym > INERTIA_TOLERANCE * scale {
            return Err(SpacearmError::model(format!(
                "{who}: inertia tensor must be symmetric, but |I - I^T| reaches {asym:.3e} (tolerance {:.1e} of its largest entry)",
                INERTIA_TOLERANCE
            )));
        }
        let sym = (inertia + inertia.transpose()) * 0.5;
        let mut moments = SymmetricEigen::new(sym).eigenvalues;
        // Entries near f64::MAX overflow the eigen-decomposition: refuse rather than compare NaNs.
        if moments.iter().any(|m| !m.is_finite()) {
            return Err(SpacearmError::model(format!(
                "{who}: inertia tensor entries are too large to analyse (largest |entry| {scale:e} kg·m²)"
            )));
        }
        moments.as_mut_slice().sort_by(|a, b| a.total_cmp(b));
        let (a, b, c) = (moments[0], moments[1], moments[2]);
        let tol = INERTIA_TOLERANCE * c.abs().max(f64::MIN_POSITIVE);
        if a < -tol {
            return Err(SpacearmError::model(format!(
                "{who}: inertia tensor must be positive semi-definite, but its principal moments are [{a:.6e}, {b:.6e}, {c:.6e}] kg·m²"
            )));
        }
        if require_positive_mass && a <= tol {
            return Err(SpacearmError::model(format!(
                "{who}: the base inertia tensor must be positive definite, but its smallest principal moment is {a:.6e} kg·m²"
            )));
        }
        // A physical body's principal moments obey I_a + I_b >= I_c (the second moments of
        // mass are non-negative).
        if a + b < c - tol {
            return Err(SpacearmError::model(format!(
                "{who}: principal moments [{a:.6e}, {b:.6e}, {c:.6e}] kg·m² violate the triangle inequality I1 + I2 >= I3 of a physical body"
            )));
        }
        Ok(MassProperties { mass, inertia: sym })
    }

    /// Inertia of a solid box of the given side lengths about its centre, in its own axes.
    pub fn solid_box(mass: f64, sx: f64, sy: f64, sz: f64) -> Matrix3<f64> {
        let k = mass / 12.0;
        Matrix3::from_diagonal(&nalgebra::Vector3::new(
            k * (sy * sy + sz * sz),
            k * (sx * sx + sz * sz),
            k * (sx * sx + sy * sy),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_non_physical_inertias() {
        let ok = MassProperties::solid_box(2.0, 0.1, 0.2, 0.3);
        assert!(MassProperties::new("b", 2.0, ok, true).is_ok());
        let mut asym = ok;
        asym[(0, 1)] = 0.01;
        assert!(MassProperties::new("b", 2.0, asym, true).unwrap_err().to_string().contains("symmetric"));
        let tri = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 1.0, 3.0));
        assert!(MassProperties::new("b", 2.0, tri, true).unwrap_err().to_string().contains("triangle"));
        let huge = Matrix3::from_diagonal(&nalgebra::Vector3::new(1e308, 1e308, 1e308)) + Matrix3::from_element(1e308);
        assert!(MassProperties::new("b", 1.0, huge, false).is_err());
        let neg = Matrix3::from_diagonal(&nalgebra::Vector3::new(-1.0, 1.0, 1.0));
        assert!(MassProperties::new("b", 2.0, neg, false).unwrap_err().to_string().contains("semi-definite"));
        assert!(MassProperties::new("base", 0.0, ok, true).unwrap_err().to_string().contains("> 0"));
        assert!(MassProperties::new("l", -1.0, ok, false).unwrap_err().to_string().contains(">= 0"));
        assert!(MassProperties::new("l", f64::NAN, ok, false).is_err());
    }
}
