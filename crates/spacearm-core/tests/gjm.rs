//! The Generalized Jacobian Matrix formulation of `spacearm_core::gjm` (paper §4–5) against
//! routes that share none of its closed-form algebra, on random trees with branches, fixed and
//! prismatic joints, at random states:
//!
//! - `H*` (eq. 45) against `H_m − H0mᵀ H0⁻¹ H0m` from the paper-form inertia blocks (Jacobian
//!   sums, no recursion) and from the CRBA blocks, with `H0` inverted by a dense Cholesky
//!   factorization (not the closed-form Schur complement gjm uses); against the kinetic energy
//!   summed body by body at the base velocity zero momentum implies (`T = ½ q̇ᵀ H* q̇`, by
//!   polarization, entry by entry); and against the ABA response to unit joint torques
//!   (`H* q̈ = τ` at rest);
//! - `c*` (eq. 46) against `c_m − H0mᵀ H0⁻¹ c0` with `c` from RNEA, and against ABA
//!   (`H* q̈ + c* = τ` with the base velocity as given);
//! - `J*` (eq. 110) against the dense `J_mX − J_0X H0⁻¹ H0m`; against the point twist of the
//!   velocity recursion at the base velocity of eq. 109 (`ẋ0 = −H0⁻¹ H0m q̇`, whose momentum the
//!   body-by-body sum finds zero); and against central differences of the point's position and
//!   attitude along that motion;
//! - the base velocity of eq. 43 and `momentum_twist` (`J_0X H0⁻¹ M0`) against the momentum
//!   summed body by body and the dense formula, and `[v_X; ω] = J* q̇ + J_0X H0⁻¹ M0` against
//!   the velocity recursion;
//! - the invariances: `H*` depends on `q` only, `J*` turns with the base attitude.
//!
//! Each comparison is relative to the size of the quantity, near 1e-12, and each test asserts
//! that the part it checks is not negligible (so a missing term would fail it).

mod common;

use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Quaternion, UnitQuaternion, Vector3, Vector6};
use spacearm_core::algorithms::{aba, crba, inertia, kinematics, momentum, rnea};
use spacearm_core::*;

/// Relative tolerance of the comparisons between exact routes.
const TOL: f64 = 1e-12;

fn rel_err(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    assert_eq!(a.shape(), b.shape());
    (a - b).abs().max() / b.abs().max().max(1e-300)
}

fn rel_err_v(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    assert_eq!(a.len(), b.len());
    (a - b).abs().max() / b.abs().max().max(1e-300)
}

fn dyn6(m: &Matrix6<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(6, 6, |i, j| m[(i, j)])
}

/// `H0⁻¹ rhs` by a dense Cholesky factorization of `H0` (not gjm's closed-form inverse).
fn h0_solve(h0: &Matrix6<f64>, rhs: &DMatrix<f64>) -> DMatrix<f64> {
    dyn6(h0).cholesky().expect("H0 is positive definite").solve(rhs)
}

/// The inertia blocks `(H0, H0m, H_m)` of the paper's Jacobian sums (eqs. 27–36).
fn paper_blocks(model: &Model, data: &mut Data, x: &[f64]) -> (Matrix6<f64>, DMatrix<f64>, DMatrix<f64>) {
    let b = inertia::inertia_blocks(model, data, x).unwrap();
    (b.h0, b.h0m, b.hm)
}

/// `H_m − H0mᵀ H0⁻¹ H0m` from dense blocks.
fn schur(h0: &Matrix6<f64>, h0m: &DMatrix<f64>, hm: &DMatrix<f64>) -> DMatrix<f64> {
    hm - h0m.transpose() * h0_solve(h0, h0m)
}

/// A model with at least one degree of freedom (the random trees may have only fixed joints).
fn random_moving_model(r: &mut rand_chacha::ChaCha8Rng, n_links: usize) -> Model {
    loop {
        let m = common::random_model(r, n_links);
        if m.n_dof() > 0 {
            return m;
        }
    }
}

