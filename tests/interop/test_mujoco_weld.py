"""The capture weld in the MJCF export (``to_mjcf(..., weld=[payload])``): the captured target is
a free body of MuJoCo's world held to the gripper by ``<equality><weld>``. Checked in MuJoCo:
the model loads with the target free and its shape; at the grasp state the weld's constraint
violation is zero after mj_forward and MuJoCo's momentum of the two bodies equals spacearm's of
the combined model; a MuJoCo simulation of the welded system keeps the relative pose to the
solver's tolerance and follows spacearm's simulation of the captured system (the target a
fixed payload, the core's DOPRI5)."""

import numpy as np
import pytest

import spacearm
from spacearm.capture import Target, attach_target, grasp_impulse
from spacearm.errors import ArgumentError, NotFoundError
from spacearm.interop import mujoco as smj
from spacearm.rotations import quat_to_matrix

mujoco = pytest.importorskip("mujoco")


@pytest.fixture(scope="module")
def captured():
    """spatial6, joints moving at zero momentum, grasping a spinning, drifting 40 kg target by a
    handle off its CM at a skew attitude (rigid grasp: the impulse that locks them)."""
    robot = spacearm.presets.spatial6()
    x = robot.neutral_configuration()
    qd = np.array([0.1, -0.2, 0.15, 0.3, -0.1, 0.2])
    u = np.concatenate([robot.base_velocity_from_momentum(x, qd), qd])
    handle = np.array([-0.3, 0.1, 0.0])
    target = Target(40.0, [2.0, 3.0, 4.0], grasp_points={"handle": handle})
    quat = np.array([0.1, 0.2, -0.3, 0.9]) / np.linalg.norm([0.1, 0.2, -0.3, 0.9])
    s = target.state(position=robot.point_position(x) - quat_to_matrix(quat) @ handle, quaternion=quat,
                     velocity=(0.02, 0.0, 0.01), angular_velocity=(0.05, 0.1, -0.2))
    impact = grasp_impulse(robot, x, u, target, s, kind="rigid")
    return attach_target(robot, x, impact.u_after, target, impact.target_state_after), target, impact.target_state_after


def _data(cs):
    model = smj.to_mujoco(cs.robot, weld=[cs.payload])
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = smj.to_mujoco_state(cs.robot, cs.x, cs.u, weld=[cs.payload])
    mujoco.mj_forward(model, data)
    return model, data


def test_the_target_is_a_free_body_held_by_a_weld(captured):
    cs, target, s = captured
    text = smj.to_mjcf(cs.robot, weld=[cs.payload])
    assert f'<freejoint name="{cs.payload}_free"' in text and "<equality>" in text
    model, data = _data(cs)
    robot = cs.robot
    assert model.nq == robot.nx + 7 and model.nv == robot.nu + 6 and model.njnt == robot.n_dof + 2
    assert model.neq == 1 and model.eq_type[0] == mujoco.mjtEq.mjEQ_WELD
    b, g = model.body(cs.payload).id, model.body(cs.gripper).id
    assert model.body_parentid[b] == 0  # a child of the world, not of the gripper
    assert (model.eq_obj1id[0], model.eq_obj2id[0]) == (g, b)
    assert model.body_mass[b] == pytest.approx(target.mass, rel=1e-15)
    assert [model.geom_bodyid[k] for k in range(model.ngeom)].count(b) == 1  # the target's shape
    # The target's pose and twist in MuJoCo are the recorded target state (independent: the Target's own).
    np.testing.assert_allclose(data.xpos[b], s[:3], atol=1e-12)
    np.testing.assert_allclose(data.xmat[b].reshape(3, 3), quat_to_matrix(s[3:7]), atol=1e-12)
    vel = np.zeros(6)
    mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_BODY, b, vel, 0)  # [ω, v] in world axes
    np.testing.assert_allclose(vel[3:], s[7:10], atol=1e-12)
    np.testing.assert_allclose(vel[:3], s[10:13], atol=1e-12)


