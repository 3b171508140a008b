"""spacearm.identify: the momentum regressor against the core's momentum of the combined model
(body sums, an independent computation), noise-free recovery of a payload attached with
attach_payload on spatial6 and ETS-VII from a floating simulation with nonzero momentum, the
identifiability report on a motion that cannot determine the inertia, the covariance against
the scatter of estimates under noise, and bad input."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import spacearm
from spacearm.errors import ArgumentError, NonPhysicalInertiaWarning, NotFoundError, ShapeError, SingularError, SpacearmTypeError
from spacearm.identify import identify_payload, momentum_regressor, to_parameters

# A payload whose own axes are turned in the gripper frame, so its inertia there is a full tensor.
MASS, COM, MOMENTS, RPY = 40.0, np.array([0.4, 0.05, -0.02]), np.array([2.0, 3.0, 4.5]), (0.3, -0.2, 0.5)
INERTIA_IN_GRIPPER = Rotation.from_euler("xyz", RPY).as_matrix() @ np.diag(MOMENTS) @ Rotation.from_euler("xyz", RPY).as_matrix().T


def robot_and_combined(preset: str):
    """The preset and the preset with the payload on link 6 ("ets7-published": ETS-VII with its
    published inertias, which break the triangle inequality)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NonPhysicalInertiaWarning)
        robot = spacearm.presets.get(preset.removesuffix("-published"), allow_nonphysical_inertia=preset.endswith("-published"))
        builder = spacearm.RobotBuilder.from_robot(robot)
        combined = builder.attach_payload("target", body="link6", mass=MASS, inertia=MOMENTS, origin=COM, rpy=RPY).build()
    return robot, combined


def floating_run(combined, seconds=4.0):
    """Torque-free floating motion with nonzero linear and angular momentum."""
    u0 = combined.zero_velocity()
    u0[:6] = [0.01, 0.02, -0.01, 0.02, -0.01, 0.03]
    u0[6:] = [0.3, -0.25, 0.35, 0.4, -0.3, 0.5]
    x0 = combined.neutral_configuration(r0=(0.5, -0.3, 0.2))
    return spacearm.simulate(combined, seconds, x0=x0, u0=u0, integrator="dopri5", rtol=1e-12, atol=1e-12, dt=0.02)


@pytest.mark.parametrize("preset", ["spatial6", "ets7"])
def test_regressor_is_the_payload_momentum(preset):
    robot, combined = robot_and_combined(preset)
    rng = np.random.default_rng(1)
    xs = np.array([combined.neutral_configuration(q=rng.uniform(-2, 2, 6), r0=rng.normal(size=3),
                                                  quat0=Rotation.random(random_state=k).as_quat()) for k in range(5)])
    us = rng.normal(size=(5, combined.nu))
    y = momentum_regressor(robot, robot.body_index("link6"), xs, us)
    pi = to_parameters(MASS, COM, INERTIA_IN_GRIPPER)
    for k in range(5):
        whole, arm = combined.momentum(xs[k], us[k]), robot.momentum(xs[k], us[k])
        expected = np.r_[whole.P - arm.P, whole.L_origin - arm.L_origin]
        np.testing.assert_allclose(y[k] @ pi, expected, rtol=1e-12, atol=1e-10 * np.abs(expected).max())


@pytest.mark.parametrize("preset", ["spatial6", "ets7", "ets7-published"])
def test_noise_free_recovery(preset):
    robot, combined = robot_and_combined(preset)
    traj = floating_run(combined)
    est = identify_payload(robot, traj, body="link6")
    assert est.identifiable and est.rank == 10 and np.isfinite(est.condition_number)
    assert abs(est.mass - MASS) / MASS < 1e-8
    assert np.abs(est.com - COM).max() / np.abs(COM).max() < 1e-8
    assert np.abs(est.inertia - INERTIA_IN_GRIPPER).max() / np.abs(INERTIA_IN_GRIPPER).max() < 1e-8
    # The estimated momentum is the combined system's (nonzero) momentum.
    h = combined.momentum(traj.x[0], traj.u[0])
    expected = np.r_[h.P, h.L_origin]
    assert np.abs(expected).min() > 1e-3
    np.testing.assert_allclose(est.momentum, expected, rtol=1e-8, atol=1e-8 * np.abs(expected).max())
    # Given that momentum, the same estimate.
    given = identify_payload(robot, x=traj.x, u=traj.u, body="link6", momentum=expected)
    assert abs(given.mass - MASS) / MASS < 1e-8 and not given.momentum_estimated


