"""Wall time of one CLI command under two builds, interleaved, with medians and the ratio.

    python benchmarks/compare_cli.py --a <python dir of build A> --b <python dir of build B> \
        [--repeat 11] [--clock wall|cpu] [CLI ARGS...]
        (default: the README's capture command without --plot)

Each run is a fresh interpreter (``PYTHONPATH=<dir> python -c ...``) that imports spacearm,
runs the command once to warm up and then times ``--inner`` runs of it in-process; the runs of
A and B alternate so that load on this machine hits both alike. ``--clock cpu`` times the
process's CPU time (``time.process_time``, all threads) instead of the wall clock: on a machine
whose cores are oversubscribed the wall clock mostly measures the wait for a core.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

README_CAPTURE = ["capture", "spatial6", "--target-mass", "50", "--target-inertia", "4,5,6", "--target-spin", "0,0,0.2",
                  "--mode", "floating", "--out", "cap.npz"]

_CHILD = r"""
import json, os, sys, tempfile, time
os.chdir(tempfile.mkdtemp())
import matplotlib; matplotlib.use("Agg")
from spacearm.cli import main
args = json.loads(sys.argv[1]); inner = int(sys.argv[2])
clock = time.process_time if sys.argv[3] == "cpu" else time.perf_counter
def run():
    try:
        main(list(args))
    except SystemExit as exc:
        if exc.code not in (0, None):
            raise
import contextlib, io
with contextlib.redirect_stdout(io.StringIO()):
    run()
    times = []
    for _ in range(inner):
        t0 = clock(); run(); times.append(clock() - t0)
print(json.dumps(times))
"""


def _time(pythonpath: str, args, inner: int, clock: str):
    env = dict(os.environ, PYTHONPATH=pythonpath)
    out = subprocess.run([sys.executable, "-c", _CHILD, json.dumps(args), str(inner), clock], env=env, capture_output=True, text=True,
                         check=True, cwd=tempfile.gettempdir())
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--a", required=True)
    ap.add_argument("--b", required=True)
    ap.add_argument("--repeat", type=int, default=5, help="interpreter launches per build")
    ap.add_argument("--inner", type=int, default=3, help="timed runs per launch")
    ap.add_argument("--clock", choices=("wall", "cpu"), default="wall", help="wall clock (default) or the process's CPU time")
    ns, cli = ap.parse_known_args()
    cli = [a for a in cli if a != "--"] or README_CAPTURE
    ta, tb = [], []
    for _ in range(ns.repeat):
        ta += _time(ns.a, cli, ns.inner, ns.clock)
        tb += _time(ns.b, cli, ns.inner, ns.clock)
    ma, mb = statistics.median(ta), statistics.median(tb)
    print(f"command: spacearm {' '.join(cli)}  ({ns.clock} clock)")
    print(f"A ({ns.a}): median {ma * 1e3:.1f} ms over {len(ta)} runs (min {min(ta) * 1e3:.1f})")
    print(f"B ({ns.b}): median {mb * 1e3:.1f} ms over {len(tb)} runs (min {min(tb) * 1e3:.1f})")
    print(f"A / B = {ma / mb:.2f}")


if __name__ == "__main__":
    main()
