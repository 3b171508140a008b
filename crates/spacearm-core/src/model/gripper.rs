//! Grippers as ordinary links with capsule fingers (docs/contact.md, "Grippers"):
//!
//! - the **palm** `<name>` on a fixed joint `<name>_mount` of its parent body at `position`
//!   (parent frame, from the parent's CM) turned by `rotation` (`[x, y, z, w]`, palm frame in the
//!   parent frame); its CM at the mount; the fingers point along the palm's `+z` (the approach
//!   axis);
//! - **two fingers** (`fingers = 2`, a parallel gripper): `<name>_finger0` and `<name>_finger1`
//!   on the prismatic joints `<name>_finger<i>_joint` at `(±w/2, 0, 0)` in the palm frame
//!   (`w` = `opening`, the distance between the finger axes when open), sliding inward along
//!   `∓x`: at the joint value `q` (m, both fingers alike) the finger axes are `w − 2q` apart and
//!   the gap between the finger surfaces is `w − 2q − 2r` (`r` the finger radius);
//! - **three fingers** (`fingers = 3`): `<name>_finger<i>` on the revolute joints
//!   `<name>_finger<i>_joint` at `(R cos θᵢ, R sin θᵢ, 0)`, `θᵢ = 2πi/3`, `R = w/2`, about the axis
//!   `r̂ᵢ × ẑ = (sin θᵢ, −cos θᵢ, 0)`, so that `q > 0` tilts the finger inward: its tip at
//!   `ℓ` from the hinge is `R − ℓ sin q` from the palm's axis and `ℓ cos q` above the palm.
//!
//! Each finger is a capsule collision shape (radius `r`, its segment from the joint to `ℓ`
//! along the finger, `ℓ` = `finger_length`), a solid cylinder's inertia about its CM at
//! `ℓ/2`, and a named point `<name>_tip<i>` at its tip; the palm carries the point
//! `<name>_center` at `(0, 0, ℓ/2)`, the middle of the grasp. The finger joints are actuated
//! (`max_force`: the motors' effort limit, N or N·m); their position limits are
//! `0 ≤ q ≤ q_closed` (the fingers meet: `w/2 − r` prismatic, `asin((R − r)/ℓ)` revolute, at most
//! π/2). A gripper is recognized in a model ([`detect_grippers`]) by these names.

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, ModelField, ModelItem};
use crate::model::appendage::Parts;
use crate::model::builder::LinkSpec;
use crate::model::geometry::{GeometryRole, GeometrySpec, Shape};
use crate::model::joint::{JointDynamics, JointLimits, JointType};
use crate::model::system::Model;
use crate::model::validate::positive;

/// Everything [`gripper_parts`] needs (module docs). TOML `[[gripper]]` reads exactly these fields.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GripperSpec {
    /// The palm link's name; the fingers are `<name>_finger<i>`.
    pub name: String,
    /// The body carrying the palm (the base when `None`).
    #[serde(default)]
    pub parent: Option<String>,
    /// The palm's mount in the parent frame, from the parent's CM, m.
    #[serde(default)]
    pub position: [f64; 3],
    /// The palm frame's rotation in the parent frame, `[x, y, z, w]` (the fingers along its `+z`).
    #[serde(default = "identity")]
    pub rotation: [f64; 4],
    /// 2 (parallel, prismatic) or 3 (revolute, 120° apart).
    #[serde(default = "two")]
    pub fingers: usize,
    /// `ℓ`, m (> 0).
    pub finger_length: f64,
    /// `r`, m (> 0).
    pub finger_radius: f64,
    /// `w`, the distance between the finger axes when open (2 fingers), or the diameter of the
    /// circle of the hinges (3 fingers), m (> 2r).
    pub opening: f64,
    /// Each finger's mass, kg (> 0; default 0.1).
    #[serde(default = "finger_mass")]
    pub finger_mass: f64,
    /// The palm's mass, kg (> 0; default 0.5).
    #[serde(default = "palm_mass")]
    pub palm_mass: f64,
    /// The finger motors' effort limit, N (2 fingers) or N·m (3 fingers); default none.
    #[serde(default)]
    pub max_force: Option<f64>,
}

