"""``spacearm capture MODEL --target-mass M --target-inertia IXX,IYY,IZZ --target-spin WX,WY,WZ ...``:
the capture of a tumbling target, approach → capture → post-capture → detumble
([`spacearm.capture.capture`][spacearm.capture.capture]), with a printed summary, the ``.npz`` record, figures and a video (``--video capture.mp4``).

The arm starts at ``--q0`` (default the model's initial joint coordinates). The target starts
at ``--target-at`` (its CM, m in 𝒥; default 0.6 m beyond the end effector, away from the base
CM), at rest apart from its spin, with its axes along 𝒥's; its grasp point is ``--grasp-offset``
from its CM in its axes (default: towards the end effector, 0.1 m short of it). A grasp point
farther from the CM than the handle bound (``spacearm.capture.MAX_HANDLE_RATIO`` times the
target's size) is refused, as is a target out of the arm's reach.

``--orbit circular:ALT_KM[,INC_DEG]`` (the parser of ``spacearm simulate``) runs the capture in
orbit (docs/orbit.md, "Capture in orbit"): the robot's system CM put on the orbit, the target
placed by ``--target-at`` (run frame) or ``--target-lvlh X,Y,Z[,VX,VY,VZ]`` (its CM relative to the
chaser's CM in LVLH), the momentum balance in place of the drift; ``--plot`` also shows the
attitude relative to LVLH and the target's relative path.

``--contact`` flies a capture on contact instead ([`spacearm.capture.ContactCapture`][spacearm.capture.ContactCapture];
docs/contact.md, "A capture on contact"): MODEL's gripper (``--gripper``, default its only one)
closes on the handle of a tumbling ``--target-mass`` kg box (default 20) placed at the grasp
centre and moved by the approach errors ``--offset X,Y,Z`` (m) and ``--attitude-error RX,RY,RZ``
(rad), spinning at ``--spin`` rad/s about its handle, with Coulomb's ``--friction``; the core
judges the grasp held, slipped or missed and the command prints it. Exit status 0 when the grasp
held, 1 when it slipped or missed (an outcome, not an error), 2 on bad input.
"""

from __future__ import annotations

import math
import sys

import numpy as np

