"""An MJCF model (a Basilisk MuJoCo scenario's XML) read into a spacearm robot.

MuJoCo itself compiles the file (``pip install mujoco``: defaults, includes, ``xyaxes`` /
``axisangle`` orientations, degrees, and every body's mass and inertia from its geoms'
``density`` are MuJoCo's), and the compiled ``MjModel`` is converted into one
[`Robot`][spacearm.Robot] (``docs/basilisk.md``, "Basilisk's models into spacearm"):

- the root body (on a ``<freejoint>``) is the base, its frame moved to its CM (spacearm's base
  frame, ``docs/conventions.md``), its axes kept;
- each body below is a link whose frame is the MuJoCo body's axes at its CM, on its
  ``hinge`` (revolute) or ``slide`` (prismatic) joint, or on none (fixed); a body with several
  joints becomes a chain of massless links named ``<body>__<joint>``, one per joint but the
  last (MuJoCo applies them in order, each in the frame the earlier ones moved); ``rotation`` =
  ``body_quat``, joint ``origin`` = ``body_pos + R jnt_pos - ipos_parent`` in the parent's
  frame, ``com`` = ``ipos - jnt_pos``, ``axis`` = ``jnt_axis``, inertia
  ``R_i diag(body_inertia) R_iᵀ`` (``R_i`` from ``body_iquat``);
- a joint driven by an actuator is actuated, one without is passive; ``range`` (``limited``)
  becomes the joint limits, ``stiffness``, ``damping`` and ``springref`` the joint's
  spring–damper; ``<site>``s become named points.

What cannot be imported is a [`ModelError`][spacearm.ModelError] naming the body or element:
a ``ball`` joint, a body fixed to the world, several free
bodies (a formation, a docking pair: pick one tree with ``root``), tendons, equality
constraints, joint armature or friction loss. Geoms, contacts, gravity and actuator gains are
not part of spacearm's multibody model and are not read.
"""

from __future__ import annotations

import os

import numpy as np

from ..errors import ModelError, SpacearmTypeError
from ..interop.mujoco import _import_mujoco
from ..model.robot import Robot

__all__ = ["from_mjcf"]


def _xyzw(wxyz) -> list:
    w, x, y, z = (float(v) for v in wxyz)
    return [x, y, z, w]


def _rot(wxyz) -> np.ndarray:
    w, x, y, z = (float(v) for v in wxyz)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _compile(source):
    mujoco = _import_mujoco()
    if not isinstance(source, (str, os.PathLike)):
        raise SpacearmTypeError(f"from_mjcf needs a path or the XML text, got {type(source).__name__}")
    text = os.fspath(source)
    try:
        if text.lstrip().startswith("<"):
            return mujoco.MjModel.from_xml_string(text), "<string>"
        return mujoco.MjModel.from_xml_path(text), text
    except ValueError as exc:
        raise ModelError(f"MuJoCo cannot compile {text if not text.lstrip().startswith('<') else 'the MJCF text'}: {exc}") from None


