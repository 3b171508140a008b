"""Draw the CMG figures of docs/cmg.md:

- docs/figures/cmg_pyramid_spatial6.png: the tutorial's run ("a pyramid cluster holding the base
  while the arm moves") — base rotation with the rotors at rest and held by the cluster, the
  gimbal angles, the singularity measure and the fraction of the momentum envelope used.

    PYTHONPATH=python python3 docs/figures/make_cmg_figures.py

The model and the runs are the page's own code (docs/cmg.md, "Tutorial"), repeated here.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm.control import CmgSteering, Combined, JointPD, QuinticJoint  # noqa: E402

HERE = Path(__file__).resolve().parent


def servicer() -> spacearm.Robot:
    b = spacearm.presets.spatial6().to_builder("servicer")
    beta = np.arccos(1 / np.sqrt(3))  # the pyramid's skew angle
    for i, a in enumerate(np.arange(4) * np.pi / 2):  # gimbal axes normal to the pyramid's faces
        b.add_cmg(f"cmg{i + 1}", gimbal_axis=[np.sin(beta) * np.cos(a), np.sin(beta) * np.sin(a), np.cos(beta)],
                  spin_axis=[-np.sin(a), np.cos(a), 0], rotor_inertia=0.05, gimbal_inertia=0.02, rotor_mass=3.0,
                  gimbal_mass=1.5, max_gimbal_rate=2.0)
    return b.build()


def tutorial_figure() -> None:
    robot = servicer()
    q0 = robot.initial_q[:6]
    move = QuinticJoint(q0, q0 + np.array([1.2, -0.6, 0.9, 0.8, -0.8, 1.0]), 0.0, 3.0)
    arm = JointPD(kp=[200, 200, 100, 10, 10, 10], kd=[60, 60, 30, 3, 3, 3], reference=move)
    hold = Combined(arm=arm, base=CmgSteering([0, 0, 0, 1], kp=1e4, kd=1e4))
    idle = spacearm.simulate(robot, 4.0, mode="rotation-floating", controller=arm, dt=2e-3)
    held = spacearm.simulate(robot, 4.0, u0=robot.cmg_velocity(250.0), mode="rotation-floating", controller=hold,
                             dt=2e-3)
    t = held.t
    fig, ax = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    ax[0].semilogy(idle.t[1:], np.degrees(idle.base_rotation_angle[1:]), label="rotors at rest, no steering")
    ax[0].semilogy(t[1:], np.degrees(held.base_rotation_angle[1:]), label="held by the CMG pyramid (250 rad/s)")
    ax[0].set_ylabel("base rotation (deg)")
    ax[0].set_ylim(1e-3, 20)
    ax[0].legend(loc="lower right")
    for name, c in robot.cmg_dofs.items():
        ax[1].plot(t, np.degrees(held.q[:, c["gimbal"]]), label=name)
    ax[1].set_ylabel("gimbal angle (deg)")
    ax[1].legend(ncol=4, loc="upper left")
    ax[2].plot(t, held.cmg_measure, label="singularity measure m = det(A Aᵀ)/h̄⁶")
    ax[2].plot(t, held.cmg_envelope_fraction, label="envelope fraction |H|/σ(Ĥ)")
    ax[2].axhline(32 / 27, color="0.6", lw=0.8, ls="--")
    ax[2].set_ylim(0, 1.05 * held.cmg_measure.max())
    ax[2].legend(loc="center right")
    ax[2].set_xlabel("t (s)")
    ax[0].set_title("spatial6 servicer with a 4-CMG pyramid: the arm moves for 3 s")
    fig.tight_layout()
    out = HERE / "cmg_pyramid_spatial6.png"
    fig.savefig(out, dpi=110)
    print(out, f"max base rotation: idle {np.degrees(idle.base_rotation_angle).max():.2f} deg, "
          f"held {np.degrees(held.base_rotation_angle).max():.3f} deg; least measure {held.cmg_measure.min():.3f}")


def main() -> None:
    tutorial_figure()


if __name__ == "__main__":
    main()
