"""The ``spacearm simulate`` and ``spacearm demo`` commands.

``spacearm simulate MODEL`` runs one simulation (mode, controller, integrator, step, target)
and writes any of: the trajectory (``--out run.npz``), a CSV table (``--csv``), the figure
(``--plot``), an animation (``--animate``) and a video (``--video run.mp4``, with
``--video-size``, ``--fps``, ``--renderer``, ``--speed``); it prints the run's summary (conservation drift
of the mode's conserved quantities, final tracking error, saturation events).

``spacearm demo`` runs the spatial 6-DOF example (the project-defined preset ``spatial6``) in
floating mode and writes its figures: a computed-torque joint maneuver (the base reacts, the
system CM stays put) and a torque-free run (momentum and energy conserved).

Registered in ``spacearm.cli`` by ``add_parsers`` and ``run``.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import List

import numpy as np

from .. import _core, control, presets
from ..orbit import Orbit
from .model_options import add_model_arguments, joint_values
from .numbers import CliError, parse_numbers
from ..sim.simulation import MODES, simulate  # MODES: the core's mode table

__all__ = ["add_parsers", "run", "build_controller", "reaction_wheel_dofs", "run_demo", "add_video_options", "video_options",
           "describe_video"]

CONTROLLERS = ("none", "pd", "computed-torque", "rmrc", "attitude", "coordinated")
#: The mode each controller runs in unless --mode says otherwise.
DEFAULT_MODE = {"none": "floating", "pd": "floating", "computed-torque": "floating", "rmrc": "floating",
                "attitude": "rotation-floating", "coordinated": "flying"}
#: A progress bar is shown for runs of at least this many steps (and with --progress).
PROGRESS_STEPS = 20_000


# ---------------------------------------------------------------------------------------------
# argument parsing
# ---------------------------------------------------------------------------------------------
def add_parsers(sub) -> None:
    """Add the ``simulate`` and ``demo`` sub-commands to ``spacearm``'s sub-parsers."""
    p = sub.add_parser("simulate", help="simulate a model under a controller and write the results",
                       description="Simulate MODEL in a maneuvering mode under a controller; print a summary and "
                                   "write the trajectory (.npz), a CSV table, a figure (PNG), an animation (GIF) and a video (MP4).")

    add_model_arguments(p)
    p.add_argument("--mode", choices=MODES, help="maneuvering mode (default: floating; rotation-floating for "
                                                 "--controller attitude, flying for coordinated)")
    p.add_argument("--controller", choices=CONTROLLERS, default="none",
                   help="none (zero torques), pd (joint PD), computed-torque (reduced EOM, eqs. 112-115), "
                        "rmrc (resolved motion rate through J*), attitude (reaction wheels hold the base attitude "
                        "while computed torque moves the arm), coordinated (flying: the base wrench holds the base "
                        "pose while the arm moves the end effector, spacearm.control.CoordinatedFlying)")
    p.add_argument("--duration", type=float, default=5.0, help="simulated time, s (default 5)")
    p.add_argument("--dt", type=float, default=1e-3, help="rk4 step; dopri5 output interval, s (default 0.001)")
    p.add_argument("--integrator", choices=("rk4", "dopri5"), default="rk4")
    p.add_argument("--rtol", type=float, default=1e-9, help="dopri5 relative tolerance (default 1e-9)")
    p.add_argument("--atol", type=float, default=1e-12, help="dopri5 absolute tolerance (default 1e-12)")
    p.add_argument("--target", help="pd, computed-torque, attitude: joint goal q1,q2,... (rad or m, one per actuated arm joint; "
                                    "default: initial q + 0.3); rmrc, coordinated: end-effector goal x,y,z in the "
                                    "inertial frame (m; default: 0.2 m from the start along each axis)")
    p.add_argument("--move-time", type=float, help="duration of the reference maneuver from t = 0, s "
                                                   "(default: 60%% of --duration)")
    p.add_argument("--kp", type=float, help="proportional gain (defaults: pd 16 H*_jj N m/rad per joint, i.e. 4 rad/s "
                                           "on the diagonal of H*; computed-torque 25 1/s^2; attitude base 50 N m/rad; "
                                           "rmrc: the position gain, default 2 1/s)")
    p.add_argument("--kd", type=float, help="derivative gain (defaults: pd 8 H*_jj N m s/rad per joint, critically "
                                           "damped; computed-torque 10 1/s; attitude base 6 I N m s/rad; coordinated: kd_ee, default 20 1/s)")
    p.add_argument("--q0", help="initial joint coordinates q1,q2,... (default: the model's initial q)")
    p.add_argument("--qd0", help="initial joint velocities (default 0)")
    p.add_argument("--base-velocity", help="initial base velocity v0x,v0y,v0z,w0x,w0y,w0z in the inertial frame "
                                           "(default 0)")
    p.add_argument("--record-every", type=int, default=1, help="rk4: keep every k-th step (default 1)")
    add_orbit_options(p)
    p.add_argument("--out", help="write the trajectory to this .npz file")
    p.add_argument("--csv", help="write one row per sample to this CSV file (header with units)")
    p.add_argument("--plot", help="write the multi-panel figure to this PNG file")
    p.add_argument("--animate", help="write a 3-D animation to this GIF file")
    p.add_argument("--frames", type=int, default=100, help="GIF frames (default 100)")
    add_video_options(p)
    p.add_argument("--progress", dest="progress", action="store_true", default=None,
                   help=f"show a progress bar (default: for runs of {PROGRESS_STEPS} steps or more, videos of 100 frames or more)")
    p.add_argument("--no-progress", dest="progress", action="store_false", help="never show a progress bar")

    d = sub.add_parser("demo", help="run the spatial 6-DOF example and write its figures",
                       description="Simulate the spatial 6-DOF example (the project-defined preset spatial6) in "
                                   "floating mode: a computed-torque maneuver and a torque-free run; print their "
                                   "summaries, write figures and say where. Figures need the plot extra: "
                                   'pip install "spacearm[plot]" (or pass --no-figures).')
    d.add_argument("--out-dir", default="spacearm-demo", help="directory for the figures (default: ./spacearm-demo)")
    d.add_argument("--no-animation", action="store_true", help="skip the GIF (the slowest part)")
    d.add_argument("--no-figures", action="store_true",
                   help="print the summaries and save the trajectory only (no matplotlib needed)")