/// What the random models of a test covered: (prismatic joint, fixed joint, branch).
#[derive(Default)]
struct Coverage {
    prismatic: bool,
    fixed: bool,
    branch: bool,
}

impl Coverage {
    fn see(&mut self, model: &Model) {
        let mut children = vec![0usize; model.n_bodies()];
        for l in model.links() {
            children[l.parent] += 1;
            self.prismatic |= l.joint.kind == JointType::Prismatic;
            self.fixed |= l.joint.kind == JointType::Fixed;
        }
        self.branch |= children.iter().any(|&c| c > 1);
    }

    fn assert_all(&self) {
        assert!(self.prismatic && self.fixed && self.branch, "the random models include prismatic and fixed joints and branches");
    }
}

/// The point twist `[v_X; ω]` in 𝒥 of the point `offset` on `body` at `(x, u)` from the
/// velocity recursion (body twists at the base CM, summed joint by joint), with the momentum
/// the body-by-body sum finds.
fn recursive_point_twist(model: &Model, data: &mut Data, x: &[f64], u: &[f64], body: usize, offset: &Vector3<f64>) -> (Vector6<f64>, momentum::Momentum) {
    let mom = momentum::momentum(model, data, x, u).unwrap();
    let v = data.body_velocity[body];
    let w = Vector3::new(v[3], v[4], v[5]);
    let p = kinematics::point_position(data, body, offset);
    let lin = Vector3::new(v[0], v[1], v[2]) + w.cross(&(p - data.base_position));
    (Vector6::new(lin.x, lin.y, lin.z, w.x, w.y, w.z), mom)
}

/// The point twist by central differences of the point's position and its body's attitude
/// along `x(t) = x ⊕ t u`.
fn finite_difference_twist(model: &Model, data: &mut Data, x: &[f64], u: &[f64], body: usize, offset: &Vector3<f64>) -> Vector6<f64> {
    let h = 1e-6;
    let mut pose = |s: f64| {
        kinematics::forward_kinematics(model, data, &common::advance(x, u, s)).unwrap();
        (kinematics::point_position(data, body, offset), data.body_to_world[body])
    };
    let (p_plus, r_plus) = pose(h);
    let (p_minus, r_minus) = pose(-h);
    let (_, r0) = pose(0.0);
    let v = (p_plus - p_minus) / (2.0 * h);
    let w_hat: Matrix3<f64> = (r_plus - r_minus) / (2.0 * h) * r0.transpose();
    let w = Vector3::new(w_hat[(2, 1)] - w_hat[(1, 2)], w_hat[(0, 2)] - w_hat[(2, 0)], w_hat[(1, 0)] - w_hat[(0, 1)]) * 0.5;
    Vector6::new(v.x, v.y, v.z, w.x, w.y, w.z)
}

/// The bodies whose points the tests use: the base, the last body, and one on another branch
/// than the last where there is one (else the first link).
fn test_bodies(model: &Model) -> Vec<usize> {
    let last = model.n_bodies() - 1;
    let mut on_path = vec![false; model.n_bodies()];
    let mut b = last;
    while b != 0 {
        on_path[b] = true;
        b = model.links()[b - 1].parent;
    }
    let other = (1..last).find(|&b| !on_path[b]).unwrap_or(1);
    let mut bodies = vec![0, last, other];
    bodies.dedup();
    bodies
}

/// Runs `check(trial, rng, model, data, x, u)` on `trials` random moving trees of
/// `2 + trial % span` links, each at a random state, and asserts that the trees covered
/// prismatic and fixed joints and branches.
fn on_random_trees(seed: u64, trials: usize, span: usize, mut check: impl FnMut(usize, &mut rand_chacha::ChaCha8Rng, &Model, &mut Data, &[f64], &[f64])) {
    let mut seen = Coverage::default();
    common::on_random_states(seed, trials, |r, trial| random_moving_model(r, 2 + trial % span), |trial, r, model, data, x, u| {
        seen.see(model);
        check(trial, r, model, data, x, u)
    });
    seen.assert_all();
}

