"""The SPART and SpaceDyn state converters of :mod:`spacearm.interop`.

Independent references: the rotation matrix and quaternion of an axis–angle rotation written
out here (Rodrigues' formula, half-angle quaternion), and the kinetic energy of the system moving
rigidly, summed body by body from forward kinematics and the model's own inertias, with the
angular velocity SPART's way (base frame) and the inertias rotated into that frame.
"""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm import interop
from spacearm.errors import ArgumentError, NonFiniteError, QuaternionError, ShapeError

ATTITUDES = [([0.3, -0.5, 0.8], 1.1), ([1.0, 0.0, 0.0], -2.9), ([0.2, 0.9, -0.4], 0.0), ([0.0, 0.0, 1.0], np.pi)]


def _skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _axis_angle(axis, angle):
    """(quaternion [x, y, z, w], rotation matrix) of a rotation by ``angle`` about ``axis``."""
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    quat = np.concatenate([a * np.sin(angle / 2), [np.cos(angle / 2)]])
    k = _skew(a)
    return quat, np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def _state(robot, axis, angle, seed):
    rng = np.random.default_rng(seed)
    quat, rot = _axis_angle(axis, angle)
    x = np.concatenate([rng.normal(size=3), quat, rng.uniform(-1.5, 1.5, robot.n_dof)])
    u = rng.normal(size=robot.nu)
    return x, u, rot


@pytest.fixture(params=["planar4", "spatial6", "dual_arm"])
def robot(request):
    return spacearm.presets.get(request.param)


@pytest.mark.parametrize("k", range(len(ATTITUDES)))
def test_spart_state_frames(robot, k):
    x, u, rot = _state(robot, *ATTITUDES[k], seed=k)
    s = interop.to_spart_state(robot, x, u)
    np.testing.assert_allclose(s.R0, rot, atol=1e-14)
    np.testing.assert_allclose(s.r0, x[:3], rtol=0, atol=0)
    np.testing.assert_allclose(s.u0[:3], rot.T @ u[3:6], atol=1e-14)  # ω0 in the base frame, first
    np.testing.assert_allclose(s.u0[3:], u[:3], atol=0)  # ṙ0 in the inertial frame
    np.testing.assert_allclose(s.qm, x[7:], atol=0)
    np.testing.assert_allclose(s.um, u[6:], atol=0)
    # the base frame's angular velocity, mapped back by R0, is the inertial one
    np.testing.assert_allclose(s.R0 @ s.u0[:3], u[3:6], atol=1e-14)


@pytest.mark.parametrize("k", range(len(ATTITUDES)))
def test_spart_round_trips(robot, k):
    x, u, _ = _state(robot, *ATTITUDES[k], seed=10 + k)
    x2, u2 = interop.from_spart_state(robot, *interop.to_spart_state(robot, x, u))
    # a quaternion and its negative are the same attitude: compare rotations, then the rest
    np.testing.assert_allclose(spacearm.rotations.quat_to_matrix(x2[3:7]), spacearm.rotations.quat_to_matrix(x[3:7]), atol=1e-14)
    assert abs(abs(np.dot(x2[3:7], x[3:7])) - 1.0) < 1e-14
    np.testing.assert_allclose(np.delete(x2, range(3, 7)), np.delete(x, range(3, 7)), atol=0)
    np.testing.assert_allclose(u2, u, atol=1e-14)
    # and from SPART's side
    rng = np.random.default_rng(k)
    _, rot = _axis_angle(*ATTITUDES[k])
    spart = (rot, rng.normal(size=3), rng.normal(size=robot.n_dof), rng.normal(size=6), rng.normal(size=robot.n_dof))
    back = interop.to_spart_state(robot, *interop.from_spart_state(robot, *spart))
    for got, want in zip(back, spart):
        np.testing.assert_allclose(got, want, atol=1e-14)


def _rigid_energy_spart(robot, s: interop.SpartState) -> float:
    """Kinetic energy of the system moving rigidly (q̇ = 0) from SPART's variables: the base
    angular velocity stays in the base frame and every body inertia is rotated into it."""
    d = robot.describe()
    x = np.concatenate([s.r0, spacearm.rotations.quat_from_matrix(s.R0), s.qm])
    kin = robot.forward_kinematics(x)
    masses = [d["base"]["mass"]] + [link["mass"] for link in d["links"]]
    inertias = [np.asarray(d["base"]["inertia"])] + [np.asarray(link["inertia"]) for link in d["links"]]
    w_base, v0 = s.u0[:3], s.u0[3:]
    energy = 0.0
    for m, inertia, rot_i, r_i in zip(masses, inertias, kin.body_to_world, kin.com_in_world):
        in_base = s.R0.T @ rot_i  # body i's axes seen from the base frame
        d_base = s.R0.T @ (r_i - s.r0)  # body CM from the base CM, base frame
        v_i = v0 + s.R0 @ np.cross(w_base, d_base)
        energy += 0.5 * m * v_i @ v_i + 0.5 * w_base @ (in_base @ inertia @ in_base.T) @ w_base
    return energy


