//! The rules a model description must satisfy, each defined once.
//!
//! [`crate::model::ModelBuilder`] applies them, and every door that makes a model goes through
//! the builder: the Python `RobotBuilder`, the URDF loader (both through the bindings), the TOML
//! reader ([`crate::io::toml`]) and the Denavit–Hartenberg converter ([`crate::io::dh`]). So a
//! model gets the same verdict, with the same message, from every door; each error is a
//! [`ModelError`] that says which item and field broke the rule, from which a model file reader
//! finds the offending text.
//!
//! Where each rule lives: a link's or point's own fields (names, unique among those given
//! before, joint origin, CM, axis, rotation, limits, offset) are checked here when it is
//! added; mass and inertia by [`MassProperties::new`](crate::model::body::MassProperties::new);
//! the rules that need the whole model (a tree, no massless moving subtree, end effector,
//! initial joint coordinates) by [`check_structure`](crate::model::structure::check_structure) when
//! the model is built (model/structure.rs).

use nalgebra::{Quaternion, Unit, UnitQuaternion, UnitVector3, Vector3};

use crate::error::{ModelError, ModelField, ModelItem};
use crate::math::rotations::unit_quaternion_from_xyzw;
use crate::model::joint::{JointDynamics, JointLimits, JointType};

/// A spring given by its `stiffness` or by its `frequency` on a clamped parent, exactly one of
/// them: the one rule of a panel's hinge ([`crate::model::appendage::Restoring`]) and of a slosh
/// mode ([`crate::model::slosh::SloshRestoring`]) for every door (the bindings, the TOML
/// reader), which prefix the item's name to the message.
pub fn stiffness_or_frequency<T>(stiffness: Option<f64>, frequency: Option<f64>, by_stiffness: fn(f64) -> T, by_frequency: fn(f64) -> T) -> Result<T, String> {
    match (stiffness, frequency) {
        (Some(k), None) => Ok(by_stiffness(k)),
        (None, Some(w)) => Ok(by_frequency(w)),
        _ => Err("give stiffness or frequency (one of them)".into()),
    }
}

/// A moving joint's axis is refused when its largest component (in magnitude) is at most this:
/// it is normalized, and a shorter vector has no reliable direction.
pub const MIN_AXIS_COMPONENT: f64 = 1e-9;

/// Whether a part's quantity that must be positive (a mass, a length, a stiffness...) is:
/// finite and > 0. The builders of passive parts (appendage.rs, slosh.rs, cmg.rs) word the
/// refusal with the quantity's name and unit.
pub(crate) fn positive(v: f64) -> bool {
    v.is_finite() && v > 0.0
}

/// Whether a part's quantity that may be zero (a damping, a distance...) is: finite and >= 0.
pub(crate) fn non_negative(v: f64) -> bool {
    v.is_finite() && v >= 0.0
}

/// The refusals of a passive part's builder (a panel, a beam, a compliant joint, a slosh model):
/// each a [`ModelError`] on `item` whose message starts with the part's name `who`, with the one
/// wording of a quantity that must be positive or non-negative and of an axis.
pub(crate) struct PartRules<'a> {
    /// The item the errors name.
    pub item: ModelItem,
    /// The part, as the messages name it (`panel 'p'`).
    pub who: &'a str,
}

impl PartRules<'_> {
    fn refuse<T>(&self, field: ModelField, msg: String) -> Result<T, ModelError> {
        Err(ModelError::new(self.item, field, format!("{}: {msg}", self.who)))
    }

    /// `v` when finite and > 0, else "`what` must be finite and > 0`unit`, got `v`" on `field`.
    pub fn positive(&self, field: ModelField, what: &str, unit: &str, v: f64) -> Result<f64, ModelError> {
        if positive(v) { Ok(v) } else { self.refuse(field, format!("{what} must be finite and > 0{unit}, got {v}")) }
    }

    /// `v` when finite and >= 0, else "`what` must be finite and >= 0`unit`, got `v`" on `field`.
    pub fn non_negative(&self, field: ModelField, what: &str, unit: &str, v: f64) -> Result<f64, ModelError> {
        if non_negative(v) { Ok(v) } else { self.refuse(field, format!("{what} must be finite and >= 0{unit}, got {v}")) }
    }

    /// The unit vector along the part's axis `v`, else "`what` must be a finite non-zero vector,
    /// got `v`" on [`ModelField::Axis`].
    pub fn direction(&self, what: &str, v: &[f64; 3]) -> Result<[f64; 3], ModelError> {
        match crate::math::spatial::unit3(v) {
            Some(u) => Ok(u),
            None => self.refuse(ModelField::Axis, format!("{what} must be a finite non-zero vector, got {v:?}")),
        }
    }
}