/// The velocity `u = [ẋ0; q̇]` of base velocity `xd0` and joint rates `qd`.
fn velocity(xd0: &[f64], qd: &[f64]) -> Vec<f64> {
    let mut u = xd0.to_vec();
    u.extend_from_slice(qd);
    u
}

/// `ẋ0 = −H0⁻¹ H0m q̇`, the base velocity zero momentum implies (eq. 109), by the dense route.
fn zero_momentum_base_velocity(h0: &Matrix6<f64>, h0m: &DMatrix<f64>, qd: &DVector<f64>) -> DMatrix<f64> {
    -h0_solve(h0, &DMatrix::from_column_slice(6, 1, (h0m * qd).as_slice()))
}

/// `M0 = [P; L_origin − r0 × P]`, the momentum about the base CM at `x` as a column.
fn base_momentum(x: &[f64], p: &Vector3<f64>, l: &Vector3<f64>) -> DMatrix<f64> {
    let r0 = Vector3::new(x[0], x[1], x[2]);
    let lb = l - r0.cross(p);
    DMatrix::from_column_slice(6, 1, &[p.x, p.y, p.z, lb.x, lb.y, lb.z])
}

#[test]
fn generalized_inertia_is_the_schur_complement_of_both_mass_matrices() {
    on_random_trees(101, 30, 11, |trial, _, model, data, x, _| {
        let hs = gjm::generalized_inertia(model, data, x).unwrap();
        // Paper form: Jacobian sums, dense Cholesky of H0.
        let (h0, h0m, hm) = paper_blocks(model, data, x);
        let reference = schur(&h0, &h0m, &hm);
        // The coupling term is a sizeable part of H*: dropping it would fail the comparison.
        assert!(rel_err(&hm, &reference) > 1e-3, "trial {trial}: H0m^T H0^-1 H0m is negligible");
        let e = rel_err(&hs, &reference);
        assert!(e < TOL, "trial {trial}: H* vs paper-form Schur complement: {e:e}");
        // CRBA blocks, split here, same dense inversion.
        let h = crba::crba(model, data, x).unwrap().clone();
        let (h0c, h0mc, hmc) = gjm::split_mass_matrix(&h);
        let e = rel_err(&hs, &schur(&h0c, &h0mc, &hmc));
        assert!(e < TOL, "trial {trial}: H* vs CRBA Schur complement: {e:e}");
        // The compute_ form leaves the same matrix in the workspace.
        let mut data2 = Data::new(model);
        assert_eq!(gjm::compute_generalized_inertia(model, &mut data2, x).unwrap(), &hs);
    });
}

#[test]
fn generalized_inertia_is_the_kinetic_energy_at_zero_momentum() {
    // T(q̇) = ½ q̇ᵀ H* q̇ when the base moves at ẋ0 = −H0⁻¹ H0m q̇ (eqs. 44–45); by polarization
    // H*_ij = T(e_i + e_j) − T(e_i) − T(e_j), with T summed body by body.
    on_random_trees(102, 16, 8, |trial, _, model, data, x, _| {
        let n = model.n_dof();
        let hs = gjm::generalized_inertia(model, data, x).unwrap();
        let (h0, h0m, _) = paper_blocks(model, data, x);
        let mut energy = |qd: &DVector<f64>| {
            let u = velocity(zero_momentum_base_velocity(&h0, &h0m, qd).as_slice(), qd.as_slice());
            momentum::kinetic_energy(model, data, x, &u).unwrap()
        };
        let unit = |i: usize| DVector::from_fn(n, |k, _| if k == i { 1.0 } else { 0.0 });
        let t: Vec<f64> = (0..n).map(|i| energy(&unit(i))).collect();
        let polarized = DMatrix::from_fn(n, n, |i, j| if i == j { 2.0 * t[i] } else { energy(&(unit(i) + unit(j))) - t[i] - t[j] });
        let e = rel_err(&hs, &polarized);
        assert!(e < TOL, "trial {trial}: H* vs kinetic-energy polarization: {e:e}");
    });
}

