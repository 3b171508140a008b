"""Momentum unloading of a CMG cluster with the thrusters (docs/cmg.md, "Momentum unloading"; the
core's control/cmg_unloading.rs through CmgSteering): a pyramid holding 0.71 of its envelope
along z, the base at rest, unloads under N_u = -k (H - H_goal) while the cluster holds the
attitude: the total angular momentum changes by exactly the thrusters' angular impulse (the
ledger), the cluster's momentum decays as the first-order closed form H0 e^{-k t}, the attitude
stays held, and the switch follows its hysteresis."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import simpson
from scipy.spatial.transform import Rotation

import spacearm
from spacearm.control import CmgSteering
from spacearm.errors import ArgumentError

from cmg_models import BETA, J_S, pyramid_axes, pyramid_sat, rodrigues  # noqa: E402

K = 1.5  # the unloading gain, 1/s
DELTA0 = np.pi / 4  # every gimbal at 45°: H = 4 h sin β sin δ along z, 0.71 of the envelope there
SPEED = 500.0  # rotor speed, rad/s (h = J_S · 500 = 25 N m s)


@pytest.fixture(scope="module")
def robot():
    return pyramid_sat(arm=False)


def _start(robot):
    x0 = robot.neutral_configuration()
    for c in robot.cmg_dofs.values():
        x0[7 + c["gimbal"]] = DELTA0
    return x0, robot.cmg_velocity(SPEED)


def _law(**kw):
    return CmgSteering([0, 0, 0, 1], kp=2000.0, kd=2000.0, unload_gain=K, **kw)


def _cluster_momentum(robot, traj):
    """H = Σ h_i ŝ_i from the recorded states (the spin axes turned by the base attitude and the
    gimbal angles; h_i the rotor's absolute spin momentum), independently of the core."""
    g0, s0 = pyramid_axes()
    cmgs = list(robot.cmg_dofs.values())
    out = []
    for x, u in zip(traj.x, traj.u):
        r0 = Rotation.from_quat(x[3:7]).as_matrix()
        s = [r0 @ rodrigues(gi, x[7 + c["gimbal"]]) @ si for gi, si, c in zip(g0, s0, cmgs)]
        out.append(sum(J_S * (si @ u[3:6] + u[6 + c["rotor"]]) * si for si, c in zip(s, cmgs)))
    return np.array(out)


@pytest.fixture(scope="module")
def unloading(robot):
    x0, u0 = _start(robot)
    return spacearm.simulate(robot, 1.0, x0=x0, u0=u0, mode="rotation-flying", controller=_law(unload_above=0.5, unload_below=0.05),
                             integrator="dopri5", dt=1e-3, rtol=1e-12, atol=1e-14)


def test_the_total_angular_momentum_changes_by_the_thrusters_angular_impulse(unloading):
    traj = unloading
    torque = traj.base_wrench[:, 3:]
    assert np.all(traj.base_wrench[:, :3] == 0.0)  # a pure torque: the moment about O is N_u
    assert np.linalg.norm(torque[0]) > 10.0  # on from the start (0.71 ≥ 0.5)
    impulse = np.array([simpson(torque[:, i], x=traj.t) for i in range(3)])
    change = traj.L_origin[-1] - traj.L_origin[0]
    assert np.linalg.norm(change) > 0.5 * np.linalg.norm(traj.L_origin[0])  # most of it unloaded
    assert np.linalg.norm(change - impulse) <= 1e-10 * np.linalg.norm(traj.L_origin[0])


def test_the_cluster_momentum_decays_as_the_closed_form_and_the_attitude_stays_held(robot, unloading):
    traj = unloading
    h = _cluster_momentum(robot, traj)
    h0 = 4 * J_S * SPEED * np.sin(BETA) * np.sin(DELTA0)
    np.testing.assert_allclose(h[0], [0.0, 0.0, h0], atol=1e-12 * h0)
    assert traj.cmg_envelope_fraction[0] == pytest.approx(np.sin(DELTA0), rel=1e-12)
    # The law, with the base held: Ḣ = N_u = -k H, so H(t) = H(t1) e^{-k (t - t1)}. It applies
    # once the gimbal rate loop (bandwidth 50 1/s) and the attitude loop have taken up the
    # thrusters' torque, which starts at its full -k H0 while the gimbals are at rest (the base
    # takes 1.6 % of H0 for a few hundredths of a second); from t1 = 0.2 s, the gimbal bodies'
    # own momentum I_g δ̇ (~1e-3 of H, not counted in H) is what is left (2.9e-4 H0 found).
    k1 = int(np.searchsorted(traj.t, 0.2))
    expected = h[k1, 2] * np.exp(-K * (traj.t[k1:] - traj.t[k1]))
    assert np.abs(h[k1:, 2] - expected).max() <= 1e-3 * h0
    assert h[-1, 2] < 0.3 * h0 and np.abs(h[:, :2]).max() < 1e-9 * h0
    # And the recorded torque is -k H of the same states.
    np.testing.assert_allclose(traj.base_wrench[:, 3:], -K * h, atol=1e-9 * h0)
    assert np.degrees(traj.base_rotation_angle.max()) < 0.1


def test_the_switch_follows_its_hysteresis(robot):
    """RK4 with a sample per step: each step starts by deciding from the envelope fraction of its
    starting state (on at >= 0.6, off at <= 0.3), and the sample there records the decision; the
    last sample, at the end of the last step, that step's."""
    x0, u0 = _start(robot)
    traj = spacearm.simulate(robot, 1.5, x0=x0, u0=u0, mode="rotation-flying", controller=_law(unload_above=0.6, unload_below=0.3), dt=2e-3)
    on = np.linalg.norm(traj.base_wrench[:, 3:], axis=1) > 0
    f = traj.cmg_envelope_fraction
    state, expected = False, []
    for k in range(len(f) - 1):
        state = True if f[k] >= 0.6 else (False if f[k] <= 0.3 else state)
        expected.append(state)
    expected.append(state)
    np.testing.assert_array_equal(on, expected)
    off = int(np.argmin(on))
    assert 0 < off < len(on) - 10 and not on[off:].any()  # it switched off once and stayed off
    assert f[off] <= 0.3 < f[off - 1]
    # Off, nothing is unloaded any more: the total momentum stays where it was.
    np.testing.assert_allclose(traj.L_origin[off:], np.broadcast_to(traj.L_origin[off], traj.L_origin[off:].shape), atol=1e-6)


def test_bad_unloading_options_are_refused(robot):
    x0, u0 = _start(robot)
    with pytest.raises(ArgumentError, match="rotation-flying"):
        spacearm.simulate(robot, 0.01, x0=x0, u0=u0, mode="rotation-floating", controller=_law())
    with pytest.raises(ArgumentError, match="unload_below < unload_above"):
        _law(unload_above=0.3, unload_below=0.5)
    with pytest.raises(ArgumentError, match="unload_gain must be finite and > 0"):
        CmgSteering([0, 0, 0, 1], kp=1.0, kd=1.0, unload_gain=-1.0)
    with pytest.raises(ArgumentError, match="rotation-floating"):  # without unloading, as before
        spacearm.simulate(robot, 0.01, x0=x0, u0=u0, mode="rotation-flying", controller=CmgSteering([0, 0, 0, 1], kp=1.0, kd=1.0))
