"""Running a campaign: native threads by default, worker processes or a Dask cluster on request.

Samples are independent. The calling thread draws every pending sample's parameters
([`Perturbations.draw`][spacearm.campaign.Perturbations.draw]), hands them to a back end in batches, and records the outcomes as
they come back (in any order; each is stored at its index, so the file does not depend on
scheduling). It keeps the [`CampaignResult`][spacearm.campaign.CampaignResult], writes it atomically every
``checkpoint_seconds`` while the back end goes on computing, at the end, and on Ctrl-C or any
other exception; and it shows a progress bar.

- ``backend="threads"`` (default): batches of native rollouts on ``workers`` threads with the GIL
  released (``local.py``): no process start, no model parse, no Python loop per sample.
- ``workers=0``: sample by sample in the calling thread (the reference path; debugging).
- ``backend="processes"``: spawned worker processes, one batch per task, for isolation; they
  die with this process (``_util/lifeline.py``).
- ``scheduler="tcp://host:8786"`` (or a ``distributed.Client``): a Dask cluster, one batch per
  task, with a watchdog for a cluster left without workers (``cluster.py``).

Failures are sorted by where they happen. A batch returns every failure of a sample itself (an
invalid plant, a singular matrix, a diverged state) as an outcome, which is recorded as failed.
Anything a back end reports instead — a broken process pool, a worker or scheduler lost, a
cluster with no workers for ``worker_timeout`` — is a failure of the infrastructure: those
samples are left pending (a rerun runs them), and once the outcomes that did arrive are recorded
and saved, the campaign raises one [`CampaignError`][spacearm.CampaignError] saying how many
samples did not run and why.
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Callable, Optional, Union

from ..errors import ArgumentError, CampaignError
from ._main_guard import GUARD_ADVICE, check_caller_is_guarded, stop_if_reimported_by_a_worker
from .perturbation import Perturbations
from .results import FAILED, PENDING, CampaignResult
from .scenario import METRIC_NAMES, Scenario
from .spec import CampaignSpec
from .worker import LostSample

__all__ = ["run_campaign", "CampaignSpec", "BACKENDS"]

#: The back ends [`run_campaign`][spacearm.campaign.run_campaign] accepts (``"in-process"`` is ``workers=0``).
BACKENDS = ("threads", "processes", "dask", "in-process")


def _progress(total: int, initial: int, enabled: Union[bool, Callable[[int, int], None]]):
    """A tqdm bar (``enabled=True``), a user callback ``fn(done, total)``, or nothing."""
    if callable(enabled):
        class _FunctionProgress:
            """tqdm's ``update``/``close`` over the user's ``fn(done, total)``."""

            def __init__(self):
                self.done = initial

            def update(self, k=1):
                self.done += k
                enabled(self.done, total)

            def close(self):
                pass

        return _FunctionProgress()
    if enabled:
        from tqdm import tqdm

        return tqdm(total=total, initial=initial, unit="sample", desc="campaign", dynamic_ncols=True)

    class _Silent:
        def update(self, k=1):
            pass

        def close(self):
            pass

    return _Silent()


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


def _choose_backend(backend: Optional[str], workers: Optional[int], scheduler) -> str:
    if backend is None:
        return "dask" if scheduler is not None else ("in-process" if workers == 0 else "threads")
    if backend not in BACKENDS:
        raise ArgumentError(f"backend must be one of {', '.join(map(repr, BACKENDS))}, got {backend!r}")
    if (backend == "dask") != (scheduler is not None):
        raise ArgumentError("the dask back end needs a scheduler (an address or a distributed.Client), and a "
                            f"scheduler needs the dask back end; got backend={backend!r}, scheduler={scheduler!r}")
    if backend == "in-process" and workers not in (None, 0):
        raise ArgumentError(f"the in-process back end runs in the calling thread; workers must be 0, got {workers!r}")
    return backend


def _record_bytes(spec: CampaignSpec, backend: str, pending) -> int:
    """Bytes of one sample's records, which bound a thread batch (0 where unknown: a scenario no
    sample can fly fails sample by sample, as data, not here)."""
    if backend != "threads" or not pending:
        return 0
    from .batch import record_bytes_per_sample

    try:
        return record_bytes_per_sample(spec)
    except Exception:  # noqa: BLE001 — see the docstring
        return 0


def run_campaign(
    robot_or_spec,
    samples: Optional[int] = None,
    *,
    seed: int = 0,
    perturbations: Optional[Perturbations] = None,
    scenario: Optional[Scenario] = None,
    workers: Optional[int] = None,
    backend: Optional[str] = None,
    scheduler=None,
    batch_size: Optional[int] = None,
    worker_timeout: Optional[float] = None,
    out: Optional[Union[str, Path]] = None,
    resume: bool = True,
    retry_failed: bool = False,
    checkpoint_seconds: float = 10.0,
    progress: Union[bool, Callable[[int, int], None]] = True,
) -> CampaignResult:
    """Run a Monte Carlo inertia-uncertainty campaign.

    ``robot_or_spec``: the nominal [`Robot`][spacearm.Robot] (then ``samples`` is required) or a
    [`CampaignSpec`][spacearm.campaign.CampaignSpec]. Each sample flies [`Scenario`][spacearm.campaign.Scenario] on a plant whose inertia is
    perturbed as drawn from ``perturbations``, with the controller built on the nominal model.

    Where the samples run: ``workers`` native threads (default ``os.cpu_count()``); ``workers=0``
    runs them one by one in the calling thread; ``backend="processes"`` on ``workers`` spawned
    processes instead; with ``scheduler`` (address or ``distributed.Client``), on a Dask
    cluster. ``batch_size``: samples per batch (default: 8 per thread; for Dask about four tasks
    per worker thread, at most 64). ``worker_timeout`` (Dask only, default 60 s): a cluster with
    no live worker for that long stops the campaign.

    With ``out`` (.npz) the result is written atomically every ``checkpoint_seconds`` and at the
    end; if ``out`` already holds this campaign and ``resume``, only its missing samples run
    (failed ones too if ``retry_failed``). Returns the [`CampaignResult`][spacearm.campaign.CampaignResult].

    Samples the back end loses (a broken pool, a lost worker or scheduler, the watchdog) stay
    pending and the call raises [`CampaignError`][spacearm.CampaignError] after saving what ran;
    with worker processes, call it under ``if __name__ == "__main__":`` in a script (checked
    first).
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
        if spec.scenario.cmg is not None:
            spec.scenario.cmg.check(robot_or_spec)  # so does CMG uncertainty on a model without CMGs
    backend = _choose_backend(backend, workers, scheduler)
    if backend == "dask":
        if workers is not None:
            raise ArgumentError("workers is for the local back ends; a Dask campaign runs on the cluster's workers")
    else:
        workers = 0 if backend == "in-process" else (os.cpu_count() or 1) if workers is None else workers
        if not isinstance(workers, int) or isinstance(workers, bool) or workers < 0:
            raise ArgumentError(f"workers must be an integer >= 0, got {workers!r}")
        if workers == 0 and backend != "in-process":
            raise ArgumentError(f"the {backend} back end needs workers >= 1 (workers=0 runs in the calling thread)")
    if batch_size is not None and (not isinstance(batch_size, int) or isinstance(batch_size, bool) or batch_size < 1):
        raise ArgumentError(f"batch_size must be an integer >= 1, got {batch_size!r}")
    if worker_timeout is not None and backend != "dask":
        raise ArgumentError("worker_timeout is the Dask watchdog's; the local back ends do not use it")
    if worker_timeout is not None and not (isinstance(worker_timeout, (int, float)) and worker_timeout > 0):
        raise ArgumentError(f"worker_timeout must be a number of seconds > 0, got {worker_timeout!r}")
    if not checkpoint_seconds > 0:
        raise ArgumentError(f"checkpoint_seconds must be > 0, got {checkpoint_seconds!r}")
    out = Path(out) if out is not None else None
    if out is not None and out.suffix != ".npz":
        raise ArgumentError(f"out must be a .npz path, got '{out}'")

    if backend == "processes":
        check_caller_is_guarded()

    spec_json = spec.to_json()
    result = None
    resumed = out is not None and out.exists() and resume
    if resumed:
        result = CampaignResult.load(out)
        if result.spec_json != spec_json:
            raise ArgumentError(f"'{out}' holds a different campaign (model, perturbations, scenario, samples or "
                                "seed differ); choose another output path, or overwrite it (resume=False; on the command line "
                                "--no-resume)")
    if result is None:
        result = CampaignResult(spec_json, spec.param_names, METRIC_NAMES, spec.samples)
    todo = result.status == PENDING
    if retry_failed:
        todo |= result.status == FAILED
    # Only the indices: each sample's inertia errors are drawn where its plant is built (in the
    # back end's pipeline), not all up front in this thread.
    pending = [int(i) for i in result.index[todo]]

    client = owned_client = None
    if backend == "dask":
        from .cluster import DEFAULT_WORKER_TIMEOUT, connect, dask_outcomes

        client, owned_client = connect(scheduler)
        scheduler_address = client.scheduler.address
        workers = len(client.scheduler_info().get("workers", {}))
        outcomes = dask_outcomes(spec, pending, client, batch_size,
                                 DEFAULT_WORKER_TIMEOUT if worker_timeout is None else float(worker_timeout))
    else:
        from .local import in_process_outcomes, process_outcomes, samples_per_batch, thread_outcomes

        if backend == "in-process":
            outcomes = in_process_outcomes(spec, pending)
        elif backend == "processes":
            workers = min(workers, max(len(pending), 1))
            outcomes = process_outcomes(spec, pending, workers,
                                        batch_size or samples_per_batch(backend, workers, len(pending)))
        else:
            workers = min(workers, max(len(pending), 1))
            size = batch_size or samples_per_batch(backend, workers, len(pending), _record_bytes(spec, backend, pending))
            # Default batches start at one sample per thread and double: the threads start sooner.
            outcomes = thread_outcomes(spec, pending, workers, size, first=None if batch_size else workers)

    bar = _progress(spec.samples, spec.samples - len(pending), progress)
    start = time.perf_counter()
    last_save = start
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
        outcomes.close()  # stops the back end's threads, pool or tasks, also on an exception
        if owned_client:
            client.close()
        bar.close()
        elapsed = time.perf_counter() - start
        result.run = {
            "backend": backend,
            "workers": workers,
            "scheduler": None if client is None else scheduler_address,
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