@pytest.mark.parametrize("k", range(len(ATTITUDES)))
def test_spart_velocities_give_the_robots_kinetic_energy(robot, k):
    x, u, _ = _state(robot, *ATTITUDES[k], seed=20 + k)
    u[6:] = 0.0  # rigid motion: the energy is then a sum over bodies of known velocities
    s = interop.to_spart_state(robot, x, u)
    expected = robot.kinetic_energy(x, u)
    assert expected > 1.0  # not a trivially zero motion
    assert _rigid_energy_spart(robot, s) == pytest.approx(expected, rel=1e-12)


def test_spart_energy_check_detects_a_wrong_frame():
    # The same check with ω0 left in the inertial frame must fail: it can tell the frames apart.
    robot = spacearm.presets.spatial6()
    x, u, _ = _state(robot, *ATTITUDES[0], seed=3)
    u[6:] = 0.0
    s = interop.to_spart_state(robot, x, u)
    wrong = s._replace(u0=np.concatenate([u[3:6], u[:3]]))
    assert abs(_rigid_energy_spart(robot, wrong) - robot.kinetic_energy(x, u)) > 1e-3 * robot.kinetic_energy(x, u)


@pytest.mark.parametrize("k", range(len(ATTITUDES)))
def test_spacedyn_state_and_round_trip(robot, k):
    x, u, rot = _state(robot, *ATTITUDES[k], seed=30 + k)
    s = interop.to_spacedyn_state(robot, x, u)
    np.testing.assert_allclose(s.A0, rot, atol=1e-14)
    np.testing.assert_allclose(s.R0, x[:3], atol=0)  # SpaceDyn's R0 is the base CM position
    np.testing.assert_allclose(np.concatenate([s.v0, s.w0, s.qd]), u, atol=0)
    np.testing.assert_allclose(s.q, x[7:], atol=0)
    x2, u2 = interop.from_spacedyn_state(robot, *s)
    assert abs(abs(np.dot(x2[3:7], x[3:7])) - 1.0) < 1e-14
    np.testing.assert_allclose(np.delete(x2, range(3, 7)), np.delete(x, range(3, 7)), atol=0)
    np.testing.assert_allclose(u2, u, atol=0)
    # SpaceDyn and SPART describe the same motion: SPART's body-frame ω0 is A0ᵀ w0
    np.testing.assert_allclose(interop.to_spart_state(robot, x, u).u0[:3], s.A0.T @ s.w0, atol=1e-14)


def test_bad_input_is_refused_with_spacearm_errors():
    robot = spacearm.presets.planar4()
    x, u = robot.neutral_configuration(), np.zeros(robot.nu)
    n = robot.n_dof
    good = (np.eye(3), np.zeros(3), np.zeros(n), np.zeros(6), np.zeros(n))
    with pytest.raises(ArgumentError, match="R0 must be a proper rotation"):
        interop.from_spart_state(robot, np.diag([1.0, 1.0, -1.0]), *good[1:])  # a reflection
    with pytest.raises(ArgumentError, match="R0 must be a proper rotation"):
        interop.from_spart_state(robot, 1.01 * np.eye(3), *good[1:])
    with pytest.raises(ShapeError, match="R0 must be a 3×3"):
        interop.from_spart_state(robot, np.eye(4), *good[1:])
    with pytest.raises(ShapeError, match="u0 must have length 6"):
        interop.from_spart_state(robot, *good[:3], np.zeros(5), good[4])
    with pytest.raises(ShapeError, match="qm must have length 4"):
        interop.from_spart_state(robot, *good[:2], np.zeros(3), *good[3:])
    with pytest.raises(NonFiniteError):
        interop.from_spart_state(robot, *good[:3], np.full(6, np.nan), good[4])
    with pytest.raises(ArgumentError, match="A0 must be a proper rotation"):
        interop.from_spacedyn_state(robot, np.zeros(3), np.zeros((3, 3)), np.zeros(3), np.zeros(3), np.zeros(n), np.zeros(n))
    bad_x = x.copy()
    bad_x[3:7] = [0.0, 0.0, 0.0, 2.0]
    with pytest.raises(QuaternionError):
        interop.to_spart_state(robot, bad_x, u)
    with pytest.raises(ShapeError, match="u must have length"):
        interop.to_spacedyn_state(robot, x, np.zeros(3))
