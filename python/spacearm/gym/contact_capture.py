"""``spacearm/ContactCapture-v0``: close a gripper on a tumbling handle by contact (docs/rl.md,
"`spacearm/ContactCapture-v0`").

The environment's class docstring gives its observation, action and reward.
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from .._util.optional import require
from ..sim.contact_capture import ContactCapture
from ..contact import grasp_outcome
from ..control import JointPD
from ..errors import ArgumentError
from ..sim.simulation import simulate
from . import _common

gymnasium = require("gymnasium", "the Gymnasium environments (spacearm.gym)")

__all__ = ["ContactCaptureEnv"]

#: The numbers of the step's [`GraspOutcome`][spacearm.contact.GraspOutcome] in ``info["grasp"]``.
_GRASP_NUMBERS = ("relative_spin", "relative_speed", "offset", "fingers_touching", "fingers", "first_touch", "reason")


def _servicer():
    from ..examples import path
    from ..io.model_file import load_toml

    return load_toml(path("gripper_servicer"))


class ContactCaptureEnv(gymnasium.Env):
    """``spacearm/ContactCapture-v0``: a robot's gripper closes on a tumbling box's handle, the
    fingers and the handle touching by the core's compliant contact with friction (a
    [`ContactCapture`][spacearm.capture.ContactCapture]; default robot: the shipped
    ``gripper_servicer``).

    Each reset draws the approach errors from ``np_random``: each component of the handle's
    offset from the grasp centre normal with ``offset_sigma`` (m), each of the attitude error
    normal with ``attitude_sigma`` (rad), the spin about the handle uniform in ``spin_rate``
    (rad/s, a range). Each step holds the action's joint set points for ``period`` s: the core
    runs robot and free target together (``spacearm.simulate`` with ``contact`` and ``target``,
    from the step's state) and judges the step's last half (``spacearm.contact.grasp_outcome``,
    window ``period/2``).

    Action (float32, one per actuated joint, in ``[-1, 1]``): the joint PD's set points — an arm
    joint's at its initial value plus ``a · arm_range`` (rad or m), a finger's at
    ``(a + 1)/2`` of its closed limit (−1 open, 1 shut); the gains are the capture's ``hold_kp``,
    ``hold_kd``, ``squeeze_kp``, ``squeeze_kd``.

    Observation (float64, ``2N + 10``): ``[q (N), q̇ (N), h − c (3, m, 𝒥: the handle's centre
    from the grasp centre), the core's numbers of the step's window — relative_spin (rad/s),
    relative_speed (m/s), offset (m), fingers_touching / fingers — and ω_target (3, rad/s, 𝒥)]``
    (after a reset the numbers are ``0, 0, ‖h − c‖, 0``).

    Reward (from the core's outcome of the step): ``−offset / max_offset − relative_spin /
    max_relative_spin·spin_weight + touch_weight · fingers_touching / fingers``, plus
    ``held_bonus`` when the step's outcome is held. Terminated after ``hold_steps`` held steps in a
    row (``info["is_success"]``) or when the handle is farther than ``lost_distance`` (m) from the
    grasp centre; truncated after ``max_episode_steps``. ``info["outcome"]`` is the step's
    outcome ("held", "slipped" or "missed") and ``info["grasp"]`` its numbers (the
    [`GraspOutcome`][spacearm.contact.GraspOutcome]'s ``relative_spin``, ``relative_speed``,
    ``offset``, ``fingers_touching``, ``fingers``, ``first_touch``, ``reason``).
    """

    metadata = {"render_modes": list(_common.RENDER_MODES), "render_fps": 10}

    def __init__(self, robot=None, capture: Optional[ContactCapture] = None, *, gripper: Optional[str] = None,
                 period: float = 0.1, offset_sigma: float = 0.002, attitude_sigma: float = 0.0, spin_rate=(0.0, 0.3),
                 arm_range: float = 0.2, spin_weight: float = 0.1, touch_weight: float = 0.5, held_bonus: float = 1.0,
                 hold_steps: int = 5, lost_distance: float = 0.2, max_episode_steps: int = 50, render_mode: Optional[str] = None):
        self.robot = _servicer() if robot is None else robot
        self.capture = ContactCapture() if capture is None else capture
        if not isinstance(self.capture, ContactCapture):
            raise ArgumentError(f"capture must be a spacearm.capture.ContactCapture, got {type(self.capture).__name__}")
        self.gripper = ContactCapture.gripper_of(self.robot, gripper)
        self.period = _common.positive(period, "period")
        if self.period < 2 * self.capture.dt:
            raise ArgumentError(f"period {self.period} s must span at least two RK4 steps of {self.capture.dt} s")
        self.offset_sigma = _common.non_negative(offset_sigma, "offset_sigma")
        self.attitude_sigma = _common.non_negative(attitude_sigma, "attitude_sigma")
        lo, hi = (spin_rate, spin_rate) if np.ndim(spin_rate) == 0 else tuple(spin_rate)
        self.spin_rate = (_common.non_negative(lo, "spin_rate"), _common.non_negative(hi, "spin_rate"))
        if self.spin_rate[1] < self.spin_rate[0]:
            raise ArgumentError(f"spin_rate must be a number or (low, high) with low <= high, got {spin_rate!r}")
        self.arm_range = _common.non_negative(arm_range, "arm_range")
        self.spin_weight = _common.non_negative(spin_weight, "spin_weight")
        self.touch_weight = _common.non_negative(touch_weight, "touch_weight")
        self.held_bonus = _common.non_negative(held_bonus, "held_bonus")
        self.hold_steps = _common.count(hold_steps, "hold_steps")
        self.lost_distance = _common.positive(lost_distance, "lost_distance")
        self.max_episode_steps = _common.count(max_episode_steps, "max_episode_steps")
        self.render_mode = _common.check_render_mode(render_mode)
        self._frame = None
        self._dofs = list(self.robot.actuated_arm_dofs)
        fingers = set(self.gripper["finger_dofs"])
        self._is_finger = np.array([d in fingers for d in self._dofs])
        upper = {link.dof: link.limits.upper for link in self.robot.description.links if link.dof is not None}
        self._closed = np.array([upper[d] if d in fingers else 0.0 for d in self._dofs])
        self._q0 = np.asarray(self.robot.neutral_configuration()[7:], dtype=float)[self._dofs]
        n = self.robot.n_dof
        self.observation_space, self.action_space = _common.boxes(2 * n + 10, len(self._dofs))
        self._target_model = self.capture.target()
        self.metadata = {**self.metadata, "render_fps": max(1, int(round(1.0 / self.period)))}
        self._state = None

    def _observe(self, x, u, s, o) -> np.ndarray:
        from ..rotations import quat_to_matrix

        n = self.robot.n_dof
        h = s[:3] + quat_to_matrix(s[3:7]) @ self.capture.handle_origin()
        c = self.robot.point_position(x, f"{self.gripper['name']}_center")
        numbers = [0.0, 0.0, float(np.linalg.norm(h - c)), 0.0] if o is None else [
            o.relative_spin, o.relative_speed, o.offset, o.fingers_touching / o.fingers]
        return np.concatenate([x[7:], u[6:6 + n], h - c, numbers, s[10:13]])

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        rng = self.np_random
        offset = rng.normal(0.0, 1.0, 3) * self.offset_sigma
        attitude = rng.normal(0.0, 1.0, 3) * self.attitude_sigma
        spin = rng.uniform(*self.spin_rate)
        self._case = self.capture.replace(offset=tuple(offset), attitude_error=tuple(attitude), spin=float(spin))
        x = np.asarray(self.robot.neutral_configuration(), dtype=float)
        u = np.zeros(self.robot.nu)
        s = self._case.target_state(self.robot, self.gripper["name"], x)
        self._state = (x, u, s)
        self._steps = 0
        self._held_run = 0
        info = {"offset": offset, "attitude_error": attitude, "spin": spin, "target_state": s.copy()}
        return self._observe(x, u, s, None), info

    def step(self, action):
        if self._state is None:
            raise ArgumentError("call reset() before step()")
        a = np.clip(_common.actions(action, (len(self._dofs),)), -1.0, 1.0)
        ref = np.where(self._is_finger, 0.5 * (a + 1.0) * self._closed, self._q0 + a * self.arm_range)
        kp = np.where(self._is_finger, self._case.squeeze_kp, self._case.hold_kp)
        kd = np.where(self._is_finger, self._case.squeeze_kd, self._case.hold_kd)
        x, u, s = self._state
        c = self._case
        traj = simulate(self.robot, self.period, dt=c.dt, x0=x, u0=u, controller=JointPD(kp=kp, kd=kd, reference=ref),
                        contact=c.contact(self.robot, self.gripper["name"]), target=self._target_model, target_state=s)
        o = grasp_outcome(self.robot, self._target_model, traj, gripper=self.gripper["name"], window=0.5 * self.period,
                          max_relative_spin=c.max_relative_spin, max_relative_speed=c.max_relative_speed,
                          max_offset=c.max_offset, touch_margin=c.touch_margin)
        x, u, s = np.array(traj.x[-1]), np.array(traj.u[-1]), np.array(traj["target"][-1])
        self._state = (x, u, s)
        self._steps += 1
        self._held_run = self._held_run + 1 if o.held else 0
        reward = (-o.offset / c.max_offset - self.spin_weight * o.relative_spin / c.max_relative_spin
                  + self.touch_weight * o.fingers_touching / o.fingers + (self.held_bonus if o.held else 0.0))
        obs = self._observe(x, u, s, o)
        lost = bool(np.linalg.norm(obs[2 * self.robot.n_dof:2 * self.robot.n_dof + 3]) > self.lost_distance)
        success = self._held_run >= self.hold_steps
        info = {"outcome": o.outcome, "grasp": {k: getattr(o, k) for k in _GRASP_NUMBERS}, "is_success": success, "lost": lost}
        return obs, float(reward), success or lost, self._steps >= self.max_episode_steps, info

    def render(self):
        if self.render_mode != "rgb_array" or self._state is None:
            return None
        from ..rotations import quat_to_matrix

        if self._frame is None:
            self._frame = _common.Frame(self.robot, half_width=1.5)
        x, _, s = self._state
        a = self._case.target_size
        rot = quat_to_matrix(s[3:7])
        box = (s[:3], rot, np.full(3, a), np.eye(3), "orange")
        handle = s[:3] + rot @ self._case.handle_origin()
        centre = self.robot.point_position(x, f"{self.gripper['name']}_center")
        return self._frame.rgb(x, [(handle, "C2"), (centre, "C3")], boxes=[box],
                               title=f"ContactCapture  t = {self._steps * self.period:.2f} s")
