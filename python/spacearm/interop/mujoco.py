"""MuJoCo: the MJCF text and compiled ``mujoco.MjModel`` of a spacearm model and the maps of
states, forces, accelerations, mass matrices and bias forces between the two layouts
(``T_mj = blkdiag(E, R0, P_e)``: the docstring of [`spacearm.interop`][spacearm.interop]). MuJoCo
(``pip install mujoco``) is imported only inside [`to_mujoco`][spacearm.interop.to_mujoco]."""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from typing import Tuple

import numpy as np

from .._util.arrays import vector
from .._util.atomic import atomic_open, write_text
from .._util.optional import require
from ..errors import ArgumentError, ModelError, ModelFileError, NotFoundError
from ..rotations import quat_from_matrix
from ._common import ROOT_JOINT, _block_transform, _split_x, _square, _tree, engine_dof_order

__all__ = [
    "to_mjcf",
    "to_mujoco",
    "save_mjcf",
    "actuator_controls",
    "mjcf_body_name",
    "to_mujoco_state",
    "from_mujoco_state",
    "to_mujoco_force",
    "from_mujoco_force",
    "to_mujoco_acceleration",
    "acceleration_from_mujoco",
    "mass_matrix_from_mujoco",
    "bias_from_mujoco",
    "mujoco_transform",
]


def _import_mujoco():
    return require("mujoco", "spacearm.interop's MuJoCo functions")


def _fmt(values) -> str:
    # repr-precision floats: the exported model must reproduce spacearm's to the last bit
    return " ".join(repr(float(v)) for v in np.ravel(values))


def _quat_wxyz(r: np.ndarray) -> np.ndarray:
    x, y, z, w = quat_from_matrix(r)
    return np.array([w, x, y, z])


#: The principal moment (kg·m²) written for a zero principal moment of a moving body with mass
#: (a point mass: a slosh bob, a spring–mass; a slender rod without ``rho_J``), which MuJoCo
#: refuses below ``mjMINVAL = 1e-15``: the only inexact entry of the export, below rounding
#: of any model's mass matrix in SI units.
POINT_INERTIA = 1e-13

#: The fraction of its parent's mass lent to a zero-mass moving body with inertia whose CM is
#: on its revolute axis (a compliant joint's rotor) and taken from the parent's inertial at the
#: same point: the point never moves in the parent, so the dynamics are unchanged (exact).
LENT_MASS = 1e-6


def _inertial(parent: ET.Element, mass: float, inertia: np.ndarray, pos=(0.0, 0.0, 0.0), floor: float = 0.0) -> None:
    """The full tensor about ``pos``; a semi-definite one (a massless link, a point mass, a slender
    rod), which MuJoCo's ``fullinertia`` refuses, as its principal moments (at least ``floor``)
    and axes."""
    i = np.asarray(inertia, dtype=float)
    moments, axes = np.linalg.eigh(i)
    if moments[0] > 0:
        ET.SubElement(parent, "inertial", pos=_fmt(pos), mass=repr(float(mass)),
                      fullinertia=_fmt([i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]))
        return
    if np.linalg.det(axes) < 0:
        axes[:, 2] = -axes[:, 2]
    ET.SubElement(parent, "inertial", pos=_fmt(pos), mass=repr(float(mass)), quat=_fmt(_quat_wxyz(axes)),
                  diaginertia=_fmt(np.maximum(moments, floor)))


def _hom(rotation=None, translation=None) -> np.ndarray:
    t = np.eye(4)
    if rotation is not None:
        t[:3, :3] = rotation
    if translation is not None:
        t[:3, 3] = translation
    return t


def _massless(body) -> bool:
    return body.kind not in ("base", "fixed") and body.mass == 0.0 and not np.any(np.asarray(body.inertia))


def _merged_chains(robot, bodies, children, points_on, geoms_on) -> dict:
    """``{b: [m1, ..., mk]}``: the massless moving links (zero mass and inertia) merged into the
    MuJoCo body of ``b``, top first: each has ``b`` (or the next of them) as its only child and
    no point or shape (they would move with the child's joints). Anything else is refused."""
    chains = {}
    for body in bodies:
        if not _massless(body) or (body.parent >= 0 and _massless(bodies[body.parent])):
            continue
        chain, b = [], body.index
        while _massless(bodies[b]):
            what = f"MJCF export of '{robot.name}': link '{bodies[b].name}' (joint '{bodies[b].joint}') has no mass and no inertia"
            if points_on.get(b) or geoms_on.get(b):
                raise ModelError(f"{what} and carries points or shapes; MuJoCo refuses a massless moving body, and they "
                                 "cannot move to its child's body (the child's joint moves them): put them on the child")
            if len(children[b]) != 1:
                raise ModelError(f"{what} and {len(children[b])} child links; MuJoCo refuses a massless moving body, and "
                                 "only one with exactly one child is exported (merged into the child's body as a joint)")
            chain.append(b)
            b = children[b][0]
        chains[b] = chain
    return chains


