#!/usr/bin/env python
"""Time two builds of spacearm against each other, interleaved: is a change slower per call?

Each build is a Python package directory (the ``python/`` folder holding ``spacearm`` with its
compiled ``_core``) and, optionally, criterion benchmark executables of the Rust core built from
the same commit (``cargo bench -p spacearm-core --no-run`` prints their paths). The two builds
run alternately, ``--rounds`` times each (A B A B ...), so a slow phase of the machine hits both:

- ``benchmarks/peers.py`` (this script's sibling, the same script for both builds) times every
  call from Python; per row, the median over rounds of each round's median;
- every criterion benchmark that both builds have, with ``--output-format bencher``.

The table gives both medians, the ratio B/A and the spread of A's own rounds (max/min − 1): a
ratio inside that spread is noise, not a change.

    python benchmarks/compare_builds.py --a before/python --b after/python --rounds 3 \\
        --criterion-a before/dynamics --criterion-b after/dynamics

The build's directory is put first on ``PYTHONPATH`` of a fresh interpreter for each run;
``--pin CPU`` runs every measurement on that one CPU (``taskset``), ``--peers-args`` is passed to
peers.py (default ``--models spatial6,planar4,random12``).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
BENCHER_LINE = re.compile(r"^test (\S+)\s+\.\.\. bench:\s+([\d,]+(?:\.\d+)?) ns/iter")


def _prefix(pin):
    return ["taskset", "-c", str(pin)] if pin is not None and shutil.which("taskset") else []


def run_peers(package_dir: str, peers_args: list, pin) -> dict:
    """One peers.py run on one build: {(model, op): median seconds of spacearm's call}."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "peers.json"
        env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(Path(package_dir).resolve()), os.environ.get("PYTHONPATH", "")]))
        cmd = _prefix(pin) + [sys.executable, str(HERE / "peers.py"), *peers_args, "--json", str(out)]
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
        if proc.returncode != 0 or not out.exists():
            raise SystemExit(f"peers.py failed on {package_dir} (exit {proc.returncode}):\n{proc.stderr[-3000:]}")
        rows = json.loads(out.read_text())["results"]
    best = {}
    for r in rows:
        if r["engine"] == "spacearm":
            key = (r["model"], r["op"])
            best[key] = min(best.get(key, float("inf")), r["median_s"])
    return best


def run_criterion(binaries: list, criterion_args: list, pin) -> dict:
    """One run of each criterion executable: {benchmark id: ns per iteration}."""
    found = {}
    for exe in binaries:
        cmd = _prefix(pin) + [str(Path(exe).resolve()), "--bench", "--output-format", "bencher", *criterion_args]
        proc = subprocess.run(cmd, capture_output=True, text=True, cwd=tempfile.gettempdir())
        if proc.returncode != 0:
            raise SystemExit(f"{exe} failed (exit {proc.returncode}):\n{proc.stderr[-3000:]}")
        for line in proc.stdout.splitlines():
            m = BENCHER_LINE.match(line.strip())
            if m:
                found[m.group(1)] = float(m.group(2).replace(",", ""))
    return found


def summarize(rounds_a: list, rounds_b: list):
    """Per key both builds have: (median A, median B, B/A, spread of A's rounds)."""
    keys = [k for k in rounds_a[0] if all(k in r for r in rounds_a + rounds_b)]
    out = []
    for k in keys:
        a = [r[k] for r in rounds_a]
        b = [r[k] for r in rounds_b]
        ma, mb = statistics.median(a), statistics.median(b)
        out.append((k, ma, mb, mb / ma, max(a) / min(a) - 1.0))
    return out


