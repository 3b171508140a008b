"""A batch of samples: the unit of work of every back end (a thread pipeline step, a process-pool
task, a Dask task).

:func:`run_batch` never raises for a failure of a sample itself (an invalid plant, a singular
matrix, a diverged state): each comes back as an outcome with its message. An exception that
escapes it is therefore not the samples' doing, and the back ends leave the whole batch pending.
"""

from __future__ import annotations

from typing import Dict, List, Sequence, Tuple

from .worker import SampleOutcome, run_sample

__all__ = ["Job", "run_batch", "split_into_batches"]

#: One sample to run: its index and its drawn parameters.
Job = Tuple[int, Dict[str, float]]


def split_into_batches(jobs: Sequence[Job], batch_size: int) -> List[List[Job]]:
    """``jobs`` in order, cut into consecutive batches of at most ``batch_size``."""
    return [list(jobs[i:i + batch_size]) for i in range(0, len(jobs), batch_size)]


def run_batch(spec, jobs: Sequence[Job], threads: int = 1) -> List[SampleOutcome]:
    """Fly every sample of ``jobs`` (of campaign ``spec``) on ``threads`` threads; one outcome per
    job, in the order of ``jobs``."""
    return [run_sample(spec, index, params) for index, params in jobs]
