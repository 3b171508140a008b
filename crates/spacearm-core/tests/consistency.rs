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
    let mut fixed_seen = false;
    common::on_random_states(11, 20, |r, t| common::random_model(r, 2 + t % 10), |trial, _, model, data, x, _| {
        kinematics::forward_kinematics(model, data, x).unwrap();
        assert_eq!(model.path_dofs(0), 0);
        for b in 1..model.n_bodies() {
            fixed_seen |= model.dof_of_body(b).is_none();
            let (jt, jr) = kinematics::link_jacobians(model, data, b);
            let nonzero = (0..model.n_dof()).filter(|&d| jt.column(d).norm() + jr.column(d).norm() > 0.0).count();
            assert_eq!(model.path_dofs(b), nonzero, "trial {trial}, body {b}");
        }
    });
    assert!(fixed_seen, "the random trees include fixed joints");
}

#[test]
fn paper_form_equals_crba() {
    common::on_random_states(1, 40, |r, t| common::random_model(r, 1 + t % 12), |trial, _, model, data, x, _| {
        let paper = inertia::inertia_blocks(model, data, x).unwrap().mass_matrix();
        let recursive = crba::crba(model, data, x).unwrap().clone();
        assert!(recursive.abs().max() > 1.0);
        assert!(rel_err(&paper, &recursive) < 1e-12, "trial {trial}: {}", rel_err(&paper, &recursive));
    });
}

#[test]
fn aba_equals_mass_matrix_route_and_rnea_inverts_it() {
    common::on_random_states(2, 40, |r, t| common::random_model(r, 1 + t % 12), |trial, r, model, data, x, u| {
        let f = common::random_vector(r, model.nu(), 10.0);
        let ext = [ExternalWrench {
            body: model.n_bodies() - 1,
            offset: Vector3::new(0.1, 0.2, -0.1),
            force: Vector3::new(1.0, -2.0, 0.5),
            torque: Vector3::new(0.3, 0.1, -0.2),
        }];
        let a1 = aba::aba(model, data, x, u, &f, &ext).unwrap().clone();
        let a2 = dynamics::forward_dynamics_via_mass_matrix(model, data, x, u, &f, &ext).unwrap();
        assert!((&a1 - &a2).abs().max() < 1e-9 * a2.abs().max(), "trial {trial}");
        let back = rnea::rnea(model, data, x, u, a1.as_slice(), &ext).unwrap().clone();
        assert!((&back - DVector::from_column_slice(&f)).abs().max() < 1e-9 * 10.0, "trial {trial}");
    });
}

#[test]
fn reduced_dynamics_equals_aba() {
    common::on_random_states(3, 30, |r, t| common::random_model(r, 1 + t % 10), |trial, r, model, data, x, u| {
        let tau = common::random_vector(r, model.n_dof(), 5.0);
        let fb = Vector6::from_column_slice(&common::random_vector(r, 6, 20.0));
        let mut f = fb.as_slice().to_vec();
        f.extend(&tau);
        let reduced = gjm::reduced_forward_dynamics(model, data, x, u, &tau, &fb).unwrap();
        let full = aba::aba(model, data, x, u, &f, &[]).unwrap().clone();
        assert!((&reduced - &full).abs().max() < 1e-8 * full.abs().max(), "trial {trial}");
    });
}

#[test]
fn schur_inverse_equals_lu_inverse() {
    common::on_random_states(4, 20, |r, _| common::random_model(r, 6), |_, _, model, data, x, _| {
        let h = crba::crba(model, data, x).unwrap().clone();
        let (h0, _, _) = gjm::split_mass_matrix(&h);
        let closed = inertia::base_inertia_inverse(&h0).unwrap();
        let lu = h0.try_inverse().unwrap();
        assert_relative_eq!(closed, lu, max_relative = 1e-10, epsilon = 1e-14);
    });
}

#[test]
fn momentum_and_energy_equal_mass_matrix_products() {
    common::on_random_states(5, 20, |r, t| common::random_model(r, 1 + t % 8), |_, _, model, data, x, u| {
        let h = crba::crba(model, data, x).unwrap().clone();
        let uv = DVector::from_column_slice(u);
        let hu = &h * &uv;
        let mom = momentum::momentum(model, data, x, u).unwrap();
        assert!((mom.linear - hu.fixed_rows::<3>(0)).norm() < 1e-10 * hu.norm());
        assert!((mom.angular_about_base - hu.fixed_rows::<3>(3)).norm() < 1e-10 * hu.norm());
        let t = momentum::kinetic_energy(model, data, x, u).unwrap();
        assert_relative_eq!(t, 0.5 * uv.dot(&hu), max_relative = 1e-12);
    });
}

#[test]
fn generalized_jacobian_matches_finite_differences_of_momentum_conserving_motion() {
    common::on_random_states(6, 20, |r, t| common::random_model(r, 2 + t % 8), |trial, r, model, data, x, _| {
        let qd = common::random_vector(r, model.n_dof(), 1.0);
        let body = model.n_bodies() - 1;
        let off = Vector3::new(0.2, -0.1, 0.3);
        let jstar = gjm::generalized_jacobian(model, data, x, body, &off).unwrap();
        let twist = &jstar * DVector::from_column_slice(&qd);
        // The base velocity momentum conservation dictates (zero momentum), then the point
        // velocity by central differences of its position along x(t) = x + h·ẋ.
        let xd0 = gjm::base_velocity_from_momentum(model, data, x, &qd, &Vector3::zeros(), &Vector3::zeros()).unwrap();
        let eps = 1e-6;
        let u: Vec<f64> = xd0.iter().chain(&qd).copied().collect();
        let step = |s: f64, data: &mut Data| {
            kinematics::forward_kinematics(model, data, &common::advance(x, &u, s)).unwrap();
            kinematics::point_position(data, body, &off)
        };
        let v_fd = (step(eps, data) - step(-eps, data)) / (2.0 * eps);
        let v = Vector3::new(twist[0], twist[1], twist[2]);
        assert!(v.norm() > 1e-3);
        assert!((v - v_fd).norm() < 1e-6 * (1.0 + v.norm()), "trial {trial}: {v} vs {v_fd}");
    });
}

#[test]
fn generalized_inertia_is_symmetric_positive_definite() {
    common::on_random_states(7, 20, |r, t| common::random_model(r, 1 + t % 12), |_, _, model, data, x, _| {
        let hs = gjm::generalized_inertia(model, data, x).unwrap();
        assert!((&hs - hs.transpose()).abs().max() < 1e-10 * hs.abs().max());
        assert!(hs.clone().cholesky().is_some());
    });
}
