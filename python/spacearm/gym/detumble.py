"""``spacearm/Detumble-v0``: after a capture, null the spin of the base with the arm and the
reaction wheels (floating mode).

The environment's class docstring gives its observation, action and reward (docs/rl.md).
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from .._util.optional import require
from ..capture import attach_target, grasp_impulse
from ..errors import ArgumentError
from ..presets import spatial6
from ..sim.simulator import Simulator
from . import _common
from .capture import _range, default_target, tumbling_target_state

gymnasium = require("gymnasium", "the Gymnasium environments (spacearm.gym)")

__all__ = ["DetumbleEnv", "wheeled_robot"]


#: How many spins a reset draws, at most, for one that leaves the base turning at least
#: ``rate_tolerance`` after the grasp.
MAX_RESET_DRAWS = 100

def wheeled_robot(robot=None, *, rotor_inertia: float = 0.5, max_torque: float = 2.0, max_speed: float = 600.0):
    """``robot`` (default ``spatial6``) with three reaction wheels on the base's x, y, z axes."""
    builder = (spatial6() if robot is None else robot).to_builder()
    for axis in np.eye(3):
        builder.add_reaction_wheel(axis=axis, rotor_inertia=rotor_inertia, max_torque=max_torque, max_speed=max_speed)
    return builder.build()


