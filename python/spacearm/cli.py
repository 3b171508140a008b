"""The ``spacearm`` command line.

``spacearm inspect MODEL [--q Q1,Q2,...]`` prints the model summary (bodies, joints, total
mass) and, at the given or initial configuration, ``H0``, ``H*`` and the end-effector ``J*``
with their conditioning. ``MODEL`` is a preset name (``planar4``, ``spatial6``), a TOML
model file (``docs/model-format.md``) or a URDF file (``docs/urdf.md``; ``--mount-on SPACECRAFT
--at x,y,z,roll,pitch,yaw`` mounts it on a spacecraft base).
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Optional

import numpy as np

from . import __version__, presets
from .errors import SpacearmError
from .robot import Robot

__all__ = ["main", "load_model"]


def load_model(spec: str, mount_on: Optional[str] = None, at: Optional[str] = None, **urdf_options) -> Robot:
    """A preset by name, or a model file (``.toml``, ``.urdf``) by path.

    ``mount_on`` (a preset or ``.toml`` file, the spacecraft) and ``at`` (``"x,y,z,roll,pitch,yaw"``,
    m and rad, the URDF base link frame in the spacecraft base frame, from its CM) mount a URDF
    arm on a spacecraft instead of making its root link the free-flying base (docs/urdf.md).
    ``urdf_options`` (``prefix``, ``mimic``, ...) go to :func:`spacearm.urdf.load_urdf`.
    """
    if spec.lower().endswith(".urdf") and os.path.exists(spec):
        from .urdf import load_urdf

        if mount_on is None:
            if at is not None:
                raise SpacearmError("--at needs --mount-on (the spacecraft to mount the URDF on)")
            return load_urdf(spec, **urdf_options)
        pose = _parse_numbers("--at", at, 6, "x,y,z,roll,pitch,yaw (m, rad)") if at is not None else None
        return load_urdf(spec, mount_on=load_model(mount_on), at=pose, **urdf_options)
    if mount_on is not None or at is not None or any(v is not None for v in urdf_options.values()):
        raise SpacearmError("--mount-on, --at, --prefix and --mimic apply to URDF models (.urdf) only")
    if spec in presets.NAMES:
        return presets.get(spec)
    if os.path.exists(spec):
        if spec.lower().endswith(".toml"):
            return Robot.from_toml(spec)
        raise SpacearmError(f"cannot read '{spec}': model files must end in .toml or .urdf")
    raise SpacearmError(f"'{spec}' is neither a preset ({', '.join(presets.NAMES)}) nor an existing model file")


def _parse_numbers(option: str, text: str, n: int, meaning: str) -> np.ndarray:
    try:
        values = np.array([float(v) for v in text.replace(" ", "").split(",") if v != ""])
    except ValueError:
        raise SpacearmError(f"{option} must be {n} comma-separated numbers {meaning}, got '{text}'") from None
    if values.shape[0] != n or not np.all(np.isfinite(values)):
        raise SpacearmError(f"{option} must be {n} finite comma-separated numbers {meaning}, got '{text}'")
    return values


def _parse_q(text: str, n: int) -> np.ndarray:
    try:
        q = np.array([float(v) for v in text.replace(" ", "").split(",") if v != ""])
    except ValueError:
        raise SpacearmError(f"--q must be {n} comma-separated numbers (rad or m), got '{text}'") from None
    if q.shape[0] != n:
        raise SpacearmError(f"--q must have N = {n} values, got {q.shape[0]}")
    return q


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
    d = robot.describe()
    w = out.write
    w(f"model '{robot.name}': {robot.n_bodies} bodies, N = {robot.n_dof} joint DOF, total mass {robot.total_mass:.6g} kg\n\n")
    w(f"{'body':<16}{'parent':<16}{'joint':<16}{'type':<10}{'axis (link frame)':<26}{'mass kg':>9}\n")
    b = d["base"]
    w(f"{b['name']:<16}{'-':<16}{'-':<16}{'free':<10}{'-':<26}{b['mass']:>9.4g}\n")
    for link in d["links"]:
        axis = "-" if link["type"] == "fixed" else "[" + ", ".join(f"{v:.3g}" for v in link["axis"]) + "]"
        w(f"{link['name']:<16}{link['parent']:<16}{link['joint']:<16}{link['type']:<10}{axis:<26}{link['mass']:>9.4g}\n")
    if d["points"]:
        w("\npoints: " + ", ".join(f"{n} on {b} at [{', '.join(f'{v:.4g}' for v in o)}]" for n, b, o in d["points"]))
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
    p_inspect.add_argument("model", help=f"a preset ({', '.join(presets.NAMES)}), a .toml model file or a .urdf file")
    p_inspect.add_argument("--mount-on", help="mount the URDF on this spacecraft (a preset or .toml file) instead of "
                                              "making its root link the free-flying base")
    p_inspect.add_argument("--at", help="with --mount-on: x,y,z,roll,pitch,yaw of the URDF base link in the spacecraft "
                                        "base frame, from its CM (m, rad; default 0)")
    p_inspect.add_argument("--prefix", help="URDF only: prefix for the URDF's link, joint and point names")
    p_inspect.add_argument("--mimic", choices=("error", "independent"),
                           help="URDF only: refuse <mimic> joints (default) or load them as independent joints")
    p_inspect.add_argument("--q", help="joint coordinates, comma-separated (default: the model's initial q)")
    from .cli_derive import add_parser as _add_derive  # noqa: E402

    _add_derive(sub)
    from .cli_analyze import add_parser as _add_analyze  # noqa: E402

    _add_analyze(sub)
    from .cli_simulate import add_parsers as _add_simulate  # noqa: E402

    _add_simulate(sub)
    from .cli_campaign import add_parser as _add_campaign  # noqa: E402

    _add_campaign(sub)
    args = parser.parse_args(argv)
    try:
        if args.command == "inspect":
            options = {k: v for k, v in (("prefix", args.prefix), ("mimic", args.mimic)) if v is not None}
            robot = load_model(args.model, mount_on=args.mount_on, at=args.at, **options)
            q = None if args.q is None else _parse_q(args.q, robot.n_dof)
            inspect(robot, q)
        elif args.command == "derive":
            from .cli_derive import run as _derive

            _derive(args, load_model)
        elif args.command == "analyze":
            from .cli_analyze import run as _analyze

            _analyze(args, load_model)
        elif args.command in ("simulate", "demo"):
            from .cli_simulate import run as _simulate

            return _simulate(args, load_model)
        elif args.command == "campaign":
            from .cli_campaign import run as _campaign

            _campaign(args, load_model)
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
