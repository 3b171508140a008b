"""The figures of the analyses ([`spacearm.analysis`][spacearm.analysis]): a singularity map, a point-to-point
motion, the workspaces. Each result's ``.figure()`` / ``.plot()`` calls these."""

from __future__ import annotations

from typing import Optional

import numpy as np

from ..errors import ArgumentError
from .figures import new_figure

__all__ = ["singularity_map_figure", "motion_figure", "workspace_figure"]


def singularity_map_figure(smap, title: Optional[str] = None):
    """Two maps side by side (``J*`` and ``J_m``), each with its own colour scale and colour
    bar (their ranges can differ by orders of magnitude), with the locus of singularities:
    the zero contour of ``det`` for a square task, else the contour ``σ_min = 2 %`` of its
    maximum. Returns the matplotlib ``Figure``."""
    fig = new_figure(figsize=(12, 4.8))
    axes = fig.subplots(1, 2, sharey=True)
    ext = [smap.axis_b[0], smap.axis_b[-1], smap.axis_a[0], smap.axis_a[-1]]
    for ax, s, det, name, symbol in (
        (axes[0], smap.sigma_min_generalized, smap.det_generalized, "free-floating", "σ_min(J*)"),
        (axes[1], smap.sigma_min_fixed, smap.det_fixed, "fixed base", "σ_min(J_m)"),
    ):
        im = ax.imshow(s, origin="lower", extent=ext, aspect="auto", cmap="viridis", vmin=0, vmax=np.nanmax(s))
        bb, aa = np.meshgrid(smap.axis_b, smap.axis_a)
        if np.all(np.isfinite(det)):
            ax.contour(bb, aa, det, levels=[0.0], colors="red", linewidths=1.5)
            locus = "det = 0"
        else:
            ax.contour(bb, aa, s, levels=[0.02 * np.nanmax(s)], colors="red", linewidths=1.5)
            locus = "σ_min = 2% of max"
        ax.set_title(f"{name}  {symbol}\n(red: singular locus, {locus})", fontsize=10)
        ax.set_xlabel(f"q{smap.joints[1] + 1} [{_unit(smap, smap.joints[1])}]")
        fig.colorbar(im, ax=ax, label=f"{symbol} (m/rad for position rows)", shrink=0.95)
    axes[0].set_ylabel(f"q{smap.joints[0] + 1} [{_unit(smap, smap.joints[0])}]")
    others = ", ".join(f"q{i + 1}={v:.3g}" for i, v in enumerate(smap.q_reference) if i not in smap.joints)
    fig.suptitle(title or f"{smap.robot_name}: dynamic vs kinematic singularities, task rows {list(smap.task)}" + (f"; {others}" if others else ""), fontsize=10)
    return fig


def _unit(smap, dof: int) -> str:
    return "m" if smap.joint_kinds and smap.joint_kinds[dof] == "prismatic" else "rad"


def motion_plane(paths) -> tuple:
    """The coordinate plane ``(i, j)`` (``i < j``) of the inertial axes along which the points of
    ``paths`` (arrays of shape (K, 3)) extend the most: the axis of the smallest extent is the
    one dropped (a motion in x–z is drawn in x–z)."""
    pts = np.vstack([np.asarray(p, dtype=float).reshape(-1, 3) for p in paths])
    drop = int(np.argmin(np.ptp(pts, axis=0)))
    i, j = (a for a in range(3) if a != drop)
    return i, j


def motion_figure(motion, others=(), title: Optional[str] = None):
    """Point path (in the coordinate plane of the motion, `motion_plane`), base attitude
    change and σ_min against time, for this motion and any ``others`` (e.g. a naive motion to the
    same target). Returns the matplotlib ``Figure``."""
    fig = new_figure(figsize=(13, 4.2))
    ax_path, ax_att, ax_sig = fig.subplots(1, 3)
    i, j = motion_plane([m.point_position for m in (motion, *others)] + [np.asarray(motion.target)])
    names = "xyz"
    for m in (motion, *others):
        ax_path.plot(m.point_position[:, i], m.point_position[:, j], label=m.strategy)
        ax_att.plot(m.times, np.degrees(m.attitude_change), label=f"{m.strategy} (max {np.degrees(m.max_attitude_change):.3g}°)")
        ax_sig.plot(m.times, m.sigma_min, label=m.strategy)
    p0 = motion.point_position[0]
    ax_path.plot([p0[i]], [p0[j]], "ko", label="start")
    ax_path.plot([motion.target[i]], [motion.target[j]], "r*", ms=12, label="target")
    ax_path.set_xlabel(f"{names[i]} (m)")
    ax_path.set_ylabel(f"{names[j]} (m)")
    ax_path.set_aspect("equal", adjustable="datalim")
    ax_path.set_title(f"end-effector path (inertial {names[i]}–{names[j]}, the plane of the motion)", fontsize=10)
    ax_path.legend(fontsize=8)
    ax_att.set_xlabel("t (s)")
    ax_att.set_ylabel("base attitude change (deg)")
    ax_att.set_title("base attitude disturbance", fontsize=10)
    ax_att.legend(fontsize=8)
    ax_sig.set_xlabel("t (s)")
    ax_sig.set_ylabel("σ_min of the task Jacobian")
    ax_sig.set_title("distance from singularity", fontsize=10)
    ax_sig.legend(fontsize=8)
    fig.suptitle(title or f"{motion.robot_name}: point-to-point motion of the free-floating system (zero momentum)", fontsize=10)
    return fig


