"""Figures of a simulation run: one multi-panel PNG per [`Trajectory`][spacearm.Trajectory].

The figure is drawn on matplotlib's Agg canvas directly (no ``pyplot``, so no global state and
no display is needed, and an interactive session's backend is left alone). Panels appear only
for what was recorded:

- joint coordinates, with the joint reference dashed: revolute joints in one panel (rad),
  prismatic joints in another (m);
- end-effector position against the Cartesian reference (Cartesian controllers);
- base attitude (roll, pitch, yaw: the Z-Y-X Euler angles of ``R0 = Rz(yaw) Ry(pitch) Rx(roll)``)
  and base CM displacement, with the system CM's;
- momentum: the change ``|v(t) − v(0)|`` of ``P`` (N s), ``L_origin`` and ``L_com`` (N m s)
  from their initial values (log scale; the mode's conserved quantities are marked; the relative
  drifts are ``Trajectory.drift``);
- kinetic energy: its signed change ``T(t) − T(0)`` in J, on a linear axis of its own (it is
  conserved only in torque-free floating runs, so it does not share the log panel of the momenta);
- arm joint torques (revolute, N m) and forces (prismatic, N) in separate panels (applied solid,
  commanded dashed where saturation clipped them), unless all are zero;
- reaction-wheel speeds (and wheel torques); the base wrench (flying modes);
- tracking error (with compliant joints: the motors' and the links', motor angle + deflection).

The panels fill two columns; an odd last panel spans both, so no slot of the grid is empty.

Each joint keeps one colour in every panel. Up to 20 joints have a legend (outside the axes
when there are more than 6); more are coloured along a colormap with a colour bar of the joint
number.
"""

from __future__ import annotations

import os
from typing import Optional, Union

import numpy as np

from .._util.summary import controller_label
from .figures import figure_format, new_figure, save_figure

__all__ = ["plot_trajectory"]

PathLike = Union[str, "os.PathLike[str]"]

_FLOOR = 1e-17  # log-scale floor for exact zeros of a relative change (below double rounding)


def _new_figure(width: float, height: float):
    return new_figure(figsize=(width, height))


def _wheel_dofs(traj) -> list:
    dofs = traj.meta.get("wheel_dofs") or []
    return [int(d) for d in dofs if 0 <= int(d) < traj.n_dof]


# What each kind of joint's coordinate and force are called, and their units. ``None``: the
# trajectory has no robot, so the kind of each joint is unknown.
_JOINT_KINDS = {
    "revolute": ("joint angles", "q [rad]", "joint torques", "τ [N m]"),
    "prismatic": ("prismatic joint positions", "q [m]", "prismatic joint forces", "f [N]"),
    None: ("joint coordinates", "q [rad or m]", "joint torques and forces", "τ [N m or N]"),
}
_LEGEND_INSIDE_MAX = 6  # more joints than this: the legend goes outside the axes
_LEGEND_MAX = 20  # more joints than this: a colormap and a colour bar instead of a legend


def _dof_kinds(traj) -> list:
    """``"revolute"``, ``"prismatic"`` or ``None`` (unknown: no robot) for each dof."""
    if traj.robot is None:
        return [None] * traj.n_dof
    from ..analysis._common import dof_kinds

    return dof_kinds(traj.robot)


def _groups_by_kind(traj, arm) -> list:
    """``[(kind, [dofs])]``: the arm's dofs split by joint kind (revolute first)."""
    kinds = _dof_kinds(traj)
    return [(k, [j for j in arm if kinds[j] == k]) for k in ("revolute", "prismatic", None)
            if any(kinds[j] == k for j in arm)]