fn identity() -> [f64; 4] {
    [0.0, 0.0, 0.0, 1.0]
}
fn two() -> usize {
    2
}
fn finger_mass() -> f64 {
    0.1
}
fn palm_mass() -> f64 {
    0.5
}

impl GripperSpec {
    /// The joint value at which the fingers meet (module docs).
    pub fn closed(&self) -> f64 {
        let (w, r, l) = (self.opening, self.finger_radius, self.finger_length);
        if self.fingers == 2 {
            0.5 * w - r
        } else {
            ((0.5 * w - r) / l).min(1.0).asin()
        }
    }
}

/// The palm and finger links of a gripper (module docs), each with its joint's dynamics, its
/// points and its capsule collision shapes; `base` is the base's name (the parent when the spec
/// names none). Every rule is checked here, with a message naming the gripper and the field.
pub fn gripper_parts(spec: &GripperSpec, base: &str, item: ModelItem) -> Result<Parts, ModelError> {
    let who = format!("gripper '{}'", spec.name);
    let bad = |field: ModelField, msg: String| Err(ModelError::new(item, field, format!("{who}: {msg}")));
    if spec.fingers != 2 && spec.fingers != 3 {
        return bad(ModelField::Name, format!("fingers must be 2 (parallel, prismatic) or 3 (revolute), got {}", spec.fingers));
    }
    for (what, v) in [("finger_length", spec.finger_length), ("finger_radius", spec.finger_radius), ("opening", spec.opening)] {
        if !positive(v) {
            return bad(ModelField::Offset, format!("{what} must be finite and > 0 m, got {v}"));
        }
    }
    if spec.opening <= 2.0 * spec.finger_radius {
        return bad(ModelField::Offset, format!("opening {} m must exceed twice the finger_radius {} m (the fingers would overlap when open)", spec.opening, spec.finger_radius));
    }
    for (what, m) in [("finger_mass", spec.finger_mass), ("palm_mass", spec.palm_mass)] {
        if !positive(m) {
            return bad(ModelField::Mass, format!("{what} must be finite and > 0 kg, got {m}"));
        }
    }
    if let Some(f) = spec.max_force {
        if f.is_nan() || f <= 0.0 {
            return bad(ModelField::Limits, format!("max_force must be > 0 (or absent: no limit), got {f}"));
        }
    }
    let q = spec.rotation;
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !(norm.is_finite() && (norm - 1.0).abs() < 1e-6) {
        return bad(ModelField::Rotation, format!("rotation must be a unit quaternion [x, y, z, w], got {q:?}"));
    }
    let (l, r, m) = (spec.finger_length, spec.finger_radius, spec.finger_mass);
    let palm = LinkSpec {
        name: spec.name.clone(),
        parent: spec.parent.clone().unwrap_or_else(|| base.to_string()),
        joint_name: Some(format!("{}_mount", spec.name)),
        kind: JointType::Fixed,
        origin_in_parent: spec.position,
        rotation_in_parent: q,
        axis: [0.0, 0.0, 1.0],
        com_from_joint: [0.0; 3],
        mass: spec.palm_mass,
        // A thin disc of the opening's diameter.
        inertia: {
            let a = spec.palm_mass * spec.opening * spec.opening / 16.0;
            [[a, 0.0, 0.0], [0.0, a, 0.0], [0.0, 0.0, 2.0 * a]]
        },
        limits: JointLimits::unlimited(),
    };
    // A solid cylinder of radius r and length ℓ about its CM, axis z.
    let (i_t, i_a) = (m * (3.0 * r * r + l * l) / 12.0, 0.5 * m * r * r);
    let limits = JointLimits { lower: 0.0, upper: spec.closed(), effort: spec.max_force.unwrap_or(f64::INFINITY), ..JointLimits::unlimited() };
    let mut parts = Parts::default();
    parts.links.push((palm, JointDynamics::default()));
    parts.points.push((format!("{}_center", spec.name), spec.name.clone(), [0.0, 0.0, 0.5 * l]));
    for i in 0..spec.fingers {
        let finger = format!("{}_finger{i}", spec.name);
        let (origin, axis, kind) = if spec.fingers == 2 {
            let side = if i == 0 { 1.0 } else { -1.0 };
            ([side * 0.5 * spec.opening, 0.0, 0.0], [-side, 0.0, 0.0], JointType::Prismatic)
        } else {
            let th = 2.0 * std::f64::consts::PI * i as f64 / 3.0;
            let rr = 0.5 * spec.opening;
            ([rr * th.cos(), rr * th.sin(), 0.0], [th.sin(), -th.cos(), 0.0], JointType::Revolute)
        };
        parts.links.push((
            LinkSpec {
                name: finger.clone(),
                parent: spec.name.clone(),
                joint_name: Some(format!("{finger}_joint")),
                kind,
                origin_in_parent: origin,
                rotation_in_parent: identity(),
                axis,
                com_from_joint: [0.0, 0.0, 0.5 * l],
                mass: m,
                inertia: [[i_t, 0.0, 0.0], [0.0, i_t, 0.0], [0.0, 0.0, i_a]],
                limits,
            },
            JointDynamics::default(),
        ));
        parts.points.push((format!("{}_tip{i}", spec.name), finger.clone(), [0.0, 0.0, 0.5 * l]));
        parts.geometries.push(GeometrySpec {
            name: Some(format!("{finger}_capsule")),
            body: finger,
            role: GeometryRole::Collision,
            shape: Shape::Capsule { radius: r, length: l },
            origin: [0.0; 3],
            rotation: identity(),
            rgba: None,
        });
    }
    Ok(parts)
}

