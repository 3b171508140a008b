#!/usr/bin/env python
"""Instructions per call of two builds of spacearm, counted by callgrind: the deterministic
complement of ``compare_builds.py`` where the machine is too noisy for wall-clock ratios.

Wall-clock timing on a shared or small machine moves by 5-90 % from run to run; the number
of instructions a call executes does not: one build gives the same count to the instruction
run after run. Between two builds the criterion rows compare to about 2 % (the iteration count
of a profiled run varies, and the set-up is spread over it); the Python rows also move by a few
percent with incidental effects of memory layout in the interpreter and numpy's allocator (one call read 0.93 in this script and 1.05 in another harness), so read
them to about ±5 %. A change that makes a call do more work shows here even when timings cannot
resolve it. It says nothing about cache misses or branch prediction (callgrind's
``--cache-sim=yes --branch-sim=yes`` models them), so it complements timing on a quiet machine
and does not replace it.

Two kinds of rows:

- **Python**: the calls ``benchmarks/peers.py`` times (the same models, states and callables,
  taken from that script with the peers left out), each run 100 and then 1,100 times in a fresh
  interpreter under callgrind; the difference over 1,000 is the per-call count, free of
  start-up;
- **criterion**: each named benchmark of the criterion executables of both builds, run under
  callgrind with ``--profile-time 1``; the count is the inclusive cost of criterion's
  ``Bencher::iter`` over the number of calls of its costliest callee (the routine measured).

    python benchmarks/instructions.py --a before/python --b after/python --ops H,c \\
        --criterion-a before/dynamics --criterion-b after/dynamics \\
        --benches spatial6/H_crba spatial6/forward_dynamics_aba

Needs ``valgrind`` (Debian: ``apt install valgrind``) and, for the criterion rows,
``callgrind_annotate`` (in the same package). Each Python row takes ~20 s, each criterion row
~3 s. ``--json PATH`` also writes the figures.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
WARM, FEW, MANY = 50, 100, 1100

# Runs in the child interpreter: peers.py's spacearm candidates, the peers blocked (setting a
# module to None in sys.modules makes its import raise ImportError, which peers.py expects).
CHILD = r"""
import sys
sys.modules["pinocchio"] = None
sys.modules["mujoco"] = None
sys.path.insert(0, {here!r})
import peers
robot = peers.MODELS[{model!r}]()
x, u, du, f = peers.state(robot)
calls = {{op: fn for op, engine, _variant, fn, _ref in peers.spacearm_candidates(robot, x, u, du, f)}}
fn = calls[{op!r}]
for _ in range({warm}):
    fn()
for _ in range({count}):
    fn()
