//! The simulation core against independent references: the integrators' convergence order
//! (RK4 error ratio ≈ 16 when halving dt), DOPRI5 against a much finer RK4 run, determinism,
//! the quaternion norm, the modes' wrench masks checked by the whole system's Newton–Euler
//! laws (dP/dt = F0, dL/dt = applied couple: closed forms independent of the ABA), and
//! actuator saturation.

mod common;

use nalgebra::Vector3;
use spacearm_core::sim::actuators::{SaturationKind, ThrusterLimits};
use spacearm_core::control::{Command, ComputedTorque, Controller, ZeroTorque};
use spacearm_core::sim::integrate::IntegratorKind;
use spacearm_core::sim::modes::{Conserved, Mode};
use spacearm_core::model::presets;
use spacearm_core::sim::reference::JointReference;
use spacearm_core::sim::simulate::{simulate, SimOptions, SimResult};
use spacearm_core::{JointLimits, JointType, LinkSpec, Model, ModelBuilder};

/// A constant command: joint torques and a base wrench.
fn constant(tau: Vec<f64>, wrench: [f64; 6]) -> common::Scripted<impl FnMut(f64, &mut Command)> {
    common::Scripted {
        name: "constant",
        command: move |_, out: &mut Command| {
            out.tau.copy_from_slice(&tau);
            out.base_wrench = nalgebra::Vector6::from_column_slice(&wrench);
        },
    }
}

/// spatial6 tumbling with every joint moving (non-zero momentum).
fn tumbling_state(model: &Model) -> (Vec<f64>, Vec<f64>) {
    let x = presets::initial_configuration(model);
    let mut u = vec![0.05, -0.03, 0.02, 0.2, -0.3, 0.25];
    u.extend((0..model.n_dof()).map(|i| 0.8 * (1.0 + i as f64).cos()));
    (x, u)
}

fn run(model: &Model, x0: &[f64], u0: &[f64], opts: &SimOptions, c: &mut dyn Controller) -> SimResult {
    simulate(model, x0, u0, opts, c, &mut |_| Ok(())).unwrap()
}

