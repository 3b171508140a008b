//! The analytic partials of inverse dynamics (Carpentier & Mansard, carried into spacearm's
//! conventions: `derivatives::rnea_partials`) against the independent dual-number route and
//! against central finite differences of RNEA, on random trees with branches, prismatic and
//! fixed joints, with and without external wrenches; and the forward-dynamics Jacobians built
//! on them against the dual-number ones.

mod common;

use nalgebra::{DMatrix, DVector, Vector3};
use rand::Rng;
use spacearm_core::algorithms::rnea;
use spacearm_core::algorithms::wrench::ExternalWrench;
use spacearm_core::derivatives::{self, DerivativeData, DerivativeMethod, LinearizationInputs};
use spacearm_core::{Data, Model};

fn random_wrenches(r: &mut rand_chacha::ChaCha8Rng, model: &Model, count: usize) -> Vec<ExternalWrench> {
    (0..count)
        .map(|_| ExternalWrench {
            body: r.random_range(0..model.n_bodies()),
            offset: Vector3::from_fn(|_, _| r.random_range(-0.5..0.5)),
            force: Vector3::from_fn(|_, _| r.random_range(-20.0..20.0)),
            torque: Vector3::from_fn(|_, _| r.random_range(-5.0..5.0)),
        })
        .collect()
}

/// Largest entry of `|a − b|` over the largest entry of `|b|`, asserting `b` is not trivial.
fn rel_max(a: &DMatrix<f64>, b: &DMatrix<f64>, what: &str) -> f64 {
    let scale = b.amax();
    assert!(scale > 1e-3, "{what}: reference {scale} is too small for a meaningful comparison");
    (a - b).amax() / scale
}

struct Case {
    model: Model,
    x: Vec<f64>,
    u: Vec<f64>,
    du: Vec<f64>,
    external: Vec<ExternalWrench>,
}

fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    for trial in 0..24u64 {
        let mut r = common::rng(700 + trial);
        let n_links = 1 + (trial as usize * 5) % 17;
        let model = common::random_model(&mut r, n_links);
        let (x, u) = common::random_state(&mut r, &model);
        let du = common::random_vector(&mut r, model.nu(), 2.0);
        let external = if trial % 2 == 0 { Vec::new() } else { random_wrenches(&mut r, &model, 1 + trial as usize % 3) };
        out.push(Case { model, x, u, du, external });
    }
    out
}

#[test]
fn analytic_inverse_dynamics_partials_equal_dual_numbers() {
    let mut worst = 0.0_f64;
    let mut with_wrenches = 0;
    for c in cases() {
        let mut work = DerivativeData::new(&c.model);
        let (ax, au) = derivatives::inverse_dynamics_partials(&c.model, &mut work, &c.x, &c.u, &c.du, &c.external, DerivativeMethod::Analytic).unwrap();
        let (ax, au) = (ax.clone(), au.clone());
        let (dx, du) = derivatives::inverse_dynamics_partials(&c.model, &mut work, &c.x, &c.u, &c.du, &c.external, DerivativeMethod::DualNumbers).unwrap();
        let ex = rel_max(&ax, dx, "dID/dx");
        let eu = rel_max(&au, du, "dID/du");
        assert!(ex < 1e-10 && eu < 1e-10, "N = {}: dID/dx {ex:e}, dID/du {eu:e}", c.model.n_dof());
        assert!(ax.columns(0, 3).amax() == 0.0);
        worst = worst.max(ex).max(eu);
        with_wrenches += !c.external.is_empty() as usize;
    }
    assert!(with_wrenches >= 10);
    println!("worst analytic vs dual (max-entry relative): {worst:e}");
}