def _lent_masses(robot, bodies, chains, fraction: float = LENT_MASS) -> dict:
    """``{parent: [(mass, point in the parent frame)]}`` for the zero-mass moving links with
    inertia (rotors): the point mass ``fraction·m_parent`` (default ``LENT_MASS``) each takes
    from its parent."""
    lent = {}
    merged = {m for chain in chains.values() for m in chain}
    for body in bodies[1:]:
        if body.kind == "fixed" or body.mass != 0.0 or _massless(body) or body.index in merged:
            continue
        what = f"MJCF export of '{robot.name}': link '{body.name}' has inertia but no mass, which MuJoCo refuses"
        on_axis = body.kind == "revolute" and np.linalg.norm(np.cross(body.com, body.axis)) <= 1e-12 * max(1.0, np.linalg.norm(body.com))
        parent = bodies[body.parent]
        if not on_axis or body.index in chains or parent.mass <= 0.0:
            raise ModelError(f"{what}; it is exported only on a revolute joint with its CM on the axis, directly on a "
                             "parent with mass (a rotor: it then borrows a point mass from its parent at its CM)")
        lent.setdefault(body.parent, []).append((fraction * parent.mass, body.origin + body.rotation @ body.com))
    return lent


def _lender_inertial(el: ET.Element, body, loans) -> None:
    """The inertial of ``body`` less the point masses it lends (CM moved, inertia by parallel
    axes), checked physical."""
    given = sum(m for m, _ in loans)
    mass = body.mass - given
    first = sum(m * d for m, d in loans)
    i_origin = np.array(body.inertia, dtype=float)
    for m, d in loans:
        i_origin -= m * (d @ d * np.eye(3) - np.outer(d, d))
    com = -first / mass
    i_com = i_origin - mass * (com @ com * np.eye(3) - np.outer(com, com))
    moments = np.linalg.eigvalsh(i_com)
    if moments[0] <= 0 or moments[2] > moments[0] + moments[1]:
        raise ModelError(f"MJCF export: body '{body.name}' cannot lend its rotors' point masses ({given:g} kg): "
                         f"its remaining inertia {moments} would not be physical")
    _inertial(el, mass, i_com, pos=com)


#: MJCF geom groups of the two geometry roles (MuJoCo's viewer shows groups 0-2 by default).
GEOM_GROUP = {"visual": 1, "collision": 3}

#: Mesh formats MuJoCo reads itself (others are converted to STL by `save_mjcf` and `to_mjcf(assets=...)`).
MUJOCO_MESH_FORMATS = (".stl", ".obj")

#: Names of the world site the base actuators' forces are expressed in, and of the base CM site.
WORLD_SITE = "world_frame"
BASE_SITE = "base_cm"


def _geom(parent: ET.Element, g, meshes: dict) -> None:
    """``g`` (a GeometryDescription) as a massless ``<geom>`` in its body: MuJoCo's sizes are
    half lengths (a box's half sides; a cylinder's and capsule's radius and half length)."""
    attrs = dict(name=g.name, pos=_fmt(g.origin), quat=_fmt(np.array([g.rotation[3], *g.rotation[:3]])),
                 rgba=_fmt(g.rgba), group=str(GEOM_GROUP[g.role]), contype="0", conaffinity="0", mass="0")
    if g.shape == "box":
        attrs.update(type="box", size=_fmt(np.asarray(g.size) / 2))
    elif g.shape in ("cylinder", "capsule"):
        attrs.update(type=g.shape, size=_fmt([g.radius, g.length / 2]))
    elif g.shape == "sphere":
        attrs.update(type="sphere", size=_fmt([g.radius]))
    else:
        key = (g.file, tuple(float(v) for v in g.scale))
        attrs.update(type="mesh", mesh=meshes.setdefault(key, f"mesh{len(meshes)}"))
    ET.SubElement(parent, "geom", **attrs)


