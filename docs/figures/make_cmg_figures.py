"""Draw the CMG figures of docs/cmg.md:

- docs/figures/cmg_pyramid_spatial6.png: the tutorial's run ("a pyramid cluster holding the base
  while the arm moves") — base rotation with the rotors at rest and held by the cluster, the
  gimbal angles, the singularity measure and the fraction of the momentum envelope used.
- docs/figures/cmg_singular_surfaces_pyramid.png: the singular surfaces of the β = 54.74° pyramid
  (spacearm.analysis.cmg_singular_surfaces), grouped by their number of negative signs, and their
  cut by the x-z plane.

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


def save(fig, name: str, dpi: int, note: str) -> None:
    """Lay out ``fig``, write it beside this script as ``name`` and say what it shows."""
    fig.tight_layout()
    out = HERE / name
    fig.savefig(out, dpi=dpi)
    print(out, note)


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
    save(fig, "cmg_pyramid_spatial6.png", 110, f"max base rotation: idle {np.degrees(idle.base_rotation_angle).max():.2f} deg, "
          f"held {np.degrees(held.base_rotation_angle).max():.3f} deg; least measure {held.cmg_measure.min():.3f}")


def singular_surfaces_figure() -> None:
    from spacearm.analysis import cmg_singular_surfaces

    beta = np.arccos(1 / np.sqrt(3))
    axes = [[np.sin(beta) * np.cos(a), np.sin(beta) * np.sin(a), np.cos(beta)] for a in np.arange(4) * np.pi / 2]
    surf = cmg_singular_surfaces(gimbal_axes=axes, h=[1.0] * 4, n=41)
    fig = plt.figure(figsize=(12, 9))
    titles = {0: "outer surface: the envelope (ε all +1)", 1: "internal, one ε = −1 (four surfaces)",
              2: "internal, two ε = −1 (three surfaces)"}
    for k, (neg, title) in enumerate(titles.items()):
        ax = fig.add_subplot(2, 2, k + 1, projection="3d")
        surf.plot(ax, negatives=neg)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("H_x / h")
        ax.set_ylabel("H_y / h")
        ax.set_zlabel("H_z / h")
        for set_lim in (ax.set_xlim, ax.set_ylim, ax.set_zlim):
            set_lim(-3.3, 3.3)
    # Directions u in the x-z plane (azimuth 0 and ±180°): the patterns with ε_2 = ε_4 keep H in
    # that plane (solid); the others leave it (their y-part is h (ε_4 − ε_2) sin β cos β u_z /
    # |ĝ_2 × u|), drawn projected (dashed).
    ax = fig.add_subplot(2, 2, 4)
    j0, j1 = np.argmin(np.abs(surf.azimuth)), np.argmin(np.abs(surf.azimuth - np.pi))
    for k, p in enumerate(surf.points):
        cut = np.concatenate([p[:, j0], p[::-1, j1]])
        in_plane = surf.signs[k, 1] == surf.signs[k, 3]
        ax.plot(cut[:, 0], cut[:, 2], "-" if in_plane else "--", color=f"C{k}", lw=1.5 if in_plane else 0.9,
                label=str(surf.signs[k].astype(int)))
    ax.plot([2 * np.cos(beta)], [0], "k*", ms=10, label="δ = (−90°, 0, 90°, 0)")
    ax.set_aspect("equal")
    ax.set_xlabel("H_x / h")
    ax.set_ylabel("H_z / h")
    ax.set_title("u in the x-z plane (dashed: H leaves it, projected)", fontsize=10)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    fig.suptitle("Singular surfaces of the 4-CMG pyramid (β = 54.74°), h = 1")
    save(fig, "cmg_singular_surfaces_pyramid.png", 100, f"outer |H| from {np.nanmin(np.linalg.norm(surf.points[0], axis=-1)):.3f} "
          f"to {np.nanmax(np.linalg.norm(surf.points[0], axis=-1)):.3f} h")


def main() -> None:
    tutorial_figure()
    singular_surfaces_figure()


if __name__ == "__main__":
    main()
