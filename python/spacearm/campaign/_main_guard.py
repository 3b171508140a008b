"""The one rule worker processes (``backend="processes"``) impose on the script that starts a
campaign (the default thread back end starts no process and needs no guard).

Worker processes are started with the ``spawn`` start method: each is a fresh interpreter that
re-runs the parent's main script (as module ``__mp_main__``) to find the code it is sent. A script
that calls [`run_campaign`][spacearm.campaign.run_campaign] at its top level, not under
``if __name__ == "__main__":``, therefore calls it again inside every worker while the worker is
still starting; Python refuses to start processes from there, the worker dies, and without a
check every sample would come back as a broken pool.

Two checks, so the user gets one clear error before any sample runs:

- in the parent, ``check_caller_is_guarded`` reads the main script and tells whether the
  line that is running lies under a ``__name__ == "__main__"`` test;
- in a worker that is re-running the script, ``stop_if_reimported_by_a_worker`` ends the
  worker quietly (the parent then reports the broken pool with the same advice), rather than
  printing one traceback per worker.
"""

from __future__ import annotations

import ast
import multiprocessing
import sys
from pathlib import Path
from typing import Optional

from ..errors import CampaignError

__all__ = ["GUARD_ADVICE", "check_caller_is_guarded", "stop_if_reimported_by_a_worker"]

GUARD_ADVICE = (
    "worker processes start with the 'spawn' method and re-run the main script, so a script that "
    "calls run_campaign with backend='processes' must do so under `if __name__ == \"__main__\":` (or use "
    "the default thread back end, which starts no process)"
)


def _script_a_worker_reruns() -> Optional[Path]:
    """The main script a ``spawn`` worker re-runs, or None when it re-runs nothing.

    Mirrors ``multiprocessing.spawn.get_preparation_data``: a module run with ``-m`` is
    re-imported by name unless it is a package's ``__main__``; a script run by path is re-run
    from that path; an interactive session, ``python -c`` or a notebook has no file to re-run.
    """
    main = sys.modules.get("__main__")
    if main is None:
        return None
    spec_name = getattr(getattr(main, "__spec__", None), "name", None)
    if spec_name is not None and (spec_name == "__main__" or spec_name.endswith(".__main__")):
        return None
    path = getattr(main, "__file__", None)
    return Path(path) if path else None


def _is_main_test(test: ast.expr) -> Optional[bool]:
    """True for ``__name__ == "__main__"``, False for ``__name__ != "__main__"`` (either operand
    order), None for any other test."""
    if not (isinstance(test, ast.Compare) and len(test.ops) == 1 and isinstance(test.ops[0], (ast.Eq, ast.NotEq))):
        return None
    operands = (test.left, test.comparators[0])
    names = [o for o in operands if isinstance(o, ast.Name) and o.id == "__name__"]
    texts = [o for o in operands if isinstance(o, ast.Constant) and o.value == "__main__"]
    if len(names) != 1 or len(texts) != 1:
        return None
    return isinstance(test.ops[0], ast.Eq)


def _within(statements, line: int) -> bool:
    return any(s.lineno <= line <= (s.end_lineno or s.lineno) for s in statements)


def line_is_guarded(source: str, line: int) -> bool:
    """Whether top-level line ``line`` of the module ``source`` runs only in the main process:
    it lies in the branch of an ``if`` that requires ``__name__ == "__main__"``."""
    tree = ast.parse(source)
    for node in ast.walk(tree):
        if isinstance(node, ast.If):
            kind = _is_main_test(node.test)
            if kind is not None and _within(node.body if kind else node.orelse, line):
                return True
    return False


def check_caller_is_guarded() -> None:
    """Raise [`CampaignError`][spacearm.CampaignError] when the main script that a worker would
    re-run is, at this moment, executing top-level code outside a main guard. Inconclusive cases
    (no script, source not readable) pass; the broken-pool check in the executor covers them."""
    script = _script_a_worker_reruns()
    main = sys.modules.get("__main__")
    if script is None or main is None:
        return
    frame = sys._getframe(1)
    while frame is not None and not (frame.f_code.co_name == "<module>" and frame.f_globals is vars(main)):
        frame = frame.f_back
    if frame is None:  # called from a thread or a callback, not from the script's top level
        return
    try:
        guarded = line_is_guarded(script.read_text(encoding="utf-8"), frame.f_lineno)
    except (OSError, UnicodeDecodeError, SyntaxError, ValueError):
        return
    if not guarded:
        raise CampaignError(f"run_campaign is called at the top level of '{script}' (line {frame.f_lineno}): {GUARD_ADVICE}")


def stop_if_reimported_by_a_worker() -> None:
    """In a worker that is re-running the main script while it starts (the unguarded case),
    end the worker without a traceback; the parent reports the failure once."""
    # The flag multiprocessing itself tests before refusing to start a process from a worker
    # that is still starting (multiprocessing.spawn._check_not_importing_main); it is set only
    # while a spawned worker runs the parent's main script.
    if getattr(multiprocessing.current_process(), "_inheriting", False):
        raise SystemExit(1)
