"""Draw docs/figures/mpc_law_spatial6.png: the native receding-horizon law (spacearm.control.MPC)
moving spatial6's joints to a goal in free floating — the joint tracking error, the base attitude
disturbance and the solve time per sample (wall clock, so it depends on the machine and its load).

    PYTHONPATH=python python3 docs/figures/make_mpc_figure.py
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import spacearm  # noqa: E402
import spacearm.mpc as mpc  # noqa: E402
from spacearm.control import MPC  # noqa: E402

OUT = Path(__file__).resolve().parent / "mpc_law_spatial6.png"


def main() -> None:
    robot = spacearm.presets.spatial6()
    goal = robot.initial_q + np.array([0.2, -0.1, 0.15, 0.1, -0.2, 0.3])
    problem = mpc.Problem(horizon=50, dt=0.02, running=[mpc.JointCost(10.0, goal, weight_qd=0.1), mpc.ControlCost(1e-2)],
                          terminal=[mpc.JointCost(100.0, goal, weight_qd=1.0)], control_limit=5.0)
    traj = spacearm.simulate(robot, 2.0, dt=0.02, controller=MPC(problem, max_iterations=3))
    t = traj.t
    err = np.linalg.norm(traj.x[:, 7:] - goal, axis=1)
    q = traj.x[:, 3:7]
    angle = 2 * np.arccos(np.clip(np.abs(q @ traj.x[0, 3:7]), 0.0, 1.0))
    fig, ax = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    ax[0].semilogy(t, err)
    ax[0].set_ylabel("|q - q_goal| (rad)")
    ax[1].plot(t, np.degrees(angle))
    ax[1].set_ylabel("base rotation (deg)")
    ax[2].plot(t[:-1], traj["solve_time"][:-1] * 1e3, ".", label="solve time (ms)")
    ax[2].set_ylabel("solve time (ms)")
    ax[2].set_ylim(bottom=0)
    twin = ax[2].twinx()
    twin.step(t[:-1], traj["solve_iterations"][:-1], "C1", where="post", lw=1)
    twin.set_ylabel("iterations", color="C1")
    twin.set_ylim(0, 4)
    ax[2].set_xlabel("t (s)")
    ax[0].set_title("spacearm.control.MPC on spatial6: 50 knots of 20 ms, 3 iterations per sample")
    fig.tight_layout()
    fig.savefig(OUT, dpi=110)
    print(OUT, f"final error {err[-1]:.2e} rad, median solve {np.median(traj['solve_time'][1:-1]) * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
