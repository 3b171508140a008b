"""Running a campaign: local processes by default, a Dask cluster when given its scheduler.

Samples are independent, so both back ends simply map :func:`~.worker.run_sample` over the
pending indices and collect outcomes as they complete (in any order; each is stored at its
index, so the file does not depend on scheduling). The parent draws every sample's parameters
(:meth:`Perturbations.draw`), keeps the :class:`~.results.CampaignResult`, writes it atomically
every ``checkpoint_seconds`` and at the end (also on Ctrl-C), and shows a progress bar.

- ``backend="processes"`` (default): :class:`concurrent.futures.ProcessPoolExecutor` with the
  ``spawn`` start method (no inherited threads or Rust state), ``workers`` processes
  (default: the CPU count).
- ``scheduler="tcp://host:8786"`` (or a ``distributed.Client``): Dask's ``client.map`` and
  ``as_completed`` on an existing cluster (``pip install "dask[distributed]"``); each worker needs
  spacearm installed.
- ``workers=0``: run in this process (debugging, profiling).

Failures are sorted by where they happen. :func:`~.worker.run_sample` returns every failure of
the sample itself (an invalid plant, a singular matrix, a diverged state) as an outcome, which is
recorded as failed. So anything the back end raises instead — a broken process pool, a worker
or scheduler lost, a task that could not be sent — is a failure of the infrastructure, not of
the sample: the sample is left pending (a rerun runs it), and once the outcomes that did arrive
are recorded and saved, the campaign raises one :class:`~spacearm.errors.CampaignError` saying
how many samples did not run and why.
"""

from __future__ import annotations

import asyncio
import multiprocessing
import os
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Callable, Iterable, Iterator, NamedTuple, Optional, Union

from ..errors import ArgumentError, CampaignError
from ._main_guard import GUARD_ADVICE, check_caller_is_guarded, stop_if_reimported_by_a_worker
from .perturbation import PARAMETER_NAMES, Perturbations
from .results import FAILED, PENDING, CampaignResult
from .scenario import METRIC_NAMES, Scenario
from .spec import CampaignSpec
from .worker import SampleOutcome, run_sample

__all__ = ["run_campaign", "CampaignSpec"]


def _progress(total: int, initial: int, enabled: Union[bool, Callable[[int, int], None]]):
    """A tqdm bar (``enabled=True``), a user callback ``fn(done, total)``, or nothing."""
    if callable(enabled):
        class _Callback:
            def __init__(self):
                self.done = initial

            def update(self, k=1):
                self.done += k
                enabled(self.done, total)

            def close(self):
                pass

        return _Callback()
    if enabled:
        from tqdm import tqdm

        return tqdm(total=total, initial=initial, unit="sample", desc="campaign", dynamic_ncols=True)

    class _Silent:
        def update(self, k=1):
            pass

        def close(self):
            pass

    return _Silent()


class LostSample(NamedTuple):
    """A sample the back end could not run, for a reason outside the sample (see the module docs)."""

    index: int
    reason: str


