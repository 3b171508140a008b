"""Serial arms from Denavit–Hartenberg tables, in two conventions (``docs/dh.md``).

``convention="classic"`` — the classic (distal) Denavit–Hartenberg convention. DH frame ``i``
is fixed to link ``i`` with its ``z`` axis on joint ``i+1``, and
``T[i-1 -> i] = Rot_z(theta_i) Trans_z(d_i) Trans_x(a_i) Rot_x(alpha_i)``; joint ``i`` turns
about (revolute: ``theta_i + q_i``) or slides along (prismatic: ``d_i + q_i``) ``z_{i-1}``.
Each row gives ``d, theta, a, alpha`` and the link's ``com`` (its CM in DH frame ``i``),
``mass`` and ``inertia`` (about the CM, DH frame ``i`` axes). The tip point is DH frame ``N``'s
origin plus ``tool_offset`` (in frame ``N``).

``convention="paper"`` — Wilde et al. (2018) §2 (also SPART's). The base is link 0; link
frame ``L_i`` has its origin at the link CM and is aligned with the frame of the next joint
(whose ``z`` axis is that joint's axis); consecutive frames turn by
``Rot_z(theta_i + q_i) Rot_x(alpha_i)``. Each row gives ``theta`` and ``alpha`` (default 0),
``joint_to_com`` (``a_i``: joint ``i`` to CM ``i``, in ``L_i``), ``com_to_next`` (``b_i``: CM ``i``
to joint ``i+1``, in ``L_i``), ``mass`` and ``inertia`` (about the CM, ``L_i`` axes). The tip
point is joint ``N+1`` (``b_N`` from the last CM) plus ``tool_offset``.

In both, joint 1's frame (classic: DH frame 0) sits on the base at ``joint1_origin`` (from
the base CM, base axes) with orientation ``joint1_rotation`` (quaternion ``[x, y, z, w]``) or
``joint1_rpy``; its ``z`` axis is joint 1's axis.

>>> import spacearm
>>> bar = [0.002, 0.834, 0.834]  # 10 kg, 1 m bar about its CM
>>> robot = spacearm.io.dh.robot_from_dh(
...     "planar2", base_mass=100.0, base_inertia=[4.0, 4.0, 4.0], joint1_origin=(0.25, 0, 0),
...     links=[dict(d=0, theta=0, a=1.0, alpha=0, com=(-0.5, 0, 0), mass=10.0, inertia=bar)] * 2)
>>> robot.n_dof
2
"""

from __future__ import annotations

from typing import Mapping, Optional, Sequence

import numpy as np

from .. import _core
from .._util.arrays import matrix3, number, quaternion, vector
from ..errors import ModelError
from ..model.robot import Robot
from ..rotations import quat_from_rpy

__all__ = ["robot_from_dh", "CONVENTIONS"]

#: Accepted values of ``convention``.
CONVENTIONS = ("classic", "paper")

_COMMON = ("name", "joint_name", "type", "mass", "inertia", "limits")
_KEYS = {
    "classic": _COMMON + ("d", "theta", "a", "alpha", "com"),
    "paper": _COMMON + ("theta", "alpha", "joint_to_com", "com_to_next"),
}
_REQUIRED = {
    "classic": ("d", "theta", "a", "alpha", "com", "mass", "inertia"),
    "paper": ("joint_to_com", "com_to_next", "mass", "inertia"),
}


def _limits(row: Mapping, who: str):
    lim = row.get("limits")
    if lim is None:
        return None
    if not isinstance(lim, Mapping):
        raise ModelError(f"{who}: limits must be a dict with any of lower, upper, velocity, effort, got {lim!r}")
    unknown = set(lim) - {"lower", "upper", "velocity", "effort"}
    if unknown:
        raise ModelError(f"{who}: unknown limit keys {sorted(unknown)}; expected lower, upper, velocity, effort")
    return [_number(lim, key, f"{who} limits", default)
            for key, default in (("lower", -np.inf), ("upper", np.inf), ("velocity", np.inf), ("effort", np.inf))]


def _number(row: Mapping, key: str, who: str, default=None) -> float:
    value = row.get(key, default)
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ModelError(f"{who}: {key} must be a number, got {value!r}") from None


