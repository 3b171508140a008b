//! The rigid frictional impact (collision/impact.rs, delassus.rs, admm.rs, pgs.rs) against closed
//! forms: a slider pair hitting a (near-infinitely heavy) base, frictionless, sticking and
//! sliding, with and without restitution; both solvers on coupled contacts of a 7-joint arm
//! agree, keep the floating system's momentum, and meet Coulomb's law.

use nalgebra::{DVector, Vector3};
use spacearm_core::collision::{contact_frame, rigid_impact, ContactPoint, ImpactSolver, ImpactSpec};
use spacearm_core::model::presets;
use spacearm_core::{Data, JointType, LinkSpec, Model, ModelBuilder};

/// A base of 1e12 kg (the heaviest the model rules allow: a fixed wall to ~1e-12) with a slider
/// along x (2 kg) carrying a slider along y (1 kg).
fn sliders() -> Model {
    let big = 1e12;
    let mut b = ModelBuilder::new("sliders", "base", big, [[big, 0.0, 0.0], [0.0, big, 0.0], [0.0, 0.0, big]]).unwrap();
    b.add_link(LinkSpec::new("sx", "base", JointType::Prismatic, [0.0; 3], [1.0, 0.0, 0.0], [0.0; 3], 2.0, [0.1; 3])).unwrap();
    b.add_link(LinkSpec::new("sy", "sx", JointType::Prismatic, [0.0; 3], [0.0, 1.0, 0.0], [0.0; 3], 1.0, [0.1; 3])).unwrap();
    b.build().unwrap()
}

fn spec(solver: ImpactSolver, restitution: f64) -> ImpactSpec {
    ImpactSpec { solver, restitution, tolerance: 1e-13, max_iterations: 5000, ..ImpactSpec::default() }
}

#[test]
fn a_slider_pair_hits_a_wall_frictionless_sticking_and_sliding_as_the_closed_forms_say() {
    let model = sliders();
    let mut data = Data::new(&model);
    let x = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.4, 0.0];
    let (m1, m2) = (2.0, 1.0);
    // Contact of the base (first) and the y-slider (second) at (0.5, 0, 0), normal +x: the
    // y-slider approaches at v_x < 0 and slips along y.
    for solver in [ImpactSolver::Admm, ImpactSolver::Pgs] {
        for (mu, vy, e) in [(0.0, 0.3, 0.0), (0.5, 0.3, 0.0), (0.5, 1.0, 0.0), (0.5, 1.0, 0.5), (0.2, -0.7, 1.0)] {
            let vx: f64 = -0.4;
            let u = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, vx, vy];
            let point = ContactPoint { body: [0, 2], point: Vector3::new(0.5, 0.0, 0.0), normal: Vector3::x(), friction: mu };
            let r = rigid_impact(&model, &mut data, &x, &u, &[point], &spec(solver, e)).unwrap();
            assert!(r.solution.converged, "{solver:?} {mu} {vy}: {:?}", r.solution);
            // Normal: both sliders stop along x (then rebound at −e v_x): λ_n = (1 + e)(m1 + m2)|v_x|.
            let ln = (1.0 + e) * (m1 + m2) * -vx;
            // Tangential: the y-slider alone; it sticks if m2 |v_y| ≤ μ λ_n, else slides by μ λ_n / m2.
            let stick = m2 * vy.abs() <= mu * ln;
            let (lt, vy_after) = if stick { (m2 * vy.abs(), 0.0) } else { (mu * ln, vy - vy.signum() * mu * ln / m2) };
            let impulse_on_second = contact_frame(&Vector3::x()) * r.impulse.fixed_rows::<3>(0);
            let expected = Vector3::new(ln, -vy.signum() * lt, 0.0);
            assert!((impulse_on_second - expected).norm() < 1e-9, "{solver:?} μ {mu} v_y {vy} e {e}: {impulse_on_second:?} vs {expected:?}");
            assert!((r.u_after[6] - (-e * vx)).abs() < 1e-9 && (r.u_after[7] - vy_after).abs() < 1e-9, "{solver:?}: {:?}", r.u_after);
            // The contact's normal velocity after the impact is −e v_n⁻ (Newton) either way.
            assert!((r.velocity_after[2] + e * vx).abs() < 1e-9);
        }
    }
}

/// A 7-joint arm on a 600 kg base with two contacts: the base against the hand, the second link
/// against the sixth.
fn arm_contacts(mu: f64) -> (Model, Vec<f64>, Vec<f64>, Vec<ContactPoint>) {
    let model = presets::spatial7();
    let mut x = presets::initial_configuration(&model);
    for (k, q) in x[7..].iter_mut().enumerate() {
        *q = 0.3 + 0.4 * (k as f64).sin();
    }
    let mut u = vec![0.05, -0.02, 0.01, 0.02, -0.01, 0.03];
    u.extend((0..model.n_dof()).map(|k| 0.2 * (1.3 * k as f64).cos()));
    let mut data = Data::new(&model);
    spacearm_core::algorithms::kinematics::forward_kinematics(&model, &mut data, &x).unwrap();
    let last = model.n_bodies() - 1;
    let points = vec![
        ContactPoint { body: [0, last], point: data.com_in_world[last] + Vector3::new(0.05, -0.02, 0.03), normal: Vector3::new(0.6, 0.0, 0.8), friction: mu },
        ContactPoint { body: [2, 6], point: data.com_in_world[6] + Vector3::new(-0.02, 0.04, 0.0), normal: Vector3::new(0.0, -0.6, 0.8), friction: mu },
    ];
    (model, x, u, points)
}

