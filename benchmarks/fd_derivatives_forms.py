#!/usr/bin/env python
"""Time the two call forms of ``Robot.forward_dynamics_derivatives`` (analytic route) against
each other and against the native call underneath, on serial arms of N = 2, 6, 12 and 30 joints.

Rows (per-call medians over interleaved batches, µs):

- ``f form``: ``robot.forward_dynamics_derivatives(x, u, f)`` with ``f = [F0, N0, tau]``;
- ``tau form``: ``robot.forward_dynamics_derivatives(x, u, tau=tau, base_wrench=fb)`` (the
  extension assembles ``f``: one native call);
- ``tau form, no base wrench``: ``robot.forward_dynamics_derivatives(x, u, tau=tau)``;
- ``Python-assembled f``: the tau form as it was before (``f`` converted and concatenated in
  Python by ``Robot._force``, then the general native call), for comparison;
- ``native f``: ``robot._derivatives().forward_dynamics_derivatives(x, u, f)``, the extension
  alone (no ``Robot`` method, no NamedTuple): the floor any call form can reach.

Columns: the median per-call time over the rounds with its quartiles, the minimum (the
least-disturbed batch), and the ratio to the ``f form`` of the same model, taken round by round
and reported as the median over rounds. Each round times every row once, one batch of the same
number of calls each, in a fresh random order. Every row is checked to return the same arrays
as the ``f form`` (bit-identical) before timing. On a shared machine run it a few times and
compare medians, never single numbers.

    python benchmarks/fd_derivatives_forms.py                 # ~30 s
    python benchmarks/fd_derivatives_forms.py --sizes 6 --repeat 201 --json fdd_forms.json
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402

import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm.model.robot import ForwardDynamicsDerivatives  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from forward_dynamics_forms import time_shuffled  # noqa: E402
from peers import random_arm  # noqa: E402

SIZES = (2, 6, 12, 30)


def python_assembled(robot):
    """The tau form as it was before the extension assembled ``f`` (``Robot._force`` in Python,
    then the general native call), kept here only to measure what it cost."""
    d = robot._derivatives()

    def call(x, u, tau, base_wrench):
        return ForwardDynamicsDerivatives(*d.forward_dynamics_derivatives(x, u, robot._force(None, tau, base_wrench), None, False))

    return call


def rows_for(robot, x, u, tau, fb):
    f = np.concatenate([fb, tau])
    free = np.concatenate([np.zeros(6), tau])
    r, old, d = robot, python_assembled(robot), robot._derivatives()
    yield "f form", lambda: r.forward_dynamics_derivatives(x, u, f), f
    yield "tau form", lambda: r.forward_dynamics_derivatives(x, u, tau=tau, base_wrench=fb), f
    yield "tau form, no base wrench", lambda: r.forward_dynamics_derivatives(x, u, tau=tau), free
    yield "Python-assembled f", lambda: old(x, u, tau, fb), f
    yield "native f", lambda: d.forward_dynamics_derivatives(x, u, f), f


def run(n: int, repeat: int, target: float):
    robot = random_arm(n, seed=n)
    k = np.arange(n)
    x = robot.neutral_configuration(q=0.4 * np.sin(1.0 + k))
    u = np.concatenate([[0.05, -0.02, 0.01, 0.03, -0.04, 0.02], 0.3 * np.sin(1.0 + k)])
    tau = 2.0 * np.sin(3.0 + k)
    fb = np.array([1.0, -2.0, 0.5, 0.3, -0.2, 0.1])
    rows = list(rows_for(robot, x, u, tau, fb))
    for name, fn, f in rows:
        got, ref = fn(), robot.forward_dynamics_derivatives(x, u, f)
        if not all(np.array_equal(a, b) for a, b in zip(got, ref)):
            raise SystemExit(f"N = {n}: '{name}' does not return the f form's result")
    samples, numbers = time_shuffled([fn for _, fn, _ in rows], repeat, target, seed=n)
    out = []
    f_form = np.asarray(samples[0])
    for (name, _, _), s, number in zip(rows, samples, numbers):
        q1, med, q3 = np.percentile(s, [25, 50, 75])
        out.append({"n_dof": n, "row": name, "median_s": med, "q1_s": q1, "q3_s": q3, "min_s": min(s),
                    "ratio_to_f_form": float(np.median(np.asarray(s) / f_form)), "calls_per_batch": number})
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default=",".join(map(str, SIZES)), help="comma-separated N (default 2,6,12,30)")
    parser.add_argument("--repeat", type=int, default=101, help="interleaved rounds (default 101)")
    parser.add_argument("--batch", type=float, default=0.002, help="seconds per batch (default 0.002)")
    parser.add_argument("--json", help="write every measurement to this file")
    args = parser.parse_args(argv)
    results = []
    print("forward_dynamics_derivatives call forms, analytic (per-call µs: median [quartiles] min; "
          "ratio = row / f form, median over rounds)")
    for n in (int(s) for s in args.sizes.split(",")):
        rows = run(n, args.repeat, args.batch)
        results += rows
        print(f"N = {n}")
        for row in rows:
            print(f"  {row['row']:<26} {row['median_s'] * 1e6:7.2f}  [{row['q1_s'] * 1e6:6.2f} {row['q3_s'] * 1e6:6.2f}]"
                  f"  min {row['min_s'] * 1e6:6.2f}  ratio {row['ratio_to_f_form']:5.3f}")
    if args.json:
        meta = {"spacearm": spacearm.__version__, "numpy": np.__version__, "python": platform.python_version(),
                "machine": platform.machine(), "processor": platform.processor(), "repeat": args.repeat,
                "batch_s": args.batch}
        with open(args.json, "w") as fh:
            json.dump({"meta": meta, "results": results}, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
