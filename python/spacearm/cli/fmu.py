"""The ``spacearm fmu`` command: write MODEL as an FMI co-simulation unit
([`spacearm.fmi.export`][spacearm.fmi.export], docs/fmi.md).

``spacearm fmu MODEL --out M.fmu [--fmi-version 3|2] [--mode MODE] [--controller joint_pd|computed_torque
--kp K --kd D [--reference Q]] [--dt DT]`` (the controller's name as the core reads it: ``pd``, ``ct``,
``computed-torque`` too). The FMU's inputs are the joint torques ``tau[k]`` (and
``base_wrench[k]`` in the flying modes); its outputs the state, the momenta and the end-effector
pose; its parameters the initial state and the controller's gains and set point.

Registered in ``spacearm.cli`` by ``add_parser`` and ``run``.
"""

from __future__ import annotations

from .. import _core
from ..errors import ArgumentError
from ..sim.simulation import MODES  # the core's mode table
from .model_options import add_model_arguments
from .numbers import parse_numbers

__all__ = ["add_parser", "run"]

#: The laws this command builds from --kp, --kd and --reference (any other native law exports
#: through spacearm.fmi.export).
FROM_FLAGS = ("joint_pd", "computed_torque")


def add_parser(sub) -> None:
    """Add the ``fmu`` sub-command to ``spacearm``'s sub-parsers."""
    p = sub.add_parser("fmu", help="write MODEL as an FMI 3 or FMI 2 co-simulation unit (FMU)",
                       description="Write MODEL as a co-simulation FMU whose binary is the spacearm C library: inputs the "
                                   "joint torques (and the base wrench in the flying modes), outputs the state, momenta "
                                   "and end-effector pose, parameters the initial state and the controller's gains and "
                                   "set point (docs/fmi.md).")
    add_model_arguments(p)
    p.add_argument("--out", required=True, help="the FMU to write (.fmu)")
    p.add_argument("--fmi-version", type=int, choices=(3, 2), default=3, help="FMI version (default 3)")
    p.add_argument("--mode", choices=MODES, default="floating", help="maneuvering mode (default floating)")
    p.add_argument("--controller", default="none",
                   help="a native controller inside the FMU: none (default), joint_pd (pd) or computed_torque (ct); other laws "
                        "through spacearm.fmi.export")
    p.add_argument("--kp", help="controller stiffness: one number or one per arm joint")
    p.add_argument("--kd", help="controller damping: one number or one per arm joint")
    p.add_argument("--reference", help="controller set point, one per actuated arm joint (default: the model's initial "
                                       "joint angles)")
    p.add_argument("--dt", type=float, default=1e-3, help="the FMU's RK4 step, s (default 0.001); communication steps "
                                                          "must be multiples of it")
    p.add_argument("--stop-time", type=float, default=1.0, help="the default experiment's stop time, s (default 1)")


def run(args, model_from_args) -> None:
    """Execute ``spacearm fmu``."""
    from ..control import ComputedTorque, JointPD
    from ..fmi import export

    if not args.out.endswith(".fmu"):
        raise ArgumentError(f"--out takes a .fmu file name, got {args.out!r}")
    robot = model_from_args(args)
    kind = _core.controller_kind(args.controller)  # the core's names and aliases
    controller = None
    if kind == "none":
        for option in ("kp", "kd", "reference"):
            if getattr(args, option) is not None:
                raise ArgumentError(f"--{option} needs --controller joint_pd or computed_torque")
    elif kind not in FROM_FLAGS:
        raise ArgumentError(f"spacearm fmu builds {' or '.join(FROM_FLAGS)} from --kp, --kd and --reference; a {kind} controller "
                            "exports through spacearm.fmi.export(robot, path, controller=...)")
    else:
        if args.kp is None or args.kd is None:
            raise ArgumentError(f"--controller {args.controller} needs --kp and --kd")
        kp = parse_numbers(args.kp, "--kp", None, "one gain or one per arm joint", "N·m/rad")
        kd = parse_numbers(args.kd, "--kd", None, "one gain or one per arm joint", "N·m·s/rad")
        arm = robot.actuated_arm_dofs
        reference = robot.initial_q[arm] if args.reference is None else parse_numbers(args.reference, "--reference", None,
                                                                                        "one per actuated arm joint", "rad or m")
        cls = JointPD if kind == "joint_pd" else ComputedTorque
        controller = cls(kp=kp.tolist(), kd=kd.tolist(), reference=list(reference))
    path = export(robot, args.out, mode=args.mode, controller=controller, dt=args.dt, fmi_version=args.fmi_version,
                  stop_time=args.stop_time)
    print(f"wrote {path} (FMI {args.fmi_version}.0 co-simulation, {robot.name}, {robot.n_dof} joints, mode {args.mode}, "
          f"controller {kind}, RK4 at {args.dt:g} s)")