/// Second, independent check: central differences of the `f64` RNEA (attitude by the
/// exponential map), external wrenches included.
#[test]
fn analytic_inverse_dynamics_partials_match_finite_differences() {
    const H: f64 = 1e-6;
    let mut worst = 0.0_f64;
    for c in cases().into_iter().take(12) {
        let (model, nu) = (&c.model, c.model.nu());
        let mut work = DerivativeData::new(model);
        let mut data = Data::new(model);
        // Finite differences with the base near the origin (see docs/derivatives.md, Accuracy).
        let mut x = c.x.clone();
        x[..3].fill(0.1);
        let (ax, au) = derivatives::inverse_dynamics_partials(model, &mut work, &x, &c.u, &c.du, &c.external, DerivativeMethod::Analytic).unwrap();
        let mut id = |x: &[f64], u: &[f64]| -> DVector<f64> { rnea::rnea(model, &mut data, x, u, &c.du, &c.external).unwrap().clone() };
        let mut fx = DMatrix::zeros(nu, nu);
        let mut fu = DMatrix::zeros(nu, nu);
        for k in 0..nu {
            fx.set_column(k, &((id(&common::perturb(&x, k, H), &c.u) - id(&common::perturb(&x, k, -H), &c.u)) / (2.0 * H)));
            let (mut up, mut um) = (c.u.clone(), c.u.clone());
            up[k] += H;
            um[k] -= H;
            fu.set_column(k, &((id(&x, &up) - id(&x, &um)) / (2.0 * H)));
        }
        let e = rel_max(ax, &fx, "dID/dx").max(rel_max(au, &fu, "dID/du"));
        assert!(e < 1e-6, "N = {}: {e:e}", model.n_dof());
        worst = worst.max(e);
    }
    println!("worst analytic vs central differences: {worst:e}");
}

#[test]
fn analytic_forward_dynamics_derivatives_equal_dual_numbers() {
    for c in cases() {
        let (model, nu) = (&c.model, c.model.nu());
        let mut work = DerivativeData::new(model);
        let mut r = common::rng(model.n_dof() as u64);
        let f = common::random_vector(&mut r, nu, 5.0);
        let (x_a, u_a, f_a) = derivatives::forward_dynamics_derivatives_with(model, &mut work, &c.x, &c.u, &f, &c.external, DerivativeMethod::Analytic).unwrap();
        let (x_a, u_a, f_a) = (x_a.clone(), u_a.clone(), f_a.clone());
        let (x_d, u_d, f_d) = derivatives::forward_dynamics_derivatives_with(model, &mut work, &c.x, &c.u, &f, &c.external, DerivativeMethod::DualNumbers).unwrap();
        for (what, a, d) in [("du/dx", &x_a, x_d), ("du/du", &u_a, u_d), ("du/df", &f_a, f_d)] {
            let e = rel_max(a, d, what);
            assert!(e < 1e-10, "N = {}: {what} {e:e}", model.n_dof());
        }
        // The default entry points are the analytic route.
        let (x_p, _, _) = derivatives::forward_dynamics_derivatives(model, &mut work, &c.x, &c.u, &f).unwrap();
        let x_p = x_p.clone();
        let (x_n, _, _) = derivatives::forward_dynamics_derivatives_with(model, &mut work, &c.x, &c.u, &f, &[], DerivativeMethod::Analytic).unwrap();
        assert_eq!(&x_p, x_n);
        let (a, _) = derivatives::linearize(model, &mut work, &c.x, &c.u, &f, LinearizationInputs::All).unwrap();
        let a = a.clone();
        let (a_d, _) = derivatives::linearize_with(model, &mut work, &c.x, &c.u, &f, LinearizationInputs::All, DerivativeMethod::DualNumbers).unwrap();
        assert!(rel_max(&a, a_d, "A") < 1e-10);
    }
}

#[test]
fn bad_wrench_is_an_error() {
    let model = spacearm_core::model::presets::spatial6();
    let mut work = DerivativeData::new(&model);
    let x = spacearm_core::model::presets::initial_configuration(&model);
    let u = vec![0.0; model.nu()];
    let w = ExternalWrench { body: 99, offset: Vector3::zeros(), force: Vector3::zeros(), torque: Vector3::zeros() };
    assert!(derivatives::inverse_dynamics_partials(&model, &mut work, &x, &u, &u, &[w], DerivativeMethod::Analytic).is_err());
    assert!(derivatives::forward_dynamics_derivatives_with(&model, &mut work, &x, &u, &u, &[w], DerivativeMethod::Analytic).is_err());
    assert!(derivatives::inverse_dynamics_partials(&model, &mut work, &x, &u, &u[1..], &[], DerivativeMethod::Analytic).is_err());
}