def add_orbit_options(p) -> None:
    """``--orbit circular:ALT_KM[,INC_DEG]`` and ``--no-gravity-gradient`` (docs/orbit.md)."""
    p.add_argument("--orbit", help="run in orbit: circular:ALT_KM[,INC_DEG] (a circular Earth orbit of that altitude, km, "
                   "and inclination, deg, default 0); the system CM starts on it; gravity gradient on every body")
    p.add_argument("--no-gravity-gradient", action="store_true", help="with --orbit: no tidal force or torque")


def add_video_options(p) -> None:
    """``--video run.mp4`` and its ``--video-size``, ``--fps``, ``--renderer``, ``--speed``
    (spacearm.viz.video)."""
    g = p.add_argument_group("video")
    g.add_argument("--video", help="write an H.264 video to this .mp4 file (extra video: imageio-ffmpeg; MuJoCo renders it "
                                   "where it can, else matplotlib)")
    g.add_argument("--video-size", default="1280x720", help="WIDTHxHEIGHT in pixels, both even (default 1280x720)")
    g.add_argument("--fps", type=int, default=30, help="video frames per second (default 30)")
    g.add_argument("--renderer", choices=("auto", "mujoco", "matplotlib"), default="auto",
                   help="auto (MuJoCo where it can render offscreen, else matplotlib), mujoco or matplotlib")
    g.add_argument("--speed", type=float, default=1.0, help="playback speed, times real time (default 1)")


def video_options(args) -> dict:
    """The keywords of ``.video(...)`` from the options, checked before any work (an error of
    an option names it); ``{}`` without ``--video``. Checks that the encoder is installed."""
    if not getattr(args, "video", None):
        return {}
    from ..viz.video import _ffmpeg, check_video_options

    w, sep, h = str(args.video_size).lower().partition("x")
    try:
        width, height = int(w), int(h)
    except ValueError:
        raise CliError(f"--video-size must be WIDTHxHEIGHT in pixels (e.g. 1280x720), got {args.video_size!r}") from None
    if not sep:
        raise CliError(f"--video-size must be WIDTHxHEIGHT in pixels (e.g. 1280x720), got {args.video_size!r}")
    opts = check_video_options(args.video, width=width, height=height, fps=args.fps, speed=args.speed, renderer=args.renderer)
    _ffmpeg()
    return opts


