"""The threads that batches run on.

Every per-state method of [`Robot`][spacearm.Robot] takes a batch of states (``x`` of shape
``(B, 7+N)``, one state per row) and computes the rows in parallel in the extension, with the
GIL released (``docs/batch.md``). By default the rows share rayon's global pool: one thread per
core, or ``RAYON_NUM_THREADS`` if that is set before the first batch. Results are bit-identical
whatever the thread count.
"""

from __future__ import annotations

from typing import Optional

from .. import _core
from .._util.arrays import integer
from ..errors import ArgumentError

__all__ = ["set_batch_threads", "batch_threads"]


def set_batch_threads(threads: Optional[int] = None) -> None:
    """Run batches on ``threads`` threads from now on (a pool of that size, shared by every
    Robot), at most 1024 (``ArgumentError`` beyond: no call starts threads without limit);
    ``None`` returns to the default (one per core, or ``RAYON_NUM_THREADS``)."""
    if threads is None:
        _core.set_batch_threads(None)
        return
    n = integer(threads, "threads")
    if n < 1:
        raise ArgumentError(f"threads must be a positive integer or None (all cores), got {threads!r}")
    _core.set_batch_threads(n)


def batch_threads() -> int:
    """The number of threads batches run on now."""
    return _core.batch_threads()