def _mesh_assets(root: ET.Element, meshes: dict, assets) -> None:
    """The ``<asset><mesh>`` of each mesh used: its file by path, or, with ``assets`` a dict, by
    a file name whose bytes are put in ``assets`` (MuJoCo's in-memory VFS)."""
    if not meshes:
        return
    asset = ET.Element("asset")
    root.insert(2, asset)
    for (file, scale), name in meshes.items():
        suffix = os.path.splitext(file)[1].lower()
        if not os.path.isfile(file):
            raise ModelFileError(f"mesh '{file}' of the model does not exist (a package:// file not found when the URDF was "
                                 "read? pass package_dirs=[...] to load_urdf)")
        readable = suffix in MUJOCO_MESH_FORMATS
        if assets is None:
            if not readable:
                raise ArgumentError(f"mesh '{file}': MuJoCo reads {', '.join(MUJOCO_MESH_FORMATS)} meshes, not '{suffix}'; "
                                    "save_mjcf(robot, path) converts it into a folder beside the MJCF (to_mjcf(robot, "
                                    "assets={}) into MuJoCo's in-memory files)")
            ET.SubElement(asset, "mesh", name=name, file=os.path.abspath(file), scale=_fmt(scale))
        else:
            # A format MuJoCo cannot read (COLLADA, PLY, glTF...) is converted to STL here
            # (trimesh, the `mesh` extra), in the file's units; `scale` still applies on top.
            if readable:
                asset_name = f"{name}{suffix}"
                with open(file, "rb") as fh:
                    assets[asset_name] = fh.read()
            else:
                from .._util.meshes import converted_bytes

                asset_name = f"{name}.stl"
                assets[asset_name] = converted_bytes(file, "stl")
            ET.SubElement(asset, "mesh", name=name, file=asset_name, scale=_fmt(scale))


#: The export's headlight (``<visual><headlight ambient diffuse>``), grey levels in [0, 1].
HEADLIGHT = ((0.35, 0.35, 0.35), (0.6, 0.6, 0.6))

#: MuJoCo's name of its world body: a spacearm body of that name is exported as ``world_body``.
MUJOCO_WORLD = "world"


def mjcf_body_name(name: str) -> str:
    """The MJCF name of the spacearm body ``name`` (itself, but ``world`` → ``world_body``)."""
    return f"{name}_body" if name == MUJOCO_WORLD else name


#: The weld's constraint softness (MuJoCo's ``solref`` time constant, s, and damping ratio; its
#: ``solimp``): stiffer than MuJoCo's defaults, the time constant at the 2-step floor of the
#: default 2 ms step (MuJoCo's ``refsafe``), the impedance near 1.
WELD_SOLREF = (0.004, 1.0)
WELD_SOLIMP = (0.99, 0.999, 0.001, 0.5, 2.0)


def _welded_bodies(robot, weld) -> list:
    """The body indices of the links named in ``weld``, checked: each a fixed link of
    ``robot`` below which no joint moves (its whole subtree rides on it)."""
    if isinstance(weld, str):
        weld = (weld,)
    names = robot.body_names
    out = []
    links = robot.description.links
    for w in weld:
        w = str(w)
        if w not in names or names.index(w) == 0:
            raise NotFoundError(f"weld: '{w}' is not a link of '{robot.name}'; the links are {list(names[1:])}")
        b = names.index(w)
        if links[b - 1].type != "fixed":
            raise ArgumentError(f"weld: link '{w}' is on a {links[b - 1].type} joint; only a fixed link (a payload, "
                                "a captured target) is exported as a free body held by a weld")
        sub = {b}
        for k, link in enumerate(links):  # links come after their parents
            if link.parent_index in sub:
                sub.add(k + 1)
                if link.type != "fixed":
                    raise ArgumentError(f"weld: joint '{link.joint}' below '{w}' moves; a welded body's subtree must be rigid")
        if b in out:
            raise ArgumentError(f"weld: '{w}' is named twice")
        out.append(b)
    return out


