#!/usr/bin/env python
"""spacearm's DDP (spacearm.mpc.solve: the core's box-FDDP on its RK4 step and exact
derivatives) against CasADi/IPOPT on the same problem (single shooting on
spacearm.casadi.rk4_step, the same cost and torque bound; exact Hessian, and the
limited-memory Hessian of examples/mpc_receding_horizon.py): planar4, a joint goal, horizon
``--horizon`` steps of ``--dt`` s.

Interleaved rounds (one solve of each per round, in turn), cold solves from zero torques, plus
spacearm's warm-started solve (from its own solution of a goal moved by 1 mrad: one MPC step);
prints medians, minima, ratios and the optimum each reached (they must agree).

``--spatial6``: issue 36's receding-horizon case instead — spatial6, a joint goal, 50 knots of
20 ms, |tau| <= 5 N·m: the cold solve, the warm solve (from the solution of a goal moved by
1 mrad), and the native law ``spacearm.control.MPC`` run in closed loop (RK4 at the law's 20 ms,
``--law-iterations`` per sample: 3, and 1 — one iteration per sample, the real-time iteration
scheme), whose recorded per-sample solve times (``solve_time``; the first sample is cold) give the
median and 99th percentile of the warm-started solves in the loop; then the ratios to issue 36's
targets (warm median <= 1 ms, p99 <= 3 ms, cold <= 20 ms) and the load average.
``--discretization rk4 euler``: the same with the semi-implicit Euler step (one derivative
evaluation per knot; a model that differs from the RK4 plant, docs/mpc.md).

    python benchmarks/mpc_ddp.py --rounds 20
    python benchmarks/mpc_ddp.py --spatial6 --rounds 10
"""

import argparse
import math
import time

import numpy as np

import spacearm
import spacearm.mpc as mpc

W_Q, W_QD, W_C, W_QT, W_QDT = 1.0, 0.1, 1e-3, 100.0, 10.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=20)
    parser.add_argument("--horizon", type=int, default=10)
    parser.add_argument("--dt", type=float, default=0.1)
    parser.add_argument("--limit", type=float, default=0.5, help="torque bound, N·m (inf: none)")
    parser.add_argument("--spatial6", action="store_true", help="the spatial6, T = 50 receding-horizon case (no IPOPT)")
    parser.add_argument("--law-iterations", type=int, nargs="+", default=[3, 1],
                        help="--spatial6: the native law's max_iterations per sample (one closed loop for each)")
    parser.add_argument("--discretization", choices=["rk4", "euler"], nargs="+", default=["rk4"],
                        help="--spatial6: the problem's step, rk4 (default) or euler (several: one run after the other)")
    args = parser.parse_args()
    if args.spatial6:
        for kind in args.discretization:
            spatial6_case(args.rounds, args.law_iterations, kind)
        return
    import casadi as ca
    import spacearm.casadi as sc

    robot = spacearm.presets.planar4()
    n, t, dt = robot.n_dof, args.horizon, args.dt
    goal = robot.initial_q + np.array([0.4, -0.3, 0.3, -0.2])

    def problem(g):
        return mpc.Problem(horizon=t, dt=dt, running=[mpc.JointCost(W_Q, g, weight_qd=W_QD), mpc.ControlCost(W_C)],
                           terminal=[mpc.JointCost(W_QT, g, weight_qd=W_QDT)], control_limit=args.limit)

    step = sc.rk4_step(robot)
    taus = ca.MX.sym("tau", n, t)
    x, u = ca.DM(robot.neutral_configuration()), ca.DM(robot.zero_velocity())
    cost = 0
    for k in range(t):
        cost += dt * (0.5 * W_Q * ca.sumsqr(x[7:] - goal) + 0.5 * W_QD * ca.sumsqr(u[6:]) + 0.5 * W_C * ca.sumsqr(taus[:, k]))
        x, u = step(x, u, taus[:, k], ca.DM.zeros(6), dt)
    cost += 0.5 * W_QT * ca.sumsqr(x[7:] - goal) + 0.5 * W_QDT * ca.sumsqr(u[6:])
    bound = args.limit if math.isfinite(args.limit) else ca.inf
    solvers = {}
    for name, hess in (("IPOPT exact Hessian", "exact"), ("IPOPT limited-memory", "limited-memory")):
        solvers[name] = ca.nlpsol(hess.replace("-", "_"), "ipopt", {"x": ca.vec(taus), "f": cost}, {"print_time": False, "ipopt": {
            "print_level": 0, "sb": "yes", "tol": 1e-8, "max_iter": 500, "hessian_approximation": hess}})

    p, p_moved = problem(goal), problem(goal + 1e-3)
    previous = mpc.solve(robot, p_moved)
    times = {k: [] for k in ["spacearm DDP (cold)", "spacearm DDP (warm)", *solvers]}
    optimum = {}
    for _ in range(args.rounds):
        start = time.perf_counter()
        sol = mpc.solve(robot, p)
        times["spacearm DDP (cold)"].append(time.perf_counter() - start)
        optimum["spacearm DDP (cold)"] = (sol.cost, sol.iterations, sol.stop)
        start = time.perf_counter()
        warm = mpc.solve(robot, p, warm_start=previous)
        times["spacearm DDP (warm)"].append(time.perf_counter() - start)
        optimum["spacearm DDP (warm)"] = (warm.cost, warm.iterations, warm.stop)
        for name, s in solvers.items():
            start = time.perf_counter()
            res = s(x0=np.zeros(n * t), lbx=-bound, ubx=bound)
            times[name].append(time.perf_counter() - start)
            optimum[name] = (float(res["f"]), s.stats()["iter_count"], s.stats()["return_status"])
    base = np.median(times["spacearm DDP (cold)"])
    print(f"planar4, horizon {t} x {dt:g} s, |tau| <= {args.limit:g}, {args.rounds} interleaved rounds (wall time per solve)")
    print(f"{'solver':28s} {'median':>10s} {'min':>10s} {'/ DDP cold':>11s}   cost, iterations, status")
    for name, ts in times.items():
        ts = np.array(ts) * 1e3
        c, it, st = optimum[name]
        print(f"{name:28s} {np.median(ts):8.3f}ms {ts.min():8.3f}ms {np.median(ts) / (base * 1e3):10.2f}x   {c:.10g}, {it}, {st}")


