"""Orbit doors (issue 38): a circular orbit below the surface or of a bool altitude is refused,
the propagation's step budget is named and stated when spent, and tidal_torques takes a Robot."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm import errors


@pytest.mark.parametrize("altitude", [-100e3, 0.0, -6378137.0 + 1.0])
def test_a_circular_orbit_at_or_below_the_surface_is_refused(altitude):
    # Before: accepted down to the body's centre.
    with pytest.raises(errors.ArgumentError, match="above the central body's surface"):
        spacearm.Orbit.circular(altitude)


@pytest.mark.parametrize("altitude", [True, False, np.True_])
def test_a_bool_is_not_an_altitude(altitude):
    # Before: circular(True) was an orbit 1 m above the surface.
    with pytest.raises(errors.SpacearmTypeError, match="bool"):
        spacearm.Orbit.circular(altitude)


def test_a_propagation_past_its_step_budget_says_where_it_stopped():
    # Before: about 100 million steps (minutes) before any answer.
    orbit = spacearm.Orbit.circular(500e3)
    with pytest.raises(errors.SimulationError, match=r"budget of \d+ DOPRI5 steps .*ORBIT_MAX_STEPS.* reached only t = "):
        orbit.propagate([1e12])
    r, v = orbit.propagate([0.0, orbit.period])
    np.testing.assert_allclose(r[1], r[0], atol=1e-3)


def test_tidal_torques_takes_a_robot_as_documented():
    robot = spacearm.presets.spatial6()
    orbit = spacearm.Orbit.circular(500e3)
    x = robot.neutral_configuration()
    by_robot = orbit.tidal_torques(robot, x)
    by_model = orbit.tidal_torques(robot.core_model, x)
    for a, b in zip(by_robot, by_model):
        np.testing.assert_array_equal(a, b)
    with pytest.raises(errors.SpacearmTypeError, match="Robot"):
        orbit.tidal_torques("spatial6", x)