def to_mjcf(robot, *, geometry=("visual", "collision"), actuators: bool = True, base_actuators: bool = False,
            assets=None, weld=(), lent_mass: float = LENT_MASS, contact=None, target=None, effective_mass=None) -> str:
    """The MJCF (MuJoCo XML) text of ``robot``.

    - Every MuJoCo body frame IS the spacearm body frame (origin at the CM, link axes), so the
      inertial sits at ``pos="0 0 0"`` with the full inertia tensor (``fullinertia``) and named
      points become ``<site>`` elements at their offsets.
    - Base: a ``<freejoint>`` (not re-aligned to the principal axes: ``align="false"``), so
      ``qpos[:3]`` is the base CM and ``qvel[3:6]`` the angular velocity in base axes.
    - Link: body ``pos = origin + R_rot com`` and ``quat = rotation`` (wxyz) in the parent body
      frame; a hinge/slide joint at ``pos = -com`` (the joint position, in the link frame)
      about ``axis``. A fixed link is a body without a joint (welded; ``fusestatic`` off keeps
      it as its own body).
    - Massless moving links (zero mass and inertia: the links between the joints of a beam
      station, the spherical slosh pendulum's gimbal), which MuJoCo refuses, are merged into the
      body of their only child: that body carries their joints first, then its own, each joint's
      ``pos`` and ``axis`` expressed in the child's body frame at the zero of the later joints
      (MuJoCo applies a body's joints in order, each in the frame the earlier ones moved), so
      ``qpos`` keeps spacearm's depth-first joint order. A massless link with points, shapes or
      other than one child is a [`ModelError`][spacearm.ModelError].
    - A zero-mass link with inertia on a revolute joint with its CM on the axis (a compliant
      joint's rotor, a reaction wheel of ``mass=0``) borrows ``lent_mass`` (default ``LENT_MASS``) of its parent's mass
      as a point at its CM, taken from the parent's inertial (moved CM, parallel axes): that
      point never moves in the parent, so the dynamics are unchanged. Other zero-mass links
      with inertia are a [`ModelError`][spacearm.ModelError].
    - A zero principal moment of a moving body with mass (a point mass: a slosh bob, a
      spring–mass) is written as ``POINT_INERTIA`` (1e-13 kg·m²; MuJoCo refuses less than
      ``mjMINVAL``): the one inexact entry, below the rounding of an SI model's mass matrix.
    - A joint's spring–damper (docs/flexibility.md) as the joint's ``stiffness``, ``springref``
      (the rest coordinate) and ``damping``: MuJoCo's ``qfrc_passive`` is then spacearm's
      passive force ``-k (q - rest) - c q̇``.
    - Bodies keep their names, but one called ``world`` (MuJoCo's world body) becomes
      ``world_body`` ([`mjcf_body_name`][spacearm.interop.mjcf_body_name]).
    - ``geometry`` (the roles exported; ``()``: none): each of the model's shapes
      (docs/geometry.md) as a massless ``<geom>``
      (``mass="0"``, ``inertiafromgeom="false"``: they change no inertia), visual ones in geom
      group 1, collision ones in group 3, contacts off. Meshes (STL, OBJ) are referenced by
      their absolute paths, or, with ``assets`` a dict, by names whose bytes are put in it (for
      ``MjModel.from_xml_string(text, assets)``; [`save_mjcf`][spacearm.interop.save_mjcf]
      writes them beside the file).
    - ``actuators``: a ``<motor>`` (gear 1, so ``ctrl`` is the joint torque or force) for every
      actuated moving joint, reaction wheels included, in spacearm's ``q`` order, its
      ``ctrlrange`` the joint's effort limit where it is finite; a passive joint gets none.
    - ``base_actuators`` (the flying modes): six motors on the base CM site ``base_cm``, the
      force ``F0`` and torque ``N0`` along the axes of the world site ``world_frame``
      (``refsite``): ``ctrl[-6:] = [F0, N0]`` in 𝒥, as spacearm's base wrench.
    - ``weld`` (names of fixed links, e.g. the payload of a captured target,
      [`attach_target`][spacearm.capture.attach_target]): each is written as a free body of
      the world (``<freejoint name="<link>_free">``, its subtree with it) held to its parent by
      ``<equality><weld body1="<parent>" body2="<link>" relpose="...">`` at the fixed joint's
      pose (``relpose``: the link's frame in the parent's, position then quaternion wxyz),
      ``solref`` ``WELD_SOLREF`` and ``solimp`` ``WELD_SOLIMP`` (stiffer than MuJoCo's defaults). Its XML pose is its pose at the
      robot's ``qpos0`` (the core's kinematics). MuJoCo's state then has 7 ``qpos`` and 6
      ``qvel`` more per welded body, after the robot's
      ([`to_mujoco_state`][spacearm.interop.to_mujoco_state] with the same ``weld``).
    - ``<visual><headlight>`` brighter than MuJoCo's default (``HEADLIGHT``).
    - ``target`` (a rigid model: a ``spacearm.Target`` or a ``Robot`` without joints, the free
      target of ``simulate(..., target=)``): a free body of the world named as its body
      (``<freejoint name="<body>_free">``) with its shapes, after the robot's bodies; its
      ``qpos``/``qvel`` follow the robot's
      ([`target_qpos_qvel`][spacearm.interop.mujoco_contact.target_qpos_qvel]).
    - ``contact`` (a [`ContactModel`][spacearm.contact.ContactModel]): contacts on (elliptic
      cones), a ``<contact><pair>`` for each pair of collision geoms it admits (the shapes keep
      ``contype``/``conaffinity`` 0, so no other pair collides) with the law mapped by
      [`mujoco_contact_parameters`][spacearm.interop.mujoco_contact.mujoco_contact_parameters]
      at ``effective_mass`` (kg, every pair; or ``{(geom_a, geom_b): kg}``), docs/contact.md,
      "In MuJoCo".
    - ``<option gravity="0 0 0">``, contacts disabled (unless ``contact``), armature and friction loss explicitly
      zero (damping and stiffness zero unless the joint has them), no limits, RK4 (the
      integrator changes no term of the continuous-time dynamics), and the ``energy`` flag on
      so that ``MjData.energy`` holds the kinetic energy.
    """
    bodies, children, points = _tree(robot)
    root = ET.Element("mujoco", model=robot.name)
    ET.SubElement(root, "compiler", angle="radian", inertiafromgeom="false", autolimits="true",
                  alignfree="false", fusestatic="false", boundmass="0", boundinertia="0", balanceinertia="false")
    option = ET.SubElement(root, "option", gravity="0 0 0", integrator="RK4", density="0", viscosity="0")
    if contact is not None:
        if effective_mass is None:
            raise ArgumentError("to_mjcf(contact=...) needs effective_mass: the mass (kg) the contacts' normal sees, "
                                "to map the stiffness and damping onto MuJoCo's solref (docs/contact.md, \"In MuJoCo\")")
        option.set("cone", "elliptic")
    ET.SubElement(option, "flag", contact="disable" if contact is None else "enable", energy="enable")
    visual = ET.SubElement(root, "visual")  # a brighter headlight than MuJoCo's: the model shows on the black sky
    ET.SubElement(visual, "headlight", ambient=_fmt(HEADLIGHT[0]), diffuse=_fmt(HEADLIGHT[1]))
    world = ET.SubElement(root, "worldbody")
    if base_actuators:
        ET.SubElement(world, "site", name=WORLD_SITE, pos="0 0 0", size="0.01")
    ET.SubElement(world, "light", name="sun", directional="true", pos="0 0 10", dir="0 0 -1")

    points_on = {}
    for p in points:
        points_on.setdefault(robot.body_index(p.body), []).append((p.name, p.offset))
    geoms_on = {}
    for g in robot.description.geometries:
        if g.role in tuple(geometry):
            geoms_on.setdefault(g.body_index, []).append(g)
    meshes: dict = {}
    welded = _welded_bodies(robot, weld)
    kin0 = robot.forward_kinematics(robot.neutral_configuration(np.zeros(robot.n_dof))) if welded else None

    chains = _merged_chains(robot, bodies, children, points_on, geoms_on)
    for b in welded:
        if chains.get(b):
            raise ArgumentError(f"weld: '{bodies[b].name}' hangs on the massless link '{bodies[chains[b][-1]].name}', "
                                "whose joint would be lost in a free body: weld a link below a link with mass")
    if not (isinstance(lent_mass, (int, float)) and 0.0 < lent_mass < 0.1):
        raise ArgumentError(f"lent_mass must be a fraction in (0, 0.1) of a rotor's parent mass, got {lent_mass!r}")
    lent = _lent_masses(robot, bodies, chains, float(lent_mass))
    lenders = {b for b in lent}

    def joint_el(el: ET.Element, j, pos, axis) -> None:
        ET.SubElement(el, "joint", name=j.joint, type="hinge" if j.kind == "revolute" else "slide",
                      pos=_fmt(pos), axis=_fmt(axis), limited="false",
                      damping=repr(float(j.damping)), stiffness=repr(float(j.stiffness)),
                      springref=repr(float(j.rest)), armature="0", frictionloss="0")

    def emit(parent_el: ET.Element, b: int) -> None:
        body = bodies[b]
        if b in chains:
            chain = [bodies[m] for m in chains[b]]
            top = chain[0] if chain else body
            # G_i: the joint frame of chain[i] → the merged body's frame at the zero of the later joints
            g = _hom(translation=body.com)
            frames = [g]
            for upper, lower in zip(reversed(chain), [body] + list(reversed(chain[1:]))):
                g = _hom(translation=upper.com) @ _hom(lower.rotation, lower.origin) @ g
                frames.append(g)
            frames.reverse()  # frames[i] belongs to chain[i]; frames[-1] to body
            pose = _hom(top.rotation, top.origin) @ frames[0]
            el = ET.SubElement(parent_el, "body", name=mjcf_body_name(body.name), pos=_fmt(pose[:3, 3]),
                               quat=_fmt(_quat_wxyz(pose[:3, :3])))
            for j, gi in zip(chain + [body], frames):
                if j.kind != "fixed":
                    r, t = gi[:3, :3], gi[:3, 3]
                    joint_el(el, j, -r.T @ t, r.T @ j.axis)
        elif b == 0:
            el = ET.SubElement(parent_el, "body", name=mjcf_body_name(body.name), pos="0 0 0")
            ET.SubElement(el, "freejoint", name=ROOT_JOINT, align="false")
        elif b in welded:  # a free body of the world at its pose in the robot's qpos0
            el = ET.SubElement(parent_el, "body", name=mjcf_body_name(body.name), pos=_fmt(kin0.com_in_world[b]),
                               quat=_fmt(_quat_wxyz(kin0.body_to_world[b])))
            ET.SubElement(el, "freejoint", name=f"{body.name}_free", align="false")
        else:
            pos = body.origin + body.rotation @ body.com
            el = ET.SubElement(parent_el, "body", name=mjcf_body_name(body.name), pos=_fmt(pos), quat=_fmt(_quat_wxyz(body.rotation)))
            if body.kind != "fixed":
                joint_el(el, body, -body.com, body.axis)
        if b in lenders:
            _lender_inertial(el, body, lent[b])
        elif body.mass == 0.0 and body.kind not in ("base", "fixed") and np.any(np.asarray(body.inertia)):
            _inertial(el, lent_mass * bodies[body.parent].mass, body.inertia)  # a rotor: the mass its parent lends
        else:
            moves = b == 0 or b in welded or bool(chains.get(b)) or body.kind != "fixed"
            if moves and body.mass <= 0.0:
                raise ModelError(f"MJCF export of '{robot.name}': body '{body.name}' moves in MuJoCo (a free body, or the "
                                 "child a massless link is merged into) but has no mass, which MuJoCo refuses: give it a mass")
            _inertial(el, body.mass, body.inertia, floor=POINT_INERTIA if moves else 0.0)
        if b == 0 and base_actuators:
            ET.SubElement(el, "site", name=BASE_SITE, pos="0 0 0", size="0.01")
        for g in geoms_on.get(b, []):
            _geom(el, g, meshes)
        for name, offset in points_on.get(b, []):
            ET.SubElement(el, "site", name=name, pos=_fmt(offset), size="0.01")
        for c in children[b]:
            while _massless(bodies[c]):  # merged into the body of its (only) child
                c = children[c][0]
            if c not in welded:
                emit(el, c)

    emit(world, 0)
    for b in welded:
        emit(world, b)
    if target is not None:
        target = _free_target_model(target)
        tb = _tree(target)[0][0]
        el = ET.SubElement(world, "body", name=mjcf_body_name(tb.name), pos="0 0 0")
        ET.SubElement(el, "freejoint", name=f"{tb.name}_free", align="false")
        _inertial(el, tb.mass, tb.inertia, floor=POINT_INERTIA)
        for g in target.description.geometries:
            if g.role in tuple(geometry):
                _geom(el, g, meshes)
    if contact is not None:
        from .mujoco_contact import write_contact

        write_contact(root, robot, contact, target, effective_mass)
    if welded:
        eq = ET.SubElement(root, "equality")
        for b in welded:
            body = bodies[b]
            rel = np.concatenate([body.origin + body.rotation @ body.com, _quat_wxyz(body.rotation)])
            ET.SubElement(eq, "weld", name=f"{body.name}_weld", body1=mjcf_body_name(bodies[body.parent].name),
                          body2=mjcf_body_name(body.name), relpose=_fmt(rel), solref=_fmt(WELD_SOLREF), solimp=_fmt(WELD_SOLIMP))
    _mesh_assets(root, meshes, assets)
    if actuators or base_actuators:
        act = ET.SubElement(root, "actuator")
        if actuators:
            moving = sorted((b for b in bodies if b.dof is not None and b.actuated), key=lambda b: b.dof)
            effort = {link.name: link.limits.effort for link in robot.description.links}
            for b in moving:
                attrs = dict(name=f"{b.joint}_motor", joint=b.joint, gear="1")
                if np.isfinite(effort[b.name]):
                    attrs.update(ctrlrange=_fmt([-effort[b.name], effort[b.name]]), ctrllimited="true")
                ET.SubElement(act, "motor", **attrs)
        if base_actuators:
            for k, axis in enumerate(("fx", "fy", "fz", "tx", "ty", "tz")):
                gear = np.zeros(6)
                gear[k] = 1.0
                ET.SubElement(act, "motor", name=f"base_{axis}", site=BASE_SITE, refsite=WORLD_SITE, gear=_fmt(gear))
    ET.indent(root)
    return ET.tostring(root, encoding="unicode")


