//! Equivalent mechanical models of propellant slosh (docs/flexibility.md, "Fuel slosh"), built
//! from passive joints with springs and dampers by [`ModelBuilder::add_slosh`]:
//!
//! - `SpringMass`: a point mass on a passive prismatic joint. Its joint sits at `position` (in
//!   the parent's frame, measured from the parent's CM) and slides along `axis`: the mass is at
//!   `position + q·axis` and feels `−k q − c q̇`.
//! - `Pendulum` (1 DOF): a point bob on a massless rod of `length` from the pivot at `position`,
//!   on a passive revolute joint about `hinge` (perpendicular to `axis`); at `q = 0` the bob is
//!   at `position + length·axis`. The joint carries `−k q − c q̇`.
//! - `SphericalPendulum` (2 DOF): the same bob on two passive revolute joints at the pivot, the
//!   first about `e₁ = hinge`, the second about `e₂ = axis × e₁` (turned with the first); the
//!   link between them (`<name>_gimbal`) is massless. Each joint carries its own spring and
//!   damper (`−k qᵢ − c q̇ᵢ`: damping per joint, not on the bob's velocity as Basilisk's
//!   `LinearSpringMassDamper`/pendulum effectors do; the two agree for small swings about
//!   `q = 0`). The pair is singular at `q₂ = ±π/2`, where the bob lies on the first joint's
//!   axis and that joint no longer moves it (the articulated inertia about it is zero: the
//!   dynamics then refuses with a `SingularError`).
//!
//! In orbit there is no gravity: the restoring force of a real slosh mode comes from the
//! vehicle's acceleration (thrust), and it is represented here by the joint spring of the
//! model, given as a `stiffness` or as the mode's `frequency` ω on a clamped tank: `k = m ω²`
//! for the spring–mass, `k = m L² ω²` for each pendulum joint (the small-swing frequency of
//! a pendulum in an acceleration field `a` is `√(a/L)`, so `ω` is that of the design
//! acceleration). A joint spring is an internal force: it gives the mode's lateral force but not
//! the thrust's moment on the vehicle when the liquid is displaced (the displaced weight
//! `m a x`); for that, a pendulum takes no spring (`Stiffness(0.0)`) and the thrust is applied
//! to the vehicle as a base force, which accelerates the tank and so restores the bob
//! (docs/flexibility.md, "Slosh under thrust: which model holds which moment").

use crate::error::{ModelError, ModelField, ModelItem};
use crate::model::builder::{LinkSpec, ModelBuilder};
use crate::model::joint::{JointDynamics, JointLimits, JointType};
use crate::model::validate::{non_negative, positive, stiffness_or_frequency, PartRules};
use crate::math::spatial::{cross3 as cross, dot3 as dot, unit3 as normalized};

/// Which equivalent mechanical model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SloshModel {
    /// A point mass on a passive prismatic joint.
    SpringMass,
    /// A point bob on one passive revolute joint.
    Pendulum,
    /// A point bob on two passive revolute joints (massless link between them).
    SphericalPendulum,
}

impl SloshModel {
    /// The names of [`SloshModel::from_name`].
    pub const NAMES: [&'static str; 3] = ["spring-mass", "pendulum", "spherical-pendulum"];

    /// `"spring-mass"`, `"pendulum"` or `"spherical-pendulum"`; any other name is refused with
    /// the one message of every door (which prefixes the slosh mode's name).
    pub fn from_name(name: &str) -> Result<SloshModel, String> {
        match name {
            "spring-mass" => Ok(SloshModel::SpringMass),
            "pendulum" => Ok(SloshModel::Pendulum),
            "spherical-pendulum" => Ok(SloshModel::SphericalPendulum),
            _ => Err(format!("model must be one of {:?}, got '{name}'", SloshModel::NAMES)),
        }
    }
}

/// The restoring spring of a slosh mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SloshRestoring {
    /// The joint stiffness itself (N/m for the spring–mass, N·m/rad per pendulum joint).
    Stiffness(f64),
    /// The mode's frequency ω on a clamped tank, rad/s (module docs).
    Frequency(f64),
}

impl SloshRestoring {
    /// From a door's options `stiffness` and `frequency` (one of them; [`stiffness_or_frequency`]).
    pub fn from_options(stiffness: Option<f64>, frequency: Option<f64>) -> Result<Self, String> {
        stiffness_or_frequency(stiffness, frequency, SloshRestoring::Stiffness, SloshRestoring::Frequency)
    }
}

/// Everything [`ModelBuilder::add_slosh`] needs (geometry: module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct SloshSpec {
    /// Name of the slosh body (the bob); joints `<name>_joint` (or `_joint1`, `_joint2`).
    pub name: String,
    /// The body carrying the tank (the base or a link).
    pub parent: String,
    /// The equivalent mechanical model.
    pub model: SloshModel,
    /// The sloshing mass, kg (> 0).
    pub mass: f64,
    /// The joint (pivot) position in the parent's frame, from its CM, m.
    pub position: [f64; 3],
    /// The slide direction (spring–mass) or the rod direction at `q = 0` (pendulums), parent frame.
    pub axis: [f64; 3],
    /// The first hinge axis of a pendulum (perpendicular to `axis`); `None`: the unit vector
    /// perpendicular to `axis` nearest the parent's axis of `axis`'s smallest component.
    pub hinge: Option<[f64; 3]>,
    /// The rod length of a pendulum, m (> 0); `None` for the spring–mass.
    pub length: Option<f64>,
    /// The restoring spring.
    pub restoring: SloshRestoring,
    /// Viscous damping per joint (N·s/m or N·m·s/rad), ≥ 0.
    pub damping: f64,
}

