#!/usr/bin/env python
"""The rotation helpers of ``spacearm.rotations`` before and after a change, interleaved.

``--before REV`` names a git revision whose ``python/spacearm/rotations.py`` is loaded beside
the current one (``f5143ef``: the last numpy one) (as ``spacearm._rotations_before``, on the same extension), so
both run in one process on the same inputs. For one quaternion (or matrix) and for ``--batch``
rows (default 1000), each round times every candidate once (``--number`` calls, per-call time)
and the figures are the medians of ``--rounds`` rounds. Where the revision's helper takes no
batch (``quat_from_matrix`` before it took ``(B, 3, 3)``), its batch is a Python loop over the
rows. Ratios are after / before: below 1 means the change is faster.

    PYTHONPATH=python python benchmarks/rotations.py --before f5143ef
    PYTHONPATH=python python benchmarks/rotations.py --before f5143ef --rounds 21 --batch 10000
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import time
import types
from pathlib import Path

import numpy as np

import spacearm  # noqa: F401  (the package the old module is loaded into)
from spacearm import rotations as after

ROOT = Path(__file__).resolve().parents[1]


def load_before(rev: str) -> types.ModuleType:
    src = subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:python/spacearm/rotations.py"],
                         capture_output=True, text=True, check=True).stdout
    mod = types.ModuleType("spacearm._rotations_before")
    mod.__package__ = "spacearm"
    exec(compile(src, f"{rev}:rotations.py", "exec"), mod.__dict__)
    return mod


def per_call(fn, number: int) -> float:
    t0 = time.perf_counter()
    for _ in range(number):
        fn()
    return (time.perf_counter() - t0) / number


def batch_or_loop(f, xs):
    try:
        return f(xs)
    except Exception:  # the revision's helper takes one item: loop over the rows
        return np.array([f(x) for x in xs])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--before", required=True, help="git revision of the rotations.py to compare with")
    ap.add_argument("--batch", type=int, default=1000)
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--number", type=int, default=0, help="calls per timing (default: 2000 for one, 20 for a batch)")
    args = ap.parse_args()
    before = load_before(args.before)

    rng = np.random.default_rng(0)
    q = rng.normal(size=(args.batch, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    p = rng.normal(size=(args.batch, 4))
    p /= np.linalg.norm(p, axis=1, keepdims=True)
    m = after.quat_to_matrix(q)
    theta = rng.normal(size=3)
    v = rng.normal(size=(args.batch, 3))

    one = {
        "quat_multiply": lambda r: r.quat_multiply(q[0], p[0]),
        "quat_to_matrix": lambda r: r.quat_to_matrix(q[0]),
        "quat_from_matrix": lambda r: r.quat_from_matrix(m[0]),
        "rotation_vector": lambda r: r.rotation_vector(m[0]),
        "quat_exp": lambda r: r.quat_exp(theta),
        "quat_log": lambda r: r.quat_log(q[0]),
        "skew": lambda r: r.skew(v[0]),
        "quat_from_rpy": lambda r: r.quat_from_rpy(0.1, -0.2, 0.3),
    }
    many = {
        "quat_multiply": lambda r: r.quat_multiply(q, p),
        "quat_to_matrix": lambda r: r.quat_to_matrix(q),
        "quat_from_matrix": lambda r: batch_or_loop(r.quat_from_matrix, m),
        "skew": lambda r: r.skew(v),
    }
    for name, f in {**one, **many}.items():  # same results, to rounding, before timing
        diff = float(np.max(np.abs(np.asarray(f(after)) - np.asarray(f(before)))))
        assert diff < 1e-12, (name, diff)

    print(f"before = {args.before}:python/spacearm/rotations.py, after = working tree; median of {args.rounds} "
          f"interleaved rounds, per call")
    print(f"{'helper':<18} {'size':>6} {'before µs':>11} {'after µs':>10} {'after/before':>13}")
    for label, table, number in (("1", one, args.number or 2000), (str(args.batch), many, args.number or 20)):
        for name, f in table.items():
            times = {"before": [], "after": []}
            for _ in range(args.rounds):
                for key, mod in (("before", before), ("after", after)):
                    times[key].append(per_call(lambda: f(mod), number))
            b, a = statistics.median(times["before"]) * 1e6, statistics.median(times["after"]) * 1e6
            print(f"{name:<18} {label:>6} {b:>11.2f} {a:>10.2f} {a / b:>13.2f}")


if __name__ == "__main__":
    main()