from .model_options import add_model_arguments, joint_values
from .numbers import parse_numbers
from .simulate import add_video_options, describe_video, video_options

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:
    p = sub.add_parser("capture", help="capture of a tumbling target: approach, grasp impact, detumbling, momentum ledger",
                       description="Simulates the approach of the grasp point (RMRC through J*), the grasp impact, the "
                                   "captured system and its detumbling; prints the impulse, the base disturbance, peak "
                                   "wrench and torques, the detumble time and the momentum drift.")
    add_model_arguments(p)
    p.add_argument("--q0", default=None, help="the arm's initial joint coordinates q1,q2,... (default: the model's initial q)")
    t = p.add_argument_group("target")
    t.add_argument("--target-mass", type=float, default=None, help="kg (required; with --contact default 20)")
    t.add_argument("--target-inertia", default=None, help="IXX,IYY,IZZ principal moments about its CM, kg m² (required "
                                                          "but with --contact: a uniform box's)")
    t.add_argument("--target-spin", default="0,0,0", help="WX,WY,WZ angular velocity in 𝒥, rad/s (default 0,0,0)")
    t.add_argument("--target-at", default=None, help="X,Y,Z of its CM in 𝒥, m (default 0.6 m beyond the end effector)")
    t.add_argument("--grasp-offset", default=None, help="X,Y,Z of the grasp point from its CM, target axes, m")
    t.add_argument("--target-lvlh", default=None,
                   help="with --orbit: X,Y,Z[,VX,VY,VZ] of its CM relative to the chaser's CM in LVLH (x radial, y along-track, "
                        "z orbit normal), m and m/s (instead of --target-at)")
    c = p.add_argument_group("capture")
    c.add_argument("--kind", default="rigid", choices=("rigid", "point", "soft"), help="grasp model (default rigid)")
    c.add_argument("--restitution", type=float, default=0.0, help="e in [0, 1] for --kind point (default 0)")
    c.add_argument("--mode", default="floating", choices=("floating", "flying"), help="maneuvering mode (default floating)")
    c.add_argument("--approach-time", type=float, default=8.0, help="longest approach, s (default 8)")
    c.add_argument("--detumble-time", type=float, default=20.0, help="s (default 20)")
    c.add_argument("--dt", type=float, default=0.01, help="recording interval, s (default 0.01)")
    c.add_argument("--max-joint-torque", type=float, default=math.inf, help="N m, every joint (default none)")
    c.add_argument("--max-force", type=float, default=math.inf, help="base thruster force limit, N (flying; default none)")
    c.add_argument("--max-torque", type=float, default=math.inf, help="base thruster torque limit, N m (flying; default none)")
    k = p.add_argument_group("capture on contact (--contact; docs/contact.md)")
    k.add_argument("--contact", action="store_true",
                   help="fly MODEL's gripper closing on a tumbling box's handle by contact and print the core's outcome "
                        "(held: exit 0; slipped or missed: exit 1)")
    k.add_argument("--gripper", default=None, help="the gripper (default MODEL's only one)")
    k.add_argument("--spin", type=float, default=0.05, help="the box's spin about its handle, rad/s (default 0.05)")
    k.add_argument("--offset", default="0,0,0", help="X,Y,Z: the handle's offset from the grasp centre, m in 𝒥 (default 0)")
    k.add_argument("--attitude-error", default="0,0,0",
                   help="RX,RY,RZ: the box's attitude error about the handle, a rotation vector in 𝒥, rad (default 0)")
    k.add_argument("--friction", type=float, default=0.5, help="Coulomb's mu between fingers and box (default 0.5)")
    k.add_argument("--duration", type=float, default=3.0, help="the run, s (default 3)")
    k.add_argument("--step", type=float, default=5e-4, help="RK4 step, s (default 0.0005)")
    from .simulate import add_orbit_options

    add_orbit_options(p)
    o = p.add_argument_group("output")
    o.add_argument("--out", default=None, help="write the record (.npz: t, phase, P, L, impulse, ...)")
    o.add_argument("--plot", default=None, help="write the figure (PNG)")
    o.add_argument("--animate", default=None, help="write an animation (GIF)")
    add_video_options(p)


def _vec(v) -> str:
    return "[" + ", ".join(f"{x:.4g}" for x in v) + "]"


def _run_contact(args, robot, out) -> int:
    """``--contact``: the capture on contact, its outcome printed; 0 if held, 1 otherwise."""
    from ..capture import ContactCapture
    from .numbers import CliError

    defaults = {"target_inertia": None, "target_at": None, "grasp_offset": None, "target_lvlh": None, "orbit": None,
                "target_spin": "0,0,0", "kind": "rigid", "mode": "floating", "animate": None, "video": None}
    given = [f"--{k.replace('_', '-')}" for k, v in defaults.items() if getattr(args, k, None) != v]
    if given:
        raise CliError(f"{', '.join(given)} not taken with --contact (the box is placed at the grasp centre and moved by "
                       "--offset and --attitude-error, spinning at --spin about its handle)")
    c = ContactCapture(spin=args.spin, offset=tuple(parse_numbers(args.offset, "--offset", 3, "X,Y,Z", "m")),
                       attitude_error=tuple(parse_numbers(args.attitude_error, "--attitude-error", 3, "RX,RY,RZ", "rad")),
                       friction=args.friction, duration=args.duration, dt=args.step,
                       **({} if args.target_mass is None else {"target_mass": args.target_mass}))
    res = c.fly(robot, args.gripper)
    out.write(res.summary() + "\n")
    if args.out:
        res.traj.save(args.out)
        out.write(f"record: {args.out}\n")
    if args.plot:
        from ..viz.figures import plot_to

        plot_to(args.plot, lambda: _contact_figure(res), dpi=110)
        out.write(f"figure: {args.plot}\n")
    return 0 if res.held else 1