/// The links of a slosh mode, in the order they are added, each with its joint's dynamics
/// (module docs): one for the spring–mass and the pendulum, the massless gimbal then the bob for
/// the spherical pendulum. `item` names the first link for the errors (the builder's next
/// link). The parent and the names are checked when the links are added.
pub fn slosh_links(spec: &SloshSpec, item: ModelItem) -> Result<Vec<(LinkSpec, JointDynamics)>, ModelError> {
    let who = format!("slosh '{}'", spec.name);
    let bad = |field: ModelField, msg: String| Err(ModelError::new(item, field, format!("{who}: {msg}")));
    let rules = PartRules { item, who: &who };
    rules.positive(ModelField::Mass, "mass", " kg", spec.mass)?;
    let axis = rules.direction("axis", &spec.axis)?;
    rules.non_negative(ModelField::JointDynamics, "damping", "", spec.damping)?;
    let length = match (spec.model, spec.length) {
        (SloshModel::SpringMass, None) => 0.0,
        (SloshModel::SpringMass, Some(_)) => return bad(ModelField::Com, "a spring-mass takes no length (its mass is at position + q·axis)".into()),
        (_, None) => return bad(ModelField::Com, "a pendulum needs a length (> 0 m)".into()),
        (_, Some(l)) if !positive(l) => return bad(ModelField::Com, format!("length must be finite and > 0 m, got {l}")),
        (_, Some(l)) => l,
    };
    if spec.model == SloshModel::SpringMass && spec.hinge.is_some() {
        return bad(ModelField::Axis, "a spring-mass takes no hinge".into());
    }
    let lever = if spec.model == SloshModel::SpringMass { 1.0 } else { length * length };
    let stiffness = match spec.restoring {
        SloshRestoring::Stiffness(k) => k,
        SloshRestoring::Frequency(w) if non_negative(w) => spec.mass * lever * w * w,
        SloshRestoring::Frequency(w) => return bad(ModelField::JointDynamics, format!("frequency must be finite and >= 0 rad/s, got {w}")),
    };
    let dynamics = JointDynamics { actuated: false, stiffness, damping: spec.damping, rest: 0.0 };
    let link = |name: String, parent: String, joint: String, origin: [f64; 3], axis: [f64; 3], com: [f64; 3], mass: f64| LinkSpec {
        name,
        parent,
        joint_name: Some(joint),
        kind: if spec.model == SloshModel::SpringMass { JointType::Prismatic } else { JointType::Revolute },
        origin_in_parent: origin,
        rotation_in_parent: [0.0, 0.0, 0.0, 1.0],
        axis,
        com_from_joint: com,
        mass,
        inertia: [[0.0; 3]; 3],
        limits: JointLimits::unlimited(),
    };
    let name = spec.name.clone();
    if spec.model == SloshModel::SpringMass {
        return Ok(vec![(link(name.clone(), spec.parent.clone(), format!("{name}_joint"), spec.position, axis, [0.0; 3], spec.mass), dynamics)]);
    }
    let hinge = match spec.hinge {
        Some(h) => {
            let Some(h) = normalized(&h) else {
                return bad(ModelField::Axis, format!("hinge must be a finite non-zero vector, got {h:?}"));
            };
            if dot(&h, &axis).abs() > 1e-9 {
                return bad(ModelField::Axis, format!("hinge {h:?} must be perpendicular to axis {axis:?}"));
            }
            h
        }
        None => {
            // The parent axis along axis's smallest component, made perpendicular to axis.
            let k = (0..3).min_by(|&i, &j| axis[i].abs().total_cmp(&axis[j].abs())).unwrap_or(0);
            let mut e = [0.0; 3];
            e[k] = 1.0;
            let d = dot(&e, &axis);
            normalized(&[e[0] - d * axis[0], e[1] - d * axis[1], e[2] - d * axis[2]]).unwrap_or([1.0, 0.0, 0.0])
        }
    };
    let rod = [length * axis[0], length * axis[1], length * axis[2]];
    if spec.model == SloshModel::Pendulum {
        return Ok(vec![(link(name.clone(), spec.parent.clone(), format!("{name}_joint"), spec.position, hinge, rod, spec.mass), dynamics)]);
    }
    let gimbal = format!("{name}_gimbal");
    let e2 = cross(&axis, &hinge);
    Ok(vec![
        (link(gimbal.clone(), spec.parent.clone(), format!("{name}_joint1"), spec.position, hinge, [0.0; 3], 0.0), dynamics),
        (link(name.clone(), gimbal, format!("{name}_joint2"), [0.0; 3], e2, rod, spec.mass), dynamics),
    ])
}

impl ModelBuilder {
    /// Add a slosh mode as passive links ([`slosh_links`]); the links are checked by the usual
    /// rules when they are added.
    pub fn add_slosh(&mut self, spec: SloshSpec) -> Result<&mut Self, ModelError> {
        for (link, dynamics) in slosh_links(&spec, ModelItem::Link(self.n_links()))? {
            let name = link.name.clone();
            self.add_link(link)?;
            self.set_joint_dynamics(&name, dynamics)?;
        }
        Ok(self)
    }
}
