//! Every rule of `spacearm_core::model::validate`, one test each: a model description that
//! breaks the rule is refused with a `ModelError` naming the item and field at fault and a
//! message naming the offending body, joint or point (and, converted, with
//! `SpacearmError::InvalidModel` carrying that message), while the nearest valid description
//! is accepted. The rules are reached through `ModelBuilder` (the one door every model goes
//! through); the whole-model rules the builder guarantees by construction (links parents
//! first, point bodies and the end effector by index) through `check_structure` directly.
//! The mass-property rules (mass range, inertia symmetry, definiteness, triangle inequality)
//! live in `model::body` and are tested there.

use spacearm_core::error::{ModelError, ModelField, ModelItem};
use spacearm_core::model::body::MassProperties;
use spacearm_core::model::validate::{MAX_LENGTH, MIN_AXIS_COMPONENT};
use spacearm_core::model::structure;
use spacearm_core::model::{Link, Point};
use spacearm_core::{JointLimits, JointType, LinkSpec, Model, ModelBuilder, SpacearmError};

const BASE_INERTIA: [[f64; 3]; 3] = [[10.0, 0.0, 0.0], [0.0, 12.0, 0.0], [0.0, 0.0, 14.0]];

fn builder() -> ModelBuilder {
    ModelBuilder::new("m", "bus", 100.0, BASE_INERTIA).unwrap()
}

/// A valid revolute link `name` on `parent`.
fn link(name: &str, parent: &str) -> LinkSpec {
    LinkSpec::new(name, parent, JointType::Revolute, [0.5, 0.1, 0.0], [0.0, 0.0, 1.0], [0.4, 0.0, 0.0], 5.0, [0.01, 0.3, 0.3])
}

fn with(name: &str, f: impl FnOnce(&mut LinkSpec)) -> LinkSpec {
    let mut s = link(name, "bus");
    f(&mut s);
    s
}

/// `e` is about `item`'s `field`, its message contains every one of `words`, and it becomes
/// `SpacearmError::InvalidModel` with the same message.
#[track_caller]
fn refused(e: ModelError, item: ModelItem, field: ModelField, words: &[&str]) {
    assert_eq!((e.item, e.field), (item, field), "{e}");
    for w in words {
        assert!(e.message.contains(w), "message {:?} does not contain {w:?}", e.message);
    }
    assert_eq!(e.to_string(), format!("invalid model: {}", e.message));
    let message = e.message.clone();
    match SpacearmError::from(e) {
        SpacearmError::InvalidModel(m) => assert_eq!(m, message),
        other => panic!("not InvalidModel: {other:?}"),
    }
}

/// Add one link to a fresh builder (a first link on the base, item `Link(0)`).
fn add_one(spec: LinkSpec) -> Result<Model, ModelError> {
    let mut b = builder();
    b.add_link(spec)?;
    b.build()
}

#[test]
fn names_must_not_be_empty() {
    let e = ModelBuilder::new("m", "", 100.0, BASE_INERTIA).unwrap_err();
    refused(e, ModelItem::Base, ModelField::Name, &["base name must not be empty"]);
    assert!(ModelBuilder::new("m", "b", 100.0, BASE_INERTIA).is_ok());

    refused(add_one(link("", "bus")).unwrap_err(), ModelItem::Link(0), ModelField::Name, &["link name must not be empty"]);
    assert!(add_one(link("a", "bus")).is_ok());

    let e = add_one(with("arm", |s| s.joint_name = Some(String::new()))).unwrap_err();
    refused(e, ModelItem::Link(0), ModelField::JointName, &["link 'arm': joint name must not be empty"]);
    let m = add_one(with("arm", |s| s.joint_name = Some("j".into()))).unwrap();
    assert_eq!(m.links()[0].joint.name, "j");

    let mut b = builder();
    b.add_link(link("arm", "bus")).unwrap();
    b.add_point("p", "arm", [0.0; 3]).unwrap();
    refused(b.add_point("", "arm", [0.0; 3]).unwrap_err(), ModelItem::Point(1), ModelField::Name, &["point name must not be empty"]);
    b.add_point("q", "arm", [0.0; 3]).unwrap();
    assert_eq!(b.build().unwrap().points().len(), 2);
}

