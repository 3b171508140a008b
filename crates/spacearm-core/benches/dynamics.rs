//! Criterion benchmarks of the core algorithms on the `spatial6` preset (6 DOF + free base) at
//! its initial configuration with a non-trivial velocity (and on `planar4`).
//!
//! Run (short):
//! `cargo bench -p spacearm-core --bench dynamics -- --warm-up-time 1 --measurement-time 2`
//! Filter with a substring, e.g. `... -- spatial6/ --warm-up-time 1 --measurement-time 2`.
//!
//! Every entry point here is the public core function a user calls: each one runs forward
//! kinematics from the configuration `x` and validates its inputs, exactly as in Python. The
//! functions returning owned matrices include that copy; `*_in_data` are the allocation-free
//! `compute_*` variants that leave the result in `Data` (what the Python bindings call).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Vector3, Vector6};
use spacearm_core::algorithms::{aba, crba, dynamics, inertia, kinematics, rnea};
use spacearm_core::gjm;
use spacearm_core::model::presets;
use spacearm_core::{Data, Model};

/// A fixed, non-trivial state: base drifting and tumbling, every joint moving.
fn state(model: &Model) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = model.n_dof();
    let x = presets::initial_configuration(model);
    let mut u = vec![0.05, -0.02, 0.01, 0.03, -0.04, 0.02];
    u.extend((0..n).map(|i| 0.3 * (1.0 + i as f64).sin()));
    let mut du = vec![0.01, 0.02, -0.01, 0.005, -0.01, 0.02];
    du.extend((0..n).map(|i| 0.5 * (2.0 + i as f64).cos()));
    let mut f = vec![1.0, -2.0, 0.5, 0.3, -0.2, 0.1];
    f.extend((0..n).map(|i| 2.0 * (3.0 + i as f64).sin()));
    (x, u, du, f)
}

fn bench_model(c: &mut Criterion, name: &str, model: Model) {
    let mut data = Data::new(&model);
    let (x, u, du, f) = state(&model);
    let n = model.n_dof();
    let ee = model.end_effector().map(|i| model.points()[i].clone()).expect("preset has an end effector");
    let (ee_body, ee_offset): (usize, Vector3<f64>) = (ee.body, ee.offset);
    let base_wrench = Vector6::from_column_slice(&f[0..6]);
    let tau = f[6..6 + n].to_vec();
    let mut g = c.benchmark_group(name);

    g.bench_function("forward_kinematics", |b| {
        b.iter(|| kinematics::forward_kinematics(&model, &mut data, black_box(&x)).unwrap())
    });
    g.bench_function("H_crba", |b| b.iter(|| black_box(crba::crba(&model, &mut data, black_box(&x)).unwrap()[(0, 0)])));
    g.bench_function("H_paper_form", |b| {
        b.iter(|| black_box(inertia::inertia_blocks(&model, &mut data, black_box(&x)).unwrap().mass_matrix()))
    });
    g.bench_function("c_rnea", |b| {
        b.iter(|| black_box(rnea::bias_forces(&model, &mut data, black_box(&x), black_box(&u)).unwrap()[0]))
    });
    g.bench_function("inverse_dynamics_rnea", |b| {
        b.iter(|| black_box(rnea::rnea(&model, &mut data, black_box(&x), black_box(&u), black_box(&du), &[]).unwrap()[0]))
    });
    g.bench_function("forward_dynamics_aba", |b| {
        b.iter(|| black_box(aba::aba(&model, &mut data, black_box(&x), black_box(&u), black_box(&f), &[]).unwrap()[0]))
    });
    g.bench_function("forward_dynamics_mass_matrix", |b| {
        b.iter(|| {
            black_box(dynamics::forward_dynamics_via_mass_matrix(&model, &mut data, black_box(&x), black_box(&u), black_box(&f), &[]).unwrap())
        })
    });
    g.bench_function("forward_dynamics_reduced", |b| {
        b.iter(|| {
            black_box(gjm::reduced_forward_dynamics(&model, &mut data, black_box(&x), black_box(&u), black_box(&tau), &base_wrench).unwrap())
        })
    });
    g.bench_function("J_star", |b| {
        b.iter(|| black_box(gjm::generalized_jacobian(&model, &mut data, black_box(&x), ee_body, &ee_offset).unwrap()))
    });
    g.bench_function("J_star_in_data", |b| {
        b.iter(|| black_box(gjm::compute_generalized_jacobian(&model, &mut data, black_box(&x), ee_body, &ee_offset).unwrap()[(0, 0)]))
    });
    g.bench_function("H_star", |b| b.iter(|| black_box(gjm::generalized_inertia(&model, &mut data, black_box(&x)).unwrap())));
    g.bench_function("H_star_in_data", |b| {
        b.iter(|| black_box(gjm::compute_generalized_inertia(&model, &mut data, black_box(&x)).unwrap()[(0, 0)]))
    });
    g.bench_function("c_star", |b| {
        b.iter(|| black_box(gjm::generalized_bias(&model, &mut data, black_box(&x), black_box(&u)).unwrap()))
    });
    g.finish();
}

fn benches(c: &mut Criterion) {
    bench_model(c, "spatial6", presets::spatial6());
    bench_model(c, "planar4", presets::planar4());
}

criterion_group!(dynamics_benches, benches);
criterion_main!(dynamics_benches);
