"""The model options every ``spacearm`` subcommand that takes MODEL shares, defined once.

``inspect``, ``derive``, ``analyze``, ``simulate`` and ``campaign`` take the same options, added
by ``add_model_arguments`` and turned into a [`Robot`][spacearm.Robot] by
``model_from_args`` / ``load_model``: ``--mount-on SPACECRAFT --at
x,y,z,roll,pitch,yaw`` (mount a URDF arm on a spacecraft base), ``--prefix``, ``--mimic``,
``--base-link`` (URDF only) and ``--end-effector`` (any model). Number lists are parsed by
``spacearm.cli.numbers.parse_numbers``.
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from typing import Optional

from .. import examples, presets
from .numbers import CliError, parse_numbers
from ..errors import NonPhysicalInertiaWarning, SpacearmError
from ..io.model_file import load_toml
from ..model.robot import Robot

__all__ = ["MODEL_HELP", "add_model_arguments", "model_from_args", "load_model", "joint_values"]


#: What MODEL may be, for the help of every subcommand.
MODEL_HELP = (f"a preset ({', '.join(presets.NAMES)}), a model file shipped with spacearm "
              f"({', '.join(n for n in examples.NAMES if n not in presets.NAMES)}; spacearm.examples), "
              "a .toml model file or a .urdf file")

#: Python keyword advice in the URDF importer's messages, as the command line spells it.
_URDF_ADVICE_AS_OPTIONS = (
    ("pass mimic='independent'", "pass --mimic independent"),
    ("base_link '", "--base-link '"),
    ("name another base_link", "name another --base-link"),
    ("(mount_on=...)", "(--mount-on SPACECRAFT)"),
    ("(prefix='arm_', CLI --prefix)", "(--prefix arm_)"),
    ("allow_outside_meshes=True", "--allow-outside-meshes"),
)


def add_model_arguments(parser: argparse.ArgumentParser) -> None:
    """Add MODEL and the model options that every subcommand taking a model shares; turn the
    parsed ``args`` into the [`Robot`][spacearm.Robot] with ``model_from_args``."""
    parser.add_argument("model", help=MODEL_HELP)
    g = parser.add_argument_group("model options")
    g.add_argument("--mount-on", metavar="SPACECRAFT",
                   help="URDF only: mount the URDF arm on this spacecraft (a preset, a shipped model such as "
                        "spacecraft_bus, or a .toml file) instead of making its root link the free-flying base")
    g.add_argument("--at", metavar="X,Y,Z,ROLL,PITCH,YAW",
                   help="with --mount-on: pose of the URDF base link frame in the spacecraft base frame, from its CM "
                        "(m, rad; URDF's R = Rz(yaw) Ry(pitch) Rx(roll); default 0,0,0,0,0,0)")
    g.add_argument("--prefix", help="URDF only: prefix for the URDF's link, joint and point names (e.g. ur_; needed "
                                    "when a URDF link has the name of a spacecraft body or point)")
    g.add_argument("--mimic", choices=("error", "independent"),
                   help="URDF only: refuse <mimic> joints (default) or load them as independent joints")
    g.add_argument("--base-link", metavar="LINK",
                   help="URDF only: the link that becomes the free-flying base, or with --mount-on the link "
                        "fixed to the spacecraft (default: the URDF root link)")
    g.add_argument("--end-effector", metavar="POINT|LINK",
                   help="the end effector: a named point of the model, or a link: a URDF link's frame origin, a "
                        "preset or .toml body's CM (its frame origin) (default: the model's own; for a URDF the only "
                        "leaf link, if there is one)")
    g.add_argument("--allow-nonphysical-inertia", action="store_true",
                   help="load inertias that break the triangle inequality I1 + I2 >= I3 (published identified data) "
                        "with a warning instead of refusing them; for the ets7 preset, its published link inertias "
                        "instead of their documented correction")
    g.add_argument("--allow-outside-meshes", action="store_true",
                   help="URDF only: read mesh files outside the URDF's folder and its package folders (refused "
                        "by default: ../ or file:// paths of a URDF you did not write)")


def model_from_args(args: argparse.Namespace) -> Robot:
    """The robot that MODEL and the model options of ``add_model_arguments`` describe. The
    warnings of ``--allow-nonphysical-inertia`` print as ``spacearm: warning: ...`` lines."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", NonPhysicalInertiaWarning)
        robot = load_model(args.model, mount_on=args.mount_on, at=args.at, prefix=args.prefix, mimic=args.mimic,
                           base_link=args.base_link, end_effector=args.end_effector,
                           allow_nonphysical_inertia=getattr(args, "allow_nonphysical_inertia", False),
                           allow_outside_meshes=getattr(args, "allow_outside_meshes", False))
    for w in caught:
        if issubclass(w.category, NonPhysicalInertiaWarning):
            print(f"spacearm: warning: {w.message}", file=sys.stderr)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return robot


