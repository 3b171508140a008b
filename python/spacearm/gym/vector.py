"""[`ReachVectorEnv`][spacearm.gym.ReachVectorEnv]: ``num_envs`` copies of ``spacearm/Reach-v0`` stepped together in one
native call per step (``spacearm._core.BatchSimulator``: the core's ``BatchStepper`` on rayon
threads, the GIL released), not a Python loop over copies.

Gymnasium 1.x vector semantics: ``reset(seed=s)`` seeds copy ``i`` with ``s + i`` (as
``gymnasium.vector.SyncVectorEnv`` does), so copy ``i`` follows exactly the episode of a
[`ReachEnv`][spacearm.gym.ReachEnv] reset with seed ``s + i``; autoreset is ``NEXT_STEP``: the step after a copy
terminates or truncates resets it (its action ignored, reward 0) and returns its first
observation. ``info`` holds ``distance``, ``base_rate``, ``is_success`` and ``runaway`` arrays with their
``_name`` masks.
"""

from __future__ import annotations

import contextlib
import threading
from typing import Optional

import numpy as np

from .. import _core
from .._util.optional import require
from ..errors import ArgumentError, SimulationError
from ..sim.simulation import DEFAULTS, _options
from . import _common
from .reach import ReachTask

gymnasium = require("gymnasium", "the Gymnasium environments (spacearm.gym)")
_seeding = require("gymnasium.utils.seeding", "the Gymnasium environments (spacearm.gym)")
_vector = require("gymnasium.vector", "the Gymnasium environments (spacearm.gym)")
_batch_space = require("gymnasium.vector.utils", "the Gymnasium environments (spacearm.gym)").batch_space

__all__ = ["ReachVectorEnv"]


class ReachVectorEnv(_vector.VectorEnv):
    """``num_envs`` Reach copies on ``threads`` native threads (None: one per core). Other
    keywords: those of [`ReachTask`][spacearm.gym.ReachTask] (``randomize`` draws one perturbed plant per copy at
    each of its resets)."""

    metadata = {"render_modes": [], "autoreset_mode": _vector.AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int = 8, robot=None, *, threads: Optional[int] = None, render_mode: Optional[str] = None, **task):
        self.num_envs = _common.count(num_envs, "num_envs")
        if threads is not None:
            threads = _common.count(threads, "threads")
        if render_mode is not None:
            raise ArgumentError(f"ReachVectorEnv renders nothing: render_mode must be None, got {render_mode!r} (render a "
                                "single ReachEnv with render_mode='rgb_array')")
        self.task = ReachTask(robot, **task)
        # One call at a time: a second thread stepping the same env gets a SimulationError.
        self._lock = threading.Lock()
        self.single_observation_space = self.task.observation_space
        self.single_action_space = self.task.action_space
        self.observation_space = _batch_space(self.single_observation_space, self.num_envs)
        self.action_space = _batch_space(self.single_action_space, self.num_envs)
        self.render_mode = None
        t = self.task
        options = _options(t.robot, mode="floating", integrator="rk4", dt=t.dt, rtol=DEFAULTS["rtol"], atol=DEFAULTS["atol"], wheels=None,
                           thrusters=None, record_every=1, joint_limits=DEFAULTS["joint_limits"], max_steps=DEFAULTS["max_steps"],
                           record_dtype="float64")
        b = self.num_envs
        # The core's admission first (a ResourceLimitError), before the copies' states are tiled.
        _core.BatchSimulator.admit(t.robot.core_model, b)
        self._core = _core.BatchSimulator([t.robot.core_model] * b, np.tile(t.x0, b), np.tile(t.u0, b), options, threads)
        self._rngs = [_seeding.np_random()[0] for _ in range(b)]
        self._goals = np.zeros((b, 3))
        self._steps = np.zeros(b, dtype=np.int64)
        self._needs_reset = np.zeros(b, dtype=bool)
        self._states = None

    def _reset_copy(self, i: int) -> None:
        t = self.task
        plant, _ = _common.randomized_plant(t.robot, t.perturbations, self._rngs[i])
        self._goals[i] = t.sample_goal(self._rngs[i])
        self._core.reset(i, t.x0, t.u0, None if t.perturbations is None else plant.core_model)
        self._steps[i] = 0

    @contextlib.contextmanager
    def _exclusive(self):
        """Hold the env's lock for one call, or raise a SimulationError when another thread
        holds it."""
        if not self._lock.acquire(blocking=False):
            raise SimulationError("this ReachVectorEnv is in use by another thread: step and reset it from one thread at a "
                                  "time (one env per thread)")
        try:
            yield
        finally:
            self._lock.release()

    def reset(self, *, seed=None, options: Optional[dict] = None):
        """Reset every copy; ``seed``: an int (copy ``i`` gets ``seed + i``), a list of one per
        copy (None entries keep their stream), or None."""
        with self._exclusive():
            return self._reset(seed)

    def _reset(self, seed):
        if seed is None:
            seeds = [None] * self.num_envs
        elif isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
            seeds = [int(seed) + i for i in range(self.num_envs)]
        else:
            seeds = list(seed)
            if len(seeds) != self.num_envs:
                raise ArgumentError(f"seed must be None, an int or {self.num_envs} seeds (one per copy), got {len(seeds)}")
            for i, s in enumerate(seeds):
                if s is not None and (isinstance(s, bool) or not isinstance(s, (int, np.integer))):
                    raise ArgumentError(f"seed[{i}] must be an integer or None, got {type(s).__name__}")
            seeds = [None if s is None else int(s) for s in seeds]
        if seed is not None:
            self._np_random, self._np_random_seed = _seeding.np_random(seeds[0])
        for i, s in enumerate(seeds):
            if s is not None:
                self._rngs[i] = _seeding.np_random(int(s))[0]
            self._reset_copy(i)
        self._needs_reset[:] = False
        self._states = self._core.states
        return self.task.observe(self._states, self._goals), {}

    def step(self, actions):
        with self._exclusive():
            return self._step(actions)

    def _step(self, actions):
        if self._states is None:
            raise ArgumentError("call reset() before step()")
        t = self.task
        a = _common.actions(actions, (self.num_envs, t.robot.n_dof), "actions")
        # One native call steps every copy (the copies due for an autoreset too: they are
        # reset just after, so their step is discarded).
        states = self._core.step(np.ascontiguousarray(t.torque(a)).ravel(), None, t.frame_skip)
        resetting = self._needs_reset.copy()
        for i in np.flatnonzero(resetting):
            self._reset_copy(int(i))
        if resetting.any():
            fresh = self._core.states
            states[resetting] = fresh[resetting]
        self._states = states
        self._steps[~resetting] += 1
        obs = t.observe(states, self._goals)
        reward, distance, success, runaway = t.reward(obs, a, self._steps)
        terminated = (success | runaway) & ~resetting
        truncated = (self._steps >= t.max_episode_steps) & ~resetting
        reward = np.where(resetting, 0.0, reward)
        self._needs_reset = terminated | truncated
        nx = t.robot.nx
        live = ~resetting
        info = {"distance": distance, "_distance": live, "base_rate": np.linalg.norm(states[:, nx + 3 : nx + 6], axis=1), "_base_rate": live,
                "is_success": success & live, "_is_success": live, "runaway": runaway & live, "_runaway": live}
        return obs, reward, terminated, truncated, info
