"""What the engine converters share: the model's tree read from ``Robot.description``, the
depth-first joint order of the exported models, the block transforms ``blkdiag(R0 or E, R0,
P_e)``, and the checks of the MATLAB libraries' state arrays (formulas in the docstring of
[`spacearm.interop`][spacearm.interop])."""

from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional, Tuple

import numpy as np

from .._util.arrays import vector
from ..errors import ArgumentError, NonFiniteError, QuaternionError, ShapeError
from ..model.description import PointDescription
from ..rotations import quat_to_matrix

#: Name of the free-flyer / free joint of the base in the exported models.
ROOT_JOINT = "root_joint"


# ---------------------------------------------------------------------------------------------
# the model's tree, read from Robot.description
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Body:
    index: int  # spacearm body index (0 = base)
    name: str
    parent: int  # -1 for the base
    kind: str  # "base", "revolute", "prismatic" or "fixed"
    joint: Optional[str]
    origin: np.ndarray  # joint position in the parent frame (from the parent CM)
    rotation: np.ndarray  # 3×3, child frame in parent frame at q = 0
    axis: np.ndarray  # unit axis in the child frame
    com: np.ndarray  # child CM from the joint, in the child frame
    mass: float
    inertia: np.ndarray  # 3×3 about the CM, child axes
    dof: Optional[int]  # spacearm dof index, None for the base and fixed joints
    # the joint's passive dynamics (docs/flexibility.md): motor, spring -k (q - rest), damper -c qd
    actuated: bool = True
    stiffness: float = 0.0
    damping: float = 0.0
    rest: float = 0.0


def _tree(robot) -> Tuple[List[_Body], List[List[int]], Tuple[PointDescription, ...]]:
    """Bodies (index order), children lists (link order) and points of ``robot``."""
    d = robot.description
    bodies = [
        _Body(0, d.base.name, -1, "base", None, np.zeros(3), np.eye(3), np.zeros(3), np.zeros(3),
              d.base.mass, np.array(d.base.inertia), None)
    ]
    # Writable copies: the engines' bindings may not accept read-only arrays.
    for k, link in enumerate(d.links):
        bodies.append(_Body(
            k + 1, link.name, link.parent_index, link.type, link.joint,
            np.array(link.origin), quat_to_matrix(link.rotation), np.array(link.axis), np.array(link.com),
            link.mass, np.array(link.inertia), link.dof,
            link.actuated, link.stiffness, link.damping, link.rest,
        ))
    children: List[List[int]] = [[] for _ in bodies]
    for b in bodies[1:]:
        children[b.parent].append(b.index)
    return bodies, children, d.points


def _depth_first(children: List[List[int]]) -> List[int]:
    """Body indices in depth-first pre-order from the base (children in link order)."""
    order, stack = [], [0]
    while stack:
        b = stack.pop()
        order.append(b)
        stack.extend(reversed(children[b]))
    return order


def engine_dof_order(robot) -> np.ndarray:
    """spacearm dof index of each joint dof of the exported Pinocchio and MuJoCo models.

    Both engines number joints depth-first (see the module docstring), so
    ``q_engine = q[order]`` and ``q[order] = q_engine``; the permutation matrix ``P_e`` of the
    converters has ``P_e[order[k], k] = 1``. The identity for a serial chain.
    """
    bodies, children, _ = _tree(robot)
    return np.array([bodies[b].dof for b in _depth_first(children) if bodies[b].dof is not None], dtype=int)


# ---------------------------------------------------------------------------------------------
# argument helpers
# ---------------------------------------------------------------------------------------------
def _split_x(robot, x) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    x = vector(x, "x", robot.nx)
    return x[:3], x[3:7], x[7:]


def _base_rotation(robot, x) -> np.ndarray:
    return quat_to_matrix(_split_x(robot, x)[1])


def _block_transform(robot, x, linear_rotated: bool) -> np.ndarray:
    """``blkdiag(R0 or E, R0, P_e)`` at configuration ``x``."""
    n = robot.n_dof
    r0 = _base_rotation(robot, x)
    t = np.zeros((6 + n, 6 + n))
    t[:3, :3] = r0 if linear_rotated else np.eye(3)
    t[3:6, 3:6] = r0
    order = engine_dof_order(robot)
    t[6 + order, 6 + np.arange(n)] = 1.0
    return t


def _square(m, n: int, name: str) -> np.ndarray:
    m = np.asarray(m, dtype=float)
    if m.shape != (n, n):
        raise ShapeError(f"{name} must be {n}×{n} (6+N), got shape {m.shape}")
    return m


# ---------------------------------------------------------------------------------------------
# SPART and SpaceDyn (MATLAB libraries; states only)
# ---------------------------------------------------------------------------------------------
#: How far from orthonormal (max |RᵀR − E|) a rotation matrix given to a converter may be.
ROTATION_TOLERANCE = 1e-6


def _checked_state(robot, x, u) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(r0, R0, q, u)`` of a spacearm state, checked as [`Robot`][spacearm.Robot] checks it."""
    x = vector(x, "x", robot.nx)
    u = vector(u, "u", robot.nu)
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(u))):
        raise NonFiniteError("x and u must be finite")
    norm = np.linalg.norm(x[3:7])
    if abs(norm - 1.0) > 1e-6:
        raise QuaternionError(f"the base quaternion x[3:7] must have unit norm (within 1e-6), got norm {norm:.9g}")
    return x[:3].copy(), quat_to_matrix(x[3:7]), x[7:].copy(), u


def _rotation(value, name: str) -> np.ndarray:
    try:
        r = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ShapeError(f"{name} must be a 3×3 rotation matrix of numbers, got {value!r}") from exc
    if r.shape != (3, 3):
        raise ShapeError(f"{name} must be a 3×3 rotation matrix, got shape {r.shape}")
    if not np.all(np.isfinite(r)):
        raise NonFiniteError(f"{name} must be finite")
    err = np.max(np.abs(r.T @ r - np.eye(3)))
    if err > ROTATION_TOLERANCE or np.linalg.det(r) <= 0:
        raise ArgumentError(f"{name} must be a proper rotation matrix (orthonormal within {ROTATION_TOLERANCE:g}, "
                            f"determinant +1); got max|{name}ᵀ{name} − E| = {err:.3g}, det = {np.linalg.det(r):.6g}")
    return r


def _finite(value, name: str, length: int) -> np.ndarray:
    v = vector(value, name, length)
    if not np.all(np.isfinite(v)):
        raise NonFiniteError(f"{name} must be finite, got {v}")
    return v
