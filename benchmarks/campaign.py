#!/usr/bin/env python
"""Campaign throughput against the native rollouts it is made of, at equal threads.

For each thread count T, two candidates fly the same samples (same seed, same plants, the same
computed-torque manoeuvre on the nominal model, every step recorded):

- ``native``: :func:`spacearm.rollout` on T threads over the prepared plants, in calls of the
  campaign's batch size (the same record memory per call), back to back: the floor a campaign
  cannot beat (the plants are built before the clock starts);
- ``campaign``: :func:`spacearm.campaign.run_campaign` with ``workers=T`` writing its result
  file, everything included: drawing the parameters, building every plant, the rollouts, the
  metrics, recording, checkpoints and the final file.

Each figure is samples per second, the median over ``--repeat`` rounds; in each round every
candidate runs once at every thread count (interleaved, so a slow phase of the machine hits all
alike). ``ratio`` = campaign / native throughput (1 = no overhead); ``scaling`` = throughput
against the same candidate at the first thread count; ``overhead`` = the campaign's extra wall
time per sample, in thread-milliseconds (T × the difference of the per-sample wall times).

    python benchmarks/campaign.py                              # spatial6, 256 samples, threads 1,2 (< 60 s)
    python benchmarks/campaign.py --threads 1,2,4,8,16         # on a 16-core machine
    python benchmarks/campaign.py --model planar4 --samples 64 --duration 1

Needs numpy and spacearm only (no Dask, no peers).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm.campaign import Perturbations, Scenario, run_campaign  # noqa: E402
from spacearm.campaign.scenario import controller, plant  # noqa: E402


def native_rollouts(robot, scenario: Scenario, plants, threads: int, batch: int) -> float:
    """Seconds of :func:`spacearm.rollout` of every plant on ``threads`` threads, ``batch`` plants a
    call, back to back (the campaign's batch size: the same record memory per call)."""
    tracker = controller(robot, scenario)
    x0 = np.stack([p.neutral_configuration() for p in plants])
    start = time.perf_counter()
    for i in range(0, len(plants), batch):
        runs = spacearm.rollout(robot, scenario.duration, x0[i:i + batch], controller=tracker,
                                plants=plants[i:i + batch], mode=scenario.mode, dt=scenario.dt, threads=threads)
        if not runs.ok.all():
            raise SystemExit(f"benchmark scenario broken: {sum(~runs.ok)} rollouts failed: {runs.reason[:3]}")
    return time.perf_counter() - start


def campaign(robot, scenario: Scenario, perturbations: Perturbations, samples: int, threads: int, out: Path) -> float:
    """Seconds of one whole campaign on ``threads`` threads, written to ``out``."""
    start = time.perf_counter()
    result = run_campaign(robot, samples, seed=0, perturbations=perturbations, scenario=scenario, workers=threads,
                          out=out, resume=False, progress=False)
    elapsed = time.perf_counter() - start
    if result.n_ok != samples:
        raise SystemExit(f"benchmark scenario broken: {result.n_failed} samples failed: {result.failures()}")
    return elapsed


def python_cost(robot, scenario: Scenario, perturbations: Perturbations, samples: int):
    """CPU seconds per sample of the campaign's Python stages (drawing and building the plants;
    metrics and recording) and of the native rollout, measured with CPU clocks so that a busy
    machine does not inflate them. The Python stages share one GIL: with T threads the campaign
    keeps up with the native work while T × python < native."""
    from spacearm.campaign import CampaignSpec, CampaignResult
    from spacearm.campaign.batch import fly, outcomes, prepare
    from spacearm.io.model_file import dumps_toml

    spec = CampaignSpec(dumps_toml(robot), samples, 0, perturbations, scenario)
    indices = list(range(samples))
    t = time.thread_time()
    prepared = prepare(spec, indices)
    t_prepare = time.thread_time() - t
    t = time.process_time()
    runs, seconds = fly(prepared, 1)
    t_native = time.process_time() - t
    t = time.thread_time()
    done = outcomes(prepared, runs, seconds, 1)
    result = CampaignResult(spec.to_json(), list(done[0].params), list(done[0].metrics), samples)
    for o in done:
        result.record(o.index, o.params, o.metrics, o.error, o.seconds)
    t_outcomes = time.thread_time() - t
    return t_prepare / samples, t_outcomes / samples, t_native / samples


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--model", default="spatial6", help="preset (default spatial6)")
    ap.add_argument("--samples", type=int, default=256, help="samples per campaign (default 256)")
    ap.add_argument("--duration", type=float, default=2.0, help="manoeuvre duration, s (default 2)")
    ap.add_argument("--dt", type=float, default=2e-3, help="RK4 step, s (default 0.002)")
    ap.add_argument("--threads", default="1,2", help="comma-separated thread counts (default 1,2)")
    ap.add_argument("--repeat", type=int, default=3, help="rounds (default 3)")
    ap.add_argument("--payload-mass-max", type=float, default=10.0,
                    help="payload up to this mass, kg (default 10; 0 = none: plants need no model rebuild)")
    args = ap.parse_args()
    threads = [int(t) for t in args.threads.split(",")]

    robot = spacearm.presets.get(args.model)
    scenario = Scenario(duration=args.duration, dt=args.dt)
    perturbations = Perturbations(payload_mass_max=args.payload_mass_max)
    plants = [plant(robot, perturbations.draw(0, i)) for i in range(args.samples)]
    steps = int(round(args.duration / args.dt))
    print(f"{args.model}: {args.samples} samples of {args.duration:g} s at dt {args.dt:g} s ({steps} RK4 steps, "
          f"computed torque, every step recorded); {os.cpu_count()} CPUs, load {os.getloadavg()[0]:.2f}; "
          f"Python {platform.python_version()}, numpy {np.__version__}")

    prep, outc, native = python_cost(robot, scenario, perturbations, min(args.samples, 64))
    print(f"CPU per sample: Python {1e3 * (prep + outc):.3f} ms (draw + plant {1e3 * prep:.3f}, metrics + record "
          f"{1e3 * outc:.3f}) against native rollout {1e3 * native:.2f} ms: the one GIL keeps up with up to "
          f"{native / (prep + outc):.0f} threads")

    from spacearm.campaign import CampaignSpec
    from spacearm.campaign.batch import record_bytes_per_sample
    from spacearm.campaign.local import samples_per_batch
    from spacearm.io.model_file import dumps_toml

    record_bytes = record_bytes_per_sample(CampaignSpec(dumps_toml(robot), 1, 0, perturbations, scenario))
    batch = {t: samples_per_batch("threads", t, args.samples, record_bytes) for t in threads}
    print(f"records {record_bytes / 2**20:.2f} MiB a sample; batch sizes {batch}")

    times = {(kind, t): [] for kind in ("native", "campaign") for t in threads}
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "campaign.npz"
        for _ in range(args.repeat):
            for t in threads:
                times["native", t].append(native_rollouts(robot, scenario, plants, t, batch[t]))
                times["campaign", t].append(campaign(robot, scenario, perturbations, args.samples, t, out))

    rate = {key: args.samples / statistics.median(v) for key, v in times.items()}
    print(f"\nsamples/s, median of {args.repeat} rounds")
    print(f"{'threads':>7}  {'native':>9}  {'campaign':>9}  {'ratio':>6}  {'native scaling':>14}  "
          f"{'campaign scaling':>16}  {'overhead ms/sample':>18}")
    base = threads[0]
    for t in threads:
        native, camp = rate["native", t], rate["campaign", t]
        overhead_ms = t * (1 / camp - 1 / native) * 1e3
        print(f"{t:>7}  {native:>9.1f}  {camp:>9.1f}  {camp / native:>6.2f}  {native / rate['native', base]:>13.2f}x"
              f"  {camp / rate['campaign', base]:>15.2f}x  {overhead_ms:>18.2f}")


if __name__ == "__main__":
    main()
