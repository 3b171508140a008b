"""Joint springs, dampers and passive joints against MuJoCo, loaded from the exported MJCF
(:func:`spacearm.interop.to_mjcf` writes each joint's ``stiffness``, ``springref`` and
``damping``; docs/flexibility.md).

MuJoCo computes the passive force itself (``qfrc_passive``) and integrates its own equations:
spacearm's passive force, forward and inverse dynamics must match its ``qfrc_passive``,
``qacc`` and ``qfrc_inverse`` (``M qacc + qfrc_bias − qfrc_passive``) to rounding, and a
simulated trajectory must match MuJoCo's RK4 rollout to integration tolerance.
"""

from __future__ import annotations

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import spacearm  # noqa: E402
from spacearm import interop  # noqa: E402
from random_models import assert_rel_close, random_model, random_state, with_joint_springs  # noqa: E402

SEEDS = [3, 8, 15]


def sprung(seed: int):
    rng = np.random.default_rng([24, seed])
    robot, dynamics = with_joint_springs(random_model(seed).robot, rng)
    x, u = random_state(robot, rng)
    f = rng.normal(scale=3.0, size=robot.nu)
    return robot, dynamics, x, u, f


def forward(model, robot, x, u, f=None, qacc=None):
    d = mujoco.MjData(model)
    d.qpos[:], d.qvel[:] = interop.to_mujoco_state(robot, x, u)
    if f is not None:
        d.qfrc_applied[:] = interop.to_mujoco_force(robot, x, f)
    mujoco.mj_forward(model, d)
    if qacc is not None:
        d.qacc[:] = qacc
        mujoco.mj_inverse(model, d)
    return d


@pytest.mark.parametrize("seed", SEEDS)
def test_passive_force_and_dynamics_match_mujoco(seed):
    robot, dynamics, x, u, f = sprung(seed)
    model = interop.to_mujoco(robot)
    order = interop.engine_dof_order(robot)
    assert np.allclose(model.jnt_stiffness[1:], [dynamics[k]["stiffness"] for k in order], rtol=0, atol=0)
    assert np.allclose(model.dof_damping[6:], [dynamics[k]["damping"] for k in order], rtol=0, atol=0)
    d = forward(model, robot, x, u, f)
    assert_rel_close(robot.passive_forces(x, u), interop.from_mujoco_force(robot, x, d.qfrc_passive), "mj qfrc_passive",
                     rtol=1e-13)
    du_mj = interop.acceleration_from_mujoco(robot, x, d.qacc)
    for method in ("aba", "mass_matrix", "reduced"):
        assert_rel_close(robot.forward_dynamics(x, u, f, method=method), du_mj, f"mj forward dynamics with springs ({method})")
    du = np.random.default_rng(seed).normal(size=robot.nu)
    d = forward(model, robot, x, u, qacc=interop.to_mujoco_acceleration(robot, x, du))
    assert_rel_close(robot.inverse_dynamics(x, u, du), interop.from_mujoco_force(robot, x, d.qfrc_inverse),
                     "mj inverse dynamics with springs")


def test_a_sprung_trajectory_matches_mujoco_rk4():
    """Zero applied force, springs and dampers only: spacearm's RK4 and MuJoCo's RK4 at the same
    step agree to the integrators' truncation error; spacearm's DOPRI5 at tight tolerance is the
    reference both converge to."""
    robot, _, x, u, _ = sprung(8)
    u = 0.3 * u
    model = interop.to_mujoco(robot)
    dt, steps = 1e-3, 400
    model.opt.timestep = dt
    d = mujoco.MjData(model)
    d.qpos[:], d.qvel[:] = interop.to_mujoco_state(robot, x, u)
    for _ in range(steps):
        mujoco.mj_step(model, d)
    x_mj, u_mj = interop.from_mujoco_state(robot, d.qpos, d.qvel)
    x_mj[3:7] /= np.linalg.norm(x_mj[3:7])
    duration = dt * steps
    rk4 = spacearm.simulate(robot, duration, x0=x, u0=u, dt=dt)
    ref = spacearm.simulate(robot, duration, x0=x, u0=u, dt=duration / 4, integrator="dopri5", rtol=1e-12, atol=1e-14)
    assert np.linalg.norm(rk4.x[-1, 7:] - x[7:]) > 0.05  # the joints move
    sign = np.sign(x_mj[3:7] @ ref.x[-1, 3:7])
    x_mj[3:7] *= sign
    for what, got in (("spacearm RK4", np.concatenate([rk4.x[-1], rk4.u[-1]])), ("MuJoCo RK4", np.concatenate([x_mj, u_mj]))):
        assert_rel_close(got, np.concatenate([ref.x[-1], ref.u[-1]]), f"{what} vs DOPRI5 after {duration} s", rtol=1e-10)
