"""Workspaces of a free-floating manipulator: reachable workspace about the system CM (Vafa &
Dubowsky's virtual manipulator), path-dependent and path-independent workspaces (Papadopoulos
& Dubowsky 1991, 1993) and the fixed-base workspace for comparison. ``docs/workspace.md``.

[`Workspace`][spacearm.analysis.Workspace] is a subclass of the extension's ``WorkspaceShells`` (the shells, computed
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
from ._common import TaskLike, chunked, concat_columns, joint_bounds, samples_2d, task_rows

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
        """Write [`figure`][spacearm.analysis.Workspace.figure] to ``path`` in the format its suffix names (atomically); returns the path."""
        from ..viz.figures import plot_to

        return plot_to(path, lambda: self.figure(plane, slab, title), bbox_inches="tight")

    def figure(self, plane: str = "xy", slab: Optional[float] = None, title: Optional[str] = None):
        """The fixed-base and free-floating workspaces in ``plane``
        (``spacearm.viz.analysis.workspace_figure``). Returns the matplotlib ``Figure``."""
        from ..viz.analysis import workspace_figure

        return workspace_figure(self, plane, slab, title)


def workspace(robot, resolution: int = 15, samples=None, point=None, task: TaskLike = None, singular_threshold: Optional[float] = None,
              radial_resolution: Optional[float] = None, progress: bool = False, seed: int = 0, random_samples: Optional[int] = None) -> Workspace:
    r"""Sample the joint space and compute the workspaces.

    Sampling: a full grid with ``resolution`` values per joint over the joint limits (±π where
    unlimited), or ``random_samples`` uniform samples (seeded), or explicit ``samples`` (M×N).
    A dynamic singularity is a sample with $\sigma_\text{min}(J^*) <$ ``singular_threshold`` (default 1 % of the
    largest $\sigma_\text{min}$ seen) or, on a grid with a square task, a sign change of $\det J^*$ between grid
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
