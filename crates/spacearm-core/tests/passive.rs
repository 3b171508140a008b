//! Passive joints and joint spring–dampers (docs/flexibility.md) against independent sources:
//!
//! - the passive force `−k (q − rest) − c q̇` through every forward dynamics (ABA, CRBA + RNEA,
//!   the reduced GJM route) against the rigid model's ABA under `f + Q` with `Q` computed here
//!   by hand, and the inverse dynamics returning `f`;
//! - the forward-dynamics Jacobians against central differences of ABA;
//! - closed forms: a spring–mass on a free base oscillates at `ω = √(k/μ)` with the reduced
//!   mass `μ = M m / (M + m)` (and decays as `μ q̈ + c q̇ + k q = 0` with a damper), a hinged
//!   link with a torsional spring on a free base at `ω = √(k/I_red)` with the reduced inertia
//!   of the two-body problem, `I_red = det M₂ / (1ᵀ M₂ 1)`; both from the linearization's
//!   eigenvalues and from a simulated trajectory;
//! - a passive joint gets no torque whatever is commanded; undamped runs conserve the kinetic
//!   plus spring energy.

mod common;

use nalgebra::{DMatrix, Vector6};
use spacearm_core::algorithms::aba::aba;
use spacearm_core::algorithms::dynamics::forward_dynamics_via_mass_matrix;
use spacearm_core::algorithms::passive::{passive_forces, spring_energy};
use spacearm_core::algorithms::rnea::rnea;
use spacearm_core::control::{Command, Controller, ZeroTorque};
use spacearm_core::derivatives::{forward_dynamics_derivatives, linearize, DerivativeData, LinearizationInputs};
use spacearm_core::gjm::{generalized_inertia, reduced_forward_dynamics};
use spacearm_core::io::toml::{model_from_toml_str, model_to_toml};
use spacearm_core::model::presets;
use spacearm_core::sim::actuators::detect_reaction_wheels;
use spacearm_core::sim::modes::Conserved;
use spacearm_core::sim::simulate::{simulate, SimOptions, SimResult};
use spacearm_core::*;

fn rel(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs())).max(1e-300);
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale
}

/// A random tree (common::random_model) and the same tree with a random spring–damper, rest
/// position and actuation on every moving joint.
fn sprung_pair(seed: u64, n_links: usize) -> (Model, Model, Vec<JointDynamics>) {
    let rigid = common::random_model(&mut common::rng(seed), n_links);
    let mut b = common::random_builder(&mut common::rng(seed), n_links);
    let mut r = common::rng(seed + 1000);
    let mut dyns = Vec::new();
    for l in rigid.links() {
        if l.joint.kind == JointType::Fixed {
            continue;
        }
        let d = JointDynamics {
            actuated: r_bool(&mut r),
            stiffness: 50.0 * r_unit(&mut r),
            damping: 5.0 * r_unit(&mut r),
            rest: 2.0 * r_unit(&mut r) - 1.0,
        };
        b.set_joint_dynamics(&l.name, d).unwrap();
        dyns.push(d);
    }
    (rigid, b.build().unwrap(), dyns)
}

fn r_unit(r: &mut impl rand::Rng) -> f64 {
    r.random_range(0.0..1.0)
}

fn r_bool(r: &mut impl rand::Rng) -> bool {
    r.random_bool(0.5)
}

