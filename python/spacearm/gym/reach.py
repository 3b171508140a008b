"""``spacearm/Reach-v0``: bring the end effector to a goal point with the least base disturbance
(floating mode: no base actuation, so every joint torque also turns the base).

The environment's class docstring gives its observation, action and reward (docs/rl.md).
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from .._util.optional import require
from ..errors import ArgumentError
from ..presets import spatial6
from ..sim.simulator import Simulator
from . import _common

gymnasium = require("gymnasium", "the Gymnasium environments (spacearm.gym)")

__all__ = ["ReachTask", "ReachEnv"]


class ReachTask:
    """The Reach task of ``robot``: goal sampling, observation and reward of ``(B, 13+2N)``
    states. Kinematics come from the nominal robot's core kinematics (a perturbed plant changes
    masses, not the link frames, so its end effector is the nominal one's at the same
    configuration)."""

    def __init__(self, robot=None, *, dt: float = 0.01, frame_skip: int = 5, max_torque="auto", goal_range: float = 0.5,
                 success_tolerance: float = 0.02, base_rate_weight: float = 10.0, action_weight: float = 1e-3,
                 max_joint_rate: float = 3.0, runaway_penalty: float = 100.0, max_episode_steps: int = 200, randomize=None):
        self.robot = spatial6() if robot is None else robot
        if self.robot.end_effector is None or self.robot.n_dof == 0:
            raise ArgumentError("Reach needs a robot with joints and an end effector")
        self.dt = _common.positive(dt, "dt")
        self.frame_skip = _common.count(frame_skip, "frame_skip")
        self.torque_scale = _common.torque_scale(self.robot, max_torque, max_joint_rate=_common.positive(max_joint_rate, "max_joint_rate"))
        self.goal_range = _common.non_negative(goal_range, "goal_range")
        self.success_tolerance = _common.positive(success_tolerance, "success_tolerance")
        self.base_rate_weight = _common.non_negative(base_rate_weight, "base_rate_weight")
        self.action_weight = _common.non_negative(action_weight, "action_weight")
        self.max_joint_rate = _common.positive(max_joint_rate, "max_joint_rate")
        self.runaway_penalty = _common.non_negative(runaway_penalty, "runaway_penalty")
        self.max_episode_steps = _common.count(max_episode_steps, "max_episode_steps")
        self.perturbations = _common.check_randomization(randomize)
        n = self.robot.n_dof
        self.observation_space, self.action_space = _common.boxes(2 * n + 9, n)
        self.x0 = self.robot.neutral_configuration()
        self.u0 = self.robot.zero_velocity()

    def sample_goal(self, rng: np.random.Generator) -> np.ndarray:
        """A goal point (3, m, in 𝒥)."""
        x = self.x0.copy()
        x[7:] += rng.uniform(-self.goal_range, self.goal_range, size=self.robot.n_dof)
        return np.asarray(self.robot.point_position(x), dtype=float)

    def torque(self, actions) -> np.ndarray:
        """Joint torques of ``(B, N)`` actions (clipped to [-1, 1])."""
        return np.clip(np.asarray(actions, dtype=float), -1.0, 1.0) * self.torque_scale

    def observe(self, states: np.ndarray, goals: np.ndarray) -> np.ndarray:
        """Observations ``(B, 2N+9)`` of states ``(B, 13+2N)`` and goals ``(B, 3)``."""
        n, nx = self.robot.n_dof, self.robot.nx
        _common.check_finite(states, "Reach")
        x = states[:, :nx]
        p = np.asarray(self.robot.point_position(x), dtype=float).reshape(-1, 3)
        return np.concatenate([x[:, 7:], states[:, nx + 6 : nx + 6 + n], p, goals - p, states[:, nx + 3 : nx + 6]], axis=1)

    def reward(self, obs: np.ndarray, actions, steps) -> tuple:
        """``(reward (B,), distance (B,), success (B,), runaway (B,))`` of observations
        ``(B, 2N+9)`` after actions ``(B, N)``, the episodes at ``steps`` (B,) steps taken.

        A runaway ends the episode; so that ending it on purpose never pays, its step also pays
        the rest of the episode, ``max_episode_steps − steps`` steps, at the cost of the state
        it ended in (as if the arm stayed there), besides ``runaway_penalty``."""
        n = self.robot.n_dof
        a = np.clip(np.asarray(actions, dtype=float), -1.0, 1.0)
        distance = np.linalg.norm(obs[:, 2 * n + 3 : 2 * n + 6], axis=1)
        base_rate = np.linalg.norm(obs[:, 2 * n + 6 : 2 * n + 9], axis=1)
        runaway = np.max(np.abs(obs[:, n : 2 * n]), axis=1) > self.max_joint_rate
        state_cost = distance + self.base_rate_weight * base_rate
        remaining = np.maximum(self.max_episode_steps - np.asarray(steps, dtype=float), 0.0)
        reward = -state_cost - self.action_weight * np.sum(a * a, axis=1) - runaway * (self.runaway_penalty + remaining * state_cost)
        return reward, distance, distance < self.success_tolerance, runaway


class ReachEnv(gymnasium.Env):
    """``spacearm/Reach-v0``: bring the end effector to a goal point with the least base disturbance
    (floating mode: no base actuation, so every joint torque also turns the base).

    Observation (float64, ``2N + 9``): ``[q (N, rad), q̇ (N, rad/s), p_ee (3, m, in 𝒥),
    p_goal − p_ee (3, m, in 𝒥), ω0 (3, rad/s, in 𝒥)]``.

    Action (float32, ``N``, in ``[-1, 1]``): joint torques as fractions of ``max_torque``,
    ``τ = a · τ_max``, held over the control period (``frame_skip`` RK4 steps of ``dt``).

    Reward (docs/rl.md): ``r = −‖p_goal − p_ee‖ − w_base ‖ω0‖ − w_action ‖a‖²`` after the step,
    minus ``runaway_penalty`` on a step that ends with a joint faster than ``max_joint_rate``
    (rad/s), and on that step the rest of the episode at the cost of the state it ended in
    (``(max_episode_steps − steps)(‖p_goal − p_ee‖ + w_base ‖ω0‖)``: ending the episode on purpose
    never pays). Terminated when ``‖p_goal − p_ee‖ < success_tolerance`` (``info["is_success"]``) or on
    such a runaway (``info["runaway"]``: an arm spun up by a random policy would otherwise run to
    rates the integration step cannot follow); truncated after ``max_episode_steps``.

    The goal is the end-effector position of a joint configuration drawn uniformly within
    ``goal_range`` (rad) of the initial one, with the base at its initial pose (reachable with the
    base fixed; the floating base moves a little, so the goal is nearly but not exactly reachable).

    [`ReachTask`][spacearm.gym.ReachTask] holds the observation and the reward of a batch of states, so the single
    environment and [`ReachVectorEnv`][spacearm.gym.ReachVectorEnv] share them.

    Keywords: those of [`ReachTask`][spacearm.gym.ReachTask] and
    ``render_mode`` (None or ``"rgb_array"``). ``randomize``: None (the nominal plant), True
    or a [`spacearm.campaign.Perturbations`][spacearm.campaign.Perturbations]: a perturbed plant
    drawn at every reset.
    """

    metadata = {"render_modes": list(_common.RENDER_MODES), "render_fps": 20}

    def __init__(self, robot=None, *, render_mode: Optional[str] = None, **task):
        self.task = ReachTask(robot, **task)
        self.render_mode = _common.check_render_mode(render_mode)
        self.observation_space = self.task.observation_space
        self.action_space = self.task.action_space
        self.metadata = {**self.metadata, "render_fps": int(round(1.0 / (self.task.dt * self.task.frame_skip)))}
        self._sim = None
        self._frame = None

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        task = self.task
        plant, params = _common.randomized_plant(task.robot, task.perturbations, self.np_random)
        self.goal = task.sample_goal(self.np_random)
        self._sim = Simulator(plant, dt=task.dt)
        self._sim.reset(task.x0, task.u0)
        self._steps = 0
        self._state = self._sim.state
        obs = task.observe(self._state[None], self.goal[None])[0]
        return obs, {"goal": self.goal.copy(), "plant": params}

    def step(self, action):
        task = self.task
        if self._sim is None:
            raise ArgumentError("call reset() before step()")
        a = _common.actions(action, (task.robot.n_dof,))[None]
        self._state = self._sim.step(task.torque(a)[0], task.frame_skip)
        self._steps += 1
        obs = task.observe(self._state[None], self.goal[None])
        reward, distance, success, runaway = task.reward(obs, a, [self._steps])
        info = {"distance": float(distance[0]), "base_rate": float(np.linalg.norm(self._state[task.robot.nx + 3 : task.robot.nx + 6])),
                "is_success": bool(success[0]), "runaway": bool(runaway[0])}
        return obs[0], float(reward[0]), bool(success[0] or runaway[0]), self._steps >= task.max_episode_steps, info

    def render(self):
        if self.render_mode != "rgb_array" or self._sim is None:
            return None
        if self._frame is None:
            self._frame = _common.Frame(self.task.robot)
        x = self._state[: self.task.robot.nx]
        return self._frame.rgb(x, [(self.goal, "C2"), (self.task.robot.point_position(x), "C3")], title=f"Reach  t = {self._sim.time:.2f} s")
