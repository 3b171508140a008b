//! Profile of the FDDP solver on issue 36's receding-horizon case (spatial6, a joint goal, 50
//! knots of 20 ms, |tau| <= 5 N·m; the problem of `benchmarks/mpc_ddp.py --spatial6`): the
//! cold solve, the warm solve (from the solution of a goal moved by 1 mrad) and the parts of
//! one iteration (the linearization of the 50 knots, the backward pass, one rollout), with
//! medians of `--rounds` repetitions. Under `perf record -g` with `cold` or `warm` as the
//! argument it runs only that solve, many times.
//!
//! `cargo run --release -p spacearm-core --example mpc_profile [cold|warm|law|trace] [rounds] [keep|nokeep] [iterations] [euler]`
//! (`law`: 50-sample receding horizons from the same start, `iterations` per sample, default 3)

use std::time::Instant;

use spacearm_core::model::presets;
use spacearm_core::optimal::backward::Backward;
use spacearm_core::optimal::costs::{CostSpec, Numbers};
use spacearm_core::optimal::discretization::DiscretizationKind;
use spacearm_core::optimal::forward::{forward_pass, Trajectory};
use spacearm_core::optimal::shooting::{KnotModel, ShootingProblem};
use spacearm_core::optimal::fddp::{solve_in, Workspace};
use spacearm_core::optimal::{solve, ProblemSpec, RobotProblem, SolverOptions};

fn spec(goal: &[f64], discretization: DiscretizationKind) -> ProblemSpec {
    ProblemSpec {
        horizon: 50,
        dt: 0.02,
        mode: "floating".into(),
        running: vec![
            CostSpec::Joint { weight_q: Numbers::One(10.0), reference: goal.to_vec(), weight_qd: Numbers::One(0.1), velocity_reference: None },
            CostSpec::Control { weights: Numbers::One(1e-2), reference: None },
        ],
        terminal: vec![CostSpec::Joint { weight_q: Numbers::One(100.0), reference: goal.to_vec(), weight_qd: Numbers::One(1.0), velocity_reference: None }],
        control_limit: Numbers::One(5.0),
        start_time: 0.0,
        discretization,
    }
}