def _free_target_model(target):
    """The rigid ``Robot`` of a free target (a ``spacearm.Target``'s body, or the model itself)."""
    from ..model.robot import Robot

    if not isinstance(target, Robot) and isinstance(getattr(target, "body", None), Robot):
        target = target.body
    if not isinstance(target, Robot) or target.n_dof != 0:
        raise ArgumentError(f"target must be a rigid model (a spacearm.Target or a Robot without joints), got {type(target).__name__}")
    return target


def to_mujoco(robot, **options):
    """The compiled ``mujoco.MjModel`` of [`to_mjcf`][spacearm.interop.to_mjcf] (same
    keywords but ``assets``: meshes travel in memory)."""
    mujoco = _import_mujoco()
    assets: dict = {}
    return mujoco.MjModel.from_xml_string(to_mjcf(robot, assets=assets, **options), assets)


def save_mjcf(robot, path, **options) -> None:
    """Write [`to_mjcf`][spacearm.interop.to_mjcf] to ``path`` with its meshes copied beside it
    (``<stem>_meshes/``, referenced relative to the file), so the folder is self-contained;
    every file written atomically."""
    path = os.fspath(path)
    assets: dict = {}
    text = to_mjcf(robot, assets=assets, **options)
    folder = os.path.splitext(os.path.basename(path))[0] + "_meshes"
    if assets:
        os.makedirs(os.path.join(os.path.dirname(os.path.abspath(path)), folder), exist_ok=True)
        for name, data in assets.items():
            with atomic_open(os.path.join(os.path.dirname(os.path.abspath(path)), folder, name), "wb") as fh:
                fh.write(data)
        text = text.replace('<compiler ', f'<compiler meshdir="{folder}" ', 1)
    write_text(path, text, suffix=".xml")


