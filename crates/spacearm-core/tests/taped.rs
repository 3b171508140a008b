//! The recorded tapes of the equations of motion (spacearm_core::taped) against the `f64`
//! functions: each tape, recorded once at its nominal state, replayed on `f64` inputs at
//! random states equals the `f64` result to rounding — on presets and random trees with
//! branches, prismatic and fixed joints, at states on both sides of every branch the code has
//! (joints exactly at zero and not, attitudes of both signs, an unnormalized quaternion).

mod common;

use nalgebra::{DMatrix, Vector3};
use rand::Rng;
use spacearm_core::algorithms::{aba, crba, kinematics, momentum, rnea};
use spacearm_core::gjm;
use spacearm_core::math::rotations::quaternion_rate;
use spacearm_core::math::tape::Tape;
use spacearm_core::model::presets;
use spacearm_core::taped::{record, TapedFunction};
use spacearm_core::{Data, JointType, LinkSpec, Model, ModelBuilder};

fn assert_close(got: &[f64], want: &[f64], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: length");
    let scale = want.iter().fold(0.0_f64, |a, v| a.max(v.abs())).max(1e-300);
    let err = got.iter().zip(want).fold(0.0_f64, |a, (g, w)| a.max((g - w).abs()));
    assert!(err <= 1e-12 * scale, "{what}: max deviation {err:e} (scale {scale:e})");
    if std::env::var_os("TAPE_REPORT").is_some() {
        eprintln!("{what}: relative deviation {:.2e}", err / scale);
    }
}

fn col_major(m: &DMatrix<f64>) -> Vec<f64> {
    m.as_slice().to_vec()
}

struct Inputs {
    x: Vec<f64>,
    u: Vec<f64>,
    tau: Vec<f64>,
    wrench: Vec<f64>,
    du: Vec<f64>,
    p: Vec<f64>,
    l: Vec<f64>,
}

fn cat(parts: &[&[f64]]) -> Vec<f64> {
    parts.iter().flat_map(|p| p.iter().copied()).collect()
}

/// Every taped function at one state against its `f64` counterpart. `x_tape` is the
/// configuration given to the tape (its quaternion may be unnormalized), `s.x` the unit one.
fn check_all(model: &Model, tapes: &[(TapedFunction, Tape)], s: &Inputs, x_tape: &[f64], what: &str) {
    let mut d = Data::new(model);
    let n = model.n_dof();
    let body = model.n_bodies() - 1;
    let offset = Vector3::new(0.1, -0.2, 0.3);
    for (function, tape) in tapes {
        let name = format!("{what}: {}", function.name());
        let (got, want): (Vec<f64>, Vec<f64>) = match function {
            TapedFunction::ForwardDynamics => {
                let f = cat(&[&s.wrench, &s.tau]);
                (tape.eval(&cat(&[x_tape, &s.u, &s.tau, &s.wrench])), aba::aba(model, &mut d, &s.x, &s.u, &f, &[]).unwrap().as_slice().to_vec())
            }
            TapedFunction::StateDerivative => {
                let f = cat(&[&s.wrench, &s.tau]);
                let du = aba::aba(model, &mut d, &s.x, &s.u, &f, &[]).unwrap().as_slice().to_vec();
                // The quaternion rate of the quaternion as given (the simulator's stage value).
                let rate = quaternion_rate(&x_tape[3..7], &Vector3::new(s.u[3], s.u[4], s.u[5]));
                (tape.eval(&cat(&[x_tape, &s.u, &s.tau, &s.wrench])), cat(&[&s.u[0..3], &rate, &s.u[6..], &du]))
            }
            TapedFunction::InverseDynamics => {
                (tape.eval(&cat(&[x_tape, &s.u, &s.du])), rnea::rnea(model, &mut d, &s.x, &s.u, &s.du, &[]).unwrap().as_slice().to_vec())
            }
            TapedFunction::BiasForces => (tape.eval(&cat(&[x_tape, &s.u])), rnea::bias_forces(model, &mut d, &s.x, &s.u).unwrap().as_slice().to_vec()),
            TapedFunction::MassMatrix => (tape.eval(x_tape), col_major(crba::crba(model, &mut d, &s.x).unwrap())),
            TapedFunction::GeneralizedInertia => (tape.eval(x_tape), col_major(&gjm::generalized_inertia(model, &mut d, &s.x).unwrap())),
            TapedFunction::GeneralizedBias => {
                (tape.eval(&cat(&[x_tape, &s.u])), gjm::generalized_bias(model, &mut d, &s.x, &s.u).unwrap().as_slice().to_vec())
            }
            TapedFunction::GeneralizedJacobian { body, offset } => {
                (tape.eval(x_tape), col_major(&gjm::generalized_jacobian(model, &mut d, &s.x, *body, offset).unwrap()))
            }
            TapedFunction::PointPosition { body, offset } => {
                kinematics::forward_kinematics(model, &mut d, &s.x).unwrap();
                (tape.eval(x_tape), kinematics::point_position(&d, *body, offset).as_slice().to_vec())
            }
            TapedFunction::Momentum => {
                let m = momentum::momentum(model, &mut d, &s.x, &s.u).unwrap();
                (tape.eval(&cat(&[x_tape, &s.u])), cat(&[m.linear.as_slice(), m.angular_about_origin.as_slice()]))
            }
            TapedFunction::BaseVelocityFromMomentum => {
                let qd = &s.u[6..];
                let (p, l) = (Vector3::from_column_slice(&s.p), Vector3::from_column_slice(&s.l));
                let want = gjm::base_velocity_from_momentum(model, &mut d, &s.x, qd, &p, &l).unwrap();
                (tape.eval(&cat(&[x_tape, qd, &s.p, &s.l])), want.as_slice().to_vec())
            }
        };
        assert_close(&got, &want, &name);
        let shape: usize = function.outputs(model).iter().map(|(_, r, c)| r * c).sum();
        assert_eq!(got.len(), shape, "{name}: outputs");
        let inputs: usize = function.inputs(model).iter().map(|(_, k)| k).sum();
        assert_eq!(tape.n_inputs, inputs, "{name}: inputs");
        let _ = (n, body, offset);
    }
}

