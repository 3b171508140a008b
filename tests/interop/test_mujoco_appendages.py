"""Panels and rigid-finite-element beams (docs/flexibility.md) against MuJoCo, loaded from the
exported MJCF: the export writes every passive joint's stiffness and damping and an actuator only
on the actuated joints, and a free-floating trajectory of a spacecraft with a panel, a one-plane
beam and an arm joint, springs and dampers only, matches MuJoCo's RK4 rollout to integration
tolerance (both against spacearm's DOPRI5 at rtol 1e-12). Massless moving links (a two-plane
beam with torsion, the spherical slosh pendulum's gimbal) are merged into their child's MuJoCo
body as extra joints and a compliant joint's rotor borrows a point mass from its parent: such a
model loads, its mass matrix is spacearm's and its trajectory matches; a massless link that
cannot be merged is refused with a ModelError before MuJoCo sees it."""

from __future__ import annotations

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import spacearm  # noqa: E402
from spacearm import interop  # noqa: E402
from random_models import assert_rel_close, flexible_sat  # noqa: E402


def test_export_writes_springs_dampers_and_actuators_only_on_motors():
    robot = flexible_sat()
    model = interop.to_mujoco(robot)
    d = robot.description
    order = interop.engine_dof_order(robot)
    moving = [link for link in d.links if link.type != "fixed"]
    assert np.array_equal(model.jnt_stiffness[1:], [moving[k].stiffness for k in order])
    assert np.array_equal(model.dof_damping[6:], [moving[k].damping for k in order])
    assert model.nu == int(robot.actuated_dofs.sum()) == 1
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, int(model.actuator_trnid[0, 0]))
    assert name == "arm_joint"


def massless_sat() -> spacearm.Robot:
    """A two-plane beam with torsion (two massless links per station), a compliant arm joint
    (a zero-mass rotor with inertia) on a tilted axis away from the CM, a spherical slosh pendulum
    (a massless gimbal, a point bob)."""
    b = spacearm.Robot.builder("massless-sat", base_mass=40.0, base_inertia=[3.0, 3.5, 4.0])
    b.add_beam("boom", root_position=(0, 0.4, 0.05), axis=(0, 1, 0.2), length=2.0, segments=2, EI=40.0, GJ=30.0,
               rho_A=0.6, rho_J=0.02, damping_ratio=0.01)
    b.add_link("arm", joint="revolute", axis=(0, 0.6, 0.8), origin=(-0.4, 0, 0.1), com=(-0.3, 0.05, 0), mass=2.0,
               inertia=[0.01, 0.06, 0.06], compliant=dict(stiffness=50.0, rotor_inertia=1e-3, gear_ratio=10.0, damping=0.02))
    b.add_slosh("tank", model="spherical-pendulum", mass=5.0, position=(0, 0, -0.2), axis=(0.3, 0, -1), length=0.3,
                frequency=2.0, damping=0.01)
    return b.build()


def _mujoco_mass_matrix(robot, x, u):
    model = interop.to_mujoco(robot)
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = interop.to_mujoco_state(robot, x, u)
    mujoco.mj_forward(model, data)
    full = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, full)
    return model, interop.mass_matrix_from_mujoco(robot, x, full)


def test_massless_links_are_merged_and_the_mass_matrix_is_spacearms():
    robot = massless_sat()
    names = robot.body_names
    assert {"boom_1_bend2", "arm_rotor", "tank_gimbal"} <= set(names)
    rng = np.random.default_rng(7)
    for _ in range(3):
        x = robot.neutral_configuration(q=rng.uniform(-0.4, 0.4, robot.n_dof))
        u = rng.normal(size=robot.nu)
        model, h = _mujoco_mass_matrix(robot, x, u)
        assert_rel_close(h, robot.mass_matrix(x), "H from MuJoCo vs spacearm", rtol=1e-10)
    # every joint is there, the massless links' bodies are not (merged into their child)
    joint_names = {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, k) for k in range(model.njnt)}
    assert {link.joint for link in robot.description.links if link.type != "fixed"} <= joint_names
    body_names = {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, k) for k in range(model.nbody)}
    assert "tank_gimbal" not in body_names and "boom_1_bend1" not in body_names and "tank" in body_names
    assert "arm_rotor" in body_names  # a rotor keeps its body: it has inertia
    assert model.body_jntnum[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "boom_1")] == 3
    assert model.nu == int(robot.actuated_dofs.sum()) == 1