#[test]
fn names_are_short_printable_labels() {
    use spacearm_core::model::validate::MAX_NAME_CHARS;
    // At the bound: accepted; one character more: refused, the message echoing 40 of them.
    let at_bound = "n".repeat(MAX_NAME_CHARS);
    assert!(add_one(link(&at_bound, "bus")).is_ok());
    let long = "x".repeat(100_000);
    let e = add_one(link(&long, "bus")).unwrap_err();
    let msg = e.to_string();
    assert!(msg.len() < 400, "the message echoes the whole name: {} bytes", msg.len());
    refused(e, ModelItem::Link(0), ModelField::Name, &["link name must be at most 256 characters, got 100000"]);
    // Control characters (NUL, newline, escape) in any name.
    for bad in ["a\0b", "a\nb", "\u{1b}[31m"] {
        refused(add_one(link(bad, "bus")).unwrap_err(), ModelItem::Link(0), ModelField::Name, &["link name must not contain control characters"]);
    }
    let e = ModelBuilder::new("m\0", "b", 100.0, BASE_INERTIA).unwrap_err();
    refused(e, ModelItem::Model, ModelField::Name, &["model name must not contain control characters, got U+0000"]);
    let e = ModelBuilder::new("", "b", 100.0, BASE_INERTIA).unwrap_err();
    refused(e, ModelItem::Model, ModelField::Name, &["model name must not be empty"]);
    // Unicode letters are names like any other.
    assert!(add_one(link("Gelenk_ä_λ", "bus")).is_ok());
}

#[test]
fn a_base_resists_rotation_about_every_axis() {
    use spacearm_core::model::body::MIN_RADIUS_OF_GYRATION;
    let diag = |a: f64, b: f64, c: f64| [[a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]];
    // A 50 kg base: the floor is m k² = 50 · (1e-6 m)² = 5e-11 kg·m² (independent arithmetic).
    let floor = 50.0 * MIN_RADIUS_OF_GYRATION.powi(2);
    assert!((floor - 5e-11).abs() < 1e-24);
    assert!(ModelBuilder::new("m", "b", 50.0, diag(6e-11, 6e-11, 6e-11)).is_ok());
    let e = ModelBuilder::new("m", "b", 50.0, diag(4e-11, 4e-11, 4e-11)).unwrap_err();
    refused(e, ModelItem::Base, ModelField::Inertia, &["smallest principal moment 4.000000e-11", "radius of", "gyration"]);
    // issue 26: a 50 kg target of 1e-20 kg·m² was accepted (its rigid lock left a twist of 1.7e4)
    let e = ModelBuilder::new("target", "t", 50.0, diag(1e-20, 1e-20, 1e-20)).unwrap_err();
    refused(e, ModelItem::Base, ModelField::Inertia, &["below m·k²"]);
    // a thin rod (1 cm radius, 50 kg) about its axis is a real body
    assert!(ModelBuilder::new("m", "b", 50.0, diag(0.5 * 50.0 * 1e-4, 4.0, 4.0)).is_ok());
    // a link may still be a point mass (zero inertia): the rule is the base's
    assert!(add_one(with("tip", |s| s.inertia = diag(0.0, 0.0, 0.0))).is_ok());
}

