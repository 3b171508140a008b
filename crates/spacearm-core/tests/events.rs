//! Stop conditions in the loop (`SimOptions::stop`, `sim::events`) against closed forms: a gap
//! whose crossing time is analytic (a drifting robot point and a quintic line reference), a
//! condition that never holds (the run is the run without it, bit for bit), a time condition
//! (the run is the run of that duration), a condition holding at t = 0, the earliest of two
//! conditions, and the refusals.

use nalgebra::Vector3;
use spacearm_core::control::{JointTorqueLimit, ResolvedMotionRate, ZeroTorque};
use spacearm_core::model::presets;
use spacearm_core::sim::events::StopCondition;
use spacearm_core::sim::integrate::IntegratorKind;
use spacearm_core::sim::reference::{quintic_scaling, CartesianLine};
use spacearm_core::sim::rollout::{rollout, RolloutSpec};
use spacearm_core::sim::simulate::{simulate, SimOptions, SimResult};
use spacearm_core::{Model, SpacearmError};

/// The drift velocity of the whole robot (base translating, joints at rest), m/s.
const V: [f64; 3] = [0.1, 0.02, 0.0];
/// Line reference: from `p0 + D` to `p0 − D` over `[0, T_LINE]`.
const D: [f64; 3] = [0.5, 0.0, 0.0];
const T_LINE: f64 = 2.0;

struct Setup {
    model: Model,
    x0: Vec<f64>,
    u0: Vec<f64>,
    body: usize,
    offset: Vector3<f64>,
    p0: Vector3<f64>,
}

fn setup() -> Setup {
    let model = presets::spatial6();
    let x0 = presets::initial_configuration(&model);
    let mut u0 = vec![0.0; model.nu()];
    u0[..3].copy_from_slice(&V);
    let ee = model.points()[model.end_effector().unwrap()].clone();
    let mut data = spacearm_core::model::data::Data::new(&model);
    spacearm_core::algorithms::kinematics::forward_kinematics(&model, &mut data, &x0).unwrap();
    let p0 = spacearm_core::algorithms::kinematics::point_position(&data, ee.body, &ee.offset);
    Setup { model, x0, u0, body: ee.body, offset: ee.offset, p0 }
}

/// RMRC on the end effector along the line, its torques clamped to ±1e-300: the robot drifts
/// freely (every body at `V`), so the point is `p0 + V t` and the reference `p0 + D (1 − 2 s(t))`.
fn controller(s: &Setup) -> JointTorqueLimit {
    let d = Vector3::from(D);
    let line = CartesianLine::new(s.p0 + d, s.p0 - d, 0.0, T_LINE).unwrap();
    JointTorqueLimit::new(Box::new(ResolvedMotionRate::new(line, 2.0, 0.05, 0.05, 20.0, s.body, s.offset)), 1e-300)
}

/// The closed-form gap `|p_ref(t) − p(t)|`.
fn gap_exact(t: f64) -> f64 {
    let (sc, _, _) = quintic_scaling(t, 0.0, T_LINE);
    let d = Vector3::from(D);
    (d * (1.0 - 2.0 * sc) - Vector3::from(V) * t).norm()
}

/// The first time the closed-form gap falls to `tol`, by bisection (it falls monotonically on
/// `[0, 0.9]` here: its least, ~0.018 m, is near 0.9 s).
fn crossing_exact(tol: f64) -> f64 {
    let (mut a, mut b) = (0.0, 0.9);
    assert!(gap_exact(a) > tol && gap_exact(b) < tol);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if gap_exact(m) > tol {
            a = m;
        } else {
            b = m;
        }
    }
    b
}

fn run(s: &Setup, opts: &SimOptions) -> Result<SimResult, SpacearmError> {
    simulate(&s.model, &s.x0, &s.u0, opts, &mut controller(s), &mut |_| Ok(()))
}

fn opts(integrator: IntegratorKind, stop: Vec<StopCondition>) -> SimOptions {
    SimOptions { integrator, duration: 1.5, dt: 0.05, rtol: 1e-10, atol: 1e-12, stop, ..SimOptions::default() }
}

fn gap(s: &Setup, tol: f64) -> StopCondition {
    StopCondition::Gap { body: s.body, offset: [s.offset.x, s.offset.y, s.offset.z], tolerance: tol }
}

#[test]
fn a_gap_event_is_located_at_the_closed_form_crossing() {
    let s = setup();
    let tol = 0.05;
    let t_exact = crossing_exact(tol);
    assert!(t_exact > 0.3 && t_exact < 0.9, "{t_exact}");
    for integrator in [IntegratorKind::Dopri5, IntegratorKind::Rk4] {
        let r = run(&s, &opts(integrator, vec![gap(&s, tol)])).unwrap();
        let stop = r.stop.expect("the gap event fired");
        assert_eq!(stop.condition, 0);
        // The motion is linear in t, which both integrators follow exactly: the located time is
        // the closed form's to rounding.
        assert!((stop.t - t_exact).abs() < 1e-12, "{integrator:?}: {} vs {t_exact}", stop.t);
        assert!(stop.value <= tol && (stop.value - tol).abs() < 1e-12, "{integrator:?}: {}", stop.value);
        // The run ends there: its last sample is the event's, the samples before on the grid.
        let rec = &r.records;
        assert_eq!(*rec.t.last().unwrap(), stop.t);
        assert!(rec.t[rec.n_samples - 2] < stop.t && stop.t - rec.t[rec.n_samples - 2] <= 0.05 + 1e-12);
        assert_eq!(rec.n_samples, (stop.t / 0.05).ceil() as usize + 1, "{integrator:?}");
        // The recorded reference and end effector at the last sample: the gap, from the records.
        let k = rec.n_samples - 1;
        let p_ref = Vector3::from_column_slice(&rec.reference.as_ref().unwrap()[3 * k..3 * k + 3]);
        let p = Vector3::from_column_slice(&rec.ee_position.as_ref().unwrap()[3 * k..3 * k + 3]);
        assert!(((p_ref - p).norm() - stop.value).abs() < 1e-14);
        assert!((p - (s.p0 + Vector3::from(V) * stop.t)).norm() < 1e-12, "the robot drifted freely");
        // The goal is not judged at an event stop.
        assert_eq!(r.goal_unreachable(), Some(false));
    }
}

