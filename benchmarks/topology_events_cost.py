#!/usr/bin/env python
"""The cost of topology events (docs/events.md): the same RK4 run of spatial6 with a free
target, without events, with three commanded events (attach, release with a push, re-dock) and
with one threshold attach located within its step (the watch evaluated at every step's end).

Interleaved rounds; the figures are medians over ``--repeat`` rounds of the wall time per RK4
step and the ratio to the run without events. The machine's other load shows in the load
average printed at the top.

    python benchmarks/topology_events_cost.py
    python benchmarks/topology_events_cost.py --steps 20000 --repeat 9
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

import spacearm
from spacearm.events import Attach, Detach


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=4000)
    p.add_argument("--repeat", type=int, default=7)
    a = p.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f}; {a.steps} RK4 steps per run, median of {a.repeat}")
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    u0 = robot.zero_velocity()
    u0[0] = 0.02
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    s0 = target.state(position=robot.point_position(x0) + np.array([0.8, 0.0, 0.0]), velocity=(-0.1, 0.0, 0.0),
                      angular_velocity=(0.0, 0.0, 0.02))
    dt = 2e-3
    duration = a.steps * dt
    run = dict(x0=x0, u0=u0, dt=dt, record_every=10)
    with_target = dict(target=target, target_state=s0)
    cases = {
        "no events": dict(),
        "3 commanded events": dict(events=[Attach(at=0.3 * duration), Detach(at=0.6 * duration, impulse=1.0),
                                           Attach(at=0.9 * duration)], **with_target),
        "threshold attach": dict(events=[Attach(gap=0.05)], **with_target),
    }
    times: dict = {k: [] for k in cases}
    for _ in range(a.repeat):
        for name, kw in cases.items():
            t0 = time.perf_counter()
            traj = spacearm.simulate(robot, duration, **run, **kw)
            times[name].append((time.perf_counter() - t0) / a.steps)
            if kw:
                assert len(traj["event_t"]) == len(kw["events"]), (name, traj.meta["events"])
    base = statistics.median(times["no events"])
    for name, ts in times.items():
        m = statistics.median(ts)
        print(f"{name:20s} {m * 1e6:8.2f} µs/step   ratio {m / base:5.2f}")


if __name__ == "__main__":
    main()