#[test]
fn every_forward_dynamics_adds_the_passive_force_and_inverse_dynamics_removes_it() {
    for seed in 0..6 {
        let (rigid, sprung, dyns) = sprung_pair(seed, 7);
        let mut r = common::rng(seed + 7);
        let (x, u) = common::random_state(&mut r, &sprung);
        let f = common::random_vector(&mut r, sprung.nu(), 3.0);
        let n = sprung.n_dof();
        // The passive force by hand.
        let mut q_passive = vec![0.0; 6 + n];
        for (j, d) in dyns.iter().enumerate() {
            q_passive[6 + j] = -d.stiffness * (x[7 + j] - d.rest) - d.damping * u[6 + j];
        }
        assert!(q_passive.iter().map(|v| v.abs()).sum::<f64>() > 1.0, "seed {seed}: the springs must matter");
        let got = passive_forces(&sprung, &x, &u).unwrap();
        assert!(rel(got.as_slice(), &q_passive) < 1e-15, "seed {seed}: passive_forces");
        let f_total: Vec<f64> = f.iter().zip(&q_passive).map(|(a, b)| a + b).collect();
        let expected = aba(&rigid, &mut Data::new(&rigid), &x, &u, &f_total, &[]).unwrap().clone();
        let via_aba = aba(&sprung, &mut Data::new(&sprung), &x, &u, &f, &[]).unwrap().clone();
        let via_h = forward_dynamics_via_mass_matrix(&sprung, &mut Data::new(&sprung), &x, &u, &f, &[]).unwrap();
        let wrench = Vector6::from_column_slice(&f[..6]);
        let via_reduced = reduced_forward_dynamics(&sprung, &mut Data::new(&sprung), &x, &u, &f[6..], &wrench).unwrap();
        for (what, v) in [("ABA", &via_aba), ("CRBA+RNEA", &via_h), ("reduced", &via_reduced)] {
            let e = rel(v.as_slice(), expected.as_slice());
            assert!(e < 1e-10, "seed {seed}: {what} differs from the rigid ABA under f + Q by {e:e}");
        }
        // And the springs change the answer (the check above would pass if both ignored them).
        let rigid_answer = aba(&rigid, &mut Data::new(&rigid), &x, &u, &f, &[]).unwrap().clone();
        assert!(rel(rigid_answer.as_slice(), expected.as_slice()) > 1e-3);
        let back = rnea(&sprung, &mut Data::new(&sprung), &x, &u, via_aba.as_slice(), &[]).unwrap().clone();
        assert!(rel(back.as_slice(), &f) < 1e-10, "seed {seed}: inverse dynamics does not return f");
    }
}

#[test]
fn forward_dynamics_jacobians_with_springs_match_central_differences() {
    let (_, sprung, _) = sprung_pair(3, 6);
    let mut r = common::rng(42);
    let (x, u) = common::random_state(&mut r, &sprung);
    let f = common::random_vector(&mut r, sprung.nu(), 3.0);
    let n = sprung.n_dof();
    let mut work = DerivativeData::new(&sprung);
    let (dx, du, _) = forward_dynamics_derivatives(&sprung, &mut work, &x, &u, &f).unwrap();
    let (dx, du) = (dx.clone(), du.clone());
    let fd = |x: &[f64], u: &[f64]| aba(&sprung, &mut Data::new(&sprung), x, u, &f, &[]).unwrap().clone();
    let h = 1e-6;
    for j in 0..n {
        let col = common::central_flat(|y| fd(y, &u), &x, 7 + j, h);
        let e = rel(dx.column(6 + j).as_slice(), col.as_slice());
        assert!(e < 1e-6, "∂u̇/∂q_{j}: {e:e}");
        let col = common::central_flat(|w| fd(&x, w), &u, 6 + j, h);
        let e = rel(du.column(6 + j).as_slice(), col.as_slice());
        assert!(e < 1e-6, "∂u̇/∂q̇_{j}: {e:e}");
    }
}

const BASE_INERTIA: [[f64; 3]; 3] = [[8.0, 0.0, 0.0], [0.0, 9.0, 0.0], [0.0, 0.0, 10.0]];

/// A 100 kg base and a 5 kg point-like mass on a prismatic joint along x through the base CM,
/// with a spring `k` (N/m) and damper `c` (N·s/m) about `rest`.
fn spring_mass(k: f64, c: f64, rest: f64) -> Model {
    let mut b = ModelBuilder::new("spring-mass", "base", 100.0, BASE_INERTIA).unwrap();
    b.add_link(LinkSpec::new("slug", "base", JointType::Prismatic, [0.5, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0], 5.0, [1e-3, 1e-3, 1e-3])).unwrap();
    b.set_joint_dynamics("slug", JointDynamics { actuated: false, stiffness: k, damping: c, rest }).unwrap();
    b.build().unwrap()
}