class _JointColours:
    """One colour per arm joint, the same in every panel: matplotlib's cycle (up to 10), the
    20-colour qualitative map (up to 20), else a continuous colormap over the joint number."""

    def __init__(self, arm):
        self.arm = list(arm)
        n = len(self.arm)
        from .._util.optional import require

        mpl = require("matplotlib", "figures")
        if n <= 10:
            self.cmap, self.positions = None, {j: f"C{i}" for i, j in enumerate(self.arm)}
        elif n <= _LEGEND_MAX:
            cmap = mpl.colormaps["tab20"]
            self.cmap, self.positions = None, {j: cmap(i) for i, j in enumerate(self.arm)}
        else:
            cmap = mpl.colormaps["viridis"]
            self.cmap = cmap
            self.positions = {j: cmap(i / (n - 1)) for i, j in enumerate(self.arm)}

    def __getitem__(self, dof):
        return self.positions[dof]

    def label(self, ax, fig, n_lines: int) -> None:
        """A legend of the joints drawn in ``ax`` (inside if few, outside the axes on the right
        if many), or a colour bar of the joint number when the joints are too many to name."""
        if self.cmap is not None:
            from .._util.optional import require

            mpl = require("matplotlib", "figures")
            mappable = mpl.cm.ScalarMappable(norm=mpl.colors.Normalize(1, len(self.arm)), cmap=self.cmap)
            fig.colorbar(mappable, ax=ax, label="joint number", pad=0.01)
        elif n_lines <= _LEGEND_INSIDE_MAX:
            ax.legend(fontsize=7, ncol=2, loc="best")
        else:
            ax.legend(fontsize=7, ncol=-(-n_lines // 12), loc="upper left", bbox_to_anchor=(1.01, 1.0),
                      borderaxespad=0.0, handlelength=1.5)


def _panel_joints(ax, fig, traj, names, dofs, kind, colours):
    q = traj.q
    ref = traj.reference if traj.has("reference") and traj.tracking_error_kind == "joint" else None
    for j in dofs:
        ax.plot(traj.t, q[:, j], lw=1.2, color=colours[j], label=names[j])
        if ref is not None and ref.shape[1] == traj.n_dof:
            ax.plot(traj.t, ref[:, j], "--", lw=1.0, color=colours[j])
    title, ylabel = _JOINT_KINDS[kind][:2]
    ax.set_title(title + (" (dashed: reference)" if ref is not None else ""))
    ax.set_ylabel(ylabel)
    colours.label(ax, fig, len(dofs))


def _panel_passive(ax, fig, traj, names, dofs):
    """The passive coordinates, in their own units and with their own legend or colour bar."""
    colours = _JointColours(dofs)
    kinds = {_dof_kinds(traj)[j] for j in dofs}
    for j in dofs:
        ax.plot(traj.t, traj.q[:, j], lw=1.0, color=colours[j], label=names[j])
    ax.set_title("passive coordinates (no motor: slosh, panels, beams, compliant links)")
    ax.set_ylabel({frozenset({"revolute"}): "q [rad]", frozenset({"prismatic"}): "q [m]"}.get(frozenset(kinds), "q [rad or m]"))
    colours.label(ax, fig, len(dofs))


def _panel_ee(ax, traj):
    p = traj.ee_position
    ref = traj.reference if traj.tracking_error_kind == "cartesian" and traj.has("reference") else None
    for i, axis in enumerate("xyz"):
        line, = ax.plot(traj.t, p[:, i], lw=1.2, label=f"ee {axis}")
        if ref is not None and ref.shape[1] >= 3:
            ax.plot(traj.t, ref[:, i], "--", lw=1.0, color=line.get_color())
    ax.set_title("end-effector position" + (" (dashed: reference)" if ref is not None else ""))
    ax.set_ylabel("position [m]")
    ax.legend(fontsize=7, loc="best")


def _panel_attitude(ax, traj):
    e = np.degrees(traj.base_euler)
    for i, lab in enumerate(("roll", "pitch", "yaw")):
        ax.plot(traj.t, e[:, i], lw=1.2, label=lab)
    ax.set_title("base attitude, Z-Y-X Euler angles (R0 = Rz(yaw) Ry(pitch) Rx(roll))")
    ax.set_ylabel("angle [deg]")
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
    ax.set_ylabel("displacement [m]")
    ax.legend(fontsize=7, ncol=2, loc="best")


def _panel_momentum(ax, traj):
    conserved, balanced = set(traj.conserved), set(traj.balanced)
    plotted = False
    for name in ("P", "L_origin", "L_com"):
        if not traj.has(name):
            continue
        v = np.asarray(traj[name], dtype=float).reshape(len(traj), -1)
        change = np.linalg.norm(v - v[0], axis=1)
        unit = "N s" if name == "P" else "N m s"
        # In orbit with the gravity gradient nothing is conserved: the tidal wrench changes the
        # momenta, and the simulator checks their balance instead (Trajectory.balanced).
        note = " (conserved)" if name in conserved else " (changed by the tidal wrench)" if name in balanced else ""
        label = f"{name} [{unit}]{note}"
        # From the second sample on: the first is zero by definition.
        ax.semilogy(traj.t[1:], np.maximum(change[1:], _FLOOR), lw=1.5 if name in conserved else 1.0,
                    ls="-" if name in conserved else "--", label=label)
        plotted = True
    ax.set_title("momentum: change from the initial value")
    ax.set_ylabel("|v(t) − v(0)| [N s (P), N m s (L)]")
    if plotted:
        ax.legend(fontsize=7, loc="best")


def _panel_energy(ax, traj):
    """Signed change of the kinetic energy from its initial value, ``T(t) − T(0)`` in J."""
    energy = np.asarray(traj["energy"], dtype=float)
    ax.plot(traj.t, energy - energy[0], lw=1.4, color="C4", label=f"T(0) = {float(energy[0]):.4g} J")
    conserved = "energy" in set(traj.conserved)
    ax.set_title("kinetic energy: change from T(0)" + (" (conserved)" if conserved else ""))
    ax.legend(fontsize=7, loc="best")
    ax.set_ylabel("T(t) − T(0) [J]")


def _panel_torques(ax, fig, traj, names, dofs, kind, colours):
    tau = traj.tau
    cmd = traj.tau_cmd if traj.has("tau_cmd") else None
    clipped = False
    for j in dofs:
        ax.plot(traj.t, tau[:, j], lw=1.2, color=colours[j], label=names[j])
        if cmd is not None and not np.allclose(cmd[:, j], tau[:, j]):
            ax.plot(traj.t, cmd[:, j], "--", lw=0.8, color=colours[j])
            clipped = True
    title, ylabel = _JOINT_KINDS[kind][2:]
    ax.set_title(title + " applied" + (" (dashed: commanded)" if clipped else ""))
    ax.set_ylabel(ylabel)
    colours.label(ax, fig, len(dofs))


def _panel_wheels(ax, traj, names, wheels):
    ws = traj.wheel_speed
    for i in range(ws.shape[1]):
        label = names[wheels[i]] if i < len(wheels) else f"wheel {i + 1}"
        ax.plot(traj.t, ws[:, i], lw=1.2, label=label)
    ax.set_title("reaction-wheel speeds" + (" (dotted: torque, right axis)" if traj.has("tau") and wheels else ""))
    ax.set_ylabel("wheel speed [rad/s]")
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
    ax.set_ylabel("force [N]")
    ax2 = ax.twinx()
    for i, lab in enumerate(("N0 x", "N0 y", "N0 z")):
        ax2.plot(traj.t, w[:, 3 + i], "--", lw=1.0, color=f"C{3 + i}", label=lab)
    ax2.set_ylabel("torque [N m] (dashed)")
    ax.set_title("base wrench (thrusters) in the inertial frame")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=7, ncol=2, loc="best")


