"""A flexibility distribution that can draw values every sample would fail on is refused when
the Flexibility is made (issue 38), instead of every such sample failing silently."""

from __future__ import annotations

import pytest

from spacearm import errors
from spacearm.campaign import Fixed, Flexibility, LogNormal, Normal, Panel, Tank, Uniform

TANK = Tank(radius=0.5, height=2.0, density=1000.0, axial_acceleration=0.1)
PANEL = Panel((0, 0, 0), (0, 0, 1), (1, 0, 0), 5.0, (1.0, 0.5, 0.01))


@pytest.mark.parametrize("kw, match", [
    (dict(fill_fraction=Uniform(0.5, 1.2)), r"fill_fraction: Uniform\(low=0.5, high=1.2\) draws values in \[0.5, 1.2\], outside"),
    (dict(fill_fraction=Uniform(-0.1, 0.5)), "fill_fraction"),
    (dict(fill_fraction=Normal(0.5, 0.1)), r"draws values in \(-inf, inf\)"),
    (dict(fill_fraction=LogNormal(0.5, 0.2)), "fill_fraction"),
    (dict(fill_fraction=Fixed(1.0)), "fill_fraction"),
    (dict(fill_fraction=1.5), "fill_fraction"),
    (dict(slosh_frequency_scale=Normal(1.0, 0.1)), "slosh_frequency_scale"),
    (dict(slosh_frequency_scale=Uniform(0.0, 2.0)), "slosh_frequency_scale"),
    (dict(slosh_damping_ratio=Uniform(0.0, 1.0)), "slosh_damping_ratio"),
    (dict(slosh_damping_ratio=LogNormal(0.01, 0.5)), "slosh_damping_ratio"),
    (dict(fill_fraction=Uniform(1e-300, 0.5)), "which the tank refuses"),
])
def test_a_tank_distribution_outside_its_domain_is_refused(kw, match):
    # Before: accepted; every sample drawn outside (0, 1) failed in the run.
    with pytest.raises(errors.ArgumentError, match=match):
        Flexibility(tank=TANK, **kw)


def test_a_panel_stiffness_that_can_be_negative_is_refused():
    with pytest.raises(errors.ArgumentError, match="panel_stiffness"):
        Flexibility(panel=PANEL, panel_stiffness=Normal(10.0, 2.0))
    Flexibility(panel=PANEL, panel_stiffness=LogNormal(10.0, 0.3))


def test_distributions_within_the_domains_are_accepted():
    flex = Flexibility(tank=TANK, fill_fraction=Uniform(0.2, 0.9), slosh_frequency_scale=LogNormal(1.0, 0.1),
                       slosh_damping_ratio=Uniform(0.0, 0.05), panel=PANEL, panel_stiffness=Uniform(5.0, 20.0))
    for i in range(20):
        values = flex.draw(1, i)
        assert 0.2 <= values["fill_fraction"] <= 0.9
