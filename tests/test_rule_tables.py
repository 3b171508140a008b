"""The core's rule tables at the extension boundary (``_core.SIM_DEFAULTS``, ``MODEL_BOUNDS``,
``DLS_DEFAULTS``): typed frozen instances whose values are the rules the core applies, checked
against the core's behaviour at each bound and against the documented defaults, plus the
read-only mapping view the package reads them through."""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest

import spacearm
from spacearm import analysis, control
from spacearm import _core

TABLES = {
    "SIM_DEFAULTS": (_core.SimDefaults, ["mode", "integrator", "dt", "rtol", "atol", "record_every", "joint_limits", "max_steps"]),
    "MODEL_BOUNDS": (_core.ModelBounds, ["min_mass", "max_mass", "max_length", "max_inertia_entry"]),
    "DLS_DEFAULTS": (_core.DlsDefaults, ["threshold", "max_damping"]),
}


@pytest.mark.parametrize("name", sorted(TABLES))
def test_typed_frozen_and_a_read_only_mapping(name):
    table = getattr(_core, name)
    cls, fields = TABLES[name]
    assert isinstance(table, cls)
    assert table.keys() == fields and list(table) == fields and len(table) == len(fields)
    as_dict = dict(table)
    assert as_dict == {f: getattr(table, f) for f in fields}
    assert table == as_dict and as_dict == table and table != {**as_dict, fields[0]: None} and table != 1
    assert all(f in table for f in fields) and "nothing" not in table
    assert repr(table).startswith(cls.__name__ + "(" + fields[0] + "=")
    for f in fields:
        assert table[f] == getattr(table, f)
        with pytest.raises(AttributeError):
            setattr(table, f, getattr(table, f))
    with pytest.raises(spacearm.NotFoundError, match="no field 'nothing'") as info:
        table["nothing"]
    assert isinstance(info.value, KeyError)


def _one_link(base_mass=100.0, mass=5.0, origin=(0.5, 0.0, 0.0), inertia=(0.01, 0.4, 0.4)):
    b = spacearm.Robot.builder("bounds", base_mass=base_mass, base_inertia=[10.0, 10.0, 10.0])
    b.add_link("arm", parent="base", joint="revolute", axis=(0, 0, 1), origin=origin, com=(0.5, 0, 0), mass=mass,
               inertia=inertia)
    return b.build()


def test_model_bounds_are_where_the_builder_refuses():
    """Each bound is accepted and the next float beyond it refused, with the field at fault."""
    bounds = _core.MODEL_BOUNDS
    up, down = math.inf, -math.inf
    cases = [
        (dict(mass=bounds.min_mass), dict(mass=np.nextafter(bounds.min_mass, down)), "mass"),
        (dict(mass=bounds.max_mass), dict(mass=np.nextafter(bounds.max_mass, up)), "mass"),
        (dict(origin=(bounds.max_length, 0, 0)), dict(origin=(np.nextafter(bounds.max_length, up), 0, 0)), "origin"),
        (dict(inertia=[bounds.max_inertia_entry] * 3), dict(inertia=[np.nextafter(bounds.max_inertia_entry, up)] * 3),
         "inertia entry"),
    ]
    for at, beyond, what in cases:
        assert _one_link(**at).n_dof == 1
        with pytest.raises(spacearm.ModelError, match=what):
            _one_link(**beyond)


def test_dls_defaults_are_the_documented_law():
    """docs/singularities.md: ``ε = λ_max = 0.05``; the law damps by λ_max at σ = 0 and not at ε."""
    law = _core.DLS_DEFAULTS
    assert (law.threshold, law.max_damping) == (0.05, 0.05)
    assert analysis.damping(0.0, law.threshold, law.max_damping) == pytest.approx(law.max_damping, rel=1e-15)
    assert analysis.damping(law.threshold, law.threshold, law.max_damping) == 0.0
    rmrc = inspect.signature(control.ResolvedMotionRate).parameters
    assert (rmrc["threshold"].default, rmrc["max_damping"].default) == (law.threshold, law.max_damping)
    detect = inspect.signature(analysis.detect).parameters
    assert (detect["threshold"].default, detect["max_damping"].default) == (law.threshold, law.max_damping)


def test_sim_defaults_types_and_readers():
    d = _core.SIM_DEFAULTS
    assert d.mode in _core.MODES and d.integrator in _core.INTEGRATORS
    assert isinstance(d.dt, float) and d.dt > 0 and isinstance(d.rtol, float) and isinstance(d.atol, float)
    assert type(d.record_every) is int and d.record_every >= 1 and type(d.max_steps) is int and d.max_steps > 0
    assert type(d.joint_limits) is bool
    simulate = inspect.signature(spacearm.simulate).parameters
    for f in d.keys():
        assert simulate[f].default == getattr(d, f), f
    # The public table stays a plain dict of the same values.
    from spacearm.sim.simulation import DEFAULTS

    assert type(DEFAULTS) is dict and DEFAULTS == dict(d)