#[test]
fn a_link_name_must_be_new_among_bodies_points_and_joints() {
    // A body name used twice: the base's, or a link's.
    let mut b = builder();
    let e = b.add_link(link("bus", "bus")).unwrap_err();
    refused(e, ModelItem::Link(0), ModelField::Name, &["body name 'bus' is used twice"]);
    b.add_link(link("arm", "bus")).unwrap();
    let e = b.add_link(link("arm", "arm")).unwrap_err();
    refused(e, ModelItem::Link(1), ModelField::Name, &["body name 'arm' is used twice"]);
    // A body name already a point's.
    b.add_point("tool", "arm", [0.0; 3]).unwrap();
    let e = b.add_link(link("tool", "arm")).unwrap_err();
    refused(e, ModelItem::Link(1), ModelField::Name, &["body name 'tool' is already used by a point"]);
    // A joint name used twice, explicit or by default (`<link>_joint`).
    let mut s = link("forearm", "arm");
    s.joint_name = Some("arm_joint".into());
    let e = b.add_link(s).unwrap_err();
    refused(e, ModelItem::Link(1), ModelField::JointName, &["link 'forearm': joint name 'arm_joint' is used twice"]);
    let mut s = link("hand", "arm");
    s.joint_name = Some("forearm_joint".into());
    b.add_link(s).unwrap();
    let e = b.add_link(link("forearm", "hand")).unwrap_err();
    refused(e, ModelItem::Link(2), ModelField::JointName, &["link 'forearm': joint name 'forearm_joint' is used twice"]);
    // The nearest valid: a fresh name (a joint may share a body's name: they are kinds apart).
    let mut s = link("forearm", "hand");
    s.joint_name = Some("arm".into());
    b.add_link(s).unwrap();
    let m = b.build().unwrap();
    assert_eq!(m.links().iter().map(|l| l.name.as_str()).collect::<Vec<_>>(), ["arm", "hand", "forearm"]);
}

#[test]
fn a_point_name_must_be_new_among_bodies_and_points() {
    let mut b = builder();
    b.add_link(link("arm", "bus")).unwrap();
    for taken in ["bus", "arm"] {
        let e = b.add_point(taken, "arm", [0.0; 3]).unwrap_err();
        refused(e, ModelItem::Point(0), ModelField::Name, &[&format!("point name '{taken}' is already used by a body or point")]);
    }
    b.add_point("tip", "arm", [0.0; 3]).unwrap();
    let e = b.add_point("tip", "bus", [0.0; 3]).unwrap_err();
    refused(e, ModelItem::Point(1), ModelField::Name, &["point name 'tip' is already used by a body or point"]);
    // A point may share a joint's name.
    b.add_point("arm_joint", "bus", [0.0; 3]).unwrap();
    assert_eq!(b.build().unwrap().points().len(), 2);
}

#[test]
fn positions_must_be_finite_and_within_the_length_limit() {
    type Setter = fn(&mut LinkSpec, [f64; 3]);
    let fields: [(&str, ModelField, Setter); 2] = [
        ("joint origin", ModelField::Origin, |s, v| s.origin_in_parent = v),
        ("com", ModelField::Com, |s, v| s.com_from_joint = v),
    ];
    for (what, field, set) in fields {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let e = add_one(with("arm", |s| set(s, [0.0, bad, 0.0]))).unwrap_err();
            refused(e, ModelItem::Link(0), field, &["link 'arm'", &format!("{what} must be finite")]);
        }
        for bad in [MAX_LENGTH * (1.0 + 1e-15), -2.0 * MAX_LENGTH, 1e300] {
            let e = add_one(with("arm", |s| set(s, [0.1, 0.0, bad]))).unwrap_err();
            refused(e, ModelItem::Link(0), field, &["link 'arm'", what, "exceeds", "check the units"]);
        }
        // At the limit itself: accepted.
        for ok in [MAX_LENGTH, -MAX_LENGTH] {
            assert!(add_one(with("arm", |s| set(s, [ok, 0.0, 0.3]))).is_ok(), "{what} = {ok}");
        }
    }
    let mut b = builder();
    b.add_link(link("arm", "bus")).unwrap();
    let e = b.add_point("tip", "arm", [f64::NAN, 0.0, 0.0]).unwrap_err();
    refused(e, ModelItem::Point(0), ModelField::Offset, &["point 'tip': offset must be finite"]);
    let e = b.add_point("tip", "arm", [0.0, 0.0, -1.5 * MAX_LENGTH]).unwrap_err();
    refused(e, ModelItem::Point(0), ModelField::Offset, &["point 'tip': offset component", "exceeds"]);
    b.add_point("tip", "arm", [0.0, MAX_LENGTH, 0.0]).unwrap();
    assert_eq!(b.build().unwrap().points()[0].offset.y, MAX_LENGTH);
}