/// A 100 kg base (I_zz = 10 kg·m²) and a 10 kg link hinged about z at 1 m from the base CM, its
/// CM 0.5 m beyond the hinge (I_zz = 0.8 kg·m²), with a torsional spring `k` (N·m/rad).
const HINGE: (f64, f64, f64, f64, f64, f64) = (100.0, 10.0, 10.0, 0.8, 1.0, 0.5);

fn hinged(k: f64) -> Model {
    let (_, _, m, i1, a, bb) = HINGE;
    let mut b = ModelBuilder::new("hinged", "base", 100.0, BASE_INERTIA).unwrap();
    b.add_link(LinkSpec::new("panel", "base", JointType::Revolute, [a, 0.0, 0.0], [0.0, 0.0, 1.0], [bb, 0.0, 0.0], m, [0.1, 0.75, i1])).unwrap();
    b.set_joint_dynamics("panel", JointDynamics { actuated: false, stiffness: k, damping: 0.0, rest: 0.0 }).unwrap();
    b.build().unwrap()
}

/// `I_red = det M₂ / (1ᵀ M₂ 1)` of two planar bodies joined by a hinge, straight (q = 0), at zero
/// momentum: `M₂ = [[μa² + I₀, μab], [μab, μb² + I₁]]` in the absolute angles, `μ` the reduced
/// mass (derived in docs/flexibility.md).
fn hinge_reduced_inertia() -> f64 {
    let (m0, i0, m, i1, a, b) = HINGE;
    let mu = m0 * m / (m0 + m);
    let (m11, m12, m22) = (mu * a * a + i0, mu * a * b, mu * b * b + i1);
    (m11 * m22 - m12 * m12) / (m11 + 2.0 * m12 + m22)
}

/// The largest imaginary part of the eigenvalues of the linearization at rest at `x`.
fn linearized_frequency(model: &Model, x: &[f64]) -> f64 {
    let mut work = DerivativeData::new(model);
    let u = vec![0.0; model.nu()];
    let f = vec![0.0; model.nu()];
    let (a, _) = linearize(model, &mut work, x, &u, &f, LinearizationInputs::Joints).unwrap();
    let a: DMatrix<f64> = a.clone();
    a.complex_eigenvalues().iter().map(|z| z.im).fold(0.0, f64::max)
}

fn run(model: &Model, x0: &[f64], u0: &[f64], duration: f64, dt: f64, c: &mut dyn Controller) -> SimResult {
    let opts = SimOptions { duration, dt, ..SimOptions::default() };
    simulate(model, x0, u0, &opts, c, &mut |_| Ok(())).unwrap()
}

/// Times at which `v` crosses zero upwards (linear interpolation between samples).
fn upward_crossings(t: &[f64], v: &[f64]) -> Vec<f64> {
    (1..v.len()).filter(|&i| v[i - 1] < 0.0 && v[i] >= 0.0).map(|i| t[i - 1] + (t[i] - t[i - 1]) * (-v[i - 1]) / (v[i] - v[i - 1])).collect()
}

