#!/usr/bin/env python
"""Time spacearm's exact derivatives against Pinocchio's ``computeABADerivatives``, from Python,
on the same models, in one run.

Every figure is the time of ONE call as a Python user makes it (argument conversion, the
computation, the result arrays), the median over interleaved batches (see ``peers.py``). The
ratio column is spacearm / Pinocchio: below 1 means spacearm is faster.

Before timing, Pinocchio's results are mapped to spacearm's conventions with
:func:`spacearm.interop.aba_derivatives_from_pinocchio` and compared with spacearm's (the
``check`` column: max relative difference), so the table compares calls that compute the same
quantity. Rows:

- ``forward dynamics``: ``Robot.forward_dynamics`` (ABA) vs ``pin.aba``: the cost of one
  evaluation, for scale;
- ``FD derivatives``: ``Robot.forward_dynamics_derivatives(x, u, f)`` (∂u̇/∂x, ∂u̇/∂u, H⁻¹)
  vs ``pin.computeABADerivatives(model, data, q, v, tau)`` (ddq_dq, ddq_dv, Minv);
- ``linearize``: ``Robot.linearize(x, u, f)`` (A, B for the joint torques) — no Pinocchio
  equivalent (its ABA derivatives plus assembly), timed for scale;
- ``dH/dx``, ``Hdot``: ``Robot.mass_matrix_partials(x)`` ((6+N)³) and
  ``Robot.mass_matrix_derivative(x, u)`` — no Pinocchio equivalent in its Python API.

    python benchmarks/derivatives.py                    # spatial6, random12
    python benchmarks/derivatives.py --quick --json derivatives.json
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402

import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm import interop  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peers import MODELS, meta, rel_diff, state, time_interleaved  # noqa: E402

try:
    import pinocchio as pin
except ImportError:  # pragma: no cover - optional peer
    pin = None


def candidates(robot, x, u, f):
    """(row, engine, timed callable, result in spacearm's conventions)."""
    r = robot
    yield "forward dynamics", "spacearm", lambda: r.forward_dynamics(x, u, f), lambda: r.forward_dynamics(x, u, f)
    yield "FD derivatives", "spacearm", lambda: r.forward_dynamics_derivatives(x, u, f), lambda: r.forward_dynamics_derivatives(x, u, f)
    yield "linearize", "spacearm", lambda: r.linearize(x, u, f), None
    yield "dH/dx", "spacearm", lambda: r.mass_matrix_partials(x), None
    yield "Hdot", "spacearm", lambda: r.mass_matrix_derivative(x, u), None
    if pin is None:
        return
    model = interop.to_pinocchio(r)
    data = model.createData()
    q, v = interop.to_pinocchio_state(r, x, u)
    tau = interop.to_pinocchio_force(r, x, f)
    yield ("forward dynamics", "pinocchio", lambda: pin.aba(model, data, q, v, tau),
           lambda: interop.acceleration_from_pinocchio(r, x, u, pin.aba(model, data, q, v, tau)))

    def mapped():
        pin.computeABADerivatives(model, data, q, v, tau)
        return interop.aba_derivatives_from_pinocchio(r, x, u, f, data.ddq_dq, data.ddq_dv, data.Minv, data.ddq)

    yield "FD derivatives", "pinocchio", lambda: pin.computeABADerivatives(model, data, q, v, tau), mapped


def run_model(name, repeat, batch):
    robot = MODELS[name]()
    x, u, _, f = state(robot)
    # Displace the joints: the presets' initial angles are zero, where many terms vanish.
    x = x.copy()
    x[7:] += 0.4 * np.sin(0.7 + np.arange(robot.n_dof))
    cands = list(candidates(robot, x, u, f))
    reference = {"forward dynamics": robot.forward_dynamics(x, u, f), "FD derivatives": robot.forward_dynamics_derivatives(x, u, f)}
    samples, numbers = time_interleaved([c[2] for c in cands], repeat, batch)
    rows = []
    for (op, engine, _, result), s, number in zip(cands, samples, numbers):
        check = None
        if result is not None and op in reference:
            got, ref = result(), reference[op]
            check = max(rel_diff(a, b) for a, b in zip(got, ref)) if isinstance(got, tuple) else rel_diff(got, ref)
        rows.append({"model": name, "n_dof": robot.n_dof, "op": op, "engine": engine, "median_s": float(np.median(s)),
                     "min_s": float(np.min(s)), "calls_per_batch": number, "check": check})
    return robot, rows


def print_table(robot, rows, out=sys.stdout):
    print(f"\n{robot.name}: N = {robot.n_dof}, {robot.n_bodies} bodies (median µs per call)", file=out)
    print(f"  {'':18s} {'spacearm':>10s} {'pinocchio':>10s} {'ratio':>7s} {'check':>9s}", file=out)
    for op in dict.fromkeys(r["op"] for r in rows):
        s = next(r for r in rows if r["op"] == op and r["engine"] == "spacearm")
        p = next((r for r in rows if r["op"] == op and r["engine"] == "pinocchio"), None)
        pt = f"{p['median_s'] * 1e6:10.2f}" if p else f"{'—':>10s}"
        ratio = f"{s['median_s'] / p['median_s']:7.2f}" if p else f"{'':7s}"
        check = f"{p['check']:9.1e}" if p and p["check"] is not None else ""
        print(f"  {op:18s} {s['median_s'] * 1e6:10.2f} {pt} {ratio} {check}", file=out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--models", default="spatial6,random12", help=f"comma-separated, from {', '.join(MODELS)}")
    ap.add_argument("--repeat", type=int, default=15, help="interleaved rounds, default 15")
    ap.add_argument("--batch", type=float, default=0.02, help="seconds per batch, default 0.02")
    ap.add_argument("--quick", action="store_true", help="5 rounds of 5 ms batches (a rough look)")
    ap.add_argument("--json", metavar="PATH", help="also write every measurement and its context here")
    args = ap.parse_args(argv)
    if args.quick:
        args.repeat, args.batch = 5, 0.005
    names = [m.strip() for m in args.models.split(",") if m.strip()]
    unknown = [m for m in names if m not in MODELS]
    if unknown:
        ap.error(f"unknown model(s) {unknown}; choose from {list(MODELS)}")
    if pin is None:
        print("note: pinocchio is not installed; its column is left out", file=sys.stderr)
    all_rows = []
    for name in names:
        robot, rows = run_model(name, args.repeat, args.batch)
        print_table(robot, rows)
        all_rows += rows
    print("\n  ratio: spacearm / pinocchio (below 1: spacearm faster). check: max relative difference of")
    print("  Pinocchio's result mapped by spacearm.interop.aba_derivatives_from_pinocchio from spacearm's.")
    if hasattr(os, "getloadavg"):
        print(f"  Load average at the end (1 min): {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs.")
    bad = [r for r in all_rows if r["check"] is not None and r["check"] > 1e-9]
    for r in bad:
        print(f"WARNING: {r['model']} {r['op']} {r['engine']}: results differ by {r['check']:.1e}", file=sys.stderr)
    if args.json:
        m = meta(args, ["spacearm"] + (["pinocchio"] if pin else []), None)
        with open(args.json + ".tmp", "w") as fh:
            json.dump({"meta": m, "results": all_rows}, fh, indent=1)
        os.replace(args.json + ".tmp", args.json)
        print(f"wrote {args.json}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