def actuator_controls(robot, tau=None, base_wrench=None, *, base_actuators: bool = False) -> np.ndarray:
    """MuJoCo ``ctrl`` of the exported actuators: the actuated joints' torques ``tau`` (N, in
    spacearm's ``q`` order; a passive joint's entry must be 0) then, with ``base_actuators``,
    ``base_wrench = [F0, N0]`` in 𝒥."""
    tau = np.zeros(robot.n_dof) if tau is None else vector(tau, "tau", robot.n_dof)
    actuated = [link.dof for link in sorted((l for l in robot.description.links if l.dof is not None and l.actuated),
                                            key=lambda l: l.dof)]
    passive = sorted(set(range(robot.n_dof)) - set(actuated))
    if passive and np.any(tau[passive] != 0):
        raise ArgumentError(f"tau drives passive joints (dofs {passive}): they have no actuator")
    ctrl = [tau[actuated]]
    if base_actuators:
        ctrl.append(np.zeros(6) if base_wrench is None else vector(base_wrench, "base_wrench", 6))
    return np.concatenate(ctrl)


def mujoco_transform(robot, x) -> np.ndarray:
    """``T_mj = blkdiag(E, R0, P_e)`` at ``x``: ``u = T_mj qvel``, ``qvel = T_mjᵀ u``."""
    return _block_transform(robot, x, linear_rotated=False)


