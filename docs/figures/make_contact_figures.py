#!/usr/bin/env python
"""Regenerate the figure of docs/contact.md, "A capture on contact" (a few seconds):

    python docs/figures/make_contact_figures.py

contact_grasp.png — a parallel gripper closing on a tumbling box's handle (the page's example):
the relative spin of handle and palm, the handle's distance from the grasp centre and the
fingers' total normal force, for a slow spin that is held, a fast one and a low-friction one
that slip.
"""

import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm.contact import ContactModel, Pair  # noqa: E402
from spacearm.control import JointPD  # noqa: E402
from spacearm.rotations import quat_to_matrix  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def servicer():
    b = spacearm.RobotBuilder("servicer", 200.0, np.eye(3) * 33.0)
    b.add_link("boom", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.25, 0, 0), mass=5.0,
               inertia=np.diag([0.01, 0.11, 0.11]))
    b.add_gripper("hand", parent="boom", position=(0.25, 0, 0), rpy=(0, np.pi / 2, 0), fingers=2,
                  finger_length=0.12, finger_radius=0.01, opening=0.10)
    return b.build()


def handle_target():
    t = spacearm.RobotBuilder("target", 20.0, np.eye(3) * 0.53, base_name="target")
    t.add_geometry("target", "box", role="collision", size=(0.4, 0.4, 0.4), name="body")
    t.add_geometry("target", "cylinder", role="collision", radius=0.02, length=0.15, origin=(-0.29, 0, 0),
                   rpy=(np.pi / 2, 0, 0), name="handle")
    return t.build()


def run(robot, target, spin, friction):
    contact = ContactModel(stiffness=2e3, damping=20.0, friction=friction, slip_velocity=1e-3,
                           pairs=[Pair("hand_finger0", "target"), Pair("hand_finger1", "target")])
    close = JointPD(kp=[500.0, 200.0, 200.0], kd=[100.0, 5.0, 5.0], reference=[0.0, 0.04, 0.04])
    s0 = np.array([1.35, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, spin, 0.0])
    traj = spacearm.simulate(robot, 3.0, dt=5e-4, record_every=2, controller=close, contact=contact, target=target, target_state=s0)
    s = traj["target"]
    axis = np.array([quat_to_matrix(x[3:7])[:, 2] for x in traj.x])
    rel_w = np.linalg.norm(s[:, 10:13] - traj.u[:, 3:6] - traj.u[:, 6:7] * axis, axis=1)
    handle = np.array([si[:3] + quat_to_matrix(si[3:7]) @ [-0.29, 0, 0] for si in s])
    centre = np.array([robot.point_position(x, "hand_center") for x in traj.x])
    return traj, rel_w, np.linalg.norm(handle - centre, axis=1)


def main():
    robot, target = servicer(), handle_target()
    fig, ax = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    for spin, mu, style in ((0.05, 0.5, "-"), (2.0, 0.5, "--"), (0.3, 0.05, ":")):
        traj, rel_w, off = run(robot, target, spin, mu)
        label = f"spin {spin} rad/s, μ {mu}"
        ax[0].semilogy(traj.t, np.maximum(rel_w / spin, 1e-6), style, label=label)
        ax[1].plot(traj.t, 1e3 * off, style, label=label)
        ax[2].plot(traj.t, traj.contact_normal_force, style, label=label)
        print(label, f"relative spin at the end {rel_w[-1]:.4f} rad/s, handle {1e3 * off[-1]:.1f} mm off")
    ax[0].set_ylabel("relative spin / initial spin")
    ax[1].set_ylabel("handle from grasp centre (mm)")
    ax[2].set_ylabel("Σ finger normal force (N)")
    ax[2].set_xlabel("t (s)")
    ax[0].legend()
    ax[0].set_title("A parallel gripper closing on a tumbling handle (compliant contact, free target)")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "contact_grasp.png"), dpi=110)


if __name__ == "__main__":
    main()
