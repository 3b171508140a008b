//! Admission control and physical bounds: oversize requests are refused with
//! `SpacearmError::ResourceLimit` before they allocate; dense workspaces are allocated only
//! when an algorithm needs them, so a long chain runs the O(N) algorithms in O(N) memory;
//! absurd models are refused by the one validation with the field at fault.

use spacearm_core::algorithms::aba::aba;
use spacearm_core::algorithms::crba::crba;
use spacearm_core::admission::MEMORY_LIMIT_BYTES;
use spacearm_core::control::ZeroTorque;
use spacearm_core::derivatives::{mass_matrix_partials, DerivativeData};
use spacearm_core::error::{ModelField, ModelItem};
use spacearm_core::io::toml::model_from_toml_str;
use spacearm_core::model::presets;
use spacearm_core::sim::integrate::IntegratorKind;
use spacearm_core::sim::simulate::{simulate, SimOptions};
use spacearm_core::{Data, JointLimits, JointType, LinkSpec, Model, ModelBuilder, SpacearmError};

const BOX: [[f64; 3]; 3] = [[0.01, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.02]];

fn link(k: usize, parent: &str) -> LinkSpec {
    LinkSpec {
        name: format!("l{k}"),
        parent: parent.to_string(),
        joint_name: None,
        kind: JointType::Revolute,
        origin_in_parent: [0.1, 0.0, 0.0],
        // 3.6° about z at each joint: the chain coils into circles of radius 1.6 m instead of
        // reaching kilometres away from the base (where the base-CM reference point would make
        // the spatial inertias huge).
        rotation_in_parent: [0.0, 0.0, (0.0314f64).sin(), (0.0314f64).cos()],
        axis: [0.0, 0.0, 1.0],
        com_from_joint: [0.05, 0.0, 0.0],
        mass: 1.0,
        inertia: BOX,
        limits: JointLimits::default(),
    }
}

/// A serial chain of `n` revolute links about z (a planar chain, coiled).
fn chain(n: usize) -> Model {
    let mut b = ModelBuilder::new("chain", "base", 100.0, [[10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]]).unwrap();
    for k in 0..n {
        let parent = if k == 0 { "base".to_string() } else { format!("l{}", k - 1) };
        b.add_link(link(k, &parent)).unwrap();
    }
    b.build().unwrap()
}

fn resource_message(e: SpacearmError) -> String {
    match e {
        SpacearmError::ResourceLimit(m) => m,
        other => panic!("expected a ResourceLimit refusal, got {other:?}"),
    }
}

#[test]
fn long_chain_runs_aba_without_dense_workspaces() {
    // (6+N)² at N = 20,000 is 3.2 GB: more than the limit, so CRBA must be refused, while
    // ABA (O(N)) runs on a workspace that never allocated the dense matrix.
    let n = 20_000;
    let model = chain(n);
    let mut data = Data::new(&model);
    assert_eq!(data.mass_matrix.len(), 0);
    let x = presets::initial_configuration(&model);
    let u = vec![0.0; model.nu()];
    let mut f = vec![0.0; model.nu()];
    f[6] = 1.0; // a torque at the first joint
    let du = aba(&model, &mut data, &x, &u, &f, &[]).unwrap().clone();
    assert!(du.iter().all(|v| v.is_finite()));
    // From rest with only τ₁ applied, q̈ = H*⁻¹ τ (the reduced dynamics), and H*⁻¹ is positive
    // definite, so q̈₁ = (H*⁻¹)₁₁ τ₁ has the sign of τ₁; and linear momentum stays zero, so the
    // base accelerates against the arm.
    assert!(du[6] > 0.0, "{}", du[6]);
    assert_eq!(data.mass_matrix.len(), 0, "ABA must not size the dense mass matrix");
    let bytes = ((n + 6) * (n + 6) * 8) as u64;
    assert!(bytes > MEMORY_LIMIT_BYTES);
    let msg = resource_message(crba(&model, &mut data, &x).unwrap_err());
    assert!(msg.contains("mass matrix") && msg.contains("ABA"), "{msg}");
}

#[test]
fn mass_matrix_is_sized_on_first_use() {
    let model = chain(5);
    let mut data = Data::new(&model);
    assert_eq!(data.mass_matrix.len(), 0);
    let x = presets::initial_configuration(&model);
    let h = crba(&model, &mut data, &x).unwrap();
    assert_eq!(h.shape(), (11, 11));
    // Symmetric positive definite: an independent property of any mass matrix.
    assert!((h - h.transpose()).abs().max() < 1e-12);
    assert!(h.clone().cholesky().is_some());
}

#[test]
fn cubic_partials_are_refused_before_allocating() {
    // (6+N)³ doubles at N = 700: 2.8 GB.
    let model = chain(700);
    DerivativeData::admit(&model).unwrap();
    let mut work = DerivativeData::new(&model);
    let x = presets::initial_configuration(&model);
    let msg = resource_message(mass_matrix_partials(&model, &mut work, &x).unwrap_err());
    assert!(msg.contains("mass_matrix_partials") && msg.contains("mass_matrix_derivative"), "{msg}");
    // A workspace that is quadratic but too large is refused at admission.
    assert!(matches!(DerivativeData::admit(&chain(5_000)), Err(SpacearmError::ResourceLimit(_))));
}

