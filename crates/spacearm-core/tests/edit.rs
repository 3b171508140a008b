//! Model editing (model/edit.rs, issue 32): a builder seeded from a model, attaching a body or a
//! whole model, removing a subtree. Each edit is checked against a second, independent
//! construction: the same model built link by link with the builder, and the composite mass
//! properties of the parallel-axis theorem computed here by hand.

#[allow(dead_code)]
mod common;

use nalgebra::{DMatrix, Matrix3, UnitQuaternion, Vector3};
use spacearm_core::algorithms::{crba, momentum};
use spacearm_core::model::body::TriangleInequality;
use spacearm_core::model::presets;
use spacearm_core::model::Link;
use spacearm_core::*;

fn h(model: &Model, x: &[f64]) -> DMatrix<f64> {
    let mut data = Data::new(model);
    crba::crba(model, &mut data, x).unwrap().clone()
}

fn rows(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

fn xyzw(q: &UnitQuaternion<f64>) -> [f64; 4] {
    [q.i, q.j, q.k, q.w]
}

/// The builder's description of `link`, `prefix` on its names, its parent renamed
/// by `parent_name`.
fn spec_of(link: &Link, prefix: &str, parent_name: &str) -> LinkSpec {
    LinkSpec {
        name: format!("{prefix}{}", link.name),
        parent: parent_name.to_string(),
        joint_name: Some(format!("{prefix}{}", link.joint.name)),
        kind: link.joint.kind,
        origin_in_parent: link.joint.origin_in_parent.into(),
        rotation_in_parent: xyzw(&link.joint.rotation_in_parent),
        axis: link.joint.axis.into_inner().into(),
        com_from_joint: link.com_from_joint.into(),
        mass: link.mass.mass,
        inertia: rows(&link.mass.inertia),
        limits: link.joint.limits,
    }
}

/// `model` rebuilt from scratch, link by link, with the builder (no seeding).
fn rebuilt(model: &Model) -> ModelBuilder {
    let base = model.base();
    let mut b = ModelBuilder::with_triangle_inequality(model.name(), model.base_name(), base.mass, rows(&base.inertia), model.triangle_inequality()).unwrap();
    for link in model.links() {
        b.add_link(spec_of(link, "", model.body_name(link.parent))).unwrap();
        b.set_joint_dynamics(&link.name, link.joint.dynamics).unwrap();
    }
    for p in model.points() {
        b.add_point(&p.name, model.body_name(p.body), p.offset.into()).unwrap();
    }
    if let Some(e) = model.end_effector() {
        b.set_end_effector(&model.points()[e].name);
    }
    b.set_initial_q(model.initial_q().to_vec());
    b
}

fn models() -> Vec<Model> {
    let mut out: Vec<Model> = ["planar4", "spatial6", "spatial7", "dual_arm", "ets7"].iter().map(|n| presets::by_name(n).unwrap()).collect();
    for seed in 0..4 {
        out.push(common::random_model(&mut common::rng(seed), 9));
    }
    out
}

#[test]
fn a_builder_seeded_from_a_model_builds_it_bit_for_bit() {
    for m in models() {
        assert_eq!(ModelBuilder::from_model(&m).build().unwrap(), m, "{}", m.name());
        assert_eq!(m.to_builder().build().unwrap(), m);
    }
    // Geometry, passive dynamics and the triangle-inequality rule are carried too.
    let ets = presets::ets7_with(TriangleInequality::Warn);
    assert_eq!(ets.to_builder().build().unwrap(), ets);
}

#[test]
fn attaching_a_payload_equals_the_model_built_with_it_from_scratch() {
    for seed in 0..6 {
        let mut r = common::rng(100 + seed);
        let mut direct = common::random_builder(&mut r, 8);
        let host = direct.build().unwrap();
        let rot = UnitQuaternion::from_euler_angles(0.3, -0.7, 1.1);
        let mount = Mount::new("link5", [0.2, -0.1, 0.4], xyzw(&rot));
        let inertia = [[0.5, 0.01, -0.02], [0.01, 0.7, 0.03], [-0.02, 0.03, 0.9]];
        let payload = LinkSpec::payload("payload", &mount, 12.5, inertia);
        direct.add_link(payload.clone()).unwrap();
        let direct = direct.build().unwrap();
        let attached = host.attach_body(payload, None).unwrap();
        assert_eq!(attached, direct);
        let (x, _) = common::random_state(&mut r, &attached);
        assert_eq!(h(&attached, &x), h(&direct, &x));
        // The untouched part is bit-identical, and the payload came last.
        assert_eq!(&attached.links()[..host.links().len()], host.links());
        assert_eq!(attached.points(), host.points());
        assert_eq!(attached.initial_q(), host.initial_q());
        assert_eq!(attached.total_mass(), host.total_mass() + 12.5);
        // Removing it is the inverse of attaching it.
        assert_eq!(attached.remove_subtree("payload").unwrap(), host);
    }
}

#[test]
fn a_payload_on_the_base_has_the_composite_mass_properties_of_the_parallel_axis_theorem() {
    let (m0, i0) = (300.0, Matrix3::new(40.0, 1.0, -2.0, 1.0, 55.0, 0.5, -2.0, 0.5, 61.0));
    let host = ModelBuilder::new("sat", "bus", m0, rows(&i0)).unwrap().build().unwrap();
    let rot = UnitQuaternion::from_euler_angles(-0.4, 0.9, 0.25);
    let (m, p) = (25.0, Vector3::new(0.8, -0.3, 1.2));
    let ip = Matrix3::new(2.0, 0.1, 0.0, 0.1, 3.0, -0.2, 0.0, -0.2, 4.0);
    let attached = host.attach_body(LinkSpec::payload("tank", &Mount::new("bus", p.into(), xyzw(&rot)), m, rows(&ip)), None).unwrap();
    // Base at the origin, aligned with the inertial frame: the base block of H is the kinetic
    // energy's Hessian of base + payload, the payload moving at v0 + ω × p.
    let x = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
    let hm = h(&attached, &x);
    let r = rot.to_rotation_matrix().into_inner();
    let px = p.cross_matrix();
    let i_about_base = i0 + r * ip * r.transpose() + (Matrix3::identity() * p.norm_squared() - p * p.transpose()) * m;
    let scale = i_about_base.amax();
    assert!((hm.fixed_view::<3, 3>(0, 0) - Matrix3::identity() * (m0 + m)).amax() <= 1e-13 * (m0 + m));
    assert!((hm.fixed_view::<3, 3>(0, 3) + px * m).amax() <= 1e-13 * scale, "{hm}");
    assert!((hm.fixed_view::<3, 3>(3, 3) - i_about_base).amax() <= 1e-13 * scale, "{hm}");
    // Total mass and CM: the mass-weighted mean.
    assert_eq!(attached.total_mass(), m0 + m);
    let mut data = Data::new(&attached);
    let c = momentum::center_of_mass(&attached, &mut data, &x).unwrap();
    assert!((c - p * (m / (m0 + m))).amax() <= 1e-15 * p.amax());
}

#[test]
fn a_payload_on_a_link_equals_the_link_with_the_merged_mass_properties() {
    // spatial6 with a payload on link 3, against spatial6 whose link 3 carries the composite
    // mass, CM and inertia (parallel-axis theorem, computed here), its frame moved to the new
    // CM (the children's joint origins and the points on it moved with it).
    let host = presets::spatial6();
    let k = 2; // link 3
    let link = &host.links()[k];
    let rot = UnitQuaternion::from_euler_angles(0.5, 0.2, -0.8);
    let (m, p) = (9.0, Vector3::new(0.05, 0.3, -0.1));
    let ip = Matrix3::new(0.2, 0.0, 0.01, 0.0, 0.3, 0.0, 0.01, 0.0, 0.25);
    let attached = host.attach_body(LinkSpec::payload("tool", &Mount::new(&link.name, p.into(), xyzw(&rot)), m, rows(&ip)), None).unwrap();
    let (ml, il) = (link.mass.mass, link.mass.inertia);
    let total = ml + m;
    let d = p * (m / total); // the composite CM in link 3's frame
    let r = rot.to_rotation_matrix().into_inner();
    let shift = |v: Vector3<f64>, mass: f64| (Matrix3::identity() * v.norm_squared() - v * v.transpose()) * mass;
    let merged_inertia = il + shift(-d, ml) + r * ip * r.transpose() + shift(p - d, m);
    let body = k + 1;
    let mut b = ModelBuilder::new(host.name(), host.base_name(), host.base().mass, rows(&host.base().inertia)).unwrap();
    for (j, l) in host.links().iter().enumerate() {
        let mut s = spec_of(l, "", host.body_name(l.parent));
        if j == k {
            s.com_from_joint = (l.com_from_joint + d).into();
            s.mass = total;
            s.inertia = rows(&merged_inertia);
        }
        if l.parent == body {
            s.origin_in_parent = (l.joint.origin_in_parent - d).into();
        }
        b.add_link(s).unwrap();
    }
    for pt in host.points() {
        let offset = if pt.body == body { pt.offset - d } else { pt.offset };
        b.add_point(&pt.name, host.body_name(pt.body), offset.into()).unwrap();
    }
    let merged = b.build().unwrap();
    let mut r = common::rng(7);
    for _ in 0..5 {
        let (x, _) = common::random_state(&mut r, &host);
        let (ha, hb) = (h(&attached, &x), h(&merged, &x));
        assert!((&ha - &hb).amax() <= 1e-12 * hb.amax(), "{}", (&ha - &hb).amax());
    }
    assert_eq!(attached.total_mass(), merged.total_mass());
}

#[test]
fn attaching_a_model_equals_building_it_in_by_hand() {
    let mut r = common::rng(42);
    let host = common::random_model(&mut r, 7);
    let mut other_builder = common::random_builder(&mut r, 5);
    other_builder.set_joint_dynamics("link2", JointDynamics { actuated: false, stiffness: 30.0, damping: 0.4, rest: 0.1 }).unwrap();
    other_builder.add_point("handle", "base", [0.0, 0.4, 0.0]).unwrap();
    let n_other = other_builder.dofs_of_first(5);
    other_builder.set_initial_q((0..n_other).map(|d| 0.1 * d as f64 - 0.2).collect());
    let other = other_builder.build().unwrap();
    let rot = UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3);
    let mount = Mount::new("link4", [0.1, 0.2, -0.3], xyzw(&rot));
    let attached = host.attach_model(&other, &mount, "t_", Some("target")).unwrap();

    // By hand: the other's base a payload, its links and points prefixed.
    let mut b = rebuilt(&host);
    let mut spec = LinkSpec::payload("target", &mount, other.base().mass, rows(&other.base().inertia));
    spec.joint_name = Some("target_joint".into());
    b.add_link(spec).unwrap();
    let name_in = |body: usize| if body == 0 { "target".to_string() } else { format!("t_{}", other.body_name(body)) };
    for l in other.links() {
        b.add_link(spec_of(l, "t_", &name_in(l.parent))).unwrap();
        b.set_joint_dynamics(&format!("t_{}", l.name), l.joint.dynamics).unwrap();
    }
    for p in other.points() {
        b.add_point(&format!("t_{}", p.name), &name_in(p.body), p.offset.into()).unwrap();
    }
    b.set_initial_q(host.initial_q().iter().chain(other.initial_q()).copied().collect());
    let by_hand = b.build().unwrap();
    assert_eq!(attached, by_hand);
    assert_eq!(attached.n_dof(), host.n_dof() + other.n_dof());
    assert_eq!(&attached.initial_q()[host.n_dof()..], other.initial_q());
    assert!(!attached.dof_dynamics()[host.n_dof() + 1].actuated || !attached.dof_dynamics()[host.n_dof()].actuated);
    for _ in 0..3 {
        let (x, _) = common::random_state(&mut r, &attached);
        assert_eq!(h(&attached, &x), h(&by_hand, &x));
    }
    // The host's part is untouched; removing the attached subtree gives the host back.
    assert_eq!(&attached.links()[..host.links().len()], host.links());
    assert_eq!(attached.end_effector(), host.end_effector());
    assert_eq!(attached.remove_subtree("target").unwrap(), host);
    // Two copies of one model, told apart by the prefix.
    let twice = attached.attach_model(&other, &Mount::new("base", [2.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]), "u_", None).unwrap();
    assert_eq!(twice.n_dof(), host.n_dof() + 2 * other.n_dof());
    assert!(twice.body_index("u_base").is_ok() && twice.point_index("u_handle").is_ok());
}