def describe_video(video) -> str:
    """What the CLI prints of a written video."""
    return f"{video.path} ({video.width}x{video.height}, {video.frames} frames at {video.fps} fps, {video.renderer} renderer)"


def orbit_from_args(args):
    """The ``spacearm.Orbit`` of ``--orbit`` (None without it), refused with a ``CliError``
    naming the option and the expected form."""
    text = getattr(args, "orbit", None)
    if text is None:
        if getattr(args, "no_gravity_gradient", False):
            raise CliError("--no-gravity-gradient needs --orbit")
        return None
    kind, _, rest = text.partition(":")
    if kind.strip() != "circular" or not rest.strip():
        raise CliError(f"--orbit must be circular:ALT_KM[,INC_DEG], got {text!r}")
    values = parse_numbers(rest, "--orbit circular:", None, "ALT_KM[,INC_DEG]", "km, deg")
    if len(values) not in (1, 2):
        raise CliError(f"--orbit must be circular:ALT_KM[,INC_DEG] (one or two numbers), got {text!r}")
    altitude_km = float(values[0])  # > 0: the core's rule (Orbit.circular refuses an orbit at or below the surface)
    inclination = math.radians(float(values[1])) if len(values) == 2 else 0.0
    if not 0.0 <= inclination <= math.pi:
        raise CliError(f"--orbit: the inclination must be in [0, 180] deg, got {values[1]}")
    return Orbit.circular(altitude_km * 1e3, inclination=inclination)


def _require_figures(what: str) -> None:
    """Fail before any work when a figure is asked for and matplotlib is missing."""
    from .._util.optional import require

    require("matplotlib", what)


def reaction_wheel_dofs(robot) -> List[int]:
    """Degrees of freedom of the reaction wheels, by the simulator's own rule (read from the
    core, ``default_wheel_dofs``): a revolute joint on the base whose link has no children, its
    CM on the axis and an inertia symmetric about it (docs/simulation-core.md)."""
    return sorted(int(d) for d in _core.default_wheel_dofs(robot.core_model))


def _mean_base_inertia(robot) -> float:
    """Mean principal moment of the base inertia, kg m^2 (the scale of the attitude gains)."""
    return float(np.trace(robot.description.base.inertia) / 3.0)


