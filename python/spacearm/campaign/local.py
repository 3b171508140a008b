"""The local back ends: native threads (the default), the calling thread, or worker processes.

**Threads** (``backend="threads"``): the pending samples are cut into batches; a driver thread
runs one batch after another (:func:`~.batch.run_batch`, native rollouts on ``threads``
threads with the GIL released) and hands each finished batch to the calling thread through a
queue. The calling thread records outcomes, draws the progress bar and writes checkpoints while
the driver is already running the next batch, so the workers never wait for a file to be
written. No process is started, so nothing can outlive the campaign.

**In this process** (``workers=0``): :func:`~.worker.run_sample` sample by sample in the calling
thread: the reference path (debugging, profiling) the other back ends must agree with bit for
bit.

**Processes** (``backend="processes"``): a :class:`~concurrent.futures.ProcessPoolExecutor`
with the ``spawn`` start method, one batch per task, for isolation: a sample that takes its
process down (an abort in native code) loses one batch, not the campaign. Every worker runs
:func:`spacearm._util.lifeline.die_with_parent` first, so workers end within a second of their parent's
death, SIGKILL included. The pool is created and fed from the calling thread, which lives as
long as the pool (the kernel's parent-death signal is tied to the thread that started a worker).
"""

from __future__ import annotations

import os
import queue
import threading
from typing import Iterator, List, Sequence, Union

from .batch import Job, run_batch, split_into_batches
from .._util.lifeline import die_with_parent
from .worker import LostSample, SampleOutcome, describe_exception, run_sample

__all__ = ["in_process_outcomes", "thread_outcomes", "process_outcomes", "samples_per_batch"]

Outcome = Union[SampleOutcome, LostSample]

# A batch holds this many samples per thread: enough that the stragglers at the end of a batch
# (threads idle while the last samples finish) cost little, few enough that the progress bar and
# the checkpoints follow the run closely.
_SAMPLES_PER_THREAD = 8
# A process-pool task holds at most this many samples (a lost worker loses one task).
_MAX_PROCESS_BATCH = 8


def samples_per_batch(backend: str, workers: int, pending: int) -> int:
    """The default batch size of the local back ends."""
    if backend == "threads":
        return max(1, _SAMPLES_PER_THREAD * workers)
    # Processes: about four tasks per worker, so the pool stays balanced to the end.
    return max(1, min(_MAX_PROCESS_BATCH, -(-pending // (4 * max(workers, 1)))))


def _lost(batch: Sequence[Job], reason: str) -> List[LostSample]:
    return [LostSample(index, reason) for index, _ in batch]


def in_process_outcomes(spec, jobs: Sequence[Job]) -> Iterator[Outcome]:
    for index, params in jobs:
        yield run_sample(spec, index, params)


_DRIVER_DONE = object()


def thread_outcomes(spec, jobs: Sequence[Job], threads: int, batch_size: int) -> Iterator[Outcome]:
    """Outcomes of ``jobs`` run as native rollouts on ``threads`` threads, a batch at a time."""
    batches = split_into_batches(jobs, batch_size)
    finished: "queue.Queue" = queue.Queue()
    stop = threading.Event()

    def drive():
        for batch in batches:
            if stop.is_set():
                break
            try:
                finished.put((batch, run_batch(spec, batch, threads)))
            except Exception as exc:  # noqa: BLE001 — not a sample's failure (run_batch returns those)
                finished.put((batch, exc))
        finished.put(_DRIVER_DONE)

    # A daemon thread: after Ctrl-C in the calling thread, the batch in flight cannot be
    # interrupted inside native code; it must not keep the interpreter from exiting.
    driver = threading.Thread(target=drive, name="spacearm-campaign-driver", daemon=True)
    driver.start()
    try:
        while True:
            item = finished.get()
            if item is _DRIVER_DONE:
                return
            batch, outcomes = item
            if isinstance(outcomes, BaseException):
                yield from _lost(batch, f"a batch failed outside its samples: {describe_exception(outcomes)}")
            else:
                yield from outcomes
    finally:
        stop.set()  # the driver ends after the batch it is running


def process_outcomes(spec, jobs: Sequence[Job], workers: int, batch_size: int) -> Iterator[Outcome]:
    """Outcomes of ``jobs`` run on ``workers`` spawned processes, one batch per task."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context, initializer=die_with_parent,
                             initargs=(os.getpid(),)) as pool:
        futures = {pool.submit(run_batch, spec, batch, 1): batch for batch in split_into_batches(jobs, batch_size)}
        try:
            for future in as_completed(futures):
                try:
                    outcomes = future.result()
                except Exception as exc:  # the pool broke: a worker died or could not start
                    outcomes = _lost(futures[future], f"worker process failed: {describe_exception(exc)}")
                yield from outcomes
        finally:
            for future in futures:
                future.cancel()