#[test]
fn removing_a_subtree_equals_the_smaller_model_built_directly() {
    let host = presets::dual_arm();
    // The subtree of the first arm's second link goes; the other arm stays.
    let gone = host.links()[1].name.clone();
    let removed = host.remove_subtree(&gone).unwrap();
    let root = host.body_index(&gone).unwrap();
    let mut b = ModelBuilder::new(host.name(), host.base_name(), host.base().mass, rows(&host.base().inertia)).unwrap();
    let mut q = Vec::new();
    for (k, l) in host.links().iter().enumerate() {
        if host.is_ancestor(root, k + 1) {
            continue;
        }
        b.add_link(spec_of(l, "", host.body_name(l.parent))).unwrap();
        if let Some(d) = host.dof_of_body(k + 1) {
            q.push(host.initial_q()[d]);
        }
    }
    for p in host.points().iter().filter(|p| !host.is_ancestor(root, p.body)) {
        b.add_point(&p.name, host.body_name(p.body), p.offset.into()).unwrap();
    }
    for g in host.geometries().iter().filter(|g| !host.is_ancestor(root, g.body)) {
        b.add_geometry(GeometrySpec {
            name: Some(g.name.clone()),
            body: host.body_name(g.body).to_string(),
            role: g.role,
            shape: g.shape.clone(),
            origin: g.origin.into(),
            rotation: xyzw(&g.rotation),
            rgba: Some(g.rgba),
        })
        .unwrap();
    }
    if let Some(e) = host.end_effector().filter(|&e| !host.is_ancestor(root, host.points()[e].body)) {
        b.set_end_effector(&host.points()[e].name);
    }
    b.set_initial_q(q);
    let direct = b.build().unwrap();
    assert_eq!(removed, direct);
    assert!(removed.n_bodies() < host.n_bodies() && removed.n_dof() < host.n_dof() && !removed.geometries().is_empty());
    assert!(removed.geometries().len() < host.geometries().len());
}

