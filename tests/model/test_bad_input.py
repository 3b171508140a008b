"""Every bad input of docs/architecture.md raises a spacearm exception that names what was wrong and
what was expected — never a panic, a crash or a silent NaN."""

import numpy as np
import pytest

import spacearm
from spacearm import errors
from spacearm import (
    ModelError,
    NonFiniteError,
    NotFoundError,
    QuaternionError,
    ShapeError,
    SpacearmError,
    SpacearmTypeError,
)

BAR = [0.01, 0.5, 0.5]


def builder():
    return spacearm.Robot.builder("t", base_mass=100.0, base_inertia=[10.0, 12.0, 14.0])


def one_link(**overrides):
    b = builder()
    kw = dict(parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.5, 0, 0), mass=5.0, inertia=BAR)
    kw.update(overrides)
    b.add_link("arm", **kw)
    b.add_point("tip", body="arm", offset=(0.5, 0, 0))
    b.set_end_effector("tip")
    return b.build()


@pytest.fixture
def robot():
    return spacearm.presets.spatial6()


# ---- states ------------------------------------------------------------------------------
def test_configuration_length(robot):
    with pytest.raises(ShapeError, match=r"x must have length 7\+N = 13, got 12"):
        robot.mass_matrix(np.zeros(12))


def test_velocity_length(robot):
    x = robot.neutral_configuration()
    with pytest.raises(ShapeError, match=r"u must have length 6\+N = 12, got 11"):
        robot.bias_forces(x, np.zeros(11))


def test_batch_of_the_wrong_width_is_rejected(robot):
    # A 2-D x is a batch of states, one per row: (13, 1) is 13 states of length 1.
    with pytest.raises(ShapeError, match=r"x must have shape \(B, 13\).*got \(13, 1\)"):
        robot.mass_matrix(np.zeros((13, 1)))


def test_three_dimensional_state_is_rejected(robot):
    with pytest.raises(ShapeError, match="1-D array .* or a 2-D array"):
        robot.mass_matrix(np.zeros((2, 13, 1)))


def test_non_numeric_state_is_rejected(robot):
    with pytest.raises(SpacearmTypeError, match="x must hold real numbers.*dtype <U1"):
        robot.mass_matrix(["a"] * 13)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_configuration(robot, bad):
    x = robot.neutral_configuration()
    x[9] = bad
    with pytest.raises(NonFiniteError, match="x must be finite, but entry 9"):
        robot.mass_matrix(x)


def test_non_finite_velocity(robot):
    x = robot.neutral_configuration()
    u = np.zeros(robot.nu)
    u[2] = np.nan
    with pytest.raises(NonFiniteError, match="u must be finite"):
        robot.forward_dynamics(x, u)


def test_non_finite_torque(robot):
    x = robot.neutral_configuration()
    tau = np.zeros(6)
    tau[0] = np.inf
    with pytest.raises(NonFiniteError):
        robot.forward_dynamics(x, np.zeros(12), tau=tau)
    with pytest.raises(NonFiniteError):
        robot.forward_dynamics(x, np.zeros(12), tau=tau, method="reduced")


def test_non_unit_quaternion(robot):
    x = robot.neutral_configuration()
    x[3:7] = [0.0, 0.0, 0.0, 1.1]
    with pytest.raises(QuaternionError, match=r"unit quaternion .* got norm 1.1"):
        robot.generalized_jacobian(x)


def test_quaternion_within_tolerance_is_normalized(robot):
    x = robot.neutral_configuration()
    h = robot.mass_matrix(x)
    x[6] = 1.0 + 5e-7
    assert np.allclose(robot.mass_matrix(x), h, rtol=0, atol=1e-10)


def test_exceptions_are_value_errors(robot):
    with pytest.raises(ValueError):
        robot.mass_matrix(np.zeros(3))
    assert issubclass(ModelError, SpacearmError)


# ---- points and bodies -------------------------------------------------------------------
def test_unknown_point_name(robot):
    x = robot.neutral_configuration()
    with pytest.raises(NotFoundError, match="no body named 'gripper'"):
        robot.generalized_jacobian(x, "gripper")


def test_body_index_out_of_range(robot):
    x = robot.neutral_configuration()
    with pytest.raises(NotFoundError, match="body index 99 does not exist"):
        robot.generalized_jacobian(x, (99, [0, 0, 0]))


@pytest.mark.parametrize("body", [True, False, np.bool_(True), 1.0, None, [1]])
def test_a_body_is_a_name_or_an_index_not_a_bool(robot, body):
    """``link_jacobians(x, True)`` was body 1 (a bool is an int to Python); issue 26."""
    x = robot.neutral_configuration()
    with pytest.raises(errors.SpacearmTypeError, match="body must be a body name .str. or index .int."):
        robot.link_jacobians(x, body)
    # the index and the name still give the same body, checked against the kinematics
    jt, jr = robot.link_jacobians(x, 1)
    jt_n, _ = robot.link_jacobians(x, robot.body_names[1])
    np.testing.assert_array_equal(jt, jt_n)
    assert np.linalg.norm(jr[:, 0]) == pytest.approx(1.0)  # body 1 turns about the first joint's unit axis


def test_point_offset_shape(robot):
    x = robot.neutral_configuration()
    with pytest.raises(ShapeError, match="point offset must have length 3"):
        robot.point_jacobian(x, ("link3", [0, 0]))


def test_wrench_on_unknown_body(robot):
    x = robot.neutral_configuration()
    with pytest.raises(NotFoundError):
        robot.forward_dynamics(x, np.zeros(12), wrenches=[spacearm.ExternalWrench(body="nope", force=(1, 0, 0))])


