#!/usr/bin/env python
"""Time spacearm's forward-dynamics Jacobians against Pinocchio's ``computeABADerivatives``,
from Python, on the same models, at N = 2, 6, 12, 30, 60, in one run.

Every figure is the time of ONE call as a Python user makes it (argument conversion, the
computation, the result arrays), the median over interleaved batches (one batch of every
candidate per round, so drifting machine load hits all alike). Time is the CPU time of this
process (``time.process_time``) unless ``--wall``: on a shared machine, wall time also counts the
moments the scheduler gives the CPU to others, CPU time does not. Ratios are spacearm /
Pinocchio: below 1 means spacearm is faster. The growth exponent ``p`` is the least-squares
slope of log(time) against log(N) over the sizes run (time ≈ c·N^p).

Models: ``peers.random_arm(N)`` — a serial arm of N revolute joints with random axes, offsets
and masses on a 400 kg free base — exported to Pinocchio with :func:`spacearm.interop.to_pinocchio`.
Columns:

- ``FD derivs``: ``Robot.forward_dynamics_derivatives(x, u, f)`` (∂u̇/∂x, ∂u̇/∂u, H⁻¹), the
  analytic route (docs/derivatives.md);
- ``pinocchio``: ``pin.computeABADerivatives(model, data, q, v, tau)`` (ddq_dq, ddq_dv, Minv);
- ``linearize``: ``Robot.linearize(x, u, f)`` (A, B for the joint torques: the Jacobians plus
  assembly);
- ``dual``: ``Robot.forward_dynamics_derivatives(x, u, f, method="dual")``, the dual-number
  route kept as the test oracle;
- ``check``: Pinocchio's result mapped to spacearm's conventions by
  :func:`spacearm.interop.aba_derivatives_from_pinocchio`, max relative difference from
  spacearm's (so the rows compare calls that compute the same quantity).

    python benchmarks/derivatives.py                        # N = 2, 6, 12, 30, 60 (< 90 s)
    python benchmarks/derivatives.py --sizes 6,12 --quick --json derivatives.json
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import timeit  # noqa: E402

import numpy as np  # noqa: E402

from spacearm import interop  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peers import meta, random_arm, rel_diff, state  # noqa: E402

try:
    import pinocchio as pin
except ImportError:  # pragma: no cover - optional peer
    pin = None

COLUMNS = ("FD derivs", "pinocchio", "linearize", "dual")


def candidates(robot, x, u, f):
    """(column, timed callable)."""
    r = robot
    yield "FD derivs", lambda: r.forward_dynamics_derivatives(x, u, f)
    if pin is not None:
        model = interop.to_pinocchio(r)
        data = model.createData()
        q, v = interop.to_pinocchio_state(r, x, u)
        tau = interop.to_pinocchio_force(r, x, f)
        yield "pinocchio", lambda: pin.computeABADerivatives(model, data, q, v, tau)
    yield "linearize", lambda: r.linearize(x, u, f)
    yield "dual", lambda: r.forward_dynamics_derivatives(x, u, f, method="dual")


def pinocchio_check(robot, x, u, f) -> float:
    """Max relative difference of Pinocchio's Jacobians (mapped) from spacearm's analytic ones."""
    model = interop.to_pinocchio(robot)
    data = model.createData()
    q, v = interop.to_pinocchio_state(robot, x, u)
    tau = interop.to_pinocchio_force(robot, x, f)
    pin.computeABADerivatives(model, data, q, v, tau)
    theirs = interop.aba_derivatives_from_pinocchio(robot, x, u, f, data.ddq_dq, data.ddq_dv, data.Minv, data.ddq)
    ours = robot.forward_dynamics_derivatives(x, u, f)
    return max(rel_diff(a, b) for a, b in zip(theirs, ours))


def time_interleaved(fns, repeat: int, batch: float, timer):
    """Per-call times (s) of every callable: ``repeat`` rounds, one batch of each per round;
    a batch has the number of calls that lasts about ``batch`` seconds."""
    timers = [timeit.Timer(fn, timer=timer) for fn in fns]
    numbers = []
    for t in timers:
        n = 1
        while (elapsed := t.timeit(n)) < batch / 5 and n < 10_000_000:
            n *= 5
        numbers.append(max(1, int(n * batch / max(elapsed, 1e-9))))
    samples = [[] for _ in fns]
    for _ in range(repeat):
        for t, number, out in zip(timers, numbers, samples):
            out.append(t.timeit(number) / number)
    return samples, numbers


def run_size(n: int, repeat: int, batch: float, timer):
    robot = random_arm(n, 7)
    x, u, _, f = state(robot)
    # Displace the joints: at zero angles many terms vanish.
    x = x.copy()
    x[7:] += 0.4 * np.sin(0.7 + np.arange(n))
    cands = list(candidates(robot, x, u, f))
    samples, numbers = time_interleaved([c[1] for c in cands], repeat, batch, timer)
    row = {"n_dof": n, "check": pinocchio_check(robot, x, u, f) if pin is not None else None}
    for (col, _), s, number in zip(cands, samples, numbers):
        row[col] = {"median_s": float(np.median(s)), "min_s": float(np.min(s)), "calls_per_batch": number}
    return row


def growth_exponent(rows, col) -> float | None:
    pts = [(r["n_dof"], r[col]["median_s"]) for r in rows if col in r]
    if len(pts) < 2:
        return None
    n, t = np.array(pts, dtype=float).T
    return float(np.polyfit(np.log(n), np.log(t), 1)[0])


def print_table(rows, out=sys.stdout):
    print("\nforward-dynamics Jacobians, µs per call from Python: median (min) over the batches;", file=out)
    print("ratios spacearm / pinocchio of the medians (of the minima)", file=out)
    print(f"  {'N':>3s} {'FD derivs':>16s} {'pinocchio':>16s} {'ratio':>12s} {'linearize':>16s} {'ratio':>12s} {'dual':>10s} {'check':>8s}", file=out)
    for r in rows:
        med = {c: r[c]["median_s"] * 1e6 for c in COLUMNS if c in r}
        low = {c: r[c]["min_s"] * 1e6 for c in COLUMNS if c in r}
        has_pin = "pinocchio" in med

        def cell(c):
            return f"{med[c]:7.2f} ({low[c]:6.2f})" if c in med else f"{'—':>16s}"

        def ratio(c):
            if not has_pin:
                return f"{'':12s}"
            return f"{med[c] / med['pinocchio']:5.2f} ({low[c] / low['pinocchio']:4.2f})"

        check = f"{r['check']:8.1e}" if r["check"] is not None else ""
        print(f"  {r['n_dof']:3d} {cell('FD derivs')} {cell('pinocchio')} {ratio('FD derivs')} {cell('linearize')} {ratio('linearize')} "
              f"{med['dual']:10.2f} {check}", file=out)
    fits = {c: growth_exponent(rows, c) for c in COLUMNS}
    shown = ", ".join(f"{c} N^{p:.2f}" for c, p in fits.items() if p is not None)
    print(f"  growth (least squares of log median on log N): {shown}", file=out)
    return fits


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", default="2,6,12,30,60", help="comma-separated joint counts, default 2,6,12,30,60")
    ap.add_argument("--repeat", type=int, default=15, help="interleaved rounds, default 15")
    ap.add_argument("--batch", type=float, default=0.02, help="seconds per batch, default 0.02")
    ap.add_argument("--quick", action="store_true", help="5 rounds of 5 ms batches (a rough look)")
    ap.add_argument("--wall", action="store_true", help="wall-clock time instead of this process's CPU time")
    ap.add_argument("--json", metavar="PATH", help="also write every measurement and its context here")
    args = ap.parse_args(argv)
    if args.quick:
        args.repeat, args.batch = 5, 0.005
    try:
        sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    except ValueError:
        ap.error(f"--sizes must be comma-separated integers, got {args.sizes!r}")
    if not sizes or min(sizes) < 1:
        ap.error("--sizes needs at least one joint count >= 1")
    if pin is None:
        print("note: pinocchio is not installed; its column is left out", file=sys.stderr)
    timer = time.perf_counter if args.wall else time.process_time
    rows = [run_size(n, args.repeat, args.batch, timer) for n in sizes]
    fits = print_table(rows)
    print("  check: max relative difference of Pinocchio's result (mapped by")
    print("  spacearm.interop.aba_derivatives_from_pinocchio) from spacearm's.")
    if hasattr(os, "getloadavg"):
        print(f"  Load average at the end (1 min): {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs.")
    bad = [r for r in rows if r["check"] is not None and r["check"] > 1e-9]
    for r in bad:
        print(f"WARNING: N = {r['n_dof']}: spacearm and Pinocchio differ by {r['check']:.1e}", file=sys.stderr)
    if args.json:
        m = meta(args, ["spacearm"] + (["pinocchio"] if pin else []), None)
        m["timer"] = "perf_counter (wall)" if args.wall else "process_time (CPU)"
        with open(args.json + ".tmp", "w") as fh:
            json.dump({"meta": m, "results": rows, "growth_exponents": fits}, fh, indent=1)
        os.replace(args.json + ".tmp", args.json)
        print(f"wrote {args.json}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
