"""The captured system: the payload carries the target's state over exactly, the post-capture
motion matches MuJoCo with a weld equality activated at the capture pose, the torque-free target
matches Euler's equations, and the soft capture conserves robot + target momentum."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest

import spacearm
from spacearm.capture import grasp_impulse
from spacearm.capture.captured import attach_target, soft_capture
from spacearm.rotations import quat_to_matrix


def _scene(spin=(0.3, -0.4, 0.5)):
    robot = spacearm.presets.spatial6()
    rng = np.random.default_rng(140)
    x = robot.neutral_configuration(q=robot.initial_q + rng.normal(scale=0.3, size=robot.n_dof))
    u = robot.zero_velocity()
    u[6:] = rng.normal(scale=0.3, size=robot.n_dof)
    target = spacearm.Target(40.0, [3.0, 4.0, 5.0], grasp_points={"handle": (-0.4, 0.1, 0.0)})
    quat = np.array([0.1, -0.3, 0.2, 0.9])
    quat /= np.linalg.norm(quat)
    X = robot.point_position(x)
    s = target.state(X - quat_to_matrix(quat) @ target.grasp_points["handle"], quat, (0.05, -0.02, 0.01), spin)
    return robot, x, u, target, s


def test_attach_carries_momentum_energy_and_pose():
    robot, x, u, target, s = _scene()
    imp = grasp_impulse(robot, x, u, target, s)
    cap = attach_target(robot, x, imp.u_after, target, imp.target_state_after)
    m_c = cap.robot.momentum(cap.x, cap.u)
    m_r, m_t = robot.momentum(x, imp.u_after), target.momentum(imp.target_state_after)
    np.testing.assert_allclose(m_c.P, m_r.P + m_t.P, atol=1e-12 * np.linalg.norm(m_t.P))
    np.testing.assert_allclose(m_c.L_origin, m_r.L_origin + m_t.L_origin, atol=1e-12 * np.linalg.norm(m_t.L_origin))
    assert cap.robot.kinetic_energy(cap.x, cap.u) == pytest.approx(
        robot.kinetic_energy(x, imp.u_after) + target.kinetic_energy(imp.target_state_after), rel=1e-12)
    kin = cap.robot.forward_kinematics(cap.x)
    b = cap.robot.body_index(cap.payload)
    np.testing.assert_allclose(kin.com_in_world[b], s[:3], atol=1e-12)
    np.testing.assert_allclose(kin.body_to_world[b], quat_to_matrix(s[3:7]), atol=1e-12)
    assert cap.robot.total_mass == pytest.approx(robot.total_mass + target.mass)
    # before the impulse the target cannot ride on the gripper
    with pytest.raises(spacearm.ArgumentError, match="grasp_impulse"):
        attach_target(robot, x, u, target, s)


def test_target_propagation_against_euler_equations():
    from scipy.integrate import solve_ivp
    from scipy.spatial.transform import Rotation

    target = spacearm.Target(50.0, [4.0, 5.0, 6.0])
    s = target.state((1, 2, 3), Rotation.from_rotvec([0.3, -0.2, 0.5]).as_quat(), (0.1, 0.2, 0.3), (0.3, -0.5, 0.8))
    out = target.propagate(s, 2.0, dt=5e-3)
    inertia = target.inertia

    def rhs(_, y):  # Euler's equations in body axes, R' = R [ω_b]×
        R, wb = y[:9].reshape(3, 3), y[9:]
        W = np.array([[0, -wb[2], wb[1]], [wb[2], 0, -wb[0]], [-wb[1], wb[0], 0]])
        return np.r_[(R @ W).ravel(), np.linalg.solve(inertia, -np.cross(wb, inertia @ wb))]

    R0 = quat_to_matrix(s[3:7])
    sol = solve_ivp(rhs, (0, 2), np.r_[R0.ravel(), R0.T @ s[10:13]], rtol=1e-11, atol=1e-12, method="DOP853")
    R1 = sol.y[:9, -1].reshape(3, 3)
    np.testing.assert_allclose(quat_to_matrix(out[3:7]), R1, atol=1e-9)
    np.testing.assert_allclose(out[10:13], R1 @ sol.y[9:, -1], atol=1e-9)
    np.testing.assert_allclose(out[:3], np.array([1, 2, 3]) + 2.0 * np.array([0.1, 0.2, 0.3]), atol=1e-12)


def _soft_energy(robot, target, run, k):
    """Kinetic energy of both bodies plus the translational spring's ½ K |p − X|²."""
    out = []
    for xr, ur, st in zip(run.x, run.u, run.target):
        gap = target.grasp_position(st) - robot.point_position(xr)
        out.append(robot.kinetic_energy(xr, ur) + target.kinetic_energy(st) + 0.5 * k * gap @ gap)
    return np.array(out)