#[test]
fn a_moving_joint_axis_must_be_finite_and_non_zero() {
    for kind in [JointType::Revolute, JointType::Prismatic] {
        let e = add_one(with("arm", |s| {
            s.kind = kind;
            s.axis = [0.0, f64::NAN, 1.0]
        }))
        .unwrap_err();
        refused(e, ModelItem::Link(0), ModelField::Axis, &["link 'arm': joint axis must be finite"]);
        // Zero, or every component at most the floor (even with a norm above it).
        let tiny = MIN_AXIS_COMPONENT;
        for bad in [[0.0; 3], [tiny, -tiny, tiny], [8e-10, 8e-10, 8e-10]] {
            let e = add_one(with("arm", |s| {
                s.kind = kind;
                s.axis = bad
            }))
            .unwrap_err();
            refused(e, ModelItem::Link(0), ModelField::Axis, &["link 'arm': joint axis must be a non-zero vector"]);
        }
        // Just above the floor: accepted and normalized.
        let m = add_one(with("arm", |s| {
            s.kind = kind;
            s.axis = [0.0, 2.0 * tiny, -2.0 * tiny]
        }))
        .unwrap();
        let a = m.links()[0].joint.axis.into_inner();
        assert!((a.norm() - 1.0).abs() < 1e-15 && (a.y - 0.5f64.sqrt()).abs() < 1e-15, "{a}");
    }
    // A fixed joint's axis is ignored: zero is accepted (it becomes z); non-finite is not.
    let m = add_one(with("arm", |s| {
        s.kind = JointType::Fixed;
        s.axis = [0.0; 3]
    }))
    .unwrap();
    assert_eq!(m.links()[0].joint.axis.into_inner(), nalgebra::Vector3::z());
    assert_eq!(m.n_dof(), 0);
    let e = add_one(with("arm", |s| {
        s.kind = JointType::Fixed;
        s.axis = [f64::INFINITY, 0.0, 0.0]
    }))
    .unwrap_err();
    refused(e, ModelItem::Link(0), ModelField::Axis, &["joint axis must be finite"]);
    // Unit axes are kept bit for bit, others normalized; huge ones do not overflow.
    let m = add_one(with("arm", |s| s.axis = [0.0, 0.6, 0.8])).unwrap();
    assert_eq!(m.links()[0].joint.axis.into_inner(), nalgebra::Vector3::new(0.0, 0.6, 0.8));
    let m = add_one(with("arm", |s| s.axis = [1e300, 0.0, 1e300])).unwrap();
    let a = m.links()[0].joint.axis.into_inner();
    assert!((a.x - 0.5f64.sqrt()).abs() < 1e-15 && (a.z - 0.5f64.sqrt()).abs() < 1e-15, "{a}");
}

