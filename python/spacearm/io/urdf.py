"""URDF import: a robot description from the ROS ecosystem as a spacearm model.

>>> robot = spacearm.io.urdf.load_urdf("ur5_robot.urdf")                    # root link = free-flying base
>>> robot = spacearm.io.urdf.load_urdf("baxter.urdf", mimic="independent")  # gripper fingers as own joints
>>> bus = spacearm.io.load_toml("bus.toml")
>>> robot = spacearm.io.urdf.load_urdf("ur5_robot.urdf", mount_on=bus, at=(0.6, 0, 0.4, 0, 0, 0))

How URDF frames become spacearm frames (docs/urdf.md has the full story):

- URDF places a child link frame at the joint (``<joint><origin>`` in the parent's link frame)
  and puts the CM anywhere (``<inertial><origin>``). spacearm's body frames have their origin at
  the CM (docs/conventions.md): a spacearm link keeps the axes of its URDF link frame, its joint
  ``origin`` is the URDF joint position measured from the **parent's CM**, and its ``com`` is the
  URDF inertial origin. Inertias given in a rotated inertial frame are rotated into link axes.
- The base (the root link, or ``base_link``) keeps its URDF link axes and has its frame origin
  moved to its CM, so ``r0`` is the base CM as the conventions require.
- Fixed joints are **merged**: a link on a fixed joint adds its mass to the moving body it is
  welded to (masses, CMs and inertias combined with the parallel-axis theorem) and becomes a
  named point at its URDF frame origin, so ``tool0`` or ``panda_hand`` remain usable as end
  effectors. ``continuous`` joints are revolute joints without position limits.
- ``base_link`` may name any link: the joints between it and the URDF root are then reversed
  (same coordinate, opposite axis), which is what a free-flying system is indifferent to.
- ``mount_on`` attaches the URDF's base link with a fixed joint to a body of another spacearm
  model (a spacecraft bus) at the pose ``at = (x, y, z, roll, pitch, yaw)`` of the URDF base link
  frame in that body's frame (from its CM). The URDF base is then a fixed body, not merged, so
  the bus's own frames and points keep their meaning.

Every problem is a [`ModelFileError`][spacearm.ModelFileError] naming the element and its line.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence

import numpy as np

from .._util.paths import inside
from ..model.builder import RobotBuilder
from ..errors import ArgumentError, ModelFileError, ShapeError, SpacearmError, SpacearmTypeError
from ..model.robot import Robot
from ..rotations import quat_from_matrix, quat_from_rpy
from .urdf_parse import UrdfJoint, UrdfRobot, parse_urdf

__all__ = ["load_urdf", "loads_urdf"]


@dataclass(frozen=True)
class _Pose:
    """A rigid transform ``x_outer = R x_inner + t`` (the inner frame's pose in the outer one)."""

    R: np.ndarray
    t: np.ndarray

    @staticmethod
    def identity() -> "_Pose":
        return _Pose(np.eye(3), np.zeros(3))

    def then(self, inner: "_Pose") -> "_Pose":
        """The pose of ``inner``'s frame in this pose's outer frame."""
        return _Pose(self.R @ inner.R, self.R @ inner.t + self.t)

    def inverse(self) -> "_Pose":
        return _Pose(self.R.T, -self.R.T @ self.t)


@dataclass
class _Body:
    """A spacearm body in the making: a moving URDF link plus the fixed links welded to it.

    Its working frame ``J`` has the axes of the spacearm body frame and its origin at the joint
    (for the base: at the base link's URDF origin); the CM is found once every part is known.
    """

    name: str
    parent: int  # body index, -1 for the base
    joint: Optional[UrdfJoint]  # a fixed one only when fixed links are kept as bodies
    joint_in_parent: _Pose  # joint frame in the parent's J frame, at q = 0
    axis: np.ndarray
    parts: List[tuple] = field(default_factory=list)  # (mass, com in J, inertia about com in J axes)
    mass: float = 0.0
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))

    def combine(self) -> None:
        """Total mass, CM and inertia about the CM (parallel-axis theorem, Featherstone §2.13)."""
        self.mass = sum(m for m, _, _ in self.parts)
        if self.mass > 0:
            self.com = sum(m * c for m, c, _ in self.parts) / self.mass
        inertia = np.zeros((3, 3))
        for m, c, i in self.parts:
            d = c - self.com
            inertia += i + m * (d @ d * np.eye(3) - np.outer(d, d))
        self.inertia = 0.5 * (inertia + inertia.T)


