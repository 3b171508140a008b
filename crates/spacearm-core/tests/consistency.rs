//! The core's independent computations held together on random trees: paper form vs CRBA,
//! ABA vs CRBA+RNEA, reduced dynamics vs ABA, Schur inverse vs LU, momentum and energy vs H,
//! and J* vs finite differences of the motion momentum conservation dictates.

mod common;

use approx::assert_relative_eq;
use nalgebra::{DMatrix, DVector, Vector3, Vector6};
use spacearm_core::algorithms::{aba, crba, dynamics, inertia, kinematics, momentum, rnea};
use spacearm_core::*;

fn rel_err(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).abs().max() / b.abs().max().max(1e-300)
}

/// `Model::path_dofs` (counted from the tree at build time) against the Jacobians: the
/// non-zero columns of a body's `[J_Ti; J_Ri]` at a random configuration are the joints on its
/// path (paper eqs. 20–21), on random trees with branches and fixed joints.
#[test]
fn path_dofs_are_the_jacobians_nonzero_columns() {
    let mut r = common::rng(11);
    let mut fixed_seen = false;
    for trial in 0..20 {
        let model = common::random_model(&mut r, 2 + trial % 10);
        let mut data = Data::new(&model);
        let (x, _) = common::random_state(&mut r, &model);
        kinematics::forward_kinematics(&model, &mut data, &x).unwrap();
        assert_eq!(model.path_dofs(0), 0);
        for b in 1..model.n_bodies() {
            fixed_seen |= model.dof_of_body(b).is_none();
            let (jt, jr) = kinematics::link_jacobians(&model, &data, b);
            let nonzero = (0..model.n_dof()).filter(|&d| jt.column(d).norm() + jr.column(d).norm() > 0.0).count();
            assert_eq!(model.path_dofs(b), nonzero, "trial {trial}, body {b}");
        }
    }
    assert!(fixed_seen, "the random trees include fixed joints");
}

#[test]
fn paper_form_equals_crba() {
    let mut r = common::rng(1);
    for trial in 0..40 {
        let model = common::random_model(&mut r, 1 + trial % 12);
        let mut data = Data::new(&model);
        let (x, _) = common::random_state(&mut r, &model);
        let paper = inertia::inertia_blocks(&model, &mut data, &x).unwrap().mass_matrix();
        let recursive = crba::crba(&model, &mut data, &x).unwrap().clone();
        assert!(recursive.abs().max() > 1.0);
        assert!(rel_err(&paper, &recursive) < 1e-12, "trial {trial}: {}", rel_err(&paper, &recursive));
    }
}

#[test]
fn aba_equals_mass_matrix_route_and_rnea_inverts_it() {
    let mut r = common::rng(2);
    for trial in 0..40 {
        let model = common::random_model(&mut r, 1 + trial % 12);
        let mut data = Data::new(&model);
        let (x, u) = common::random_state(&mut r, &model);
        let f = common::random_vector(&mut r, model.nu(), 10.0);
        let ext = [ExternalWrench {
            body: model.n_bodies() - 1,
            offset: Vector3::new(0.1, 0.2, -0.1),
            force: Vector3::new(1.0, -2.0, 0.5),
            torque: Vector3::new(0.3, 0.1, -0.2),
        }];
        let a1 = aba::aba(&model, &mut data, &x, &u, &f, &ext).unwrap().clone();
        let a2 = dynamics::forward_dynamics_via_mass_matrix(&model, &mut data, &x, &u, &f, &ext).unwrap();
        assert!((&a1 - &a2).abs().max() < 1e-9 * a2.abs().max(), "trial {trial}");
        let back = rnea::rnea(&model, &mut data, &x, &u, a1.as_slice(), &ext).unwrap().clone();
        assert!((&back - DVector::from_column_slice(&f)).abs().max() < 1e-9 * 10.0, "trial {trial}");
    }
}

#[test]
fn reduced_dynamics_equals_aba() {
    let mut r = common::rng(3);
    for trial in 0..30 {
        let model = common::random_model(&mut r, 1 + trial % 10);
        let mut data = Data::new(&model);
        let (x, u) = common::random_state(&mut r, &model);
        let tau = common::random_vector(&mut r, model.n_dof(), 5.0);
        let fb = Vector6::from_column_slice(&common::random_vector(&mut r, 6, 20.0));
        let mut f = fb.as_slice().to_vec();
        f.extend(&tau);
        let reduced = gjm::reduced_forward_dynamics(&model, &mut data, &x, &u, &tau, &fb).unwrap();
        let full = aba::aba(&model, &mut data, &x, &u, &f, &[]).unwrap().clone();
        assert!((&reduced - &full).abs().max() < 1e-8 * full.abs().max(), "trial {trial}");
    }
}

