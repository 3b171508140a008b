"""The extension's typed run results as the plain dicts the public classes hold.

``spacearm._core.simulate`` and ``Simulator.result`` return a ``RunResult`` (``records``,
``events``, ``meta``); ``spacearm._core.rollout`` a ``RolloutBatch`` with the same pieces per
rollout. :class:`~spacearm.Trajectory` and :class:`~spacearm.Rollouts` keep the public form:
the records and saturation events as one dict of numpy arrays (the arrays themselves, no copy)
and the description as the ``meta`` dict of ``docs/simulation.md``. Plain dicts also keep
whatever holds them picklable (campaign workers send results between processes).
"""

from __future__ import annotations

from typing import Optional

__all__ = ["events_dict", "meta_dict", "records_dict", "run_data"]


def records_dict(records) -> dict:
    """The records a ``_core.RunRecords`` holds, by name (only those the run made)."""
    return {name: getattr(records, name) for name in records.fields}


def events_dict(events) -> dict:
    """The saturation onsets of a ``_core.RunEvents`` under their record names."""
    return {
        "saturation_t": events.saturation_t,
        "saturation_actuator": events.saturation_actuator,
        "saturation_kind": events.saturation_kind,
    }


def run_data(result) -> dict:
    """The records and saturation onsets of a ``_core.RunResult``: the data of a Trajectory."""
    data = records_dict(result.records)
    data.update(events_dict(result.events))
    return data


def meta_dict(meta) -> Optional[dict]:
    """A ``_core.RunMeta`` as the run-description dict (``Trajectory.meta`` less ``duration``
    and ``robot``, which the caller adds); ``None`` stays ``None`` (a failed rollout)."""
    if meta is None:
        return None
    drift = meta.drift  # a new list at each read: read once
    return {
        "mode": meta.mode,
        "integrator": meta.integrator,
        "dt": meta.dt,
        "rtol": meta.rtol,
        "atol": meta.atol,
        "controller": meta.controller,
        "conserved": [d.quantity for d in drift],
        "drift": {d.quantity: d.drift for d in drift},
        "drift_scales": {d.quantity: d.scale for d in drift},
        "n_steps": meta.n_steps,
        "n_rejected": meta.n_rejected,
        "n_rhs_evals": meta.n_rhs_evals,
        "actuator_names": list(meta.actuator_names),
        "wheel_dofs": list(meta.wheel_dofs),
        "tracking_error_kind": meta.tracking_error_kind,
        "record_every": meta.record_every,
        "record_dtype": meta.record_dtype,
        "joint_limits": meta.joint_limits,
        "dropped_base_wrench": {"max_norm": meta.dropped_base_wrench_max_norm, "count": meta.dropped_base_wrench_count},
    }
