"""Shared pieces of the example scripts: the output directory and a case-study figure.

Not part of the package: the examples use only the public API (``spacearm.simulate``,
``spacearm.control``, ``Trajectory.plot``) plus this figure of paths and momenta.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np


def out_dir(description: str) -> Path:
    """Parse ``--out-dir`` (default ``./out/<script name>``) and create it."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--out-dir", default=None, help="where to write the figures (default: ./out/examples)")
    args = parser.parse_args()
    path = Path(args.out_dir or "out/examples")
    path.mkdir(parents=True, exist_ok=True)
    return path


def case_figure(traj, path, title: str, plane=(0, 1)):
    """Paths of the base CM, the end effector and the system CM in one coordinate plane, the
    base rotation angle, and the momenta: what the paper's case studies illustrate (the base reacts,
    the system CM stays put, momentum is conserved). Written as PNG, atomically."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from spacearm._util.atomic import atomic_open

    fig = Figure(figsize=(12, 3.8), layout="constrained")
    FigureCanvasAgg(fig)
    ax1, ax2, ax3 = fig.subplots(1, 3)
    a, b = plane
    names = "xyz"
    base, com = traj.base_position, traj.com
    ax1.plot(base[:, a], base[:, b], lw=2, label="base CM")
    if traj.has("ee_position"):
        ee = traj.ee_position
        ax1.plot(ee[:, a], ee[:, b], lw=1.5, label="end effector")
        ax1.plot(ee[0, a], ee[0, b], "o", color="C1", ms=4)
    ax1.plot(com[:, a], com[:, b], "kx", ms=8, label=f"system CM (moved {np.max(np.linalg.norm(com - com[0], axis=1)):.1e} m)")
    ax1.plot(base[0, a], base[0, b], "o", color="C0", ms=4)
    ax1.set_aspect("equal", adjustable="datalim")
    ax1.set_xlabel(f"{names[a]} [m]")
    ax1.set_ylabel(f"{names[b]} [m]")
    ax1.set_title("paths in the inertial frame (dots: start)")
    ax1.legend(fontsize=7)
    ax2.plot(traj.t, np.degrees(traj.base_rotation_angle), lw=1.5, label="base rotation since t = 0")
    ax2.set_xlabel("t [s]")
    ax2.set_ylabel("deg")
    ax2.set_title("base attitude change")
    ax2.legend(fontsize=7)
    # The angular momentum the mode conserves: about the CM in translation-flying, else the origin.
    l_key = "L_com" if "L_com" in traj.conserved else "L_origin"
    for key, style in (("P", "-"), (l_key, "--")):
        if traj.has(key):
            v = traj[key]
            for i in range(3):
                ax3.plot(traj.t, v[:, i], style, lw=1.2, color=f"C{i}", label=f"{key} {names[i]}")
    ax3.set_xlabel("t [s]")
    ax3.set_ylabel("N s  |  N m s")
    ax3.set_title("linear and angular momentum")
    ax3.legend(fontsize=7, ncol=2)
    for ax in (ax1, ax2, ax3):
        ax.grid(True, alpha=0.3)
    fig.suptitle(title)
    with atomic_open(path, "wb", suffix=".png") as f:
        fig.savefig(f, format="png", dpi=110)
    return path
