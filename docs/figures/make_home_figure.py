#!/usr/bin/env python
"""Regenerate the figure of the home page (docs/index.md), a few seconds:

    python docs/figures/make_home_figure.py

The spatial6 computed-torque maneuver of docs/figures/make_sim_figures.py (floating mode, no
base control), drawn in 3-D: the base box and the arm at five instants (faint to solid), the
end-effector path, and the base CM path; the base turns and drifts as the arm moves, while
the system CM stays put.
"""

import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

import spacearm  # noqa: E402
from spacearm import control  # noqa: E402
from spacearm.rotations import quat_to_matrix  # noqa: E402
from spacearm.viz.animation import arm_segments, box_faces, equivalent_box  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    robot = spacearm.presets.spatial6()
    q0 = robot.initial_q
    goal = q0 + np.array([0.8, 0.5, 0.6, 0.5, 0.6, 0.5])
    controller = control.ComputedTorque(kp=25.0, kd=10.0, reference=control.QuinticJoint(q0, goal, 0.0, 4.0))
    traj = spacearm.simulate(robot, 5.0, dt=1e-3, record_every=10, controller=controller)
    base = robot.description.base
    sides, axes = equivalent_box(base.mass, base.inertia)

    fig = plt.figure(figsize=(7.5, 5.0))
    ax = fig.add_subplot(projection="3d")
    picks = [int(np.argmin(abs(traj.t - t))) for t in (0.0, 1.0, 2.0, 3.0, 4.0)]  # the move ends at 4 s
    for k, i in enumerate(picks):
        alpha = 0.15 + 0.85 * k / (len(picks) - 1)
        x = traj.x[i]
        faces = box_faces(x[:3], quat_to_matrix(x[3:7]), sides, axes)
        ax.add_collection3d(Poly3DCollection(faces, facecolor=(0.55, 0.65, 0.8, 0.25 * alpha),
                                             edgecolor=(0.2, 0.3, 0.5, alpha), linewidth=0.6))
        for start, end in arm_segments(robot, x):
            ax.plot(*np.stack([start, end]).T, color=(0.85, 0.35, 0.1, alpha), linewidth=2.5)
        if k in (0, len(picks) - 1):
            ax.text(*(robot.point_position(x) + [0, 0, 0.08]), f"t = {traj.t[i]:.0f} s", fontsize=8)
    ee = np.array([robot.point_position(x) for x in traj.x])
    ax.plot(*ee.T, color="tab:green", linewidth=1.2, label="end-effector path")
    ax.plot(*traj.x[:, :3].T, color="tab:blue", linewidth=1.2, label="base CM path (it drifts: the system CM stays put)")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    ax.set_xlim(-0.8, 2.8)
    ax.set_ylim(-1.8, 1.8)
    ax.set_zlim(-1.6, 1.0)
    ax.set_box_aspect((3.6, 3.6, 2.6))
    ax.view_init(elev=22, azim=-60)
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title("spatial6, floating: a computed-torque maneuver turns the free base", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "home_spatial6_maneuver.png"), dpi=130)


if __name__ == "__main__":
    main()