def _panel_tracking(ax, traj, arm):
    e = traj.tracking_error
    if traj.tracking_error_kind == "joint":
        # The norm over the joints: in rad, in m, a mix of both when the arm has both kinds, or
        # either when the kinds are unknown (no robot).
        kinds = frozenset(_dof_kinds(traj)[j] for j in arm)
        unit = {frozenset({"revolute"}): "rad", frozenset({"prismatic"}): "m",
                frozenset({None}): "rad or m"}.get(kinds, "rad and m")
    else:
        unit = {"cartesian": "m"}.get(traj.tracking_error_kind or "", "?")
    link = traj.has("link_tracking_error")
    ax.plot(traj.t, e, lw=1.4, color="C3", label="motors (θ)" if link else None)
    ax.set_title(f"tracking error ({traj.tracking_error_kind or '?'})")
    ax.set_ylabel(f"‖e‖ [{unit}]")
    if link:
        # Compliant joints: the links (motor angle + deflection) against the same reference.
        e2 = traj.link_tracking_error
        ax.plot(traj.t, e2, lw=1.2, ls="--", color="C4", label="links (θ + δ)")
        ax.legend(fontsize=7, loc="best")
        e = np.concatenate([e, e2])
    if np.all(e > 0) and e.max() / e.min() > 1e3:
        ax.set_yscale("log")