/// A joint axis or rotation already of unit norm within this is kept bit for bit rather than
/// normalized again, so that a model written to a file reads back identical.
const UNIT_NORM_KEPT: f64 = 4.0 * f64::EPSILON;

/// Longest name of a model, body, joint, point or geometry, in characters: names are labels in
/// files, messages and figures; a longer one is garbage (and would be echoed into every message).
pub const MAX_NAME_CHARS: usize = 256;

/// A name must not be empty, longer than [`MAX_NAME_CHARS`], or hold control characters (NUL,
/// newlines, escapes: a name is one printable label); `what` says which name, for the message,
/// which shows at most the name's first 40 characters.
pub fn non_empty_name(item: ModelItem, field: ModelField, what: &str, name: &str) -> Result<(), ModelError> {
    if name.is_empty() {
        return Err(ModelError::new(item, field, format!("{what} must not be empty")));
    }
    let n = name.chars().count();
    if n > MAX_NAME_CHARS {
        let head: String = name.chars().take(40).collect();
        return Err(ModelError::new(item, field, format!("{what} must be at most {MAX_NAME_CHARS} characters, got {n} ('{head}...')")));
    }
    if let Some(c) = name.chars().find(|c| c.is_control()) {
        let shown: String = name.chars().take(40).map(|c| if c.is_control() { '?' } else { c }).collect();
        return Err(ModelError::new(item, field, format!("{what} must not contain control characters, got U+{:04X} in '{shown}'", c as u32)));
    }
    Ok(())
}

/// Which names are already given to a model under construction, as the caller looks them up
/// (the builder keeps hash sets, so that checking a name costs O(1) and a model of N items
/// builds in O(N)).
pub struct NamesTaken {
    /// The new item's name is already a body's (the base included).
    pub by_body: bool,
    /// The new item's name is already a point's.
    pub by_point: bool,
    /// The new link's joint name is already a joint's.
    pub joint_by_joint: bool,
}

/// A new link's body and joint names must differ from every body, point and joint name given
/// before.
pub fn new_link_names(item: ModelItem, name: &str, joint_name: &str, taken: NamesTaken) -> Result<(), ModelError> {
    if taken.by_body {
        return Err(ModelError::new(item, ModelField::Name, format!("body name '{name}' is used twice")));
    }
    if taken.by_point {
        return Err(ModelError::new(item, ModelField::Name, format!("body name '{name}' is already used by a point")));
    }
    if taken.joint_by_joint {
        return Err(ModelError::new(item, ModelField::JointName, format!("link '{name}': joint name '{joint_name}' is used twice")));
    }
    Ok(())
}

/// A new point's name must differ from every body and point name given before (`taken`: it
/// does not).
pub fn new_point_name(item: ModelItem, name: &str, taken: bool) -> Result<(), ModelError> {
    if taken {
        return Err(ModelError::new(item, ModelField::Name, format!("point name '{name}' is already used by a body or point")));
    }
    Ok(())
}

/// Largest magnitude of a length in a model (a joint origin, CM or point offset component, an
/// initial joint coordinate), m: 1000 km, larger than any spacecraft. Larger values are a units
/// mistake or garbage, and they ruin the numbers (at 1e150 m the mass matrix comes out
/// indefinite, at 1e300 non-finite) without any error.
pub const MAX_LENGTH: f64 = 1e6;

/// A position 3-vector of a link or point (joint origin, CM, offset): finite, each component
/// within [`MAX_LENGTH`] in magnitude.
pub fn position(item: ModelItem, field: ModelField, who: &str, what: &str, v: &[f64; 3]) -> Result<Vector3<f64>, ModelError> {
    if v.iter().any(|x| !x.is_finite()) {
        return Err(ModelError::new(item, field, format!("{who}: {what} must be finite, got {v:?}")));
    }
    if let Some(x) = v.iter().find(|x| x.abs() > MAX_LENGTH) {
        return Err(ModelError::new(
            item,
            field,
            format!("{who}: {what} component {x:e} m exceeds {MAX_LENGTH:e} m in magnitude (check the units), got {v:?}"),
        ));
    }
    Ok(Vector3::from(*v))
}