#[test]
fn generalized_inertia_inverts_the_articulated_body_response() {
    // At rest (u = 0, so c = 0) and with no base wrench, ABA's q̈ under τ satisfies H* q̈ = τ.
    on_random_trees(103, 20, 10, |trial, _, model, data, x, _| {
        let n = model.n_dof();
        let hs = gjm::generalized_inertia(model, data, x).unwrap();
        let rest = vec![0.0; model.nu()];
        let mut qdd = DMatrix::zeros(n, n);
        for j in 0..n {
            let mut f = vec![0.0; model.nu()];
            f[6 + j] = 1.0;
            let du = aba::aba(model, data, x, &rest, &f, &[]).unwrap();
            qdd.column_mut(j).copy_from(&du.rows(6, n));
        }
        let e = rel_err(&(&hs * &qdd), &DMatrix::identity(n, n));
        // H* q̈ = I to the conditioning of H* times rounding.
        let cond = hs.abs().max() * qdd.abs().max();
        assert!(e < TOL * cond.max(1.0), "trial {trial}: H* · ABA response: {e:e} (scale {cond:e})");
    });
}

#[test]
fn generalized_bias_equals_the_rnea_reduction_and_the_aba_response() {
    on_random_trees(104, 30, 11, |trial, r, model, data, x, u| {
        let n = model.n_dof();
        let cs = gjm::generalized_bias(model, data, x, u).unwrap();
        // c* = c_m − H0mᵀ H0⁻¹ c0 with c from RNEA and the paper-form blocks.
        let c = rnea::bias_forces(model, data, x, u).unwrap().clone();
        let (h0, h0m, hm) = paper_blocks(model, data, x);
        let c0 = DMatrix::from_column_slice(6, 1, &c.as_slice()[..6]);
        let cm = DVector::from_column_slice(&c.as_slice()[6..]);
        let coupling = DVector::from_column_slice((h0m.transpose() * h0_solve(&h0, &c0)).as_slice());
        assert!(coupling.abs().max() > 1e-3 * cm.abs().max(), "trial {trial}: H0m^T H0^-1 c0 is negligible");
        let reference = &cm - &coupling;
        let e = rel_err_v(&cs, &reference);
        assert!(e < TOL * (cm.abs().max() / reference.abs().max()).max(1.0), "trial {trial}: c* vs RNEA reduction: {e:e}");
        // ABA with f = [0; τ] at (x, u): its q̈ satisfies H* q̈ + c* = τ (eq. 46, the base
        // velocity as given).
        let tau = common::random_vector(r, n, 5.0);
        let mut f = vec![0.0; 6];
        f.extend(&tau);
        let du = aba::aba(model, data, x, u, &f, &[]).unwrap().clone();
        let hs = schur(&h0, &h0m, &hm);
        let qdd = DVector::from_column_slice(&du.as_slice()[6..]);
        let lhs = &hs * &qdd + &cs;
        let scale = (hs.abs().max() * qdd.abs().max()).max(cs.abs().max()).max(5.0);
        let e = (&lhs - DVector::from_column_slice(&tau)).abs().max() / scale;
        assert!(e < 1e-11, "trial {trial}: H* q̈_ABA + c* − τ: {e:e}");
    });
}