def from_mjcf(source, *, root=None, name=None) -> Robot:
    """The spacearm [`Robot`][spacearm.Robot] of the MJCF ``source`` (a path or the XML text).

    ``root``: the name of the free body whose tree is imported (needed when the world holds
    several); ``name``: the model's name (default the MJCF ``model`` attribute or
    ``"mjcf"``). The robot's base frame is the root body's at its CM, so a MuJoCo state maps to
    spacearm's with that offset; ``H*`` and ``J*`` (joint space and point twists in 𝒥) compare
    directly. See the module's documentation for what is read and what is refused.
    """
    mujoco = _import_mujoco()
    m, where = _compile(source)
    body_name = lambda b: mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}"  # noqa: E731
    joint_name = lambda j: mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) or f"joint{j}"  # noqa: E731
    free = [b for b in range(1, m.nbody) if m.body_parentid[b] == 0]
    if root is None:
        if len(free) != 1:
            raise ModelError(f"{where}: the world holds {len(free)} bodies ({[body_name(b) for b in free]}); spacearm models one "
                             "spacecraft: name the one to import with root=")
        top = free[0]
    else:
        top = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, str(root))
        if top not in free:
            raise ModelError(f"{where}: root={root!r} is not a body of the world; they are {[body_name(b) for b in free]}")
    if m.body_jntnum[top] != 1 or int(m.jnt_type[m.body_jntadr[top]]) != int(mujoco.mjtJoint.mjJNT_FREE):
        raise ModelError(f"{where}: the root body '{body_name(top)}' must carry one <freejoint> (a spacecraft flies free); "
                         "a body fixed to the world cannot be imported")
    if m.ntendon:
        raise ModelError(f"{where}: tendons ({m.ntendon}) cannot be imported: spacearm's joints are driven one by one")
    if m.neq:
        raise ModelError(f"{where}: equality constraints ({m.neq}) cannot be imported: spacearm models an open tree "
                         "(a loop closure is spacearm.sim's closed chain, a weld a fixed link)")
    subtree = [top]
    for b in range(top + 1, m.nbody):  # MuJoCo numbers bodies parents first
        if m.body_parentid[b] in subtree:
            subtree.append(b)
    actuated = {int(m.actuator_trnid[a, 0]) for a in range(m.nu) if int(m.actuator_trntype[a]) == int(mujoco.mjtTrn.mjTRN_JOINT)}

    def inertia(b):
        r = _rot(m.body_iquat[b])
        return r @ np.diag(m.body_inertia[b]) @ r.T

    ipos = {b: np.array(m.body_ipos[b]) for b in subtree}
    builder = Robot.builder(name or m.names.split(b"\0", 1)[0].decode() or "mjcf",
                            float(m.body_mass[top]), inertia(top), base_name=body_name(top))
    for b in subtree[1:]:
        who = f"{where}: body '{body_name(b)}'"
        parent = int(m.body_parentid[b])
        rb = _rot(m.body_quat[b])
        kw = dict(parent=body_name(parent), rotation=_xyzw(m.body_quat[b]), mass=float(m.body_mass[b]), inertia=inertia(b))
        if m.body_jntnum[b] == 0:
            builder.add_link(body_name(b), joint="fixed", origin=m.body_pos[b] - ipos[parent],
                             com=ipos[b], **kw)
            continue
        hinge, slide = int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)
        joints = list(range(int(m.body_jntadr[b]), int(m.body_jntadr[b]) + int(m.body_jntnum[b])))
        # MuJoCo applies a body's joints in order, each about its axis through its position, both
        # in the body frame as the earlier joints moved it: a chain of massless links, one per
        # joint but the last, each with its frame at its joint point (body axes at q = 0).
        link_parent, at = body_name(parent), m.body_pos[b] - ipos[parent]
        for k, j in enumerate(joints):
            kind = int(m.jnt_type[j])
            if kind not in (hinge, slide):
                raise ModelError(f"{who}: joint '{joint_name(j)}' is a {mujoco.mjtJoint(kind).name[6:].lower()} joint; only "
                                 "hinge and slide joints (and the root's free joint) can be imported")
            d = int(m.jnt_dofadr[j])
            if m.dof_armature[d] != 0.0 or m.dof_frictionloss[d] != 0.0:
                raise ModelError(f"{who}: joint '{joint_name(j)}' has armature or friction loss, which spacearm does not model")
            limits = None
            if m.jnt_limited[j]:
                limits = dict(lower=float(m.jnt_range[j, 0]), upper=float(m.jnt_range[j, 1]))
            jp = np.array(m.jnt_pos[j])
            last = k == len(joints) - 1
            common = dict(joint="revolute" if kind == hinge else "prismatic", joint_name=joint_name(j),
                          axis=np.array(m.jnt_axis[j]), limits=limits, actuated=j in actuated,
                          stiffness=float(m.jnt_stiffness[j]), damping=float(m.dof_damping[d]),
                          rest=float(m.qpos_spring[m.jnt_qposadr[j]]), parent=link_parent)
            if k == 0:
                origin, rotation = at + rb @ jp, _xyzw(m.body_quat[b])
            else:
                origin, rotation = jp - previous, [0.0, 0.0, 0.0, 1.0]
            if last:
                builder.add_link(body_name(b), origin=origin, rotation=rotation, com=ipos[b] - jp, mass=kw["mass"],
                                 inertia=kw["inertia"], **common)
            else:
                link_parent = f"{body_name(b)}__{joint_name(j)}"
                builder.add_link(link_parent, origin=origin, rotation=rotation, com=np.zeros(3), mass=0.0,
                                 inertia=np.zeros((3, 3)), **common)
            previous = jp
    for s in range(m.nsite):
        b = int(m.site_bodyid[s])
        if b in subtree:
            builder.add_point(mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_SITE, s) or f"site{s}", body=body_name(b),
                              offset=np.array(m.site_pos[s]) - ipos[b])
    return builder.build()
