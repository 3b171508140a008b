"""Reading URDF text into plain records, safely and with line numbers.

This module only parses: XML → ``UrdfRobot`` (links, joints, inertials, limits, each with
the line of its element). Turning that tree into a spacearm model (frames at the CM, fixed
joints merged, choice of base) is [`spacearm.io.urdf`][spacearm.io.urdf].

Why this parser: the XML is read by the standard library's expat parser through
``defusedxml`` (a small, maintained, pure-Python guard used by pip-installed tools that read
untrusted XML). With ``forbid_entities`` and ``forbid_external`` it refuses every entity
declaration and every external DTD or entity reference before anything is expanded, so a
"billion laughs" document or an ``<!ENTITY x SYSTEM "file:///etc/passwd">`` is a
[`ModelFileError`][spacearm.ModelFileError], never an expansion. ``forbid_dtd`` refuses any
``<!DOCTYPE>`` as well: URDF has no DTD, and with an external DTD subset expat would otherwise
silently skip undefined entity references (nothing is fetched, but a name could become empty). expat also reports the line and column
of each element, which the error messages cite. A Rust crate (``urdf-rs``, ``roxmltree``)
would have meant a second XML stack in the core and a rebuild for every change; the model
itself is still validated by the Rust core when it is built.

URDF (https://wiki.ros.org/urdf/XML) numbers are attribute strings: ``xyz="0 0 0.1"``.
A link's ``<visual>`` and ``<collision>`` elements become ``UrdfGeometry`` records
(box, cylinder, sphere, ``<capsule>`` as Drake and SDFormat write it, mesh with its filename as
written; a visual's colour from its ``<material>``, inline or named at the robot level).
Elements this reader does not need (``gazebo``, ``transmission``, ``calibration``, ``safety_controller``) are ignored; elements that
change the kinematics in a way spacearm cannot represent (``mimic``) are errors. A moving
joint's ``<dynamics damping>`` is its viscous damping (``friction`` is ignored: spacearm has
no Coulomb friction), and the extension element ``<spacearm stiffness="…" rest="…"
actuated="false"/>`` inside a ``<joint>`` gives its spring and makes it passive
(docs/flexibility.md; URDF readers that do not know it ignore it, as they ignore ``<gazebo>``).
At the robot level, ``<spacearm>`` holds ``<cmg name= parent= gimbal_axis= spin_axis=
rotor_inertia= .../>`` elements: control-moment gyros, each read as the gimbal and rotor links and
joints the core's ``cmg_parts`` makes of the ``[[cmg]]`` fields (docs/urdf.md, docs/cmg.md).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Tuple

import numpy as np
from defusedxml import DefusedXmlException
from defusedxml.ElementTree import DefusedXMLParser

from .. import _core
from ..errors import ArgumentError, ModelFileError, SpacearmError
from ..rotations import quat_from_rpy, quat_to_matrix

__all__ = ["UrdfGeometry", "UrdfInertial", "UrdfLink", "UrdfJoint", "UrdfRobot", "parse_urdf", "urdf_error"]


@dataclass
class UrdfInertial:
    """A link's ``<inertial>``: mass, CM ``origin`` and ``rotation`` (of the inertial frame in
    the link frame) and the inertia matrix about the CM in the inertial frame's axes."""

    mass: float
    origin: np.ndarray
    rotation: np.ndarray
    inertia: np.ndarray
    line: int


@dataclass
class UrdfGeometry:
    """A link's ``<visual>`` or ``<collision>``: ``role``, ``shape`` and its dimension keys (as
    [`RobotBuilder.add_geometry`][spacearm.RobotBuilder.add_geometry] takes them), the pose ``origin``/``rotation``
    (matrix) in the URDF link frame, the colour (None: not given) and the name (None: not given)."""

    role: str
    shape: str
    dims: Dict[str, object]
    origin: np.ndarray
    rotation: np.ndarray
    rgba: Optional[Tuple[float, float, float, float]]
    name: Optional[str]
    line: int


@dataclass
class UrdfLink:
    name: str
    inertial: Optional[UrdfInertial]
    line: int
    geometries: List[UrdfGeometry] = field(default_factory=list)