/// One gripper found in a model by [`detect_grippers`].
#[derive(Debug, Clone, PartialEq)]
pub struct Gripper {
    /// The palm's name (the gripper's).
    pub name: String,
    /// The palm's body index.
    pub palm: usize,
    /// The finger joints' degrees of freedom, in finger order.
    pub finger_dofs: Vec<usize>,
    /// `"prismatic"` (parallel) or `"revolute"`.
    pub kind: JointType,
}

/// The grippers of a model, in link order: a link `G` on a fixed joint `G_mount` whose children
/// include the links `G_finger0`, `G_finger1` (and `G_finger2`), all prismatic or all revolute
/// on the joints `G_finger<i>_joint` (what [`gripper_parts`] makes).
pub fn detect_grippers(model: &Model) -> Vec<Gripper> {
    let links = model.links();
    let mut out = Vec::new();
    for (k, g) in links.iter().enumerate() {
        if g.joint.kind != JointType::Fixed || g.joint.name != format!("{}_mount", g.name) {
            continue;
        }
        let palm = k + 1;
        let mut dofs = Vec::new();
        let mut kind = None;
        for i in 0..3 {
            let name = format!("{}_finger{i}", g.name);
            let Some((f, fl)) = links.iter().enumerate().find(|(_, l)| l.name == name && l.parent == palm) else { break };
            if fl.joint.name != format!("{name}_joint") || !matches!(fl.joint.kind, JointType::Prismatic | JointType::Revolute) || kind.is_some_and(|k| k != fl.joint.kind) {
                break;
            }
            kind = Some(fl.joint.kind);
            let Some(d) = model.dof_of_body(f + 1) else { break };
            dofs.push(d);
        }
        if let (Some(kind), 2..=3) = (kind, dofs.len()) {
            out.push(Gripper { name: g.name.clone(), palm, finger_dofs: dofs, kind });
        }
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::algorithms::kinematics::{forward_kinematics, point_position};
    use crate::model::builder::ModelBuilder;
    use crate::model::data::Data;

    /// A gripper `hand` of `fingers` fingers (ℓ 0.12 m, r 0.01 m, opening 0.1 m) mounted at
    /// `(0, 0, 0.5)`, fingers along `+z`, as its TOML table reads.
    pub(crate) fn spec(fingers: usize) -> GripperSpec {
        toml::from_str(&format!("name = \"hand\"\nfingers = {fingers}\nfinger_length = 0.12\nfinger_radius = 0.01\nopening = 0.1\nposition = [0.0, 0.0, 0.5]"))
            .unwrap()
    }

    /// A 10 kg base (unit inertia) carrying the gripper `s`.
    pub(crate) fn model(s: &GripperSpec) -> Model {
        let mut b = ModelBuilder::new("g", "base", 10.0, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]).unwrap();
        b.add_parts(&gripper_parts(s, "base", ModelItem::Model).unwrap()).unwrap();
        b.build().unwrap()
    }

    fn tips(m: &Model, q: f64) -> Vec<nalgebra::Vector3<f64>> {
        let mut x = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        x.extend(std::iter::repeat(q).take(m.n_dof()));
        let mut d = Data::new(m);
        forward_kinematics(m, &mut d, &x).unwrap();
        m.points().iter().map(|p| point_position(&d, p.body, &p.offset)).collect()
    }

    #[test]
    fn two_fingers_close_by_twice_the_joint_value_and_three_tilt_inward() {
        let s2 = spec(2);
        let m = model(&s2);
        assert_eq!(detect_grippers(&m), vec![Gripper { name: "hand".into(), palm: 1, finger_dofs: vec![0, 1], kind: JointType::Prismatic }]);
        for q in [0.0, 0.01, 0.03] {
            let p = tips(&m, q);
            // points: center, tip0, tip1
            assert!(((p[1] - p[2]).norm() - (0.1 - 2.0 * q)).abs() < 1e-15);
            assert!((p[1].z - (0.5 + 0.12)).abs() < 1e-15 && (p[0].z - 0.56).abs() < 1e-15);
        }
        assert!((s2.closed() - 0.04).abs() < 1e-15);
        let s3 = spec(3);
        let m = model(&s3);
        assert_eq!(detect_grippers(&m)[0].finger_dofs, vec![0, 1, 2]);
        for q in [0.0, 0.2, 0.4] {
            let p = tips(&m, q);
            for tip in &p[1..] {
                let radial = (tip.x * tip.x + tip.y * tip.y).sqrt();
                assert!((radial - (0.05 - 0.12 * q.sin())).abs() < 1e-15, "{radial}");
                assert!((tip.z - (0.5 + 0.12 * q.cos())).abs() < 1e-15);
            }
        }
        assert!((s3.closed() - (0.04f64 / 0.12).asin()).abs() < 1e-15);
    }

    #[test]
    fn bad_values_are_named() {
        let err = |f: &dyn Fn(&mut GripperSpec)| {
            let mut s = spec(2);
            f(&mut s);
            gripper_parts(&s, "base", ModelItem::Model).unwrap_err().to_string()
        };
        assert!(err(&|s| s.fingers = 4).contains("fingers must be 2"));
        assert!(err(&|s| s.finger_radius = -1.0).contains("finger_radius must be finite and > 0"));
        assert!(err(&|s| s.opening = 0.015).contains("must exceed twice the finger_radius"));
        assert!(err(&|s| s.rotation = [0.0, 0.0, 0.0, 2.0]).contains("unit quaternion"));
        assert!(err(&|s| s.max_force = Some(0.0)).contains("max_force"));
        assert!(toml::from_str::<GripperSpec>("name = \"h\"\nfinger_length = 1.0\nfinger_radius = 0.1\nopening = 1.0\nfoo = 1").is_err());
    }
}
