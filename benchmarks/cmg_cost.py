#!/usr/bin/env python
"""The cost of a CMG against a reaction wheel (docs/cmg.md): the spatial6 servicer with a 4-CMG
pyramid (eight more degrees of freedom: a gimbal and a rotor each) against the same arm with 4
reaction wheels on the pyramid's spin axes (four more), and the bare arm.

Per call, through the Python API: the mass matrix H (``Robot.mass_matrix``), the forward
dynamics (``Robot.forward_dynamics``) and one RK4 step (``Simulator.step``, timed over ``--steps``
steps in one call so the per-call overhead is spread). Interleaved rounds; the figures are
medians over ``--repeat`` rounds, with the CMG/wheel ratio of the medians and of the minima (the
minimum is the steadier figure on a loaded machine). The machine's other load shows in
the load average printed at the top.

    python benchmarks/cmg_cost.py
    python benchmarks/cmg_cost.py --calls 5000 --steps 5000 --repeat 9
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

import spacearm

BETA = np.arccos(1 / np.sqrt(3))  # the pyramid's skew angle
AZ = np.arange(4) * np.pi / 2


def with_cmgs() -> spacearm.Robot:
    b = spacearm.presets.spatial6().to_builder("cmgs")
    for i, a in enumerate(AZ):
        b.add_cmg(f"cmg{i + 1}", gimbal_axis=[np.sin(BETA) * np.cos(a), np.sin(BETA) * np.sin(a), np.cos(BETA)],
                  spin_axis=[-np.sin(a), np.cos(a), 0], rotor_inertia=0.05, gimbal_inertia=0.02, rotor_mass=3.0,
                  gimbal_mass=1.5)
    return b.build()


def with_wheels() -> spacearm.Robot:
    b = spacearm.presets.spatial6().to_builder("wheels")
    for a in AZ:  # the pyramid's spin axes at zero gimbal angle, the same rotors
        b.add_reaction_wheel([-np.sin(a), np.cos(a), 0], rotor_inertia=0.05, mass=3.0)
    return b.build()


def states(robot: spacearm.Robot, rng, k: int = 16):
    """``k`` random states and torques, cycled through so that no call can reuse the last one's work."""
    xs = [robot.neutral_configuration(q=robot.initial_q + 0.3 * rng.standard_normal(robot.n_dof)) for _ in range(k)]
    us = [0.1 * rng.standard_normal(6 + robot.n_dof) for _ in range(k)]
    return xs, us, [0.1 * rng.standard_normal(robot.n_dof) for _ in range(k)]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--calls", type=int, default=2000)
    p.add_argument("--steps", type=int, default=2000)
    p.add_argument("--repeat", type=int, default=7)
    a = p.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f}; {a.calls} calls, {a.steps} RK4 steps per round, median of {a.repeat}")
    rng = np.random.default_rng(0)
    robots = {"arm only": spacearm.presets.spatial6(), "4 wheels": with_wheels(), "4 CMGs": with_cmgs()}
    cases = {}
    for name, robot in robots.items():
        xs, us, taus = states(robot, rng)
        cases[name] = (robot, xs, us, taus, spacearm.Simulator(robot, dt=1e-3))
    ops = ("H", "forward dynamics", "RK4 step")
    times = {(n, op): [] for n in robots for op in ops}
    for _ in range(a.repeat):
        for name, (robot, xs, us, taus, sim) in cases.items():
            k = len(xs)
            t0 = time.perf_counter()
            for i in range(a.calls):
                robot.mass_matrix(xs[i % k])
            times[name, "H"].append((time.perf_counter() - t0) / a.calls)
            t0 = time.perf_counter()
            for i in range(a.calls):
                robot.forward_dynamics(xs[i % k], us[i % k], tau=taus[i % k])
            times[name, "forward dynamics"].append((time.perf_counter() - t0) / a.calls)
            sim.reset(xs[0], us[0])
            t0 = time.perf_counter()
            sim.step(taus[0], n=a.steps)
            times[name, "RK4 step"].append((time.perf_counter() - t0) / a.steps)
    print(f"{'':18s}" + "".join(f"{n + ' (N=' + str(r.n_dof) + ')':>22s}" for n, r in robots.items())
          + "   CMGs / wheels (median, min)")
    for op in ops:
        med = {n: statistics.median(times[n, op]) for n in robots}
        low = {n: min(times[n, op]) for n in robots}
        print(f"{op:18s}" + "".join(f"{med[n] * 1e6:19.2f} µs" for n in robots)
              + f"   {med['4 CMGs'] / med['4 wheels']:6.2f} {low['4 CMGs'] / low['4 wheels']:6.2f}")

if __name__ == "__main__":
    main()