#[test]
fn a_joint_rotation_must_be_a_unit_quaternion() {
    for bad in [[0.0, 0.0, 0.0, 1.1], [0.0, 0.0, 0.0, 0.0], [0.5, 0.5, 0.5, 0.5 + 3e-6]] {
        let e = add_one(with("arm", |s| s.rotation_in_parent = bad)).unwrap_err();
        refused(e, ModelItem::Link(0), ModelField::Rotation, &["link 'arm': joint rotation must be a unit quaternion"]);
    }
    let e = add_one(with("arm", |s| s.rotation_in_parent = [0.0, f64::NAN, 0.0, 1.0])).unwrap_err();
    refused(e, ModelItem::Link(0), ModelField::Rotation, &["link 'arm': joint rotation must be finite"]);
    // Within the tolerance: accepted and normalized exactly.
    let m = add_one(with("arm", |s| s.rotation_in_parent = [0.5, 0.5, 0.5, 0.5 + 5e-7])).unwrap();
    let q = m.links()[0].joint.rotation_in_parent;
    assert!((q.coords.norm() - 1.0).abs() < 1e-15);
    // A unit quaternion is kept bit for bit.
    let (s, c) = 0.7f64.sin_cos();
    let m = add_one(with("arm", |sp| sp.rotation_in_parent = [s, 0.0, 0.0, c])).unwrap();
    assert_eq!(m.links()[0].joint.rotation_in_parent.coords, nalgebra::Vector4::new(s, 0.0, 0.0, c));
}

#[test]
fn joint_limits_must_be_ordered_and_non_negative() {
    let free = JointLimits::unlimited();
    let position_cases = [
        JointLimits { lower: 1.0, upper: -1.0, ..free },
        JointLimits { lower: f64::NAN, ..free },
        JointLimits { upper: f64::NAN, ..free },
    ];
    for limits in position_cases {
        let e = add_one(with("arm", |s| s.limits = limits)).unwrap_err();
        refused(e, ModelItem::Link(0), ModelField::Limits, &["joint 'arm_joint' of link 'arm'", "position limits must satisfy lower <= upper"]);
    }
    let rate_cases = [
        JointLimits { velocity: -1.0, ..free },
        JointLimits { effort: -0.5, ..free },
        JointLimits { velocity: f64::NAN, ..free },
        JointLimits { effort: f64::NAN, ..free },
    ];
    for limits in rate_cases {
        let e = add_one(with("arm", |s| s.limits = limits)).unwrap_err();
        refused(e, ModelItem::Link(0), ModelField::Limits, &["joint 'arm_joint' of link 'arm'", "velocity and effort limits must be >= 0"]);
    }
    // The nearest valid: equal position limits, zero velocity and effort.
    let edge = JointLimits { lower: 0.3, upper: 0.3, velocity: 0.0, effort: 0.0 };
    let m = add_one(with("arm", |s| s.limits = edge)).unwrap();
    assert_eq!(m.links()[0].joint.limits, edge);
}

/// The parts of a valid model with a branch, a fixed link and two points, for direct calls
/// of `check_structure`.
fn parts() -> (MassProperties, Vec<Link>, Vec<Point>, Vec<f64>) {
    let mut b = builder();
    b.add_link(link("a", "bus")).unwrap();
    b.add_link(link("b", "a")).unwrap();
    b.add_link(with("c", |s| s.kind = JointType::Fixed)).unwrap();
    b.add_point("tip", "b", [0.1, 0.0, 0.0]).unwrap();
    b.add_point("dock", "c", [0.0; 3]).unwrap();
    b.set_initial_q(vec![0.1, -0.2]);
    let m = b.build().unwrap();
    (m.mass_properties(0).clone(), m.links().to_vec(), m.points().to_vec(), m.initial_q().to_vec())
}

#[test]
fn links_must_come_after_their_parents() {
    let (base, mut links, points, q) = parts();
    assert!(structure::check_structure(&base, &links, &points, Some(0), &q).is_ok());
    // Link 1 ('b') naming itself (body 2) or a later link (body 3) as its parent.
    for parent in [2, 3] {
        links[1].parent = parent;
        let e = structure::check_structure(&base, &links, &points, Some(0), &q).unwrap_err();
        refused(e, ModelItem::Link(1), ModelField::Parent, &["link 'b'", &format!("parent index {parent}"), "(1..=1)"]);
    }
    // The nearest valid: the link before it, or the base.
    for parent in [0, 1] {
        links[1].parent = parent;
        assert!(structure::check_structure(&base, &links, &points, Some(0), &q).is_ok());
    }
    // Through the builder: a parent not (yet) defined.
    let mut b = builder();
    let e = b.add_link(link("a", "later")).unwrap_err();
    refused(e, ModelItem::Link(0), ModelField::Parent, &["parent body 'later' is not defined (yet)", "bus"]);
}