/// The unit axis of a joint, in the link frame: finite; for a moving joint, a vector whose
/// largest component exceeds [`MIN_AXIS_COMPONENT`] (scaled by that component before it is
/// normalized, so that the norm cannot overflow); a fixed joint's axis is ignored, and a zero
/// one becomes `z`.
pub fn joint_axis(item: ModelItem, who: &str, kind: JointType, axis: &[f64; 3]) -> Result<UnitVector3<f64>, ModelError> {
    let v = Vector3::from(*axis);
    if v.iter().any(|x| !x.is_finite()) {
        return Err(ModelError::new(item, ModelField::Axis, format!("{who}: joint axis must be finite, got {axis:?}")));
    }
    let largest = v.amax();
    if largest.is_nan() || largest <= MIN_AXIS_COMPONENT {
        if kind == JointType::Fixed {
            return Ok(Vector3::z_axis());
        }
        return Err(ModelError::new(
            item,
            ModelField::Axis,
            format!("{who}: joint axis must be a non-zero vector (it is normalized), got {axis:?}"),
        ));
    }
    if (v.norm() - 1.0).abs() <= UNIT_NORM_KEPT {
        return Ok(Unit::new_unchecked(v));
    }
    Ok(Unit::new_normalize(v / largest))
}

/// The rotation of a joint's child frame at `q = 0`, `[x, y, z, w]`: a unit quaternion within
/// [`crate::math::rotations::QUATERNION_TOLERANCE`], then normalized.
pub fn joint_rotation(item: ModelItem, who: &str, xyzw: &[f64; 4]) -> Result<UnitQuaternion<f64>, ModelError> {
    let rotation = unit_quaternion_from_xyzw(&format!("{who}: joint rotation"), xyzw)
        .map_err(|e| ModelError::new(item, ModelField::Rotation, e.to_string()))?;
    let raw = Quaternion::new(xyzw[3], xyzw[0], xyzw[1], xyzw[2]);
    if (raw.norm() - 1.0).abs() <= UNIT_NORM_KEPT {
        return Ok(UnitQuaternion::new_unchecked(raw));
    }
    Ok(rotation)
}

/// Joint limits: `lower <= upper` (neither NaN), velocity and effort limits `>= 0`.
pub fn joint_limits(item: ModelItem, who: &str, limits: &JointLimits) -> Result<(), ModelError> {
    let l = limits;
    if l.lower.is_nan() || l.upper.is_nan() || l.lower > l.upper {
        return Err(ModelError::new(
            item,
            ModelField::Limits,
            format!("{who}: position limits must satisfy lower <= upper, got [{}, {}]", l.lower, l.upper),
        ));
    }
    if l.velocity.is_nan() || l.effort.is_nan() || l.velocity < 0.0 || l.effort < 0.0 {
        return Err(ModelError::new(
            item,
            ModelField::Limits,
            format!("{who}: velocity and effort limits must be >= 0, got {} and {}", l.velocity, l.effort),
        ));
    }
    Ok(())
}

/// Largest joint stiffness or damping accepted (N·m/rad, N/m, N·m·s/rad, N·s/m): larger values
/// are a units mistake, and they make the motion too stiff for any step.
pub const MAX_JOINT_STIFFNESS: f64 = 1e12;

/// A joint's passive dynamics (docs/flexibility.md): stiffness and damping finite, `>= 0` and at
/// most [`MAX_JOINT_STIFFNESS`]; `rest` finite within [`MAX_LENGTH`]; a fixed joint has no
/// coordinate, so it can carry no spring, damper or rest value and cannot be passive.
pub fn joint_dynamics(item: ModelItem, who: &str, kind: JointType, d: &JointDynamics) -> Result<(), ModelError> {
    let bad = |msg: String| Err(ModelError::new(item, ModelField::JointDynamics, format!("{who}: {msg}")));
    for (what, v) in [("stiffness", d.stiffness), ("damping", d.damping)] {
        if !(v.is_finite() && v >= 0.0) {
            return bad(format!("{what} must be finite and >= 0, got {v}"));
        }
        if v > MAX_JOINT_STIFFNESS {
            return bad(format!("{what} {v:e} exceeds {MAX_JOINT_STIFFNESS:e} (check the units)"));
        }
    }
    if !d.rest.is_finite() || d.rest.abs() > MAX_LENGTH {
        return bad(format!("rest must be finite and within {MAX_LENGTH:e} (m or rad) in magnitude, got {}", d.rest));
    }
    if kind == JointType::Fixed && *d != JointDynamics::default() {
        return bad(format!(
            "a fixed joint has no coordinate: it takes no stiffness, damping, rest or actuated = false, got {d:?}"
        ));
    }
    Ok(())
}