#[test]
fn spring_mass_on_a_free_base_oscillates_at_the_reduced_mass_frequency() {
    let (k, rest) = (200.0, 0.1);
    let model = spring_mass(k, 0.0, rest);
    let mu = 100.0 * 5.0 / 105.0;
    let omega = (k / mu).sqrt();
    let mut x0 = presets::initial_configuration(&model);
    x0[7] = rest;
    let lin = linearized_frequency(&model, &x0);
    assert!((lin / omega - 1.0).abs() < 1e-10, "linearization: {lin} rad/s, closed form {omega}");
    // Released from rest at rest + A: q − rest = A cos ωt exactly (a linear two-body problem).
    let amp = 0.02;
    x0[7] = rest + amp;
    let u0 = vec![0.0; model.nu()];
    let period = 2.0 * std::f64::consts::PI / omega;
    let res = run(&model, &x0, &u0, 2.2 * period, 1e-3, &mut ZeroTorque);
    let (nx, rec) = (model.nx(), &res.records);
    let q: Vec<f64> = rec.x.chunks(nx).map(|row| row[7] - rest).collect();
    let worst = rec.t.iter().zip(&q).map(|(t, q)| (q - amp * (omega * t).cos()).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-8 * amp, "trajectory off the closed form by {worst:e} m");
    let ups = upward_crossings(&rec.t, &q);
    assert!(ups.len() >= 2);
    let measured = ups[1] - ups[0];
    assert!((measured / period - 1.0).abs() < 1e-6, "simulated period {measured} s, closed form {period} s");
    // Undamped and torque-free: the mechanical energy (kinetic + spring) is a conserved quantity.
    let drift = res.drift.iter().find(|(c, _)| *c == Conserved::Energy).expect("energy monitored").1;
    assert!(drift < 1e-9, "energy drift {drift:e}");
    let e0 = rec.energy[0];
    assert!((e0 - 0.5 * k * amp * amp).abs() < 1e-12 * e0, "the initial energy is the spring's");
    assert!((spring_energy(&model, &x0).unwrap() - e0).abs() < 1e-15);
}

#[test]
fn a_damped_spring_mass_follows_the_damped_closed_form() {
    let (k, c) = (200.0, 4.0);
    let model = spring_mass(k, c, 0.0);
    let mu = 100.0 * 5.0 / 105.0;
    let (omega, zeta) = ((k / mu).sqrt(), c / (2.0 * (k * mu).sqrt()));
    let wd = omega * (1.0 - zeta * zeta).sqrt();
    let amp = 0.02;
    let mut x0 = presets::initial_configuration(&model);
    x0[7] = amp;
    let res = run(&model, &x0, &vec![0.0; model.nu()], 2.0, 1e-3, &mut ZeroTorque);
    let nx = model.nx();
    let mut worst: f64 = 0.0;
    for (t, row) in res.records.t.iter().zip(res.records.x.chunks(nx)) {
        // μ q̈ + c q̇ + k q = 0, q(0) = A, q̇(0) = 0.
        let exact = amp * (-zeta * omega * t).exp() * ((wd * t).cos() + zeta * omega / wd * (wd * t).sin());
        worst = worst.max((row[7] - exact).abs());
    }
    assert!(worst < 1e-8 * amp, "damped trajectory off the closed form by {worst:e} m");
    assert!(res.drift.iter().all(|(c, _)| *c != Conserved::Energy), "a damped run does not monitor the energy");
}

#[test]
fn hinged_link_on_a_free_base_oscillates_at_the_reduced_inertia_frequency() {
    let k = 30.0;
    let model = hinged(k);
    let i_red = hinge_reduced_inertia();
    let omega = (k / i_red).sqrt();
    let x0 = presets::initial_configuration(&model);
    let h_star = generalized_inertia(&model, &mut Data::new(&model), &x0).unwrap()[(0, 0)];
    assert!((h_star / i_red - 1.0).abs() < 1e-12, "H* = {h_star}, closed-form reduced inertia {i_red}");
    let lin = linearized_frequency(&model, &x0);
    assert!((lin / omega - 1.0).abs() < 1e-10, "linearization: {lin} rad/s, closed form {omega}");
    // A small swing: the period approaches 2π/ω as the amplitude goes to zero (the error is
    // second order in the amplitude).
    let amp = 1e-4;
    let mut x1 = x0.clone();
    x1[7] = amp;
    let period = 2.0 * std::f64::consts::PI / omega;
    let res = run(&model, &x1, &vec![0.0; model.nu()], 2.2 * period, 2e-3, &mut ZeroTorque);
    let q: Vec<f64> = res.records.x.chunks(model.nx()).map(|row| row[7]).collect();
    let ups = upward_crossings(&res.records.t, &q);
    let measured = ups[1] - ups[0];
    assert!((measured / period - 1.0).abs() < 1e-6, "simulated period {measured} s, closed form {period} s");
    // The rigid link (no spring) has no oscillation at all: the frequency is the spring's.
    assert!(linearized_frequency(&hinged(0.0), &x0) < 1e-9);
}