def _describe(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {exc}" if str(exc) else type(exc).__name__


def _local_outcomes(spec: CampaignSpec, jobs, workers: int) -> Iterator[Union[SampleOutcome, LostSample]]:
    if workers == 0:
        for index, params in jobs:
            yield run_sample(spec, index, params)
        return
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        futures = {pool.submit(run_sample, spec, index, params): index for index, params in jobs}
        try:
            for future in as_completed(futures):
                try:
                    outcome = future.result()
                except Exception as exc:  # the pool broke (a worker died or could not start)
                    outcome = LostSample(futures[future], f"worker process failed: {_describe(exc)}")
                yield outcome
        finally:
            for future in futures:
                future.cancel()


def _dask_outcomes(spec: CampaignSpec, jobs, scheduler) -> Iterator[Union[SampleOutcome, LostSample]]:
    from .._util.optional import require

    distributed = require("distributed", "campaigns on a Dask cluster")
    Client, dask_as_completed = distributed.Client, distributed.as_completed
    own_client = not isinstance(scheduler, Client)
    if own_client:
        try:
            client = Client(scheduler)
        except (OSError, TimeoutError) as exc:
            raise CampaignError(f"cannot connect to the Dask scheduler '{scheduler}': {_describe(exc)}") from None
    else:
        client = scheduler
    try:
        indices = [index for index, _ in jobs]
        params = [p for _, p in jobs]
        futures = client.map(run_sample, [spec] * len(jobs), indices, params, pure=False)
        index_of = {f.key: index for f, index in zip(futures, indices)}
        for future in dask_as_completed(futures):
            try:
                outcome = future.result()
            except (Exception, asyncio.CancelledError) as exc:  # worker killed, scheduler lost, task not sent
                outcome = LostSample(index_of[future.key], f"Dask task failed: {_describe(exc)}")
            yield outcome
    finally:
        if own_client:
            client.close()


def _lost_message(lost, done: int, backend: str, out: Optional[Path]) -> str:
    """The one error a campaign raises when samples were lost to the back end."""
    reason = lost[0].reason
    if done == 0 and backend == "processes":
        return (f"no worker process returned a sample ({reason}); nothing was recorded. If the script that "
                f"calls run_campaign has no main guard, that is the cause: {GUARD_ADVICE}")
    if out is None:
        where = "run the campaign again (with out=... to keep what runs)"
    elif done == 0:
        where = f"run the same campaign with out='{out}' again to run them"
    else:
        where = f"the {done} sample(s) that ran are saved in '{out}'; run the same campaign with the same out to run the rest"
    return (f"{len(lost)} sample(s) did not run because the {backend} back end failed outside them ({reason}); "
            f"they are not recorded as failed and stay pending: {where}")


def run_campaign(
    robot_or_spec,
    samples: Optional[int] = None,
    *,
    seed: int = 0,
    perturbations: Optional[Perturbations] = None,
    scenario: Optional[Scenario] = None,
    workers: Optional[int] = None,
    scheduler=None,
    out: Optional[Union[str, Path]] = None,
    resume: bool = True,
    retry_failed: bool = False,
    checkpoint_seconds: float = 10.0,
    progress: Union[bool, Callable[[int, int], None]] = True,
) -> CampaignResult:
    """Run a Monte Carlo inertia-uncertainty campaign.

    ``robot_or_spec``: the nominal :class:`~spacearm.Robot` (then ``samples`` is required) or a
    :class:`CampaignSpec`. Each sample flies :class:`Scenario` on a plant whose inertia is
    perturbed as drawn from ``perturbations``, with the controller built on the nominal model.
    ``workers`` local processes (default ``os.cpu_count()``; 0 = in this process) or, with
    ``scheduler`` (address or ``distributed.Client``), a Dask cluster. With ``out`` (.npz) the
    result is written atomically every ``checkpoint_seconds`` and at the end; if ``out``
    already holds this campaign and ``resume``, only its missing samples run (failed ones too if
    ``retry_failed``). Returns the :class:`CampaignResult`.

    Samples the back end loses (a broken pool, a lost worker or scheduler) stay pending and the
    call raises :class:`~spacearm.errors.CampaignError` after saving what ran; with local
    processes, call it under ``if __name__ == "__main__":`` in a script (checked first).
    """
    stop_if_reimported_by_a_worker()
    if isinstance(robot_or_spec, CampaignSpec):
        if samples is not None or perturbations is not None or scenario is not None:
            raise ArgumentError("give either a CampaignSpec or a robot with samples/perturbations/scenario, not both")
        spec = robot_or_spec
    else:
        if samples is None:
            raise ArgumentError("run_campaign(robot, samples=...): the number of samples is required")
        from ..io.model_file import dumps_toml

        spec = CampaignSpec(dumps_toml(robot_or_spec), samples, seed, perturbations or Perturbations(),
                            scenario or Scenario())
        spec.scenario.goal(robot_or_spec)  # a wrong-length q_goal fails here, not in every worker
    if workers is None:
        workers = os.cpu_count() or 1
    if not isinstance(workers, int) or workers < 0:
        raise ArgumentError(f"workers must be an integer >= 0, got {workers!r}")
    if scheduler is not None and workers == 0:
        raise ArgumentError("workers=0 runs in this process; it cannot be combined with a Dask scheduler")
    if not checkpoint_seconds > 0:
        raise ArgumentError(f"checkpoint_seconds must be > 0, got {checkpoint_seconds!r}")
    out = Path(out) if out is not None else None
    if out is not None and out.suffix != ".npz":
        raise ArgumentError(f"out must be a .npz path, got '{out}'")

    if workers > 0 and scheduler is None:
        check_caller_is_guarded()

    spec_json = spec.to_json()
    result = None
    resumed = out is not None and out.exists() and resume
    if resumed:
        result = CampaignResult.load(out)
        if result.spec_json != spec_json:
            raise ArgumentError(f"'{out}' holds a different campaign (model, perturbations, scenario, samples or "
                                "seed differ); choose another output path or pass resume=False to overwrite it")
    if result is None:
        result = CampaignResult(spec_json, PARAMETER_NAMES, METRIC_NAMES, spec.samples)
    todo = result.status == PENDING
    if retry_failed:
        todo |= result.status == FAILED
    jobs = [(int(i), spec.perturbations.draw(spec.seed, int(i))) for i in result.index[todo]]

    backend = "in-process" if workers == 0 else ("dask" if scheduler is not None else "processes")
    n_workers = workers
    if scheduler is not None:
        n_workers = None  # filled from the cluster below when possible
    bar = _progress(spec.samples, spec.samples - len(jobs), progress)
    start = time.perf_counter()
    last_save = start
    outcomes: Iterable[SampleOutcome]
    if scheduler is not None:
        outcomes = _dask_outcomes(spec, jobs, scheduler)
        try:
            from distributed import Client

            if isinstance(scheduler, Client):
                n_workers = len(scheduler.scheduler_info().get("workers", {}))
        except ImportError:
            pass
    else:
        outcomes = _local_outcomes(spec, jobs, min(workers, max(len(jobs), 1)) if workers else 0)
    done = 0
    lost = []
    try:
        for outcome in outcomes:
            if isinstance(outcome, LostSample):
                lost.append(outcome)
                continue
            result.record(outcome.index, outcome.params, outcome.metrics, outcome.error, outcome.seconds)
            done += 1
            bar.update(1)
            now = time.perf_counter()
            if out is not None and now - last_save >= checkpoint_seconds:
                result.save(out)
                last_save = now
    finally:
        bar.close()
        elapsed = time.perf_counter() - start
        result.run = {
            "backend": backend,
            "workers": n_workers,
            "scheduler": None if scheduler is None else str(getattr(scheduler, "scheduler", scheduler)),
            "samples_run": done,
            "samples_lost": len(lost),
            "elapsed_s": elapsed,
            "samples_per_s": done / elapsed if elapsed > 0 else float("nan"),
        }
        if lost:
            result.run["lost_reason"] = lost[0].reason
        # Nothing new to keep in a fresh file; an existing one is not overwritten by an empty run.
        if out is not None and (done > 0 or resumed):
            result.save(out)
    if lost:
        raise CampaignError(_lost_message(lost, done, backend, out))
    return result