#[test]
fn both_solvers_agree_on_coupled_contacts_keep_the_momentum_and_meet_coulombs_law() {
    for mu in [0.0, 0.1, 0.8] {
        let (model, x, u, mut points) = arm_contacts(mu);
        let mut data = Data::new(&model);
        // Make both points approach: flip a normal that separates.
        let probe = rigid_impact(&model, &mut data, &x, &u, &points, &spec(ImpactSolver::Admm, 0.0)).unwrap();
        for (i, p) in points.iter_mut().enumerate() {
            if probe.velocity_before[3 * i + 2] > 0.0 {
                p.normal = -p.normal;
            }
        }
        let a = rigid_impact(&model, &mut data, &x, &u, &points, &spec(ImpactSolver::Admm, 0.0)).unwrap();
        let p = rigid_impact(&model, &mut data, &x, &u, &points, &spec(ImpactSolver::Pgs, 0.0)).unwrap();
        assert!(a.solution.converged && p.solution.converged, "{:?} {:?}", a.solution, p.solution);
        assert!(a.impulse.norm() > 1e-3, "the contacts push: {:?}", a.impulse);
        assert!((&a.impulse - &p.impulse).amax() < 1e-9 * a.impulse.amax(), "μ {mu}: {} vs {}", a.impulse, p.impulse);
        assert!((&a.u_after - &p.u_after).amax() < 1e-9, "μ {mu}");
        // H Δu = Jᵀ λ, and the impulses are internal: the base rows (the momenta [P; L] about the
        // base CM, eq. 42) do not change.
        let h = spacearm_core::algorithms::crba::crba(&model, &mut data, &x).unwrap().clone();
        let dm = &h * &a.du;
        assert!((&dm - a.jacobian.transpose() * &a.impulse).amax() < 1e-10);
        assert!(dm.rows(0, 6).amax() < 1e-12 * dm.amax().max(1.0), "{dm}");
        // Coulomb's law, checked here from J u⁺ (not the solver's residual): no penetration, the
        // impulses in their cones, and a pushing point does not move along its normal.
        for i in 0..points.len() {
            let (l, v) = (a.impulse.fixed_rows::<3>(3 * i), a.velocity_after.fixed_rows::<3>(3 * i));
            assert!(v[2] > -1e-9 && l[2] >= 0.0 && l.xy().norm() <= mu * l[2] * (1.0 + 1e-12) + 1e-15);
            if l[2] > 1e-9 {
                assert!(v[2].abs() < 1e-9, "point {i} pushes and moves along its normal: {v}");
                if v.xy().norm() > 1e-9 && mu > 0.0 {
                    // Sliding: friction on the rim, against the slip.
                    assert!((l.xy() / l.xy().norm() + v.xy() / v.xy().norm()).norm() < 1e-6 && (l.xy().norm() - mu * l[2]).abs() < 1e-9);
                }
            }
        }
        // The impact dissipates: ½ uᵀHu does not grow.
        let ud = DVector::from_column_slice(&u);
        assert!(a.u_after.dot(&(&h * &a.u_after)) <= ud.dot(&(&h * &ud)) + 1e-12);
    }
}

#[test]
fn bad_input_is_refused_and_an_exhausted_solver_says_so() {
    let model = sliders();
    let mut data = Data::new(&model);
    let x = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.4, 0.0];
    let u = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.4, 1.0];
    let p = ContactPoint { body: [0, 2], point: Vector3::new(0.5, 0.0, 0.0), normal: Vector3::x(), friction: 0.5 };
    let err = |points: &[ContactPoint], s: &ImpactSpec| rigid_impact(&model, &mut Data::new(&model), &x, &u, points, s).unwrap_err().to_string();
    assert!(err(&[ContactPoint { normal: Vector3::new(2.0, 0.0, 0.0), ..p }], &ImpactSpec::default()).contains("unit vector"));
    assert!(err(&[ContactPoint { friction: -1.0, ..p }], &ImpactSpec::default()).contains("friction"));
    assert!(err(&[ContactPoint { body: [2, 2], ..p }], &ImpactSpec::default()).contains("itself"));
    assert!(err(&[ContactPoint { body: [0, 9], ..p }], &ImpactSpec::default()).contains("body index 9"));
    assert!(err(&[], &ImpactSpec::default()).contains("no contact point"));
    assert!(err(&[p], &ImpactSpec { restitution: 1.5, ..ImpactSpec::default() }).contains("restitution"));
    assert!(err(&[p], &ImpactSpec { tolerance: 0.0, ..ImpactSpec::default() }).contains("tolerance"));
    let spec: ImpactSpec = toml::from_str("solver = \"pgs\"\nrestitution = 0.2").unwrap();
    assert_eq!((spec.solver, spec.restitution, spec.max_iterations), (ImpactSolver::Pgs, 0.2, 1000));
    assert!(toml::from_str::<ImpactSpec>("solver = \"lemke\"").is_err());
    // One iteration cannot reach 1e-13: reported, not hidden.
    let r = rigid_impact(&model, &mut data, &x, &u, &[p], &ImpactSpec { max_iterations: 1, tolerance: 1e-13, ..ImpactSpec::default() }).unwrap();
    assert!(!r.solution.converged && r.solution.iterations == 1 && r.solution.residual.max() > 1e-13, "{:?}", r.solution);
}