def test_wheels_and_point_masses_load_with_spacearms_mass_matrix():
    """Zero-mass reaction wheels (rotors that borrow a point mass from the base) and point masses
    (a spring–mass, a pendulum bob: the POINT_INERTIA floor), which MuJoCo refused before."""
    b = spacearm.Robot.builder("wheels", base_mass=30.0, base_inertia=[2.0, 2.5, 3.0])
    for k, axis in enumerate(np.eye(3)):
        b.add_reaction_wheel(axis, 0.02, position=0.1 * axis + [0, 0, 0.05], name=f"w{k}")
    b.add_slosh("tank", model="spring-mass", mass=3.0, position=(0.1, 0, -0.2), axis=(0, 0.6, 0.8), frequency=2.0)
    b.add_slosh("tank2", model="pendulum", mass=2.0, position=(-0.1, 0.2, 0), axis=(0, 0, -1), length=0.2, frequency=3.0)
    robot = b.build()
    assert all(link.mass == 0.0 for link in robot.description.links if link.name.startswith("w"))
    rng = np.random.default_rng(3)
    x = robot.neutral_configuration(q=rng.uniform(-0.5, 0.5, robot.n_dof))
    _, h = _mujoco_mass_matrix(robot, x, rng.normal(size=robot.nu))
    assert_rel_close(h, robot.mass_matrix(x), "H from MuJoCo vs spacearm (wheels, point masses)", rtol=1e-10)


def test_massless_sat_trajectory_matches_mujoco_rk4():
    robot = massless_sat()
    rng = np.random.default_rng(11)
    x = robot.neutral_configuration(q=rng.uniform(-0.2, 0.2, robot.n_dof))
    u = np.zeros(robot.nu)
    u[:6] = rng.normal(scale=0.05, size=6)
    u[6:] = rng.normal(scale=0.3, size=robot.n_dof)
    model = interop.to_mujoco(robot)
    dt, steps = 2.5e-4, 1200  # the fast twist and rotor modes: at 5e-4 both RK4s are 2.7e-7 off, 16x less here
    model.opt.timestep = dt
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = interop.to_mujoco_state(robot, x, u)
    for _ in range(steps):
        mujoco.mj_step(model, data)
    x_mj, u_mj = interop.from_mujoco_state(robot, data.qpos, data.qvel)
    x_mj[3:7] /= np.linalg.norm(x_mj[3:7])
    duration = dt * steps
    ref = spacearm.simulate(robot, duration, x0=x, u0=u, dt=duration / 4, integrator="dopri5", rtol=1e-12, atol=1e-14)
    assert np.linalg.norm(ref.x[-1, 7:] - x[7:]) > 0.05  # the passive joints move
    x_mj[3:7] *= np.sign(x_mj[3:7] @ ref.x[-1, 3:7])
    rk4 = spacearm.simulate(robot, duration, x0=x, u0=u, dt=dt)
    got = np.concatenate([x_mj, u_mj])
    assert_rel_close(got, np.concatenate([ref.x[-1], ref.u[-1]]), f"MuJoCo RK4 vs spacearm DOPRI5 after {duration} s", rtol=1e-7)
    # the same integrator on the same equations: far closer than the integration error
    assert_rel_close(got, np.concatenate([rk4.x[-1], rk4.u[-1]]), "MuJoCo RK4 vs spacearm RK4 (massless links)", rtol=1e-10)


def _hub(b):
    b.add_link("hub", joint="revolute", axis=(0, 0, 1), origin=(0.4, 0, 0), com=(0, 0, 0), mass=0.0, inertia=[0, 0, 0])
    b.add_link("a", parent="hub", joint="revolute", axis=(0, 0, 1), origin=(0.1, 0, 0), com=(0.1, 0, 0), mass=1.0,
               inertia=[0.01, 0.01, 0.01])


