"""Figures of a simulation run: one multi-panel PNG per :class:`~spacearm.Trajectory`.

The figure is drawn on matplotlib's Agg canvas directly (no ``pyplot``, so no global state and
no display is needed, and an interactive session's backend is left alone). Panels appear only
for what was recorded:

- joint coordinates, with the joint reference dashed;
- end-effector position against the Cartesian reference (Cartesian controllers);
- base attitude (roll, pitch, yaw) and base CM displacement, with the system CM's;
- conservation: relative change of ``P``, ``L_origin``, ``L_com`` and kinetic energy from
  their initial values (log scale; the mode's conserved quantities are marked);
- arm joint forces (applied solid, commanded dashed where saturation clipped them), unless
  all are zero;
- reaction-wheel speeds (and wheel torques); the base wrench (flying modes);
- tracking error.
"""

from __future__ import annotations

import os
from typing import Optional, Union

import numpy as np

from ._atomic import atomic_open

__all__ = ["plot_trajectory"]

PathLike = Union[str, "os.PathLike[str]"]

_FLOOR = 1e-17  # log-scale floor for exact zeros of a relative change (below double rounding)


def _new_figure(width: float, height: float):
    from ._optional import require

    FigureCanvasAgg = require("matplotlib.backends.backend_agg", "figures").FigureCanvasAgg
    Figure = require("matplotlib.figure", "figures").Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _wheel_dofs(traj) -> list:
    dofs = traj.meta.get("wheel_dofs") or []
    return [int(d) for d in dofs if 0 <= int(d) < traj.n_dof]


def _panel_joints(ax, traj, names, arm):
    q = traj.q
    ref = traj.reference if traj.has("reference") and traj.tracking_error_kind == "joint" else None
    for j in arm:
        line, = ax.plot(traj.t, q[:, j], lw=1.2, label=names[j])
        if ref is not None and ref.shape[1] == traj.n_dof:
            ax.plot(traj.t, ref[:, j], "--", lw=1.0, color=line.get_color())
    ax.set_title("joint coordinates" + (" (dashed: reference)" if ref is not None else ""))
    ax.set_ylabel("q [rad or m]")
    if len(arm) <= 8:
        ax.legend(fontsize=7, ncol=2, loc="best")


def _panel_ee(ax, traj):
    p = traj.ee_position
    ref = traj.reference if traj.tracking_error_kind == "cartesian" and traj.has("reference") else None
    for i, axis in enumerate("xyz"):
        line, = ax.plot(traj.t, p[:, i], lw=1.2, label=f"ee {axis}")
        if ref is not None and ref.shape[1] >= 3:
            ax.plot(traj.t, ref[:, i], "--", lw=1.0, color=line.get_color())
    ax.set_title("end-effector position" + (" (dashed: reference)" if ref is not None else ""))
    ax.set_ylabel("m")
    ax.legend(fontsize=7, loc="best")


def _panel_attitude(ax, traj):
    e = np.degrees(traj.base_euler)
    for i, lab in enumerate(("roll", "pitch", "yaw")):
        ax.plot(traj.t, e[:, i], lw=1.2, label=lab)
    ax.set_title("base attitude")
    ax.set_ylabel("deg")
    ax.legend(fontsize=7, loc="best")


def _panel_position(ax, traj):
    d = traj.base_position - traj.base_position[0]
    lines = []
    for i, axis in enumerate("xyz"):
        line, = ax.plot(traj.t, d[:, i], lw=1.2, label=f"base {axis}")
        lines.append(line)
    if traj.has("com"):
        g = traj.com - traj.com[0]
        for i, axis in enumerate("xyz"):
            ax.plot(traj.t, g[:, i], ":", lw=1.5, color=lines[i].get_color(), label=f"system CM {axis}")
    ax.set_title("base CM and system CM displacement")
    ax.set_ylabel("m")
    ax.legend(fontsize=7, ncol=2, loc="best")


def _panel_conservation(ax, traj):
    conserved = set(traj.conserved)
    plotted = False
    for name in ("P", "L_origin", "L_com", "energy"):
        if not traj.has(name):
            continue
        v = np.asarray(traj[name], dtype=float).reshape(len(traj), -1)
        ref = max(float(np.linalg.norm(v[0])), traj.drift_scale(name))
        rel = np.linalg.norm(v - v[0], axis=1) / (ref if ref > 0 else 1.0)
        label = f"{name} (conserved)" if name in conserved else name
        # From the second sample on: the first is zero by definition.
        ax.semilogy(traj.t[1:], np.maximum(rel[1:], _FLOOR), lw=1.5 if name in conserved else 1.0,
                    ls="-" if name in conserved else "--", label=label)
        plotted = True
    ax.set_title("relative change from the initial value")
    ax.set_ylabel("|v(t) - v(0)| / scale")
    if plotted:
        ax.legend(fontsize=7, loc="best")


