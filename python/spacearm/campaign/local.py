"""The local back ends: native threads (the default), the calling thread, or worker processes.

**Threads** (``backend="threads"``): the pending samples are cut into batches, and each batch
goes through the three stages of ``batch.py`` on three threads at once: a *preparer* thread
builds the plants of the next batch while a *driver* thread flies the current one
([`spacearm.rollout`][spacearm.rollout] on ``threads`` native threads, the GIL released), and the calling
thread turns the batch before into metrics, records them, draws the progress bar and writes
checkpoints. So the native threads go from one batch to the next without waiting for Python or
for a file to be written. No process is started: nothing can outlive the campaign.

**In this process** (``workers=0``): ``run_sample`` sample by sample in the calling
thread, with [`spacearm.simulate`][spacearm.simulate]: the reference path (debugging, profiling) the other back
ends agree with bit for bit.

**Processes** (``backend="processes"``): a ``ProcessPoolExecutor``
with the ``spawn`` start method, one batch per task, for isolation: a sample that takes its
process down (an abort in native code) loses one batch, not the campaign. Every worker runs
``spacearm._util.lifeline.die_with_parent`` first, so workers end within a second of their
parent's death, SIGKILL included. The pool is created and fed from the calling thread, which
lives as long as the pool (the kernel's parent-death signal is tied to the thread that started a
worker).
"""

from __future__ import annotations

import os
import queue
import threading
from typing import Iterator, List, Optional, Sequence, Union

from .._util.lifeline import die_with_parent
from .batch import Prepared, fly, outcomes, prepare, run_batch, split_into_batches
from .worker import LostSample, SampleOutcome, describe_exception, run_sample

__all__ = ["in_process_outcomes", "thread_outcomes", "process_outcomes", "samples_per_batch"]

Outcome = Union[SampleOutcome, LostSample]

# A thread batch holds up to this many samples per thread: enough that the threads rarely wait
# for each other at the end of a batch (the samples of a campaign cost about the same), few
# enough that the progress bar and the checkpoints follow the run closely.
_SAMPLES_PER_THREAD = 8
# ... and its records (every step of every rollout) stay under this many bytes; about three
# batches are alive at once (one being flown, one waiting, one being turned into metrics).
_BATCH_RECORD_BYTES = 128 * 2**20
# A process-pool task holds at most this many samples (a lost worker loses one task).
_MAX_PROCESS_BATCH = 8


def samples_per_batch(backend: str, workers: int, pending: int, record_bytes: int = 0) -> int:
    """The default batch size of the local back ends: for threads a multiple of ``workers`` (so
    every thread gets as many samples) within the record budget, given the bytes of one sample's
    records; for processes about four tasks per worker."""
    if backend == "threads":
        per_thread = _BATCH_RECORD_BYTES // max(record_bytes * workers, 1)
        return workers * max(1, min(_SAMPLES_PER_THREAD, per_thread))
    return max(1, min(_MAX_PROCESS_BATCH, -(-pending // (4 * max(workers, 1)))))


def _lost(batch: Sequence[int], reason: str) -> List[LostSample]:
    return [LostSample(index, reason) for index in batch]


def in_process_outcomes(spec, indices: Sequence[int]) -> Iterator[Outcome]:
    for index in indices:
        yield run_sample(spec, index)


_END = object()


class _Failed:
    """A batch that failed outside its samples in the preparer or the driver."""

    def __init__(self, batch: Sequence[int], exc: BaseException):
        self.batch, self.exc = batch, exc


def _put(q: "queue.Queue", item, stop: threading.Event) -> bool:
    """Put ``item`` on the bounded queue ``q`` unless the campaign stops first."""
    while not stop.is_set():
        try:
            q.put(item, timeout=0.1)
            return True
        except queue.Full:
            pass
    return False


def thread_outcomes(spec, indices: Sequence[int], threads: int, batch_size: int,
                    first: Optional[int] = None) -> Iterator[Outcome]:
    """Outcomes of samples ``indices`` run as native rollouts on ``threads`` threads, a batch at a
    time (batches of ``batch_size``, or from ``first`` doubling up to it)."""
    batches = split_into_batches(indices, batch_size, first)
    prepared: "queue.Queue" = queue.Queue(maxsize=1)  # the next batch's plants, ready to fly
    flown: "queue.Queue" = queue.Queue(maxsize=2)  # flown batches waiting for the calling thread
    stop = threading.Event()

    def prepare_all():
        for batch in batches:
            try:
                item = prepare(spec, batch)
            except Exception as exc:  # noqa: BLE001 — not a sample's failure (prepare returns those)
                item = _Failed(batch, exc)
            if not _put(prepared, item, stop):
                return
        _put(prepared, _END, stop)

    def fly_all():
        while not stop.is_set():
            try:
                item = prepared.get(timeout=0.1)
            except queue.Empty:
                continue
            if item is _END:
                break
            if isinstance(item, Prepared):
                try:
                    item = (item, *fly(item, threads, stop))
                except Exception as exc:  # noqa: BLE001 — not a sample's failure (fly returns those)
                    item = _Failed([index for index, _ in item.flying], exc)
            if not _put(flown, item, stop):
                return
        _put(flown, _END, stop)

    # Daemon threads: after Ctrl-C in the calling thread, the batch in flight cannot be
    # interrupted inside native code; it must not keep the interpreter from exiting.
    workers = [threading.Thread(target=prepare_all, name="spacearm-campaign-prepare", daemon=True),
               threading.Thread(target=fly_all, name="spacearm-campaign-fly", daemon=True)]
    for w in workers:
        w.start()
    try:
        while True:
            item = flown.get()
            if item is _END:
                return
            if isinstance(item, _Failed):
                yield from _lost(item.batch, f"a batch failed outside its samples: {describe_exception(item.exc)}")
                continue
            batch, runs, seconds = item
            yield from outcomes(batch, runs, seconds, threads)
    finally:
        # The threads end after the step they are in: the batch in flight is stopped within
        # 0.1 s (the rollout's stop event). Joined before returning, so that no thread is still
        # in native code when the interpreter exits (it aborted then: "FATAL: exception not
        # rethrown", issue 26).
        stop.set()
        for w in workers:
            w.join(timeout=30.0)


def process_outcomes(spec, indices: Sequence[int], workers: int, batch_size: int) -> Iterator[Outcome]:
    """Outcomes of samples ``indices`` run on ``workers`` spawned processes, one batch per task."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context, initializer=die_with_parent,
                             initargs=(os.getpid(),)) as pool:
        futures = {pool.submit(run_batch, spec, batch, 1): batch for batch in split_into_batches(indices, batch_size)}
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