TARGETS_MS = {"warm median": 1.0, "warm p99": 3.0, "cold median": 20.0}  # issue 36, one idle core


def spatial6_case(rounds: int, law_iterations: list, discretization: str = "rk4") -> None:
    import os

    from spacearm.control import MPC

    robot = spacearm.presets.spatial6()
    goal = robot.initial_q + np.array([0.2, -0.1, 0.15, 0.1, -0.2, 0.3])

    def problem(g):
        return mpc.Problem(horizon=50, dt=0.02, running=[mpc.JointCost(10.0, g, weight_qd=0.1), mpc.ControlCost(1e-2)],
                           terminal=[mpc.JointCost(100.0, g, weight_qd=1.0)], control_limit=5.0, discretization=discretization)

    p = problem(goal)
    previous = mpc.solve(robot, problem(goal + 1e-3))
    laws = {it: MPC(p, max_iterations=it) for it in law_iterations}
    cold, warm, info = [], [], {}
    loop = {it: [] for it in law_iterations}
    for _ in range(rounds):
        start = time.perf_counter()
        sol = mpc.solve(robot, p)
        cold.append(time.perf_counter() - start)
        info["cold"] = (sol.cost, sol.iterations, sol.stop)
        start = time.perf_counter()
        w = mpc.solve(robot, p, warm_start=previous)
        warm.append(time.perf_counter() - start)
        info["warm"] = (w.cost, w.iterations, w.stop)
        for it, law in laws.items():
            traj = spacearm.simulate(robot, 1.0, dt=0.02, controller=law)
            loop[it].extend(traj["solve_time"][1:-1])  # the samples after the cold first; the last row repeats the one before
            info[it] = (float(np.abs(traj.x[-1, 7:] - goal).max()), float(np.mean(traj["solve_iterations"][1:-1])),
                        float(np.mean(traj["solve_converged"][1:-1])))
    ms = lambda v: np.asarray(v) * 1e3  # noqa: E731
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"spatial6, horizon 50 x 20 ms, |tau| <= 5 N·m, {discretization} steps, {rounds} interleaved rounds"
          f" (wall time per solve; load average {load:.2f})")
    for name, ts in (("cold solve", cold), ("warm solve (goal moved 1 mrad)", warm)):
        c, it, st = info["cold" if name.startswith("cold") else "warm"]
        print(f"{name:34s} median {np.median(ms(ts)):8.3f} ms  p99 {np.percentile(ms(ts), 99):8.3f} ms  min {ms(ts).min():8.3f} ms"
              f"   cost {c:.10g}, {it} iterations, {st}")
    for it, ts in loop.items():
        err, iters, conv = info[it]
        print(f"{f'native law, {it} iteration(s) max':34s} median {np.median(ms(ts)):8.3f} ms  p99 {np.percentile(ms(ts), 99):8.3f} ms"
              f"   ({len(ts)} warm-started samples: mean {iters:.2f} iterations, {100 * conv:.0f}% converged;"
              f" joint error after 1 s {err:.2e} rad)")
    print("ratios to issue 36's targets (warm median <= 1 ms, warm p99 <= 3 ms, cold median <= 20 ms; < 1: met):")
    print(f"  cold median / 20 ms: {np.median(ms(cold)) / TARGETS_MS['cold median']:.2f}")
    for it, ts in loop.items():
        print(f"  native law ({it} max): median / 1 ms: {np.median(ms(ts)) / TARGETS_MS['warm median']:.2f},"
              f"  p99 / 3 ms: {np.percentile(ms(ts), 99) / TARGETS_MS['warm p99']:.2f}")


if __name__ == "__main__":
    main()