# ---------------------------------------------------------------------------------------------
# controllers from the options
# ---------------------------------------------------------------------------------------------
def build_controller(name: str, robot, x0, u0, *, duration: float, target=None, move_time=None, kp=None, kd=None):
    """The [`spacearm.control`][spacearm.control] object that ``--controller name`` means (``None`` for
    ``"none"``): references start at the initial state and reach ``target`` at ``move_time``."""
    if name == "none":
        return None
    wheels = reaction_wheel_dofs(robot)
    # The actuated arm joints: the passive ones (slosh, panels) take no reference (docs/flexibility.md).
    actuated = robot.actuated_dofs
    arm = [j for j in range(robot.n_dof) if j not in wheels and actuated[j]]
    t_move = 0.6 * duration if move_time is None else float(move_time)
    if not t_move > 0:
        raise CliError(f"--move-time must be > 0 s, got {t_move}")
    q_arm0 = np.asarray(x0[7:])[arm]

    def joint_goal():
        if not arm:
            raise CliError(f"--controller {name} moves the arm joints, but '{robot.name}' has none (only reaction wheels)")
        if target is None:
            return q_arm0 + 0.3
        return parse_numbers(target, "--target", len(arm), f"joint goal, one per {'arm' if actuated.all() else 'actuated arm'} joint of '{robot.name}'",
                             "rad, or m for prismatic joints")

    def ee_line():
        """The end effector's straight line from its initial position to the goal."""
        if robot.end_effector is None:
            raise CliError(f"--controller {name} moves the end effector, but '{robot.name}' has none: name one with "
                           f"--end-effector (points: {', '.join(robot.point_names) or 'none'})")
        p0 = robot.point_position(x0)
        goal = p0 + 0.2 if target is None else parse_numbers(target, "--target", 3, "end-effector goal x,y,z in the inertial frame", "m")
        return control.CartesianLine(p0, goal, 0.0, t_move)

    kind = _core.controller_kind(name)  # the core's one table of names (control/spec.rs)
    if kind in ("joint_pd", "computed_torque"):
        ref = control.QuinticJoint(q_arm0, joint_goal(), 0.0, t_move)
        if kind == "joint_pd":
            kp_d, kd_d = control.inertia_scaled_gains(robot, x0, arm)
            return control.JointPD(kp=kp_d if kp is None else kp, kd=kd_d if kd is None else kd, reference=ref)
        return control.ComputedTorque(kp=25.0 if kp is None else kp, kd=10.0 if kd is None else kd, reference=ref)
    if kind == "resolved_motion_rate":
        return control.ResolvedMotionRate(ee_line(), gain=2.0 if kp is None else kp)
    if kind == "attitude":
        if not wheels:
            raise CliError(f"--controller attitude needs reaction wheels, but '{robot.name}' has none "
                           "(add them with RobotBuilder.add_reaction_wheel, or use a model file with wheel links such as "
                           "the shipped spatial6_wheels)")
        i_base = _mean_base_inertia(robot)
        base = control.AttitudeControl(quat_ref=np.asarray(x0[3:7]), kp=9.0 * i_base if kp is None else kp,
                                       kd=6.0 * i_base if kd is None else kd)
        if not arm:
            return base
        ref = control.QuinticJoint(q_arm0, joint_goal(), 0.0, t_move)
        return control.Combined(arm=control.ComputedTorque(kp=25.0, kd=10.0, reference=ref), base=base)
    if kind == "coordinated_flying":
        # Base pose held (the initial one), end effector along the line.
        gains = {k: v for k, v in (("kp_ee", kp), ("kd_ee", kd)) if v is not None}
        return control.CoordinatedFlying(ee_reference=ee_line(), **gains)
    raise CliError(f"--controller must be one of {', '.join(CONTROLLERS)}, got {name!r}")


# ---------------------------------------------------------------------------------------------
# commands
# ---------------------------------------------------------------------------------------------
def simulate_command(args, model_from_args, out=None) -> int:
    """Run ``spacearm simulate`` with parsed ``args``; ``model_from_args`` is the CLI's model
    loader (``spacearm.cli.model_from_args``)."""
    out = sys.stdout if out is None else out
    robot = model_from_args(args)
    if not (np.isfinite(args.duration) and args.duration > 0):
        raise CliError(f"--duration must be > 0 s, got {args.duration}")
    if not (np.isfinite(args.dt) and args.dt > 0):
        raise CliError(f"--dt must be > 0 s, got {args.dt}")
    if args.frames < 1:
        raise CliError(f"--frames must be >= 1, got {args.frames}")
    if args.plot or args.animate:
        _require_figures("--plot and --animate")
    video = video_options(args)
    x0 = robot.neutral_configuration(None if args.q0 is None else joint_values(args.q0, "--q0", robot))
    u0 = np.zeros(robot.nu)
    if args.qd0 is not None:
        u0[6:] = joint_values(args.qd0, "--qd0", robot)
    if args.base_velocity is not None:
        u0[:6] = parse_numbers(args.base_velocity, "--base-velocity", 6, "v0x,v0y,v0z,w0x,w0y,w0z in the inertial frame",
                               "m/s, rad/s")
    controller = build_controller(args.controller, robot, x0, u0, duration=args.duration, target=args.target,
                                  move_time=args.move_time, kp=args.kp, kd=args.kd)
    mode = args.mode or DEFAULT_MODE[args.controller]
    orbit = orbit_from_args(args)
    if orbit is not None:
        x0[:3] -= robot.center_of_mass(x0)  # the system CM on the orbit
    steps = args.duration / args.dt
    show = (steps >= PROGRESS_STEPS) if args.progress is None else bool(args.progress)
    traj = simulate(robot, args.duration, x0=x0, u0=u0, mode=mode, integrator=args.integrator,
                             dt=args.dt, rtol=args.rtol, atol=args.atol, controller=controller,
                             record_every=args.record_every, progress=show,  # True: a tqdm bar
                             orbit=orbit, gravity_gradient=None if orbit is None else not args.no_gravity_gradient)
    out.write(traj.summary() + "\n")
    written = []
    if args.out:
        written.append(("trajectory", traj.save(args.out)))
    if args.csv:
        written.append(("table", traj.to_csv(args.csv)))
    if args.plot:
        traj.plot(args.plot)
        written.append(("figure", str(args.plot)))
        if orbit is not None:
            lvlh = Path(args.plot).with_name(Path(args.plot).stem + "_lvlh" + Path(args.plot).suffix)
            traj.plot_lvlh(lvlh)
            written.append(("LVLH attitude figure", str(lvlh)))
    if args.animate:
        traj.animate(args.animate, frames=args.frames)
        written.append(("animation", str(args.animate)))
    if video:
        written.append(("video", describe_video(traj.video(args.video, progress=args.progress, **video))))
    for what, path in written:
        out.write(f"wrote {what}: {path}\n")
    return 0