#[test]
fn a_passive_joint_gets_no_torque_and_is_no_wheel() {
    let model = hinged(30.0);
    let mut x0 = presets::initial_configuration(&model);
    x0[7] = 0.05;
    let u0 = vec![0.0; model.nu()];
    let pushed = run(&model, &x0, &u0, 0.5, 1e-2, &mut common::Scripted { name: "push", command: |_, out: &mut Command| out.tau.fill(3.0) });
    let free = run(&model, &x0, &u0, 0.5, 1e-2, &mut ZeroTorque);
    assert!(pushed.records.tau.iter().all(|t| *t == 0.0), "applied torque on a passive joint");
    assert!(pushed.records.tau_cmd.iter().all(|t| *t == 3.0), "the command is recorded as given");
    assert_eq!(pushed.records.x, free.records.x, "the command moved a passive joint");
    assert!(pushed.events.is_empty(), "a passive joint has no actuator to saturate");
    // A symmetric rotor on a passive joint is a free spinning body, not a wheel.
    let mut b = ModelBuilder::new("rotor", "base", 100.0, BASE_INERTIA).unwrap();
    b.add_link(LinkSpec::new("rotor", "base", JointType::Revolute, [0.1, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0], 1.0, [0.03, 0.03, 0.05])).unwrap();
    assert_eq!(detect_reaction_wheels(&b.build().unwrap()), vec![0]);
    b.set_joint_dynamics("rotor", JointDynamics { actuated: false, ..JointDynamics::default() }).unwrap();
    assert!(detect_reaction_wheels(&b.build().unwrap()).is_empty());
}

#[test]
fn bad_joint_dynamics_are_refused_with_the_field_named() {
    let model_b = || {
        let mut b = ModelBuilder::new("m", "base", 100.0, BASE_INERTIA).unwrap();
        for (name, kind) in [("arm", JointType::Revolute), ("bolt", JointType::Fixed)] {
            b.add_link(LinkSpec::new(name, "base", kind, [0.5, 0.0, 0.0], [0.0, 0.0, 1.0], [0.5, 0.0, 0.0], 2.0, [0.01, 0.4, 0.4])).unwrap();
        }
        b
    };
    let d = JointDynamics::default();
    for (link, dynamics, needle) in [
        ("arm", JointDynamics { stiffness: -1.0, ..d }, "stiffness must be finite and >= 0"),
        ("arm", JointDynamics { damping: f64::NAN, ..d }, "damping must be finite and >= 0"),
        ("arm", JointDynamics { stiffness: 1e13, ..d }, "exceeds"),
        ("arm", JointDynamics { rest: f64::INFINITY, ..d }, "rest must be finite"),
        ("bolt", JointDynamics { stiffness: 1.0, ..d }, "a fixed joint has no coordinate"),
        ("bolt", JointDynamics { actuated: false, ..d }, "a fixed joint has no coordinate"),
        ("base", d, "is not a link of the model"),
        ("nope", d, "is not a link of the model"),
    ] {
        let e = model_b().set_joint_dynamics(link, dynamics).map(|_| ()).unwrap_err();
        assert!(e.message.contains(needle), "{link} {dynamics:?}: {}", e.message);
        if link == "arm" || link == "bolt" {
            assert_eq!(e.field, spacearm_core::error::ModelField::JointDynamics);
        }
    }
}

const SPRUNG_TOML: &str = r#"
[model]
name = "sprung"

[base]
mass = 100.0
inertia = [8.0, 9.0, 10.0]

[[link]]
name = "panel"
parent = "base"
com = [0.5, 0.0, 0.0]
mass = 10.0
inertia = [0.1, 0.75, 0.8]
joint = { type = "revolute", origin = [1.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], actuated = false, stiffness = 30.0, damping = 0.5, rest = 0.25 }
"#;