def test_wrench_must_be_typed(robot):
    x = robot.neutral_configuration()
    with pytest.raises(TypeError, match="ExternalWrench"):
        robot.forward_dynamics(x, np.zeros(12), wrenches=[(6, [0, 0, 0], [1, 0, 0], [0, 0, 0])])


def test_unknown_preset():
    with pytest.raises(NotFoundError, match="no preset named 'x7'"):
        spacearm.presets.get("x7")


def test_unknown_method(robot):
    with pytest.raises(ValueError, match="method must be"):
        robot.mass_matrix(robot.neutral_configuration(), method="magic")


# ---- models --------------------------------------------------------------------------------
def test_base_mass_must_be_positive():
    with pytest.raises(ModelError, match=r"base 'base': mass must be > 0 kg, got 0"):
        spacearm.Robot.builder("t", base_mass=0.0, base_inertia=[1, 1, 1])


def test_link_mass_must_be_non_negative():
    with pytest.raises(ModelError, match=r"link 'arm': mass must be >= 0 kg, got -1"):
        one_link(mass=-1.0)


def test_non_finite_mass():
    with pytest.raises(ModelError, match="link 'arm': mass must be finite"):
        one_link(mass=float("nan"))


def test_asymmetric_inertia():
    with pytest.raises(ModelError, match="link 'arm': inertia tensor must be symmetric"):
        one_link(inertia=[[1, 0.1, 0], [0, 1, 0], [0, 0, 1]])


def test_indefinite_inertia():
    with pytest.raises(ModelError, match="positive semi-definite"):
        one_link(inertia=[-0.1, 1.0, 1.0])


def test_triangle_inequality():
    with pytest.raises(ModelError, match="triangle inequality"):
        one_link(inertia=[0.1, 0.1, 1.0])


def test_base_inertia_must_be_positive_definite():
    with pytest.raises(ModelError, match="positive definite"):
        spacearm.Robot.builder("t", base_mass=10.0, base_inertia=[0.0, 1.0, 1.0])


def test_an_ill_conditioned_base_inertia_is_refused_for_its_conditioning():
    # [1e12, 1e12, 2.34] is positive definite: the refusal is about its conditioning, and says
    # so (it said "must be positive definite", issue 37 item 8).
    with pytest.raises(ModelError, match=r"too ill-conditioned: its principal moments .* span a ratio of 4\.274e\+?11") as e:
        spacearm.Robot.builder("t", base_mass=10.0, base_inertia=[1e12, 1e12, 2.34])
    assert "must be positive definite" not in str(e.value)


def test_inertia_shape():
    with pytest.raises(ShapeError, match="3x3"):
        one_link(inertia=[1.0, 2.0])


def test_zero_axis():
    with pytest.raises(ModelError, match="link 'arm': joint axis must be a non-zero vector"):
        one_link(axis=(0, 0, 0))


def test_non_unit_joint_rotation():
    with pytest.raises(ModelError, match="unit quaternion"):
        one_link(rotation=(0, 0, 0, 2.0))


def test_unknown_joint_type():
    with pytest.raises(ModelError, match="joint type must be 'revolute', 'prismatic' or 'fixed', got 'ball'"):
        one_link(joint="ball")


def test_unknown_parent():
    b = builder()
    with pytest.raises(ModelError, match="parent body 'ghost' is not defined"):
        b.add_link("arm", parent="ghost", mass=1.0, inertia=BAR)


def test_duplicate_body_name():
    b = builder()
    b.add_link("arm", mass=1.0, inertia=BAR)
    with pytest.raises(ModelError, match="body name 'arm' is used twice"):
        b.add_link("arm", parent="arm", mass=1.0, inertia=BAR)


def test_cycle_is_impossible_child_cannot_be_its_own_parent():
    b = builder()
    with pytest.raises(ModelError, match="not defined"):
        b.add_link("arm", parent="arm", mass=1.0, inertia=BAR)


def test_massless_moving_leaf_is_rejected():
    with pytest.raises(ModelError, match="zero mass and inertia"):
        one_link(mass=0.0, inertia=[0, 0, 0])


def test_unknown_end_effector():
    b = builder()
    b.add_link("arm", mass=1.0, inertia=BAR)
    b.set_end_effector("tip")
    with pytest.raises(ModelError, match="end effector 'tip' is not a defined point"):
        b.build()


def test_initial_q_length():
    b = builder()
    b.add_link("arm", mass=1.0, inertia=BAR)
    b.set_initial_q([0.0, 1.0])
    with pytest.raises(ModelError, match=r"initial_q must have N = 1 entries \(one per moving joint\), got 2"):
        b.build()


def test_unknown_limit_key():
    with pytest.raises(ValueError, match="unknown limit keys"):
        one_link(limits={"lowr": -1})


def test_inverted_limits():
    with pytest.raises(ModelError, match="lower <= upper"):
        one_link(limits={"lower": 1.0, "upper": -1.0})


def test_robot_cannot_be_built_from_arbitrary_objects():
    with pytest.raises(TypeError):
        spacearm.Robot(object())


def test_huge_axis_is_normalized_not_overflowed():
    robot = one_link(axis=(1.34e154, 0, 1))
    assert np.allclose(robot.describe()["links"][0]["axis"], [1.0, 0.0, 0.0], rtol=0, atol=1e-15)


def test_overflowing_inertia_is_rejected():
    with pytest.raises(ModelError, match="inertia"):
        one_link(inertia=[[1e308, 1e308, 0], [1e308, 1e308, 0], [0, 0, 1e308]])