#[test]
fn oversize_simulations_are_refused_with_the_way_out() {
    let model = presets::spatial6();
    let x0 = presets::initial_configuration(&model);
    let u0 = vec![0.0; model.nu()];
    let dense = SimOptions { integrator: IntegratorKind::Dopri5, duration: 1.0, dt: 1e-9, ..SimOptions::default() };
    let msg = resource_message(simulate(&model, &x0, &u0, &dense, &mut ZeroTorque, &mut |_| Ok(())).unwrap_err());
    assert!(msg.contains("coarser output grid") && msg.contains("GB"), "{msg}");
    let rk4 = SimOptions { duration: 100.0, dt: 1e-6, ..SimOptions::default() };
    let msg = resource_message(simulate(&model, &x0, &u0, &rk4, &mut ZeroTorque, &mut |_| Ok(())).unwrap_err());
    assert!(msg.contains("record_every"), "{msg}");
    // The same run recording every 1000th step is admitted (checked by running a short one).
    let thinned = SimOptions { duration: 0.01, dt: 1e-6, record_every: 1000, ..SimOptions::default() };
    let r = simulate(&model, &x0, &u0, &thinned, &mut ZeroTorque, &mut |_| Ok(())).unwrap();
    assert_eq!(r.records.n_samples, 11);
}

fn toml_with(mass: &str, origin: &str, com: &str) -> String {
    format!(
        "[model]\nname = \"m\"\n[base]\nmass = 100.0\ninertia = [10.0, 10.0, 10.0]\n[[link]]\nname = \"arm\"\nparent = \"base\"\n\
         com = {com}\nmass = {mass}\ninertia = [0.01, 0.4, 0.4]\n\
         joint = {{ type = \"revolute\", origin = {origin}, axis = [0.0, 0.0, 1.0] }}\n"
    )
}

#[test]
fn absurd_models_are_refused_with_field_and_location() {
    let ok = "[0.5, 0.0, 0.0]";
    assert!(model_from_toml_str(&toml_with("5.0", ok, ok), "m.toml").is_ok());
    for (text, line, what) in [
        (toml_with("1e308", ok, ok), 10, "physical range"),
        (toml_with("1e-12", ok, ok), 10, "physical range"),
        (toml_with("5.0", "[1e150, 0.0, 0.0]", ok), 12, "joint origin"),
        (toml_with("5.0", ok, "[0.0, 1e300, 0.0]"), 9, "com"),
    ] {
        let msg = model_from_toml_str(&text, "m.toml").unwrap_err().to_string();
        assert!(msg.starts_with(&format!("m.toml:{line}:")) && msg.contains(what), "{msg}");
    }
    // The builder door: the same rule, with item and field.
    let mut b = ModelBuilder::new("m", "base", 100.0, [[10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]]).unwrap();
    let mut far = link(0, "base");
    far.origin_in_parent = [0.0, 0.0, 2e6];
    let e = b.add_link(far).unwrap_err();
    assert_eq!((e.item, e.field), (ModelItem::Link(0), ModelField::Origin));
    let e = ModelBuilder::new("m", "base", 1e13, [[10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]]).unwrap_err();
    assert_eq!((e.item, e.field), (ModelItem::Base, ModelField::Mass));
    let mut b = ModelBuilder::new("m", "base", 100.0, [[10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]]).unwrap();
    b.add_link(link(0, "base")).unwrap();
    let e = b.add_point("tip", "l0", [1e7, 0.0, 0.0]).unwrap_err();
    assert_eq!((e.item, e.field), (ModelItem::Point(0), ModelField::Offset));
}

#[test]
fn paper_form_is_refused_beyond_its_work_limit() {
    let x_of = |m: &Model| presets::initial_configuration(m);
    // A chain of 3,000 joints: Σ depth² ≈ 9·10⁹ multiply-adds, over the limit; CRBA is named.
    let long = chain(3_000);
    let Err(e) = spacearm_core::algorithms::inertia::inertia_blocks(&long, &mut Data::new(&long), &x_of(&long)) else {
        panic!("the paper form of a 3000-joint chain was admitted");
    };
    let msg = resource_message(e);
    assert!(msg.contains("multiply-adds") && msg.contains("crba"), "{msg}");
    // A short chain agrees with CRBA (the independent computation).
    let short = chain(8);
    let mut data = Data::new(&short);
    let h_paper = spacearm_core::algorithms::inertia::inertia_blocks(&short, &mut data, &x_of(&short)).unwrap().mass_matrix();
    let h_crba = crba(&short, &mut data, &x_of(&short)).unwrap().clone();
    assert!((h_paper - h_crba).abs().max() < 1e-10);
}