def plot_trajectory(traj, path: Optional[PathLike] = None, *, title: Optional[str] = None, dpi: int = 110):
    """Draw the run's panels (see the module docstring) and, if ``path`` is given, write the
    figure there as PNG (atomically). Returns the matplotlib ``Figure``."""
    names = traj.joint_names()
    wheels = _wheel_dofs(traj)
    # The passive coordinates (slosh, panels, beams, compliant links: no motor) get a panel of
    # their own: their ~1e-2 rad would be lost in the arm's scale, and their legend in its.
    actuated = traj.robot.actuated_dofs if traj.robot is not None else np.ones(traj.n_dof, dtype=bool)
    arm = [j for j in range(traj.n_dof) if j not in wheels and actuated[j]]
    passive = [j for j in range(traj.n_dof) if j not in wheels and not actuated[j]]
    colours = _JointColours(arm)
    groups = _groups_by_kind(traj, arm)
    panels = []
    for kind, dofs in groups:
        panels.append(lambda ax, fig, dofs=dofs, kind=kind: _panel_joints(ax, fig, traj, names, dofs, kind, colours))
    if passive:
        panels.append(lambda ax, fig: _panel_passive(ax, fig, traj, names, passive))
    if traj.has("ee_position") and traj.tracking_error_kind == "cartesian":
        panels.append(lambda ax, fig: _panel_ee(ax, traj))
    panels.append(lambda ax, fig: _panel_attitude(ax, traj))
    panels.append(lambda ax, fig: _panel_position(ax, traj))
    if any(traj.has(k) for k in ("P", "L_origin", "L_com")):
        panels.append(lambda ax, fig: _panel_momentum(ax, traj))
    if traj.has("energy"):
        panels.append(lambda ax, fig: _panel_energy(ax, traj))
    if traj.has("tau"):
        for kind, dofs in groups:  # not for torque-free runs
            if np.any(traj.tau[:, dofs] != 0) or (traj.has("tau_cmd") and np.any(traj.tau_cmd[:, dofs] != 0)):
                panels.append(lambda ax, fig, dofs=dofs, kind=kind: _panel_torques(ax, fig, traj, names, dofs, kind, colours))
    if traj.has("wheel_speed"):
        panels.append(lambda ax, fig: _panel_wheels(ax, traj, names, wheels))
    if traj.has("base_wrench") and np.any(traj.base_wrench != 0):
        panels.append(lambda ax, fig: _panel_wrench(ax, traj))
    if traj.has("tracking_error"):
        panels.append(lambda ax, fig: _panel_tracking(ax, traj, arm))
    rows = (len(panels) + 1) // 2
    if path is not None:
        figure_format(path)  # an unwritable format fails before anything is drawn
    fig = _new_figure(12.0, 2.9 * rows + 0.6)
    # Two columns; an odd last panel spans both, so the grid has no empty slot.
    grid = fig.add_gridspec(rows, 2)
    for i, draw in enumerate(panels):
        row, col = divmod(i, 2)
        span = i == len(panels) - 1 and col == 0
        ax = fig.add_subplot(grid[row, :] if span else grid[row, col])
        draw(ax, fig)
        ax.grid(True, alpha=0.3)
        ax.set_xlabel("t [s]")
    if title is None:
        m = traj.meta
        name = traj.robot.name if traj.robot is not None else "run"
        title = f"{name}: {m.get('mode', '?')} mode, {controller_label(m.get('controller'))}, {m.get('integrator', '?')}"
    fig.suptitle(title)
    if path is not None:
        save_figure(fig, path, dpi=dpi)
    return fig