def test_soft_capture_conserves_momentum_and_energy():
    """A translational spring alone (no damping) between the two grasp points conserves robot +
    target momentum and the total energy T + ½ K |p − X|²; with damping the energy only falls."""
    robot, x, u, target, s = _scene(spin=(0.0, 0.0, 0.2))
    s[:3] += np.array([0.02, -0.01, 0.015])  # start with the spring stretched
    k = 100.0
    run = soft_capture(robot, x, u, target, s, 0.3, dt=2e-3, stiffness=k, damping=0.0, rotational_stiffness=0.0, rotational_damping=0.0)
    mr = [robot.momentum(a, b) for a, b in zip(run.x, run.u)]
    mt = [target.momentum(c) for c in run.target]
    P = np.array([a.P + b.P for a, b in zip(mr, mt)])
    L = np.array([a.L_origin + b.L_origin for a, b in zip(mr, mt)])
    # relative to the momentum in play: the largest |robot part| + |target part|
    scale_p = max(np.linalg.norm(a.P) + np.linalg.norm(b.P) for a, b in zip(mr, mt))
    scale_l = max(np.linalg.norm(a.L_origin) + np.linalg.norm(b.L_origin) for a, b in zip(mr, mt))
    assert np.ptp(P, axis=0).max() < 1e-9 * scale_p
    assert np.ptp(L, axis=0).max() < 1e-9 * scale_l
    assert np.abs(run.wrench[:, :3]).max() > 0.5  # the spring is doing work
    energy = _soft_energy(robot, target, run, k)
    assert np.ptp(energy) < 1e-7 * energy[0]
    damped = soft_capture(robot, x, u, target, s, 0.3, dt=2e-3, stiffness=k, damping=50.0, rotational_stiffness=0.0, rotational_damping=0.0)
    e2 = _soft_energy(robot, target, damped, k)
    assert np.all(np.diff(e2) < 1e-9 * e2[0])
    assert e2[-1] < 0.99 * e2[0]



def test_post_capture_motion_against_mujoco_weld():
    """MuJoCo: the robot and the target as a free body, a weld equality gripper–target activated
    at the capture pose; spacearm: the combined model. Same post-impact state, 1 s of free motion."""
    from spacearm import interop

    mujoco = pytest.importorskip("mujoco")
    robot, x, u, target, s = _scene()
    imp = grasp_impulse(robot, x, u, target, s)
    cap = attach_target(robot, x, imp.u_after, target, imp.target_state_after)
    duration = 1.0
    traj = spacearm.simulate(cap.robot, duration, x0=cap.x, u0=cap.u, integrator="dopri5", rtol=1e-11, atol=1e-13, dt=0.1)

    root = ET.fromstring(interop.to_mjcf(robot))
    world = root.find("worldbody")
    tb = ET.SubElement(world, "body", name="target", pos="0 0 0")
    ET.SubElement(tb, "freejoint", name="target_free", align="false")
    I = target.inertia
    ET.SubElement(tb, "inertial", pos="0 0 0", mass=repr(float(target.mass)),
                  fullinertia=" ".join(repr(float(v)) for v in (I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2])))
    eq = ET.SubElement(root, "equality")
    ET.SubElement(eq, "weld", name="grasp", body1=cap.gripper, body2="target", solref="0.0002 1", solimp="0.9999 0.9999 0.001 0.5 2")
    root.find("option").set("timestep", "0.0001")
    model = mujoco.MjModel.from_xml_string(ET.tostring(root, encoding="unicode"))
    data = mujoco.MjData(model)
    qpos_r, qvel_r = interop.to_mujoco_state(robot, x, imp.u_after)
    st = target.split(imp.target_state_after)
    Rt = quat_to_matrix(st.quaternion)
    data.qpos[:] = np.r_[qpos_r, st.position, st.quaternion[3], st.quaternion[:3]]
    data.qvel[:] = np.r_[qvel_r, st.velocity, Rt.T @ st.angular_velocity]
    mujoco.mj_kinematics(model, data)
    # the weld's relative pose: the target's pose in the gripper frame at this instant
    g = model.body(cap.gripper).id
    Rg, pg = data.xmat[g].reshape(3, 3), data.xpos[g]
    rel_q = np.zeros(4)
    mujoco.mju_mat2Quat(rel_q, (Rg.T @ Rt).ravel())
    model.eq_data[0, 3:6] = Rg.T @ (st.position - pg)
    model.eq_data[0, 6:10] = rel_q
    model.eq_active0[0] = 1
    data.eq_active[0] = 1
    for _ in range(int(round(duration / model.opt.timestep))):
        mujoco.mj_step(model, data)
    x_mj, u_mj = interop.from_mujoco_state(robot, data.qpos[: robot.nx], data.qvel[: robot.nu])
    x_sa, u_sa = traj.x[-1], traj.u[-1]
    b = cap.robot.body_index(cap.payload)
    p_sa = cap.robot.forward_kinematics(x_sa).com_in_world[b]
    # the motion is substantial, and the two engines agree on it
    assert np.linalg.norm(p_sa - st.position) > 0.02
    assert np.linalg.norm(u_sa[6:] - imp.u_after[6:]) > 0.05
    # (measured: positions agree to 1e-10, velocities to 1e-7 of their size)
    np.testing.assert_allclose(data.qpos[robot.nx: robot.nx + 3], p_sa, atol=1e-8)
    np.testing.assert_allclose(x_mj[:3], x_sa[:3], atol=1e-8)
    np.testing.assert_allclose(x_mj[7:], x_sa[7:], atol=1e-8)
    np.testing.assert_allclose(u_mj, u_sa, atol=1e-6 * np.abs(u_sa).max())