#[test]
fn schur_inverse_equals_lu_inverse() {
    let mut r = common::rng(4);
    for _ in 0..20 {
        let model = common::random_model(&mut r, 6);
        let mut data = Data::new(&model);
        let (x, _) = common::random_state(&mut r, &model);
        let h = crba::crba(&model, &mut data, &x).unwrap().clone();
        let (h0, _, _) = gjm::split_mass_matrix(&h);
        let closed = inertia::base_inertia_inverse(&h0).unwrap();
        let lu = h0.try_inverse().unwrap();
        assert_relative_eq!(closed, lu, max_relative = 1e-10, epsilon = 1e-14);
    }
}

#[test]
fn momentum_and_energy_equal_mass_matrix_products() {
    let mut r = common::rng(5);
    for trial in 0..20 {
        let model = common::random_model(&mut r, 1 + trial % 8);
        let mut data = Data::new(&model);
        let (x, u) = common::random_state(&mut r, &model);
        let h = crba::crba(&model, &mut data, &x).unwrap().clone();
        let uv = DVector::from_column_slice(&u);
        let hu = &h * &uv;
        let mom = momentum::momentum(&model, &mut data, &x, &u).unwrap();
        assert!((mom.linear - hu.fixed_rows::<3>(0)).norm() < 1e-10 * hu.norm());
        assert!((mom.angular_about_base - hu.fixed_rows::<3>(3)).norm() < 1e-10 * hu.norm());
        let t = momentum::kinetic_energy(&model, &mut data, &x, &u).unwrap();
        assert_relative_eq!(t, 0.5 * uv.dot(&hu), max_relative = 1e-12);
    }
}

#[test]
fn generalized_jacobian_matches_finite_differences_of_momentum_conserving_motion() {
    let mut r = common::rng(6);
    for trial in 0..20 {
        let model = common::random_model(&mut r, 2 + trial % 8);
        let mut data = Data::new(&model);
        let (x, _) = common::random_state(&mut r, &model);
        let qd = common::random_vector(&mut r, model.n_dof(), 1.0);
        let body = model.n_bodies() - 1;
        let off = Vector3::new(0.2, -0.1, 0.3);
        let jstar = gjm::generalized_jacobian(&model, &mut data, &x, body, &off).unwrap();
        let twist = &jstar * DVector::from_column_slice(&qd);
        // The base velocity momentum conservation dictates (zero momentum), then the point
        // velocity by central differences of its position along x(t) = x + h·ẋ.
        let xd0 = gjm::base_velocity_from_momentum(&model, &mut data, &x, &qd, &Vector3::zeros(), &Vector3::zeros()).unwrap();
        let eps = 1e-6;
        let step = |s: f64, data: &mut Data| {
            let mut xs = x.clone();
            for i in 0..3 {
                xs[i] += s * xd0[i];
            }
            let w = Vector3::new(xd0[3], xd0[4], xd0[5]);
            let q0 = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(x[6], x[3], x[4], x[5]));
            let qn = nalgebra::UnitQuaternion::from_scaled_axis(w * s) * q0;
            xs[3] = qn.i;
            xs[4] = qn.j;
            xs[5] = qn.k;
            xs[6] = qn.w;
            for j in 0..qd.len() {
                xs[7 + j] += s * qd[j];
            }
            kinematics::forward_kinematics(&model, data, &xs).unwrap();
            kinematics::point_position(data, body, &off)
        };
        let v_fd = (step(eps, &mut data) - step(-eps, &mut data)) / (2.0 * eps);
        let v = Vector3::new(twist[0], twist[1], twist[2]);
        assert!(v.norm() > 1e-3);
        assert!((v - v_fd).norm() < 1e-6 * (1.0 + v.norm()), "trial {trial}: {v} vs {v_fd}");
    }
}

#[test]
fn generalized_inertia_is_symmetric_positive_definite() {
    let mut r = common::rng(7);
    for trial in 0..20 {
        let model = common::random_model(&mut r, 1 + trial % 12);
        let mut data = Data::new(&model);
        let (x, _) = common::random_state(&mut r, &model);
        let hs = gjm::generalized_inertia(&model, &mut data, &x).unwrap();
        assert!((&hs - hs.transpose()).abs().max() < 1e-10 * hs.abs().max());
        assert!(hs.clone().cholesky().is_some());
    }
}
