//! The dual-number derivatives of `spacearm_core::derivatives` against central finite
//! differences of the `f64` algorithms (tangent perturbation of the attitude by the exponential
//! map), and against each other (`Ḣ = Σ ∂H/∂x_k u_k`), on random trees with prismatic, fixed
//! and revolute joints and branches.

mod common;

use nalgebra::{DMatrix, Vector3};
use spacearm_core::derivatives::{self, DerivativeData, LinearizationInputs};
use spacearm_core::algorithms::{aba, crba};
use spacearm_core::gjm;
use spacearm_core::{Data, Model};

/// Central difference of a matrix function of the configuration along tangent coordinate `k`.
fn central<F: FnMut(&[f64]) -> DMatrix<f64>>(mut f: F, x: &[f64], k: usize, h: f64) -> DMatrix<f64> {
    (f(&common::perturb(x, k, h)) - f(&common::perturb(x, k, -h))) / (2.0 * h)
}

/// `‖a − b‖ / ‖b‖`, asserting the reference is not trivially small.
fn rel_err(a: &DMatrix<f64>, b: &DMatrix<f64>, what: &str) -> f64 {
    let nb = b.norm();
    assert!(nb > 1e-3, "{what}: reference norm {nb} is too small for a meaningful comparison");
    (a - b).norm() / nb
}

const H: f64 = 1e-6;
const RTOL: f64 = 1e-6;

fn models() -> Vec<(Model, Vec<f64>, Vec<f64>)> {
    let mut out = Vec::new();
    for (seed, n_links) in [(1u64, 3usize), (2, 6), (3, 9), (4, 12), (5, 14)] {
        let mut r = common::rng(seed);
        let model = common::random_model(&mut r, n_links);
        let (x, u) = common::random_state(&mut r, &model);
        out.push((model, x, u));
    }
    out.push((spacearm_core::model::presets::spatial6(), spacearm_core::model::presets::initial_configuration(&spacearm_core::model::presets::spatial6()), {
        let mut u = vec![0.05, -0.02, 0.01, 0.03, -0.04, 0.02];
        u.extend((0..6).map(|i| 0.3 * (1.0 + i as f64).sin()));
        u
    }));
    out
}

#[test]
fn mass_matrix_partials_match_finite_differences() {
    let mut worst = 0.0_f64;
    for (model, x, u) in models() {
        let mut work = DerivativeData::new(&model);
        let mut data = Data::new(&model);
        let partials = derivatives::mass_matrix_partials(&model, &mut work, &x).unwrap().to_vec();
        let nu = model.nu();
        let mut all_fd = DMatrix::zeros(nu * nu, nu);
        let mut all_ad = DMatrix::zeros(nu * nu, nu);
        for k in 0..nu {
            let fd = central(|y| crba::crba(&model, &mut data, y).unwrap().clone(), &x, k, H);
            if k < 3 {
                // Translation invariance: the δr0 partials are zero (to rounding of the FD).
                assert!(partials[k].norm() == 0.0);
                assert!(fd.norm() < 1e-6 * partials[6].norm().max(1.0), "dH/dr0 = {}", fd.norm());
            }
            all_fd.column_mut(k).copy_from_slice(fd.as_slice());
            all_ad.column_mut(k).copy_from_slice(partials[k].as_slice());
        }
        let e = rel_err(&all_ad, &all_fd, "dH/dx");
        worst = worst.max(e);
        assert!(e < RTOL, "dH/dx relative error {e}");
        // Ḣ is the directional derivative along u: Σ_k ∂H/∂x_k u_k.
        let hdot = derivatives::mass_matrix_derivative(&model, &mut work, &x, &u).unwrap().clone();
        let mut sum = DMatrix::zeros(nu, nu);
        for k in 0..nu {
            sum += &partials[k] * u[k];
        }
        let e2 = rel_err(&hdot, &sum, "Hdot");
        assert!(e2 < 1e-12, "Hdot vs sum of partials: {e2}");
    }
    println!("worst dH/dx relative error vs central differences: {worst:e}");
}

/// Stack matrices as the columns of one matrix (each flattened), to compare whole tensors.
fn stack(ms: &[DMatrix<f64>]) -> DMatrix<f64> {
    let len = ms[0].len();
    let mut out = DMatrix::zeros(len, ms.len());
    for (k, m) in ms.iter().enumerate() {
        out.column_mut(k).copy_from_slice(m.as_slice());
    }
    out
}

#[test]
fn generalized_inertia_partials_match_finite_differences() {
    for (model, x, u) in models() {
        let mut work = DerivativeData::new(&model);
        let mut data = Data::new(&model);
        let n = model.n_dof();
        let partials = derivatives::generalized_inertia_partials(&model, &mut work, &x).unwrap().to_vec();
        let mut fds = Vec::new();
        let mut sum = DMatrix::zeros(n, n);
        for k in 0..6 + n {
            let fd = central(|y| gjm::generalized_inertia(&model, &mut data, y).unwrap(), &x, k, H);
            if k < 6 {
                // H* is invariant under rigid motions of the whole system.
                let scale = stack(&partials).norm();
                assert!(fd.norm() < 1e-6 * scale, "dH*/dx_{k} = {} should vanish", fd.norm());
                continue;
            }
            sum += &partials[k - 6] * u[k];
            fds.push(fd);
        }
        let e = rel_err(&stack(&partials), &stack(&fds), "dH*/dq");
        assert!(e < RTOL, "dH*/dq relative error {e}");
        let hdot = derivatives::generalized_inertia_derivative(&model, &mut work, &x, &u).unwrap().clone();
        assert!(rel_err(&hdot, &sum, "H*dot") < 1e-12);
    }
}

