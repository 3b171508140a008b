"""ReachVectorEnv: gymnasium's vector API contract, checked against gymnasium's own
SyncVectorEnv of ReachEnv copies (the same observations, rewards, flags and autoresets, bit for
bit), whatever the thread count."""

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import spacearm.gym as sgym  # noqa: E402
from gymnasium.vector import AutoresetMode, SyncVectorEnv  # noqa: E402
from spacearm.errors import ArgumentError  # noqa: E402


def _run(env, steps, seed, rng):
    obs, info = env.reset(seed=seed)
    out = [(obs, None, None, None)]
    for _ in range(steps):
        a = rng.uniform(-1, 1, env.action_space.shape).astype(np.float32)
        obs, reward, terminated, truncated, info = env.step(a)
        out.append((obs, reward, terminated, truncated))
    return out


@pytest.mark.parametrize("threads", [1, 2])
def test_the_vector_env_equals_gymnasiums_sync_vector_env_of_single_envs(threads):
    kw = dict(max_episode_steps=4, success_tolerance=0.3, goal_range=0.3)
    vec = sgym.ReachVectorEnv(3, threads=threads, randomize=True, **kw)
    ref = SyncVectorEnv([lambda: sgym.ReachEnv(randomize=True, **kw) for _ in range(3)], autoreset_mode=AutoresetMode.NEXT_STEP)
    assert vec.metadata["autoreset_mode"] == ref.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    assert vec.observation_space == ref.observation_space and vec.action_space == ref.action_space
    ours, theirs = _run(vec, 14, 21, np.random.default_rng(1)), _run(ref, 14, 21, np.random.default_rng(1))
    resets = 0
    for k, ((o1, r1, te1, tr1), (o2, r2, te2, tr2)) in enumerate(zip(ours, theirs)):
        assert o1 in vec.observation_space
        assert np.array_equal(o1, o2), k
        if r1 is not None:
            assert r1.dtype == np.float64 and te1.dtype == bool and tr1.dtype == bool
            assert np.array_equal(r1, r2) and np.array_equal(te1, te2) and np.array_equal(tr1, tr2), k
            resets += int(np.sum(te1 | tr1))
    assert resets >= 3  # the episodes ended and were reset on the next step


def test_make_vec_through_the_registry_gives_the_native_batch():
    env = gymnasium.make_vec("spacearm/Reach-v0", num_envs=4, vectorization_mode="vector_entry_point")
    assert isinstance(env.unwrapped, sgym.ReachVectorEnv)
    obs, _ = env.reset(seed=0)
    assert obs.shape == (4, env.single_observation_space.shape[0])
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    assert reward.shape == (4,) and info["distance"].shape == (4,) and info["_distance"].all()


def test_vector_wrappers_accept_it():
    env = gymnasium.wrappers.vector.RecordEpisodeStatistics(sgym.make_vec(2, max_episode_steps=3))
    env.reset(seed=0)
    episodes = []
    for _ in range(4):
        *_, info = env.step(np.zeros(env.action_space.shape, dtype=np.float32))
        if "episode" in info:
            episodes.append(info["episode"]["l"][info["_episode"]])
    assert np.array_equal(np.concatenate(episodes), [3, 3])


def test_bad_vector_arguments_are_spacearm_errors():
    with pytest.raises(ArgumentError):
        sgym.ReachVectorEnv(0)
    with pytest.raises(ArgumentError):
        sgym.ReachVectorEnv(2, threads=0)
    env = sgym.ReachVectorEnv(2)
    with pytest.raises(ArgumentError):
        env.step(np.zeros((2, 6)))
    env.reset(seed=[1, 2])
    with pytest.raises(ArgumentError):
        env.step(np.zeros((3, 6)))
    with pytest.raises(ArgumentError):
        env.reset(seed=[1, 2, 3])


def test_numpy_integer_seeds_are_seeds_and_others_are_refused():
    """seed=[np.int64(...), ...] (what np.arange gives) seeds as the same Python ints; it raised
    gymnasium's own error ("Seed must be a python integer")."""
    a, b = sgym.ReachVectorEnv(2), sgym.ReachVectorEnv(2)
    obs_np, _ = a.reset(seed=list(np.arange(5, 7)))
    obs_int, _ = b.reset(seed=[5, 6])
    assert np.array_equal(obs_np, obs_int)
    with pytest.raises(ArgumentError, match=r"seed\[1\] must be an integer"):
        a.reset(seed=[1, 2.5])
    with pytest.raises(ArgumentError, match=r"seed\[0\] must be an integer"):
        a.reset(seed=[True, 2])
