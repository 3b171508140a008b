//! Mass properties of one rigid body and the physical rules they obey (each rule defined here
//! once; every door that makes a model reaches them through [`crate::model::ModelBuilder`]).

use nalgebra::{Matrix3, SymmetricEigen};

use crate::error::{ModelError, ModelField, ModelItem};

/// Relative tolerance on the symmetry, positive semi-definiteness and triangle inequality of
/// an inertia tensor, scaled by its largest principal moment.
pub const INERTIA_TOLERANCE: f64 = 1e-9;

/// Smallest non-zero mass of a body, kg (a microgram; a massless link, mass 0, is allowed).
pub const MIN_MASS: f64 = 1e-9;

/// Smallest radius of gyration `k = √(I_min / m)` of a base (a free-flying body: the
/// spacecraft, a target), m: a micrometre. A base must resist rotation about every axis (its
/// inertia is positive definite); below `m·k²` the moment is a units mistake or garbage (a 50 kg
/// target of 1e-20 kg·m² has k = 1.4e-11 m) and the base's response to any torque is round-off.
pub const MIN_RADIUS_OF_GYRATION: f64 = 1e-6;

/// Largest mass of a body, kg (10⁹ t, far above any spacecraft). Larger masses are a units
/// mistake, and near the top of the floats they make the mass matrix non-finite.
pub const MAX_MASS: f64 = 1e12;

/// Largest magnitude accepted for an inertia entry, kg·m²: a body of [`MAX_MASS`] with its mass
/// [`crate::model::validate::MAX_LENGTH`] from its CM. Anything larger is certainly a units
/// mistake.
pub const MAX_INERTIA_ENTRY: f64 = MAX_MASS * crate::model::validate::MAX_LENGTH * crate::model::validate::MAX_LENGTH;

/// The option that loads inertias breaking the triangle inequality, by the name it has in Rust,
/// Python (keyword argument) and, with dashes, on the command line. The refusal names it.
pub const ALLOW_NONPHYSICAL_INERTIA: &str = "allow_nonphysical_inertia";

