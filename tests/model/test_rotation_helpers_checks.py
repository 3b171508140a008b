"""The ``spacearm.rotations`` helpers check their input: a non-unit quaternion, a non-finite
value, a wrong shape or a matrix that is not a rotation is refused with a spacearm error; valid
input gives scipy's result (an independent implementation)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import spacearm
from spacearm import rotations

Rotation = pytest.importorskip("scipy.spatial.transform").Rotation

RNG = np.random.default_rng(7)


def test_valid_input_matches_scipy():
    for _ in range(20):
        rot = Rotation.from_rotvec(RNG.normal(size=3))
        q = rot.as_quat()
        np.testing.assert_allclose(rotations.quat_to_matrix(q), rot.as_matrix(), atol=1e-14)
        back = rotations.quat_from_matrix(rot.as_matrix())
        np.testing.assert_allclose(Rotation.from_quat(back).as_matrix(), rot.as_matrix(), atol=1e-13)
        axis = RNG.normal(size=3)
        angle = float(RNG.uniform(-3, 3))
        expected = Rotation.from_rotvec(axis / np.linalg.norm(axis) * angle).as_matrix()
        np.testing.assert_allclose(rotations.quat_to_matrix(rotations.quat_from_axis_angle(axis, angle)), expected,
                                   atol=1e-14)
    # A quaternion within the tolerance is normalized exactly.
    q = np.array([0.0, 0.0, 0.0, 1.0 + 5e-7])
    np.testing.assert_array_equal(rotations.quat_to_matrix(q), np.eye(3))


@pytest.mark.parametrize("call, error, fragment", [
    (lambda: rotations.quat_to_matrix([0, 0, 0, 2]), spacearm.QuaternionError, "unit quaternion"),
    (lambda: rotations.quat_to_matrix([0, 0, 0, 1 + 2e-6]), spacearm.QuaternionError, "unit quaternion"),
    (lambda: rotations.quat_to_matrix([0, 0, math.nan, 1]), spacearm.NonFiniteError, "finite"),
    (lambda: rotations.quat_to_matrix([0, 0, 1]), spacearm.ShapeError, r"shape \(4,\) or \(B, 4\)"),
    (lambda: rotations.quat_multiply([0, 0, 1], [0, 0, 0, 1]), spacearm.ShapeError, "a must have shape"),
    (lambda: rotations.quat_multiply([0, 0, 0, 1], [0, 0, math.inf, 1]), spacearm.NonFiniteError, "b must be finite"),
    (lambda: rotations.skew([[1, 2]]), spacearm.ShapeError, "3-vector"),
    (lambda: rotations.quat_exp([0, math.nan, 0]), spacearm.NonFiniteError, "theta"),
    (lambda: rotations.rotation_vector(np.diag([1.0, 1.0, -1.0])), spacearm.ArgumentError, "det R = -1"),
    (lambda: rotations.quat_from_axis_angle([0, 0, 0], 1.0), spacearm.ArgumentError, "non-zero"),
    (lambda: rotations.quat_from_axis_angle([0, 0, 1], math.inf), spacearm.NonFiniteError, "angle"),
    (lambda: rotations.quat_from_axis_angle([0, 1], 1.0), spacearm.ShapeError, "length 3"),
    (lambda: rotations.quat_from_rpy(0.1, "x", 0.0), spacearm.ArgumentError, "pitch"),
    (lambda: rotations.quat_from_rpy(0.1, math.nan, 0.0), spacearm.NonFiniteError, "pitch"),
    (lambda: rotations.quat_from_matrix(np.eye(3) * 2), spacearm.ArgumentError, "rotation matrix"),
    (lambda: rotations.quat_from_matrix(np.diag([1.0, 1.0, -1.0])), spacearm.ArgumentError, "det R = -1"),
    (lambda: rotations.quat_from_matrix(np.eye(4)), spacearm.ShapeError, "3x3"),
    (lambda: rotations.quat_from_matrix([[1, 0], [0, 1, 0]]), spacearm.ShapeError, "3x3"),
    (lambda: rotations.quat_from_matrix(np.full((3, 3), math.nan)), spacearm.NonFiniteError, "finite"),
    (lambda: rotations.quat_from_matrix(np.eye(3) + 0j), spacearm.SpacearmTypeError, "real numbers"),
])
def test_bad_input_is_refused(call, error, fragment):
    with pytest.raises(error, match=fragment):
        call()