#[test]
fn a_condition_that_never_holds_changes_nothing() {
    let s = setup();
    for integrator in [IntegratorKind::Dopri5, IntegratorKind::Rk4] {
        let plain = run(&s, &opts(integrator, vec![])).unwrap();
        // The gap stays above 0.05 m until ~0.7 s: a 1e-3 m tolerance within 0.5 s never holds.
        let watched = run(&s, &SimOptions { duration: 0.5, ..opts(integrator, vec![gap(&s, 1e-3)]) }).unwrap();
        let plain_short = run(&s, &SimOptions { duration: 0.5, ..opts(integrator, vec![]) }).unwrap();
        assert!(watched.stop.is_none());
        assert_eq!(watched.records.t, plain_short.records.t);
        assert_eq!(watched.records.x, plain_short.records.x, "{integrator:?}: bit for bit");
        assert_eq!(watched.records.u, plain_short.records.u);
        assert_eq!(plain.stop, None);
        assert_eq!(*plain.records.t.last().unwrap(), 1.5);
    }
}

#[test]
fn a_time_event_is_the_run_of_that_duration() {
    let s = setup();
    for integrator in [IntegratorKind::Dopri5, IntegratorKind::Rk4] {
        let stopped = run(&s, &opts(integrator, vec![StopCondition::Time { t: 0.37 }, StopCondition::Time { t: 0.9 }])).unwrap();
        let short = run(&s, &SimOptions { duration: 0.37, ..opts(integrator, vec![]) }).unwrap();
        let stop = stopped.stop.unwrap();
        assert_eq!((stop.condition, stop.t, stop.value), (0, 0.37, 0.37));
        assert_eq!(*stopped.records.t.last().unwrap(), 0.37);
        assert_eq!(stopped.records.t, short.records.t);
        assert_eq!(stopped.records.x, short.records.x, "{integrator:?}: bit for bit");
        // Beyond the duration: never.
        let long = run(&s, &opts(integrator, vec![StopCondition::Time { t: 2.0 }])).unwrap();
        assert!(long.stop.is_none());
        assert_eq!(*long.records.t.last().unwrap(), 1.5);
    }
}

#[test]
fn the_earliest_event_wins_and_a_condition_holding_at_the_start_stops_there() {
    let s = setup();
    let (t_wide, t_narrow) = (crossing_exact(0.2), crossing_exact(0.05));
    assert!(t_wide < t_narrow);
    for integrator in [IntegratorKind::Dopri5, IntegratorKind::Rk4] {
        let r = run(&s, &opts(integrator, vec![gap(&s, 0.05), gap(&s, 0.2), StopCondition::Time { t: 1.2 }])).unwrap();
        let stop = r.stop.unwrap();
        assert_eq!(stop.condition, 1, "{integrator:?}");
        assert!((stop.t - t_wide).abs() < 1e-12);
        // The gap at t = 0 is 0.5 m: a 0.6 m tolerance holds at once.
        let r = run(&s, &opts(integrator, vec![gap(&s, 0.6)])).unwrap();
        let stop = r.stop.unwrap();
        assert_eq!((stop.condition, stop.t, r.records.n_samples), (0, 0.0, 1));
        assert!((stop.value - gap_exact(0.0)).abs() < 1e-12);
    }
}

#[test]
fn conditions_are_checked() {
    let s = setup();
    let bad = |stop: Vec<StopCondition>| run(&s, &opts(IntegratorKind::Dopri5, stop)).unwrap_err();
    assert!(matches!(bad(vec![StopCondition::Time { t: -1.0 }]), SpacearmError::InvalidArgument(_)));
    assert!(matches!(bad(vec![StopCondition::Gap { body: 99, offset: [0.0; 3], tolerance: 0.1 }]), SpacearmError::NotFound(_)));
    assert!(matches!(bad(vec![StopCondition::Gap { body: 1, offset: [0.0; 3], tolerance: 0.0 }]), SpacearmError::InvalidArgument(_)));
    // A gap needs a controller with a point reference.
    let e = simulate(&s.model, &s.x0, &s.u0, &opts(IntegratorKind::Dopri5, vec![gap(&s, 0.1)]), &mut ZeroTorque, &mut |_| Ok(())).unwrap_err();
    assert!(e.to_string().contains("tracks no point"), "{e}");
    // Rollouts stack equal-length runs: they refuse stop conditions.
    let spec = RolloutSpec { model: &s.model, x0: &s.x0, u0: &s.u0, controller: Box::new(ZeroTorque) };
    let e = rollout(vec![spec], &opts(IntegratorKind::Rk4, vec![StopCondition::Time { t: 0.5 }]), Some(1)).err().unwrap();
    assert!(e.to_string().contains("rollout does not take stop conditions"), "{e}");
}