#[test]
fn toml_reads_and_writes_the_joint_dynamics() {
    let m = model_from_toml_str(SPRUNG_TOML, "sprung.toml").unwrap();
    assert_eq!(m.links()[0].joint.dynamics, JointDynamics { actuated: false, stiffness: 30.0, damping: 0.5, rest: 0.25 });
    assert_eq!(m.actuated_dofs(), vec![false]);
    let text = model_to_toml(&m);
    assert_eq!(model_from_toml_str(&text, "again.toml").unwrap(), m, "round trip:\n{text}");
    // A rigid model's file has none of the keys.
    assert!(!model_to_toml(&presets::spatial6()).contains("stiffness"));
    let e = model_from_toml_str(&SPRUNG_TOML.replace("damping = 0.5", "damping = -0.5"), "bad.toml").unwrap_err().to_string();
    assert!(e.contains("bad.toml:15") && e.contains("damping must be finite and >= 0"), "{e}");
}

/// A base, an arm link (actuated, or welded when `held`), a sprung panel on the arm and a sprung
/// slosh mass on the base.
fn arm_panel_slosh(held: bool) -> Model {
    let mut b = ModelBuilder::new("aps", "base", 300.0, [[40.0, 1.0, 0.0], [1.0, 50.0, 0.0], [0.0, 0.0, 60.0]]).unwrap();
    let link = |name: &str, parent: &str, kind: JointType, origin: [f64; 3], axis: [f64; 3], com: [f64; 3], mass: f64| {
        LinkSpec::new(name, parent, kind, origin, axis, com, mass, [0.2, 0.5, 0.6])
    };
    let arm_kind = if held { JointType::Fixed } else { JointType::Revolute };
    b.add_link(link("arm", "base", arm_kind, [0.8, 0.1, 0.0], [0.0, 0.0, 1.0], [0.6, 0.0, 0.1], 12.0)).unwrap();
    b.add_link(link("panel", "arm", JointType::Revolute, [0.6, 0.0, 0.0], [0.0, 1.0, 1.0], [0.7, 0.0, 0.0], 8.0)).unwrap();
    b.add_link(link("slosh", "base", JointType::Prismatic, [0.0, 0.3, -0.2], [1.0, 0.0, 0.2], [0.0; 3], 40.0)).unwrap();
    b.set_joint_dynamics("panel", JointDynamics { actuated: false, stiffness: 25.0, damping: 0.0, rest: 0.3 }).unwrap();
    b.set_joint_dynamics("slosh", JointDynamics { actuated: false, stiffness: 900.0, damping: 0.0, rest: -0.05 }).unwrap();
    b.build().unwrap()
}

/// The positive imaginary parts of the linearization's eigenvalues at rest at `x`, ascending.
fn linearized_frequencies(model: &Model, x: &[f64]) -> Vec<f64> {
    let mut work = DerivativeData::new(model);
    let zeros = vec![0.0; model.nu()];
    let (a, _) = linearize(model, &mut work, x, &zeros, &zeros, LinearizationInputs::Joints).unwrap();
    let mut w: Vec<f64> = a.clone().complex_eigenvalues().iter().map(|z| z.im).filter(|im| *im > 1e-6).collect();
    w.sort_by(f64::total_cmp);
    w
}