def load_model(spec: str, mount_on: Optional[str] = None, at=None, prefix: Optional[str] = None,
               mimic: Optional[str] = None, base_link: Optional[str] = None,
               end_effector: Optional[str] = None, allow_nonphysical_inertia: bool = False,
               allow_outside_meshes: bool = False) -> Robot:
    """A preset by name, a model file shipped with spacearm by name (``spacecraft_bus``,
    ``spatial6_wheels``: [`spacearm.examples`][spacearm.examples]), or a model file (``.toml``,
    ``.urdf``) by path.

    URDF only ([`spacearm.io.urdf.load_urdf`][spacearm.io.load_urdf], docs/urdf.md): ``mount_on`` (a preset or
    ``.toml`` file, the spacecraft) and ``at`` (``"x,y,z,roll,pitch,yaw"`` or 6 numbers, m and
    rad, the URDF base link frame in the spacecraft base frame, from its CM) mount the arm on a
    spacecraft instead of making its root link the free-flying base; ``prefix`` renames its
    links, joints and points; ``mimic`` is ``"error"`` or ``"independent"``; ``base_link``
    picks the base (or mounted) link.

    Any model: ``end_effector`` names the end effector: a point of the model; or a URDF link,
    with or without the prefix (its URDF link frame origin, as ``load_urdf(end_effector=...)``:
    a link welded by a fixed joint is already a point, a moving link gets a point
    ``<link>_frame``); or a body of a preset or ``.toml`` model (its CM, which is its frame
    origin in spacearm; a point ``<body>_cm`` is added). ``allow_nonphysical_inertia``: load
    inertias that break the triangle inequality with a warning (``ets7``: the published values).
    ``allow_outside_meshes`` (URDF only): read mesh files outside the URDF's folder and its
    package folders (``load_urdf(allow_outside_meshes=True)``).
    """
    if spec not in presets.NAMES and spec in examples.NAMES and not os.path.exists(spec):
        spec = str(examples.path(spec))
    if spec not in presets.NAMES and not os.path.exists(spec):
        shipped = ", ".join(n for n in examples.NAMES if n not in presets.NAMES)
        raise SpacearmError(f"'{spec}' is neither a preset ({', '.join(presets.NAMES)}), nor a shipped model ({shipped}), "
                            "nor an existing model file")
    if spec.lower().endswith(".urdf"):
        return _load_urdf_model(spec, mount_on, at, prefix, mimic, base_link, end_effector, allow_nonphysical_inertia,
                                allow_outside_meshes)
    given = [option for option, value in (("--mount-on", mount_on), ("--at", at), ("--prefix", prefix),
                                          ("--mimic", mimic), ("--base-link", base_link)) if value is not None]
    if given:
        verb = "applies" if len(given) == 1 else "apply"
        raise CliError(f"{', '.join(given)} {verb} to URDF models (.urdf files) only, not to '{spec}'")
    if spec in presets.NAMES:
        robot = presets.get(spec, allow_nonphysical_inertia=allow_nonphysical_inertia)
    elif spec.lower().endswith(".toml"):
        robot = load_toml(spec, allow_nonphysical_inertia=allow_nonphysical_inertia)
    else:
        raise SpacearmError(f"cannot read '{spec}': model files must end in .toml or .urdf")
    return robot if end_effector is None else _with_end_effector(robot, end_effector)


def _load_urdf_model(path, mount_on, at, prefix, mimic, base_link, end_effector, allow_nonphysical_inertia,
                     allow_outside_meshes=False) -> Robot:
    from ..errors import ModelFileError
    from ..io.urdf import load_urdf
    from ..io.urdf_parse import parse_urdf

    if mount_on is None and at is not None:
        raise CliError("--at needs --mount-on (the spacecraft to mount the URDF on)")
    options = {k: v for k, v in (("prefix", prefix), ("mimic", mimic), ("base_link", base_link)) if v is not None}
    if allow_nonphysical_inertia:
        options["allow_nonphysical_inertia"] = True
    if allow_outside_meshes:
        options["allow_outside_meshes"] = True
    if mount_on is not None:
        pose = parse_numbers(at, "--at", 6, "x,y,z,roll,pitch,yaw", "m, rad") if isinstance(at, str) else at
        try:
            spacecraft = load_model(mount_on, allow_nonphysical_inertia=allow_nonphysical_inertia)
        except SpacearmError as exc:
            raise type(exc)(f"--mount-on: {exc}") from None
        options.update(mount_on=spacecraft, at=pose)
    try:
        robot = load_urdf(path, **options)
        if end_effector is None:
            return robot
        p = prefix or ""
        with open(path, "rb") as fh:
            links = parse_urdf(fh.read(), path, mimic=mimic or "error").links
        link = end_effector[len(p):] if p and end_effector.startswith(p) and end_effector[len(p):] in links else end_effector
        if link in links:
            return load_urdf(path, end_effector=link, **options)
    except ModelFileError as exc:
        message = str(exc)
        for keyword, option in _URDF_ADVICE_AS_OPTIONS:
            message = message.replace(keyword, option)
        raise ModelFileError(message) from None
    return _with_end_effector(robot, end_effector)


def _with_end_effector(robot: Robot, name: str) -> Robot:
    """``robot`` with the end effector ``name``: a point of it, or a body (its CM, the body
    frame origin, as the new point ``<body>_cm``). Everything else stays exactly as it was."""
    if name == robot.end_effector:
        return robot
    if name in robot.point_names:
        point = name
    elif name in robot.body_names:
        point = f"{name}_cm"
        if point in robot.point_names or point in robot.body_names:
            raise CliError(f"--end-effector {name}: the model already has a '{point}' (name its point instead)")
    else:
        raise CliError(f"--end-effector must name a point or a body/link of model '{robot.name}', got '{name}'; "
                       f"points: {', '.join(robot.point_names) or 'none'}; bodies: {', '.join(robot.body_names)}")
    builder = robot.to_builder()
    if point not in robot.point_names:
        builder.add_point(point, body=name)
    return builder.set_end_effector(point).build()


def joint_values(text: str, option: str, robot: Robot):
    """One number per joint of ``robot`` (``--q``, ``--q0``, ``--qd0``) from ``text``."""
    unit = "rad/s, or m/s for prismatic joints" if option == "--qd0" else "rad, or m for prismatic joints"
    return parse_numbers(text, option, robot.n_dof, f"one per joint of '{robot.name}'", unit)
