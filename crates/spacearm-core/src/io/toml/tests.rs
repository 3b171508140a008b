//! The TOML reader and writer: documents read, errors located, round trips exact.

#[test]
fn errors_quote_lines_of_model_files_only() {
    // Pointed at any file, the reader quoted the line of its first syntax error: the
    // content of /etc/shadow or a credentials file ended up in the message (issue 38).
    for (text, want) in [
        ("root:SECRETHASH:19000:0:99999:7:::\ndaemon:*:19000\n", "not TOML"),
        ("token = \"SECRET-abc\"\ntoken = \"SECRET-abc\"\n", "not TOML"),
        ("[server]\npassword = \"SECRET-abc\"\n", "no [model] table"),
        ("\u{0}\u{1}SECRET\u{ff}", "not TOML"),
    ] {
        let e = model_from_toml_str(text, "secrets.txt").unwrap_err().to_string();
        assert!(e.starts_with("secrets.txt") && e.contains(want) && !e.contains("SECRET") && !e.contains('\n'), "{e}");
    }
    // A model file that breaks the schema still gets its line quoted, with the caret.
    let e = model_from_toml_str("[model]\nname = 5\n", "m.toml").unwrap_err().to_string();
    assert!(e.starts_with("m.toml:2:8: ") && e.contains("\n 2 | name = 5\n"), "{e}");
}

use super::write::vec_str;
use super::*;
use crate::error::SpacearmError;
use crate::model::joint::{JointLimits, JointType};
use crate::model::{GeometryRole, LinkSpec, ModelBuilder, Shape};
use crate::math::rotations::xyzw;
use crate::model::presets;
use nalgebra::{UnitQuaternion, Vector3};

const DEMO: &str = r#"
[model]
name = "demo"
end_effector = "tip"
initial_q = [0.3, 0.1]

[base]
mass = 100
inertia = { ixx = 10, iyy = 12, izz = 14, ixy = 0.5 }

[[link]]
name = "arm"
parent = "base"
com = [0.5, 0.0, 0.0]
mass = 5.0
inertia = [0.01, 0.4, 0.4]
joint = { type = "revolute", origin = [0.5, 0.0, 0.0], axis = [0.0, 0.0, 2.0], limits = { lower = -1.0, upper = 1.0 } }

[[link]]
name = "slider"
parent = "arm"
com = [0.1, 0.0, 0.0]
mass = 1.0
inertia = [[0.01, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.02]]
[link.joint]
type = "prismatic"
name = "slide"
origin = [0.5, 0.0, 0.0]
rpy = [0.0, 0.0, 1.5707963267948966]
axis = [1.0, 0.0, 0.0]

[[point]]
name = "tip"
body = "slider"
offset = [0.2, 0.0, 0.0]
"#;

fn err(text: &str) -> String {
    match model_from_toml_str(text, "test.toml") {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => {
            assert!(matches!(e, SpacearmError::Parse(_)), "{e:?}");
            e.to_string()
        }
    }
}

