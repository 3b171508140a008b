//! Criterion benchmarks of the simulation core on the `spatial6` preset: one RK4 step (four
//! right-hand-side evaluations, each running the controller and the articulated-body algorithm)
//! with zero torque and with computed torque on the reduced EOM, and one DOPRI5 attempt.
//!
//! Run (short): `cargo bench -p spacearm-core --bench simulation -- --warm-up-time 1 --measurement-time 2`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use spacearm_core::control::{ComputedTorque, Controller, ZeroTorque};
use spacearm_core::sim::integrate::{Dopri5, OdeSystem, Rk4};
use spacearm_core::model::presets;
use spacearm_core::sim::reference::JointReference;
use spacearm_core::sim::simulate::{Plant, SimOptions};

fn state(n: usize) -> (Vec<f64>, Vec<f64>) {
    let model = presets::spatial6();
    let mut y = presets::initial_configuration(&model);
    y.extend_from_slice(&[0.05, -0.02, 0.01, 0.03, -0.04, 0.02]);
    y.extend((0..n).map(|i| 0.3 * (1.0 + i as f64).sin()));
    let dy = vec![0.0; y.len()];
    (y, dy)
}

fn bench_step(c: &mut Criterion, name: &str, controller: &mut dyn Controller) {
    let model = presets::spatial6();
    let opts = SimOptions::default();
    let mut plant = Plant::new(&model, &opts, controller).expect("valid setup");
    let (y0, _) = state(model.n_dof());
    let mut rk = Rk4::new(plant.dim());
    let mut y = y0.clone();
    c.bench_function(&format!("spatial6/rk4_step/{name}"), |b| {
        b.iter(|| {
            y.copy_from_slice(&y0);
            rk.step(&mut plant, black_box(0.5), black_box(1e-3), &mut y, false).unwrap();
            black_box(&y);
        })
    });
    let mut dp = Dopri5::new(plant.dim(), 1e-9, 1e-12);
    dp.initial_step(&mut plant, 0.5, &y0, 1.0).unwrap();
    c.bench_function(&format!("spatial6/dopri5_attempt/{name}"), |b| {
        b.iter(|| {
            y.copy_from_slice(&y0);
            black_box(dp.try_step(&mut plant, black_box(0.5), black_box(1e-3), &mut y).unwrap());
        })
    });
}

fn benches(c: &mut Criterion) {
    let model = presets::spatial6();
    let q0 = model.initial_q().to_vec();
    let q1: Vec<f64> = q0.iter().map(|q| q + 0.5).collect();
    bench_step(c, "zero_torque", &mut ZeroTorque);
    let mut ct = ComputedTorque::new(vec![25.0], vec![10.0], JointReference::quintic(q0, q1, 0.0, 2.0).unwrap(), None);
    bench_step(c, "computed_torque", &mut ct);
}

criterion_group!(simulation, benches);
criterion_main!(simulation);