@dataclass
class UrdfJoint:
    """A ``<joint>``; ``origin``/``rotation`` place the child link frame in the parent link
    frame at ``q = 0``; ``axis`` is in that (joint = child) frame."""

    name: str
    kind: str
    parent: str
    child: str
    origin: np.ndarray
    rotation: np.ndarray
    axis: np.ndarray
    limits: Dict[str, float]
    line: int
    #: ``actuated``, ``stiffness``, ``damping``, ``rest`` as given (docs/flexibility.md).
    dynamics: Dict[str, object] = field(default_factory=dict)


@dataclass
class UrdfRobot:
    name: str
    links: Dict[str, UrdfLink] = field(default_factory=dict)
    joints: List[UrdfJoint] = field(default_factory=list)
    source: str = "<string>"

    def error(self, line: int, message: str) -> ModelFileError:
        return urdf_error(self.source, line, message)


def urdf_error(source: str, line: int, message: str) -> ModelFileError:
    """A [`ModelFileError`][spacearm.ModelFileError] whose message starts ``source:line:`` like the TOML reader's."""
    return ModelFileError(f"{source}:{line}: {message}")


class _LineRecorder(ET.TreeBuilder):
    """A tree builder that remembers the line of every element (ElementTree drops it)."""

    def __init__(self):
        super().__init__()
        self.parser: Optional[DefusedXMLParser] = None
        self.lines: Dict[int, int] = {}

    def start(self, tag, attrs):
        el = super().start(tag, attrs)
        self.lines[id(el)] = self.parser.parser.CurrentLineNumber
        return el


def _xml_tree(text, source: str) -> Tuple[ET.Element, Dict[int, int]]:
    target = _LineRecorder()
    parser = DefusedXMLParser(target=target, forbid_dtd=True, forbid_entities=True, forbid_external=True)
    target.parser = parser
    try:
        parser.feed(text)
        root = parser.close()
    except ET.ParseError as exc:
        line, col = exc.position
        raise ModelFileError(f"{source}:{line}:{col + 1}: not well-formed XML: {exc}") from None
    except DefusedXmlException as exc:
        line = parser.parser.CurrentLineNumber if parser.parser is not None else 1
        raise urdf_error(source, line, f"refused unsafe XML ({type(exc).__name__}: {exc}); URDF files need no DTD entities") from None
    except (ValueError, RecursionError) as exc:  # e.g. expat "cannot be larger than 2 GB", deep nesting
        raise urdf_error(source, 1, f"could not parse XML: {exc}") from None
    return root, target.lines