#[test]
fn generalized_jacobian_equals_the_dense_formula_and_the_zero_momentum_twist() {
    let mut points = 0;
    on_random_trees(105, 24, 10, |trial, r, model, data, x, _| {
        let qd = DVector::from_column_slice(&common::random_vector(r, model.n_dof(), 1.0));
        let (h0, h0m, _) = paper_blocks(model, data, x);
        // Eq. 109: the base velocity zero momentum implies, by the dense route.
        let xd0 = zero_momentum_base_velocity(&h0, &h0m, &qd);
        let u = velocity(xd0.as_slice(), qd.as_slice());
        for body in test_bodies(model) {
            let offset = Vector3::new(r_f(r), r_f(r), r_f(r));
            let jstar = gjm::generalized_jacobian(model, data, x, body, &offset).unwrap();
            // Dense J_mX − J_0X H0⁻¹ H0m (eq. 110).
            kinematics::forward_kinematics(model, data, x).unwrap();
            let (j0x, jmx) = kinematics::point_jacobians(model, data, body, &offset).unwrap();
            let reference = &jmx - dyn6(&j0x) * h0_solve(&h0, &h0m);
            let e = rel_err(&jstar, &reference);
            assert!(e < TOL, "trial {trial}, body {body}: J* vs dense formula: {e:e}");
            // The base part is a sizeable part of J*.
            assert!(rel_err(&jmx, &reference) > 1e-3, "trial {trial}, body {body}: J_0X H0^-1 H0m is negligible");
            // J* q̇ is the point twist of the recursion at the base velocity of eq. 109, and
            // that motion has zero momentum by the body-by-body sum.
            let (twist, mom) = recursive_point_twist(model, data, x, &u, body, &offset);
            let scale = xd0.abs().max() * 1e3 + qd.abs().max();
            assert!(mom.linear.amax() < 1e-12 * scale && mom.angular_about_origin.amax() < 1e-11 * scale, "trial {trial}: momentum {mom:?}");
            let jq = DVector::from_column_slice((&jstar * &qd).as_slice());
            let tw = DVector::from_column_slice(twist.as_slice());
            assert!(tw.norm() > 1e-3);
            let e = rel_err_v(&jq, &tw);
            assert!(e < TOL, "trial {trial}, body {body}: J* q̇ vs recursive twist: {e:e}");
            // ... and the central differences of the point's position and attitude.
            let fd = DVector::from_column_slice(finite_difference_twist(model, data, x, &u, body, &offset).as_slice());
            let e = rel_err_v(&jq, &fd);
            assert!(e < 1e-7, "trial {trial}, body {body}: J* q̇ vs finite differences: {e:e}");
            points += 1;
        }
    });
    assert!(points >= 60);
}

fn r_f(r: &mut rand_chacha::ChaCha8Rng) -> f64 {
    common::random_vector(r, 1, 0.5)[0]
}

#[test]
fn base_velocity_from_momentum_gives_the_system_that_momentum() {
    on_random_trees(106, 24, 10, |trial, r, model, data, x, _| {
        let qd = common::random_vector(r, model.n_dof(), 1.0);
        let p = Vector3::from_column_slice(&common::random_vector(r, 3, 50.0));
        let l = Vector3::from_column_slice(&common::random_vector(r, 3, 50.0));
        let xd0 = gjm::base_velocity_from_momentum(model, data, x, &qd, &p, &l).unwrap();
        let u = velocity(xd0.as_slice(), &qd);
        let mom = momentum::momentum(model, data, x, &u).unwrap();
        let scale = p.amax().max(l.amax());
        assert!((mom.linear - p).amax() < TOL * scale * 10.0, "trial {trial}: P {} vs {p}", mom.linear);
        assert!((mom.angular_about_origin - l).amax() < TOL * scale * 10.0 * (1.0 + x[..3].iter().map(|v| v.abs()).fold(0.0, f64::max)), "trial {trial}: L {} vs {l}", mom.angular_about_origin);
        // The dense route: H0⁻¹ (M0 − H0m q̇), M0 = [P; L_origin − r0 × P].
        let (h0, h0m, _) = paper_blocks(model, data, x);
        let m0 = base_momentum(x, &p, &l);
        let reference = h0_solve(&h0, &(m0 - &h0m * DMatrix::from_column_slice(qd.len(), 1, &qd)));
        let e = rel_err(&DMatrix::from_column_slice(6, 1, xd0.as_slice()), &reference);
        assert!(e < TOL, "trial {trial}: base velocity vs dense formula: {e:e}");
    });
}