def _contact_figure(res):
    """The finger squeeze and the handle's distance from the grasp centre over the run."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    traj = res.traj
    fig, ax = plt.subplots(2, 1, figsize=(6.4, 5.0), sharex=True)
    ax[0].plot(traj.t, traj["contact_normal_force"], lw=1)
    ax[0].set_ylabel("contact normal force (N)")
    ax[1].plot(traj.t, traj["contact_count"], lw=1)
    ax[1].set_ylabel("contacts")
    ax[1].set_xlabel("t (s)")
    ax[0].set_title(f"capture on contact: {res.outcome.outcome}")
    fig.tight_layout()
    return fig


def run(args, model_from_args, out=None) -> int:
    from ..capture import Target, capture
    from ..errors import ArgumentError
    from .numbers import CliError

    out = sys.stdout if out is None else out
    robot = model_from_args(args)
    if args.contact:
        return _run_contact(args, robot, out)
    for flag, value in (("--target-mass", args.target_mass), ("--target-inertia", args.target_inertia)):
        if value is None:
            raise CliError(f"the capture needs {flag} (or --contact for a capture on contact)")
    if robot.end_effector is None:
        raise ArgumentError(f"model '{robot.name}' has no end effector to grasp with; give one with the model options")
    video = video_options(args)
    inertia = parse_numbers(args.target_inertia, "--target-inertia", 3, "IXX,IYY,IZZ", "kg m²")
    spin = parse_numbers(args.target_spin, "--target-spin", 3, "WX,WY,WZ", "rad/s")
    from .numbers import CliError
    from .simulate import orbit_from_args

    orbit = orbit_from_args(args)
    x0 = robot.neutral_configuration(None if args.q0 is None else joint_values(args.q0, "--q0", robot))
    if orbit is not None:
        x0[:3] -= robot.center_of_mass(x0)  # the system CM on the orbit
    ee = robot.point_position(x0)
    rel = None
    if args.target_lvlh is not None:
        if orbit is None:
            raise CliError("--target-lvlh needs --orbit")
        if args.target_at is not None:
            raise CliError("give --target-at or --target-lvlh, not both")
        values = parse_numbers(args.target_lvlh, "--target-lvlh", None, "X,Y,Z[,VX,VY,VZ]", "m, m/s")
        if len(values) not in (3, 6):
            raise CliError(f"--target-lvlh takes 3 or 6 numbers (X,Y,Z[,VX,VY,VZ]), got {len(values)}")
        rel = np.concatenate([values, np.zeros(6 - len(values))])
        center = np.concatenate([robot.center_of_mass(x0), np.zeros(3)])
        at = orbit.lvlh_to_run(rel, center=center)[:3]
    elif args.target_at is None:
        outward = ee - x0[:3]
        outward = outward / np.linalg.norm(outward) if np.linalg.norm(outward) > 1e-9 else np.array([1.0, 0.0, 0.0])
        at = ee + 0.6 * outward
    else:
        at = parse_numbers(args.target_at, "--target-at", 3, "X,Y,Z", "m")
    if args.grasp_offset is None:
        to_ee = ee - at
        dist = float(np.linalg.norm(to_ee))
        grasp = to_ee * max(dist - 0.1, 0.0) / dist if dist > 1e-9 else np.zeros(3)
    else:
        grasp = parse_numbers(args.grasp_offset, "--grasp-offset", 3, "X,Y,Z", "m")
    if not 0.0 <= args.restitution <= 1.0:
        raise ArgumentError(f"--restitution must be in [0, 1], got {args.restitution}")
    target = Target(args.target_mass, inertia, grasp_points={"grasp": grasp})
    if rel is not None:
        state = target.state_in_orbit(orbit, rel, center=center, angular_velocity=spin)
    else:
        state = target.state(position=at, angular_velocity=spin)
    res = capture(robot, target, state, x0=x0, mode=args.mode, kind=args.kind, restitution=args.restitution,
                  approach_time=args.approach_time, detumble_time=args.detumble_time, dt=args.dt,
                  max_joint_torque=args.max_joint_torque, max_force=args.max_force, max_torque=args.max_torque,
                  orbit=orbit, gravity_gradient=None if orbit is None else not args.no_gravity_gradient)
    s = res.summary()
    w = out.write
    w(f"capture of a {target.mass:g} kg target spinning at {np.linalg.norm(spin):.4g} rad/s by {robot.name}: "
      f"{args.kind} grasp, {args.mode} mode\n")
    if args.kind == "soft":
        locked = res.phase_start("post-capture")
        w(f"  contact at t = {s['capture_time']:.3f} s, wrist impedance until t = {locked:.3f} s, then locked with "
          f"the grasp points {1e3 * s['gap']:.2f} mm apart (the impulse below is the lock's)\n")
    else:
        w(f"  grasp at t = {s['capture_time']:.3f} s, grasp points {1e3 * s['gap']:.2f} mm apart\n")
    w(f"  impulse on the robot: {_vec(s['impulse'][:3])} N s, {_vec(s['impulse'][3:])} N m s "
      f"(|f| {s['impulse_force_norm']:.4g} N s, |n| {s['impulse_moment_norm']:.4g} N m s)\n")
    w(f"  base jump: dv0 = {_vec(s['base_dv'])} m/s, dw0 = {_vec(s['base_dw'])} rad/s\n")
    w(f"  energy lost at the impact: {s['energy_lost']:.4g} J\n")
    w(f"  peak grasp wrench: {s['peak_grasp_force']:.4g} N, {s['peak_grasp_torque']:.4g} N m\n")
    w(f"  peak joint torque: {s['peak_joint_torque']:.4g} N m\n")
    detumble = s["time_to_detumble"]
    w(f"  detumbled: {'not within the run' if not math.isfinite(detumble) else f'{detumble:.2f} s after the detumble starts'}"
      f" (residual base spin {s['residual_spin']:.3g} rad/s)\n")
    if orbit is not None:
        rel_g = s["target_lvlh_at_grasp"]
        w(f"  in orbit: {s['orbit_altitude_km']:.6g} km, {s['orbit_inclination_deg']:.4g} deg, gravity gradient "
          f"{'on' if s['gravity_gradient'] else 'off'}; target at the grasp {_vec(rel_g)} m in LVLH\n")
        w(f"  external impulse (tidal + thrusters): {s['external_impulse_norm']:.4g} N s, "
          f"{s['external_angular_impulse_norm']:.4g} N m s; base attitude from LVLH {s['initial_lvlh_angle_deg']:.4g} deg at the "
          f"start, {s['final_lvlh_angle_deg']:.4g} deg at the end\n")
        w(f"  momentum balance of robot + target (relative residual): P {s['drift_P']:.2e}, L {s['drift_L']:.2e}\n")
    elif args.mode == "floating":
        w(f"  momentum drift of robot + target (relative): P {s['drift_P']:.2e}, L {s['drift_L']:.2e}\n")
    else:
        w(f"  momentum change by the thrusters (relative): P {s['drift_P']:.3g}, L {s['drift_L']:.3g}\n")
    if args.out:
        res.save(args.out)
        w(f"record: {args.out}\n")
    if args.plot:
        res.plot(args.plot)
        w(f"figure: {args.plot}\n")
    if args.animate:
        res.animate(args.animate)
        w(f"animation: {args.animate}\n")
    if video:
        w(f"video: {describe_video(res.video(args.video, **video))}\n")
    return 0