def test_rigid_translation_rank_has_its_closed_form():
    # Joints still, no rotation: the whole system drifts at constant velocity v. The payload's
    # momentum is then constant, m v and m r_g(0) x v - [v]x R_g h (r_g x v does not change), so
    # with the momentum unknown nothing is determined (rank 0), and with it known only m and
    # the two components of h across v (rank 3); the inertia never shows.
    robot, combined = robot_and_combined("spatial6")
    u0 = combined.zero_velocity()
    v = np.array([0.1, -0.05, 0.02])
    u0[:3] = v
    traj = spacearm.simulate(combined, 2.0, u0=u0, dt=0.05)
    unknown = identify_payload(robot, traj, body="link6")
    assert unknown.rank == 0 and unknown.null_space.shape == (10, 10) and not unknown.identifiable
    h = combined.momentum(traj.x[0], traj.u[0])
    known = identify_payload(robot, traj, body="link6", momentum=np.r_[h.P, h.L_origin])
    assert known.rank == 3
    along_v = np.zeros(10)
    along_v[1:4] = robot.forward_kinematics(traj.x[0]).body_to_world[robot.body_index("link6")].T @ v
    expected_null = np.column_stack([np.eye(10)[:, 4:], along_v / np.linalg.norm(along_v)])
    projector = known.null_space @ known.null_space.T
    np.testing.assert_allclose(projector @ expected_null, expected_null, atol=1e-9)
    assert known.identifiable_combinations.shape == (3, 10)
    np.testing.assert_allclose(known.identifiable_combinations @ known.null_space, 0.0, atol=1e-9)
    assert known.parameters[0] == pytest.approx(MASS, rel=1e-9)  # the mass is among what is determined
    with pytest.raises(SingularError, match="determined only 3"):
        known.mass


def test_covariance_matches_the_scatter_under_velocity_noise():
    robot, combined = robot_and_combined("spatial6")
    traj = floating_run(combined, seconds=6.0)
    rng = np.random.default_rng(7)
    masses, stds = [], []
    for _ in range(12):
        noisy_u = traj.u + rng.normal(scale=1e-4, size=traj.u.shape)
        est = identify_payload(robot, x=traj.x, u=noisy_u, body="link6")
        masses.append(est.mass)
        stds.append(est.physical_std[0])
    scatter, predicted = np.std(masses, ddof=1), np.mean(stds)
    assert 0.4 < scatter / predicted < 2.5, (scatter, predicted)
    assert abs(np.mean(masses) - MASS) < 5 * predicted


def test_bad_input():
    robot, combined = robot_and_combined("spatial6")
    traj = spacearm.simulate(combined, 0.2, dt=0.05)
    with pytest.raises(NotFoundError):
        identify_payload(robot, traj, body="no_such_link")
    with pytest.raises(SpacearmTypeError):
        identify_payload("spatial6", traj, body="link6")
    with pytest.raises(ShapeError, match=r"\(K, 13\)"):
        identify_payload(robot, x=traj.x[:, :-1], u=traj.u, body="link6")
    with pytest.raises(ArgumentError, match="not both"):
        identify_payload(robot, traj, x=traj.x, u=traj.u, body="link6")
    with pytest.raises(ArgumentError, match="at least"):
        identify_payload(robot, x=traj.x[:2], u=traj.u[:2], body="link6")
    with pytest.raises(ArgumentError, match="rcond"):
        identify_payload(robot, traj, body="link6", rcond=0.0)
    flying = spacearm.simulate(combined, 0.2, dt=0.05, mode="flying")
    with pytest.raises(ArgumentError, match="conserves"):
        identify_payload(robot, flying, body="link6")


def test_bad_inputs_are_spacearm_errors_not_numpy_or_builtin_ones():
    """Complex arrays, a non-number rcond, a recording without motion and a NaN momentum (issue 26)."""
    robot = spacearm.presets.planar4()
    x = np.tile(robot.neutral_configuration(), (5, 1))
    u = np.zeros((5, robot.nu))
    body = robot.body_names[-1]
    with pytest.raises(spacearm.SpacearmTypeError, match="real numbers"):
        identify_payload(robot, x=x.astype(complex), u=u, body=body)
    with pytest.raises(spacearm.ArgumentError, match="rcond must be a number"):
        identify_payload(robot, x=x, u=u, body=body, rcond="small")
    with pytest.raises(spacearm.SingularError, match="nothing to identify"):
        identify_payload(robot, x=x, u=u, body=body)  # static: the regressor is zero
    with pytest.raises(spacearm.NonFiniteError, match="momentum"):
        identify_payload(robot, x=x, u=u, body=body, momentum=[np.nan] * 6)