def to_mujoco_state(robot, x, u, *, weld=()) -> Tuple[np.ndarray, np.ndarray]:
    """spacearm ``(x, u)`` → MuJoCo ``(qpos, qvel)``.

    ``qpos = [r0, w, x, y, z, q[order]]`` (quaternion scalar first) and
    ``qvel = T_mjᵀ u = [v0, R0ᵀ ω0, q̇[order]]``; with ``weld`` (the links exported as free
    bodies, [`to_mjcf`][spacearm.interop.to_mjcf]) each one's free joint follows: its CM and
    attitude ``[r_b, w, x, y, z]``, then ``[v_b, R_bᵀ ω_b]``, from the core's kinematics of
    ``robot`` at ``(x, u)`` (where the weld holds it).
    """
    r0, quat, q = _split_x(robot, x)
    u = vector(u, "u", robot.nu)
    order = engine_dof_order(robot)
    qpos = np.concatenate([r0, [quat[3]], quat[:3], q[order]])
    qvel = mujoco_transform(robot, x).T @ u
    welded = _welded_bodies(robot, weld)
    if not welded:
        return qpos, qvel
    xv = np.asarray(x, dtype=float)
    kin = robot.forward_kinematics(xv)
    extra_pos, extra_vel = [qpos], [qvel]
    for b in welded:
        rb = kin.body_to_world[b]
        j0, jm = robot.point_jacobian(xv, (b, np.zeros(3)))
        twist = j0 @ u[:6] + jm @ u[6:]
        extra_pos.append(np.concatenate([kin.com_in_world[b], _quat_wxyz(rb)]))
        extra_vel.append(np.concatenate([twist[:3], rb.T @ twist[3:]]))
    return np.concatenate(extra_pos), np.concatenate(extra_vel)


