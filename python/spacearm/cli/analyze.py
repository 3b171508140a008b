"""``spacearm analyze MODEL --singularities|--workspace|--reactionless --out FIG.png [...]``.

Runs one of the analyses of [`spacearm.analysis`][spacearm.analysis] on a model, prints its numbers (with the
scan's samples per second) and writes its figure atomically. Registered in ``spacearm.cli``.
"""

from __future__ import annotations

import sys

import numpy as np

from .model_options import add_model_arguments, joint_values

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:

    p = sub.add_parser("analyze", help="dynamic singularities, workspaces or reactionless motion, with a figure")
    add_model_arguments(p)
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--singularities", action="store_true", help="σ_min(J*) and σ_min(J_m) map over two joints, with the singular locus")
    what.add_argument("--workspace", action="store_true", help="reachable / path-dependent / path-independent and fixed-base workspaces")
    what.add_argument("--reactionless", action="store_true", help="reactionless vs naive (and minimum-disturbance) motion to a target")
    p.add_argument("--out", required=True, metavar="FIG.png", help="figure to write (png, pdf or svg)")
    p.add_argument("--resolution", type=int, default=None,
                   help="grid values per joint (default: 121 for --singularities over two joints, 11 for --workspace)")
    p.add_argument("--samples", type=int, default=None, help="--workspace: this many uniform random samples instead of a grid")
    p.add_argument("--seed", type=int, default=0, help="--workspace: seed of the random samples (default 0)")
    p.add_argument("--task", default="auto",
                   help="twist rows: position, planar, planar_pose, orientation, full, or indices like 0,1,5 (default: planar for a "
                        "planar arm, else position)")
    p.add_argument("--point", default=None, help="a point name (default: the end effector)")
    p.add_argument("--joints", default=None, help="--singularities: the two joints to vary, 1-based (default: the last two)")
    p.add_argument("--q", default=None, help="joint coordinates of the other joints / the start (default: the model's initial q)")
    p.add_argument("--plane", default="xy", choices=("xy", "xz", "yz"), help="--workspace: the slice plotted (default xy)")
    p.add_argument("--target", default=None,
                   help="--reactionless: displacement dx,dy,dz of the point from its start, m (default -0.3,0.3,0 for a planar arm, "
                        "-0.3,0,0.2 otherwise)")
    p.add_argument("--duration", type=float, default=4.0, help="--reactionless: motion time, s (default 4; plus 1 s settling)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")


def _task(text):
    from .numbers import parse_numbers

    if text in (None, "auto"):
        return None
    if text.strip()[:1].isdigit():
        return [int(v) for v in parse_numbers(text, "--task", None, "twist row indices 0..5", "dimensionless", integer=True)]
    return text


