"""``spacearm.rotations`` computes through the core (``_core.quat_multiply`` and the others of
``crates/spacearm-py/src/rotations_py.rs``): on random batches every helper equals scipy's
``Rotation`` (an independent implementation) to rounding, a batch equals its rows one by one
bit for bit, and the half turns that the former numpy ``rotation_vector`` got wrong are right."""

from __future__ import annotations

import math

import numpy as np
import pytest

import spacearm
from spacearm import _core, rotations

Rotation = pytest.importorskip("scipy.spatial.transform").Rotation

N = 500
ROT = Rotation.random(N, random_state=11)
OTHER = Rotation.random(N, random_state=12)


def _same_rotation(q, expected):
    """q equals expected or -expected, row by row (scipy does not fix the sign of w)."""
    q, expected = np.atleast_2d(q), np.atleast_2d(expected)
    sign = np.where(np.sum(q * expected, axis=-1, keepdims=True) < 0, -1.0, 1.0)
    return float(np.max(np.abs(q - sign * expected)))


def test_products_and_matrices_match_scipy_on_random_batches():
    q, p = ROT.as_quat(), OTHER.as_quat()
    assert _same_rotation(rotations.quat_multiply(q, p), (ROT * OTHER).as_quat()) < 1e-15
    assert _same_rotation(rotations.quat_multiply(q, p[3]), (ROT * OTHER[3]).as_quat()) < 1e-15
    np.testing.assert_allclose(rotations.quat_to_matrix(q), ROT.as_matrix(), rtol=0, atol=1e-15)
    back = rotations.quat_from_matrix(ROT.as_matrix())
    assert back.shape == (N, 4) and np.all(back[:, 3] >= 0)
    assert _same_rotation(back, ROT.as_quat()) < 1e-15


def test_exponential_logarithm_and_rotation_vector_match_scipy():
    theta = ROT.as_rotvec()
    for k in range(0, N, 5):
        assert _same_rotation(rotations.quat_exp(theta[k]), ROT[k].as_quat()) < 1e-15
        np.testing.assert_allclose(rotations.quat_log(ROT[k].as_quat()), theta[k], rtol=0, atol=2e-15)
        np.testing.assert_allclose(rotations.rotation_vector(ROT[k].as_matrix()), theta[k], rtol=0, atol=2e-15)
    for rpy in np.random.default_rng(3).uniform(-3, 3, size=(50, 3)):
        expected = Rotation.from_euler("ZYX", rpy[::-1]).as_quat()
        assert _same_rotation(rotations.quat_from_rpy(*rpy), expected) < 1e-15


def test_a_batch_is_its_rows_bit_for_bit():
    q, p, m = ROT.as_quat(), OTHER.as_quat(), ROT.as_matrix()
    assert np.array_equal(rotations.quat_multiply(q, p), np.array([rotations.quat_multiply(a, b) for a, b in zip(q, p)]))
    assert np.array_equal(rotations.quat_to_matrix(q), np.array([rotations.quat_to_matrix(a) for a in q]))
    assert np.array_equal(rotations.quat_from_matrix(m), np.array([rotations.quat_from_matrix(a) for a in m]))
    v = np.random.default_rng(4).normal(size=(6, 5, 3))
    assert np.array_equal(rotations.skew(v)[2, 3], rotations.skew(v[2, 3]))
    assert rotations.quat_from_matrix(np.zeros((0, 3, 3))).shape == (0, 4)
    assert rotations.quat_to_matrix(np.zeros((0, 4))).shape == (0, 3, 3)
    # Non-contiguous rows are read in order.
    assert np.array_equal(_core.quat_to_matrix(q[::2]), rotations.quat_to_matrix(q)[::2])


def test_half_turns_and_tiny_rotations():
    for axis in range(3):
        r = -np.eye(3)
        r[axis, axis] = 1.0
        expected = np.zeros(3)
        expected[axis] = math.pi
        np.testing.assert_allclose(np.abs(rotations.rotation_vector(r)), expected, rtol=0, atol=1e-15)
    near = Rotation.from_rotvec([0.0, 0.0, math.pi - 1e-7])
    np.testing.assert_allclose(rotations.rotation_vector(near.as_matrix()), near.as_rotvec(), rtol=0, atol=1e-14)
    tiny = Rotation.from_rotvec([1e-5, -2e-6, 3e-7])
    np.testing.assert_allclose(rotations.rotation_vector(tiny.as_matrix()), tiny.as_rotvec(), rtol=1e-10, atol=0)


def test_batch_matrices_are_checked_row_by_row():
    good = ROT[:3].as_matrix()
    bad = good.copy()
    bad[1] = np.diag([1.0, 1.0, -1.0])
    with pytest.raises(spacearm.ArgumentError, match="det R = -1"):
        rotations.quat_from_matrix(bad)
    bad = good.copy()
    bad[2, 0, 0] = math.nan
    with pytest.raises(spacearm.NonFiniteError, match="finite"):
        rotations.quat_from_matrix(bad)
    with pytest.raises(spacearm.ShapeError, match=r"3x3 rotation matrix \(or \(B, 3, 3\) rows of them\)"):
        rotations.quat_from_matrix(np.zeros((2, 2, 3, 3)))
    with pytest.raises(spacearm.ShapeError, match="3x3"):
        rotations.rotation_vector(good)  # one matrix only
    with pytest.raises(spacearm.ShapeError, match=r"a and b must have the same number of rows"):
        rotations.quat_multiply(ROT[:3].as_quat(), ROT[:2].as_quat())


def test_the_bindings_check_shapes():
    with pytest.raises(spacearm.ShapeError, match=r"q must have shape \(4,\) or \(B, 4\), got \(3,\)"):
        _core.quat_to_matrix(np.zeros(3))
    with pytest.raises(spacearm.ShapeError, match=r"r must have shape \(3, 3\) or \(B, 3, 3\)"):
        _core.quat_from_matrix(np.zeros((3, 4)))
