"""Figures of an orbital run (docs/orbit.md): the base attitude relative to LVLH
(``plot_lvlh_attitude``: roll about the along-track axis, pitch about the orbit normal, yaw
about the radial axis, against time in orbits) and a path in the LVLH plane
(``plot_lvlh_path``: along-track against radial). matplotlib (extra ``plot``) on its Agg
canvas, files written atomically."""

from __future__ import annotations

import numpy as np

from .figures import new_figure, plot_to

__all__ = ["plot_lvlh_attitude", "plot_lvlh_path", "lvlh_angles"]


def lvlh_angles(rotations) -> np.ndarray:
    """Small-angle roll, pitch, yaw ``(K, 3)`` (rad) of rotations base → LVLH ``(K, 3, 3)``:
    roll about LVLH y (along-track), pitch about z (orbit normal), yaw about x (radial), read
    from the matrix entries (exact for one angle at a time)."""
    r = np.asarray(rotations, dtype=float)
    roll = np.arctan2(r[:, 2, 1], r[:, 2, 2])
    pitch = np.arctan2(r[:, 1, 0], r[:, 0, 0])
    yaw = np.arcsin(np.clip(-r[:, 2, 0], -1.0, 1.0))
    return np.stack([roll, pitch, yaw], axis=1)


def _draw_attitude(traj):
    period = float(traj.meta["orbit"]["period"])
    ang = lvlh_angles(traj.attitude_lvlh())
    fig = new_figure(figsize=(7.0, 3.6), layout="constrained")
    ax = fig.subplots()
    t = np.asarray(traj.t) / period
    for k, name in enumerate(("roll (about along-track y)", "pitch (about orbit normal z)", "yaw (about radial x)")):
        ax.plot(t, np.degrees(ang[:, k]), label=name)
    ax.set_xlabel("time [orbits]")
    ax.set_ylabel("base attitude relative to LVLH [deg]")
    ax.set_title(f"attitude in orbit (a = {traj.meta['orbit']['elements']['a'] / 1e3:.0f} km)", fontsize=9)
    ax.legend(fontsize=7, loc="upper right")
    ax.grid(alpha=0.3)
    return fig


def plot_lvlh_attitude(traj, path=None):
    """The base attitude of orbital run ``traj`` relative to LVLH, in degrees against time in
    orbits; written to ``path`` if given; returns the figure (or the path)."""
    if path is not None:
        return plot_to(path, lambda: _draw_attitude(traj), dpi=110)
    return _draw_attitude(traj)


def _draw_path(t, paths, labels, period):
    fig = new_figure(figsize=(6.0, 4.6), layout="constrained")
    ax = fig.subplots()
    for p, label in zip(paths, labels):
        p = np.asarray(p, dtype=float)
        ax.plot(p[:, 1], p[:, 0], label=label)
        ax.plot(p[0, 1], p[0, 0], "o", color=ax.lines[-1].get_color(), ms=4)
    ax.plot(0.0, 0.0, "k+", ms=10, label="chaser CM")
    ax.set_xlabel("along-track y [m]")
    ax.set_ylabel("radial x [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(f"relative path in LVLH over {float(t[-1]) / period:.2f} orbits (dot: start)", fontsize=9)
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    return fig


def plot_lvlh_path(t, paths, labels, period, path=None):
    """Paths ``(K, 3)`` in LVLH (x radial, y along-track), drawn along-track against radial;
    ``labels`` one per path; ``period`` (s) for the title; written to ``path`` if given."""
    if path is not None:
        return plot_to(path, lambda: _draw_path(t, paths, labels, period), dpi=110)
    return _draw_path(t, paths, labels, period)
