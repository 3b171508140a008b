"""The fills a slosh model describes (issue 38): a full cylinder has no free surface and does
not slosh (refused, as a full sphere is), and a fill shallower than MIN_FILL_DEPTH_RATIO of the
radius has no slosh modes the models describe (refused, instead of a pendulum of 7e298 m)."""

from __future__ import annotations

import pytest

import spacearm
from spacearm import errors
from spacearm.model.slosh import slosh_parameters


def cylinder(**kw):
    args = dict(radius=0.5, axial_acceleration=0.1, tank_height=2.0, density=1000.0)
    args.update(kw)
    return slosh_parameters("cylinder", **args)


def test_a_full_cylinder_does_not_slosh():
    # Before: fill_fraction=1.0 gave a 178 kg slosh mode.
    with pytest.raises(errors.ArgumentError, match="full tank has no free surface"):
        cylinder(fill_fraction=1.0)
    assert cylinder(fill_fraction=0.999).modes[0].mass > 0


@pytest.mark.parametrize("tank, kw", [
    ("cylinder", dict(fill_fraction=1e-300, tank_height=2.0)),
    ("cylinder", dict(fill_height=4e-5)),
    ("sphere", dict(fill_fraction=1e-300)),
    ("sphere", dict(fill_height=4e-5)),
])
def test_a_fill_too_shallow_for_slosh_modes_is_refused(tank, kw):
    # Before: the cylinder at fill_fraction=1e-300 got a pendulum of about 7e298 m.
    with pytest.raises(errors.ArgumentError, match="below 1e-4 of the tank radius"):
        slosh_parameters(tank, radius=0.5, axial_acceleration=0.1, density=1000.0, **kw)


def test_the_shallowest_fill_described_is_the_stated_bound():
    # At h = 1e-4 R exactly the cylinder's first pendulum is R / (xi tanh(xi h/R)) ~ 2950 R.
    p = cylinder(fill_height=0.5e-4)
    assert 2900 * 0.5 < p.modes[0].length < 3000 * 0.5


def test_the_core_states_the_cylinder_fill_rule():
    assert spacearm._core.cylinder_fill_height(2.0, 0.25) == 0.5
    with pytest.raises(errors.ArgumentError, match="below 1"):
        spacearm._core.cylinder_fill_height(2.0, 1.0)