class DetumbleEnv(gymnasium.Env):
    """``spacearm/Detumble-v0``: after a capture, null the spin of the base with the arm and the
    reaction wheels (floating mode).

    The robot (default: the ``spatial6`` preset with three reaction wheels on the base axes,
    ``wheeled_robot``) has grasped a tumbling target at reset: the target of
    ``spacearm/Capture-v0`` with its handle at the end effector, spinning at ``spin_rate`` (rad/s, a
    range) about a uniform axis, is locked to the gripper by the core's rigid grasp impulse
    (``spacearm.capture.grasp_impulse``) and attached as a payload (``spacearm.capture.attach_target``);
    the episode steps that captured system. Internal torques conserve the system's angular momentum,
    so the base can stop turning only by moving it into the wheels (and the arm).

    Observation (float64, ``2M + 3``, ``M`` the dofs, arm then wheels): ``[q (M, rad), q̇ (M, rad/s),
    ω0 (3, rad/s, 𝒥)]``.

    Action (float32, ``M``, in ``[-1, 1]``): torques of every dof (arm joints and wheels) as
    fractions of their scales ``τ = a · τ_max`` (the arm's ``max_torque``; each wheel's effort
    limit).

    Reward (docs/rl.md): ``r = −‖ω0‖ − w_action ‖a‖²``, minus ``runaway_penalty`` on a step that
    ends with an arm joint faster than ``max_joint_rate`` (rad/s; the wheels are free to spin up to
    their own limits); terminated when ``‖ω0‖ < rate_tolerance`` or on such a runaway, truncated
    after ``max_episode_steps``.
    """

    metadata = {"render_modes": list(_common.RENDER_MODES), "render_fps": 20}

    def __init__(self, robot=None, target=None, *, dt: float = 0.01, frame_skip: int = 5, max_torque="auto", spin_rate=(0.02, 0.08),
                 rate_tolerance: float = 1e-3, action_weight: float = 1e-3, max_joint_rate: float = 3.0, runaway_penalty: float = 100.0,
                 max_episode_steps: int = 300, randomize=None,
                 render_mode: Optional[str] = None):
        self.robot = wheeled_robot() if robot is None else robot
        if self.robot.end_effector is None or self.robot.n_dof == 0:
            raise ArgumentError("Detumble needs a robot with joints and an end effector")
        self.target = default_target() if target is None else target
        self.dt = _common.positive(dt, "dt")
        self.frame_skip = _common.count(frame_skip, "frame_skip")
        wheels = list(self.robot.wheel_dofs)
        arm = [d for d in range(self.robot.n_dof) if d not in wheels]
        scale = np.zeros(self.robot.n_dof)
        scale[arm] = _common.torque_scale(self.robot, max_torque, arm, max_joint_rate=_common.positive(max_joint_rate, "max_joint_rate"))
        if wheels:
            scale[wheels] = _common.torque_scale(self.robot, None, wheels)
        self.torque_scale = scale
        self.spin_rate = _range(spin_rate, "spin_rate")
        self.rate_tolerance = _common.positive(rate_tolerance, "rate_tolerance")
        self.action_weight = _common.non_negative(action_weight, "action_weight")
        self.max_joint_rate = _common.positive(max_joint_rate, "max_joint_rate")
        self.runaway_penalty = _common.non_negative(runaway_penalty, "runaway_penalty")
        self._arm = np.array(arm, dtype=int)
        self.max_episode_steps = _common.count(max_episode_steps, "max_episode_steps")
        self.perturbations = _common.check_randomization(randomize)
        self.render_mode = _common.check_render_mode(render_mode)
        m = self.robot.n_dof
        self.observation_space, self.action_space = _common.boxes(2 * m + 3, m)
        self.metadata = {**self.metadata, "render_fps": int(round(1.0 / (self.dt * self.frame_skip)))}
        self._sim = None
        self._frame = None

    def _observe(self) -> np.ndarray:
        nx, m = self.robot.nx, self.robot.n_dof
        return np.concatenate([self._state[7:nx], self._state[nx + 6 : nx + 6 + m], self._state[nx + 3 : nx + 6]])

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        plant, params = _common.randomized_plant(self.robot, self.perturbations, self.np_random)
        x, u = plant.neutral_configuration(), plant.zero_velocity()
        handle = np.asarray(plant.point_position(x), dtype=float)
        # An episode starts unsolved: a draw whose base already turns slower than rate_tolerance
        # after the grasp (a spin axis the base barely feels) is drawn again (31 of 100 resets
        # started solved, issue 37 item 3).
        for _ in range(MAX_RESET_DRAWS):
            s = tumbling_target_state(self.target, handle, self.np_random.uniform(*self.spin_rate), self.np_random)
            impact = grasp_impulse(plant, x, u, self.target, s)
            if np.linalg.norm(np.asarray(impact.u_after)[3:6]) >= self.rate_tolerance:
                break
        else:
            raise ArgumentError(f"Detumble: {MAX_RESET_DRAWS} draws of the target's spin all left the base turning slower than "
                                f"rate_tolerance = {self.rate_tolerance} rad/s; raise spin_rate or lower rate_tolerance")
        self.captured = attach_target(plant, x, impact.u_after, self.target, impact.target_state_after)
        self._sim = Simulator(self.captured.robot, dt=self.dt)
        self._sim.reset(self.captured.x, self.captured.u)
        self._state = self._sim.state
        self._steps = 0
        return self._observe(), {"plant": params, "impulse": np.asarray(impact.impulse, dtype=float)}

    def step(self, action):
        if self._sim is None:
            raise ArgumentError("call reset() before step()")
        a = np.clip(_common.actions(action, (self.robot.n_dof,)), -1.0, 1.0)
        self._state = _common.check_finite(self._sim.step(a * self.torque_scale, self.frame_skip)[None], "Detumble")[0]
        self._steps += 1
        nx = self.robot.nx
        rate = float(np.linalg.norm(self._state[nx + 3 : nx + 6]))
        runaway = bool(self._arm.size and np.max(np.abs(self._state[nx + 6 + self._arm])) > self.max_joint_rate)
        reward = -rate - self.action_weight * float(a @ a) - self.runaway_penalty * runaway
        success = rate < self.rate_tolerance
        info = {"base_rate": rate, "is_success": success, "runaway": runaway}
        return self._observe(), reward, success or runaway, self._steps >= self.max_episode_steps, info

    def render(self):
        if self.render_mode != "rgb_array" or self._sim is None:
            return None
        if self._frame is None:
            self._frame = _common.Frame(self.captured.robot)
        x = self._state[: self.robot.nx]
        return self._frame.rgb(x, [(self.captured.robot.point_position(x), "C3")],
                               title=f"Detumble  t = {self._steps * self.dt * self.frame_skip:.2f} s")
