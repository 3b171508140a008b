"""The momentum envelope of a CMG cluster and its singular surfaces (docs/cmg.md; the core's
``analysis/cmg_envelope.rs`` and ``analysis/cmg_singular_surface.rs``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _core
from .._util.arrays import vector
from ..errors import ArgumentError


@dataclass(frozen=True)
class CmgEnvelope:
    """The envelope's points ``points[i, j]`` (N·m·s, in the base frame) in the directions
    ``directions[i, j]`` (unit), on a grid of ``elevation[i]`` × ``azimuth[j]`` (rad)."""

    elevation: np.ndarray
    azimuth: np.ndarray
    directions: np.ndarray
    points: np.ndarray

    @property
    def magnitude(self) -> np.ndarray:
        """``|H|`` of each point, N·m·s."""
        return np.linalg.norm(self.points, axis=-1)

    def plot(self, ax=None):
        """Draw the envelope as a surface (matplotlib 3-D axes; made when not given)."""
        import matplotlib.pyplot as plt

        if ax is None:
            ax = plt.figure().add_subplot(projection="3d")
        p = self.points
        ax.plot_surface(p[..., 0], p[..., 1], p[..., 2], cmap="viridis", alpha=0.8, linewidth=0)
        ax.set_xlabel("H_x, N m s")
        ax.set_ylabel("H_y, N m s")
        ax.set_zlabel("H_z, N m s")
        ax.set_title("CMG momentum envelope")
        return ax


def _cluster(what: str, robot, wheel_speed, gimbal_axes, h):
    """The gimbal axes and rotor momenta of a cluster, from ``robot`` (its CMGs, ``wheel_speed``)
    or given (``gimbal_axes``, ``h``)."""
    if robot is not None:
        if gimbal_axes is not None or h is not None:
            raise ArgumentError(f"{what}: give robot (with wheel_speed) or gimbal_axes with h, not both")
        cmgs = list(robot.cmg_dofs.values())
        if not cmgs:
            raise ArgumentError(f"{what}: the robot has no CMG (RobotBuilder.add_cmg)")
        if wheel_speed is None:
            raise ArgumentError(f"{what}: give wheel_speed (rad/s), one number or one per CMG")
        speeds = np.broadcast_to(np.asarray(wheel_speed, dtype=float), (len(cmgs),))
        gimbal_axes = [c["gimbal_axis"] for c in cmgs]
        h = [c["rotor_inertia"] * w for c, w in zip(cmgs, speeds)]
    elif gimbal_axes is None or h is None:
        raise ArgumentError(f"{what}: give robot (with wheel_speed) or gimbal_axes with h")
    g = [list(vector(a, f"{what} gimbal axis", 3)) for a in gimbal_axes]
    hs = [float(v) for v in np.atleast_1d(np.asarray(h, dtype=float))]
    return g, hs


def _grid(what: str, n):
    """The elevation × azimuth grid of unit directions (``n`` elevations, ``2n + 1`` azimuths)."""
    if not (isinstance(n, (int, np.integer)) and n >= 2):
        raise ArgumentError(f"{what}: n must be an integer >= 2, got {n!r}")
    el = np.linspace(-np.pi / 2, np.pi / 2, int(n))
    az = np.linspace(-np.pi, np.pi, 2 * int(n) + 1)  # closed: the first and last meridians meet
    E, A = np.meshgrid(el, az, indexing="ij")
    return el, az, np.stack([np.cos(E) * np.cos(A), np.cos(E) * np.sin(A), np.sin(E)], axis=-1)


def cmg_envelope(robot=None, *, wheel_speed=None, gimbal_axes=None, h=None, n: int = 36) -> CmgEnvelope:
    """The momentum envelope of a CMG cluster: for each direction ``u`` the largest momentum the
    cluster holds along it, ``H(u) = Σ h_i ŝ_i`` with every spin axis as close to ``u`` as its
    gimbal plane allows (docs/cmg.md). Either ``robot`` (its [`cmg_dofs`][spacearm.Robot.cmg_dofs], the
    rotor momenta ``h_i = J_s,i · wheel_speed`` with ``wheel_speed`` one number or one per CMG,
    rad/s) or ``gimbal_axes`` (k × 3) with ``h`` (k rotor momenta, N·m·s). ``n``: the grid's
    points in elevation (and ``2n + 1`` in azimuth, both ends at ±180°)."""
    g, hs = _cluster("cmg_envelope", robot, wheel_speed, gimbal_axes, h)
    el, az, d = _grid("cmg_envelope", n)
    pts = np.array(_core.analysis_cmg_envelope(g, hs, d.reshape(-1, 3).tolist())).reshape(d.shape)
    return CmgEnvelope(el, az, d, pts)


@dataclass(frozen=True)
class CmgSingularSurfaces:
    """The singular surfaces of a CMG cluster (docs/cmg.md, "The singular surfaces"): for sign
    pattern ``signs[k]`` (``ε_i = ±1`` per CMG) and direction ``directions[i, j]`` (the singular
    direction ``u``, on the ``elevation[i]`` × ``azimuth[j]`` grid, rad), the singular momentum
    ``points[k, i, j]`` (N·m·s, base frame) and the spin axes ``spin_axes[k, i, j]`` (one unit row
    per CMG) that hold it; NaN where ``u`` lies along a gimbal axis. ``signs[0]`` all ``+1`` is the
    outer surface, the momentum envelope; the others are internal."""

    elevation: np.ndarray
    azimuth: np.ndarray
    directions: np.ndarray
    signs: np.ndarray
    points: np.ndarray
    spin_axes: np.ndarray

    @property
    def negatives(self) -> np.ndarray:
        """The number of negative signs of each pattern (0: the outer surface)."""
        return np.sum(self.signs < 0, axis=1)

    def plot(self, ax=None, *, negatives=None):
        """Draw the surfaces whose patterns have ``negatives`` negative signs (all when None),
        one colour per pattern (matplotlib 3-D axes; made when not given)."""
        import matplotlib.pyplot as plt

        if ax is None:
            ax = plt.figure().add_subplot(projection="3d")
        for k, p in enumerate(self.points):
            if negatives is None or self.negatives[k] == negatives:
                ax.plot_surface(p[..., 0], p[..., 1], p[..., 2], color=f"C{k % 10}", alpha=0.35, linewidth=0)
        ax.set_xlabel("H_x, N m s")
        ax.set_ylabel("H_y, N m s")
        ax.set_zlabel("H_z, N m s")
        return ax


def cmg_singular_surfaces(robot=None, *, wheel_speed=None, gimbal_axes=None, h=None, signs=None,
                          n: int = 36) -> CmgSingularSurfaces:
    """The singular surfaces of a CMG cluster's momentum space (Margulies & Aubrun 1978; the core's
    ``analysis/cmg_singular_surface.rs``): for a singular direction ``u`` and signs ``ε_i = ±1``,
    the spin axes ``ŝ_i = ε_i (ĝ_i × u) × ĝ_i / |ĝ_i × u|`` make the cluster's Jacobian singular
    (``Aᵀ u = 0``) and hold ``H = Σ h_i ŝ_i``. The cluster as for [`cmg_envelope`][spacearm.analysis.cmg_envelope]
    (``robot`` with ``wheel_speed``, or ``gimbal_axes`` with ``h``); ``signs``: the patterns
    (m × k, each entry ±1), default all ``2^(k-1)`` distinct ones (``ε_1 = +1``: ``ε`` and ``-ε``
    sweep the same surface), the outer one first; ``n``: the grid of [`cmg_envelope`][spacearm.analysis.cmg_envelope]."""
    g, hs = _cluster("cmg_singular_surfaces", robot, wheel_speed, gimbal_axes, h)
    el, az, d = _grid("cmg_singular_surfaces", n)
    if signs is not None:
        arr = np.asarray(signs, dtype=float)
        if arr.ndim == 1:
            arr = arr[None, :]
        if arr.ndim != 2:
            raise ArgumentError(f"cmg_singular_surfaces: signs must be one pattern or a list of patterns of ±1, got shape {arr.shape}")
        signs = arr.tolist()
    used, pts, spins = _core.analysis_cmg_singular_surfaces(g, hs, signs, d.reshape(-1, 3).tolist())
    used = np.array(used, dtype=float)
    m = len(used)
    return CmgSingularSurfaces(el, az, d, used, np.array(pts).reshape((m,) + d.shape),
                               np.array(spins).reshape((m,) + d.shape[:2] + (len(g), 3)))