/// The `p`-th percentile (0..=100, nearest rank) of `v`.
fn percentile(v: &mut [f64], p: f64) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[(((p / 100.0) * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1]
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

fn main() {
    // `euler` anywhere in the arguments: the semi-implicit Euler step instead of RK4.
    let all: Vec<String> = std::env::args().collect();
    let kind = if all.iter().any(|a| a == "euler") { DiscretizationKind::Euler } else { DiscretizationKind::Rk4 };
    let args: Vec<String> = all.into_iter().filter(|a| a != "euler").collect();
    let which = args.get(1).cloned().unwrap_or_else(|| "all".into());
    let rounds: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20);
    let model = presets::spatial6();
    let n = model.n_dof();
    let offsets = [0.2, -0.1, 0.15, 0.1, -0.2, 0.3];
    let goal: Vec<f64> = model.initial_q().iter().zip(offsets).map(|(q, d)| q + d).collect();
    let moved: Vec<f64> = goal.iter().map(|g| g + 1e-3).collect();
    let mut z0 = vec![0.0; 13 + 2 * n];
    z0[6] = 1.0;
    z0[7..7 + n].copy_from_slice(model.initial_q());
    let mut problem = RobotProblem::new(&model, &spec(&goal, kind), &z0).unwrap();
    let mut previous_problem = RobotProblem::new(&model, &spec(&moved, kind), &z0).unwrap();
    let opts = SolverOptions::default();
    let previous = solve(&mut previous_problem, None, None, &opts).unwrap();
    let (mut cold, mut warm) = (Vec::new(), Vec::new());
    let mut last = None;
    for _ in 0..rounds {
        if which != "warm" {
            let s = Instant::now();
            let sol = solve(&mut problem, None, None, &opts).unwrap();
            cold.push(s.elapsed().as_secs_f64());
            last = Some(("cold", sol.cost, sol.iterations, sol.steps, sol.stop));
        }
        if which != "cold" {
            let s = Instant::now();
            let sol = solve(&mut problem, Some(&previous.zs), Some(&previous.cs), &opts).unwrap();
            warm.push(s.elapsed().as_secs_f64());
            println!("warm: cost {:.12} iterations {} steps {} {:?}", sol.cost, sol.iterations, sol.steps, sol.stop);
        }
    }
    if which == "law" {
        // The native law's warm starts (control::mpc): each sample from the plan's next state,
        // the last solution shifted by a knot, the knot models kept (Workspace::shift).
        let keep = args.get(3).map(|s| s != "nokeep").unwrap_or(true);
        // The most iterations per sample (default 3; 1: the real-time iteration scheme).
        let per_sample: usize = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(3);
        let mut times = Vec::new();
        let mut iterations = 0;
        for _ in 0..rounds {
            let mut ws = Workspace::new(&problem);
            problem.set_initial_state(&z0).unwrap();
            let mut sol = solve_in(&mut ws, &mut problem, None, None, &opts).unwrap();
            for _ in 0..49 {
                let t = sol.cs.len();
                let mut zs = sol.zs.clone();
                let mut cs = sol.cs.clone();
                zs.rotate_left(1);
                cs.rotate_left(1);
                zs[t] = zs[t - 1].clone();
                cs[t - 1] = cs[t - 2].clone();
                problem.set_initial_state(&zs[0]).unwrap();
                if keep {
                    ws.shift(1);
                }
                let s = Instant::now();
                sol = solve_in(&mut ws, &mut problem, Some(&zs), Some(&cs), &SolverOptions { max_iterations: per_sample, ..opts }).unwrap();
                times.push(s.elapsed().as_secs_f64());
                iterations += sol.iterations;
            }
        }
        let n = times.len();
        println!(
            "law-like warm solves (keep {keep}, at most {per_sample} iterations): median {:.3} ms, p99 {:.3} ms, mean iterations {:.2}",
            1e3 * median(&mut times),
            1e3 * percentile(&mut times, 99.0),
            iterations as f64 / n as f64
        );
        return;
    }
    if which == "trace" {
        for (name, zs, cs) in [("cold", None, None), ("warm", Some(previous.zs.as_slice()), Some(previous.cs.as_slice()))] {
            for it in 1..10 {
                let o = SolverOptions { max_iterations: it, ..opts };
                let sol = solve(&mut problem, zs, cs, &o).unwrap();
                println!("{name} max_it {it}: cost {:.15} d_g(pre-step) {:.3e} steps {} mu {:e} {:?}", sol.cost, sol.expected_decrease, sol.steps, sol.regularization, sol.stop);
                if sol.stop == spacearm_core::optimal::StopReason::Converged {
                    break;
                }
            }
        }
        return;
    }
    if let Some(l) = last {
        println!("{l:?}");
    }
    if !cold.is_empty() {
        println!("cold median {:.3} ms, p99 {:.3} ms", 1e3 * median(&mut cold), 1e3 * percentile(&mut cold, 99.0));
    }
    if !warm.is_empty() {
        println!("warm median {:.3} ms, p99 {:.3} ms", 1e3 * median(&mut warm), 1e3 * percentile(&mut warm, 99.0));
    }
    if which != "all" {
        return;
    }
    // The parts of one iteration at the warm start.
    let (t, nd, m) = (problem.horizon(), problem.nd(), problem.nc());
    let mut traj = Trajectory::zeros(&problem);
    traj.zs.clone_from(&previous.zs);
    traj.cs.clone_from(&previous.cs);
    let mut trial = traj.clone();
    let mut knots = vec![KnotModel::zeros(nd, m); t + 1];
    let gaps = vec![nalgebra::DVector::zeros(nd); t + 1];
    let mut bw = Backward::new(t, nd, m);
    let (lo, hi) = (problem.lower().to_vec(), problem.upper().to_vec());
    let (mut lin, mut back, mut fwd, mut plain) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for _ in 0..rounds {
        let s = Instant::now();
        for k in 0..t {
            problem.running_with_derivatives(k, &traj.zs[k], &traj.cs[k], &mut traj.next[k], &mut knots[k]).unwrap();
        }
        problem.terminal_derivatives(&traj.zs[t], &mut knots[t]).unwrap();
        lin.push(s.elapsed().as_secs_f64());
        let s = Instant::now();
        assert!(bw.run(&knots, &gaps, &traj.cs, &lo, &hi, 1e-9, true));
        back.push(s.elapsed().as_secs_f64());
        let s = Instant::now();
        forward_pass(&mut problem, &traj, &gaps, &bw, 1.0, true, &mut trial).unwrap();
        fwd.push(s.elapsed().as_secs_f64());
        let s = Instant::now();
        let mut next = vec![0.0; problem.nz()];
        for k in 0..t {
            problem.running(k, &traj.zs[k], &traj.cs[k], &mut next).unwrap();
        }
        plain.push(s.elapsed().as_secs_f64());
    }
    println!(
        "per iteration: linearization (50 knots, RK4 with Jacobians) {:.3} ms, backward pass {:.3} ms, one rollout {:.3} ms (50 RK4 steps + costs: {:.3} ms)",
        1e3 * median(&mut lin),
        1e3 * median(&mut back),
        1e3 * median(&mut fwd),
        1e3 * median(&mut plain)
    );
}