#[test]
fn a_moving_joint_must_carry_mass_or_inertia() {
    // A link of `kind` on the bus with zero mass and inertia.
    let massless = |name: &str, kind: JointType| {
        with(name, |s| {
            s.kind = kind;
            s.mass = 0.0;
            s.inertia = [[0.0; 3]; 3];
        })
    };
    // A massless leaf on a moving joint.
    let mut b = builder();
    b.add_link(link("arm", "bus")).unwrap();
    b.add_link(massless("ghost", JointType::Revolute).tap_parent("arm")).unwrap();
    let e = b.build().unwrap_err();
    refused(e, ModelItem::Link(1), ModelField::Mass, &["joint 'ghost_joint' moves link 'ghost'", "zero mass and inertia"]);
    // A massless link carrying only massless fixed links is as empty.
    let mut b = builder();
    b.add_link(massless("ghost", JointType::Revolute)).unwrap();
    b.add_link(massless("plate", JointType::Fixed).tap_parent("ghost")).unwrap();
    refused(b.build().unwrap_err(), ModelItem::Link(0), ModelField::Mass, &["joint 'ghost_joint' moves link 'ghost'"]);
    // Prismatic joints too.
    let mut b = builder();
    b.add_link(massless("slider", JointType::Prismatic)).unwrap();
    refused(b.build().unwrap_err(), ModelItem::Link(0), ModelField::Mass, &["link 'slider'"]);
    // The nearest valid: something downstream has mass, or the link has inertia only, or the
    // massless link is fixed.
    let mut b = builder();
    b.add_link(massless("ghost", JointType::Revolute)).unwrap();
    b.add_link(link("hand", "ghost")).unwrap();
    assert_eq!(b.build().unwrap().n_dof(), 2);
    // ... also when what is downstream has only mass (a point mass) or only inertia (a rotor),
    // through a fixed link: each sum is carried up the tree on its own.
    for (mass, inertia) in [(2.0, 0.0), (0.0, 1e-3)] {
        let mut b = builder();
        b.add_link(massless("ghost", JointType::Revolute)).unwrap();
        b.add_link(massless("mount", JointType::Fixed).tap_parent("ghost")).unwrap();
        b.add_link(with("bob", |s| {
            s.kind = JointType::Fixed;
            s.mass = mass;
            s.inertia = [[inertia, 0.0, 0.0], [0.0, inertia, 0.0], [0.0, 0.0, inertia]];
        })
        .tap_parent("mount"))
        .unwrap();
        assert_eq!(b.build().unwrap().n_dof(), 1, "mass {mass}, inertia {inertia}");
    }
    let mut b = builder();
    b.add_link(with("wheel", |s| {
        s.mass = 0.0;
        s.inertia = [[1e-3, 0.0, 0.0], [0.0, 1e-3, 0.0], [0.0, 0.0, 1e-3]];
    }))
    .unwrap();
    assert_eq!(b.build().unwrap().n_dof(), 1);
    let mut b = builder();
    b.add_link(massless("mount", JointType::Fixed)).unwrap();
    assert_eq!(b.build().unwrap().n_dof(), 0);
}

trait TapParent {
    fn tap_parent(self, parent: &str) -> Self;
}

impl TapParent for LinkSpec {
    fn tap_parent(mut self, parent: &str) -> Self {
        self.parent = parent.into();
        self
    }
}