fn last_row(v: &[f64], width: usize) -> &[f64] {
    &v[v.len() - width..]
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

fn rk4_final(model: &Model, dt: f64, duration: f64) -> Vec<f64> {
    let (x0, u0) = tumbling_state(model);
    let opts = SimOptions { duration, dt, record_every: 1_000_000, ..SimOptions::default() };
    let r = run(model, &x0, &u0, &opts, &mut ZeroTorque);
    let mut y = last_row(&r.records.x, model.nx()).to_vec();
    y.extend_from_slice(last_row(&r.records.u, model.nu()));
    y
}

#[test]
fn rk4_converges_with_order_four() {
    let model = presets::spatial6();
    let reference = rk4_final(&model, 1.0 / 1280.0, 0.5);
    let e1 = max_abs_diff(&rk4_final(&model, 1.0 / 80.0, 0.5), &reference);
    let e2 = max_abs_diff(&rk4_final(&model, 1.0 / 160.0, 0.5), &reference);
    let e3 = max_abs_diff(&rk4_final(&model, 1.0 / 320.0, 0.5), &reference);
    assert!(e1 > 1e-9, "coarse error {e1:e} too small to measure an order");
    let (r1, r2) = (e1 / e2, e2 / e3);
    println!("RK4 errors {e1:e} {e2:e} {e3:e}, ratios {r1:.2} {r2:.2}");
    for r in [r1, r2] {
        assert!((r - 16.0).abs() < 2.0, "error ratio {r:.2} when halving dt (order 4 gives 16)");
    }
}

#[test]
fn dopri5_meets_its_tolerance_against_a_fine_rk4_run() {
    let model = presets::spatial6();
    let (x0, u0) = tumbling_state(&model);
    let fine = rk4_final(&model, 1.0 / 1280.0, 1.0);
    let mut errors = Vec::new();
    for rtol in [1e-6, 1e-9] {
        let opts = SimOptions { duration: 1.0, dt: 0.05, integrator: IntegratorKind::Dopri5, rtol, atol: rtol * 1e-2, ..SimOptions::default() };
        let r = run(&model, &x0, &u0, &opts, &mut ZeroTorque);
        let mut y = last_row(&r.records.x, model.nx()).to_vec();
        y.extend_from_slice(last_row(&r.records.u, model.nu()));
        let scale = fine.iter().map(|v| v.abs()).fold(0.0, f64::max);
        let err = max_abs_diff(&y, &fine) / scale;
        println!("DOPRI5 rtol {rtol:e}: relative error {err:e}, {} steps, {} rejected", r.n_steps, r.n_rejected);
        assert!(err < 50.0 * rtol, "relative error {err:e} at rtol {rtol:e}");
        assert_eq!(r.records.n_samples, 21);
        errors.push(err);
    }
    assert!(errors[1] < 1e-2 * errors[0], "tightening rtol by 1000 must shrink the error: {errors:?}");
}

#[test]
fn dopri5_dense_output_matches_the_fine_solution_between_steps() {
    let model = presets::spatial6();
    let (x0, u0) = tumbling_state(&model);
    let opts = SimOptions { duration: 1.0, dt: 0.01, integrator: IntegratorKind::Dopri5, rtol: 1e-8, atol: 1e-10, ..SimOptions::default() };
    let dp = run(&model, &x0, &u0, &opts, &mut ZeroTorque);
    println!("DOPRI5 {} steps for {} output samples", dp.n_steps, dp.records.n_samples);
    assert!(dp.n_steps < 80, "steps longer than the output interval expected, got {}", dp.n_steps);
    let rk = run(&model, &x0, &u0, &SimOptions { duration: 1.0, dt: 1.0 / 800.0, record_every: 8, ..SimOptions::default() }, &mut ZeroTorque);
    assert_eq!(dp.records.n_samples, rk.records.n_samples);
    let err = max_abs_diff(&dp.records.x, &rk.records.x);
    println!("dense output vs fine RK4: {err:e}");
    assert!(err < 1e-6, "dense output vs fine RK4 at the output times: {err:e}");
}

#[test]
fn quaternion_norm_stays_one_and_runs_are_bit_identical() {
    let model = presets::spatial6();
    let (x0, mut u0) = tumbling_state(&model);
    u0[3] = 3.0; // fast spin
    let q0 = model.initial_q().to_vec();
    let q1: Vec<f64> = q0.iter().map(|q| q + 0.4).collect();
    for integrator in [IntegratorKind::Rk4, IntegratorKind::Dopri5] {
        let opts = SimOptions { duration: 1.5, dt: 5e-3, integrator, rtol: 1e-8, atol: 1e-10, ..SimOptions::default() };
        let mk = || ComputedTorque::new(vec![50.0], vec![14.0], JointReference::quintic(q0.clone(), q1.clone(), 0.2, 1.2).unwrap(), None);
        let a = run(&model, &x0, &u0, &opts, &mut mk());
        let b = run(&model, &x0, &u0, &opts, &mut mk());
        assert_eq!(a.records, b.records, "{integrator:?}: two runs differ");
        let worst = a.records.x.chunks_exact(model.nx()).map(|x| ((x[3] * x[3] + x[4] * x[4] + x[5] * x[5] + x[6] * x[6]).sqrt() - 1.0).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-12, "{integrator:?}: | |quat| - 1 | reaches {worst:e}");
        // The base really turned (the test is not trivially satisfied).
        let last = last_row(&a.records.x, model.nx());
        assert!((last[6] - x0[6]).abs() > 0.1);
    }
}

/// Row `k` of a recorded (K, 3) array.
fn row3(which: &[f64], k: usize) -> Vector3<f64> {
    Vector3::from_column_slice(&which[3 * k..3 * k + 3])
}

#[test]
fn modes_apply_only_their_wrench_and_obey_newton_euler() {
    let model = presets::spatial6();
    let (x0, u0) = tumbling_state(&model);
    let n = model.n_dof();
    let (f, tq) = ([3.0, -2.0, 1.5], [0.4, 0.7, -0.5]);
    let wrench = [f[0], f[1], f[2], tq[0], tq[1], tq[2]];
    let duration = 0.5;
    let tau: Vec<f64> = (0..n).map(|i| 0.2 * (i as f64 - 2.0)).collect();
    let f = Vector3::from(f);
    let tq = Vector3::from(tq);
    for mode in [Mode::Floating, Mode::RotationFloating, Mode::RotationFlying, Mode::TranslationFlying, Mode::Flying] {
        let opts = SimOptions { mode, duration, dt: 2e-3, ..SimOptions::default() };
        let r = run(&model, &x0, &u0, &opts, &mut constant(tau.clone(), wrench));
        let k_last = r.records.n_samples - 1;
        let p0 = row3(&r.records.linear_momentum, 0);
        let p1 = row3(&r.records.linear_momentum, k_last);
        let l0 = row3(&r.records.angular_momentum_origin, 0);
        let l1 = row3(&r.records.angular_momentum_origin, k_last);
        let lc0 = row3(&r.records.angular_momentum_com, 0);
        let lc1 = row3(&r.records.angular_momentum_com, k_last);
        let applied = &r.records.base_wrench;
        // Newton: dP/dt = F0 applied, so P(T) − P(0) = F T when a force is allowed.
        let expect_dp = if mode.allows_force() { f * duration } else { Vector3::zeros() };
        assert!((p1 - p0 - expect_dp).norm() < 1e-9, "{mode:?}: ΔP = {} expected {}", p1 - p0, expect_dp);
        match mode {
            Mode::Floating | Mode::RotationFloating => {
                assert!(applied.iter().all(|v| *v == 0.0), "{mode:?} applied a base wrench");
                assert!((l1 - l0).norm() < 1e-9);
                assert!(r.dropped_wrench_count > 0 && (r.dropped_wrench_max - (f.norm_squared() + tq.norm_squared()).sqrt()).abs() < 1e-12);
                assert_eq!(r.drift.iter().map(|d| d.0).collect::<Vec<_>>(), vec![Conserved::LinearMomentum, Conserved::AngularMomentumOrigin]);
            }
            Mode::RotationFlying => {
                // Euler: a pure couple N0 changes L about any point by N0 T.
                assert!((l1 - l0 - tq * duration).norm() < 1e-9, "ΔL = {}", l1 - l0);
                assert!((r.dropped_wrench_max - f.norm()).abs() < 1e-12);
                assert_eq!(r.drift.iter().map(|d| d.0).collect::<Vec<_>>(), vec![Conserved::LinearMomentum]);
            }
            Mode::TranslationFlying => {
                // A force through the system CM: no moment about it.
                assert!((lc1 - lc0).norm() < 1e-9, "ΔL_com = {}", lc1 - lc0);
                assert!((l1 - l0).norm() > 0.01, "L about the origin must change");
                for k in [0, k_last / 2, k_last] {
                    let w = &applied[6 * k..6 * k + 6];
                    let com = Vector3::from_column_slice(&r.records.com[3 * k..3 * k + 3]);
                    let r0 = Vector3::from_column_slice(&r.records.x[model.nx() * k..model.nx() * k + 3]);
                    let couple = (com - r0).cross(&f);
                    assert!((Vector3::from_column_slice(&w[3..6]) - couple).norm() < 1e-12);
                }
                assert_eq!(r.drift.iter().map(|d| d.0).collect::<Vec<_>>(), vec![Conserved::AngularMomentumCom]);
                assert!(r.drift[0].1 < 1e-10);
            }
            Mode::Flying => {
                assert!(applied.chunks_exact(6).all(|w| w == wrench), "flying applies the full wrench");
                assert_eq!(r.dropped_wrench_count, 0);
                assert!(r.drift.is_empty());
            }
        }
        for (c, d) in &r.drift {
            assert!(*d < 1e-10, "{mode:?}: drift of {} is {d:e}", c.name());
        }
    }
}

/// A 100 kg base with one reaction wheel about z (rotor 0.05 kg·m², limits 0.2 N·m, 5 rad/s).
fn one_wheel() -> Model {
    let mut b = ModelBuilder::new("wheel", "base", 100.0, [[8.0, 0.0, 0.0], [0.0, 9.0, 0.0], [0.0, 0.0, 10.0]]).unwrap();
    b.add_link(LinkSpec { limits: JointLimits { lower: f64::NEG_INFINITY, upper: f64::INFINITY, velocity: 5.0, effort: 0.2 }, ..LinkSpec::new("wheel1", "base", JointType::Revolute, [0.1, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0], 1.0, [0.03, 0.03, 0.05]) })
    .unwrap();
    b.build().unwrap()
}

#[test]
fn wheel_torque_and_speed_limits_clamp_and_record_events() {
    let model = one_wheel();
    let x0 = presets::initial_configuration(&model);
    let u0 = vec![0.0; model.nu()];
    let dt = 2e-3;
    let opts = SimOptions { mode: Mode::RotationFloating, duration: 2.0, dt, ..SimOptions::default() };
    let r = run(&model, &x0, &u0, &opts, &mut constant(vec![1.0], [0.0; 6]));
    assert_eq!(r.wheel_dofs, vec![0]);
    // Torque limit: hit from the first step, applied torque exactly the limit.
    let first = r.events[0];
    assert_eq!((first.t, first.actuator, first.kind), (0.0, 0, SaturationKind::Torque));
    assert_eq!(r.records.tau[0], 0.2);
    assert_eq!(r.records.tau_cmd[0], 1.0);
    // Speed limit: the relative rate grows at τ (1/I_s + 1/I_zz,base) (a rotor on a free base,
    // closed form), so it reaches 5 rad/s at t = 5 / (0.2 (1/0.05 + 1/10)) ≈ 1.244 s.
    let speed_events: Vec<_> = r.events.iter().filter(|e| e.kind == SaturationKind::Speed).collect();
    assert_eq!(speed_events.len(), 1, "{:?}", r.events);
    let t_expect = 5.0 / (0.2 * (1.0 / 0.05 + 1.0 / 10.0));
    assert!(speed_events[0].t <= t_expect && t_expect - speed_events[0].t < dt, "speed limit reached at {} s, expected {t_expect}", speed_events[0].t);
    let ws = r.records.wheel_speed.as_ref().unwrap();
    let last = *ws.last().unwrap();
    // Held at the limit, overshooting by less than one step of acceleration (the limit acts
    // from the stage at which it is crossed).
    let accel = 0.2 * (1.0 / 0.05 + 1.0 / 10.0);
    assert!(last >= 5.0 && last - 5.0 < accel * dt, "wheel speed held at the limit, got {last}");
    assert!(ws.iter().all(|w| *w < 5.0 + accel * dt));
    assert_eq!(*r.records.tau.last().unwrap(), 0.0);
    // The wheel is internal: the total angular momentum stays zero.
    assert!(r.drift.iter().all(|(_, d)| *d < 1e-9), "{:?}", r.drift);
    let lz = r.records.angular_momentum_origin.chunks_exact(3).map(|l| l[2].abs()).fold(0.0, f64::max);
    assert!(lz < 1e-12);
}

#[test]
fn thruster_limits_clamp_each_axis_and_record_events() {
    let model = presets::planar4();
    let x0 = presets::initial_configuration(&model);
    let u0 = vec![0.0; model.nu()];
    let lim = ThrusterLimits::new(Vector3::new(1.0, 1.0, 1.0), Vector3::new(0.5, 0.5, 0.5)).unwrap();
    let opts = SimOptions { mode: Mode::Flying, duration: 0.1, dt: 1e-3, thrusters: Some(lim), ..SimOptions::default() };
    let r = run(&model, &x0, &u0, &opts, &mut constant(vec![0.0; 4], [3.0, -0.5, 0.0, 0.0, 0.0, -2.0]));
    assert_eq!(&r.records.base_wrench[0..6], &[1.0, -0.5, 0.0, 0.0, 0.0, -0.5]);
    let n = model.n_dof();
    let kinds: Vec<(usize, SaturationKind)> = r.events.iter().map(|e| (e.actuator, e.kind)).collect();
    assert_eq!(kinds, vec![(n, SaturationKind::Thruster), (n + 5, SaturationKind::Thruster)]);
    assert_eq!(r.actuator_names[n], "base_force_x");
}

#[test]
fn bad_options_are_argument_errors() {
    let model = presets::planar4();
    let x0 = presets::initial_configuration(&model);
    let u0 = vec![0.0; model.nu()];
    let bad = |opts: SimOptions| simulate(&model, &x0, &u0, &opts, &mut ZeroTorque, &mut |_| Ok(())).unwrap_err();
    for opts in [
        SimOptions { duration: -1.0, ..SimOptions::default() },
        SimOptions { duration: f64::NAN, ..SimOptions::default() },
        SimOptions { dt: 0.0, ..SimOptions::default() },
        SimOptions { rtol: 0.0, ..SimOptions::default() },
        SimOptions { record_every: 0, ..SimOptions::default() },
    ] {
        assert!(matches!(bad(opts), spacearm_core::SpacearmError::InvalidArgument(_)));
    }
    assert!(matches!(bad(SimOptions { wheels: Some(vec![7]), ..SimOptions::default() }), spacearm_core::SpacearmError::NotFound(_)));
    let mut x_bad = x0.clone();
    x_bad[7] = f64::NAN;
    let e = simulate(&model, &x_bad, &u0, &SimOptions::default(), &mut ZeroTorque, &mut |_| Ok(())).unwrap_err();
    assert!(matches!(e, spacearm_core::SpacearmError::NonFinite { .. }));
}
