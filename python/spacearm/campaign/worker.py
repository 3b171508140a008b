"""What runs on a worker (a local process or a Dask worker): one sample, failures included.

:func:`run_sample` never raises for a failure of the sample itself: a model the perturbation
made invalid, a singular matrix, a non-finite state — each comes back as an outcome with the
message, so one bad sample is recorded and the campaign goes on. It follows that an exception
the executor sees instead of an outcome was not the sample's doing (see ``executor.py``).
"""

from __future__ import annotations

import time
import traceback
from typing import Dict, NamedTuple, Optional

__all__ = ["SampleOutcome", "run_sample"]

# The nominal robot of the last campaign this process served, keyed by its TOML text, so a
# worker parses the model once per campaign rather than once per sample.
_NOMINAL_CACHE: Dict[str, object] = {}


class SampleOutcome(NamedTuple):
    index: int
    params: Dict[str, float]
    metrics: Optional[Dict[str, float]]
    error: str
    seconds: float


def _nominal(model_toml: str):
    robot = _NOMINAL_CACHE.get(model_toml)
    if robot is None:
        from ..io.model_file import loads_toml

        robot = loads_toml(model_toml, source="<campaign model>")
        _NOMINAL_CACHE.clear()
        _NOMINAL_CACHE[model_toml] = robot
    return robot


def run_sample(spec, index: int, params: Dict[str, float]) -> SampleOutcome:
    """Fly sample ``index`` of ``spec`` with the inertia errors ``params``."""
    from .scenario import evaluate

    start = time.perf_counter()
    try:
        metrics = evaluate(_nominal(spec.model_toml), spec.scenario, params)
        return SampleOutcome(index, params, metrics, "", time.perf_counter() - start)
    except Exception as exc:  # noqa: BLE001 — a failed sample is data, not a crash
        last = traceback.extract_tb(exc.__traceback__)[-1:] if exc.__traceback__ else []
        where = f" (at {last[0].filename.rsplit('/', 1)[-1]}:{last[0].lineno})" if last else ""
        return SampleOutcome(index, params, None, f"{type(exc).__name__}: {exc}{where}", time.perf_counter() - start)
