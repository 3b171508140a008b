"""Plan a maneuver, re-simulate it and print the accuracy and the cost, for one build:
``PYTHONPATH=<python dir> python benchmarks/plan_resim.py [--case planar4|spatial6]``.

``planar4``: to (3.364, 0.4, 0) over 3 s with 15 nodes (docs/optimal-control.md); the median of
``--repeat`` re-simulations is quoted. ``spatial6``: the command line's default plan,
``spacearm plan spatial6 --to=2.5203,0.2,0.20607`` (T = 4 s, 20 nodes, the default Hessian), the
case of issue 26. Both print IPOPT's status, iterations, wall and CPU time of the whole call, the
planned base rotation, and — computed here from ``Plan.resimulate()``, so that builds before the
plan checks existed compare — the re-simulated point's distance from the target and the largest
angle between the re-simulated and the planned base attitude at the knots, plus the open-loop
error: the plan's torques integrated from its initial state by RK4 at 32 times its own steps.
The CPU time (``time.process_time``) is the number to compare on a shared machine.
"""

from __future__ import annotations

import argparse
import ast
import statistics
import time
import warnings

import numpy as np

import spacearm
from spacearm.casadi import rk4_step
from spacearm.plan import point_to_point
from spacearm.plan.result import attitude_angle

CASES = {
    "planar4": (spacearm.presets.planar4, (3.364, 0.4, 0.0), {"duration": 3.0, "nodes": 15}),
    "spatial6": (spacearm.presets.spatial6, (2.5203, 0.2, 0.20607), {}),
}


def angles_between(qa, qb):
    return 2.0 * np.arccos(np.clip(np.abs(np.sum(qa * qb, axis=1)), 0.0, 1.0))


def open_loop_error(robot, plan, refine=32):
    """Distance (m) from the target of the plan's torques integrated open loop, finely."""
    step = rk4_step(robot, refine * plan.substeps, torque="linear")
    x, u = plan.x[0], plan.u[0]
    for k in range(len(plan.t) - 1):
        xn, un = step(x, u, plan.tau[k], plan.tau[k + 1], np.zeros(6), plan.t[k + 1] - plan.t[k])
        x, u = np.ravel(np.array(xn)), np.ravel(np.array(un))
    return float(np.linalg.norm(robot.point_position(x) - plan.target))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--case", choices=sorted(CASES), default="planar4")
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--option", action="append", default=[], metavar="NAME=VALUE",
                    help="a point_to_point keyword (Python literal or string), e.g. hessian=exact")
    ns = ap.parse_args()
    make, target, options = CASES[ns.case]
    options = dict(options)
    for item in ns.option:
        name, _, text = item.partition("=")
        try:
            options[name] = ast.literal_eval(text)
        except (ValueError, SyntaxError):
            options[name] = text
    robot = make()
    wall, cpu = time.perf_counter(), time.process_time()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        plan = point_to_point(robot, target, **options)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    times = []
    for _ in range(ns.repeat):
        t0 = time.perf_counter()
        traj = plan.resimulate()
        times.append(time.perf_counter() - t0)
    knots = np.searchsorted(traj.t, plan.t - 1e-9 * plan.duration)
    p_end = robot.point_position(traj.x[-1])
    att = np.degrees(np.max(angles_between(traj.x[knots, 3:7], plan.x[:, 3:7])))
    print(f"spacearm {spacearm.__file__}, options {options}")
    print(f"joint speeds at the knots: max {np.max(np.abs(plan.u[:, 6:])):.3g} rad/s; torque steps between knots: max "
          f"{np.max(np.abs(np.diff(plan.tau, axis=0))):.3g} N·m")
    print(f"case {ns.case}: IPOPT {plan.status}, {plan.iterations} iterations; point_to_point {wall:.1f} s wall, {cpu:.1f} s CPU; "
          f"success {plan.success}; warnings: {[str(w.message)[:120] for w in caught if 'plan' in str(w.message)]}")
    print(f"plan: max base rotation {np.degrees(np.max(attitude_angle(plan.x[:, 3:7]))):.4g} deg, "
          f"final point error {np.linalg.norm(robot.point_position(plan.x[-1]) - plan.target):.3e} m")
    print(f"resimulate: median {statistics.median(times) * 1e3:.1f} ms over {ns.repeat} (min {min(times) * 1e3:.1f}), {len(traj.t)} samples")
    print(f"re-simulation: final point error {np.linalg.norm(p_end - plan.target):.3e} m, base attitude vs plan {att:.3e} deg (max at the knots)")
    print(f"open loop (plan torques, RK4 at 1/32 of the plan's step): final point error {open_loop_error(robot, plan):.3e} m")


if __name__ == "__main__":
    main()