#[test]
fn edits_refuse_bad_input_and_leave_the_builder_unchanged() {
    let host = presets::spatial6();
    let e = host.remove_subtree(host.base_name()).unwrap_err();
    assert!(e.message.contains("is the base"), "{e}");
    let e = host.remove_subtree("ghost").unwrap_err();
    assert!(e.message.contains("'ghost' is not a link") && e.message.contains("link1"), "{e}");
    // A name clash: attaching spatial6 to itself without a prefix.
    let mut b = host.to_builder();
    let before = b.clone().build().unwrap();
    let e = b.attach_model(&host, &Mount::new("base", [1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]), "", Some("other")).unwrap_err();
    assert!(e.message.contains("used twice"), "{e}");
    assert_eq!(b.build().unwrap(), before, "a refused attach changed the builder");
    // A bad mount: an unknown parent, a non-unit rotation, a non-finite origin.
    let e = host.attach_model(&host, &Mount::new("nope", [0.0; 3], [0.0, 0.0, 0.0, 1.0]), "c_", None).unwrap_err();
    assert!(e.message.contains("'nope' is not defined"), "{e}");
    let e = host.attach_model(&host, &Mount::new("base", [0.0; 3], [0.0, 0.0, 0.0, 0.0]), "c_", None).unwrap_err();
    assert!(e.message.contains("rotation"), "{e}");
    let e = host.attach_body(LinkSpec::payload("p", &Mount::new("base", [f64::NAN, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]), 1.0, [[0.0; 3]; 3]), None).unwrap_err();
    assert!(e.message.contains("finite"), "{e}");
    // A non-physical payload inertia is refused by the host's rule.
    let e = host.attach_body(LinkSpec::payload("p", &Mount::new("base", [0.0; 3], [0.0, 0.0, 0.0, 1.0]), 1.0, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 3.0]]), None)
        .unwrap_err();
    assert!(e.message.contains("triangle"), "{e}");
}
