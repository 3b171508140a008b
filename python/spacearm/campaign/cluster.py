"""The Dask back end: a batch of samples per task, and a watchdog for a cluster with no workers.

Each task runs ``run_batch`` on one batch (one thread per task: Dask runs as many
tasks at once as its workers have threads). Outcomes are yielded as tasks finish, in any order.

Failures outside the samples leave them pending (a rerun runs them), never failed:

- a task Dask gives up on (its worker died ``allowed-failures`` times, a lost scheduler, which
  cancels every task of the client, a restart) yields its samples as ``LostSample``;
- the **watchdog**: a cluster with no live worker (or a client that has lost its scheduler) for
  ``worker_timeout`` seconds would wait forever; the campaign instead cancels what is left and
  yields it as lost, so [`run_campaign`][spacearm.campaign.run_campaign] saves what ran and raises one
  [`CampaignError`][spacearm.CampaignError] that says so.

The watchdog reads the worker count the client keeps up to date (``Client.scheduler_info()``,
refreshed every couple of seconds) and the client's connection status, so it costs no call to the
scheduler and cannot itself hang on a dead one.
"""

from __future__ import annotations

import asyncio
import time
from typing import Iterator, Optional, Sequence, Union

from ..errors import CampaignError
from .batch import run_batch, split_into_batches
from .worker import LostSample, SampleOutcome, describe_exception

__all__ = ["dask_outcomes", "DEFAULT_WORKER_TIMEOUT", "connect"]

#: Seconds a campaign waits for a live Dask worker before it stops (``worker_timeout``).
DEFAULT_WORKER_TIMEOUT = 60.0

# How long the calling thread sleeps when no task has finished, before it looks again (s).
_POLL_SECONDS = 0.05
# How long one attempt to fetch a finished task's result waits before the watchdog is asked (s).
_FETCH_SECONDS = 1.0
# Tasks per worker thread when the batch size is chosen: enough to balance the load at the end.
_TASKS_PER_THREAD = 4
_MAX_BATCH = 64

Outcome = Union[SampleOutcome, LostSample]


def connect(scheduler):
    """``(client, owned)``: the ``distributed.Client`` given, or a new one to the address given."""
    from .._util.optional import require

    distributed = require("distributed", "campaigns on a Dask cluster")
    if isinstance(scheduler, distributed.Client):
        return scheduler, False
    try:
        return distributed.Client(scheduler), True
    except (OSError, TimeoutError) as exc:
        raise CampaignError(f"cannot connect to the Dask scheduler '{scheduler}': {describe_exception(exc)}") from None


def worker_threads(client) -> int:
    """Threads of the live workers, as the client last heard from the scheduler (0 if none, or if
    the client is not connected)."""
    if client.status != "running":
        return 0
    workers = client.scheduler_info().get("workers", {})
    return sum(int(w.get("nthreads", 1)) for w in workers.values())


def samples_per_task(pending: int, threads: int) -> int:
    """The default batch size: about four tasks per worker thread, at most 64 samples."""
    return max(1, min(_MAX_BATCH, -(-pending // (_TASKS_PER_THREAD * max(threads, 1)))))


class _Watchdog:
    """Time since the cluster last had a live worker."""

    def __init__(self, client, timeout: float):
        self.client = client
        self.timeout = timeout
        self.last_alive = time.monotonic()

    def expired(self) -> bool:
        now = time.monotonic()
        if worker_threads(self.client) > 0:
            self.last_alive = now
        return now - self.last_alive >= self.timeout

    def reason(self) -> str:
        state = "no live Dask worker" if self.client.status == "running" else "no connection to the Dask scheduler"
        return f"{state} for {self.timeout:g} s (worker_timeout)"


def dask_outcomes(spec, indices: Sequence[int], client, batch_size: Optional[int],
                  worker_timeout: float) -> Iterator[Outcome]:
    """Outcomes of samples ``indices`` run on the Dask cluster of ``client``, one batch per task."""
    import distributed

    if batch_size is None:
        batch_size = samples_per_task(len(indices), worker_threads(client))
    batches = split_into_batches(indices, batch_size)
    futures = client.map(run_batch, [spec] * len(batches), batches, pure=False)
    unfinished = {future.key: (future, batch) for future, batch in zip(futures, batches)}
    arrivals = distributed.as_completed(futures)
    watchdog = _Watchdog(client, worker_timeout)

    def give_up() -> Iterator[LostSample]:
        reason = watchdog.reason()
        for _, batch in unfinished.values():
            yield from (LostSample(index, reason) for index in batch)

    try:
        while unfinished:
            ready = arrivals.next_batch(block=False) if arrivals.has_ready() else []
            if not ready:
                if watchdog.expired():
                    yield from give_up()
                    return
                time.sleep(_POLL_SECONDS)
                continue
            for future in ready:
                if future.key not in unfinished:
                    continue
                try:
                    outcomes = _result(future, watchdog)
                except _NoWorker:
                    yield from give_up()
                    return
                except (Exception, asyncio.CancelledError) as exc:  # worker killed, scheduler lost, task not sent
                    reason = f"Dask task failed: {describe_exception(exc)}"
                    outcomes = [LostSample(index, reason) for index in unfinished[future.key][1]]
                del unfinished[future.key]
                yield from outcomes
    finally:
        if unfinished:
            try:
                client.cancel([future for future, _ in unfinished.values()])
            except Exception:  # noqa: BLE001 — a client without a scheduler cannot cancel; nothing to undo
                pass


class _NoWorker(Exception):
    """The watchdog expired while a finished task's result was being fetched."""


def _result(future, watchdog: _Watchdog):
    """The result of a finished task, fetched without waiting forever: a result held by a worker
    that has since left is recomputed when a worker comes back, and until then the fetch waits
    under the watchdog (``_NoWorker`` when it expires)."""
    while True:
        try:
            return future.result(timeout=_FETCH_SECONDS)
        except (TimeoutError, asyncio.TimeoutError):
            if watchdog.expired():
                raise _NoWorker from None
