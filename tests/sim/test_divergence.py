"""A run whose integration lost the motion is an error, not a normal-looking result."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from cmg_models import pyramid_sat  # tests/ is on the path (conftest.py)


def test_a_step_far_too_long_is_refused():
    robot = spacearm.presets.spatial6()
    u0 = robot.zero_velocity()
    u0[6:] = 1.0
    # RK4 at dt = 5 s kept every state finite (positions of ~1e113 m) while the momenta,
    # conserved in floating mode, overflowed: refused before the first step, with the limit.
    with pytest.raises(spacearm.SimulationError, match="fastest mode"):
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


def _rk4_excess(z):
    """|R(z)| / max(1, |e^z|) for RK4's stability function R (Hairer & Wanner II, IV.2)."""
    r = 1 + z + z**2 / 2 + z**3 / 6 + z**4 / 24
    return np.abs(r) / np.maximum(1.0, np.exp(z.real))


def test_a_step_longer_than_the_fastest_pd_mode_allows_is_refused_before_it_runs():
    # Independent estimate of the fastest mode: at rest on its set point, the PD-controlled arm
    # of a free-floating robot moves by q̈ = -H*⁻¹ (kp q + kd q̇) (H* the generalized inertia,
    # eq. 45); its eigenvalues and RK4's stability function give the longest stable step.
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    n = robot.n_dof
    kp, kd = 400.0, 4.0
    m_inv = np.linalg.inv(robot.generalized_inertia(x0))
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-kp * m_inv, -kd * m_inv]])
    lam = np.linalg.eigvals(a)
    grid = np.geomspace(1e-4, 1.0, 4000)
    too_long = np.array([np.any(_rk4_excess(lam * h) > 1.01) for h in grid])
    dt_max = grid[np.argmax(too_long)]
    assert 1e-3 < dt_max < 0.5  # a limit inside the grid: the gains set it
    controller = spacearm.control.JointPD(kp=kp, kd=kd, reference=list(x0[7:]))
    u0 = robot.zero_velocity()
    u0[6:] = 1e-6  # the linear regime
    with pytest.raises(spacearm.SimulationError, match=r"fastest mode .* use dt <= ") as err:
        spacearm.simulate(robot, 40 * dt_max, dt=1.05 * dt_max, x0=x0, u0=u0, controller=controller)
    # the limit the message gives is the independent one, to the grid's resolution
    given = float(str(err.value).split("use dt <= ")[1].split(" s")[0])
    assert given == pytest.approx(dt_max, rel=0.01)
    traj = spacearm.simulate(robot, 40 * dt_max, dt=0.95 * dt_max, x0=x0, u0=u0, controller=controller)
    assert np.all(np.isfinite(traj["x"]))


def test_a_step_the_start_allows_but_the_motion_outgrows_is_a_drift_error():
    robot = spacearm.presets.spatial6()
    u0 = robot.zero_velocity()
    u0[6:] = 1.0
    # dt = 0.1 s passes the fastest-mode check at t = 0 (limit 0.45 s) but the motion speeds
    # up; the angular momentum then drifts by more than DIVERGED_DRIFT = 0.1: refused.
    with pytest.raises(spacearm.SimulationError, match="diverged: the L_origin drifted"):
        spacearm.simulate(robot, 3.0, dt=0.1, u0=u0)


def test_rotors_spinning_on_a_base_at_rest_are_not_a_divergence():
    # A CMG pyramid's rotors spinning at 500 rad/s on a base at rest, free floating: P is zero
    # from two terms per rotor that cancel (the velocity of its point at the base CM and
    # ω × (r − r0)); measured against Σ|pᵢ| = 0 its rounding (1e-15 N·s) read as a drift of 1.0
    # and the run was refused as diverged. The scale is now those terms' sizes.
    robot = pyramid_sat(arm=False)
    u0 = robot.cmg_velocity([500.0, 300.0, 400.0, 200.0])  # unequal: the cluster holds 7 N·m·s
    traj = spacearm.simulate(robot, 0.5, dt=0.01, u0=u0)
    P = traj["P"]
    assert np.max(np.abs(P)) < 1e-9  # P stays zero (rounding)
    scale = traj.meta["drift_scales"]["P"]
    assert scale > 1.0  # 4 rotors × 3 kg × 500 rad/s × their offsets from the base CM, twice
    assert traj.meta["drift"]["P"] < 1e-12
    # The spinning rotors hold their momentum, constant: J_s (200 − 300, 500 − 400, 0).
    L = traj["L_com"]
    assert np.allclose(L[0], [-5.0, 5.0, 0.0], atol=1e-12)
    assert np.max(np.linalg.norm(L - L[0], axis=1)) / np.linalg.norm(L[0]) < 1e-9
