"""Two-arm grasp as a closed chain: the loop stays closed, momentum is conserved, and the motion
matches MuJoCo with a weld equality between the two grippers."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest

import spacearm
from spacearm.capture.closed_chain import simulate_closed_chain


def _dual_arm():
    b = spacearm.Robot.builder("dual", base_mass=200.0, base_inertia=[20.0, 25.0, 30.0])
    bar = lambda m, length: [m * 0.01 / 6, m * (length**2 + 0.01) / 12, m * (length**2 + 0.01) / 12]  # noqa: E731
    for side, y in (("a", 0.4), ("b", -0.4)):
        b.add_link(f"{side}1", parent="base", axis=(0, 0, 1), origin=(0.8, y, 0.0), com=(0.3, 0, 0), mass=6.0, inertia=bar(6.0, 0.6))
        b.add_link(f"{side}2", parent=f"{side}1", axis=(0, 1, 0), origin=(0.3, 0, 0), com=(0.3, 0, 0), mass=4.0, inertia=bar(4.0, 0.6))
        b.add_link(f"{side}3", parent=f"{side}2", axis=(1, 0, 0), origin=(0.3, 0, 0), com=(0.1, 0, 0), mass=2.0, inertia=bar(2.0, 0.2))
        b.add_link(f"{side}4", parent=f"{side}3", axis=(0, 1, 0), origin=(0.2, 0, 0), com=(0.1, 0, 0), mass=1.5, inertia=bar(1.5, 0.2))
    # the captured target rides on arm a's wrist; arm b's wrist holds it too: a loop of 8 joints, 2 degrees of freedom
    b.attach_payload("target", body="a4", mass=30.0, inertia=[2.0, 2.5, 3.0], origin=(0.3, -0.4, 0.0))
    b.add_point("grip_b", body="b4", offset=(0.1, 0.0, 0.0))
    robot = b.build()
    x = robot.neutral_configuration(q=[0.3, 0.2, 0.1, 0.2, -0.3, 0.25, -0.1, -0.2])
    return robot, x


def _consistent_velocity(robot, x, rng):
    kin = robot.forward_kinematics(x)
    ta = robot.body_index("target")
    pb = robot.point_position(x, "grip_b")
    oa = kin.body_to_world[ta].T @ (pb - kin.com_in_world[ta])
    ja0, jam = robot.point_jacobian(x, (ta, oa))
    jb0, jbm = robot.point_jacobian(x, "grip_b")
    J = np.hstack([jb0 - ja0, jbm - jam])
    u = rng.normal(scale=0.5, size=robot.nu)
    return u - np.linalg.pinv(J) @ (J @ u)


def test_closed_chain_stays_closed_and_conserves_momentum():
    robot, x = _dual_arm()
    u = _consistent_velocity(robot, x, np.random.default_rng(5))
    run = simulate_closed_chain(robot, x, u, 0.5, "target", "grip_b", dt=1e-3)
    assert np.abs(run.pose_error).max() < 1e-8
    assert np.abs(run.constraint_wrench).max() > 0.1  # the loop carries load
    assert np.abs(run.u[:, 6:]).max() > 0.05  # and moves
    P = np.array([robot.momentum(a, b).P for a, b in zip(run.x, run.u)])
    L = np.array([robot.momentum(a, b).L_origin for a, b in zip(run.x, run.u)])
    assert np.ptp(P, axis=0).max() < 1e-9 * max(1.0, np.abs(P).max())
    assert np.ptp(L, axis=0).max() < 1e-9 * max(1.0, np.abs(L).max())
    with pytest.raises(spacearm.ArgumentError, match="loop closure"):
        simulate_closed_chain(robot, x, np.ones(robot.nu), 0.1, "target", "grip_b")


def test_closed_chain_against_mujoco_weld():
    mujoco = pytest.importorskip("mujoco")
    from spacearm import interop

    robot, x = _dual_arm()
    u = _consistent_velocity(robot, x, np.random.default_rng(6))
    duration = 0.5
    run = simulate_closed_chain(robot, x, u, duration, "target", "grip_b", dt=1e-3)

    root = ET.fromstring(interop.to_mjcf(robot))
    eq = ET.SubElement(root, "equality")
    ET.SubElement(eq, "weld", name="loop", body1="target", body2="b4", solref="0.0002 1", solimp="0.9999 0.9999 0.001 0.5 2")
    root.find("option").set("timestep", "0.0001")
    model = mujoco.MjModel.from_xml_string(ET.tostring(root, encoding="unicode"))
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = interop.to_mujoco_state(robot, x, u)
    mujoco.mj_kinematics(model, data)
    a, b = model.body("target").id, model.body("b4").id
    Ra, Rb = data.xmat[a].reshape(3, 3), data.xmat[b].reshape(3, 3)
    rel_q = np.zeros(4)
    mujoco.mju_mat2Quat(rel_q, (Ra.T @ Rb).ravel())
    model.eq_data[0, 3:6] = Ra.T @ (data.xpos[b] - data.xpos[a])
    model.eq_data[0, 6:10] = rel_q
    for _ in range(int(round(duration / model.opt.timestep))):
        mujoco.mj_step(model, data)
    x_mj, u_mj = interop.from_mujoco_state(robot, data.qpos, data.qvel)
    assert np.linalg.norm(run.x[-1][7:] - x[7:]) > 0.02  # the chain moved
    # (measured: 2e-7 in the configuration, 3e-6 of the velocity's size: MuJoCo's weld is a stiff
    # spring, not an exact constraint)
    np.testing.assert_allclose(x_mj, run.x[-1], atol=1e-6)
    np.testing.assert_allclose(u_mj, run.u[-1], atol=2e-5 * np.abs(run.u[-1]).max())
