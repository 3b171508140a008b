"""Spatial algebra on CasADi symbols, in spacearm's frame: spatial vectors with the axes of 𝒥,
referred to the point fixed in 𝒥 that coincides with the base CM at the current instant,
ordered ``[linear (3); angular (3)]`` (docs/architecture.md, "One reference point for every
spatial quantity"). Every body shares that one frame, so the recursions never transform a
vector between bodies.

The functions take and return CasADi column matrices (``SX`` or ``MX``); constants may be
numpy arrays. The formulas are Featherstone's (*Rigid Body Dynamics Algorithms*, 2008, §2.9,
§2.13) with his ``[angular; linear]`` blocks swapped to the paper's ``[linear; angular]`` order.
"""

from __future__ import annotations

import numpy as np


def skew(ca, v):
    """``[v]×``, the 3×3 matrix with ``[v]× w = v × w``."""
    return ca.vertcat(
        ca.horzcat(0, -v[2], v[1]),
        ca.horzcat(v[2], 0, -v[0]),
        ca.horzcat(-v[1], v[0], 0),
    )


def quaternion_to_matrix(ca, quat):
    """Rotation matrix of the quaternion ``[x, y, z, w]`` (Hamilton), normalised first so that
    the function is defined (and its derivative tangent to the unit sphere) off the sphere."""
    qx, qy, qz, qw = (quat[i] for i in range(4))
    n2 = qx * qx + qy * qy + qz * qz + qw * qw
    s = 2.0 / n2
    return ca.vertcat(
        ca.horzcat(1 - s * (qy * qy + qz * qz), s * (qx * qy - qz * qw), s * (qx * qz + qy * qw)),
        ca.horzcat(s * (qx * qy + qz * qw), 1 - s * (qx * qx + qz * qz), s * (qy * qz - qx * qw)),
        ca.horzcat(s * (qx * qz - qy * qw), s * (qy * qz + qx * qw), 1 - s * (qx * qx + qy * qy)),
    )


def axis_rotation(ca, axis: np.ndarray, angle):
    """Rotation by ``angle`` about the constant unit ``axis`` (Rodrigues' formula)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + ca.sin(angle) * k + (1 - ca.cos(angle)) * (k @ k)


def motion_cross(ca, twist, motion):
    """``twist ×ₘ motion``: the rate of change of ``motion`` carried by a body moving with
    ``twist`` (both ``[linear; angular]``)."""
    v, w = twist[0:3], twist[3:6]
    ml, ma = motion[0:3], motion[3:6]
    return ca.vertcat(ca.cross(w, ml) + ca.cross(v, ma), ca.cross(w, ma))


def force_cross(ca, twist, force):
    """``twist ×* force``: the rate of change of a spatial force (or momentum) carried by a
    body moving with ``twist``; ``force = [force; torque about the reference point]``."""
    v, w = twist[0:3], twist[3:6]
    fl, fa = force[0:3], force[3:6]
    return ca.vertcat(ca.cross(w, fl), ca.cross(w, fa) + ca.cross(v, fl))


def body_inertia(ca, mass: float, com_from_ref, inertia_at_com_in_world):
    """Spatial inertia (6×6) about the reference point of a body of ``mass`` whose CM is at
    ``com_from_ref`` (from the reference point, in 𝒥) with rotational inertia
    ``inertia_at_com_in_world`` (about its CM, axes of 𝒥): the momentum ``[m v_c; h_ref]``
    of the body moving with twist ``[v_ref; ω]`` is this matrix times the twist."""
    c = skew(ca, com_from_ref)
    return ca.vertcat(
        ca.horzcat(mass * ca.DM.eye(3), -mass * c),
        ca.horzcat(mass * c, inertia_at_com_in_world - mass * ca.mtimes(c, c)),
    )