#[test]
fn natural_frequencies_equal_the_linearizations_with_joints_free_or_held() {
    use spacearm_core::analysis::passive_modes::{passive_modes, ActuatedJoints};
    let free_model = arm_panel_slosh(false);
    let mut x = presets::initial_configuration(&free_model);
    x[7..].copy_from_slice(&[0.0, 0.3, -0.05]); // the springs at rest: an equilibrium
    let free = passive_modes(&free_model, &mut Data::new(&free_model), &x, ActuatedJoints::Free).unwrap();
    assert_eq!(free.dofs, vec![0, 1, 2]);
    assert!(free.frequencies[0].abs() < 1e-9, "the unsprung arm joint is a zero-frequency mode");
    let lin = linearized_frequencies(&free_model, &x);
    assert_eq!(lin.len(), 2);
    for (got, want) in free.frequencies[1..].iter().zip(&lin) {
        assert!((got / want - 1.0).abs() < 1e-9, "free: {got} rad/s, linearization {want}");
    }
    // Held: the same as the model with the arm joint welded at its angle (0 here).
    let held = passive_modes(&free_model, &mut Data::new(&free_model), &x, ActuatedJoints::Held).unwrap();
    assert_eq!(held.dofs, vec![1, 2]);
    let welded = arm_panel_slosh(true);
    let mut xw = presets::initial_configuration(&welded);
    xw[7..].copy_from_slice(&[0.3, -0.05]);
    let lin = linearized_frequencies(&welded, &xw);
    for (got, want) in held.frequencies.iter().zip(&lin) {
        assert!((got / want - 1.0).abs() < 1e-9, "held: {got} rad/s, linearization of the welded model {want}");
    }
    // Holding one joint is one constraint: the frequencies interlace (Rayleigh), free[i] ≤ held[i] ≤ free[i+1].
    for i in 0..2 {
        assert!(free.frequencies[i] <= held.frequencies[i] + 1e-12 && held.frequencies[i] <= free.frequencies[i + 1] + 1e-12);
    }
    assert!((held.frequencies[0] / free.frequencies[1] - 1.0).abs() > 1e-3, "holding the arm must matter");
    // Mass-normalized shapes, zero on the held joint.
    let h = generalized_inertia(&free_model, &mut Data::new(&free_model), &x).unwrap();
    for i in 0..2 {
        let v = held.shapes.column(i);
        assert_eq!(v[0], 0.0);
        assert!(((v.transpose() * &h * v)[(0, 0)] - 1.0).abs() < 1e-12);
    }
}

mod slosh {
    use super::*;
    use spacearm_core::algorithms::kinematics::forward_kinematics;
    use spacearm_core::analysis::passive_modes::{passive_modes, ActuatedJoints};
    use spacearm_core::model::slosh::{SloshModel, SloshRestoring, SloshSpec};

    fn spec(model: SloshModel, length: Option<f64>) -> SloshSpec {
        SloshSpec {
            name: "fuel".into(),
            parent: "base".into(),
            model,
            mass: 20.0,
            position: [0.6, 0.0, 0.0],
            axis: [1.0, 0.0, 0.0],
            hinge: Some([0.0, 0.0, 1.0]),
            length,
            restoring: SloshRestoring::Frequency(2.0),
            damping: 0.0,
        }
    }

    fn with(base_mass: f64, base_izz: f64, s: SloshSpec) -> Model {
        let mut b = ModelBuilder::new("tank", "base", base_mass, [[0.9 * base_izz, 0.0, 0.0], [0.0, 0.95 * base_izz, 0.0], [0.0, 0.0, base_izz]]).unwrap();
        b.add_slosh(s).unwrap();
        b.build().unwrap()
    }

    fn frequencies(m: &Model) -> Vec<f64> {
        let x = presets::initial_configuration(m);
        passive_modes(m, &mut Data::new(m), &x, ActuatedJoints::Held).unwrap().frequencies
    }

