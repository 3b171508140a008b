"""Workspaces of a free-floating manipulator: reachable workspace about the system CM (Vafa &
Dubowsky's virtual manipulator), path-dependent and path-independent workspaces (Papadopoulos
& Dubowsky 1991, 1993) and the fixed-base workspace for comparison. ``docs/workspace.md``.

:class:`Workspace` is a subclass of the extension's ``WorkspaceShells`` (the shells, computed
in the core when it is constructed): it adds the samples and scan columns they came from, how
they were sampled, the timing, and the figure; the shells' fields are the extension's own.
"""

from __future__ import annotations

import time
from typing import Optional

import numpy as np

from .. import _core
from .._util.arrays import integer
from ..errors import ArgumentError
from ._common import TaskLike, chunked, concat_columns, joint_bounds, new_figure, samples_2d, save_figure, task_rows

__all__ = ["Workspace", "workspace"]


class Workspace(_core.WorkspaceShells):
    """Sampled workspaces (radii in m): the extension's ``WorkspaceShells`` (``reachable``
    (R_min, R_max) of the free-floating reachable workspace about the system CM, ``fixed_base``
    (min, max) distance from the base CM with the base held fixed, ``singular_radii``,
    ``path_dependent`` and ``path_independent`` shells [(a, b), ...], ``radial_resolution``) with
    the scan it came from: ``robot_name``, ``task``, ``samples`` (M, N) joint samples,
    ``point_from_base`` (M, 3) point from the base CM in the base frame (fixed-base workspace),
    ``point_from_com`` (M, 3) from the system CM (virtual manipulator), ``sigma_min_generalized``
    (M,), ``resolution`` (how the joint space was sampled), ``singular_threshold``, ``seconds``
    and ``samples_per_second``."""

    __slots__ = ("robot_name", "task", "samples", "point_from_base", "point_from_com", "sigma_min_generalized", "resolution",
                 "singular_threshold", "seconds", "samples_per_second")

    def plot(self, path, plane: str = "xy", slab: Optional[float] = None, title: Optional[str] = None) -> str:
        """Write :meth:`figure` to ``path`` (PNG, atomically); returns the path."""
        return save_figure(self.figure(plane, slab, title), path)

    def figure(self, plane: str = "xy", slab: Optional[float] = None, title: Optional[str] = None):
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
        r_max = max(self.reachable[1], self.fixed_base[1])
        slab = 0.05 * r_max if slab is None else slab
        for ax, pts, name in ((ax_fix, self.point_from_base, "fixed base: point from the base CM"),
                              (ax_ff, self.point_from_com, "free floating: point from the system CM")):
            sel = np.abs(pts[:, k]) <= slab
            ax.scatter(pts[sel, i], pts[sel, j], s=0.5, c="0.3", alpha=0.12, rasterized=True, zorder=3,
                       label=f"sampled positions (|{'xyz'[k]}| ≤ {slab:.2g} m)")
            ax.set_aspect("equal")
            ax.set_xlabel(f"{'xyz'[i]} (m, base frame)")
            ax.set_ylabel(f"{'xyz'[j]} (m, base frame)")
            ax.set_title(name, fontsize=10)
        th = np.linspace(0, 2 * np.pi, 361)
        for a, b in self.path_independent:
            ax_ff.fill(np.r_[b * np.cos(th), a * np.cos(th[::-1])], np.r_[b * np.sin(th), a * np.sin(th[::-1])], color="tab:green", alpha=0.25, lw=0)
        for a, b in self.path_dependent:
            bb = max(b, a + 0.5 * self.radial_resolution)
            ax_ff.fill(np.r_[bb * np.cos(th), a * np.cos(th[::-1])], np.r_[bb * np.sin(th), a * np.sin(th[::-1])], color="tab:red", alpha=0.35, lw=0)
        for rr in self.reachable:
            ax_ff.plot(rr * np.cos(th), rr * np.sin(th), "k--", lw=0.8)
        ax_ff.plot([], [], color="tab:green", lw=6, alpha=0.4, label="PIW (path independent)")
        ax_ff.plot([], [], color="tab:red", lw=6, alpha=0.5, label="PDW (path dependent)")
        ax_ff.plot([], [], "k--", lw=0.8, label=f"reachable shell R = {self.reachable[0]:.3g}…{self.reachable[1]:.3g} m")
        ax_ff.plot([0], [0], "k+", ms=10)
        ax_fix.plot([0], [0], "k+", ms=10)
        for ax in (ax_fix, ax_ff):
            ax.set_xlim(-1.05 * r_max, 1.05 * r_max)
            ax.set_ylim(-1.05 * r_max, 1.05 * r_max)
            ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2)
        fig.suptitle(title or f"{self.robot_name}: workspaces ({self.resolution}; radial resolution {self.radial_resolution:.3g} m; "
                     f"task rows {list(self.task)})", fontsize=10)
        return fig