#[test]
fn momentum_twist_is_the_base_jacobian_times_h0_inverse_momentum() {
    on_random_trees(107, 24, 10, |trial, r, model, data, x, _| {
        let qd = DVector::from_column_slice(&common::random_vector(r, model.n_dof(), 1.0));
        let p = Vector3::from_column_slice(&common::random_vector(r, 3, 50.0));
        let l = Vector3::from_column_slice(&common::random_vector(r, 3, 50.0));
        let (h0, _, _) = paper_blocks(model, data, x);
        let m0 = base_momentum(x, &p, &l);
        for body in test_bodies(model) {
            let offset = Vector3::new(r_f(r), r_f(r), r_f(r));
            let mt = gjm::momentum_twist(model, data, x, body, &offset, &p, &l).unwrap();
            kinematics::forward_kinematics(model, data, x).unwrap();
            let (j0x, _) = kinematics::point_jacobians(model, data, body, &offset).unwrap();
            let reference = dyn6(&j0x) * h0_solve(&h0, &m0);
            let e = rel_err(&DMatrix::from_column_slice(6, 1, mt.as_slice()), &reference);
            assert!(e < TOL, "trial {trial}, body {body}: momentum twist vs dense formula: {e:e}");
            // With momentum M0 the point twist is J* q̇ + J_0X H0⁻¹ M0 (eq. 109 generalized).
            let xd0 = gjm::base_velocity_from_momentum(model, data, x, qd.as_slice(), &p, &l).unwrap();
            let u = velocity(xd0.as_slice(), qd.as_slice());
            let jstar = gjm::generalized_jacobian(model, data, x, body, &offset).unwrap();
            let predicted = DVector::from_column_slice((&jstar * &qd).as_slice()) + DVector::from_column_slice(mt.as_slice());
            let (twist, _) = recursive_point_twist(model, data, x, &u, body, &offset);
            let e = rel_err_v(&predicted, &DVector::from_column_slice(twist.as_slice()));
            assert!(e < TOL * 10.0, "trial {trial}, body {body}: J* q̇ + momentum twist vs recursive twist: {e:e}");
            assert!(mt.norm() > 1e-3 * twist.norm(), "trial {trial}: the momentum term is negligible");
        }
    });
}

#[test]
fn generalized_inertia_depends_on_q_only_and_the_jacobian_turns_with_the_base() {
    let mut r = common::rng(108);
    for trial in 0..12 {
        let model = random_moving_model(&mut r, 2 + trial % 8);
        let mut data = Data::new(&model);
        let (x, _) = common::random_state(&mut r, &model);
        let (mut y, _) = common::random_state(&mut r, &model);
        y[7..].copy_from_slice(&x[7..]);
        let hx = gjm::generalized_inertia(&model, &mut data, &x).unwrap();
        let hy = gjm::generalized_inertia(&model, &mut data, &y).unwrap();
        let e = rel_err(&hy, &hx);
        assert!(e < TOL, "trial {trial}: H* moved with the base pose: {e:e}");
        let body = model.n_bodies() - 1;
        let offset = Vector3::new(0.1, -0.3, 0.2);
        let jx = gjm::generalized_jacobian(&model, &mut data, &x, body, &offset).unwrap();
        let jy = gjm::generalized_jacobian(&model, &mut data, &y, body, &offset).unwrap();
        let quat = |s: &[f64]| UnitQuaternion::from_quaternion(Quaternion::new(s[6], s[3], s[4], s[5]));
        let turn = (quat(&y) * quat(&x).inverse()).to_rotation_matrix().into_inner();
        let mut t = DMatrix::zeros(6, 6);
        t.view_mut((0, 0), (3, 3)).copy_from(&turn);
        t.view_mut((3, 3), (3, 3)).copy_from(&turn);
        let e = rel_err(&jy, &(&t * &jx));
        assert!(e < TOL, "trial {trial}: J* under a base rotation: {e:e}");
        assert!(rel_err(&jy, &jx) > 1e-3, "trial {trial}: the two base attitudes are too close");
    }
}

