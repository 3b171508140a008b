"""Calls into the extension, Python calls and wall time of one CLI run (default: the README's capture command).

    python benchmarks/capture_calls.py [--repeat 3] [CLI ARGS...]

Counts with ``sys.setprofile`` (every ``c_call`` whose function belongs to ``spacearm._core``:
a module function, or a method of one of its classes) and every Python-level ``call`` event; the
wall time is the median of ``--repeat`` runs without the profiler.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time

README_CAPTURE = ["capture", "spatial6", "--target-mass", "50", "--target-inertia", "4,5,6", "--target-spin", "0,0,0.2",
                  "--mode", "floating", "--out", "cap.npz", "--plot", "cap.png"]


def _is_core(fn) -> bool:
    mod = getattr(fn, "__module__", None)
    if mod == "spacearm._core":
        return True
    owner = getattr(fn, "__self__", None)
    return owner is not None and (type(owner).__module__ == "spacearm._core" or getattr(owner, "__module__", None) == "spacearm._core"
                                  or getattr(owner, "__name__", None) == "spacearm._core")


def run(args):
    from spacearm.cli import main

    try:
        main(list(args))
    except SystemExit as exc:
        if exc.code not in (0, None):
            raise


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ns, cli = ap.parse_known_args()
    cli = [a for a in cli if a != "--"] or README_CAPTURE
    os.chdir(tempfile.mkdtemp())
    import spacearm  # noqa: F401  (import time not counted)
    import matplotlib

    matplotlib.use("Agg")
    run(cli)  # warm-up: imports, caches
    counts = {"core": 0, "python": 0}

    def prof(frame, event, arg):
        if event == "c_call" and _is_core(arg):
            counts["core"] += 1
        elif event == "call":
            counts["python"] += 1

    sys.setprofile(prof)
    try:
        run(cli)
    finally:
        sys.setprofile(None)
    times = []
    for _ in range(ns.repeat):
        t0 = time.perf_counter()
        run(cli)
        times.append(time.perf_counter() - t0)
    print(f"command: spacearm {' '.join(cli)}")
    print(f"calls into spacearm._core: {counts['core']}")
    print(f"Python calls: {counts['python']}")
    print(f"wall time, median of {ns.repeat}: {statistics.median(times):.3f} s  (all: {', '.join(f'{t:.3f}' for t in times)})")


if __name__ == "__main__":
    main()
