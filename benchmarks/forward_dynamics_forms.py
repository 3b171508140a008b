#!/usr/bin/env python
"""Time the two call forms of ``Robot.forward_dynamics`` (ABA) against each other and against
the native call underneath, on serial arms of N = 2, 6, 12 and 30 joints.

Rows (per-call medians over interleaved batches, µs):

- ``f form``: ``robot.forward_dynamics(x, u, f)`` with ``f = [F0, N0, tau]``;
- ``tau form``: ``robot.forward_dynamics(x, u, tau=tau, base_wrench=fb)`` (the extension
  assembles ``f``: one native call);
- ``tau form, no base wrench``: ``robot.forward_dynamics(x, u, tau=tau)`` (free-floating);
- ``Python-assembled f``: what the tau form cost when ``f`` was built in Python
  (``np.concatenate`` of the converted parts, then the native call), for comparison;
- ``native f``: ``robot._m.forward_dynamics_aba(x, u, f)``, the extension alone (no
  ``Robot`` method): the floor any call form can reach.

Columns: the median per-call time over the rounds with its quartiles, the minimum (the
least-disturbed batch), and the ratio to the ``f form`` of the same model, taken round by round
and reported as the median over rounds. Each round times every row once, one batch of the same
number of calls each, in a fresh random order (so that a disturbance that recurs with the
rounds does not always land on the same row). Every row is checked to return the same array as the
``f form`` (bit-identical) before timing. On a shared machine run it a few times and compare
medians, never single numbers.

    python benchmarks/forward_dynamics_forms.py                 # ~20 s
    python benchmarks/forward_dynamics_forms.py --repeat 31 --json fd_forms.json
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
from spacearm._util.arrays import vector  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peers import calibrate, random_arm  # noqa: E402

SIZES = (2, 6, 12, 30)


def python_assembled(robot):
    """The tau form as it was before the extension assembled ``f`` (conversion, concatenation
    and the native call), kept here only to measure what it cost."""
    m, n = robot._m, robot.n_dof

    def call(x, u, tau, base_wrench):
        f = np.concatenate([vector(base_wrench, "base_wrench", 6), vector(tau, "tau", n)])
        return m.forward_dynamics_aba(x, u, f)

    return call


def rows_for(robot, x, u, tau, fb):
    f = np.concatenate([fb, tau])
    r, old = robot, python_assembled(robot)
    yield "f form", lambda: r.forward_dynamics(x, u, f), f
    yield "tau form", lambda: r.forward_dynamics(x, u, tau=tau, base_wrench=fb), f
    yield "tau form, no base wrench", lambda: r.forward_dynamics(x, u, tau=tau), np.concatenate([np.zeros(6), tau])
    yield "Python-assembled f", lambda: old(x, u, tau, fb), f
    yield "native f", lambda: r._m.forward_dynamics_aba(x, u, f), f


def time_shuffled(fns, repeat: int, target: float, seed: int):
    """Per-call times (s) of every callable over ``repeat`` rounds, each round in a random order."""
    import timeit

    number = calibrate(fns[0], target)
    timers = [timeit.Timer(fn) for fn in fns]
    samples = [[] for _ in fns]
    rng = np.random.default_rng(seed)
    for _ in range(repeat):
        for i in rng.permutation(len(fns)):
            samples[i].append(timers[i].timeit(number) / number)
    return samples, [number] * len(fns)


def run(n: int, repeat: int, target: float):
    robot = random_arm(n, seed=n)
    k = np.arange(n)
    x = robot.neutral_configuration(q=0.4 * np.sin(1.0 + k))
    u = np.concatenate([[0.05, -0.02, 0.01, 0.03, -0.04, 0.02], 0.3 * np.sin(1.0 + k)])
    tau = 2.0 * np.sin(3.0 + k)
    fb = np.array([1.0, -2.0, 0.5, 0.3, -0.2, 0.1])
    rows = list(rows_for(robot, x, u, tau, fb))
    for name, fn, f in rows:
        if not np.array_equal(fn(), robot.forward_dynamics(x, u, f)):
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
    print("forward_dynamics call forms, ABA (per-call µs: median [quartiles] min; ratio = row / f form, "
          "median over rounds)")
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