class _Reader:
    """Turns the element tree into records; every error names the element and its line."""

    def __init__(self, lines: Dict[int, int], source: str, mimic: str, materials: Optional[Dict[str, tuple]] = None):
        self.lines = lines
        self.source = source
        self.mimic = mimic
        self.materials = {} if materials is None else materials  # robot-level <material name> -> rgba

    def line(self, el: ET.Element) -> int:
        return self.lines.get(id(el), 0)

    def fail(self, el: ET.Element, message: str) -> ModelFileError:
        return urdf_error(self.source, self.line(el), message)

    def attr(self, el: ET.Element, name: str, who: str) -> str:
        value = el.get(name)
        if value is None or value.strip() == "":
            raise self.fail(el, f"{who}: <{el.tag}> needs a non-empty '{name}' attribute")
        return value.strip()

    def numbers(self, el: ET.Element, name: str, n: int, default, who: str) -> np.ndarray:
        text = el.get(name)
        if text is None:
            return np.array(default, dtype=float)
        parts = text.split()
        try:
            values = np.array([float(p) for p in parts], dtype=float)
        except ValueError:
            raise self.fail(el, f"{who}: <{el.tag} {name}=\"{text}\"> must be {n} numbers separated by spaces") from None
        if values.shape[0] != n:
            raise self.fail(el, f"{who}: <{el.tag} {name}=\"{text}\"> must be {n} numbers, got {values.shape[0]}")
        if not np.all(np.isfinite(values)):
            raise self.fail(el, f"{who}: <{el.tag} {name}=\"{text}\"> must be finite")
        return values

    def number(self, el: ET.Element, name: str, who: str, default: Optional[float] = None) -> float:
        text = el.get(name)
        if text is None:
            if default is None:
                raise self.fail(el, f"{who}: <{el.tag}> needs a '{name}' attribute")
            return default
        try:
            value = float(text)
        except ValueError:
            raise self.fail(el, f"{who}: <{el.tag} {name}=\"{text}\"> must be a number") from None
        if math.isnan(value):
            raise self.fail(el, f"{who}: <{el.tag} {name}=\"{text}\"> must not be NaN")
        return value

    def single(self, parent: ET.Element, tag: str, who: str) -> Optional[ET.Element]:
        found = parent.findall(tag)
        if len(found) > 1:
            raise self.fail(found[1], f"{who}: more than one <{tag}> (first on line {self.line(found[0])})")
        return found[0] if found else None

    def pose(self, parent: ET.Element, who: str) -> Tuple[np.ndarray, np.ndarray]:
        """``<origin xyz rpy>`` → (position, rotation matrix); absent means identity."""
        el = self.single(parent, "origin", who)
        if el is None:
            return np.zeros(3), np.eye(3)
        xyz = self.numbers(el, "xyz", 3, [0.0, 0.0, 0.0], who)
        rpy = self.numbers(el, "rpy", 3, [0.0, 0.0, 0.0], who)
        return xyz, quat_to_matrix(quat_from_rpy(*rpy))

    def inertial(self, el: ET.Element, who: str) -> UrdfInertial:
        origin, rotation = self.pose(el, who)
        m_el = self.single(el, "mass", who)
        if m_el is None:
            raise self.fail(el, f"{who}: <inertial> needs a <mass value=...>")
        mass = self.number(m_el, "value", who)
        i_el = self.single(el, "inertia", who)
        if i_el is None:
            raise self.fail(el, f"{who}: <inertial> needs an <inertia ixx=... iyy=... izz=...>")
        v = {k: self.number(i_el, k, who, default=0.0 if k in ("ixy", "ixz", "iyz") else None)
             for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")}
        # URDF's ixy, ixz, iyz are the off-diagonal entries of the inertia matrix (not products
        # of inertia with the opposite sign), as in spacearm's TOML format.
        inertia = np.array([[v["ixx"], v["ixy"], v["ixz"]], [v["ixy"], v["iyy"], v["iyz"]], [v["ixz"], v["iyz"], v["izz"]]])
        # Each link's own inertial meets the core's rule for one body (model/body.rs: the verdict
        # and message the builder would give) here, because merging fixed links could hide a
        # negative mass or moment inside a good total. The triangle inequality is left to the
        # merged body (checked when the model is built): published URDFs often give massless
        # sensor frames rod-like inertias that violate it and vanish in the merge.
        broken = _core.body_mass_properties_error(who, mass, inertia.tolist(), triangle_inequality=False)
        if broken is not None:
            field, message = broken
            raise self.fail(m_el if field == "mass" else i_el, message)
        return UrdfInertial(mass, origin, rotation, inertia, self.line(el))

    def color(self, material: Optional[ET.Element], who: str) -> Optional[tuple]:
        """A ``<material>``'s rgba: its own ``<color>``, else the robot-level material it names."""
        if material is None:
            return None
        color = material.find("color")
        if color is not None:
            rgba = self.numbers(color, "rgba", 4, [0.7, 0.7, 0.7, 1.0], who)
            if np.any(rgba < 0) or np.any(rgba > 1):
                raise self.fail(color, f"{who}: <color rgba> must be 4 numbers in [0, 1]")
            return tuple(float(c) for c in rgba)
        return self.materials.get((material.get("name") or "").strip())

    def geometry(self, el: ET.Element, who: str) -> UrdfGeometry:
        origin, rotation = self.pose(el, who)
        g = self.single(el, "geometry", who)
        if g is None or len(g) != 1:
            raise self.fail(el if g is None else g, f"{who}: <{el.tag}> needs a <geometry> with one shape "
                                                    "(box, cylinder, sphere, capsule or mesh)")
        shape = g[0]
        dims: Dict[str, object] = {}
        if shape.tag == "box":
            dims["size"] = self.numbers(shape, "size", 3, None, who) if shape.get("size") else None
        elif shape.tag in ("cylinder", "capsule"):
            dims["radius"] = self.number(shape, "radius", who)
            dims["length"] = self.number(shape, "length", who)
        elif shape.tag == "sphere":
            dims["radius"] = self.number(shape, "radius", who)
        elif shape.tag == "mesh":
            dims["file"] = self.attr(shape, "filename", who)
            dims["scale"] = self.numbers(shape, "scale", 3, [1.0, 1.0, 1.0], who)
        else:
            raise self.fail(shape, f"{who}: unknown geometry <{shape.tag}>; expected box, cylinder, sphere, capsule or mesh")
        if dims.get("size", 0) is None:
            raise self.fail(shape, f"{who}: <box> needs a 'size' attribute")
        rgba = self.color(self.single(el, "material", who), who) if el.tag == "visual" else None
        name = (el.get("name") or "").strip() or None
        return UrdfGeometry(el.tag, shape.tag, dims, origin, rotation, rgba, name, self.line(el))

    def link(self, el: ET.Element) -> UrdfLink:
        name = self.attr(el, "name", "<link>")
        who = f"link '{name}'"
        inertial_el = self.single(el, "inertial", who)
        inertial = None if inertial_el is None else self.inertial(inertial_el, who)
        geometries = [self.geometry(g, f"{who} <{g.tag}>") for g in el if g.tag in ("visual", "collision")]
        return UrdfLink(name, inertial, self.line(el), geometries)

    def joint(self, el: ET.Element) -> UrdfJoint:
        name = self.attr(el, "name", "<joint>")
        who = f"joint '{name}'"
        kind = self.attr(el, "type", who)
        if kind in ("floating", "planar"):
            raise self.fail(el, f"{who}: type '{kind}' is not supported inside the tree (spacearm's only "
                                "multi-DOF joint is the free-flying base); supported: revolute, continuous, prismatic, fixed")
        if kind not in ("revolute", "continuous", "prismatic", "fixed"):
            raise self.fail(el, f"{who}: unknown joint type '{kind}'; expected revolute, continuous, prismatic or fixed")
        mimic = el.find("mimic")
        if mimic is not None and self.mimic != "independent":
            raise self.fail(mimic, f"{who}: <mimic> joints are not supported (a mimic joint is a constraint between "
                                   "coordinates, not a tree joint); pass mimic='independent' to load it as an "
                                   "ordinary joint with its own coordinate (as Pinocchio does by default), or remove it")
        links = {}
        for tag in ("parent", "child"):
            sub = self.single(el, tag, who)
            if sub is None:
                raise self.fail(el, f"{who}: needs a <{tag} link=...>")
            links[tag] = self.attr(sub, "link", who)
        origin, rotation = self.pose(el, who)
        axis_el = self.single(el, "axis", who)
        axis = np.array([1.0, 0.0, 0.0]) if axis_el is None else self.numbers(axis_el, "xyz", 3, [1.0, 0.0, 0.0], who)
        # The axis and the limits are checked (and the axis normalized) by the core's one
        # validation when the link is added (crates/spacearm-core/src/model/validate.rs); a refusal
        # names this joint's line (UrdfModel._add).
        limits: Dict[str, float] = {}
        limit_el = self.single(el, "limit", who)
        if limit_el is not None and kind != "fixed":
            # A continuous joint has no position limits (URDF ignores lower/upper there).
            keys = ("velocity", "effort") if kind == "continuous" else ("lower", "upper", "velocity", "effort")
            for key in keys:
                if limit_el.get(key) is not None:
                    limits[key] = self.number(limit_el, key, who)
        dynamics: Dict[str, object] = {}
        if kind != "fixed":
            dyn_el = self.single(el, "dynamics", who)
            if dyn_el is not None and dyn_el.get("damping") is not None:
                dynamics["damping"] = self.number(dyn_el, "damping", who)
            ext = self.single(el, "spacearm", who)
            if ext is not None:
                unknown = set(ext.attrib) - {"stiffness", "rest", "actuated"}
                if unknown:
                    raise self.fail(ext, f"{who}: <spacearm> takes stiffness, rest and actuated, got {sorted(unknown)}")
                for key in ("stiffness", "rest"):
                    if ext.get(key) is not None:
                        dynamics[key] = self.number(ext, key, who)
                if ext.get("actuated") is not None:
                    flag = ext.get("actuated").strip().lower()
                    if flag not in ("true", "false"):
                        raise self.fail(ext, f"{who}: <spacearm actuated> must be 'true' or 'false', got {ext.get('actuated')!r}")
                    dynamics["actuated"] = flag == "true"
        return UrdfJoint(name, kind, links["parent"], links["child"], origin, rotation, axis, limits, self.line(el), dynamics)

    def cmg(self, el: ET.Element) -> Tuple[UrdfLink, UrdfJoint, UrdfLink, UrdfJoint]:
        """A ``<spacearm><cmg .../></spacearm>`` (docs/urdf.md, "Control-moment gyros") as the
        gimbal and rotor links and joints the core's ``model/cmg.rs`` makes of it: the attributes
        are the fields of TOML's ``[[cmg]]`` (the core's ``CmgSpec``), vectors as space-separated
        numbers; ``position`` and the axes are in the ``parent`` link's URDF frame (as a joint's
        ``<origin xyz>`` and ``<axis xyz>``). Every rule of a CMG is the core's (``cmg_parts``);
        this adds the file, the line and the element to its message."""
        name = self.attr(el, "name", "<spacearm><cmg>")
        who = f"<spacearm><cmg name=\"{name}\">"
        unknown = set(el.attrib) - set(_CMG_ATTRIBUTES)
        if "wheel_speed" in unknown:
            raise self.fail(el, f"{who}: 'wheel_speed' is not a model parameter: a rotor's speed is the run's initial "
                                "condition, u0 = robot.cmg_velocity(wheel_speed) (docs/cmg.md)")
        if unknown:
            raise self.fail(el, f"{who}: unknown attribute(s) {sorted(unknown)}; a <cmg> takes {', '.join(_CMG_ATTRIBUTES)}")
        spec: Dict[str, object] = {"name": name, "parent": self.attr(el, "parent", who)}
        for key in ("gimbal_axis", "spin_axis", "rotor_inertia"):
            if el.get(key) is None:
                raise self.fail(el, f"{who}: needs a '{key}' attribute")
        spec["position"] = self.numbers(el, "position", 3, [0.0, 0.0, 0.0], who).tolist()
        spec["gimbal_axis"] = self.numbers(el, "gimbal_axis", 3, None, who).tolist()
        spec["spin_axis"] = self.numbers(el, "spin_axis", 3, None, who).tolist()
        spec["rotor_inertia"] = self.number(el, "rotor_inertia", who)
        for key in ("rotor_transverse_inertia", "max_gimbal_rate", "max_wheel_speed", "max_gimbal_torque", "max_wheel_torque"):
            spec[key] = None if el.get(key) is None else self.number(el, key, who)
        for key in ("rotor_mass", "gimbal_mass"):
            spec[key] = self.number(el, key, who, default=0.0)
        gimbal = (el.get("gimbal_inertia") or "0").split()
        spec["gimbal_inertia"] = self.numbers(el, "gimbal_inertia", len(gimbal) if len(gimbal) in (1, 3) else 3, [0.0], who).tolist()
        if len(spec["gimbal_inertia"]) == 1:
            spec["gimbal_inertia"] = spec["gimbal_inertia"] * 3
        flag = (el.get("variable_speed") or "false").strip().lower()
        if flag not in ("true", "false"):
            raise self.fail(el, f"{who}: variable_speed must be 'true' or 'false', got {el.get('variable_speed')!r}")
        spec["variable_speed"] = flag == "true"
        try:
            links, _points, _geometries = _core.cmg_parts(spec, spec["parent"])
        except SpacearmError as exc:
            raise self.fail(el, f"{who}: {exc}") from None
        line = self.line(el)
        out: List[object] = []
        for (link, parent, _kind, origin, _rotation, axis, _com, mass, inertia, joint, lim, dyn) in links:
            # cmg_parts' links: identity rotations and CMs at the joint (model/cmg.rs).
            inertial = UrdfInertial(mass, np.zeros(3), np.eye(3), np.array(inertia, dtype=float), line)
            limits = {k: v for k, v in zip(("velocity", "effort"), lim[2:]) if np.isfinite(v)}
            dynamics = {} if dyn is None else {"actuated": bool(dyn[0])}
            out.append(UrdfLink(link, inertial, line))
            out.append(UrdfJoint(joint, "continuous", parent, link, np.array(origin, dtype=float), np.eye(3),
                                 np.array(axis, dtype=float), limits, line, dynamics))
        return tuple(out)  # type: ignore[return-value]


#: The attributes of ``<spacearm><cmg>``: the core's ``CmgSpec`` fields (model/cmg.rs), as TOML ``[[cmg]]``.
_CMG_ATTRIBUTES = ("name", "parent", "position", "gimbal_axis", "spin_axis", "rotor_inertia", "rotor_transverse_inertia",
                   "gimbal_inertia", "rotor_mass", "gimbal_mass", "variable_speed", "max_gimbal_rate", "max_wheel_speed",
                   "max_gimbal_torque", "max_wheel_torque")


def parse_urdf(text, source: str = "<string>", mimic: str = "error") -> UrdfRobot:
    """Parse URDF text (``str`` or ``bytes``) into a ``UrdfRobot``.

    Raises [`ModelFileError`][spacearm.ModelFileError] (``source:line: message``) for XML that is not
    well formed or declares entities, a root element other than ``<robot>``, missing or
    malformed attributes, unsupported joints (``floating``, ``planar``, ``<mimic>``) and
    duplicate link or joint names. The tree structure is checked by [`spacearm.io.urdf`][spacearm.io.urdf].
    ``mimic="independent"`` reads a ``<mimic>`` joint as an ordinary joint instead.
    """
    if mimic not in ("error", "independent"):
        raise ArgumentError(f"mimic must be 'error' or 'independent', got {mimic!r}")
    root, lines = _xml_tree(text, source)
    reader = _Reader(lines, source, mimic)
    if root.tag != "robot":
        raise reader.fail(root, f"the root element must be <robot>, got <{root.tag}>")
    for el in root.findall("material"):
        rgba = reader.color(el, "<material>")
        if rgba is not None and el.get("name"):
            reader.materials[el.get("name").strip()] = rgba
    robot = UrdfRobot(name=(root.get("name") or "robot").strip() or "robot", source=source)
    joint_lines: Dict[str, int] = {}
    for el in root:
        if el.tag == "link":
            link = reader.link(el)
            if link.name in robot.links:
                raise reader.fail(el, f"link name '{link.name}' is used twice (first on line {robot.links[link.name].line})")
            robot.links[link.name] = link
        elif el.tag == "joint":
            joint = reader.joint(el)
            if joint.name in joint_lines:
                raise reader.fail(el, f"joint name '{joint.name}' is used twice (first on line {joint_lines[joint.name]})")
            joint_lines[joint.name] = joint.line
            robot.joints.append(joint)
        elif el.tag == "spacearm":
            # spacearm's robot-level extension element: control-moment gyros (docs/urdf.md).
            for sub in el:
                if sub.tag != "cmg":
                    raise reader.fail(sub, f"<spacearm> at the robot level takes <cmg> elements, got <{sub.tag}>")
                parts = reader.cmg(sub)
                for link, joint in (parts[0:2], parts[2:4]):
                    if link.name in robot.links:
                        raise reader.fail(sub, f"<spacearm><cmg>: link name '{link.name}' is used twice (first on line {robot.links[link.name].line})")
                    if joint.name in joint_lines:
                        raise reader.fail(sub, f"<spacearm><cmg>: joint name '{joint.name}' is used twice (first on line {joint_lines[joint.name]})")
                    robot.links[link.name] = link
                    joint_lines[joint.name] = joint.line
                    robot.joints.append(joint)
    return robot
