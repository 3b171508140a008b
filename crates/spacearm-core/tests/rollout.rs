//! Rollouts on threads against one `simulate` call per rollout: bit-identical records whatever
//! the thread count, per-rollout plants and controllers, and a failed rollout reported in its
//! slot while the others run on. Also the step-by-step RK4 stepper against `simulate`.

mod common;

use spacearm_core::control::mismatch::{perturbed_model, Slosh};
use spacearm_core::control::{Command, ComputedTorque, Controller, JointPd};
use spacearm_core::model::presets;
use spacearm_core::sim::reference::JointReference;
use spacearm_core::sim::rollout::{rollout, RolloutSpec};
use spacearm_core::sim::simulate::{simulate, Plant, SimOptions, SimResult};
use spacearm_core::sim::stepper::Rk4Stepper;
use spacearm_core::{Model, SpacearmError};

fn initial_state(model: &Model, k: usize) -> (Vec<f64>, Vec<f64>) {
    let x = presets::initial_configuration(model);
    let mut u = vec![0.01 * k as f64, -0.02, 0.01, 0.1, -0.05 * k as f64, 0.02];
    u.extend((0..model.n_dof()).map(|i| 0.3 * ((1 + i + k) as f64).sin()));
    (x, u)
}

fn pd(model: &Model, k: usize) -> Box<dyn Controller> {
    let n = model.n_dof();
    let goal: Vec<f64> = (0..n).map(|i| 0.2 + 0.05 * (i + k) as f64).collect();
    Box::new(JointPd::new(vec![40.0], vec![12.0], JointReference::quintic(vec![0.0; n], goal, 0.0, 0.3).unwrap()))
}

fn plants(nominal: &Model, b: usize) -> Vec<Model> {
    (0..b).map(|k| perturbed_model(nominal, 1.0 + 0.03 * k as f64, 1.0 - 0.02 * k as f64, 1.0 + 0.01 * k as f64, Slosh::None).unwrap()).collect()
}

fn assert_same(a: &SimResult, b: &SimResult) {
    // Bit-identical: exact equality of every record and counter.
    assert_eq!(a.records, b.records);
    assert_eq!(a.n_steps, b.n_steps);
    assert_eq!(a.n_rhs_evals, b.n_rhs_evals);
    assert_eq!(a.drift, b.drift);
    assert_eq!(a.events, b.events);
}

#[test]
fn rollouts_equal_simulate_whatever_the_thread_count() {
    let nominal = presets::spatial6();
    let b = 6;
    let models = plants(&nominal, b);
    let states: Vec<_> = (0..b).map(|k| initial_state(&nominal, k)).collect();
    let opts = SimOptions { duration: 0.3, dt: 1e-3, record_every: 3, ..SimOptions::default() };
    let reference: Vec<SimResult> = (0..b)
        .map(|k| {
            let mut c = pd(&nominal, k);
            simulate(&models[k], &states[k].0, &states[k].1, &opts, c.as_mut(), &mut |_| Ok(())).unwrap()
        })
        .collect();
    // The rollouts differ from each other (so equality below is not that of identical runs).
    assert_ne!(reference[0].records.x, reference[1].records.x);
    for threads in [Some(1), Some(2), Some(5), None] {
        let specs = (0..b).map(|k| RolloutSpec { model: &models[k], x0: &states[k].0, u0: &states[k].1, controller: pd(&nominal, k) }).collect();
        let results = rollout(specs, &opts, threads).unwrap();
        assert_eq!(results.len(), b);
        for (r, expected) in results.iter().zip(&reference) {
            assert_same(r.as_ref().unwrap(), expected);
        }
    }
}

#[test]
fn a_failed_rollout_is_reported_and_the_others_run_on() {
    let model = presets::spatial6();
    let (x0, u0) = initial_state(&model, 0);
    let opts = SimOptions { duration: 0.2, dt: 1e-3, ..SimOptions::default() };
    let make = |k: usize| -> Box<dyn Controller> {
        if k == 1 {
            // Joint torques that are NaN from t = 0.1 s on.
            Box::new(common::Scripted {
                name: "nan_after",
                command: |t, out: &mut Command| {
                    if t >= 0.1 {
                        out.tau.fill(f64::NAN);
                    }
                },
            })
        } else {
            Box::new(ComputedTorque::new(vec![10.0], vec![5.0], JointReference::constant(vec![0.1; 6]).unwrap(), None))
        }
    };
    let specs = (0..3).map(|k| RolloutSpec { model: &model, x0: &x0, u0: &u0, controller: make(k) }).collect();
    let results = rollout(specs, &opts, Some(2)).unwrap();
    assert!(results[0].is_ok() && results[2].is_ok());
    match &results[1] {
        Err(SpacearmError::Simulation(msg)) => assert!(msg.contains("non-finite") && msg.contains("t = 0.1"), "{msg}"),
        other => panic!("expected a simulation error, got {:?}", other.as_ref().map(|r| r.n_steps)),
    }
    // A bad option is the whole call's error.
    let specs = vec![RolloutSpec { model: &model, x0: &x0, u0: &u0, controller: make(0) }];
    assert!(rollout(specs, &SimOptions { dt: -1.0, ..opts.clone() }, None).is_err());
    let specs = vec![RolloutSpec { model: &model, x0: &x0, u0: &u0, controller: make(0) }];
    assert!(rollout(specs, &opts, Some(0)).is_err());
}

#[test]
fn stepping_equals_simulate() {
    let model = presets::spatial6();
    let (x0, u0) = initial_state(&model, 2);
    // 0.25 = 250 · 1e-3 exactly in floating point, so the last step of `simulate` (which lands
    // on the duration) is the stepper's step to 250 · dt.
    let (dt, n) = (1e-3, 250usize);
    assert_eq!(n as f64 * dt, 0.25);
    let opts = SimOptions { duration: 0.25, dt, record_every: 7, ..SimOptions::default() };
    let mut c = pd(&model, 1);
    let expected = simulate(&model, &x0, &u0, &opts, c.as_mut(), &mut |_| Ok(())).unwrap();
    let plant = Plant::owned(model.clone(), &opts, pd(&model, 1)).unwrap();
    let mut stepper = Rk4Stepper::new(plant, &x0, &u0, Some((10, 7))).unwrap();
    for i in 0..n {
        stepper.step_to((i + 1) as f64 * dt).unwrap();
        if i == 100 {
            // A snapshot in the middle does not disturb the run.
            let mid = stepper.snapshot().unwrap();
            assert_eq!(mid.records.n_samples, 100 / 7 + 1 + 1);
        }
    }
    assert_same(&stepper.finish().unwrap(), &expected);
}
