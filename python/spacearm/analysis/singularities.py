"""Dynamic singularities of free-floating systems (Papadopoulos & Dubowsky 1991, 1993):
rank loss of the Generalized Jacobian ``J*`` (paper eq. 110), compared with the fixed-base
Jacobian ``J_m`` (eq. 106). Theory and the damping law: ``docs/singularities.md``.

[`SingularityReport`][spacearm.analysis.SingularityReport], [`JacobianMeasures`][spacearm.analysis.JacobianMeasures] and [`Detection`][spacearm.analysis.Detection] are the extension's
own frozen classes (``crates/spacearm-py/src/analysis_results_py.rs``), returned as they are.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from .. import _core
from .._core import Detection, JacobianMeasures, SingularityReport
from .._util.arrays import integer, number
from .._util.summary import summary_repr
from ._common import TaskLike, chunked, concat_columns, dof_kinds, samples_2d, task_rows

#: The keys of [`scan`][spacearm.analysis.scan]'s dict: the columns of the extension's ``ScanResult``.
SCAN_COLUMNS = ("sigma_min_generalized", "sigma_max_generalized", "manipulability_generalized", "det_generalized",
                "sigma_min_fixed", "manipulability_fixed", "det_fixed", "point_from_base", "point_from_com")

__all__ = ["JacobianMeasures", "SingularityReport", "Detection", "SingularityMap", "analyze", "detect", "damping", "scan", "singularity_map"]


def analyze(robot, x=None, point=None, task: TaskLike = None) -> SingularityReport:
    """Singular values, condition numbers, manipulability and singular directions of the task
    rows of ``J*`` and of ``J_m`` at ``x`` (default: the initial configuration)."""
    x = robot.neutral_configuration() if x is None else x
    body, off = robot.resolve_point(point)
    rows = task_rows(robot, task)
    return _core.analysis_singularity(robot.core_model, x, body, off, rows)


def damping(sigma_min: float, threshold: float, max_damping: float) -> float:
    r"""$\lambda(\sigma_\text{min})$ with $\lambda^2 = \lambda_\text{max}^2 \bigl(1 - (\sigma_\text{min}/\varepsilon)^2\bigr)$ for $\sigma_\text{min} < \varepsilon$, else 0."""
    return _core.analysis_damping(number(sigma_min, "sigma_min"), number(threshold, "threshold"), number(max_damping, "max_damping"))


def detect(robot, x, point=None, task: TaskLike = None, threshold: float = _core.DLS_DEFAULTS.threshold, max_damping: float = _core.DLS_DEFAULTS.max_damping) -> Detection:
    r"""Singularity detector for RMRC: $\sigma_\text{min}$ and condition of the task rows of $J^*$ and
    the recommended DLS damping (``threshold`` $= \varepsilon$, ``max_damping`` $= \lambda_\text{max}$)."""
    body, off = robot.resolve_point(point)
    return _core.analysis_detect(robot.core_model, x, body, off, task_rows(robot, task), number(threshold, "threshold"),
                                 number(max_damping, "max_damping"))


def scan(robot, samples, point=None, task: TaskLike = None, progress: bool = False) -> dict:
    """Joint-space scan (parallel, in Rust) with the base at the origin and aligned with 𝒥:
    for each row ``q`` of ``samples`` (M×N), the smallest/largest singular values,
    manipulability and determinant (square tasks, else NaN) of ``J*`` and ``J_m`` and the
    point's position from the base CM and from the system CM (base frame). Returns a dict of
    arrays."""
    body, off = robot.resolve_point(point)
    rows = task_rows(robot, task)
    q = samples_2d(samples, robot.n_dof)
    parts = chunked(lambda s: _core.analysis_scan(robot.core_model, s, body, off, rows), q, progress, "scan")
    return concat_columns(parts, SCAN_COLUMNS)


@dataclass(repr=False)
class SingularityMap:
    r"""$\sigma_\text{min}$ of $J^*$ and $J_m$ on a grid over two joints (the others fixed)."""

    robot_name: str
    joints: tuple  #: the two joints varied (0-based dof indices)
    q_reference: np.ndarray  #: the other joints' values
    axis_a: np.ndarray  #: values of joint ``joints[0]`` (rad or m)
    axis_b: np.ndarray  #: values of joint ``joints[1]``
    sigma_min_generalized: np.ndarray  #: (len(axis_a), len(axis_b))
    sigma_min_fixed: np.ndarray
    det_generalized: np.ndarray  #: NaN unless the task is square
    det_fixed: np.ndarray
    task: tuple
    seconds: float  #: wall time of the scan
    samples_per_second: float
    joint_kinds: tuple = ()  #: "revolute" or "prismatic" for each dof (axis units of the figure)

    __repr__ = summary_repr

    def singular_mask(self, relative: float = 0.02) -> np.ndarray:
        r"""Grid cells with $\sigma_\text{min}(J^*) < \text{relative} \cdot \max \sigma_\text{min}(J^*)$ over the map."""
        return self.sigma_min_generalized < relative * np.nanmax(self.sigma_min_generalized)

    def plot(self, path, title: Optional[str] = None) -> str:
        """Write [`figure`][spacearm.analysis.SingularityMap.figure] to ``path`` in the format its suffix names (atomically); returns the path."""
        from ..viz.figures import plot_to

        return plot_to(path, lambda: self.figure(title), bbox_inches="tight")

    def figure(self, title: Optional[str] = None):
        """Two maps side by side (``J*`` and ``J_m``) with the singular locus
        (``spacearm.viz.analysis.singularity_map_figure``). Returns the matplotlib ``Figure``."""
        from ..viz.analysis import singularity_map_figure

        return singularity_map_figure(self, title)



def singularity_map(robot, joints: Sequence[int] = None, resolution: int = 101, q=None, point=None, task: TaskLike = None,
                    bounds=None, progress: bool = False) -> SingularityMap:
    """Scan ``σ_min(J*)`` and ``σ_min(J_m)`` over a ``resolution × resolution`` grid of two
    joints (default: the last two; 0-based), the other joints at ``q`` (default: the initial
    angles), each varied over ``bounds`` (default: its limits, or ±π)."""
    import time

    from ._common import joint_bounds

    n = robot.n_dof
    joints = (n - 2, n - 1) if joints is None else tuple(integer(j, "joints") for j in joints)
    if len(joints) != 2 or len(set(joints)) != 2 or not all(0 <= j < n for j in joints):
        from ..errors import ShapeError

        raise ShapeError(f"joints must be two different dof indices in 0..{n - 1}, got {joints}")
    q_ref = np.array(robot.initial_q if q is None else q, dtype=float)
    lo, hi = joint_bounds(robot) if bounds is None else (np.asarray(bounds[0], float), np.asarray(bounds[1], float))
    grid = _core.analysis_joint_grid([lo[joints[0]], lo[joints[1]]], [hi[joints[0]], hi[joints[1]]], integer(resolution, "resolution"))
    samples = np.tile(q_ref, (grid.shape[0], 1))
    samples[:, joints[0]] = grid[:, 0]
    samples[:, joints[1]] = grid[:, 1]
    t0 = time.perf_counter()
    r = scan(robot, samples, point=point, task=task, progress=progress)
    dt = time.perf_counter() - t0
    shape = (resolution, resolution)
    return SingularityMap(
        robot.name, joints, q_ref,
        np.linspace(lo[joints[0]], hi[joints[0]], resolution), np.linspace(lo[joints[1]], hi[joints[1]], resolution),
        r["sigma_min_generalized"].reshape(shape), r["sigma_min_fixed"].reshape(shape),
        r["det_generalized"].reshape(shape), r["det_fixed"].reshape(shape),
        tuple(task_rows(robot, task)), dt, samples.shape[0] / dt,
        tuple(dof_kinds(robot)),
    )
