"""A batch of samples: the unit of work of every back end (a step of the thread pipeline, a
process-pool task, a Dask task), flown as native rollouts.

A batch goes through three stages, which the thread back end runs on three threads so that the
cores never wait for Python:

1. ``prepare`` (Python): each sample's plant (``plant``), built on the nominal
   model the spec carries; a plant that cannot be built is that sample's failure;
2. ``fly`` (native, GIL released): [`spacearm.rollout`][spacearm.rollout] of every plant under the one
   nominal-model controller, on ``threads`` threads, every step recorded;
3. ``outcomes`` (numpy): the metrics of every run from its records
   (``metrics_from_records``), a failed rollout recorded with its reason.

Each rollout is bit-identical to [`spacearm.simulate`][spacearm.simulate] of the same plant, and the metrics
are computed with the same operations for one run or many, so a batched sample equals the
per-sample reference (``run_sample``) bit for bit, whatever the batch and the
thread count.

``run_batch`` never raises for a failure of a sample itself: each comes back as an outcome
with its message. An exception that escapes it is therefore not the samples' doing, and the back
ends leave the whole batch pending.
"""

from __future__ import annotations

import time
from typing import Dict, List, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from .scenario import METRIC_NAMES, control_model, controller, metrics_from_records, non_finite_message, plant
from .worker import SampleOutcome, failure_message, nominal_robot

__all__ = ["Job", "Prepared", "prepare", "fly", "outcomes", "run_batch", "split_into_batches",
           "record_bytes_per_sample"]

def split_into_batches(indices: Sequence[int], batch_size: int, first: Optional[int] = None) -> List[List[int]]:
    """``indices`` in order, cut into consecutive batches of ``batch_size`` (the last one may be
    shorter). With ``first``, the batches start at that size and double up to ``batch_size``: the
    first batch is flying while the next are prepared, so a small one starts the threads sooner."""
    batches, start, size = [], 0, min(first or batch_size, batch_size)
    while start < len(indices):
        batches.append(list(indices[start:start + size]))
        start += size
        size = min(2 * size, batch_size)
    return batches


#: A sample to fly: its index and its drawn inertia errors.
Job = Tuple[int, Dict[str, float]]


class Prepared(NamedTuple):
    """A batch ready to fly: the samples whose plant was built (with the plants and their initial
    velocities), and the failures of the others (sample → message)."""

    spec: object
    flying: List[Job]
    plants: list
    failed: List[Tuple[Job, str]]
    velocities: Optional[list] = None  # each plant's u0 (None: every plant at rest)


def prepare(spec, indices: Sequence[int]) -> Prepared:
    """Draw the inertia errors of samples ``indices`` of campaign ``spec`` and build their plants."""
    nominal = nominal_robot(spec.model_toml)
    flying, plants, velocities, failed = [], [], [], []
    for index in indices:
        job = (index, spec.draw(index))
        try:
            p = plant(nominal, job[1], spec.scenario.flexibility, spec.scenario.cmg)
            u0 = spec.scenario.initial_velocity(p, job[1])  # a wheel speed beyond the rotors' limit fails here
        except Exception as exc:  # noqa: BLE001 — an invalid plant is the sample's failure
            failed.append((job, failure_message(exc)))
            continue
        plants.append(p)
        velocities.append(u0)
        flying.append(job)
    return Prepared(spec, flying, plants, failed, velocities)


def fly(prepared: Prepared, threads: int, stop=None):
    """``(rollouts, seconds)``: every plant of ``prepared`` flown on ``threads`` threads (GIL
    released), or the failure message shared by every sample when the scenario itself cannot be
    flown (e.g. a goal of the wrong length). ``stop``: a threading.Event that stops the
    rollouts within 0.1 s (the threads back end's, when the campaign ends early)."""
    from ..sim.rollout import rollout

    if not prepared.plants:
        return None, 0.0
    spec = prepared.spec
    nominal = nominal_robot(spec.model_toml)
    start = time.perf_counter()
    try:
        tracker = controller(nominal, spec.scenario)
        x0 = np.stack([spec.scenario.initial_configuration(p) for p in prepared.plants])
        u0 = None if prepared.velocities is None else np.stack(prepared.velocities)
        runs = rollout(control_model(nominal, spec.scenario), spec.scenario.duration, x0, u0, controller=tracker, plants=prepared.plants,
                       mode=spec.scenario.mode, dt=spec.scenario.dt, threads=threads, stop=stop, **spec.scenario.run_options())
    except Exception as exc:  # noqa: BLE001 — the scenario cannot be flown by any sample
        return failure_message(exc), time.perf_counter() - start
    return runs, time.perf_counter() - start


def outcomes(prepared: Prepared, runs, seconds: float, threads: int) -> List[SampleOutcome]:
    """The outcome of every job of ``prepared`` from the rollouts ``runs`` (or the message that
    failed them all). ``seconds``: the batch's wall time, shared out as thread time per sample."""
    result = [SampleOutcome(index, params, None, message, float("nan")) for (index, params), message in prepared.failed]
    if not prepared.flying:
        return result
    per_sample = seconds * min(threads, len(prepared.flying)) / len(prepared.flying)
    if isinstance(runs, str):
        return result + [SampleOutcome(i, p, None, runs, per_sample) for i, p in prepared.flying]
    if runs.ok.any():
        metrics = metrics_from_records(runs["tracking_error"], runs["x"], runs.saturation_count, runs["u"])
    else:  # every rollout failed: there are no records to compute metrics from
        metrics = np.full((len(prepared.flying), len(METRIC_NAMES)), np.nan)
    for k, (index, params) in enumerate(prepared.flying):
        if not runs.ok[k]:
            message = f"{runs.error_class[k]}: {runs.reason[k]}"
        else:
            message = non_finite_message(metrics[k])
        if message:
            result.append(SampleOutcome(index, params, None, message, per_sample))
        else:
            result.append(SampleOutcome(index, params, dict(zip(METRIC_NAMES, metrics[k].tolist())), "", per_sample))
    return result


def run_batch(spec, indices: Sequence[int], threads: int = 1) -> List[SampleOutcome]:
    """Fly samples ``indices`` of campaign ``spec`` on ``threads`` threads: one outcome per sample
    (the failed plants first)."""
    prepared = prepare(spec, indices)
    runs, seconds = fly(prepared, threads)
    return outcomes(prepared, runs, seconds, threads)


def record_bytes_per_sample(spec, nominal: Optional[object] = None) -> int:
    """Bytes of the records one sample's rollout keeps (every step of every record), measured on
    a two-step rollout of the nominal model: what a batch's size is limited by."""
    from ..sim.rollout import rollout

    nominal = nominal if nominal is not None else nominal_robot(spec.model_toml)
    scenario = spec.scenario
    nominal = control_model(nominal, scenario)
    probe = rollout(nominal, 2 * scenario.dt, nominal.neutral_configuration()[None], mode=scenario.mode,
                    dt=scenario.dt, threads=1)
    rows = probe["t"].shape[1]
    per_row = sum(probe[name].nbytes for name in probe.keys) / rows
    steps = int(np.ceil(scenario.duration / scenario.dt - 1e-9)) + 1
    return int(per_row * steps)