def run_demo(out_dir, animation: bool = True, out=None, figures: bool = True) -> List[Path]:
    """The spatial 6-DOF example in floating mode; returns the files written.

    ``figures=False`` writes only the trajectory file (no matplotlib needed).

    1. Computed torque (reduced EOM, paper eqs. 112–115) drives the arm along a 4 s quintic
       from the preset's initial angles to ``q_goal``: the base turns and moves the opposite
       way, the system CM stays where it was (zero momentum), the tracking error stays at the
       integration level.
    2. The same model released with joint velocities (the base with the velocity that zeroes
       the momentum, eq. 109) and no torque: ``P``, ``L`` and the kinetic energy stay at their
       initial values to ~1e-13 and the system CM stays put.
    """
    out = sys.stdout if out is None else out
    if figures:
        _require_figures("the demo's figures (or pass --no-figures)")
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    robot = presets.spatial6()
    x0 = robot.neutral_configuration()
    q_goal = robot.initial_q + np.array([0.8, 0.5, 0.6, 0.5, 0.6, 0.5])
    ct = control.ComputedTorque(kp=25.0, kd=10.0, reference=control.QuinticJoint(robot.initial_q, q_goal, 0.0, 4.0))
    traj = simulate(robot, 5.0, x0=x0, controller=ct, dt=1e-3, record_every=10)
    files = []
    out.write("spatial 6-DOF example (preset spatial6, project-defined), floating mode\n\n")
    out.write("1. computed-torque maneuver, 5 s at 1 ms RK4\n" + traj.summary() + "\n")
    if figures:
        traj.plot(out_dir / "spatial6_computed_torque.png")
        files.append(out_dir / "spatial6_computed_torque.png")
    traj.save(out_dir / "spatial6_computed_torque.npz")
    files.append(out_dir / "spatial6_computed_torque.npz")
    if animation and figures:
        traj.animate(out_dir / "spatial6_computed_torque.gif", frames=50, fps=10)
        files.append(out_dir / "spatial6_computed_torque.gif")
    # Joints released with velocities, the base with the velocity that zeroes the momentum
    # (eq. 109): the base reacts, the CM stays put, P, L and the energy are conserved.
    qd0 = np.array([0.3, -0.2, 0.4, 0.5, -0.3, 0.6])
    u0 = np.concatenate([robot.base_velocity_from_momentum(x0, qd0), qd0])
    free = simulate(robot, 10.0, x0=x0, u0=u0, dt=1e-3, record_every=10)
    out.write("\n2. torque-free run, joints released with velocities at zero momentum, 10 s at 1 ms RK4\n" + free.summary() + "\n")
    if figures:
        free.plot(out_dir / "spatial6_torque_free.png")
        files.append(out_dir / "spatial6_torque_free.png")
    out.write("\nwrote:\n" + "".join(f"  {p}\n" for p in files))
    return files


def run(args, model_from_args) -> int:
    """Dispatch ``simulate`` or ``demo`` (called by ``spacearm.cli.main``)."""
    if args.command == "simulate":
        return simulate_command(args, model_from_args)
    if args.command == "demo":
        run_demo(args.out_dir, animation=not args.no_animation, figures=not args.no_figures)
        return 0
    raise CliError(f"unknown command {args.command!r}")