def test_massless_links_that_cannot_be_merged_are_refused_before_mujoco():
    b = spacearm.Robot.builder("m", base_mass=40.0, base_inertia=[3.0, 3.5, 4.0])
    _hub(b)
    b.add_link("b", parent="hub", joint="revolute", axis=(0, 0, 1), origin=(0.1, 0.1, 0), com=(0.1, 0, 0), mass=1.0,
               inertia=[0.01, 0.01, 0.01])
    with pytest.raises(spacearm.ModelError, match="'hub'.*2 child links"):
        interop.to_mjcf(b.build())
    b = spacearm.Robot.builder("m", base_mass=40.0, base_inertia=[3.0, 3.5, 4.0])
    _hub(b)
    b.add_point("tip", body="hub", offset=(0.1, 0, 0))
    with pytest.raises(spacearm.ModelError, match="'hub'.*points or shapes"):
        interop.to_mjcf(b.build())
    b = spacearm.Robot.builder("m", base_mass=40.0, base_inertia=[3.0, 3.5, 4.0])
    b.add_link("hub", joint="revolute", axis=(0, 0, 1), origin=(0.4, 0, 0), com=(0, 0, 0), mass=0.0, inertia=[0, 0, 0])
    b.add_link("pay", parent="hub", joint="fixed", origin=(0.1, 0, 0.1), com=(0.1, 0, 0), mass=1.0, inertia=[0.01, 0.02, 0.03])
    robot = b.build()
    x = robot.neutral_configuration(q=[0.7])
    _, h = _mujoco_mass_matrix(robot, x, np.ones(robot.nu))  # merged into a fixed child: fine
    assert_rel_close(h, robot.mass_matrix(x), "H, massless link on a fixed child", rtol=1e-10)
    with pytest.raises(spacearm.ArgumentError, match="'pay' hangs on the massless link 'hub'"):
        interop.to_mjcf(robot, weld=["pay"])
    b = spacearm.Robot.builder("m", base_mass=40.0, base_inertia=[3.0, 3.5, 4.0])
    b.add_link("spinner", joint="revolute", axis=(0, 0, 1), origin=(0.4, 0, 0), com=(0.1, 0, 0), mass=0.0,
               inertia=[0.01, 0.01, 0.01])
    with pytest.raises(spacearm.ModelError, match="'spinner' has inertia but no mass"):
        interop.to_mjcf(b.build())


def test_flexible_sat_trajectory_matches_mujoco_rk4():
    robot = flexible_sat()
    rng = np.random.default_rng(24)
    x = robot.neutral_configuration(q=rng.uniform(-0.2, 0.2, robot.n_dof))
    u = np.zeros(robot.nu)
    u[:6] = rng.normal(scale=0.05, size=6)
    u[6:] = rng.normal(scale=0.3, size=robot.n_dof)
    model = interop.to_mujoco(robot)
    dt, steps = 5e-4, 600
    model.opt.timestep = dt
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = interop.to_mujoco_state(robot, x, u)
    for _ in range(steps):
        mujoco.mj_step(model, data)
    x_mj, u_mj = interop.from_mujoco_state(robot, data.qpos, data.qvel)
    x_mj[3:7] /= np.linalg.norm(x_mj[3:7])
    duration = dt * steps
    rk4 = spacearm.simulate(robot, duration, x0=x, u0=u, dt=dt)
    ref = spacearm.simulate(robot, duration, x0=x, u0=u, dt=duration / 4, integrator="dopri5", rtol=1e-12, atol=1e-14)
    assert np.linalg.norm(ref.x[-1, 7:] - x[7:]) > 0.05  # the passive joints move
    x_mj[3:7] *= np.sign(x_mj[3:7] @ ref.x[-1, 3:7])
    want = np.concatenate([ref.x[-1], ref.u[-1]])
    for what, got in (("spacearm RK4", np.concatenate([rk4.x[-1], rk4.u[-1]])), ("MuJoCo RK4", np.concatenate([x_mj, u_mj]))):
        assert_rel_close(got, want, f"{what} vs DOPRI5 after {duration} s", rtol=1e-7)