    #[test]
    fn spring_mass_is_a_passive_prismatic_point_mass_at_position_plus_q_axis() {
        let m = with(100.0, 10.0, SloshSpec { hinge: None, ..spec(SloshModel::SpringMass, None) });
        let l = &m.links()[0];
        assert_eq!((l.joint.kind, l.joint.dynamics.actuated, l.joint.dynamics.stiffness), (JointType::Prismatic, false, 20.0 * 4.0));
        let mut x = presets::initial_configuration(&m);
        x[7] = 0.1;
        let mut d = Data::new(&m);
        forward_kinematics(&m, &mut d, &x).unwrap();
        assert!((d.com_in_world[1] - nalgebra::Vector3::new(0.7, 0.0, 0.0)).norm() < 1e-15);
        // Reduced mass on the free base: ω² = k / μ.
        let mu = 100.0 * 20.0 / 120.0;
        assert!((frequencies(&m)[0] / (80.0_f64 / mu).sqrt() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn pendulum_frequency_is_the_given_one_on_a_heavy_base_and_the_reduced_one_on_a_free_base() {
        let heavy = with(1e9, 1e9, spec(SloshModel::Pendulum, Some(0.3)));
        assert!((frequencies(&heavy)[0] / 2.0 - 1.0).abs() < 1e-7, "{:?}", frequencies(&heavy));
        let m = with(100.0, 10.0, spec(SloshModel::Pendulum, Some(0.3)));
        // The bob at position + length·axis at q = 0.
        let mut d = Data::new(&m);
        forward_kinematics(&m, &mut d, &presets::initial_configuration(&m)).unwrap();
        assert!((d.com_in_world[1] - nalgebra::Vector3::new(0.9, 0.0, 0.0)).norm() < 1e-15);
        // The hinged-body closed form with a point bob: a = 0.6, b = 0.3, I1 = 0.
        let (mu, a, b, i0): (f64, f64, f64, f64) = (100.0 * 20.0 / 120.0, 0.6, 0.3, 10.0);
        let (m11, m12, m22) = (mu * a * a + i0, mu * a * b, mu * b * b);
        let i_red = (m11 * m22 - m12 * m12) / (m11 + 2.0 * m12 + m22);
        let k: f64 = 20.0 * 0.09 * 4.0;
        assert!((frequencies(&m)[0] / (k / i_red).sqrt() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn spherical_pendulum_has_two_equal_modes_and_refuses_its_singular_posture() {
        let heavy = with(1e9, 1e9, spec(SloshModel::SphericalPendulum, Some(0.3)));
        assert_eq!(heavy.n_dof(), 2);
        assert_eq!(heavy.links()[0].mass.mass, 0.0, "the gimbal link is massless");
        for w in frequencies(&heavy) {
            assert!((w / 2.0 - 1.0).abs() < 1e-7, "{w}");
        }
        // Joint axes: e1 = hinge (z), e2 = axis × e1 = x × z = −y.
        assert_eq!(heavy.links()[0].joint.axis.into_inner(), nalgebra::Vector3::z());
        assert_eq!(heavy.links()[1].joint.axis.into_inner(), -nalgebra::Vector3::y());
        let m = with(100.0, 10.0, spec(SloshModel::SphericalPendulum, Some(0.3)));
        let mut x = presets::initial_configuration(&m);
        x[8] = std::f64::consts::FRAC_PI_2;
        let e = aba(&m, &mut Data::new(&m), &x, &vec![0.0; m.nu()], &vec![0.0; m.nu()], &[]).unwrap_err();
        assert!(matches!(e, SpacearmError::Singular(_)), "{e}");
    }

    #[test]
    fn bad_slosh_specs_are_refused() {
        let mut b = ModelBuilder::new("tank", "base", 100.0, BASE_INERTIA).unwrap();
        for (s, needle) in [
            (SloshSpec { mass: 0.0, ..spec(SloshModel::SpringMass, None) }, "mass must be finite and > 0"),
            (SloshSpec { hinge: None, ..spec(SloshModel::SpringMass, Some(1.0)) }, "takes no length"),
            (spec(SloshModel::Pendulum, None), "needs a length"),
            (spec(SloshModel::Pendulum, Some(-1.0)), "length must be finite and > 0"),
            (SloshSpec { hinge: Some([1.0, 0.0, 0.0]), ..spec(SloshModel::Pendulum, Some(1.0)) }, "must be perpendicular"),
            (SloshSpec { restoring: SloshRestoring::Stiffness(-1.0), ..spec(SloshModel::Pendulum, Some(1.0)) }, "stiffness must be finite and >= 0"),
            (SloshSpec { restoring: SloshRestoring::Frequency(f64::NAN), ..spec(SloshModel::Pendulum, Some(1.0)) }, "frequency must be finite"),
            (SloshSpec { parent: "tank".into(), ..spec(SloshModel::Pendulum, Some(1.0)) }, "parent body 'tank' is not defined"),
        ] {
            let e = b.add_slosh(s).map(|_| ()).unwrap_err();
            assert!(e.message.contains(needle), "{}", e.message);
        }
    }
}
