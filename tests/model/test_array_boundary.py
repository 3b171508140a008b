"""The array boundary: only real numbers (bool, int, float) cross it, every input vector is
checked for NaN/inf, and a non-finite result computed from finite inputs is raised as
NonFiniteError naming the call, never returned."""

import numpy as np
import pytest

from spacearm import presets
from spacearm.errors import NonFiniteError, QuaternionError, SpacearmTypeError


@pytest.fixture(scope="module")
def robot():
    return presets.spatial6()


@pytest.mark.parametrize("bad, dtype", [
    (lambda a: a + 0j, "complex128"),
    (lambda a: a.astype(object), "object"),
    (lambda a: a.astype("datetime64[s]"), "datetime64"),
    (lambda a: a.astype("timedelta64[s]"), "timedelta64"),
    (lambda a: a.astype(str), "<U"),
])
def test_arrays_that_are_not_real_numbers_are_refused_naming_the_argument(robot, bad, dtype):
    x, u = robot.neutral_configuration(), robot.zero_velocity()
    with pytest.raises(SpacearmTypeError, match=rf"^x must hold real numbers \(bool, int or float\), got an array of dtype .*{dtype[:3]}"):
        robot.mass_matrix(bad(np.round(x)))
    with pytest.raises(SpacearmTypeError, match=r"^u must hold real numbers"):
        robot.bias_forces(x, bad(np.round(u)))
    with pytest.raises(SpacearmTypeError, match=r"^tau must hold real numbers"):
        robot.forward_dynamics(x, u, tau=bad(np.zeros(robot.n_dof)))
    with pytest.raises(SpacearmTypeError, match=r"^qd must hold real numbers"):
        robot.point_twist(x, bad(np.zeros(robot.n_dof)))
    with pytest.raises(SpacearmTypeError, match=r"^q must hold real numbers"):
        robot.neutral_configuration(q=bad(np.zeros(robot.n_dof)))


def test_bool_and_integer_arrays_are_numbers(robot):
    x = robot.neutral_configuration(q=np.zeros(robot.n_dof))
    as_int = x.astype(np.int32)
    assert np.array_equal(robot.mass_matrix(as_int), robot.mass_matrix(x))
    qd = np.array([True, False, True, False, False, True])
    assert np.array_equal(robot.point_twist(x, qd), robot.point_twist(x, qd.astype(float)))


def test_point_twist_checks_qd(robot):
    x = robot.neutral_configuration()
    qd = np.zeros(robot.n_dof)
    qd[2] = np.nan
    with pytest.raises(NonFiniteError, match=r"^qd must be finite, but entry 2 is NaN"):
        robot.point_twist(x, qd)
    with pytest.raises(NonFiniteError, match=r"^P must be finite"):
        robot.point_twist(x, np.zeros(robot.n_dof), P=[0, np.inf, 0])


def test_neutral_configuration_checks_q_and_the_quaternion(robot):
    with pytest.raises(QuaternionError, match="unit quaternion"):
        robot.neutral_configuration(quat0=[0, 0, 0, 2])
    q = np.zeros(robot.n_dof)
    q[1] = np.nan
    with pytest.raises(NonFiniteError, match=r"x must be finite, but entry 8 is NaN"):
        robot.neutral_configuration(q=q)
    # Within the tolerance every other door uses: accepted.
    robot.neutral_configuration(quat0=[0, 0, 0, 1 + 1e-12])


def test_overflowing_results_are_raised_not_returned(robot):
    x = robot.neutral_configuration()
    u = np.zeros(robot.nu)
    u[6:] = 1e200
    with pytest.raises(NonFiniteError, match=r"^forward_dynamics gave a non-finite result .*joint rates of 1e200"):
        robot.forward_dynamics(x, u)
    u[6:] = 1e160
    with pytest.raises(NonFiniteError, match=r"^bias_forces gave a non-finite result"):
        robot.bias_forces(x, u)
    xs = np.array([x] * 4)
    us = np.zeros((4, robot.nu))
    us[2, 6:] = 1e200
    with pytest.raises(NonFiniteError, match=r"^row 2 of the batch: forward_dynamics gave a non-finite result"):
        robot.forward_dynamics(xs, us)
    # The same magnitudes that stay finite are returned.
    u[6:] = 1e10
    assert np.all(np.isfinite(robot.bias_forces(x, u)))


def test_a_nan_offset_is_refused(robot):
    with pytest.raises(NonFiniteError, match="offset"):
        robot.point_position(robot.neutral_configuration(), (1, [0.0, np.nan, 0.0]))
