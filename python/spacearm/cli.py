"""The ``spacearm`` command line.

``spacearm inspect MODEL [--q Q1,Q2,...]`` prints the model summary (bodies, joints, total
mass) and, at the given or initial configuration, ``H0``, ``H*`` and the end-effector ``J*``
with their conditioning. ``MODEL`` is a preset name (``planar4``, ``spatial6``), a TOML
model file (``docs/model-format.md``) or a URDF file (``docs/urdf.md``).

Every subcommand that takes MODEL (``inspect``, ``derive``, ``analyze``, ``simulate``,
``campaign``) takes the same model options, defined once by :func:`add_model_arguments` and
turned into a :class:`~spacearm.Robot` by :func:`model_from_args` / :func:`load_model`:
``--mount-on SPACECRAFT --at x,y,z,roll,pitch,yaw`` (mount a URDF arm on a spacecraft base),
``--prefix``, ``--mimic``, ``--base-link`` (URDF only) and ``--end-effector`` (any model).
Number lists are parsed by :func:`spacearm.cli_numbers.parse_numbers`.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Optional

import numpy as np

from . import __version__, presets
from .cli_numbers import CliError, attach_negative_values, parse_numbers
from .errors import SpacearmError
from .robot import Robot

__all__ = ["main", "load_model", "add_model_arguments", "model_from_args", "MODEL_HELP"]


#: What MODEL may be, for the help of every subcommand.
MODEL_HELP = f"a preset ({', '.join(presets.NAMES)}), a .toml model file or a .urdf file"

#: Python keyword advice in the URDF importer's messages, as the command line spells it.
_URDF_ADVICE_AS_OPTIONS = (
    ("pass mimic='independent'", "pass --mimic independent"),
    ("base_link '", "--base-link '"),
    ("name another base_link", "name another --base-link"),
    ("(mount_on=...)", "(--mount-on SPACECRAFT)"),
    ("(prefix='arm_', CLI --prefix)", "(--prefix arm_)"),
)


def add_model_arguments(parser: argparse.ArgumentParser) -> None:
    """Add MODEL and the model options that every subcommand taking a model shares; turn the
    parsed ``args`` into the :class:`~spacearm.Robot` with :func:`model_from_args`."""
    parser.add_argument("model", help=MODEL_HELP)
    g = parser.add_argument_group("model options")
    g.add_argument("--mount-on", metavar="SPACECRAFT",
                   help="URDF only: mount the URDF arm on this spacecraft (a preset or .toml file, e.g. "
                        "examples/models/spacecraft_bus.toml) instead of making its root link the free-flying base")
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


def model_from_args(args: argparse.Namespace) -> Robot:
    """The robot that MODEL and the model options of :func:`add_model_arguments` describe."""
    return load_model(args.model, mount_on=args.mount_on, at=args.at, prefix=args.prefix, mimic=args.mimic,
                      base_link=args.base_link, end_effector=args.end_effector)


def load_model(spec: str, mount_on: Optional[str] = None, at=None, prefix: Optional[str] = None,
               mimic: Optional[str] = None, base_link: Optional[str] = None,
               end_effector: Optional[str] = None) -> Robot:
    """A preset by name, or a model file (``.toml``, ``.urdf``) by path.

    URDF only (:func:`spacearm.urdf.load_urdf`, docs/urdf.md): ``mount_on`` (a preset or
    ``.toml`` file, the spacecraft) and ``at`` (``"x,y,z,roll,pitch,yaw"`` or 6 numbers, m and
    rad, the URDF base link frame in the spacecraft base frame, from its CM) mount the arm on a
    spacecraft instead of making its root link the free-flying base; ``prefix`` renames its
    links, joints and points; ``mimic`` is ``"error"`` or ``"independent"``; ``base_link``
    picks the base (or mounted) link.

    Any model: ``end_effector`` names the end effector: a point of the model; or a URDF link,
    with or without the prefix (its URDF link frame origin, as ``load_urdf(end_effector=...)``:
    a link welded by a fixed joint is already a point, a moving link gets a point
    ``<link>_frame``); or a body of a preset or ``.toml`` model (its CM, which is its frame
    origin in spacearm; a point ``<body>_cm`` is added).
    """
    if spec not in presets.NAMES and not os.path.exists(spec):
        raise SpacearmError(f"'{spec}' is neither a preset ({', '.join(presets.NAMES)}) nor an existing model file")
    if spec.lower().endswith(".urdf"):
        return _load_urdf_model(spec, mount_on, at, prefix, mimic, base_link, end_effector)
    given = [option for option, value in (("--mount-on", mount_on), ("--at", at), ("--prefix", prefix),
                                          ("--mimic", mimic), ("--base-link", base_link)) if value is not None]
    if given:
        verb = "applies" if len(given) == 1 else "apply"
        raise CliError(f"{', '.join(given)} {verb} to URDF models (.urdf files) only, not to '{spec}'")
    if spec in presets.NAMES:
        robot = presets.get(spec)
    elif spec.lower().endswith(".toml"):
        robot = Robot.from_toml(spec)
    else:
        raise SpacearmError(f"cannot read '{spec}': model files must end in .toml or .urdf")
    return robot if end_effector is None else _with_end_effector(robot, end_effector)


def _load_urdf_model(path, mount_on, at, prefix, mimic, base_link, end_effector) -> Robot:
    from .errors import ModelFileError
    from .urdf import load_urdf
    from .urdf_parse import parse_urdf

    if mount_on is None and at is not None:
        raise CliError("--at needs --mount-on (the spacecraft to mount the URDF on)")
    options = {k: v for k, v in (("prefix", prefix), ("mimic", mimic), ("base_link", base_link)) if v is not None}
    if mount_on is not None:
        pose = parse_numbers(at, "--at", 6, "x,y,z,roll,pitch,yaw", "m, rad") if isinstance(at, str) else at
        try:
            spacecraft = load_model(mount_on)
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


def _matrix(name: str, m: np.ndarray, unit: str) -> str:
    rows = [f"{name}  [{unit}]  ({m.shape[0]}x{m.shape[1]})"]
    for row in m:
        # Adding 0.0 turns IEEE negative zeros into plain zeros for display.
        rows.append("  " + " ".join(f"{v + 0.0:11.4g}" for v in row))
    return "\n".join(rows)


def _conditioning(name: str, m: np.ndarray) -> str:
    s = np.linalg.svd(m, compute_uv=False)
    cond = s[0] / s[-1] if s[-1] > 0 else np.inf
    return f"  {name}: singular values [{', '.join(f'{v:.4g}' for v in s)}], condition number {cond:.4g}"


def inspect(robot: Robot, q=None, out=None) -> None:
    """Print the model summary and the GJM quantities at ``q`` (default: initial angles)."""
    # Resolve the stream at call time, not at import time, so redirections of sys.stdout count.
    out = sys.stdout if out is None else out
    d = robot.description
    w = out.write
    w(f"model '{robot.name}': {robot.n_bodies} bodies, N = {robot.n_dof} joint DOF, total mass {robot.total_mass:.6g} kg\n\n")
    rows = [(d.base.name, "-", "-", "free", "-", d.base.mass)]
    for link in d.links:
        axis = "-" if link.type == "fixed" else "[" + ", ".join(f"{v:.3g}" for v in link.axis) + "]"
        rows.append((link.name, link.parent, link.joint, link.type, axis, link.mass))
    # Columns as wide as their longest name (URDF names such as 'shoulder_pan_joint' are long).
    widths = [max(16, 2 + max(len(r[k]) for r in rows)) for k in range(3)]
    w(f"{'body':<{widths[0]}}{'parent':<{widths[1]}}{'joint':<{widths[2]}}{'type':<10}{'axis (link frame)':<26}{'mass kg':>9}\n")
    for name, parent, joint, kind, axis, mass in rows:
        w(f"{name:<{widths[0]}}{parent:<{widths[1]}}{joint:<{widths[2]}}{kind:<10}{axis:<26}{mass:>9.4g}\n")
    if d.points:
        w("\npoints: " + ", ".join(f"{p.name} on {p.body} at [{', '.join(f'{v:.4g}' for v in p.offset)}]" for p in d.points))
        w(f"   (end effector: {robot.end_effector})\n")
    x = robot.neutral_configuration(q)
    qs = ", ".join(f"{v:.4g}" for v in x[7:])
    w(f"\nconfiguration: base at the origin aligned with the inertial frame, q = [{qs}]\n\n")
    np.set_printoptions(linewidth=160)
    h0 = robot.inertia_blocks(x).H0
    w(_matrix("H0 (base inertia, eq. 30)", h0, "kg | kg m | kg m^2 blocks") + "\n\n")
    if robot.n_dof > 0:
        hs = robot.generalized_inertia(x)
        w(_matrix("H* (generalized inertia, eq. 45)", hs, "kg m^2 between revolute joints") + "\n\n")
    if robot.end_effector is not None and robot.n_dof > 0:
        js = robot.generalized_jacobian(x)
        w(_matrix(f"J* of '{robot.end_effector}' (generalized Jacobian, eq. 110)", js, "linear rows m/rad, angular rows 1") + "\n")
        p = robot.point_position(x)
        w(f"  end-effector position: [{', '.join(f'{v:.6g}' for v in p)}] m\n\n")
    w("conditioning:\n")
    w(_conditioning("H0", h0) + "\n")
    if robot.n_dof > 0:
        w(_conditioning("H*", hs) + "\n")
        if robot.end_effector is not None:
            w(_conditioning("J*", js) + "\n")
            _, jm = robot.point_jacobian(x)
            w(_conditioning("J_m (fixed-base Jacobian, for comparison)", jm) + "\n")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        prog="spacearm",
        description="Equations of motion of spacecraft-manipulator systems (GJM formulation).",
    )
    parser.add_argument("--version", action="version", version=f"spacearm {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    p_inspect = sub.add_parser("inspect", help="print a model summary and H0, H*, J* at a configuration")
    add_model_arguments(p_inspect)
    p_inspect.add_argument("--q", metavar="Q1,Q2,...", help="joint coordinates, one per joint (rad, or m for prismatic "
                                                            "joints; default: the model's initial q)")
    from .cli_derive import add_parser as _add_derive  # noqa: E402

    _add_derive(sub)
    from .cli_analyze import add_parser as _add_analyze  # noqa: E402

    _add_analyze(sub)
    from .cli_simulate import add_parsers as _add_simulate  # noqa: E402

    _add_simulate(sub)
    from .cli_campaign import add_parser as _add_campaign  # noqa: E402

    _add_campaign(sub)
    # "--target -0.3,0.3,0" would be read as two options: pass such values as "--target=-0.3,...".
    args = parser.parse_args(attach_negative_values(sys.argv[1:] if argv is None else argv))
    try:
        if args.command == "inspect":
            robot = model_from_args(args)
            inspect(robot, None if args.q is None else joint_values(args.q, "--q", robot))
        elif args.command == "derive":
            from .cli_derive import run as _derive

            _derive(args, model_from_args)
        elif args.command == "analyze":
            from .cli_analyze import run as _analyze

            _analyze(args, model_from_args)
        elif args.command in ("simulate", "demo"):
            from .cli_simulate import run as _simulate

            return _simulate(args, model_from_args)
        elif args.command == "campaign":
            from .cli_campaign import run as _campaign

            _campaign(args, model_from_args)
    except SpacearmError as exc:
        print(f"spacearm: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # The reader went away (e.g. `spacearm inspect spatial6 | head`): not an error of ours.
        # Point stdout at devnull so the interpreter's final flush cannot raise again.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
