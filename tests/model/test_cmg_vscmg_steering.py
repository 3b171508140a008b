"""VSCMG steering in a run (docs/cmg.md, "VSCMG steering"; the core's control/vscmg_steering.rs,
whose unit tests check the weighted minimum-norm inverse itself: the commanded torque to 1e-10 at
the internal singular state, against an SVD solution): a variable-speed pyramid at its internal
singular state δ = (-90°, 0, 90°, 0), the base turning about x, the one direction no gimbal rate
gives momentum along. The SR inverse cannot stop the base there; the VSCMG law does, with the
wheels. From δ = 0 (far from singular states) the VSCMG law is the CMG pseudo-inverse's, the
wheel torques nearly zero as their weight e^{-μ m} ≈ 7e-6 says."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm.control import CmgSteering
from spacearm.errors import ArgumentError

from cmg_models import pyramid_sat  # noqa: E402

W0X = 0.05  # the base's initial rate about x, rad/s
SINGULAR = [-np.pi / 2, 0.0, np.pi / 2, 0.0]


@pytest.fixture(scope="module")
def robot():
    return pyramid_sat(arm=False, variable_speed=True)


def _run(robot, delta0, **law):
    x0 = robot.neutral_configuration()
    for c, d in zip(robot.cmg_dofs.values(), delta0):
        x0[7 + c["gimbal"]] = d
    u0 = robot.cmg_velocity(500.0)
    u0[3] = W0X
    return spacearm.simulate(robot, 1.0, x0=x0, u0=u0, mode="rotation-floating", dt=1e-3,
                             controller=CmgSteering([0, 0, 0, 1], kp=200.0, kd=400.0, **law))


def _torques(robot, traj):
    cmgs = list(robot.cmg_dofs.values())
    return traj.tau[:, [c["rotor"] for c in cmgs]], traj.tau[:, [c["gimbal"] for c in cmgs]]


def test_at_the_internal_singular_state_the_wheels_stop_the_base_where_the_sr_inverse_cannot(robot):
    sr = _run(robot, SINGULAR)
    vs = _run(robot, SINGULAR, wheel_weight=1.0)
    assert sr.cmg_measure[0] < 1e-20 and vs.cmg_measure[0] < 1e-20
    # The SR inverse: (A Aᵀ + λE)⁻¹ x = x/λ and Aᵀ x = 0, so no gimbal moves and the base keeps
    # its rate: it turns W0X · 1 s.
    assert sr.u[-1, 3] == pytest.approx(W0X, rel=1e-9)
    assert np.abs(_torques(robot, sr)[1]).max() < 1e-9
    assert np.degrees(sr.base_rotation_angle[-1]) == pytest.approx(np.degrees(W0X), rel=1e-6)
    # The VSCMG law: the wheels take the base's momentum about x, the base stops within 0.25 s.
    wheels, _ = _torques(robot, vs)
    assert np.abs(wheels).max() > 1.0
    assert np.abs(vs.u[250:, 3]).max() < 0.05 * W0X
    assert vs.base_rotation_angle[-1] < 0.1 * sr.base_rotation_angle[-1]
    # The wheels' torques are internal: the total angular momentum is conserved all the same.
    assert vs.meta["drift"]["L_origin"] < 1e-9


def test_far_from_singular_states_the_wheels_rest_and_the_law_is_the_pseudo_inverse(robot):
    pinv = _run(robot, [0.0] * 4, lambda0=0.0)
    vs = _run(robot, [0.0] * 4, wheel_weight=1.0)
    assert vs.cmg_measure.min() > 1.0  # m = 32/27 at δ = 0
    wheels, gimbals = _torques(robot, vs)
    # W_s = e^{-10 m} ≈ 7e-6, and the wheel's share of the torque W_s |B|²/|A|² ~ 1e-11 more.
    assert np.abs(wheels).max() < 1e-8 * np.abs(gimbals).max()
    np.testing.assert_allclose(vs.u, pinv.u, rtol=1e-10, atol=1e-10)


def test_bad_vscmg_options_are_refused(robot):
    with pytest.raises(ArgumentError, match="not a variable-speed CMG"):
        spacearm.simulate(pyramid_sat(arm=False), 0.01, mode="rotation-floating",
                          controller=CmgSteering([0, 0, 0, 1], kp=1.0, kd=1.0, wheel_weight=1.0))
    with pytest.raises(ArgumentError, match="takes no dither"):
        CmgSteering([0, 0, 0, 1], kp=1.0, kd=1.0, wheel_weight=1.0, dither=0.1)
    with pytest.raises(ArgumentError, match="wheel_mu must be finite and >= 0"):
        CmgSteering([0, 0, 0, 1], kp=1.0, kd=1.0, wheel_weight=1.0, wheel_mu=-1.0)
