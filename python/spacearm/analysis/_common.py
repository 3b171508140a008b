"""Helpers shared by the analysis modules: task rows, points, progress-bar chunking and atomic
figure output."""

from __future__ import annotations


import numpy as np

from ..errors import ShapeError

from ..model.tasks import TASKS, TaskLike, is_planar, task_rows  # noqa: F401  (the one home: model/tasks.py)


def dof_kinds(robot) -> list:
    """``"revolute"`` or ``"prismatic"`` for each degree of freedom, in ``q`` order (fixed
    joints have none); sets the unit of each joint on figure axes (rad or m)."""
    kinds = [""] * robot.n_dof
    for link in robot.description.links:
        if link.dof is not None:
            kinds[link.dof] = link.type
    return kinds


def joint_bounds(robot, default_span=np.pi):
    """Lower and upper joint bounds for scans: the model's limits where finite, else ±π (±1 m
    for prismatic joints)."""
    lower, upper = [], []
    types = robot.dof_types
    limits = [link.limits for link in sorted((l for l in robot.description.links if l.dof is not None), key=lambda l: l.dof)]
    for t, lim in zip(types, limits):
        lo, hi = lim.lower, lim.upper
        span = default_span if t == "revolute" else 1.0
        lower.append(lo if np.isfinite(lo) else -span)
        upper.append(hi if np.isfinite(hi) else span)
    return np.array(lower), np.array(upper)


def samples_2d(samples, n_dof: int) -> np.ndarray:
    a = np.ascontiguousarray(np.asarray(samples, dtype=float))
    if a.ndim != 2 or a.shape[1] != n_dof:
        raise ShapeError(f"joint samples must have shape (M, N = {n_dof}), got {a.shape}")
    if a.shape[0] == 0:
        raise ShapeError("joint samples must hold at least one row")
    return a


def chunked(run, samples: np.ndarray, progress: bool, desc: str):
    """Run ``run(rows)`` over row chunks (a progress bar per chunk); returns the list of results.
    Chunking changes nothing in the numbers: every sample is computed from its own row only."""
    m = samples.shape[0]
    n_chunks = 1 if m < 2000 else min(50, m // 1000)
    bounds = np.linspace(0, m, n_chunks + 1).astype(int)
    out = []
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=m, desc=desc, unit="sample", leave=False)
    try:
        for a, b in zip(bounds[:-1], bounds[1:]):
            out.append(run(np.ascontiguousarray(samples[a:b])))
            if bar is not None:
                bar.update(b - a)
    finally:
        if bar is not None:
            bar.close()
    return out


def concat_columns(parts, names) -> dict:
    """The attributes ``names`` of the chunk results (one row per sample), each concatenated
    over the chunks: a dict of arrays."""
    return {k: np.concatenate([getattr(p, k) for p in parts], axis=0) for k in names}