#[test]
fn reads_a_valid_document() {
    let m = model_from_toml_str(DEMO, "demo.toml").unwrap();
    assert_eq!(m.name(), "demo");
    assert_eq!(m.n_dof(), 2);
    assert_eq!(m.base().inertia[(0, 1)], 0.5);
    assert_eq!(m.links()[0].joint.name, "arm_joint");
    assert_eq!(m.links()[0].joint.axis.into_inner(), Vector3::z());
    assert_eq!(m.links()[0].joint.limits.upper, 1.0);
    assert_eq!(m.links()[0].joint.limits.effort, f64::INFINITY);
    assert_eq!(m.links()[1].joint.kind, JointType::Prismatic);
    assert!((m.links()[1].joint.rotation_in_parent.angle() - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    assert_eq!(m.points()[m.end_effector().unwrap()].name, "tip");
    assert_eq!(m.initial_q(), vec![0.3, 0.1]);
}

#[test]
fn round_trip_is_exact() {
    for m in [presets::planar4(), presets::spatial6(), model_from_toml_str(DEMO, "demo.toml").unwrap()] {
        let text = model_to_toml(&m);
        let back = model_from_toml_str(&text, "round.toml").unwrap();
        assert_eq!(back, m, "{text}");
        assert_eq!(model_to_toml(&back), text);
    }
}

#[test]
fn round_trip_of_awkward_values() {
    let rotation = xyzw(&UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3));
    let mut b = ModelBuilder::new("we\"ird\\ name 'é' #[x] = λ", "base", 100.0, [[10.0, 0.5, 0.0], [0.5, 12.0, 0.0], [0.0, 0.0, 14.0]]).unwrap();
    b.add_link(LinkSpec {
        name: "arm".into(),
        parent: "base".into(),
        joint_name: None,
        kind: JointType::Revolute,
        origin_in_parent: [0.5, 0.0, 0.0],
        rotation_in_parent: rotation,
        axis: [0.0, 0.6, 0.8],
        com_from_joint: [1e-300, -0.1, 1.0 / 3.0],
        mass: 5.0,
        inertia: [[0.01, 0.0, 0.0], [0.0, 0.4, 0.0], [0.0, 0.0, 0.4]],
        limits: JointLimits { velocity: 7.5, ..JointLimits::unlimited() },
    })
    .unwrap();
    let m = b.build().unwrap();
    let text = model_to_toml(&m);
    assert_eq!(model_from_toml_str(&text, "x").unwrap(), m, "{text}");
}

#[test]
fn syntax_errors_carry_line_and_column() {
    let e = err("[model]\nname = \"x\"\n\n[base]\nmass = = 3\n");
    assert!(e.starts_with("test.toml:5:"), "{e}");
    assert!(e.contains("mass = = 3"), "{e}");
    let e = err("[model\nname = 1");
    assert!(e.starts_with("test.toml:1:"), "{e}");
}

/// Each case edits DEMO (`from` → `to`, `from` present) and expects an error that starts with
/// `prefix` and contains every one of `contains`.
fn assert_demo_errors(cases: &[(&str, &str, &str, &[&str])]) {
    for (from, to, prefix, contains) in cases {
        assert!(DEMO.contains(from), "DEMO has no {from:?}");
        let e = err(&DEMO.replace(from, to));
        assert!(e.starts_with(prefix) && contains.iter().all(|c| e.contains(c)), "{from:?} -> {to:?}: {e}");
    }
}

#[test]
fn unknown_keys_are_named() {
    assert_demo_errors(&[
        ("mass = 5.0", "mas = 5.0", "test.toml:15:", &["unknown field `mas`"]),
        ("[[point]]", "[[points]]", "", &["unknown field `points`"]),
    ]);
}

#[test]
fn wrong_types_and_missing_fields() {
    assert_demo_errors(&[
        ("mass = 5.0", "mass = \"five\"", "test.toml:15:", &["invalid type"]),
        ("com = [0.5, 0.0, 0.0]\n", "", "test.toml:", &["missing field `com`"]),
        ("offset = [0.2, 0.0, 0.0]", "offset = [0.2, 0.0]", "", &["test.toml:35:", "length 3"]),
        ("type = \"prismatic\"", "type = \"hinge\"", "", &["hinge", "revolute"]),
        ("inertia = [0.01, 0.4, 0.4]", "inertia = [0.01, 0.4]", "", &["link 'arm': inertia must be [ixx, iyy, izz]"]),
    ]);
}

#[test]
fn semantic_errors_name_the_link_and_line() {
    assert_demo_errors(&[
        ("mass = 5.0", "mass = -5.0", "test.toml:15:8:", &["link 'arm'", ">= 0"]),
        ("inertia = [0.01, 0.4, 0.4]", "inertia = [0.01, 0.4, 1.4]", "", &["link 'arm'", "triangle"]),
        ("axis = [0.0, 0.0, 2.0]", "axis = [0.0, 0.0, 0.0]", "", &["link 'arm'", "non-zero"]),
        ("rpy = [0.0, 0.0, 1.5707963267948966]", "rotation = [0.0, 0.0, 0.0, 2.0]", "test.toml:29:", &["link 'slider'", "unit quaternion"]),
        ("parent = \"arm\"", "parent = \"nope\"", "", &["parent 'nope'", "\"base\", \"arm\""]),
        ("parent = \"base\"", "parent = \"slider\"", "", &["cycle 'arm' -> 'slider' -> 'arm'"]),
        ("parent = \"base\"", "parent = \"arm\"", "", &["its own parent"]),
        ("initial_q = [0.3, 0.1]", "initial_q = [0.3]", "test.toml:5:", &["N = 2"]),
        ("body = \"slider\"", "body = \"hand\"", "", &["point 'tip'", "'hand'"]),
        ("end_effector = \"tip\"", "end_effector = \"hand\"", "", &["end effector 'hand'"]),
        ("limits = { lower = -1.0, upper = 1.0 }", "limits = { lower = 1.0, upper = -1.0 }", "", &["lower <= upper", "arm_joint"]),
        ("name = \"slider\"", "name = \"arm\"", "", &["'arm' is used twice"]),
        ("[base]\nmass = 100", "[base]\nmass = 0", "", &["base 'base'", "> 0"]),
    ]);
}

#[test]
fn forward_reference_is_explained() {
    // Link "b" (line 7, its parent on line 9) names "a", which only the next table (line 14)
    // defines.
    let link = |name: &str, parent: &str| {
        format!(
            "[[link]]\nname = \"{name}\"\nparent = \"{parent}\"\ncom = [0, 0, 0]\nmass = 1\ninertia = [1, 1, 1]\n\
             joint = {{ type = \"revolute\", origin = [0, 0, 0], axis = [0, 0, 1] }}\n"
        )
    };
    let text = format!("\n[model]\nname = \"f\"\n[base]\nmass = 1\ninertia = [1, 1, 1]\n{}{}", link("b", "a"), link("a", "base"));
    let e = err(&text);
    assert!(e.starts_with("test.toml:9:") && e.contains("defined later in the file (line 14)"), "{e}");
}

#[test]
fn dh_section_builds_the_planar4_preset() {
    let q0 = presets::planar4().initial_q().to_vec();
    let text = format!(
        r#"
[model]
name = "planar4"
initial_q = {}
[base]
mass = 100.0
inertia = [4.1667, 4.1667, 4.1667]
[dh]
convention = "classic"
joint1_origin = [0.25, 0.0, 0.0]
{}"#,
        vec_str(&q0),
        (0..4)
            .map(|_| "[[dh.link]]\nd = 0.0\ntheta = 0.0\na = 1.0\nalpha = 0.0\ncom = [-0.5, 0.0, 0.0]\nmass = 10.0\n\
                      inertia = [0.004166666666666667, 0.8354166666666667, 0.8354166666666667]\n")
            .collect::<String>()
    );
    let m = model_from_toml_str(&text, "dh.toml").unwrap();
    let p = presets::planar4();
    assert_eq!(m.n_dof(), 4);
    assert_eq!(m.points()[m.end_effector().unwrap()].name, "end_effector");
    for (a, b) in m.links().iter().zip(p.links()) {
        assert!((a.joint.origin_in_parent - b.joint.origin_in_parent).norm() < 1e-15);
        assert!((a.com_from_joint - b.com_from_joint).norm() < 1e-15);
        assert!((a.mass.inertia - b.mass.inertia).abs().max() < 1e-15);
    }
    let e = err(&text.replace("a = 1.0\n", "a = 1.0\ncom_to_next = [1.0, 0.0, 0.0]\n"));
    assert!(e.contains("DH link 1") && e.contains("`com_to_next` does not belong to a classic"), "{e}");
    let e = err(&text.replacen("alpha = 0.0\n", "", 1));
    assert!(e.contains("DH link 1: missing `alpha`"), "{e}");
    let e = err(&text.replacen("mass = 10.0", "mass = -1.0", 1));
    assert!(e.contains("link 'link1'") && e.starts_with("test.toml:11:1:"), "{e}");
}

#[test]
fn mutated_documents_never_panic() {
    use rand::{Rng, SeedableRng};
    let mut r = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let base = model_to_toml(&presets::spatial6());
    let pieces = ["", "0", "-1", "1e400", "nan", "\"", "[", "]", "{", "}", "=", "\n", "[[link]]", "inf", "1e308", ",", "\u{e9}", "#"];
    for _ in 0..3000 {
        let mut t: Vec<char> = base.chars().collect();
        for _ in 0..r.random_range(1..4) {
            let pos = r.random_range(0..=t.len());
            match r.random_range(0..3) {
                0 if pos < t.len() => {
                    t.remove(pos);
                }
                1 => {
                    let p = pieces[r.random_range(0..pieces.len())];
                    for (k, c) in p.chars().enumerate() {
                        t.insert(pos + k, c);
                    }
                }
                _ => {
                    let end = (pos + r.random_range(0..40)).min(t.len());
                    t.drain(pos..end);
                }
            }
        }
        let text: String = t.into_iter().collect();
        if let Err(e) = model_from_toml_str(&text, "fuzz") {
            assert!(matches!(e, SpacearmError::Parse(_)));
            assert!(e.to_string().starts_with("fuzz"));
        }
    }
}

#[test]
fn huge_inertias_are_rejected_not_panicking() {
    let e = err(&DEMO.replace("inertia = [0.01, 0.4, 0.4]", "inertia = [[1e308, 1e308, 1e308], [1e308, 1e308, 1e308], [1e308, 1e308, 1e308]]"));
    assert!(e.contains("link 'arm'"), "{e}");
}

#[test]
fn geometry_tables_read_write_and_round_trip() {
    let text = format!(
        "{DEMO}\n[[geometry]]\nbody = \"base\"\nshape = \"box\"\nsize = [1.0, 0.8, 0.6]\nrgba = [0.9, 0.7, 0.3, 1.0]\n\
         [[geometry]]\nname = \"arm_rod\"\nbody = \"arm\"\nshape = \"capsule\"\nradius = 0.05\nlength = 0.9\nrpy = [0.0, 1.5707963267948966, 0.0]\n\
         [[geometry]]\nbody = \"arm\"\nrole = \"collision\"\nshape = \"cylinder\"\nradius = 0.06\nlength = 1.0\norigin = [0.0, 0.0, 0.1]\n\
         [[geometry]]\nbody = \"slider\"\nshape = \"sphere\"\nradius = 0.1\n\
         [[geometry]]\nbody = \"slider\"\nshape = \"mesh\"\nfile = \"meshes/hand.stl\"\nscale = [0.001, 0.001, 0.001]\n"
    );
    let m = model_from_toml_str(&text, "g.toml").unwrap();
    let g = m.geometries();
    assert_eq!(g.len(), 5);
    assert_eq!((g[0].name.as_str(), g[0].body, g[0].role), ("base_visual0", 0, GeometryRole::Visual));
    assert_eq!(g[0].shape, Shape::Box { size: [1.0, 0.8, 0.6] });
    assert_eq!(g[0].rgba, [0.9, 0.7, 0.3, 1.0]);
    assert_eq!(g[1].name, "arm_rod");
    // rpy (0, π/2, 0) is Ry(π/2): it turns the capsule's z onto the body's x.
    let z = g[1].rotation * Vector3::z();
    assert!((z - Vector3::x()).norm() < 1e-15, "{z:?}");
    assert_eq!((g[2].name.as_str(), g[2].role), ("arm_collision0", GeometryRole::Collision));
    assert_eq!(g[2].origin, Vector3::new(0.0, 0.0, 0.1));
    assert_eq!(g[3].shape, Shape::Sphere { radius: 0.1 });
    assert_eq!(g[4].shape, Shape::Mesh { file: "meshes/hand.stl".into(), scale: [0.001; 3] });
    assert_eq!(g[4].rgba, crate::model::geometry::DEFAULT_RGBA);
    let again = model_from_toml_str(&model_to_toml(&m), "again.toml").unwrap();
    assert_eq!(again, m);
    // Errors point at the offending key.
    let bad = |geometry: &str| err(&format!("{DEMO}\n[[geometry]]\n{geometry}"));
    let e = bad("body = \"ghost\"\nshape = \"sphere\"\nradius = 1.0\n");
    assert!(e.contains("'ghost': not a body") && e.contains("body = \"ghost\""), "{e}");
    let e = bad("body = \"arm\"\nshape = \"sphere\"\nradius = -1.0\n");
    assert!(e.contains("sphere radius must be a finite length > 0") && e.contains("radius = -1.0"), "{e}");
    let e = bad("body = \"arm\"\nshape = \"box\"\nradius = 1.0\n");
    assert!(e.contains("a box takes size, not `radius`"), "{e}");
    let e = bad("body = \"arm\"\nshape = \"cylinder\"\nradius = 1.0\n");
    assert!(e.contains("a cylinder needs `length`"), "{e}");
    let e = bad("body = \"arm\"\nshape = \"cone\"\nradius = 1.0\n");
    assert!(e.contains("shape must be \"box\""), "{e}");
    let e = bad("body = \"arm\"\nrole = \"both\"\nshape = \"sphere\"\nradius = 1.0\n");
    assert!(e.contains("role must be 'visual' or 'collision', got 'both'"), "{e}");
    let e = bad("body = \"arm\"\nshape = \"sphere\"\nradius = 1.0\nrgba = [1.0, 1.0, 1.0, 2.0]\n");
    assert!(e.contains("rgba must be 4 numbers in [0, 1]") && e.contains("rgba = [1.0"), "{e}");
    let e = bad("name = \"g\"\nbody = \"arm\"\nshape = \"sphere\"\nradius = 1.0\n[[geometry]]\nname = \"g\"\nbody = \"arm\"\nshape = \"sphere\"\nradius = 1.0\n");
    assert!(e.contains("geometry name 'g' is used twice"), "{e}");
}

#[test]
fn cmg_tables_make_a_gimbal_and_a_rotor_that_survive_a_round_trip() {
    let text = r#"
[model]
name = "cmg-hub"
[base]
mass = 100
inertia = { ixx = 10, iyy = 12, izz = 14 }
[[cmg]]
name = "c1"
position = [0.2, 0, 0]
gimbal_axis = [0, 0, 1]
spin_axis = [1, 0, 0]
rotor_inertia = 0.05
gimbal_inertia = [0.01, 0.01, 0.01]
max_gimbal_rate = 1.5
[[cmg]]
name = "c2"
gimbal_axis = [1, 0, 0]
spin_axis = [0, 1, 0]
rotor_inertia = 0.05
variable_speed = true
max_wheel_speed = 600
"#;
    let m = model_from_toml_str(text, "cmg.toml").unwrap();
    assert_eq!(m.n_dof(), 4);
    let cmgs = crate::model::cmg::detect_cmgs(&m);
    assert_eq!(cmgs.iter().map(|c| (c.name.as_str(), c.gimbal_dof, c.rotor_dof, c.variable_speed)).collect::<Vec<_>>(), vec![("c1", 0, 1, false), ("c2", 2, 3, true)]);
    assert_eq!((cmgs[0].max_gimbal_rate, cmgs[1].max_wheel_speed), (1.5, 600.0));
    let again = model_from_toml_str(&model_to_toml(&m), "again.toml").unwrap();
    assert_eq!(crate::model::cmg::detect_cmgs(&again), cmgs);
    // A bad table is refused with the CMG's name and the line of its table.
    let e = model_from_toml_str(&text.replace("spin_axis = [1, 0, 0]", "spin_axis = [1, 0, 1]"), "cmg.toml").unwrap_err().to_string();
    assert!(e.starts_with("cmg.toml:7:") && e.contains("cmg 'c1'") && e.contains("perpendicular"), "{e}");
    let e = model_from_toml_str(&text.replace("max_gimbal_rate", "max_gimbal_speed"), "cmg.toml").unwrap_err().to_string();
    assert!(e.contains("max_gimbal_speed"), "{e}");
}
