#!/usr/bin/env python
"""Time spacearm's joint-space singularity scan against the same computation with Pinocchio, in
one run: for every sample q, σ_min (and the whole SVD) of the task rows of J* and of J_m.

spacearm: one call of ``spacearm.analysis.scan`` (Rust, rayon over the samples, GIL released).
Pinocchio: a Python loop per sample — ``crba``, ``computeJointJacobians``, ``getFrameJacobian``,
``J* = J_m + J_b (−M_bb⁻¹ M_bm)`` and ``numpy.linalg.svd`` — the loop a user would write without
spacearm. Before timing, both σ_min are compared (``check``: max relative difference).

Figures: median over ``--repeat`` rounds of the time per sample, and samples per second; the
ratio is spacearm / Pinocchio (below 1: spacearm is faster). The machine's other load shows in
the load average printed at the top.

    python benchmarks/analysis_scan.py                 # planar4 and spatial6, 20,000 samples
    python benchmarks/analysis_scan.py --samples 5000 --repeat 3
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm import analysis, interop  # noqa: E402


def pin_scan(robot, samples, rows):
    import pinocchio as pin

    model = interop.to_pinocchio(robot)
    data = model.createData()
    order = interop.engine_dof_order(robot)
    fid = model.getFrameId(robot.end_effector)
    out = np.empty((samples.shape[0], 2))
    for k, q in enumerate(samples):
        qp, _ = interop.to_pinocchio_state(robot, robot.neutral_configuration(q=q), np.zeros(robot.nu))
        m = pin.crba(model, data, qp)
        m = np.triu(m) + np.triu(m, 1).T
        pin.computeJointJacobians(model, data, qp)
        pin.updateFramePlacements(model, data)
        jac = pin.getFrameJacobian(model, data, fid, pin.LOCAL_WORLD_ALIGNED)
        jstar = jac[:, 6:] - jac[:, :6] @ np.linalg.solve(m[:6, :6], m[:6, 6:])
        cols = np.empty_like(jstar)
        cols[:, order] = jstar
        jm = np.empty_like(jstar)
        jm[:, order] = jac[:, 6:]
        out[k, 0] = np.linalg.svd(cols[rows], compute_uv=False)[-1]
        out[k, 1] = np.linalg.svd(jm[rows], compute_uv=False)[-1]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", default="planar4,spatial6")
    ap.add_argument("--samples", type=int, default=20000, help="samples per spacearm scan")
    ap.add_argument("--pin-samples", type=int, default=2000, help="samples per Pinocchio loop (it is slow)")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    print(f"load average {os.getloadavg()}, cpus {os.cpu_count()}")
    print(f"{'model':10s} {'task':>12s} {'spacearm us/sample':>20s} {'samples/s':>12s} {'pinocchio us/sample':>20s} {'samples/s':>12s} "
          f"{'ratio':>8s} {'check':>9s}")
    for name in args.models.split(","):
        robot = spacearm.presets.get(name)
        rows = analysis.task_rows(robot, "planar" if name == "planar4" else "full")
        rng = np.random.default_rng(0)
        q = rng.uniform(-np.pi, np.pi, size=(args.samples, robot.n_dof))
        qp = q[: args.pin_samples]
        ref = pin_scan(robot, qp[:200], rows)
        mine = analysis.scan(robot, qp[:200], task=rows)
        check = max(np.max(np.abs(mine["sigma_min_generalized"] - ref[:, 0]) / np.max(ref[:, 0])),
                    np.max(np.abs(mine["sigma_min_fixed"] - ref[:, 1]) / np.max(ref[:, 1])))
        t_sa, t_pin = [], []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            analysis.scan(robot, q, task=rows)
            t_sa.append((time.perf_counter() - t0) / q.shape[0])
            t0 = time.perf_counter()
            pin_scan(robot, qp, rows)
            t_pin.append((time.perf_counter() - t0) / qp.shape[0])
        a, b = statistics.median(t_sa), statistics.median(t_pin)
        print(f"{name:10s} {str(rows):>12s} {a * 1e6:20.3f} {1 / a:12.0f} {b * 1e6:20.3f} {1 / b:12.0f} {a / b:8.4f} {check:9.1e}")


if __name__ == "__main__":
    main()
