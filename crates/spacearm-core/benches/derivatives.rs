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

use criterion::{criterion_group, criterion_main, Criterion};
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

fn bench_model(c: &mut Criterion, name: &str, model: Model) {
    let mut work = DerivativeData::new(&model);
    let (x, u, f) = state(&model);
    let ee = model.points()[model.end_effector().expect("an end effector")].clone();
    let mut g = c.benchmark_group(name);
    g.bench_function("forward_dynamics_aba", |b| {
        b.iter(|| black_box(aba::aba(&model, &mut work.data, black_box(&x), black_box(&u), black_box(&f), &[]).unwrap()[0]))
    });
    g.bench_function("forward_dynamics_derivatives", |b| {
        b.iter(|| black_box(derivatives::forward_dynamics_derivatives(&model, &mut work, black_box(&x), black_box(&u), black_box(&f)).unwrap().0[(6, 6)]))
    });
    g.bench_function("forward_dynamics_derivatives_dual", |b| {
        b.iter(|| {
            black_box(
                derivatives::forward_dynamics_derivatives_with(&model, &mut work, black_box(&x), black_box(&u), black_box(&f), &[], DerivativeMethod::DualNumbers)
                    .unwrap()
                    .0[(6, 6)],
            )
        })
    });
    g.bench_function("inverse_dynamics_partials", |b| {
        b.iter(|| {
            black_box(
                derivatives::inverse_dynamics_partials(&model, &mut work, black_box(&x), black_box(&u), black_box(&f), &[], DerivativeMethod::Analytic)
                    .unwrap()
                    .0[(6, 6)],
            )
        })
    });
    g.bench_function("linearize", |b| {
        b.iter(|| {
            black_box(derivatives::linearize(&model, &mut work, black_box(&x), black_box(&u), black_box(&f), LinearizationInputs::Joints).unwrap().0[(6, 6)])
        })
    });
    if model.n_dof() > 12 {
        // The dual-number tensors below grow as N³: timed on the small models only.
        g.finish();
        return;
    }
    g.bench_function("mass_matrix_partials", |b| {
        b.iter(|| black_box(derivatives::mass_matrix_partials(&model, &mut work, black_box(&x)).unwrap()[6][(0, 0)]))
    });
    g.bench_function("mass_matrix_derivative", |b| {
        b.iter(|| black_box(derivatives::mass_matrix_derivative(&model, &mut work, black_box(&x), black_box(&u)).unwrap()[(0, 0)]))
    });
    g.bench_function("generalized_inertia_partials", |b| {
        b.iter(|| black_box(derivatives::generalized_inertia_partials(&model, &mut work, black_box(&x)).unwrap()[0][(0, 0)]))
    });
    g.bench_function("generalized_jacobian_derivative", |b| {
        b.iter(|| {
            black_box(derivatives::generalized_jacobian_derivative(&model, &mut work, black_box(&x), black_box(&u), ee.body, &ee.offset).unwrap()[(0, 0)])
        })
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