/// What [`MassProperties::checked`] does with an inertia tensor whose principal moments break
/// the triangle inequality `I1 + I2 >= I3`. Only that rule can be relaxed: symmetry and positive
/// semi-definiteness are what the dynamics need (a positive definite mass matrix), while the
/// triangle inequality only says the moments come from a real mass distribution. Identified
/// inertias published for flown robots break it (ETS-VII), hence the option.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TriangleInequality {
    /// Refuse such a tensor (the default).
    #[default]
    Enforce,
    /// Accept it, with a warning naming the body (the option [`ALLOW_NONPHYSICAL_INERTIA`]).
    Warn,
}

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
    /// Build and validate: the mass finite and `>= 0` (`> 0` for the base, whose CM defines the
    /// base frame) and, unless zero, within [`MIN_MASS`]..=[`MAX_MASS`], the inertia finite, at most [`MAX_INERTIA_ENTRY`] in magnitude, symmetric,
    /// positive semi-definite (definite for the base) and obeying the triangle inequality.
    /// `item` and `who` say which body it is, in the error's location and message.
    pub fn new(item: ModelItem, who: &str, mass: f64, inertia: Matrix3<f64>, require_positive_mass: bool) -> Result<Self, ModelError> {
        Self::checked(item, who, mass, inertia, require_positive_mass, TriangleInequality::Enforce).map(|(m, _)| m)
    }

    /// As [`MassProperties::new`], with the triangle inequality enforced or, under
    /// [`TriangleInequality::Warn`], reported: the second value is then the warning's text when
    /// the tensor breaks it.
    pub fn checked(
        item: ModelItem,
        who: &str,
        mass: f64,
        inertia: Matrix3<f64>,
        require_positive_mass: bool,
        triangle: TriangleInequality,
    ) -> Result<(Self, Option<String>), ModelError> {
        let mass_error = |m: String| ModelError::new(item, ModelField::Mass, m);
        let inertia_error = |m: String| ModelError::new(item, ModelField::Inertia, m);
        if !mass.is_finite() {
            return Err(mass_error(format!("{who}: mass must be finite, got {mass}")));
        }
        if require_positive_mass && mass <= 0.0 {
            return Err(mass_error(format!("{who}: mass must be > 0 kg, got {mass}")));
        }
        if mass < 0.0 {
            return Err(mass_error(format!("{who}: mass must be >= 0 kg, got {mass}")));
        }
        if mass != 0.0 && !(MIN_MASS..=MAX_MASS).contains(&mass) {
            return Err(mass_error(format!(
                "{who}: mass {mass:e} kg is outside the physical range [{MIN_MASS:e}, {MAX_MASS:e}] kg (or 0 for a massless link; check the units)"
            )));
        }
        for v in inertia.iter() {
            if !v.is_finite() {
                return Err(inertia_error(format!("{who}: inertia must be finite, found {v}")));
            }
            if v.abs() > MAX_INERTIA_ENTRY {
                return Err(inertia_error(format!(
                    "{who}: inertia entry {v:e} kg·m² exceeds {MAX_INERTIA_ENTRY:e} in magnitude (check the units)"
                )));
            }
        }
        let scale = inertia.abs().max().max(f64::MIN_POSITIVE);
        let asym = (inertia - inertia.transpose()).abs().max();
        if asym > INERTIA_TOLERANCE * scale {
            return Err(inertia_error(format!(
                "{who}: inertia tensor must be symmetric, but |I - I^T| reaches {asym:.3e} (tolerance {:.1e} of its largest entry)",
                INERTIA_TOLERANCE
            )));
        }
        let sym = (inertia + inertia.transpose()) * 0.5;
        let mut moments = SymmetricEigen::new(sym).eigenvalues;
        // Entries near f64::MAX overflow the eigen-decomposition: refuse rather than compare NaNs.
        if moments.iter().any(|m| !m.is_finite()) {
            return Err(inertia_error(format!(
                "{who}: inertia tensor entries are too large to analyse (largest |entry| {scale:e} kg·m²)"
            )));
        }
        moments.as_mut_slice().sort_by(|a, b| a.total_cmp(b));
        let (a, b, c) = (moments[0], moments[1], moments[2]);
        let tol = INERTIA_TOLERANCE * c.abs().max(f64::MIN_POSITIVE);
        if a < -tol {
            return Err(inertia_error(format!(
                "{who}: inertia tensor must be positive semi-definite, but its principal moments are [{a:.6e}, {b:.6e}, {c:.6e}] kg·m²"
            )));
        }
        if require_positive_mass && a <= tol {
            // A positive smallest moment this far below the largest is positive definite in
            // exact arithmetic, but not distinguishable from singular in double precision: say
            // that it is the conditioning that is refused (issue 37 item 8).
            if a > 0.0 {
                return Err(inertia_error(format!(
                    "{who}: the base inertia tensor is too ill-conditioned: its principal moments [{a:.6e}, {b:.6e}, {c:.6e}] kg·m² span a \
                     ratio of {:.3e}, and a smallest moment below {INERTIA_TOLERANCE:e} × the largest ({tol:.3e} kg·m²) cannot be told \
                     from zero in double precision (the mass matrix would be numerically singular); check the units of the moments",
                    c / a
                )));
            }
            return Err(inertia_error(format!(
                "{who}: the base inertia tensor must be positive definite, but its smallest principal moment is {a:.6e} kg·m²"
            )));
        }
        let floor = mass * MIN_RADIUS_OF_GYRATION * MIN_RADIUS_OF_GYRATION;
        if require_positive_mass && a < floor {
            return Err(inertia_error(format!(
                "{who}: the base's smallest principal moment {a:.6e} kg·m² is below m·k² = {floor:.3e} kg·m² with the smallest radius of \
                 gyration k = {MIN_RADIUS_OF_GYRATION:e} m of a real body of {mass} kg (check the units): a body that small cannot \
                 turn against anything, and its dynamics are round-off"
            )));
        }
        // A physical body's principal moments obey I_a + I_b >= I_c (the second moments of
        // mass are non-negative).
        let mut warning = None;
        if a + b < c - tol {
            let broken = format!(
                "{who}: principal moments [{a:.6e}, {b:.6e}, {c:.6e}] kg·m² violate the triangle inequality I1 + I2 >= I3 of a physical body"
            );
            match triangle {
                TriangleInequality::Enforce => {
                    return Err(inertia_error(format!(
                        "{broken}; to load published data that break it anyway, pass {ALLOW_NONPHYSICAL_INERTIA}=True \
                         (command line: --allow-nonphysical-inertia)"
                    )))
                }
                TriangleInequality::Warn => warning = Some(format!("{broken}; loaded anyway ({ALLOW_NONPHYSICAL_INERTIA})")),
            }
        }
        Ok((MassProperties { mass, inertia: sym }, warning))
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
        assert!(MassProperties::new(ModelItem::Base, "b", 2.0, ok, true).is_ok());
        let mut asym = ok;
        asym[(0, 1)] = 0.01;
        assert!(MassProperties::new(ModelItem::Base, "b", 2.0, asym, true).unwrap_err().to_string().contains("symmetric"));
        let tri = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 1.0, 3.0));
        assert!(MassProperties::new(ModelItem::Base, "b", 2.0, tri, true).unwrap_err().to_string().contains("triangle"));
        let huge = Matrix3::from_diagonal(&nalgebra::Vector3::new(1e308, 1e308, 1e308)) + Matrix3::from_element(1e308);
        assert!(MassProperties::new(ModelItem::Base, "b", 1.0, huge, false).unwrap_err().to_string().contains("finite"));
        let huge = Matrix3::from_diagonal(&nalgebra::Vector3::new(1e200, 1e200, 1e200));
        assert!(MassProperties::new(ModelItem::Base, "b", 1.0, huge, false).unwrap_err().to_string().contains("exceeds"));
        // At the magnitude limit (1e12 kg at 1e6 m: 1e24 kg·m²): a valid tensor; just above, refused.
        let big = Matrix3::from_diagonal(&nalgebra::Vector3::new(1e24, 1e24, 1e24));
        assert!(MassProperties::new(ModelItem::Base, "b", 1.0, big, false).is_ok());
        let over = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.1e24, 1.1e24, 1.1e24));
        assert!(MassProperties::new(ModelItem::Base, "b", 1.0, over, false).unwrap_err().to_string().contains("exceeds"));
        // Masses: 0 (a massless link) and the bounds themselves accepted; outside them refused.
        for m in [0.0, MIN_MASS, 1.0, MAX_MASS] {
            assert!(MassProperties::new(ModelItem::Link(0), "l", m, ok, false).is_ok(), "{m}");
        }
        for m in [1e-12, 0.9e-9, 1.1e12, 1e308] {
            let e = MassProperties::new(ModelItem::Link(0), "l", m, ok, false).unwrap_err();
            assert_eq!(e.field, ModelField::Mass);
            assert!(e.to_string().contains("physical range"), "{e}");
        }
        let e = MassProperties::new(ModelItem::Link(2), "l", -1.0, ok, false).unwrap_err();
        assert_eq!((e.item, e.field), (ModelItem::Link(2), ModelField::Mass));
        let e = MassProperties::new(ModelItem::Link(2), "l", 1.0, tri, false).unwrap_err();
        assert_eq!((e.item, e.field), (ModelItem::Link(2), ModelField::Inertia));
        assert!(e.message.contains(ALLOW_NONPHYSICAL_INERTIA), "{e}");
        let (m, warning) = MassProperties::checked(ModelItem::Link(2), "l", 1.0, tri, false, TriangleInequality::Warn).unwrap();
        assert_eq!(m.inertia, tri);
        assert!(warning.unwrap().contains("triangle"));
        let (_, warning) = MassProperties::checked(ModelItem::Link(2), "l", 1.0, ok, false, TriangleInequality::Warn).unwrap();
        assert!(warning.is_none());
        let neg = Matrix3::from_diagonal(&nalgebra::Vector3::new(-1.0, 1.0, 1.0));
        // Only the triangle inequality is relaxed.
        assert!(MassProperties::checked(ModelItem::Base, "b", 2.0, neg, false, TriangleInequality::Warn).is_err());
        assert!(MassProperties::new(ModelItem::Base, "b", 2.0, neg, false).unwrap_err().to_string().contains("semi-definite"));
        assert!(MassProperties::new(ModelItem::Base, "base", 0.0, ok, true).unwrap_err().to_string().contains("> 0"));
        assert!(MassProperties::new(ModelItem::Base, "l", -1.0, ok, false).unwrap_err().to_string().contains(">= 0"));
        assert!(MassProperties::new(ModelItem::Base, "l", f64::NAN, ok, false).is_err());
    }
}