class _Importer:
    def __init__(self, urdf: UrdfRobot, base_link: Optional[str], fixed: str = "merge"):
        if fixed not in ("merge", "keep"):
            raise ArgumentError(f"fixed must be 'merge' or 'keep', got {fixed!r}")
        self.keep_fixed = fixed == "keep"
        self.urdf = urdf
        self.fail = urdf.error
        self._check_tree()
        if base_link is None:
            base_link = self.root
        elif base_link not in urdf.links:
            raise ModelFileError(f"{urdf.source}: base_link '{base_link}' is not a link of the URDF; links: {sorted(urdf.links)}")
        self.base_link = base_link
        self.bodies: List[_Body] = []
        self.body_of_link: Dict[str, int] = {}
        self.pose_of_link: Dict[str, _Pose] = {}  # URDF link frame in its body's J frame
        self.leaves: List[str] = []
        self._walk()
        for b in self.bodies:
            with np.errstate(all="ignore"):  # overflow is reported below, by body and line
                b.combine()
            if not (np.isfinite(b.mass) and np.all(np.isfinite(b.com)) and np.all(np.isfinite(b.inertia))):
                raise self.fail(self.urdf.links[b.name].line, f"link '{b.name}': combined mass properties of the links "
                                                              "welded to it overflow (values near 1e308: a units mistake?)")
        self._check_moving_subtrees()

    # ---- topology -----------------------------------------------------------------------
    def _check_tree(self) -> None:
        urdf = self.urdf
        if not urdf.links:
            raise self.fail(1, "the URDF has no <link>")
        self.parent_joint: Dict[str, UrdfJoint] = {}
        self.adjacent: Dict[str, list] = {name: [] for name in urdf.links}
        for j in urdf.joints:
            for role, link in (("parent", j.parent), ("child", j.child)):
                if link not in urdf.links:
                    raise self.fail(j.line, f"joint '{j.name}': {role} link '{link}' is not defined by any <link>")
            if j.parent == j.child:
                raise self.fail(j.line, f"joint '{j.name}': link '{j.child}' cannot be its own parent")
            if j.child in self.parent_joint:
                other = self.parent_joint[j.child]
                raise self.fail(j.line, f"joint '{j.name}': link '{j.child}' is already the child of joint '{other.name}' "
                                        f"(line {other.line}): closed kinematic loops are not supported (a URDF must be a tree)")
            self.parent_joint[j.child] = j
            self.adjacent[j.parent].append((j, j.child, True))
            self.adjacent[j.child].append((j, j.parent, False))
        roots = [name for name in self.urdf.links if name not in self.parent_joint]
        if not roots:
            j = self.urdf.joints[0]
            raise self.fail(j.line, "every link is the child of a joint, so the joints form a closed loop "
                                    f"(e.g. through joint '{j.name}'); a URDF must be a tree with one root link")
        if len(roots) > 1:
            line = self.urdf.links[roots[1]].line
            raise self.fail(line, f"the links do not form one tree: {roots[:5]} have no parent joint; "
                                  "connect them with joints (exactly one root link)")
        self.root = roots[0]

    def _walk(self) -> None:
        """Depth-first from the base link, children in document order (Pinocchio's order too)."""
        base = self.base_link
        self.bodies.append(_Body(base, -1, None, _Pose.identity(), np.zeros(3)))
        self._visit(base, 0, _Pose.identity())
        stack = [(base, None, None, True)]  # (link, joint reached through, from link, forward)
        while stack:
            link, via, came_from, forward = stack.pop()
            if via is not None:
                self._attach(came_from, via, link, forward)
            children = [(j, other, fwd) for j, other, fwd in self.adjacent[link] if j is not via]
            if not children:
                self.leaves.append(link)
            for j, other, fwd in reversed(children):  # popped in document order
                stack.append((other, j, link, fwd))
        missing = [n for n in self.urdf.links if n not in self.body_of_link]
        if missing:
            link = self.urdf.links[missing[0]]
            raise self.fail(link.line, f"link '{link.name}' is not connected to the base: its joints form a closed loop")

    def _visit(self, link: str, body: int, pose: _Pose) -> None:
        self.body_of_link[link] = body
        self.pose_of_link[link] = pose
        inertial = self.urdf.links[link].inertial
        if inertial is not None:
            com = pose.R @ inertial.origin + pose.t
            r = pose.R @ inertial.rotation  # inertial axes in the J frame
            self.bodies[body].parts.append((inertial.mass, com, r @ inertial.inertia @ r.T))

    def _attach(self, link: str, j: UrdfJoint, other: str, forward: bool) -> None:
        body = self.body_of_link[link]
        here = self.pose_of_link[link]
        origin = _Pose(j.rotation, j.origin)  # URDF child frame in the parent frame at q = 0
        # With fixed="keep", a fixed link with an <inertial> stays a (fixed) body; frames
        # without one are always merged into points.
        if j.kind == "fixed" and not (self.keep_fixed and self.urdf.links[other].inertial is not None):
            self._visit(other, body, here.then(origin if forward else origin.inverse()))
            return
        if forward:
            # child = parent · origin · motion(axis, q): the joint frame is the child's URDF frame.
            joint_pose, axis, link_in_body = here.then(origin), j.axis, _Pose.identity()
        else:
            # Reversed: parent = child · motion(−axis, q) · origin⁻¹, same coordinate q.
            joint_pose, axis, link_in_body = here, -j.axis, origin.inverse()
        self.bodies.append(_Body(other, body, j, joint_pose, axis))  # normalized by the core's builder
        self._visit(other, len(self.bodies) - 1, link_in_body)

    def _check_moving_subtrees(self) -> None:
        carried = [b.mass + np.trace(b.inertia) for b in self.bodies]
        for k in range(len(self.bodies) - 1, 0, -1):
            b = self.bodies[k]
            if carried[k] == 0.0 and b.joint.kind != "fixed":
                raise self.fail(b.joint.line, f"joint '{b.joint.name}' ({b.joint.kind}) moves link '{b.name}', but neither "
                                              "it nor anything attached beyond it has an <inertial> with mass or inertia: "
                                              "its acceleration would be undetermined (add inertials or make it fixed)")
            carried[b.parent] += carried[k]

    # ---- model --------------------------------------------------------------------------
    def build(self, name: str, mount_on: Optional[Robot], mount_body: Optional[str], at, end_effector: Optional[str],
              prefix: str = "", allow_nonphysical_inertia: bool = False, package_dirs: Sequence[str] = (),
              allow_outside_meshes: bool = False) -> Robot:
        p = prefix
        base = self.bodies[0]
        base_line = self.urdf.links[self.base_link].line
        if mount_on is None:
            try:
                builder = RobotBuilder(name, base.mass, base.inertia, base_name=p + base.name,
                                       allow_nonphysical_inertia=allow_nonphysical_inertia)
            except SpacearmError as exc:
                raise self.fail(base_line, f"link '{base.name}' is the free-flying base (with the links welded to it by "
                                           f"fixed joints) but {exc}; name another base_link or mount the robot on a "
                                           "spacecraft base (mount_on=...)") from None
        else:
            builder = RobotBuilder.from_robot(mount_on, name=name, allow_nonphysical_inertia=(
                allow_nonphysical_inertia or mount_on.allows_nonphysical_inertia))
            taken = set(mount_on.body_names) | set(mount_on.point_names)
            clash = sorted(taken & {p + link for link in self.body_of_link})
            if clash:
                raise ModelFileError(f"{self.urdf.source}: URDF link names {clash[:5]} are already bodies or points of the "
                                     "spacecraft it is mounted on; pass a prefix (prefix='arm_', CLI --prefix) to rename "
                                     "the URDF's links and joints")
            pose = np.asarray(at if at is not None else np.zeros(6), dtype=float)
            if pose.shape != (6,) or not np.all(np.isfinite(pose)):
                raise ShapeError(f"at must be 6 finite numbers (x, y, z, roll, pitch, yaw), got {at!r}")
            parent = mount_body if mount_body is not None else mount_on.body_names[0]
            self._add(builder, base_line, p + base.name, parent=parent, joint="fixed", origin=pose[:3],
                      rotation=quat_from_rpy(*pose[3:]), com=base.com, mass=base.mass, inertia=base.inertia,
                      joint_name=f"{p}{base.name}_mount")
        for b in self.bodies[1:]:
            parent = self.bodies[b.parent]
            self._add(builder, b.joint.line, p + b.name, parent=p + parent.name,
                      joint={"prismatic": "prismatic", "fixed": "fixed"}.get(b.joint.kind, "revolute"),
                      axis=b.axis, origin=b.joint_in_parent.t - parent.com, rotation=quat_from_matrix(b.joint_in_parent.R),
                      com=b.com, mass=b.mass, inertia=b.inertia, joint_name=p + b.joint.name, limits=dict(b.joint.limits),
                      **b.joint.dynamics)
        points = {}
        for link, body in self.body_of_link.items():
            if self.bodies[body].name != link:
                points[link] = (body, link)
        if end_effector is None and len(self.leaves) == 1:
            end_effector = self.leaves[0]
        ee_point = None
        if end_effector is not None:
            if end_effector not in self.body_of_link:
                raise ModelFileError(f"{self.urdf.source}: end_effector '{end_effector}' is not a link of the URDF")
            ee_point = end_effector
            if end_effector not in points:  # a moving link: its URDF frame origin, under another name
                ee_point = f"{end_effector}_frame"
                points[ee_point] = (self.body_of_link[end_effector], end_effector)
        for point, (body, link) in points.items():
            b = self.bodies[body]
            try:
                builder.add_point(p + point, body=p + b.name, offset=self.pose_of_link[link].t - b.com)
            except SpacearmError as exc:
                raise self.fail(self.urdf.links[link].line, f"link '{link}': {exc}") from None
        if ee_point is not None:
            builder.set_end_effector(p + ee_point)
        self._add_geometries(builder, p, package_dirs, allow_outside_meshes)
        try:
            return builder.build()
        except SpacearmError as exc:
            raise ModelFileError(f"{self.urdf.source}: {exc}") from None

    def _mesh_file(self, file: str, folder: Optional[str], package_dirs: Sequence[str], line: int,
                   allow_outside: bool) -> str:
        """A mesh ``filename`` as a path: a relative one against the URDF's folder; a
        ``package://NAME/rest`` one as ``DIR/NAME/rest`` for the first of ``package_dirs`` that
        has it, else the ``rest`` below the nearest folder called ``NAME`` above the URDF (a ROS
        package layout). Kept as written when no such file exists.

        Confined (unless ``allow_outside``): a ``package://`` file must stay inside its package's
        folder, and every other file (relative, absolute or ``file://``) inside the URDF's folder
        (the current folder for URDF text) or one of ``package_dirs``, symbolic links resolved;
        anything else (``../../etc/passwd``, ``file:///etc/shadow``, ``package://pkg/../..``)
        is a [`ModelFileError`][spacearm.ModelFileError] naming the line."""
        def confined(path: str, roots: Sequence[str], what: str) -> str:
            if allow_outside or inside(path, roots):
                return path
            raise self.fail(line, f"mesh '{file[:200]}' resolves to '{path[:200]}', outside {what}: refused (mesh "
                                  "files are read from the URDF's folder and the package folders only; pass "
                                  "allow_outside_meshes=True to read it anyway, or package_dirs=[...])")

        if file.startswith("package://"):
            package, _, rest = file[len("package://"):].partition("/")
            roots = [os.path.join(d, package) for d in package_dirs]
            here = folder
            while here and os.path.dirname(here) != here:
                if os.path.basename(here) == package:
                    roots.append(here)
                here = os.path.dirname(here)
            for root in roots:
                c = os.path.join(root, rest)
                if os.path.isfile(c):
                    return confined(os.path.normpath(c), [root], f"the folder of package '{package[:80]}' ({root[:200]})")
            return file
        local = list(package_dirs) + [folder if folder is not None else os.getcwd()]
        where = "the URDF's folder and the package folders"
        if file.startswith("file://"):
            return confined(file[len("file://"):], local, where)
        if "://" in file:
            return file  # a URL: not a file of this machine, never read
        if folder is not None and not os.path.isabs(file):
            return confined(os.path.normpath(os.path.join(folder, file)), local, where)
        confined(file, local, where)
        return file

    def _add_geometries(self, builder: RobotBuilder, p: str, package_dirs: Sequence[str], allow_outside: bool) -> None:
        """Each link's visuals and collisions on the body it became: the URDF pose in the link
        frame, carried into the body's J frame and measured from the body's CM; mesh files
        resolved by `_mesh_file`."""
        folder = os.path.dirname(os.path.abspath(self.urdf.source)) if os.path.isfile(self.urdf.source) else None
        for link, body in self.body_of_link.items():
            b = self.bodies[body]
            for g in self.urdf.links[link].geometries:
                pose = self.pose_of_link[link].then(_Pose(g.rotation, g.origin))
                dims = dict(g.dims)
                if isinstance(dims.get("file"), str):
                    dims["file"] = self._mesh_file(dims["file"], folder, package_dirs, g.line, allow_outside)
                try:
                    builder.add_geometry(p + b.name, g.shape, role=g.role, origin=pose.t - b.com,
                                         rotation=quat_from_matrix(pose.R), rgba=g.rgba,
                                         name=None if g.name is None else p + g.name, **dims)
                except SpacearmError as exc:
                    raise self.fail(g.line, f"link '{link}': {exc}") from None

    def _add(self, builder: RobotBuilder, line: int, name: str, **kwargs) -> None:
        try:
            builder.add_link(name, **kwargs)
        except SpacearmError as exc:
            # The core's message names the link or joint and the broken rule (one message from
            # every door, model/validate.rs); the URDF adds the file and the joint's line.
            raise self.fail(line, str(exc)) from None