#[test]
fn gjm_functions_refuse_bad_arguments_with_typed_errors() {
    let mut r = common::rng(109);
    let model = random_moving_model(&mut r, 5);
    let n = model.n_dof();
    let mut data = Data::new(&model);
    let (x, u) = common::random_state(&mut r, &model);
    let z = Vector3::zeros();
    let nb = model.n_bodies();
    let not_found = |e: SpacearmError| matches!(&e, SpacearmError::NotFound(m) if m.contains(&format!("body index {nb}")));
    assert!(not_found(gjm::generalized_jacobian(&model, &mut data, &x, nb, &z).unwrap_err()));
    assert!(not_found(gjm::momentum_twist(&model, &mut data, &x, nb, &z, &z, &z).unwrap_err()));
    let nan = Vector3::new(0.0, f64::NAN, 0.0);
    let e = gjm::momentum_twist(&model, &mut data, &x, 0, &z, &nan, &z).unwrap_err();
    assert!(matches!(&e, SpacearmError::NonFinite { what, index: 1, .. } if what == "linear momentum"), "{e:?}");
    let e = gjm::base_velocity_from_momentum(&model, &mut data, &x, &vec![0.0; n], &z, &nan).unwrap_err();
    assert!(matches!(&e, SpacearmError::NonFinite { what, .. } if what == "angular momentum"), "{e:?}");
    let e = gjm::base_velocity_from_momentum(&model, &mut data, &x, &vec![0.0; n + 1], &z, &z).unwrap_err();
    assert!(matches!(&e, SpacearmError::Dimension { what, got, .. } if what == "qd" && *got == n + 1), "{e:?}");
    let e = gjm::generalized_bias(&model, &mut data, &x, &u[1..]).unwrap_err();
    assert!(matches!(&e, SpacearmError::Dimension { what, .. } if what == "u"), "{e:?}");
    let e = gjm::generalized_inertia(&model, &mut data, &x[1..]).unwrap_err();
    assert!(matches!(&e, SpacearmError::Dimension { .. }), "{e:?}");
    let mut bad = x.clone();
    bad[6] += 0.5;
    let e = gjm::generalized_inertia(&model, &mut data, &bad).unwrap_err();
    assert!(matches!(&e, SpacearmError::NotUnitQuaternion { .. }), "{e:?}");
    let fb = Vector6::zeros();
    let e = gjm::reduced_forward_dynamics(&model, &mut data, &x, &u, &vec![0.0; n + 1], &fb).unwrap_err();
    assert!(matches!(&e, SpacearmError::Dimension { what, .. } if what == "tau"), "{e:?}");
    let mut fb_nan = fb;
    fb_nan[4] = f64::INFINITY;
    let e = gjm::reduced_forward_dynamics(&model, &mut data, &x, &u, &vec![0.0; n], &fb_nan).unwrap_err();
    assert!(matches!(&e, SpacearmError::NonFinite { what, index: 4, .. } if what == "base wrench"), "{e:?}");
    // After the refusals the workspace still gives the right answers.
    let hs = gjm::generalized_inertia(&model, &mut data, &x).unwrap();
    let (h0, h0m, hm) = paper_blocks(&model, &mut Data::new(&model), &x);
    assert!(rel_err(&hs, &schur(&h0, &h0m, &hm)) < TOL);
}
