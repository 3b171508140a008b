"""``spacearm/Capture-v0``: approach and grasp a tumbling target (floating mode).

The environment's class docstring gives its observation, action and reward (docs/rl.md).
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from .._util.optional import require
from ..capture import Target, attach_target, grasp_impulse, relative_twist
from ..errors import ArgumentError
from ..presets import spatial6
from ..rotations import quat_from_matrix
from ..sim.simulator import Simulator
from . import _common

gymnasium = require("gymnasium", "the Gymnasium environments (spacearm.gym)")

__all__ = ["CaptureEnv", "default_target", "tumbling_target_state"]


def default_target() -> Target:
    """A 100 kg box (inertia diag(20, 25, 30) kg·m²) with a handle 0.5 m from its CM."""
    return Target(100.0, [20.0, 25.0, 30.0], name="target", grasp_points={"handle": (0.5, 0.0, 0.0)})


def _unit(rng) -> np.ndarray:
    v = rng.standard_normal(3)
    return v / np.linalg.norm(v)


def _rotation(rng) -> np.ndarray:
    """A uniform random rotation matrix (QR of a Gaussian matrix, signs fixed)."""
    q, r = np.linalg.qr(rng.standard_normal((3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def tumbling_target_state(target: Target, handle_at, spin_rate: float, rng) -> np.ndarray:
    """The state (13) of ``target`` with its handle at ``handle_at`` (m, 𝒥), a uniform attitude,
    spinning at ``spin_rate`` (rad/s) about a uniform axis, its CM at rest."""
    rot = _rotation(rng)
    offset = next(iter(target.grasp_points.values()))
    return target.state(position=np.asarray(handle_at, dtype=float) - rot @ offset, quaternion=quat_from_matrix(rot),
                        angular_velocity=spin_rate * _unit(rng))


def _range(value, name: str):
    lo, hi = (value, value) if np.ndim(value) == 0 else tuple(value)
    lo, hi = _common.non_negative(lo, name), _common.non_negative(hi, name)
    if hi < lo:
        raise ArgumentError(f"{name} must be a number or (low, high) with low <= high, got {value!r}")
    return lo, hi


class CaptureEnv(gymnasium.Env):
    """``spacearm/Capture-v0``: approach and grasp a tumbling target (floating mode).

    The target is a rigid [`Target`][spacearm.Target] with one grasp point (its handle), drawn at each reset:
    handle ``approach_distance`` (m, a range) from the end effector in a uniform direction, a
    uniform attitude, a tumble of ``spin_rate`` (rad/s, a range) about a uniform axis, and the CM at
    rest. It moves torque-free by the core's free-body propagation (``Target.propagate``) over each
    control period while the robot steps in the core's RK4 stepper.

    Observation (float64, ``2N + 15``): ``[q (N, rad), q̇ (N, rad/s), p_ee (3, m, 𝒥),
    p_handle − p_ee (3, m, 𝒥), v_handle − v_ee (3, m/s, 𝒥; the linear part of the relative twist),
    ω_target (3, rad/s, 𝒥), ω0 (3, rad/s, 𝒥)]``.

    Action (float32, ``N``, in ``[-1, 1]``): joint torques ``τ = a · τ_max``.

    Reward (docs/rl.md): every step ``−d − w_base ‖ω0‖ − w_action ‖a‖²`` with ``d = ‖p_handle −
    p_ee‖``; on the grasp (``d < capture_tolerance``) the core's rigid grasp impulse
    ``Λ = [f̂; n̂]`` (``spacearm.capture.grasp_impulse``) is applied, the robot becomes the captured
    system (``spacearm.capture.attach_target``: the target a payload of the gripper) and the step
    adds ``capture_bonus − w_impulse ‖Λ‖`` (``‖Λ‖`` the 2-norm of the six SI components) and
    terminates. A step that ends with a joint faster than ``max_joint_rate`` (rad/s) costs
    ``runaway_penalty`` and terminates (``info["runaway"]``). Truncated after ``max_episode_steps``. ``info["captured"]`` is the
    [`CapturedSystem`][spacearm.capture.CapturedSystem] after a grasp (None before).
    """

    metadata = {"render_modes": list(_common.RENDER_MODES), "render_fps": 20}

    def __init__(self, robot=None, target: Optional[Target] = None, *, dt: float = 0.01, frame_skip: int = 5, max_torque="auto",
                 approach_distance=(0.2, 0.4), spin_rate=(0.02, 0.08), capture_tolerance: float = 0.05,
                 base_rate_weight: float = 10.0, action_weight: float = 1e-3, impulse_weight: float = 0.1, capture_bonus: float = 50.0,
                 max_joint_rate: float = 3.0, runaway_penalty: float = 100.0, max_episode_steps: int = 300, randomize=None,
                 render_mode: Optional[str] = None):
        self.robot = spatial6() if robot is None else robot
        if self.robot.end_effector is None or self.robot.n_dof == 0:
            raise ArgumentError("Capture needs a robot with joints and an end effector")
        self.target = default_target() if target is None else target
        if not isinstance(self.target, Target) or not self.target.is_rigid:
            raise ArgumentError("target must be a rigid spacearm.Target")
        self.dt = _common.positive(dt, "dt")
        self.frame_skip = _common.count(frame_skip, "frame_skip")
        self.torque_scale = _common.torque_scale(self.robot, max_torque, max_joint_rate=_common.positive(max_joint_rate, "max_joint_rate"))
        self.approach_distance = _range(approach_distance, "approach_distance")
        self.spin_rate = _range(spin_rate, "spin_rate")
        self.capture_tolerance = _common.positive(capture_tolerance, "capture_tolerance")
        self.base_rate_weight = _common.non_negative(base_rate_weight, "base_rate_weight")
        self.action_weight = _common.non_negative(action_weight, "action_weight")
        self.impulse_weight = _common.non_negative(impulse_weight, "impulse_weight")
        self.capture_bonus = _common.non_negative(capture_bonus, "capture_bonus")
        self.max_joint_rate = _common.positive(max_joint_rate, "max_joint_rate")
        self.runaway_penalty = _common.non_negative(runaway_penalty, "runaway_penalty")
        self.max_episode_steps = _common.count(max_episode_steps, "max_episode_steps")
        self.perturbations = _common.check_randomization(randomize)
        self.render_mode = _common.check_render_mode(render_mode)
        n = self.robot.n_dof
        self.observation_space, self.action_space = _common.boxes(2 * n + 15, n)
        self.metadata = {**self.metadata, "render_fps": int(round(1.0 / (self.dt * self.frame_skip)))}
        self._sim = None
        self._frame = None

    def _observe(self) -> np.ndarray:
        plant, nx, n = self._plant, self.robot.nx, self.robot.n_dof
        x, u = self._state[:nx], self._state[nx:]
        p = np.asarray(plant.point_position(x), dtype=float)
        handle = self.target.grasp_position(self._target_state)
        v_rel = -relative_twist(plant, x, u, self.target, self._target_state)[:3] if self.captured is None else np.zeros(3)
        w_t = self._target_state[10:13] if self.captured is None else u[3:6]
        return np.concatenate([x[7:], u[6 : 6 + n], p, handle - p, v_rel, w_t, u[3:6]])

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        self._plant, params = _common.randomized_plant(self.robot, self.perturbations, self.np_random)
        self._sim = Simulator(self._plant, dt=self.dt)
        self._sim.reset()
        self._state = self._sim.state
        x = self._state[: self.robot.nx]
        handle = np.asarray(self._plant.point_position(x), dtype=float) + self.np_random.uniform(*self.approach_distance) * _unit(self.np_random)
        self._target_state = tumbling_target_state(self.target, handle, self.np_random.uniform(*self.spin_rate), self.np_random)
        self.captured = None
        self._steps = 0
        return self._observe(), {"plant": params, "target_state": self._target_state.copy()}

    def step(self, action):
        if self._sim is None:
            raise ArgumentError("call reset() before step()")
        if self.captured is not None:
            raise ArgumentError("the episode ended with the capture; call reset()")
        a = np.clip(_common.actions(action, (self.robot.n_dof,)), -1.0, 1.0)
        nx = self.robot.nx
        self._state = _common.check_finite(self._sim.step(a * self.torque_scale, self.frame_skip)[None], "Capture")[0]
        self._target_state = self.target.propagate(self._target_state, self.dt * self.frame_skip, dt=self.dt)
        self._steps += 1
        x, u = self._state[:nx], self._state[nx:]
        distance = float(np.linalg.norm(self.target.grasp_position(self._target_state) - self._plant.point_position(x)))
        base_rate = float(np.linalg.norm(u[3:6]))
        runaway = bool(np.max(np.abs(u[6:])) > self.max_joint_rate)
        reward = -distance - self.base_rate_weight * base_rate - self.action_weight * float(a @ a) - self.runaway_penalty * runaway
        info = {"distance": distance, "base_rate": base_rate, "is_success": False, "runaway": runaway, "impulse": None, "captured": None}
        if distance < self.capture_tolerance:
            impact = grasp_impulse(self._plant, x, u, self.target, self._target_state, capture_tolerance=self.capture_tolerance)
            self.captured = attach_target(self._plant, x, impact.u_after, self.target, impact.target_state_after)
            self._sim = Simulator(self.captured.robot, dt=self.dt)
            self._sim.reset(self.captured.x, self.captured.u)
            self._state = self._sim.state
            self._target_state = np.asarray(impact.target_state_after, dtype=float)
            impulse = np.asarray(impact.impulse, dtype=float)
            reward += self.capture_bonus - self.impulse_weight * float(np.linalg.norm(impulse))
            info.update(is_success=True, impulse=impulse, captured=self.captured, base_rate=float(np.linalg.norm(self._state[nx + 3 : nx + 6])))
        terminated = self.captured is not None or runaway
        return self._observe(), float(reward), terminated, self._steps >= self.max_episode_steps, info

    def render(self):
        if self.render_mode != "rgb_array" or self._sim is None:
            return None
        if self._frame is None:
            self._frame = _common.Frame(self.robot)
        x = self._state[: self.robot.nx]
        s = self._target_state
        from ..viz.animation import equivalent_box

        sides, axes = equivalent_box(self.target.mass, self.target.inertia)
        box = (s[:3], self.target.rotation(s), sides, axes, "orange")
        status = "captured" if self.captured is not None else "approach"
        return self._frame.rgb(x, [(self.target.grasp_position(s), "C2"), (self._plant.point_position(x), "C3")], boxes=[box],
                               title=f"Capture ({status})  t = {self._steps * self.dt * self.frame_skip:.2f} s")