def workspace(robot, resolution: int = 15, samples=None, point=None, task: TaskLike = None, singular_threshold: Optional[float] = None,
              radial_resolution: Optional[float] = None, progress: bool = False, seed: int = 0, random_samples: Optional[int] = None) -> Workspace:
    """Sample the joint space and compute the workspaces.

    Sampling: a full grid with ``resolution`` values per joint over the joint limits (±π where
    unlimited), or ``random_samples`` uniform samples (seeded), or explicit ``samples`` (M×N).
    A dynamic singularity is a sample with ``σ_min(J*) < singular_threshold`` (default 1 % of the
    largest σ_min seen) or, on a grid with a square task, a sign change of ``det J*`` between grid
    neighbours. ``radial_resolution`` (default 1 % of R_max) merges singular radii into PDW shells.
    """
    rows = task_rows(robot, task)
    body, off = robot.resolve_point(point)
    n = robot.n_dof
    grid_res = None
    if samples is not None:
        q = samples_2d(samples, n)
        how = f"{q.shape[0]} given samples"
    elif random_samples is not None:
        lo, hi = joint_bounds(robot)
        rng = np.random.default_rng(seed)
        n_random = integer(random_samples, "random_samples")
        if n_random < 1:
            raise ArgumentError(f"random_samples must be >= 1, got {random_samples!r}")
        q = lo + (hi - lo) * rng.random((n_random, n))
        how = f"{n_random} uniform random samples (seed {seed})"
    else:
        lo, hi = joint_bounds(robot)
        grid_res = integer(resolution, "resolution")
        q = _core.analysis_joint_grid(list(lo), list(hi), grid_res)
        step = np.max(hi - lo) / (grid_res - 1)
        how = f"grid {resolution}^{n} = {q.shape[0]} samples, step ≤ {step:.3g} rad"
    t0 = time.perf_counter()
    parts = chunked(lambda s: _core.analysis_scan(robot.core_model, s, body, off, rows), q, progress, "workspace")
    elapsed = time.perf_counter() - t0
    r = concat_columns(parts, ("sigma_min_generalized", "det_generalized", "point_from_com", "point_from_base"))
    thr = 0.01 * float(np.max(r["sigma_min_generalized"])) if singular_threshold is None else float(singular_threshold)
    rres = 0.01 * float(np.max(np.linalg.norm(r["point_from_com"], axis=1))) if radial_resolution is None else float(radial_resolution)
    w = Workspace(r["sigma_min_generalized"], r["det_generalized"], r["point_from_com"], r["point_from_base"], thr, rres,
                  None if grid_res is None else (grid_res, n))
    w.robot_name, w.task, w.samples, w.resolution = robot.name, tuple(rows), q, how
    w.point_from_base, w.point_from_com, w.sigma_min_generalized = r["point_from_base"], r["point_from_com"], r["sigma_min_generalized"]
    w.singular_threshold, w.seconds, w.samples_per_second = thr, elapsed, q.shape[0] / elapsed
    return w
