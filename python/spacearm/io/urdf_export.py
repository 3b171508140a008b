"""URDF export: any spacearm model as a URDF document (docs/urdf.md, "Export").

The inverse of [`spacearm.io.urdf`][spacearm.io.urdf]'s frame conversion. URDF puts a link frame at its joint;
spacearm puts it at the CM (docs/conventions.md). So each spacearm body becomes a URDF link
whose frame is at its **joint** with the body's axes, its ``<inertial><origin>`` is the
spacearm ``com``, and a child joint's URDF ``<origin xyz>`` is the spacearm ``origin`` (from
the parent CM) plus the parent's ``com``. The base becomes the root link with its frame at the
base CM. Named points become massless links on fixed joints (a URDF has no other way to name a
frame); reading the file back merges them into their bodies as points again. Each geometry
(docs/geometry.md) becomes a ``<visual>`` or ``<collision>`` of its body's link, its origin
moved by the body's ``com`` like the joints'; a capsule is written as ``<capsule>`` (the
extension Drake and SDFormat read; ROS's urdfdom skips it), a visual's colour as an inline
``<material>``.

A control-moment gyro (docs/cmg.md) is written, by default (``cmgs="links"``), as what it is in
the model, its gimbal and rotor links and joints, which every URDF reader understands and
spacearm recognizes again as a CMG; ``cmgs="element"`` writes each CMG that is exactly what the
core's ``cmg_parts`` makes (unturned frames, CMs at the gimbal joint, the gimbal's inertia
principal along the gimbal and spin axes, no springs, no shapes) as spacearm's ``<spacearm><cmg .../>``
extension element instead, where its links would be (docs/urdf.md), and any other as links.

Joints without position limits are written as ``continuous`` (revolute) or as ``prismatic``
without ``lower``/``upper``; infinite velocity or effort limits are left out (URDF cannot
write infinity). Every number is written in its shortest round-trip form (``repr``), so reading
the file back reproduces the model to rounding (rotations go through roll-pitch-yaw angles).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np

from .._util.atomic import write_text
from ..errors import ArgumentError
from ..rotations import quat_to_matrix

__all__ = ["to_urdf", "save_urdf"]

_CMG_WRITING = ("links", "element")


def _num(v: float) -> str:
    return repr(float(v) + 0.0)  # + 0.0: no negative zeros


def _vec(v) -> str:
    return " ".join(_num(x) for x in v)


def _rpy(quat) -> np.ndarray:
    """URDF roll-pitch-yaw (``R = Rz(yaw) Ry(pitch) Rx(roll)``) of a quaternion ``[x, y, z, w]``."""
    r = quat_to_matrix(quat)
    pitch = math.atan2(-r[2, 0], math.hypot(r[0, 0], r[1, 0]))
    if math.hypot(r[0, 0], r[1, 0]) > 1e-12:
        return np.array([math.atan2(r[2, 1], r[2, 2]), pitch, math.atan2(r[1, 0], r[0, 0])])
    # gimbal lock (pitch = ±90°): only roll ∓ yaw is defined; put it all in roll
    return np.array([math.atan2(-r[1, 2], r[1, 1]), pitch, 0.0])


def _inertial(link: ET.Element, mass: float, com, inertia) -> None:
    el = ET.SubElement(link, "inertial")
    ET.SubElement(el, "origin", xyz=_vec(com), rpy="0 0 0")
    ET.SubElement(el, "mass", value=_num(mass))
    i = np.asarray(inertia, dtype=float)
    ET.SubElement(el, "inertia", ixx=_num(i[0, 0]), ixy=_num(i[0, 1]), ixz=_num(i[0, 2]),
                  iyy=_num(i[1, 1]), iyz=_num(i[1, 2]), izz=_num(i[2, 2]))


def _geometry(link: ET.Element, g, com) -> None:
    """``g`` (a GeometryDescription) as a ``<visual>`` or ``<collision>`` of ``link``, whose
    frame is at the joint: the geometry's origin from the CM plus the body's ``com``."""
    el = ET.Element(g.role, name=g.name)
    # URDF wants <inertial> first by convention; visuals and collisions follow it.
    link.append(el)
    ET.SubElement(el, "origin", xyz=_vec(g.origin + com), rpy=_vec(_rpy(g.rotation)))
    geometry = ET.SubElement(el, "geometry")
    if g.shape == "box":
        ET.SubElement(geometry, "box", size=_vec(g.size))
    elif g.shape in ("cylinder", "capsule"):
        ET.SubElement(geometry, g.shape, radius=_num(g.radius), length=_num(g.length))
    elif g.shape == "sphere":
        ET.SubElement(geometry, "sphere", radius=_num(g.radius))
    else:
        ET.SubElement(geometry, "mesh", filename=g.file, scale=_vec(g.scale))
    if g.role == "visual":
        material = ET.SubElement(el, "material", name=f"{g.name}_color")
        ET.SubElement(material, "color", rgba=_vec(g.rgba))


def _cmg_elements(robot, com) -> dict:
    """``{gimbal link name: (rotor link name, <cmg> attributes)}`` of every CMG of ``robot`` that
    the element describes exactly (module docs): its ``CmgSpec`` fields read back from the links."""
    d = robot.description
    out = {}
    shaped = {g.body for g in d.geometries}  # an element has no <visual> or <collision>
    for name, c in robot.cmg_dofs.items():
        g_link = d.links[robot.body_of_dof[c["gimbal"]] - 1]
        r_link = d.links[robot.body_of_dof[c["rotor"]] - 1]
        g, s = np.asarray(g_link.axis, dtype=float), np.asarray(r_link.axis, dtype=float)
        t = np.cross(g, s)
        axes = np.array([g, s, t])
        gi = axes @ np.asarray(g_link.inertia, dtype=float) @ axes.T  # the gimbal's inertia in (g, s, t)
        ri = axes @ np.asarray(r_link.inertia, dtype=float) @ axes.T
        scale = max(float(np.abs(gi).max()), float(np.abs(ri).max()), 1e-300)
        exact = (np.array_equal(g_link.rotation, [0.0, 0.0, 0.0, 1.0]) and np.array_equal(r_link.rotation, [0.0, 0.0, 0.0, 1.0])
                 and not np.any(g_link.com) and not np.any(r_link.com) and not np.any(r_link.origin)
                 and np.abs(gi - np.diag(np.diag(gi))).max() <= 1e-12 * scale
                 and g_link.actuated and all(v == 0.0 for v in (g_link.stiffness, g_link.damping, g_link.rest,
                                                                r_link.stiffness, r_link.damping, r_link.rest))
                 and not any(np.isfinite(v) for v in (g_link.limits.lower, g_link.limits.upper, r_link.limits.lower, r_link.limits.upper))
                 and (r_link.actuated or not np.isfinite(r_link.limits.effort))
                 and g_link.name not in shaped and r_link.name not in shaped)
        if not exact:
            continue
        attrs = {"name": name, "parent": g_link.parent, "position": _vec(np.asarray(g_link.origin) + com[g_link.parent]),
                 "gimbal_axis": _vec(g), "spin_axis": _vec(s), "rotor_inertia": _num(ri[1, 1]),
                 "rotor_transverse_inertia": _num(ri[0, 0]), "gimbal_inertia": _vec(np.diag(gi)),
                 "rotor_mass": _num(r_link.mass), "gimbal_mass": _num(g_link.mass),
                 "variable_speed": "true" if r_link.actuated else "false"}
        for key, v in (("max_gimbal_rate", g_link.limits.velocity), ("max_wheel_speed", r_link.limits.velocity),
                       ("max_gimbal_torque", g_link.limits.effort), ("max_wheel_torque", r_link.limits.effort)):
            if np.isfinite(v):
                attrs[key] = _num(v)
        out[g_link.name] = (r_link.name, attrs)
    return out


def to_urdf(robot, *, cmgs: str = "links") -> str:
    """The model as URDF text (``<robot name>`` = the model name); ``cmgs``: ``"links"`` (default)
    or ``"element"`` (module docs)."""
    if cmgs not in _CMG_WRITING:
        raise ArgumentError(f"cmgs must be one of {_CMG_WRITING}, got {cmgs!r}")
    d = robot.description
    root = ET.Element("robot", name=robot.name)
    # URDF frames sit at the joints, spacearm's at the CMs: a body's CM from its URDF frame.
    com = {d.base.name: np.zeros(3)}
    base = ET.SubElement(root, "link", name=d.base.name)
    _inertial(base, d.base.mass, np.zeros(3), d.base.inertia)
    elements = {d.base.name: base}
    for link in d.links:
        com[link.name] = link.com
    as_element = _cmg_elements(robot, com) if cmgs == "element" else {}
    rotors = {rotor for rotor, _ in as_element.values()}
    for link in d.links:
        if link.name in as_element:
            # spacearm's extension element where the gimbal's link would be (the importer numbers
            # the joints in document order, depth first: the CMG keeps its degrees of freedom).
            ET.SubElement(ET.SubElement(root, "spacearm"), "cmg", **as_element[link.name][1])
            continue
        if link.name in rotors:
            continue
        el = ET.SubElement(root, "link", name=link.name)
        elements[link.name] = el
        _inertial(el, link.mass, link.com, link.inertia)
        com[link.name] = link.com
        lim = link.limits
        lower, upper, velocity, effort = lim.lower, lim.upper, lim.velocity, lim.effort
        kind = link.type
        if kind == "revolute" and not (np.isfinite(lower) and np.isfinite(upper)):
            kind, lower, upper = "continuous", -np.inf, np.inf
        joint = ET.SubElement(root, "joint", name=link.joint, type=kind)
        ET.SubElement(joint, "parent", link=link.parent)
        ET.SubElement(joint, "child", link=link.name)
        ET.SubElement(joint, "origin", xyz=_vec(link.origin + com[link.parent]), rpy=_vec(_rpy(link.rotation)))
        if kind != "fixed":
            ET.SubElement(joint, "axis", xyz=_vec(link.axis))
            limits = {k: _num(v) for k, v in (("lower", lower), ("upper", upper), ("velocity", velocity), ("effort", effort))
                      if np.isfinite(v)}
            if limits:
                ET.SubElement(joint, "limit", **limits)
            # The joint's passive dynamics (docs/flexibility.md): URDF's damping, and the
            # <spacearm> extension element for the spring and passivity.
            if link.damping != 0.0:
                ET.SubElement(joint, "dynamics", damping=_num(link.damping))
            ext = {k: _num(v) for k, v in (("stiffness", link.stiffness), ("rest", link.rest)) if v != 0.0}
            if not link.actuated:
                ext["actuated"] = "false"
            if ext:
                ET.SubElement(joint, "spacearm", **ext)
    for g in d.geometries:
        _geometry(elements[g.body], g, com[g.body])
    for p in d.points:
        ET.SubElement(root, "link", name=p.name)
        joint = ET.SubElement(root, "joint", name=f"{p.name}_point", type="fixed")
        ET.SubElement(joint, "parent", link=p.body)
        ET.SubElement(joint, "child", link=p.name)
        ET.SubElement(joint, "origin", xyz=_vec(p.offset + com[p.body]), rpy="0 0 0")
    ET.indent(root)
    return '<?xml version="1.0"?>\n<!-- written by spacearm (docs/urdf.md) -->\n' + ET.tostring(root, encoding="unicode") + "\n"


def save_urdf(robot, path, *, cmgs: str = "links") -> None:
    """Write [`to_urdf`][spacearm.io.to_urdf] to ``path`` atomically (``spacearm._util.atomic``: temporary
    file, flush, rename; the mode of a normal file)."""
    write_text(path, to_urdf(robot, cmgs=cmgs), suffix=".urdf")
