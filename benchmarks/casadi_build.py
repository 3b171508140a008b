"""Build and evaluation time of spacearm.casadi's Functions against N (serial chains of
revolute joints), and the planner's solve time with the two Hessian options.

    python benchmarks/casadi_build.py            # N = 6, 12, 30
    python benchmarks/casadi_build.py --plan     # also planar4 plans: objective vs exact Hessian

Prints medians of repeated builds (a build is the core recording its recursions on a tape and
the replay of that tape on fresh SX symbols, spacearm/casadi/_tape.py), the part of it spent
recording in the core, the tape's size, and medians of evaluations at one random state with the
core's time for the same quantity.

    python benchmarks/casadi_build.py --sizes 30 --repeat 7    # the 30-DOF row of docs/optimal-control.md
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import spacearm
import spacearm.casadi as sc
from _chain import chain


def median_time(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def builds(sizes, repeat: int = 3) -> None:
    print(f"{'N':>3} {'function':<22} {'build (s)':>10} {'record (s)':>10} {'tape nodes':>10} {'eval (µs)':>10} {'core (µs)':>10} "
          f"{'SX instr.':>10}")
    for n in sizes:
        robot = chain(n)
        rng = np.random.default_rng(0)
        x = robot.neutral_configuration(q=rng.uniform(-1, 1, n))
        u = rng.normal(size=robot.nu)
        tau = rng.normal(size=n)
        cases = {
            "forward_dynamics": (sc.forward_dynamics, (x, u, tau, np.zeros(6)), lambda: robot.forward_dynamics(x, u, tau=tau)),
            "inverse_dynamics": (sc.inverse_dynamics, (x, u, u), lambda: robot.inverse_dynamics(x, u, u)),
            "mass_matrix": (sc.mass_matrix, (x,), lambda: robot.mass_matrix(x)),
            "generalized_inertia": (sc.generalized_inertia, (x,), lambda: robot.generalized_inertia(x)),
            "generalized_jacobian": (sc.generalized_jacobian, (x,), lambda: robot.generalized_jacobian(x)),
        }
        for name, (build, args, core) in cases.items():
            t_build = median_time(lambda: build(robot), repeat)
            body, offset = robot._point(None) if name == "generalized_jacobian" else (None, None)
            t_record = median_time(lambda: robot._m.tape(name, body, offset), repeat)
            nodes = len(robot._m.tape(name, body, offset).ops)
            f = build(robot)
            t_eval = median_time(lambda: f(*args), 50)
            t_core = median_time(core, 50)
            print(f"{n:>3} {name:<22} {t_build:>10.3f} {t_record:>10.4f} {nodes:>10} {1e6 * t_eval:>10.1f} {1e6 * t_core:>10.1f} "
                  f"{f.n_instructions():>10}")
        print(f"{n:>3} {'rk4_step':<22} {median_time(lambda: sc.rk4_step(robot), repeat):>10.3f}")


def plans() -> None:
    from spacearm.plan import point_to_point

    robot = spacearm.presets.planar4()
    target = robot.point_position(robot.neutral_configuration()) + np.array([-0.3, 0.4, 0.0])
    for hessian in ("objective", "exact"):
        t = time.perf_counter()
        plan = point_to_point(robot, target, duration=3.0, nodes=15, hessian=hessian)
        total = time.perf_counter() - t
        print(f"planar4, K = 15, attitude, hessian={hessian}: {plan.status}, {plan.iterations} iterations, "
              f"IPOPT {plan.solve_time:.2f} s, total {total:.2f} s")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="6,12,30")
    parser.add_argument("--repeat", type=int, default=3, help="builds per median")
    parser.add_argument("--plan", action="store_true")
    args = parser.parse_args()
    builds([int(v) for v in args.sizes.split(",")], args.repeat)
    if args.plan:
        plans()
