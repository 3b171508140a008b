"""The momentum envelope of a CMG cluster (docs/cmg.md; the core's ``analysis/cmg_envelope.rs``)."""

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


def cmg_envelope(robot=None, *, wheel_speed=None, gimbal_axes=None, h=None, n: int = 36) -> CmgEnvelope:
    """The momentum envelope of a CMG cluster: for each direction ``u`` the largest momentum the
    cluster holds along it, ``H(u) = Σ h_i ŝ_i`` with every spin axis as close to ``u`` as its
    gimbal plane allows (docs/cmg.md). Either ``robot`` (its [`cmg_dofs`][spacearm.Robot.cmg_dofs], the
    rotor momenta ``h_i = J_s,i · wheel_speed`` with ``wheel_speed`` one number or one per CMG,
    rad/s) or ``gimbal_axes`` (k × 3) with ``h`` (k rotor momenta, N·m·s). ``n``: the grid's
    points in elevation (and ``2n + 1`` in azimuth, both ends at ±180°)."""
    if robot is not None:
        if gimbal_axes is not None or h is not None:
            raise ArgumentError("cmg_envelope: give robot (with wheel_speed) or gimbal_axes with h, not both")
        cmgs = list(robot.cmg_dofs.values())
        if not cmgs:
            raise ArgumentError("cmg_envelope: the robot has no CMG (RobotBuilder.add_cmg)")
        if wheel_speed is None:
            raise ArgumentError("cmg_envelope: give wheel_speed (rad/s), one number or one per CMG")
        speeds = np.broadcast_to(np.asarray(wheel_speed, dtype=float), (len(cmgs),))
        gimbal_axes = [c["gimbal_axis"] for c in cmgs]
        h = [c["rotor_inertia"] * w for c, w in zip(cmgs, speeds)]
    elif gimbal_axes is None or h is None:
        raise ArgumentError("cmg_envelope: give robot (with wheel_speed) or gimbal_axes with h")
    g = [list(vector(a, "cmg_envelope gimbal axis", 3)) for a in gimbal_axes]
    hs = [float(v) for v in np.atleast_1d(np.asarray(h, dtype=float))]
    if not (isinstance(n, (int, np.integer)) and n >= 2):
        raise ArgumentError(f"cmg_envelope: n must be an integer >= 2, got {n!r}")
    el = np.linspace(-np.pi / 2, np.pi / 2, int(n))
    az = np.linspace(-np.pi, np.pi, 2 * int(n) + 1)  # closed: the first and last meridians meet
    E, A = np.meshgrid(el, az, indexing="ij")
    d = np.stack([np.cos(E) * np.cos(A), np.cos(E) * np.sin(A), np.sin(E)], axis=-1)
    pts = np.array(_core.analysis_cmg_envelope(g, hs, d.reshape(-1, 3).tolist())).reshape(d.shape)
    return CmgEnvelope(el, az, d, pts)