fn all_functions(model: &Model) -> Vec<(TapedFunction, Tape)> {
    let body = model.n_bodies() - 1;
    let offset = Vector3::new(0.1, -0.2, 0.3);
    TapedFunction::NAMES
        .iter()
        .map(|name| {
            let point = matches!(*name, "generalized_jacobian" | "point_position").then_some((body, offset));
            let f = TapedFunction::from_name(name, point).unwrap();
            let tape = record(model, &f).unwrap();
            (f, tape)
        })
        .collect()
}

fn check_model(model: &Model, seed: u64) {
    let tapes = all_functions(model);
    let mut r = common::rng(seed);
    let (n, nu) = (model.n_dof(), model.nu());
    for k in 0..6 {
        let (mut x, u) = common::random_state(&mut r, model);
        match k {
            // Every joint exactly at zero: the f64 path skips the joint rotations there.
            0 => x[7..].iter_mut().for_each(|q| *q = 0.0),
            // Half of them at zero, the attitude with a negative scalar part.
            1 => {
                for q in x[7..].iter_mut().step_by(2) {
                    *q = 0.0;
                }
                if x[6] > 0.0 {
                    x[3..7].iter_mut().for_each(|v| *v = -*v);
                }
            }
            // The identity attitude (the nominal state of the recordings).
            2 => {
                x[3..7].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
            }
            _ => {}
        }
        let s = Inputs {
            x: x.clone(),
            u,
            tau: common::random_vector(&mut r, n, 5.0),
            wrench: common::random_vector(&mut r, 6, 20.0),
            du: common::random_vector(&mut r, nu, 2.0),
            p: common::random_vector(&mut r, 3, 10.0),
            l: common::random_vector(&mut r, 3, 10.0),
        };
        check_all(model, &tapes, &s, &x, &format!("{} state {k}", model.name()));
        // The tape normalizes its quaternion: a scaled quaternion gives the same results.
        let mut scaled = x.clone();
        let factor = r.random_range(0.3..3.0);
        scaled[3..7].iter_mut().for_each(|v| *v *= factor);
        check_all(model, &tapes, &s, &scaled, &format!("{} state {k}, quaternion × {factor}", model.name()));
    }
}

#[test]
fn tapes_equal_the_f64_functions_on_the_presets() {
    check_model(&presets::planar4(), 1);
    check_model(&presets::spatial6(), 2);
}

#[test]
fn tapes_equal_the_f64_functions_on_random_trees() {
    let mut r = common::rng(17);
    for (k, links) in [3, 7, 12].into_iter().enumerate() {
        let model = common::random_model(&mut r, links);
        check_model(&model, 100 + k as u64);
    }
}

#[test]
fn tapes_are_linear_in_the_size_for_the_recursions() {
    // ABA: O(N) nodes. A 30-joint chain stays well within what a replay builds in a second.
    let chain = |n: usize| {
        let diag = |a: f64, b: f64, c: f64| [[a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]];
        let mut b = ModelBuilder::new("chain", "base", 500.0, diag(50.0, 60.0, 70.0)).unwrap();
        for i in 0..n {
            let axis = [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]][i % 3];
            let parent = if i == 0 { "base".to_string() } else { format!("l{}", i - 1) };
            b.add_link(LinkSpec::new(&format!("l{i}"), &parent, JointType::Revolute, [if i == 0 { 1.0 } else { 0.3 }, 0.0, 0.0], axis, [0.15, 0.0, 0.0], 2.0, [0.01, 0.02, 0.02])).unwrap();
        }
        b.build().unwrap()
    };
    let (t10, t30) = (record(&chain(10), &TapedFunction::ForwardDynamics).unwrap(), record(&chain(30), &TapedFunction::ForwardDynamics).unwrap());
    let ratio = t30.len() as f64 / t10.len() as f64;
    eprintln!("forward dynamics tape: {} nodes at N = 10, {} at N = 30", t10.len(), t30.len());
    assert!(ratio < 3.5, "forward dynamics tape: {} nodes at N = 10, {} at N = 30", t10.len(), t30.len());
}

#[test]
fn a_bad_point_or_name_is_an_error() {
    let m = presets::planar4();
    assert!(record(&m, &TapedFunction::PointPosition { body: 99, offset: Vector3::zeros() }).is_err());
    assert!(TapedFunction::from_name("nope", None).is_err());
    assert!(TapedFunction::from_name("point_position", None).is_err());
    assert!(TapedFunction::from_name("mass_matrix", Some((0, Vector3::zeros()))).is_err());
}
