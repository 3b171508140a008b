"""The figures of docs/optimal-control.md: ``python docs/figures/make_plan_figures.py`` (with
spacearm importable) writes plan_planar4.png and plan_spatial6.png next to this file and prints
the numbers the page quotes.

- planar4: ``spacearm plan planar4 --to=3.364,0.4,0 --duration 3 --nodes 15``;
- spatial6: the command line's default plan, ``spacearm plan spatial6 --to=2.5203,0.2,0.20607``.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

import spacearm
from spacearm.plan import point_to_point

HERE = Path(__file__).resolve().parent


def main() -> None:
    cases = [
        ("plan_planar4.png", spacearm.presets.planar4(), (3.364, 0.4, 0.0), {"duration": 3.0, "nodes": 15}),
        ("plan_spatial6.png", spacearm.presets.spatial6(), (2.5203, 0.2, 0.20607), {}),
    ]
    for name, robot, target, options in cases:
        cpu = time.process_time()
        plan = point_to_point(robot, target, **options)
        cpu = time.process_time() - cpu
        check = plan.verification
        rows = plan.comparison()
        print(f"{name}: IPOPT {plan.status}, {plan.iterations} iterations, {cpu:.1f} s CPU; success {plan.success}")
        print(f"  defect {check.defect:.2e}, RK4 local error estimate {check.transcription_error:.2e}, re-simulation "
              f"{check.point_error:.2e} m from the target, attitude within {np.degrees(check.attitude_error):.2e} deg")
        for label, (t, angle, torque, _) in rows.items():
            effort = np.sum(0.5 * (torque[1:] ** 2 + torque[:-1] ** 2) * np.diff(t))
            print(f"  {label}: max base rotation {np.degrees(np.max(angle)):.3g} deg, final {np.degrees(angle[-1]):.3g} deg, "
                  f"effort {effort:.3g}")
        print(f"  wrote {plan.plot(HERE / name)}")


if __name__ == "__main__":
    main()