#[test]
fn generalized_jacobian_partials_match_finite_differences() {
    for (model, x, u) in models() {
        let mut work = DerivativeData::new(&model);
        let mut data = Data::new(&model);
        let p = &model.points()[model.end_effector().unwrap()];
        let (body, offset) = (p.body, p.offset);
        let n = model.n_dof();
        let partials = derivatives::generalized_jacobian_partials(&model, &mut work, &x, body, &offset).unwrap().to_vec();
        let mut fds = Vec::new();
        let mut sum = DMatrix::zeros(6, n);
        for k in 0..6 + n {
            let fd = central(|y| gjm::generalized_jacobian(&model, &mut data, y, body, &offset).unwrap(), &x, k, H);
            if k < 3 {
                assert!(partials[k].norm() == 0.0 && fd.norm() < 1e-6, "dJ*/dr0 = {}", fd.norm());
            }
            sum += &partials[k] * u[k];
            fds.push(fd);
        }
        let e = rel_err(&stack(&partials), &stack(&fds), "dJ*/dx");
        assert!(e < RTOL, "dJ*/dx relative error {e}");
        let jdot = derivatives::generalized_jacobian_derivative(&model, &mut work, &x, &u, body, &offset).unwrap().clone();
        assert!(rel_err(&jdot, &sum, "J*dot") < 1e-12);
    }
}

#[test]
fn forward_dynamics_derivatives_match_finite_differences() {
    for (seed, (model, x, u)) in models().into_iter().enumerate() {
        let mut work = DerivativeData::new(&model);
        let mut data = Data::new(&model);
        let nu = model.nu();
        let mut r = common::rng(100 + seed as u64);
        let f = common::random_vector(&mut r, nu, 3.0);
        let (dx, du, df) = derivatives::forward_dynamics_derivatives(&model, &mut work, &x, &u, &f).unwrap();
        let (dx, du, df) = (dx.clone(), du.clone(), df.clone());
        let mut fd_x = DMatrix::zeros(nu, nu);
        let mut fd_u = DMatrix::zeros(nu, nu);
        let mut fd_f = DMatrix::zeros(nu, nu);
        for k in 0..nu {
            let col = central(|y| DMatrix::from_column_slice(nu, 1, aba::aba(&model, &mut data, y, &u, &f, &[]).unwrap().as_slice()), &x, k, H);
            fd_x.column_mut(k).copy_from(&col.column(0));
            fd_u.column_mut(k).copy_from(&common::central_flat(|w| aba::aba(&model, &mut data, &x, w, &f, &[]).unwrap().clone(), &u, k, H));
            fd_f.column_mut(k).copy_from(&common::central_flat(|w| aba::aba(&model, &mut data, &x, &u, w, &[]).unwrap().clone(), &f, k, H));
        }
        for (what, ad, fd) in [("du/dx", &dx, &fd_x), ("du/du", &du, &fd_u), ("du/df", &df, &fd_f)] {
            let e = rel_err(ad, fd, what);
            assert!(e < RTOL, "{what} relative error {e}");
        }
        assert!(dx.columns(0, 3).norm() == 0.0 && fd_x.columns(0, 3).norm() < 1e-6 * fd_x.norm());
        // H⁻¹ is the inverse of CRBA's H.
        let h = crba::crba(&model, &mut data, &x).unwrap().clone();
        assert!((&h * &df - DMatrix::identity(nu, nu)).norm() < 1e-9);
        // A and B assemble the same blocks.
        let (a, b) = derivatives::linearize(&model, &mut work, &x, &u, &f, LinearizationInputs::Joints).unwrap();
        assert_eq!(a.shape(), (2 * nu, 2 * nu));
        assert_eq!(b.shape(), (2 * nu, nu - 6));
        assert!((a.view((nu, 0), (nu, nu)) - &dx).norm() == 0.0);
        assert!((b.view((nu, 0), (nu, nu - 6)) - df.columns(6, nu - 6)).norm() == 0.0);
    }
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let model = spacearm_core::model::presets::planar4();
    let mut work = DerivativeData::new(&model);
    let x = spacearm_core::model::presets::initial_configuration(&model);
    assert!(derivatives::mass_matrix_partials(&model, &mut work, &x[1..]).is_err());
    let mut bad = x.clone();
    bad[3] = 2.0;
    assert!(derivatives::mass_matrix_partials(&model, &mut work, &bad).is_err());
    let u = vec![0.0; model.nu()];
    assert!(derivatives::mass_matrix_derivative(&model, &mut work, &x, &u[1..]).is_err());
    let mut nan = u.clone();
    nan[2] = f64::NAN;
    assert!(derivatives::forward_dynamics_derivatives(&model, &mut work, &x, &u, &nan).is_err());
    assert!(derivatives::generalized_jacobian_partials(&model, &mut work, &x, 99, &Vector3::zeros()).is_err());
}
