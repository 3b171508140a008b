"""Target states and steps are checked like every other input (issue 38): non-finite parts,
non-unit quaternions, wrong shapes, bool steps, unbounded durations and a propagation that
overflows are refused with spacearm.errors, never returned as NaN or raised as a builtin."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm import errors


@pytest.fixture
def target():
    return spacearm.Target(100.0, [10.0, 12.0, 14.0])


@pytest.mark.parametrize("kw, error", [
    (dict(position=(np.inf, 0, 0)), errors.NonFiniteError),
    (dict(velocity=(np.nan, 0, 0)), errors.NonFiniteError),
    (dict(angular_velocity=(0, -np.inf, 0)), errors.NonFiniteError),
    (dict(quaternion=(0, 0, 0, 2)), errors.QuaternionError),
    (dict(position=(1.0, 2.0)), errors.ShapeError),
    (dict(velocity=[[1.0, 2.0, 3.0]]), errors.ShapeError),
    (dict(angular_velocity=(1j, 0, 0)), errors.SpacearmTypeError),
])
def test_target_state_refuses_invalid_parts(target, kw, error):
    # Before: an infinite position, a NaN velocity and a norm-2 quaternion were accepted.
    with pytest.raises(error):
        target.state(**kw)


def test_state_in_orbit_refuses_a_non_finite_angular_velocity(target):
    orbit = spacearm.Orbit.circular(500e3)
    with pytest.raises(errors.NonFiniteError):
        target.state_in_orbit(orbit, [0, 10.0, 0, 0, 0, 0], angular_velocity=(np.nan, 0, 0))


@pytest.mark.parametrize("kw, error", [
    (dict(duration=1.0, dt=np.inf), errors.ArgumentError),
    (dict(duration=1.0, dt=-1e-3), errors.ArgumentError),
    (dict(duration=1.0, dt=True), errors.SpacearmTypeError),
    (dict(duration=np.inf), errors.ArgumentError),
    (dict(duration=-1.0), errors.ArgumentError),
])
def test_propagate_refuses_invalid_steps(target, kw, error):
    with pytest.raises(error):
        target.propagate(target.state(), **kw)


def test_a_propagation_that_overflows_is_refused_not_nan(target):
    # Before: a state with a finite but huge angular velocity propagated to NaN.
    s = target.state(angular_velocity=(1e300, 0, 0))
    with pytest.raises(errors.SimulationError, match="left the finite numbers"):
        target.propagate(s, 1.0)


def test_trajectory_refuses_an_infinite_or_unbounded_duration(target):
    s = target.state()
    # Before: OverflowError (inf) and MemoryError (1e15 samples).
    with pytest.raises(errors.ArgumentError, match="finite"):
        target.trajectory(s, np.inf, 0.1)
    with pytest.raises(errors.ResourceLimitError, match="samples"):
        target.trajectory(s, 1e12, 1e-3)
    t, states = target.trajectory(s, 0.2, 0.1)
    assert states.shape == (3, 13) and np.all(np.isfinite(states))