def run(args, model_from_args, out=None) -> None:
    out = sys.stdout if out is None else out
    from .. import analysis
    from .numbers import parse_numbers
    from ..errors import SpacearmError

    robot = model_from_args(args)
    if robot.n_dof == 0:
        raise SpacearmError(f"model '{robot.name}' has no joints to analyse")
    q = None if args.q is None else joint_values(args.q, "--q", robot)
    task = _task(args.task)
    rows = analysis.task_rows(robot, task)
    progress = not args.no_progress
    w = out.write
    if args.singularities:
        if robot.n_dof < 2:
            raise SpacearmError("--singularities maps two joints: the model has only one")
        joints = None
        if args.joints is not None:
            joints = tuple(int(v) - 1 for v in parse_numbers(args.joints, "--joints", 2, "two joint numbers, 1-based", "dimensionless",
                                                             integer=True))
        res = 121 if args.resolution is None else args.resolution
        m = analysis.singularity_map(robot, joints=joints, resolution=res, q=q, point=args.point, task=task, progress=progress)
        rep = analysis.analyze(robot, robot.neutral_configuration(q), point=args.point, task=task)
        w(f"model '{robot.name}', task rows {rows}, at q = [{', '.join(f'{v:.4g}' for v in (robot.initial_q if q is None else q))}]:\n")
        for name, meas in (("J* (free floating)", rep.generalized), ("J_m (fixed base)", rep.fixed_base)):
            w(f"  {name:20s} singular values [{', '.join(f'{v:.4g}' for v in meas.singular_values)}], condition {meas.condition:.4g}, "
              f"manipulability {meas.manipulability:.4g}\n")
        w(f"map over q{m.joints[0] + 1} x q{m.joints[1] + 1}: {res}x{res} = {res * res} samples in {m.seconds:.3f} s "
          f"({m.samples_per_second:.0f} samples/s)\n")
        w(f"  sigma_min(J*): min {np.nanmin(m.sigma_min_generalized):.4g}, max {np.nanmax(m.sigma_min_generalized):.4g}; "
          f"sigma_min(J_m): min {np.nanmin(m.sigma_min_fixed):.4g}, max {np.nanmax(m.sigma_min_fixed):.4g}\n")
        path = m.plot(args.out)
    elif args.workspace:
        if args.samples is not None:
            ws = analysis.workspace(robot, random_samples=args.samples, seed=args.seed, point=args.point, task=task, progress=progress)
        else:
            ws = analysis.workspace(robot, resolution=11 if args.resolution is None else args.resolution, point=args.point, task=task,
                                    progress=progress)
        fmt = lambda ivs: ", ".join(f"[{a:.4g}, {b:.4g}]" for a, b in ivs) or "none"  # noqa: E731
        w(f"model '{robot.name}', task rows {rows}; {ws.resolution}; {ws.seconds:.3f} s ({ws.samples_per_second:.0f} samples/s)\n")
        w(f"  fixed base: distance of the point from the base CM {ws.fixed_base[0]:.4g} … {ws.fixed_base[1]:.4g} m\n")
        w(f"  free floating (zero momentum), about the system CM: reachable shell {ws.reachable[0]:.4g} … {ws.reachable[1]:.4g} m\n")
        w(f"  path-dependent shells (dynamic singularities, sigma_min < {ws.singular_threshold:.3g}, merged at "
          f"{ws.radial_resolution:.3g} m): {fmt(ws.path_dependent)}\n")
        w(f"  path-independent shells: {fmt(ws.path_independent)}\n")
        points = [iv for iv in ws.path_dependent if iv[1] - iv[0] <= 0.0]
        if points:
            w(f"  degenerate: {len(points)} of the {len(ws.path_dependent)} path-dependent shells have zero width (a single radius): "
              "the sampling met a singularity only at isolated samples (on a grid, joints at exactly 0 or ±π), so these "
              "shells are radii, not measured regions, and the path-independent shells between them are gaps between radii")
            if len(rows) < robot.n_dof:
                w(f". The task is redundant ({len(rows)} rows, {robot.n_dof} joints): J* loses rank only on a thin set of "
                  "configurations (e.g. the arm stretched or folded), which denser sampling does not widen; a square task "
                  "(as many rows as joints, e.g. spatial6 with --task full) has singular surfaces that sweep shells with width\n")
            else:
                w(". Denser samples (--resolution, --samples) resolve more of them\n")
        path = ws.plot(args.out, plane=args.plane)
    else:
        planar = rows == [0, 1]
        if args.target is None:
            delta = np.array([-0.3, 0.3, 0.0]) if planar else np.array([-0.3, 0.0, 0.2])
        else:
            delta = parse_numbers(args.target, "--target", 3, "dx,dy,dz of the point from its start", "m")
        x0 = robot.neutral_configuration(q)
        target = robot.point_position(x0, args.point) + delta
        motions = []
        for strategy in ("reactionless", "minimum_disturbance", "naive"):
            motions.append(analysis.move_to(robot, target, x0=x0, point=args.point, task=task, strategy=strategy, duration=args.duration))
        rns = analysis.reaction_null_space(robot, x0)
        w(f"model '{robot.name}', task rows {rows}; reaction null space at the start: dimension {rns.dimension} of {robot.n_dof}\n")
        w(f"target {np.array2string(target, precision=4)} m (start + {np.array2string(delta, precision=3)}), {args.duration:g} s + 1 s settling:\n")
        for m in motions:
            w(f"  {m.strategy:20s} base attitude change max {m.max_attitude_change:.3e} rad ({np.degrees(m.max_attitude_change):.4g} deg), "
              f"final error {m.final_position_error:.3e} m, min sigma {m.sigma_min.min():.3g}\n")
        path = motions[0].plot(args.out, others=motions[1:])
    w(f"figure written to {path}\n")