def print_table(title: str, unit: str, scale: float, rows) -> None:
    print(f"\n{title}")
    print(f"{'':44s} {'A ' + unit:>12s} {'B ' + unit:>12s} {'B/A':>6s} {'A spread':>9s}")
    for key, ma, mb, ratio, spread in rows:
        name = " / ".join(key) if isinstance(key, tuple) else key
        flag = "  <- slower beyond A's spread" if ratio - 1.0 > max(spread, 0.02) else ""
        print(f"{name:44s} {ma * scale:12.3f} {mb * scale:12.3f} {ratio:6.3f} {spread * 100:8.1f}%{flag}")
    ratios = [r[3] for r in rows]
    if ratios:
        print(f"median B/A over {len(ratios)} rows: {statistics.median(ratios):.3f} (min {min(ratios):.3f}, max {max(ratios):.3f})")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--a", required=True, help="build A: the python/ directory holding spacearm (e.g. before a change)")
    ap.add_argument("--b", required=True, help="build B: the python/ directory holding spacearm (e.g. after)")
    ap.add_argument("--rounds", type=int, default=3, help="runs of each build, alternating (default 3)")
    ap.add_argument("--peers-args", default="--models spatial6,planar4,random12", help="arguments for peers.py")
    ap.add_argument("--no-peers", action="store_true", help="skip peers.py (criterion only)")
    ap.add_argument("--criterion-a", nargs="*", default=[], help="criterion executables of build A")
    ap.add_argument("--criterion-b", nargs="*", default=[], help="criterion executables of build B (same benches)")
    ap.add_argument("--criterion-args", default="--warm-up-time 0.5 --measurement-time 1", help="arguments for each criterion run")
    ap.add_argument("--pin", type=int, default=None, help="run every measurement on this CPU (taskset)")
    ap.add_argument("--json", metavar="PATH", help="also write every round's figures here")
    args = ap.parse_args(argv)
    if args.rounds < 1:
        ap.error("--rounds must be at least 1")
    if len(args.criterion_a) != len(args.criterion_b):
        ap.error("give as many --criterion-b executables as --criterion-a, in the same order")
    for exe in args.criterion_a + args.criterion_b:
        if not os.access(exe, os.X_OK):
            ap.error(f"{exe} is not an executable file")
    for d in (args.a, args.b):
        if not (Path(d) / "spacearm" / "__init__.py").exists():
            ap.error(f"{d} does not hold the spacearm package (expected {d}/spacearm/__init__.py)")

    peers_args = shlex.split(args.peers_args)
    crit_args = shlex.split(args.criterion_args)
    record = {"peers": {"a": [], "b": []}, "criterion": {"a": [], "b": []}}
    for i in range(args.rounds):
        for build, pkg, exes in (("a", args.a, args.criterion_a), ("b", args.b, args.criterion_b)):
            print(f"round {i + 1}/{args.rounds}: build {build.upper()}", file=sys.stderr, flush=True)
            if not args.no_peers:
                record["peers"][build].append(run_peers(pkg, peers_args, args.pin))
            if exes:
                record["criterion"][build].append(run_criterion(exes, crit_args, args.pin))

    print(f"A = {args.a}\nB = {args.b}\n{args.rounds} rounds each, alternating; pinned to CPU {args.pin}; "
          f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs at the end")
    if not args.no_peers:
        print_table("peers.py, spacearm's call from Python (µs, median of the rounds' medians)", "µs", 1e6,
                    summarize(record["peers"]["a"], record["peers"]["b"]))
    if args.criterion_a:
        print_table("criterion, the Rust core (ns per iteration)", "ns", 1.0,
                    summarize(record["criterion"]["a"], record["criterion"]["b"]))
    if args.json:
        serial = {kind: {b: [{" / ".join(k) if isinstance(k, tuple) else k: v for k, v in r.items()} for r in runs]
                         for b, runs in d.items()} for kind, d in record.items()}
        tmp = args.json + ".tmp"
        with open(tmp, "w") as fh:
            json.dump({"a": args.a, "b": args.b, "rounds": args.rounds, "figures": serial}, fh, indent=1)
        os.replace(tmp, args.json)
        print(f"wrote {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
