//! Criterion benchmarks of the derivative functions on `spatial6` (6 DOF + free base) and
//! serial arms of 12, 30 and 60 DOF, at a non-trivial state: the forward-dynamics Jacobians by
//! the analytic route (the default) and by dual numbers, the analytic partials of inverse
//! dynamics alone, `linearize`, and the dual-number `∂H/∂x`, `Ḣ`, `∂H*/∂q`, `J̇*`.
//!
//! Run (short):
//! `cargo bench -p spacearm-core --bench derivatives -- --warm-up-time 1 --measurement-time 2`
//! (a filter such as `arm30/` selects one model).
//!
//! `benchmarks/derivatives.py` times the same functions from Python next to Pinocchio's
//! `computeABADerivatives`.

use std::hint::black_box;

use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion};
use spacearm_core::derivatives::{self, DerivativeData, DerivativeMethod, LinearizationInputs};
use spacearm_core::algorithms::aba;
use spacearm_core::model::presets;
use spacearm_core::Model;

/// A fixed, non-trivial state: base drifting and tumbling, every joint displaced and moving.
fn state(model: &Model) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = model.n_dof();
    let mut x = presets::initial_configuration(model);
    for (j, q) in x[7..].iter_mut().enumerate() {
        *q += 0.4 * (0.7 + j as f64).sin();
    }
    let mut u = vec![0.05, -0.02, 0.01, 0.03, -0.04, 0.02];
    u.extend((0..n).map(|i| 0.3 * (1.0 + i as f64).sin()));
    let mut f = vec![1.0, -2.0, 0.5, 0.3, -0.2, 0.1];
    f.extend((0..n).map(|i| 2.0 * (3.0 + i as f64).sin()));
    (x, u, f)
}

/// A serial `n`-DOF arm on a 500 kg base: alternating joint axes, 0.5 m links.
pub fn serial_arm(n: usize) -> Model {
    use spacearm_core::{JointLimits, JointType, LinkSpec, ModelBuilder};
    let mut b = ModelBuilder::new(&format!("arm{n}"), "base", 500.0, [[60.0, 0.0, 0.0], [0.0, 70.0, 0.0], [0.0, 0.0, 80.0]]).unwrap();
    let axes = [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]];
    let mut parent = "base".to_string();
    for k in 0..n {
        let name = format!("link{}", k + 1);
        b.add_link(LinkSpec {
            name: name.clone(),
            parent: parent.clone(),
            joint_name: None,
            kind: JointType::Revolute,
            origin_in_parent: if k == 0 { [1.0, 0.0, 0.5] } else { [0.25, 0.0, 0.0] },
            rotation_in_parent: [0.0, 0.0, 0.0, 1.0],
            axis: axes[k % 3],
            com_from_joint: [0.25, 0.0, 0.0],
            mass: 5.0,
            inertia: [[0.02, 0.0, 0.0], [0.0, 0.11, 0.0], [0.0, 0.0, 0.11]],
            limits: JointLimits::unlimited(),
        })
        .unwrap();
        parent = name;
    }
    b.add_point("tip", &parent, [0.25, 0.0, 0.0]).unwrap();
    b.set_end_effector("tip");
    b.build().unwrap()
}

/// One timed entry of group `g`: `call` at the state `(x, u, f)`, the inputs and the entry of
/// the result it returns passed through `black_box` (every entry is timed the same way).
fn time(g: &mut BenchmarkGroup<'_, WallTime>, name: &str, (x, u, f): &(Vec<f64>, Vec<f64>, Vec<f64>), mut call: impl FnMut(&[f64], &[f64], &[f64]) -> f64) {
    g.bench_function(name, |b| b.iter(|| black_box(call(black_box(x), black_box(u), black_box(f)))));
}

fn bench_model(c: &mut Criterion, name: &str, model: Model) {
    let mut work = DerivativeData::new(&model);
    let s = state(&model);
    let ee = model.points()[model.end_effector().expect("an end effector")].clone();
    let mut g = c.benchmark_group(name);
    time(&mut g, "forward_dynamics_aba", &s, |x, u, f| aba::aba(&model, &mut work.data, x, u, f, &[]).unwrap()[0]);
    time(&mut g, "forward_dynamics_derivatives", &s, |x, u, f| derivatives::forward_dynamics_derivatives(&model, &mut work, x, u, f).unwrap().0[(6, 6)]);
    time(&mut g, "forward_dynamics_derivatives_dual", &s, |x, u, f| {
        derivatives::forward_dynamics_derivatives_with(&model, &mut work, x, u, f, &[], DerivativeMethod::DualNumbers).unwrap().0[(6, 6)]
    });
    time(&mut g, "inverse_dynamics_partials", &s, |x, u, f| {
        derivatives::inverse_dynamics_partials(&model, &mut work, x, u, f, &[], DerivativeMethod::Analytic).unwrap().0[(6, 6)]
    });
    time(&mut g, "linearize", &s, |x, u, f| derivatives::linearize(&model, &mut work, x, u, f, LinearizationInputs::Joints).unwrap().0[(6, 6)]);
    if model.n_dof() > 12 {
        // The dual-number tensors below grow as N³: timed on the small models only.
        g.finish();
        return;
    }
    time(&mut g, "mass_matrix_partials", &s, |x, _, _| derivatives::mass_matrix_partials(&model, &mut work, x).unwrap()[6][(0, 0)]);
    time(&mut g, "mass_matrix_derivative", &s, |x, u, _| derivatives::mass_matrix_derivative(&model, &mut work, x, u).unwrap()[(0, 0)]);
    time(&mut g, "generalized_inertia_partials", &s, |x, _, _| derivatives::generalized_inertia_partials(&model, &mut work, x).unwrap()[0][(0, 0)]);
    time(&mut g, "generalized_jacobian_derivative", &s, |x, u, _| {
        derivatives::generalized_jacobian_derivative(&model, &mut work, x, u, ee.body, &ee.offset).unwrap()[(0, 0)]
    });
    g.finish();
}

fn benches(c: &mut Criterion) {
    bench_model(c, "spatial6", presets::spatial6());
    for n in [12, 30, 60] {
        bench_model(c, &format!("arm{n}"), serial_arm(n));
    }
}

criterion_group!(derivative_benches, benches);
criterion_main!(derivative_benches);
