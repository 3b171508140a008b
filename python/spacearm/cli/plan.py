"""The ``spacearm plan`` command: an optimal point-to-point maneuver of the free-floating
system ([`spacearm.plan.point_to_point`][spacearm.plan.point_to_point]), checked by re-simulation.

``spacearm plan MODEL --to X,Y,Z`` solves the multiple-shooting problem with IPOPT (progress on
stderr), re-simulates the plan in the native simulator under computed torque, prints both, and
writes the plan (``--out plan.npz``: ``t``, ``x``, ``u``, ``tau`` in spacearm's conventions) and
its figure (``--plot plan.png``, with the re-simulation). A plan that IPOPT did not solve, or
whose shooting defect or re-simulation is beyond the tolerances of
[`spacearm.plan.verify`][spacearm.plan.verify], is an error (``spacearm: error: no plan: ...``, exit 2, no file).

Registered in ``spacearm.cli`` by ``add_parser`` and ``run``.
"""

from __future__ import annotations

import sys
import warnings

import numpy as np

from ..errors import ArgumentError, PlanCheckWarning, SimulationError
from .model_options import add_model_arguments
from .numbers import parse_numbers

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:
    """Add the ``plan`` sub-command to ``spacearm``'s sub-parsers."""
    p = sub.add_parser("plan", help="plan an optimal point-to-point maneuver (CasADi + IPOPT)",
                       description="Plan a point-to-point end-effector maneuver of MODEL with the base free floating, "
                                   "minimising the base attitude disturbance or the joint effort under joint limits "
                                   "(direct multiple shooting, IPOPT; needs the optimal-control extra), re-simulate it "
                                   "and write it.")
    add_model_arguments(p)
    p.add_argument("--to", "--target", dest="target", required=True, metavar="X,Y,Z",
                   help="end-effector target position in the inertial frame, m")
    p.add_argument("--objective", "--minimize", dest="objective", choices=("attitude", "effort"), default="attitude",
                   help="minimise the base attitude disturbance (default) or the joint effort")
    p.add_argument("--duration", type=float, default=4.0, help="maneuver time, s (default 4)")
    p.add_argument("--nodes", type=int, default=20, help="knot intervals; the torque is linear between knots, a first-order hold (default 20)")
    p.add_argument("--substeps", type=int, default=2, help="RK4 steps per interval (default 2)")
    p.add_argument("--effort-limit", help="joint torque bound(s), N·m or N: one number or one per joint (default: the model's)")
    p.add_argument("--velocity-limit", help="joint speed bound(s), rad/s or m/s (default: the model's)")
    p.add_argument("--no-rest", action="store_true", help="do not require zero joint speeds at the end")
    p.add_argument("--reactionless-end", action="store_true", help="require zero base angular velocity at the end")
    p.add_argument("--max-iter", type=int, default=500, help="IPOPT iteration limit (default 500)")
    p.add_argument("--hessian", choices=("objective", "exact"), default="objective",
                   help="the Hessian IPOPT uses: the objective's only (default, fast per iteration) or the exact one "
                        "(slower; for problems without a reactionless path, docs/optimal-control.md)")
    p.add_argument("--out", required=True, help="write the plan here (.npz: t, x, u, tau, target, solver status)")
    p.add_argument("--plot", help="write the figure here (PNG): the plan against a quintic joint move and reactionless RMRC")


def _limit(text, option, robot):
    if text is None:
        return None
    values = parse_numbers(text, option, None, f"one number or {robot.n_dof} (one per joint)", "N·m or rad/s")
    if values.size not in (1, robot.n_dof):
        raise ArgumentError(f"{option} takes one number or {robot.n_dof} (one per joint), got {values.size}")
    return values if values.size > 1 else float(values[0])


def run(args, model_from_args) -> None:
    """Execute ``spacearm plan``."""
    from ..plan import point_to_point
    from ..plan.verify import POINT_TOLERANCE

    robot = model_from_args(args)
    target = parse_numbers(args.target, "--to", 3, "X,Y,Z", "m")
    if not args.out.endswith(".npz"):
        raise ArgumentError(f"--out takes a .npz file name, got {args.out!r}")

    def progress(iteration: int, objective: float) -> None:
        if iteration == 0:  # the arguments passed every check: the solve has started
            print(f"planning {robot.name}: {args.objective}, T = {args.duration:g} s, {args.nodes} intervals", file=sys.stderr)
        # One line rewritten in place on a terminal, one line per iteration otherwise.
        end = "" if sys.stderr.isatty() else "\n"
        print(f"\rIPOPT iteration {iteration:4d}  objective {objective:.6g}", end=end, file=sys.stderr, flush=True)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlanCheckWarning)  # the command reports a failed check itself, below
        plan = point_to_point(robot, target, duration=args.duration, nodes=args.nodes, substeps=args.substeps,
                              objective=args.objective, effort_limit=_limit(args.effort_limit, "--effort-limit", robot),
                              velocity_limit=_limit(args.velocity_limit, "--velocity-limit", robot), rest_at_end=not args.no_rest,
                              reactionless_end=args.reactionless_end, max_iter=args.max_iter, hessian=args.hessian,
                              progress=progress)
    if sys.stderr.isatty():
        print(file=sys.stderr)
    check = plan.verification
    print(f"IPOPT: {plan.status}, {plan.iterations} iterations, {plan.solve_time:.2f} s")
    print(f"plan: max base attitude change {np.degrees(plan.attitude_change.max()):.4g} deg, "
          f"effort {plan.effort:.4g} N²m²s, final point error {plan.final_position_error:.3g} m, shooting defect {check.defect:.3g}, "
          f"RK4 local error estimate {check.transcription_error:.3g}")
    if check.trajectory is not None:
        traj = check.trajectory
        print(f"re-simulation (computed torque, rk4 dt = {traj.t[1] - traj.t[0]:.3g} s): final point error "
              f"{check.point_error * 1e3:.3g} mm (tolerance {POINT_TOLERANCE * 1e3:g} mm), base attitude vs plan within "
              f"{np.degrees(check.attitude_error):.3g} deg (tolerance {np.degrees(check.attitude_tolerance):.3g} deg)")
    if not plan.success:
        raise SimulationError(f"no plan: {plan.failure}; nothing written (try a longer --duration, more --nodes or "
                             "--substeps, or a nearer target)")
    print(f"wrote {plan.save(args.out)}")
    if args.plot:
        print(f"wrote {plan.plot(args.plot)}")
