"""``spacearm/ContactCapture-v0`` (docs/rl.md; spacearm.gym.contact_capture): it steps and resets
deterministically with a seed, its observation's numbers are the core's grasp outcome of the
step (recomputed here by running the same step through spacearm.simulate and grasp_outcome), and
a shut gripper on a slow tumble is rewarded more than an open one."""

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import spacearm  # noqa: E402
from spacearm.contact import grasp_outcome  # noqa: E402
from spacearm.control import JointPD  # noqa: E402
from spacearm.errors import ArgumentError  # noqa: E402
from spacearm.gym import ContactCaptureEnv  # noqa: E402


def episode(seed: int, steps: int = 4, shut: float = 1.0):
    env = ContactCaptureEnv(period=0.1)
    obs, info = env.reset(seed=seed)
    out = [obs]
    rewards = []
    a = np.array([0.0, shut, shut], dtype=np.float32)
    for _ in range(steps):
        obs, r, terminated, truncated, info = env.step(a)
        out.append(obs)
        rewards.append(r)
    return np.array(out), np.array(rewards), info


def test_it_steps_and_resets_deterministically_with_a_seed():
    o1, r1, _ = episode(5)
    o2, r2, _ = episode(5)
    assert np.array_equal(o1, o2) and np.array_equal(r1, r2)
    o3, _, _ = episode(6)
    assert not np.array_equal(o1[0], o3[0])
    # A reset of the same env with the seed starts the same episode again.
    env = ContactCaptureEnv(period=0.1)
    first, _ = env.reset(seed=5)
    env.step(env.action_space.sample())
    again, _ = env.reset(seed=5)
    assert np.array_equal(first, again) and np.array_equal(first, o1[0])


def test_the_observation_holds_the_cores_outcome_of_the_step():
    env = ContactCaptureEnv(period=0.1, spin_rate=0.05, offset_sigma=0.0)
    env.reset(seed=1)
    x, u, s = env._state
    obs, reward, *_ , info = env.step(np.array([0.0, 1.0, 1.0], dtype=np.float32))
    # The same step by hand: the boom held at 0, the fingers set to their closed limit 0.04 m.
    robot, c = env.robot, env._case
    traj = spacearm.simulate(robot, 0.1, dt=c.dt, x0=x, u0=u, controller=JointPD(kp=[500.0, 200.0, 200.0], kd=[100.0, 5.0, 5.0],
                             reference=[0.0, 0.04, 0.04]), contact=c.contact(robot), target=env._target_model, target_state=s)
    o = grasp_outcome(robot, env._target_model, traj, window=0.05)
    n = robot.n_dof
    assert np.array_equal(obs[:n], traj.x[-1, 7:]) and np.array_equal(obs[2 * n + 3:2 * n + 7],
                                                                       [o.relative_spin, o.relative_speed, o.offset, o.fingers_touching / 2])
    assert info["outcome"] == o.outcome and info["grasp"]["offset"] == o.offset and info["grasp"]["reason"] == o.reason
    assert reward == pytest.approx(-o.offset / 0.005 - 0.1 * o.relative_spin / 0.005 + 0.5 * o.fingers_touching / 2
                                   + (1.0 if o.held else 0.0), abs=1e-12)


def test_a_shut_gripper_earns_more_than_an_open_one():
    _, shut, _ = episode(2, steps=3, shut=1.0)
    _, open_, _ = episode(2, steps=3, shut=-1.0)
    assert shut.sum() > open_.sum()


def test_bad_arguments_are_named():
    with pytest.raises(ArgumentError, match="grippers"):
        ContactCaptureEnv(robot=spacearm.presets.planar4())
    with pytest.raises(ArgumentError, match="period"):
        ContactCaptureEnv(period=1e-4)
    with pytest.raises(ArgumentError, match="reset"):
        ContactCaptureEnv().step(np.zeros(3, dtype=np.float32))
