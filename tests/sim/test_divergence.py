"""A run whose integration lost the motion is an error, not a normal-looking result."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm


def test_a_step_far_too_long_is_a_divergence_error():
    robot = spacearm.presets.spatial6()
    u0 = robot.zero_velocity()
    u0[6:] = 1.0
    # RK4 at dt = 5 s keeps every state finite (positions of ~1e113 m) while the momenta,
    # conserved in floating mode, overflow: refused.
    with pytest.raises(spacearm.SimulationError, match="diverged"):
        spacearm.simulate(robot, 10.0, dt=5.0, u0=u0)


def test_an_accurate_run_is_returned_with_its_small_drift():
    robot = spacearm.presets.spatial6()
    u0 = robot.zero_velocity()
    u0[6:] = 1.0
    traj = spacearm.simulate(robot, 1.0, dt=0.01, u0=u0)
    # the drift the check reads, computed here from the records with the simulator's scales
    P = traj["P"]
    scale = traj.meta["drift_scales"]["P"]
    assert np.max(np.linalg.norm(P - P[0], axis=1)) / max(np.linalg.norm(P[0]), scale) == pytest.approx(traj.meta["drift"]["P"], rel=1e-12)
    assert traj.meta["drift"]["P"] < 1e-4  # RK4 error, far below the divergence bound (0.1)