def test_weld_violation_is_zero_at_the_grasp_and_momentum_matches(captured):
    cs, target, s = captured
    model, data = _data(cs)
    assert data.nefc == 6 and np.all(data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY)
    assert np.abs(data.efc_pos).max() < 1e-12
    mujoco.mj_subtreeVel(model, data)
    m = cs.robot.momentum(cs.x, cs.u)
    total = float(model.body_subtreemass[0])
    assert total == pytest.approx(cs.robot.total_mass, rel=1e-14)
    np.testing.assert_allclose(total * data.subtree_linvel[0], m.P, atol=1e-12)
    np.testing.assert_allclose(data.subtree_angmom[0], m.L_com, atol=1e-12)
    assert np.linalg.norm(m.L_com) > 0.1  # momentum actually in play
    # and it is the robot's plus the free target's just after the lock (the two bodies apart)
    mr, mt = spacearm.presets.spatial6().momentum(cs.x, cs.u), target.momentum(s)
    np.testing.assert_allclose(total * data.subtree_linvel[0], np.add(mr.P, mt.P), atol=1e-12)
    mujoco.mj_subtreeVel(model, data)
    L_origin = data.subtree_angmom[0] + np.cross(data.subtree_com[0], total * data.subtree_linvel[0])
    np.testing.assert_allclose(L_origin, np.add(mr.L_origin, mt.L_origin), atol=1e-12)


def test_a_welded_simulation_keeps_the_grasp_and_follows_spacearm(captured):
    cs, target, s = captured
    model, data = _data(cs)
    model.opt.timestep = 1e-3
    duration = 2.0
    spa = spacearm.simulate(cs.robot, duration, x0=cs.x, u0=cs.u, integrator="dopri5", rtol=1e-11, atol=1e-13, dt=0.5)
    b, g = model.body(cs.payload).id, model.body(cs.gripper).id
    rel0 = data.xmat[g].reshape(3, 3).T @ (data.xpos[b] - data.xpos[g])
    worst = 0.0
    samples = iter(range(1, len(spa.t)))
    k = next(samples)
    for step in range(1, int(round(duration / model.opt.timestep)) + 1):
        mujoco.mj_step(model, data)
        rg = data.xmat[g].reshape(3, 3)
        worst = max(worst, np.abs(rg.T @ (data.xpos[b] - data.xpos[g]) - rel0).max())
        if abs(step * model.opt.timestep - spa.t[k]) < 1e-9:
            mujoco.mj_forward(model, data)
            x, u = smj.from_mujoco_state(cs.robot, data.qpos, data.qvel, weld=[cs.payload])
            # MuJoCo's RK4 with a soft weld against the core's DOPRI5 with the target rigidly fixed
            np.testing.assert_allclose(x, spa.x[k], atol=2e-6)
            np.testing.assert_allclose(u, spa.u[k], atol=2e-6)
            kin = cs.robot.forward_kinematics(spa.x[k])
            np.testing.assert_allclose(data.xpos[b], kin.com_in_world[-1], atol=2e-6)
            mujoco.mj_subtreeVel(model, data)
            np.testing.assert_allclose(model.body_subtreemass[0] * data.subtree_linvel[0], spa.P[k], atol=1e-9)
            np.testing.assert_allclose(data.subtree_angmom[0], spa.L_com[k], atol=1e-6)
            k = next(samples, k)
    assert worst < 1e-6, worst  # the relative position held to the solver's tolerance
    assert np.abs(data.efc_pos).max() < 1e-6


def test_weld_refuses_a_moving_or_unknown_link(captured):
    cs, _, _ = captured
    with pytest.raises(ArgumentError, match="fixed link"):
        smj.to_mjcf(cs.robot, weld=["link3"])
    with pytest.raises(NotFoundError, match="not a link"):
        smj.to_mjcf(cs.robot, weld=["nothing"])
    with pytest.raises(NotFoundError, match="not a link"):
        smj.to_mjcf(cs.robot, weld=[cs.robot.body_names[0]])