def _panel_torques(ax, traj, names, arm):
    tau = traj.tau
    cmd = traj.tau_cmd if traj.has("tau_cmd") else None
    for j in arm:
        line, = ax.plot(traj.t, tau[:, j], lw=1.2, label=names[j])
        if cmd is not None and not np.allclose(cmd[:, j], tau[:, j]):
            ax.plot(traj.t, cmd[:, j], "--", lw=0.8, color=line.get_color())
    clipped = cmd is not None and any(not np.allclose(cmd[:, j], tau[:, j]) for j in arm)
    ax.set_title("joint forces applied" + (" (dashed: commanded)" if clipped else ""))
    ax.set_ylabel("N m or N")
    if len(arm) <= 8:
        ax.legend(fontsize=7, ncol=2, loc="best")


def _panel_wheels(ax, traj, names, wheels):
    ws = traj.wheel_speed
    for i in range(ws.shape[1]):
        label = names[wheels[i]] if i < len(wheels) else f"wheel {i + 1}"
        ax.plot(traj.t, ws[:, i], lw=1.2, label=label)
    ax.set_title("reaction-wheel speeds" + (" (dotted: torque, right axis)" if traj.has("tau") and wheels else ""))
    ax.set_ylabel("rad/s")
    ax.legend(fontsize=7, loc="best")
    if traj.has("tau") and wheels:
        ax2 = ax.twinx()
        for i, d in enumerate(wheels):
            ax2.plot(traj.t, traj.tau[:, d], ":", lw=1.0, color=f"C{i}")
        ax2.set_ylabel("wheel torque [N m]")


def _panel_wrench(ax, traj):
    w = traj.base_wrench
    for i, lab in enumerate(("F0 x", "F0 y", "F0 z")):
        ax.plot(traj.t, w[:, i], lw=1.2, label=lab)
    ax.set_ylabel("N")
    ax2 = ax.twinx()
    for i, lab in enumerate(("N0 x", "N0 y", "N0 z")):
        ax2.plot(traj.t, w[:, 3 + i], "--", lw=1.0, color=f"C{3 + i}", label=lab)
    ax2.set_ylabel("N m (dashed)")
    ax.set_title("base wrench (thrusters) in the inertial frame")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=7, ncol=2, loc="best")


def _panel_tracking(ax, traj):
    e = traj.tracking_error
    unit = {"joint": "rad", "cartesian": "m"}.get(traj.tracking_error_kind or "", "")
    ax.plot(traj.t, e, lw=1.4, color="C3")
    ax.set_title(f"tracking error ({traj.tracking_error_kind or '?'})")
    ax.set_ylabel(unit)
    if np.all(e > 0) and e.max() / e.min() > 1e3:
        ax.set_yscale("log")


def plot_trajectory(traj, path: Optional[PathLike] = None, *, title: Optional[str] = None, dpi: int = 110):
    """Draw the run's panels (see the module docstring) and, if ``path`` is given, write the
    figure there as PNG (atomically). Returns the matplotlib ``Figure``."""
    names = traj.joint_names()
    wheels = _wheel_dofs(traj)
    arm = [j for j in range(traj.n_dof) if j not in wheels]
    panels = []
    if arm:
        panels.append(lambda ax: _panel_joints(ax, traj, names, arm))
    if traj.has("ee_position") and traj.tracking_error_kind == "cartesian":
        panels.append(lambda ax: _panel_ee(ax, traj))
    panels.append(lambda ax: _panel_attitude(ax, traj))
    panels.append(lambda ax: _panel_position(ax, traj))
    if any(traj.has(k) for k in ("P", "L_origin", "L_com", "energy")):
        panels.append(lambda ax: _panel_conservation(ax, traj))
    if traj.has("tau") and arm and (np.any(traj.tau[:, arm] != 0) or (traj.has("tau_cmd") and np.any(traj.tau_cmd[:, arm] != 0))):
        panels.append(lambda ax: _panel_torques(ax, traj, names, arm))  # not for torque-free runs
    if traj.has("wheel_speed"):
        panels.append(lambda ax: _panel_wheels(ax, traj, names, wheels))
    if traj.has("base_wrench") and np.any(traj.base_wrench != 0):
        panels.append(lambda ax: _panel_wrench(ax, traj))
    if traj.has("tracking_error"):
        panels.append(lambda ax: _panel_tracking(ax, traj))
    rows = (len(panels) + 1) // 2
    fig = _new_figure(12.0, 2.9 * rows + 0.6)
    axes = fig.subplots(rows, 2, squeeze=False).ravel()
    for ax, draw in zip(axes, panels):
        draw(ax)
        ax.grid(True, alpha=0.3)
        ax.set_xlabel("t [s]")
    for ax in axes[len(panels):]:
        ax.set_visible(False)
    if title is None:
        m = traj.meta
        name = traj.robot.name if traj.robot is not None else "run"
        title = f"{name}: {m.get('mode', '?')} mode, controller {m.get('controller') or 'none'}, {m.get('integrator', '?')}"
    fig.suptitle(title)
    if path is not None:
        with atomic_open(path, "wb", suffix=".png") as f:
            fig.savefig(f, format="png", dpi=dpi)
    return fig