def _mount_robot(mount_on):
    """``mount_on`` as a Robot: a Robot as it is, a TOML model file's path or a shipped example
    model's name (``"spacecraft_bus"``, [`spacearm.examples`][spacearm.examples]) loaded, the CLI's
    ``--mount-on`` in Python; anything else a [`SpacearmTypeError`][spacearm.errors.SpacearmTypeError]."""
    if mount_on is None or isinstance(mount_on, Robot):
        return mount_on
    from .. import examples  # here, not at import: spacearm.examples loads on first use
    if isinstance(mount_on, (str, os.PathLike)):
        from .model_file import load_toml
        spec = os.fspath(mount_on)
        if not os.path.exists(spec) and (spec in examples.NAMES or spec[:-5] in examples.NAMES):
            spec = str(examples.path(spec))
        return load_toml(spec)
    raise SpacearmTypeError(f"mount_on must be a spacearm Robot, a TOML model file's path or a shipped example "
                            f"model's name ({', '.join(examples.NAMES)}), got {type(mount_on).__name__}")


def loads_urdf(
    text,
    source: str = "<string>",
    *,
    base_link: Optional[str] = None,
    mount_on: Optional[Robot] = None,
    mount_body: Optional[str] = None,
    at: Optional[Sequence[float]] = None,
    end_effector: Optional[str] = None,
    mimic: str = "error",
    name: Optional[str] = None,
    prefix: str = "",
    fixed: str = "merge",
    allow_nonphysical_inertia: bool = False,
    package_dirs: Sequence[str] = (),
    allow_outside_meshes: bool = False,
) -> Robot:
    """Build a [`Robot`][spacearm.Robot] from URDF text (``str`` or ``bytes``); see [`load_urdf`][spacearm.io.load_urdf]."""
    mount_on = _mount_robot(mount_on)
    urdf = parse_urdf(text, source, mimic=mimic)
    importer = _Importer(urdf, base_link, fixed)
    dirs = [package_dirs] if isinstance(package_dirs, (str, os.PathLike)) else list(package_dirs)
    return importer.build(name or urdf.name, mount_on, mount_body, at, end_effector, str(prefix), bool(allow_nonphysical_inertia),
                          [os.fspath(d) for d in dirs], bool(allow_outside_meshes))