"""


def _callgrind(cmd: list, env: dict) -> str:
    """Run ``cmd`` under callgrind; the path of its output file (in a temporary directory the
    caller removes)."""
    out = Path(tempfile.mkdtemp(prefix="spacearm-cg-")) / "callgrind.out"
    proc = subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", *cmd],
                          env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if proc.returncode != 0 or not out.exists():
        raise SystemExit(f"callgrind failed on {' '.join(cmd)} (exit {proc.returncode}):\n{proc.stderr[-2000:]}")
    return str(out)


def _total(path: str) -> int:
    for line in Path(path).read_text().splitlines():
        if line.startswith("totals:") or line.startswith("summary:"):
            return int(line.split()[1])
    raise SystemExit(f"no instruction total in {path}")


def _cleanup(path: str) -> None:
    shutil.rmtree(Path(path).parent, ignore_errors=True)


def python_per_call(package_dir: str, model: str, op: str) -> float:
    """Instructions per call of peers.py's spacearm ``op`` on ``model`` with the build in
    ``package_dir``."""
    env = dict(os.environ, PYTHONPATH=str(Path(package_dir).resolve()), PYTHONHASHSEED="0",
               OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    totals = []
    for count in (FEW, MANY):
        code = CHILD.format(here=str(HERE), model=model, op=op, warm=WARM, count=count)
        path = _callgrind([sys.executable, "-c", code], env)
        totals.append(_total(path))
        _cleanup(path)
    return (totals[1] - totals[0]) / (MANY - FEW)


ITER_SELF = re.compile(r"\s*([\d,]+) \([^)]*\)\s+\*\s+\S*criterion::bencher::Bencher<M>::iter")
ITER_CALLEE = re.compile(r"\s*([\d,]+) \([^)]*\)\s+<\s+\S*criterion::bencher::Bencher<M>::iter \(([\d,]+)x\)")


def criterion_per_call(executable: str, bench: str) -> float:
    """Instructions per iteration of one criterion benchmark (see the module documentation)."""
    path = _callgrind([str(Path(executable).resolve()), "--bench", "--profile-time", "1", f"^{re.escape(bench)}$"],
                      dict(os.environ))
    text = subprocess.run(["callgrind_annotate", "--tree=caller", "--inclusive=yes", path],
                          capture_output=True, text=True).stdout
    _cleanup(path)
    inclusive, calls, costliest = None, 0, 0
    for line in text.splitlines():
        m = ITER_SELF.match(line)
        if m:
            inclusive = int(m.group(1).replace(",", ""))
        m = ITER_CALLEE.match(line)
        if m and int(m.group(1).replace(",", "")) > costliest:
            costliest, calls = int(m.group(1).replace(",", "")), int(m.group(2).replace(",", ""))
    if not inclusive or not calls:
        raise SystemExit(f"{bench}: no criterion iterations found in {executable} (is the name right? --list shows them)")
    return inclusive / calls


def _row(name: str, a: float, b: float, rows: list) -> None:
    rows.append({"row": name, "a": a, "b": b, "ratio": b / a})
    print(f"{name:44s} {a:10.0f} {b:10.0f} {b / a:7.3f}", flush=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--a", help="build A: the python/ directory holding spacearm (e.g. before a change)")
    ap.add_argument("--b", help="build B: the python/ directory holding spacearm (e.g. after)")
    ap.add_argument("--models", default="spatial6,planar4,random12", help="peers.py models (default all three)")
    ap.add_argument("--ops", default="", help="peers.py operations, comma-separated (default: all of them)")
    ap.add_argument("--criterion-a", nargs="*", default=[], help="criterion executables of build A")
    ap.add_argument("--criterion-b", nargs="*", default=[], help="criterion executables of build B, in the same order")
    ap.add_argument("--benches", nargs="*", default=[], help="criterion benchmark ids (e.g. spatial6/H_crba)")
    ap.add_argument("--json", metavar="PATH", help="also write the figures here")
    args = ap.parse_args(argv)
    if shutil.which("valgrind") is None:
        print("instructions.py: error: valgrind is not installed (Debian: apt install valgrind)", file=sys.stderr)
        return 2
    if bool(args.a) != bool(args.b) or len(args.criterion_a) != len(args.criterion_b) or (args.benches and not args.criterion_a):
        print("instructions.py: error: give --a with --b, and --criterion-a and --criterion-b (same length) with --benches",
              file=sys.stderr)
        return 2
    rows: list = []
    print(f"{'':44s} {'A instr':>10s} {'B instr':>10s} {'B/A':>7s}")
    if args.a:
        sys.modules["pinocchio"] = None  # the list of operations, without importing the peers
        sys.modules["mujoco"] = None
        sys.path.insert(0, str(HERE))
        import peers
        for model in args.models.split(","):
            ops = [o for o in args.ops.split(",") if o]
            if not ops:
                robot = peers.MODELS[model]()
                ops = [op for op, *_ in peers.spacearm_candidates(robot, *peers.state(robot))]
            for op in ops:
                _row(f"python {model} / {op}", python_per_call(args.a, model, op), python_per_call(args.b, model, op), rows)
    for exe_a, exe_b in zip(args.criterion_a, args.criterion_b):
        listed = subprocess.run([str(Path(exe_b).resolve()), "--bench", "--list"], capture_output=True, text=True).stdout
        held = {line.split(": ")[0] for line in listed.splitlines() if line.endswith(": benchmark")}
        for bench in [b for b in args.benches if b in held]:
            _row(f"criterion {bench}", criterion_per_call(exe_a, bench), criterion_per_call(exe_b, bench), rows)
    if rows:
        ratios = [r["ratio"] for r in rows]
        print(f"median B/A over {len(ratios)} rows: {statistics.median(ratios):.3f} (min {min(ratios):.3f}, max {max(ratios):.3f})")
    if args.json:
        Path(args.json).write_text(json.dumps({"a": args.a, "b": args.b, "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
