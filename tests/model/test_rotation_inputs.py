"""A ``scipy.spatial.transform.Rotation`` is accepted wherever spacearm takes a quaternion.

Each entry point is checked against scipy's own matrices and rotation vectors (an independent
implementation): the base attitude that ``neutral_configuration(quat0=R)`` produces is
``R.as_matrix()`` after forward kinematics, a builder link rotated by ``R`` sits at ``R``, and so
on. A Rotation holding several rotations is a ShapeError, and ``import spacearm`` does not
import scipy (not a dependency).
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

Rotation = pytest.importorskip("scipy.spatial.transform").Rotation

import spacearm  # noqa: E402
from spacearm import control, presets, rotations
from spacearm.analysis.free_floating import attitude_change  # noqa: E402
from spacearm.errors import ShapeError  # noqa: E402

RNG = np.random.default_rng(20261126)
ROTATIONS = [Rotation.from_rotvec(v) for v in RNG.normal(size=(5, 3))] + [Rotation.from_euler("z", 90, degrees=True)]
STACK = Rotation.from_rotvec(RNG.normal(size=(3, 3)))


@pytest.mark.parametrize("k", range(len(ROTATIONS)))
def test_neutral_configuration_base_attitude(k):
    rot = ROTATIONS[k]
    robot = presets.spatial6()
    x = robot.neutral_configuration(quat0=rot)
    assert np.array_equal(x, robot.neutral_configuration(quat0=list(rot.as_quat())))
    body_to_world = robot.forward_kinematics(x).body_to_world[0]
    np.testing.assert_allclose(body_to_world, rot.as_matrix(), atol=1e-14)


def test_builder_link_rotation():
    rot = ROTATIONS[0]
    robot = (spacearm.RobotBuilder("b", 100.0, [10.0, 12.0, 14.0])
             .add_link("arm", parent="base", joint="revolute", axis=[0, 0, 1], origin=[0.5, 0, 0], rotation=rot,
                       com=[0.2, 0, 0], mass=3.0, inertia=[0.01, 0.1, 0.1])
             .build())
    x = robot.neutral_configuration(q=[0.0])
    np.testing.assert_allclose(robot.forward_kinematics(x).body_to_world[1], rot.as_matrix(), atol=1e-14)


def test_attach_payload_rotation():
    # A payload with an anisotropic inertia, rotated by R: the body's merged inertia about its CM
    # in 𝒥 gains R I R^T (the body frame is aligned with 𝒥 at the neutral configuration).
    rot = ROTATIONS[5]
    inertia = np.diag([1.0, 2.0, 3.0])

    def base_inertia(rotation):
        robot = spacearm.RobotBuilder("b", 100.0, [10.0, 12.0, 14.0]).attach_payload(
            "p", body="base", mass=2.0, inertia=inertia, rotation=rotation).build()
        return robot.mass_matrix(robot.neutral_configuration())[3:6, 3:6]

    np.testing.assert_allclose(base_inertia(rot) - base_inertia(None), rot.as_matrix() @ inertia @ rot.as_matrix().T - inertia,
                               atol=1e-12)


def test_dh_joint1_rotation():
    rot = ROTATIONS[1]
    links = [dict(d=0.1, theta=0.0, a=0.5, alpha=0.3, com=(-0.25, 0, 0), mass=4.0, inertia=[0.01, 0.1, 0.1]),
             dict(d=0.0, theta=0.2, a=0.4, alpha=0.0, com=(-0.2, 0, 0), mass=3.0, inertia=[0.01, 0.05, 0.05])]
    args = dict(base_mass=100.0, base_inertia=[10.0, 12.0, 14.0])
    with_rotation = spacearm.io.robot_from_dh("r", links, joint1_rotation=rot, **args)
    with_quat = spacearm.io.robot_from_dh("r", links, joint1_rotation=list(rot.as_quat()), **args)
    x = with_rotation.neutral_configuration(q=[0.4, -0.7])
    assert np.array_equal(with_rotation.mass_matrix(x), with_quat.mass_matrix(x))
    # Joint 1's axis is the z axis of its frame, rotated by R from the base frame.
    axis1 = with_rotation.forward_kinematics(x).joint_axis_in_world[1]
    np.testing.assert_allclose(axis1, rot.as_matrix()[:, 2], atol=1e-14)


def test_controllers_take_rotations():
    robot = presets.spatial6()
    rot = ROTATIONS[2]
    from spacearm._util.spec import controller_spec

    def data(c):
        return controller_spec(c).to_data()

    assert np.array_equal(data(control.AttitudeControl(quat_ref=rot, kp=1.0, kd=1.0))["quat_ref"], rot.as_quat())
    assert np.array_equal(data(control.BaseThrusterControl(quat_ref=rot))["quat_ref"], rot.as_quat())
    line = control.CartesianLine(p_start=[1.0, 0.5, 0.2], p_goal=[1.1, 0.5, 0.2], t_start=0.0, t_end=1.0)
    spec = data(control.CoordinatedFlying(line, base_pose_ref=([0.0, 0.0, 0.0], rot)))
    assert np.array_equal(spec["base_pose_ref"][1], rot.as_quat())


def test_a_simulation_with_a_rotation_reference_is_the_same_as_with_its_quaternion():
    robot = presets.spatial6()
    rot = Rotation.from_rotvec([0.0, 0.0, 0.05])
    runs = [spacearm.simulate(robot, 0.02, dt=0.005, mode="rotation-flying",
                              controller=control.BaseThrusterControl(quat_ref=ref, kp_attitude=50.0, kd_attitude=10.0))
            for ref in (rot, list(rot.as_quat()))]
    assert np.array_equal(runs[0].x, runs[1].x)
    assert not np.array_equal(runs[0].x[-1, 3:7], runs[0].x[0, 3:7])  # the reference did act


def test_rotation_helpers():
    a, b = ROTATIONS[3], ROTATIONS[4]
    np.testing.assert_allclose(rotations.quat_to_matrix(a), a.as_matrix(), atol=1e-14)
    np.testing.assert_allclose(attitude_change(a, b), (a.inv() * b).magnitude(), atol=1e-12)
    np.testing.assert_allclose(rotations.quat_to_matrix(rotations.quat_multiply(a, b)), (a * b).as_matrix(), atol=1e-14)
    np.testing.assert_allclose(rotations.quat_log(a), a.as_rotvec(), atol=1e-12)
    np.testing.assert_allclose(rotations.quat_to_matrix(rotations.quat_exp(a.as_rotvec())), a.as_matrix(), atol=1e-14)
    np.testing.assert_allclose(rotations.rotation_vector(a.as_matrix()), a.as_rotvec(), atol=1e-12)
    # Batches: rows of quaternions against scipy's products and matrices, one side broadcast.
    many = Rotation.from_quat(np.array([r.as_quat() for r in ROTATIONS]))
    np.testing.assert_allclose(rotations.quat_to_matrix(many.as_quat()), many.as_matrix(), atol=1e-14)
    prod = rotations.quat_multiply(many.as_quat(), b)
    np.testing.assert_allclose(rotations.quat_to_matrix(prod), (many * b).as_matrix(), atol=1e-14)
    # skew: [v]x w = v x w, for one vector and for rows.
    rng = np.random.default_rng(5)
    v, w = rng.normal(size=(4, 3)), rng.normal(size=3)
    np.testing.assert_allclose(rotations.skew(v[0]) @ w, np.cross(v[0], w), atol=1e-15)
    np.testing.assert_allclose(rotations.skew(v) @ w, np.cross(v, w), atol=1e-15)
    with pytest.raises(spacearm.ShapeError):
        rotations.skew([1.0, 2.0])
    with pytest.raises(spacearm.QuaternionError):
        rotations.quat_to_matrix([[0.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.0, 2.0]])
    with pytest.raises(spacearm.ArgumentError):
        rotations.rotation_vector(2 * np.eye(3))


def test_scalar_last_order():
    # 90 degrees about z: [x, y, z, w] = [0, 0, sin 45°, cos 45°]; scalar-first would put w first.
    x = presets.planar4().neutral_configuration(quat0=ROTATIONS[-1])
    np.testing.assert_allclose(x[3:7], [0.0, 0.0, np.sqrt(0.5), np.sqrt(0.5)], atol=1e-15)


def test_several_rotations_are_a_shape_error():
    robot = presets.spatial6()
    calls = [
        lambda: robot.neutral_configuration(quat0=STACK),
        lambda: robot.neutral_configuration(quat0=Rotation.from_quat([[0, 0, 0, 1]])),  # a stack of one
        lambda: rotations.quat_to_matrix(STACK),
        lambda: control.AttitudeControl(quat_ref=STACK, kp=1.0, kd=1.0),
        lambda: spacearm.RobotBuilder("b", 1.0, [1, 1, 1]).add_link(
            "l", parent="base", joint="fixed", origin=[0, 0, 0], rotation=STACK, com=[0, 0, 0], mass=1.0,
            inertia=[1, 1, 1]),
    ]
    for call in calls:
        with pytest.raises(ShapeError, match="rotation"):
            call()


def test_import_spacearm_does_not_import_scipy():
    code = "import sys, spacearm, spacearm.rotations, spacearm._util.arrays; print('scipy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
