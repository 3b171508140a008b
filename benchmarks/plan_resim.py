"""Time ``Plan.resimulate`` (the plan tracked by computed torque in the native simulator) and
print its accuracy, for one build: ``PYTHONPATH=<python dir> python benchmarks/plan_resim.py``.

The plan is planar4 to (3.364, 0.4, 0) over 3 s with 15 nodes (docs/optimal-control.md); the
median of ``--repeat`` re-simulations is quoted with the final point error and the base-attitude
deviation from the plan.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import spacearm
from spacearm.plan import point_to_point
from spacearm.plan.result import attitude_angle


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=7)
    ns = ap.parse_args()
    robot = spacearm.presets.planar4()
    plan = point_to_point(robot, (3.364, 0.4, 0.0), duration=3.0, nodes=15)
    times = []
    for _ in range(ns.repeat):
        t0 = time.perf_counter()
        traj = plan.resimulate()
        times.append(time.perf_counter() - t0)
    p_end = robot.point_position(traj.x[-1])
    att = np.degrees(np.abs(attitude_angle(traj.x[:, 3:7])[-1] - plan.attitude_change[-1]))
    print(f"spacearm {spacearm.__file__}")
    print(f"resimulate: median {statistics.median(times) * 1e3:.1f} ms over {ns.repeat} (min {min(times) * 1e3:.1f})")
    print(f"final point error {np.linalg.norm(p_end - plan.target):.3e} m, final attitude vs plan {att:.3e} deg, {len(traj.t)} samples")


if __name__ == "__main__":
    main()