def load_urdf(path, **kwargs) -> Robot:
    """Load a URDF file as a spacearm model.

    ``base_link``: the link that becomes the free-flying base (default: the URDF root).
    ``mount_on``: a spacearm [`Robot`][spacearm.Robot] (a spacecraft), a TOML model file's path or a
    shipped example model's name (``"spacecraft_bus"``) to attach the URDF's base
    link to, with a fixed joint on ``mount_body`` (default: its base) at
    ``at = (x, y, z, roll, pitch, yaw)`` (the URDF base link frame in that body's frame, from
    its CM; m and rad, URDF's ``R = Rz(yaw) Ry(pitch) Rx(roll)``). ``end_effector``: a URDF link
    name (default: the only leaf link, if there is exactly one). ``mimic``: ``"error"`` (default)
    or ``"independent"`` (load ``<mimic>`` joints as ordinary joints, as Pinocchio does).
    ``fixed``: ``"merge"`` (default) welds links on fixed joints into their moving parent;
    ``"keep"`` keeps those with an ``<inertial>`` as fixed bodies (massless frames still become
    points), which keeps the base CM where a spacearm model exported by
    [`spacearm.io.urdf_export.to_urdf`][spacearm.io.to_urdf] had it.
    ``prefix``: prepended to every URDF link, joint and point name (for mounting two arms, or an
    arm whose link names clash with the spacecraft's). ``name``: the model name (default: the
    ``<robot name>``). ``allow_nonphysical_inertia``: accept inertias that break the triangle
    inequality ``I1 + I2 >= I3`` (published identified data), with a
    [`NonPhysicalInertiaWarning`][spacearm.errors.NonPhysicalInertiaWarning] per body, instead of refusing the file.
    ``package_dirs``: folders holding ROS packages, where ``package://NAME/...`` mesh files
    are looked up (as Pinocchio's ``package_dirs``); the folders above the URDF are searched
    too. Every ``<visual>`` and ``<collision>`` becomes a geometry of its body (docs/geometry.md).
    Mesh files are confined: a ``package://`` one to its package's folder, any other (relative,
    absolute, ``file://``) to the URDF's folder and ``package_dirs``, symbolic links resolved;
    one outside is refused unless ``allow_outside_meshes=True``.

    Raises [`ModelFileError`][spacearm.ModelFileError] with ``file:line:`` for every problem in the file,
    and ``OSError`` if it cannot be read.
    """
    with open(os.fspath(path), "rb") as fh:
        data = fh.read()
    return loads_urdf(data, source=os.fspath(path), **kwargs)
