"""The N-link chain the benchmarks scale over (casadi_build.py, mpc_crocoddyl.py): a 500 kg base,
links of 2 kg and 0.3 m whose axes cycle through z, y, x, the end effector 0.15 m past the last."""

import numpy as np

import spacearm


def chain(n: int) -> spacearm.Robot:
    b = spacearm.Robot.builder(f"chain{n}", 500.0, np.diag([50.0, 60.0, 70.0]))
    for i in range(n):
        b.add_link(f"l{i}", parent="base" if i == 0 else f"l{i - 1}", axis=[(0, 0, 1), (0, 1, 0), (1, 0, 0)][i % 3],
                   origin=(0.3, 0, 0) if i else (1.0, 0, 0), com=(0.15, 0, 0), mass=2.0, inertia=[0.01, 0.02, 0.02])
    b.add_point("tip", body=f"l{n - 1}", offset=(0.15, 0, 0))
    b.set_end_effector("tip")
    return b.build()