#[test]
fn points_must_name_existing_bodies() {
    let (base, links, mut points, q) = parts();
    points[1].body = links.len() + 1;
    let e = structure::check_structure(&base, &links, &points, Some(0), &q).unwrap_err();
    refused(e, ModelItem::Point(1), ModelField::Body, &["point 'dock'", "body index 4 does not exist", "0..=3"]);
    points[1].body = links.len();
    assert!(structure::check_structure(&base, &links, &points, Some(0), &q).is_ok());
    // Through the builder: a body name not defined.
    let mut b = builder();
    let e = b.add_point("tip", "arm", [0.0; 3]).unwrap_err();
    refused(e, ModelItem::Point(0), ModelField::Body, &["point 'tip': body 'arm' is not a body of the model", "bus"]);
    b.add_point("tip", "bus", [0.0; 3]).unwrap();
}

#[test]
fn the_end_effector_must_name_a_point() {
    let (base, links, points, q) = parts();
    let e = structure::check_structure(&base, &links, &points, Some(2), &q).unwrap_err();
    refused(e, ModelItem::Model, ModelField::EndEffector, &["end effector index 2 does not name a point"]);
    assert!(structure::check_structure(&base, &links, &points, Some(1), &q).is_ok());
    assert!(structure::check_structure(&base, &links, &points, None, &q).is_ok());
    // Through the builder: by name.
    let mut b = builder();
    b.add_link(link("arm", "bus")).unwrap();
    b.add_point("tip", "arm", [0.0; 3]).unwrap();
    b.set_end_effector("arm");
    refused(b.build().unwrap_err(), ModelItem::Model, ModelField::EndEffector, &["end effector 'arm' is not a defined point", "tip"]);
    b.set_end_effector("tip");
    assert_eq!(b.build().unwrap().end_effector(), Some(0));
}

#[test]
fn initial_q_must_have_one_finite_bounded_entry_per_moving_joint() {
    let (base, links, points, _) = parts();
    let check = |q: &[f64]| structure::check_structure(&base, &links, &points, Some(0), q);
    for q in [vec![], vec![0.0], vec![0.0; 3]] {
        refused(check(&q).unwrap_err(), ModelItem::Model, ModelField::InitialQ, &["initial_q must have N = 2 entries", &format!("got {}", q.len())]);
    }
    for bad in [f64::NAN, f64::INFINITY] {
        refused(check(&[0.0, bad]).unwrap_err(), ModelItem::Model, ModelField::InitialQ, &["initial_q must be finite"]);
    }
    refused(check(&[-1.5 * MAX_LENGTH, 0.0]).unwrap_err(), ModelItem::Model, ModelField::InitialQ, &["initial_q entry", "exceeds"]);
    assert!(check(&[MAX_LENGTH, -MAX_LENGTH]).is_ok());
    // Through the builder (the fixed link has no entry).
    let mut b = builder();
    b.add_link(link("arm", "bus")).unwrap();
    b.add_link(with("mount", |s| s.kind = JointType::Fixed)).unwrap();
    b.set_initial_q(vec![0.1, 0.2]);
    refused(b.build().unwrap_err(), ModelItem::Model, ModelField::InitialQ, &["N = 1 entries", "got 2"]);
    b.set_initial_q(vec![0.25]);
    assert_eq!(b.build().unwrap().initial_q(), &[0.25]);
}

#[test]
fn joint_type_names_are_read_back_and_a_wrong_name_is_refused() {
    for kind in [JointType::Revolute, JointType::Prismatic, JointType::Fixed] {
        assert_eq!(JointType::from_name(kind.as_str()).unwrap(), kind);
    }
    for bad in ["ball", "Revolute", ""] {
        match JointType::from_name(bad) {
            Err(SpacearmError::InvalidModel(m)) => {
                assert!(m.contains("'revolute', 'prismatic' or 'fixed'") && m.contains(&format!("got '{bad}'")), "{m}")
            }
            other => panic!("{bad:?}: {other:?}"),
        }
    }
}
