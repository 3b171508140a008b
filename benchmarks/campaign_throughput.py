"""Campaign throughput by back end: in-process, 1 and 2 threads, 1 and 2 processes, Dask.

    python benchmarks/campaign_throughput.py [--samples 16] [--model spatial6] [--duration 2]

Every configuration runs the same samples (same seed), so the figures compare back ends, not
workloads. Start-up (spawning processes, starting the Dask LocalCluster) is outside the timed
region for Dask but inside it for local processes (a ProcessPoolExecutor is created per
campaign, as run_campaign does for its users). Campaign against native rollouts at equal
threads: benchmarks/campaign.py. The per-sample work is one simulate() call of
`--duration` seconds at RK4 `--dt` under computed torque.
"""

from __future__ import annotations

import argparse
import os
import time

import spacearm
from spacearm.campaign import Scenario, run_campaign


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=16)
    ap.add_argument("--model", default="spatial6")
    ap.add_argument("--duration", type=float, default=2.0)
    ap.add_argument("--dt", type=float, default=1e-3)
    args = ap.parse_args()
    robot = spacearm.presets.get(args.model)
    scenario = Scenario(duration=args.duration, dt=args.dt)
    print(f"{args.samples} samples of {args.model}, {args.duration} s at dt {args.dt} s each; "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}")
    rows = []
    for backend, workers in (("in-process", 0), ("threads", 1), ("threads", 2), ("processes", 1), ("processes", 2)):
        t = time.perf_counter()
        r = run_campaign(robot, args.samples, scenario=scenario, workers=workers, backend=backend, progress=False)
        elapsed = time.perf_counter() - t
        label = "in-process" if workers == 0 else f"{backend}, {workers} worker(s)"
        rows.append((label, r.n_ok, elapsed))
    try:
        import distributed
    except ImportError:
        distributed = None
    if distributed is not None:
        for workers in (1, 2):
            with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                          dashboard_address=None) as cluster, distributed.Client(cluster) as client:
                client.run(lambda: __import__("spacearm"))  # import on every worker before timing
                t = time.perf_counter()
                r = run_campaign(robot, args.samples, scenario=scenario, scheduler=client, progress=False)
                rows.append((f"dask LocalCluster, {workers} worker(s)", r.n_ok, time.perf_counter() - t))
    base = rows[1][1] / rows[1][2]
    print(f"{'back end':<34}{'ok':>4}{'seconds':>10}{'samples/s':>11}{'vs 1 thread':>14}")
    for label, ok, elapsed in rows:
        rate = ok / elapsed
        print(f"{label:<34}{ok:>4}{elapsed:>10.2f}{rate:>11.2f}{rate / base:>14.2f}")


if __name__ == "__main__":
    main()