def from_mujoco_state(robot, qpos, qvel, *, weld=()) -> Tuple[np.ndarray, np.ndarray]:
    """MuJoCo ``(qpos, qvel)`` → spacearm ``(x, u)``: the quaternion goes scalar last and
    ``u = T_mj qvel``. With ``weld``, the welded bodies' free joints (the last ``7`` and ``6``
    entries per body) are dropped: in the spacearm model they ride on their parents."""
    k = len(_welded_bodies(robot, weld))
    qpos = vector(qpos, "qpos", robot.nx + 7 * k)[: robot.nx]
    qvel = vector(qvel, "qvel", robot.nu + 6 * k)[: robot.nu]
    order = engine_dof_order(robot)
    joints = np.empty(robot.n_dof)
    joints[order] = qpos[7:]
    x = np.concatenate([qpos[:3], qpos[4:7], qpos[3:4], joints])
    return x, mujoco_transform(robot, x) @ qvel


def to_mujoco_force(robot, x, f) -> np.ndarray:
    """spacearm ``f`` → MuJoCo generalized force (e.g. ``qfrc_applied``) ``T_mjᵀ f =
    [F0, R0ᵀ N0, τ[order]]``."""
    return mujoco_transform(robot, x).T @ vector(f, "f", robot.nu)


def from_mujoco_force(robot, x, qfrc) -> np.ndarray:
    """MuJoCo generalized force → spacearm ``f = T_mj qfrc``."""
    return mujoco_transform(robot, x) @ vector(qfrc, "qfrc", robot.nu)


def acceleration_from_mujoco(robot, x, qacc) -> np.ndarray:
    """MuJoCo ``qacc`` → spacearm ``u̇ = T_mj qacc`` (no velocity-product term: the free
    joint's linear velocity is in 𝒥 and ``d/dt(R0ᵀ ω0) = R0ᵀ ω̇0``)."""
    return mujoco_transform(robot, x) @ vector(qacc, "qacc", robot.nu)


def to_mujoco_acceleration(robot, x, du) -> np.ndarray:
    """spacearm ``u̇`` → MuJoCo ``qacc = T_mjᵀ u̇``."""
    return mujoco_transform(robot, x).T @ vector(du, "du", robot.nu)


def mass_matrix_from_mujoco(robot, x, M) -> np.ndarray:
    """MuJoCo dense mass matrix (``mujoco.mj_fullM``) → spacearm ``H = T_mj M T_mjᵀ``."""
    t = mujoco_transform(robot, x)
    return t @ _square(M, robot.nu, "M") @ t.T


def bias_from_mujoco(robot, x, qfrc_bias) -> np.ndarray:
    """MuJoCo ``qfrc_bias`` (zero gravity) → spacearm ``c = T_mj qfrc_bias``."""
    return mujoco_transform(robot, x) @ vector(qfrc_bias, "qfrc_bias", robot.nu)
