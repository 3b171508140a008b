"""Non-finite arguments of the derivatives are named as given (issue 26)."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm


def test_non_finite_tau_and_base_wrench_are_named_by_the_derivatives():
    """The derivatives joined tau and base_wrench into f and named f (issue 26, "left from the
    last round")."""
    robot = spacearm.presets.planar4()
    x, u = robot.neutral_configuration(), robot.zero_velocity()
    tau = np.zeros(robot.n_dof)
    tau[1] = np.nan
    with pytest.raises(spacearm.NonFiniteError, match="^tau must be finite, but entry 1 is (nan|NaN)"):
        robot.forward_dynamics_derivatives(x, u, tau=tau)
    with pytest.raises(spacearm.NonFiniteError, match="^base_wrench must be finite"):
        robot.forward_dynamics_derivatives(x, u, base_wrench=[0, 0, np.inf, 0, 0, 0])
