"""Worker processes that die with the process that started them, however it dies.

A campaign's worker process must not outlive its parent: when the parent is killed (SIGKILL
included, which runs no clean-up), orphaned workers would go on computing samples nobody
collects, and they hold the parent's stdout and stderr open, so a shell pipeline around the CLI
never ends. ``die_with_parent``, run first in every worker (the process pool's
``initializer``), arms two mechanisms:

- **Linux**: ``prctl(PR_SET_PDEATHSIG, SIGKILL)``: the kernel kills the worker the moment its
  parent exits, even while the worker is deep in a native call. The parent may already be gone
  by the time the worker runs this (the worker would then have been re-parented and never get
  the signal), so the parent's pid is checked right after arming it.
- **Everywhere**: a daemon thread that polls ``os.getppid()`` and ends the process when the
  parent changes (the orphan was re-parented to init or to a subreaper). It needs the GIL, so it
  is the fallback (other systems, a ``prctl`` that failed), not the main mechanism.

Either way the worker ends with ``os._exit``: no clean-up that could block on the dead parent
(flushing a pipe nobody reads, joining queues it fed).

The kernel's parent-death signal fires when the *thread* that started the worker exits, not
only the process: a pool must therefore start its workers from a thread that lives as long as
the pool (the process back end starts them from the thread that runs the campaign).
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time

__all__ = ["die_with_parent", "POLL_SECONDS"]

#: How often the watchdog thread looks at the parent's pid (s).
POLL_SECONDS = 0.5

_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>


def _arm_parent_death_signal() -> bool:
    """``prctl(PR_SET_PDEATHSIG, SIGKILL)`` on Linux; False where it is not available."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def _watch_parent(parent_pid: int) -> None:
    while True:
        if os.getppid() != parent_pid:
            os._exit(1)
        time.sleep(POLL_SECONDS)


def die_with_parent(parent_pid: int) -> None:
    """Make this process exit when the process ``parent_pid`` (its parent) exits.

    Call it first thing in a worker process, with the parent's pid taken in the parent
    (``os.getpid()`` there), so that a parent that died before this call is noticed too.
    """
    _arm_parent_death_signal()
    if os.getppid() != parent_pid:  # the parent died before the signal was armed
        os._exit(1)
    threading.Thread(target=_watch_parent, args=(parent_pid,), name="spacearm-parent-watch", daemon=True).start()
