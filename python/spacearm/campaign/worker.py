"""What a sample comes back as, and the per-sample reference path.

A sample that ran comes back as a ``SampleOutcome``: its metrics, or the message of its own
failure (a model the perturbation made invalid, a singular matrix, a non-finite state), so one
bad sample is recorded and the campaign goes on. A sample a back end could not run comes back as
a ``LostSample`` and stays pending. ``run_sample`` flies one sample with
[`spacearm.simulate`][spacearm.simulate] in the calling thread (``workers=0``): the reference that the batched
path (``batch.py``) reproduces bit for bit.
"""

from __future__ import annotations

import time
import traceback
from typing import Dict, NamedTuple, Optional

__all__ = ["SampleOutcome", "LostSample", "describe_exception", "failure_message", "nominal_robot", "run_sample"]

# The nominal robot of the last campaign this process served, keyed by its TOML text, so a
# worker parses the model once per campaign rather than once per sample.
_NOMINAL_CACHE: Dict[str, object] = {}


class SampleOutcome(NamedTuple):
    index: int
    params: Dict[str, float]
    metrics: Optional[Dict[str, float]]
    error: str
    seconds: float


class LostSample(NamedTuple):
    """A sample a back end could not run, for a reason outside the sample (a dead worker, a lost
    scheduler, a batch that could not be sent): it is not recorded and stays pending."""

    index: int
    reason: str


def describe_exception(exc: BaseException) -> str:
    """``Class: message`` (the class alone when the message is empty)."""
    message = " ".join(str(exc).split())  # one line: some back ends' messages span several
    return f"{type(exc).__name__}: {message}" if message else type(exc).__name__


def nominal_robot(model_toml: str):
    """The campaign's nominal robot, parsed once per process and campaign (keyed by its TOML)."""
    robot = _NOMINAL_CACHE.get(model_toml)
    if robot is None:
        from ..io.model_file import loads_toml

        robot = loads_toml(model_toml, source="<campaign model>")
        _NOMINAL_CACHE.clear()
        _NOMINAL_CACHE[model_toml] = robot
    return robot


def failure_message(exc: BaseException) -> str:
    """A sample's failure as recorded: ``Class: message (at file:line)``, the line that raised."""
    last = traceback.extract_tb(exc.__traceback__)[-1:] if exc.__traceback__ else []
    where = f" (at {last[0].filename.rsplit('/', 1)[-1]}:{last[0].lineno})" if last else ""
    return f"{type(exc).__name__}: {exc}{where}"


def run_sample(spec, index: int) -> SampleOutcome:
    """Fly sample ``index`` of ``spec`` (its inertia errors drawn here, from its own stream)."""
    from .scenario import evaluate

    start = time.perf_counter()
    params = spec.draw(index)
    try:
        metrics = evaluate(nominal_robot(spec.model_toml), spec.scenario, params)
        return SampleOutcome(index, params, metrics, "", time.perf_counter() - start)
    except Exception as exc:  # noqa: BLE001 — a failed sample is data, not a crash
        return SampleOutcome(index, params, None, failure_message(exc), time.perf_counter() - start)