def workspace_figure(ws, plane: str = "xy", slab: Optional[float] = None, title: Optional[str] = None):
    """Left: fixed-base reachable points (base at the origin, held fixed). Right: the
    free-floating workspace about the system CM: reachable shell, PDW shells (red) and PIW
    shells (green), with the samples' barycentric positions at the initial attitude (grey).
    ``plane``: ``"xy"``, ``"xz"`` or ``"yz"``; for spatial arms only samples within ``slab``
    (default: 5 % of R_max) of the plane are drawn (a slice). Returns the matplotlib ``Figure``."""
    if plane not in ("xy", "xz", "yz"):
        raise ArgumentError(f"plane must be 'xy', 'xz' or 'yz', got {plane!r}")
    i, j = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}[plane]
    k = 3 - i - j
    fig = new_figure(figsize=(12, 5.6))
    ax_fix, ax_ff = fig.subplots(1, 2)
    r_max = max(ws.reachable[1], ws.fixed_base[1])
    slab = 0.05 * r_max if slab is None else slab
    for ax, pts, name in ((ax_fix, ws.point_from_base, "fixed base: point from the base CM"),
                          (ax_ff, ws.point_from_com, "free floating: point from the system CM")):
        sel = np.abs(pts[:, k]) <= slab
        ax.scatter(pts[sel, i], pts[sel, j], s=0.5, c="0.3", alpha=0.12, rasterized=True, zorder=3,
                   label=f"sampled positions (|{'xyz'[k]}| ≤ {slab:.2g} m)")
        ax.set_aspect("equal")
        ax.set_xlabel(f"{'xyz'[i]} (m, base frame)")
        ax.set_ylabel(f"{'xyz'[j]} (m, base frame)")
        ax.set_title(name, fontsize=10)
    th = np.linspace(0, 2 * np.pi, 361)
    for a, b in ws.path_independent:
        ax_ff.fill(np.r_[b * np.cos(th), a * np.cos(th[::-1])], np.r_[b * np.sin(th), a * np.sin(th[::-1])], color="tab:green", alpha=0.25, lw=0)
    for a, b in ws.path_dependent:
        bb = max(b, a + 0.5 * ws.radial_resolution)
        ax_ff.fill(np.r_[bb * np.cos(th), a * np.cos(th[::-1])], np.r_[bb * np.sin(th), a * np.sin(th[::-1])], color="tab:red", alpha=0.35, lw=0)
    for rr in ws.reachable:
        ax_ff.plot(rr * np.cos(th), rr * np.sin(th), "k--", lw=0.8)
    ax_ff.plot([], [], color="tab:green", lw=6, alpha=0.4, label="PIW (path independent)")
    ax_ff.plot([], [], color="tab:red", lw=6, alpha=0.5, label="PDW (path dependent)")
    ax_ff.plot([], [], "k--", lw=0.8, label=f"reachable shell R = {ws.reachable[0]:.3g}…{ws.reachable[1]:.3g} m")
    ax_ff.plot([0], [0], "k+", ms=10)
    ax_fix.plot([0], [0], "k+", ms=10)
    for ax in (ax_fix, ax_ff):
        ax.set_xlim(-1.05 * r_max, 1.05 * r_max)
        ax.set_ylim(-1.05 * r_max, 1.05 * r_max)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2)
    fig.suptitle(title or f"{ws.robot_name}: workspaces ({ws.resolution}; radial resolution {ws.radial_resolution:.3g} m; "
                 f"task rows {list(ws.task)})", fontsize=10)
    return fig