def _row(row, k: int, convention: str) -> tuple:
    who = f"DH link {k + 1}"
    if not isinstance(row, Mapping):
        raise ModelError(f"{who}: each DH row is a dict (keys: {', '.join(_KEYS[convention])}), got {type(row).__name__}")
    unknown = [key for key in row if key not in _KEYS[convention]]
    if unknown:
        raise ModelError(
            f"{who}: unknown key(s) {unknown} for the {convention} convention; expected {', '.join(_KEYS[convention])}"
        )
    missing = [key for key in _REQUIRED[convention] if key not in row]
    if missing:
        raise ModelError(f"{who}: missing {missing}; the {convention} convention needs {', '.join(_REQUIRED[convention])}")
    name = None if row.get("name") is None else str(row["name"])
    who = f"{who} ('{name or f'link{k + 1}'}')"
    joint_name = None if row.get("joint_name") is None else str(row["joint_name"])
    kind = str(row.get("type", "revolute"))
    mass = _number(row, "mass", who)
    inertia = matrix3(row["inertia"], f"{who} inertia")
    limits = _limits(row, who)
    if convention == "classic":
        d, theta, a, alpha = (_number(row, key, who) for key in ("d", "theta", "a", "alpha"))
        com = list(vector(row["com"], f"{who} com", 3))
        return (name, joint_name, kind, d, theta, a, alpha, com, mass, inertia, limits)
    theta = _number(row, "theta", who, 0.0)
    alpha = _number(row, "alpha", who, 0.0)
    to_com = list(vector(row["joint_to_com"], f"{who} joint_to_com", 3))
    to_next = list(vector(row["com_to_next"], f"{who} com_to_next", 3))
    return (name, joint_name, kind, theta, alpha, to_com, to_next, mass, inertia, limits)


def robot_from_dh(
    name: str,
    links: Sequence[Mapping],
    *,
    base_mass: float,
    base_inertia,
    convention: str = "classic",
    base_name: str = "base",
    joint1_origin: Sequence[float] = (0.0, 0.0, 0.0),
    joint1_rotation: Optional[Sequence[float]] = None,
    joint1_rpy: Optional[Sequence[float]] = None,
    tool_offset: Sequence[float] = (0.0, 0.0, 0.0),
    tip_point: Optional[str] = "end_effector",
    initial_q: Optional[Sequence[float]] = None,
) -> Robot:
    """A spacecraft base carrying one serial arm given by a DH table.

    Parameters
    ----------
    name:
        Model name.
    links:
        One dict per link, base to tip. Keys for ``convention="classic"``: ``d`` (m),
        ``theta`` (rad), ``a`` (m), ``alpha`` (rad), ``com`` (CM in DH frame ``i``, m), ``mass``
        (kg), ``inertia`` (about the CM in DH frame ``i`` axes: 3×3 or its diagonal, kg·m²).
        For ``convention="paper"``: ``theta`` and ``alpha`` (rad, default 0),
        ``joint_to_com`` and ``com_to_next`` (m, in the link frame), ``mass``, ``inertia``.
        Optional in both: ``type`` (``"revolute"``, default, ``"prismatic"`` or
        ``"fixed"``), ``name`` (default ``link{i}``), ``joint_name`` (default ``joint{i}``),
        ``limits`` (dict with any of ``lower``, ``upper``, ``velocity``, ``effort``).
    base_mass, base_inertia:
        Base mass (kg, > 0) and inertia about its CM in base axes (3×3 or diagonal).
    convention:
        ``"classic"`` or ``"paper"`` (module docstring, ``docs/dh.md``).
    base_name:
        Name of the base body.
    joint1_origin, joint1_rotation, joint1_rpy:
        Pose of joint 1's frame (classic: DH frame 0) in the base CM frame; its ``z`` axis is
        joint 1's axis. Give the rotation as a quaternion ``[x, y, z, w]`` (or a scipy
        ``Rotation``) or as URDF
        roll-pitch-yaw (rad), not both; default: aligned with the base.
    tool_offset:
        Offset of the tip point in the last link frame (classic: from DH frame ``N``'s origin;
        paper: from joint ``N+1``), m.
    tip_point:
        Name of the point added at the tip and made the end effector (``None``: none).
    initial_q:
        Initial joint coordinates (length N, default zeros).

    Returns
    -------
    Robot
        Link frames at the link CMs with the DH frame axes (inertias need no rotation); see
        ``docs/dh.md`` for the conversion.

    Raises
    ------
    ModelError
        Unknown or missing keys, non-finite numbers, negative masses, non-physical inertias,
        a non-unit ``joint1_rotation``: the message names the DH row.
    """
    if convention not in CONVENTIONS:
        raise ModelError(f"convention must be 'classic' or 'paper', got {convention!r}")
    if isinstance(links, (Mapping, str, bytes)) or not isinstance(links, Sequence):
        raise ModelError(f"links must be a list of dicts (one per DH row), got {type(links).__name__}")
    rows = [_row(row, k, convention) for k, row in enumerate(links)]
    if joint1_rotation is not None and joint1_rpy is not None:
        raise ModelError("give joint1_rotation or joint1_rpy, not both")
    if joint1_rpy is not None:
        rotation = list(quat_from_rpy(*vector(joint1_rpy, "joint1_rpy", 3)))
    elif joint1_rotation is not None:
        rotation = list(quaternion(joint1_rotation, "joint1_rotation"))
    else:
        rotation = [0.0, 0.0, 0.0, 1.0]
    return Robot(
        _core.model_from_dh(
            convention,
            str(name),
            str(base_name),
            number(base_mass, "base_mass"),
            matrix3(base_inertia, "base_inertia"),
            rows,
            list(vector(joint1_origin, "joint1_origin", 3)),
            rotation,
            list(vector(tool_offset, "tool_offset", 3)),
            None if tip_point is None else str(tip_point),
            None if initial_q is None else list(vector(initial_q, "initial_q")),
        )
    )
