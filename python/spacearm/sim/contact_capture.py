"""A capture on contact (docs/contact.md, "A capture on contact" and "The grasp's outcome"): a
robot's gripper closes on a tumbling box's handle, the fingers and the handle touching by the
core's compliant contact with friction, and the core judges the grasp held, slipped or missed.

[`ContactCapture`][spacearm.capture.ContactCapture] describes one such capture as numbers — the
approach errors (the handle's position and attitude relative to the gripper, the target's spin),
the target box and handle, the contact law, the joint PD that holds the arm and squeezes the
fingers, the run's length and step, the outcome's thresholds — and
[`ContactCapture.fly`][spacearm.capture.ContactCapture.fly] flies it: the target model is built
from those numbers, the run is the core's ``simulate`` with a free target, and the outcome is the
core's ``grasp_outcome``. This module converts and calls; nothing here decides the outcome.

The nominal placement puts the handle's centre at the gripper's grasp centre ``<gripper>_center``
(at the robot's initial configuration), the handle's axis along the palm's ``y`` (across the
fingers' closing direction, palm ``x``, and the approach axis, palm ``z``), the box beyond the
handle along the approach axis. The target frame's axes are then ``[z_palm, y_palm, −x_palm]``;
the handle is at ``(−(size/2 + handle_standoff), 0, 0)`` from the box's CM, along the target's
``y``. The approach errors move that placement: ``offset`` (m, in 𝒥) shifts it, ``attitude_error``
(a rotation vector in 𝒥, rad) turns the target about the handle's centre, and ``spin`` (rad/s)
spins it about ``spin_axis`` (target axes; default the handle's axis) through its CM, whose
velocity is zero.

It lives in ``spacearm.sim`` (below ``capture``, ``campaign`` and ``gym``, which all use it) and is
exported as ``spacearm.capture.ContactCapture``. Used by ``spacearm capture MODEL --contact``, by the capture-on-contact campaign
([`spacearm.campaign.run_capture_campaign`][spacearm.campaign.run_capture_campaign]) and by the
Gym environment ``spacearm.gym.ContactCaptureEnv``.
"""

from __future__ import annotations

import dataclasses
from typing import Optional, Tuple

import numpy as np

from .. import _core
from ..errors import ArgumentError, SpacearmTypeError
from .._util.arrays import number

__all__ = ["ContactCapture", "ContactCaptureRun"]


def _vec3(value, what: str) -> Tuple[float, float, float]:
    a = np.asarray(value, dtype=float)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ArgumentError(f"ContactCapture.{what} must be 3 finite numbers, got {value!r}")
    return (float(a[0]), float(a[1]), float(a[2]))


@dataclasses.dataclass(frozen=True)
class ContactCapture:
    """One capture on contact (module docs), every value a number: approach errors ``offset``
    (m, 𝒥), ``attitude_error`` (rotation vector, rad, 𝒥), ``spin`` (rad/s) about ``spin_axis``
    (target axes); the target: a ``target_size`` m cube of ``target_mass`` kg (uniform inertia)
    with a cylindrical handle of ``handle_radius`` and ``handle_length`` m, its centre
    ``handle_standoff`` m off the box's face; the contact: ``stiffness`` (N/m), ``damping``
    (N·s/m), ``friction`` (μ), ``slip_velocity`` (m/s) between each finger and the target; the
    controller: a joint PD holding the arm's joints at their initial values (``hold_kp``,
    ``hold_kd``) and pushing the fingers to their closed limit (``squeeze_kp``, ``squeeze_kd``);
    the run: ``duration`` (s), RK4 ``dt`` (s), ``record_every``; the outcome's thresholds
    (``window`` s, ``max_relative_spin`` rad/s, ``max_relative_speed`` m/s, ``max_offset`` m,
    ``touch_margin`` m; docs/contact.md, "The grasp's outcome"). The defaults are
    docs/contact.md's example (held at 0.05 rad/s about the handle).
    """

    spin: float = 0.05
    spin_axis: Tuple[float, float, float] = (0.0, 1.0, 0.0)
    offset: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    attitude_error: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    target_mass: float = 20.0
    target_size: float = 0.4
    handle_radius: float = 0.02
    handle_length: float = 0.15
    handle_standoff: float = 0.09
    stiffness: float = 2e3
    damping: float = 20.0
    friction: float = 0.5
    slip_velocity: float = 1e-3
    hold_kp: float = 500.0
    hold_kd: float = 100.0
    squeeze_kp: float = 200.0
    squeeze_kd: float = 5.0
    duration: float = 3.0
    dt: float = 5e-4
    record_every: int = 2
    window: float = 0.5
    max_relative_spin: float = 0.005
    max_relative_speed: float = 0.005
    max_offset: float = 0.005
    touch_margin: float = 0.001

    def __post_init__(self):
        for name in ("spin_axis", "offset", "attitude_error"):
            object.__setattr__(self, name, _vec3(getattr(self, name), name))
        for f in dataclasses.fields(self):
            if f.name in ("spin_axis", "offset", "attitude_error", "record_every"):
                continue
            object.__setattr__(self, f.name, number(getattr(self, f.name), f"ContactCapture.{f.name}"))
        if isinstance(self.record_every, bool) or not isinstance(self.record_every, (int, np.integer)) or self.record_every < 1:
            raise ArgumentError(f"ContactCapture.record_every must be an integer >= 1, got {self.record_every!r}")
        if not np.linalg.norm(self.spin_axis) > 0:
            raise ArgumentError("ContactCapture.spin_axis must be a non-zero vector")
        # Every other value (masses, sizes, gains, contact law, thresholds) is checked by the core
        # where it is used: the builder, the contact law, the run options and grasp_outcome.

    def to_dict(self) -> dict:
        """The description as plain numbers (JSON-able)."""
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in dataclasses.asdict(self).items()}

    def replace(self, **changes) -> "ContactCapture":
        """A copy with ``changes``."""
        return dataclasses.replace(self, **changes)

    # -- the models -------------------------------------------------------------------------
    def handle_origin(self) -> np.ndarray:
        """The handle's centre from the target's CM, target axes, m."""
        return np.array([-(0.5 * self.target_size + self.handle_standoff), 0.0, 0.0])

    def target(self):
        """The target: one rigid body with the collision box ``body`` and the cylinder ``handle``."""
        from ..model.builder import RobotBuilder

        m, a = self.target_mass, self.target_size
        b = RobotBuilder("target", m, np.eye(3) * m * a * a / 6.0, base_name="target")
        b.add_geometry("target", "box", role="collision", size=(a, a, a), name="body")
        b.add_geometry("target", "cylinder", role="collision", radius=self.handle_radius, length=self.handle_length,
                       origin=tuple(self.handle_origin()), rpy=(np.pi / 2, 0.0, 0.0), name="handle")
        return b.build()

    @staticmethod
    def gripper_of(robot, gripper: Optional[str] = None) -> dict:
        """The core's description of ``robot``'s gripper ``gripper`` (None: its only one)."""
        grippers = _core.grippers(robot.core_model)
        names = [g["name"] for g in grippers]
        if gripper is None:
            if len(grippers) != 1:
                raise ArgumentError(f"robot '{robot.name}' has {len(grippers)} grippers {names}: a capture on contact "
                                    "needs one (add_gripper, TOML [[gripper]]), or name it (gripper=...)")
            return grippers[0]
        for g in grippers:
            if g["name"] == gripper:
                return g
        raise ArgumentError(f"robot '{robot.name}' has no gripper '{gripper}'; its grippers are {names}")

    def target_state(self, robot, gripper: Optional[str] = None, x0=None) -> np.ndarray:
        """The target's initial 13-state ``[r, quat xyzw, v, ω]`` beside ``robot`` at ``x0``
        (default its initial configuration): the nominal placement moved by the approach errors
        (module docs)."""
        from ..rotations import quat_exp, quat_from_matrix, quat_to_matrix

        g = self.gripper_of(robot, gripper)
        x0 = robot.neutral_configuration() if x0 is None else np.asarray(x0, dtype=float)
        rot = robot.forward_kinematics(x0).body_to_world[g["palm"]]
        px, py, pz = rot[:, 0], rot[:, 1], rot[:, 2]
        nominal = np.column_stack([pz, py, -px])
        R = quat_to_matrix(quat_exp(np.array(self.attitude_error))) @ nominal
        h = robot.point_position(x0, f"{g['name']}_center") + np.array(self.offset)
        r = h - R @ self.handle_origin()
        axis = np.array(self.spin_axis) / np.linalg.norm(self.spin_axis)
        w = self.spin * (R @ axis)
        return np.concatenate([r, quat_from_matrix(R), np.zeros(3), w])

    def controller(self, robot, gripper: Optional[str] = None):
        """The joint PD: the arm's joints held at their initial values, the fingers pushed to
        their closed limit (their joints' upper bound)."""
        from ..control import JointPD

        g = self.gripper_of(robot, gripper)
        links = robot.description.links
        dofs = robot.actuated_arm_dofs
        upper = {link.dof: link.limits.upper for link in links if link.dof is not None}
        q0 = robot.neutral_configuration()[7:]
        fingers = set(g["finger_dofs"])
        kp = [self.squeeze_kp if d in fingers else self.hold_kp for d in dofs]
        kd = [self.squeeze_kd if d in fingers else self.hold_kd for d in dofs]
        ref = [upper[d] if d in fingers else q0[d] for d in dofs]
        return JointPD(kp=kp, kd=kd, reference=ref)

    def contact(self, robot, gripper: Optional[str] = None):
        """The compliant contact between each finger and the target."""
        from ..contact import ContactModel, Pair

        g = self.gripper_of(robot, gripper)
        pairs = [Pair(f"{g['name']}_finger{i}", "target") for i in range(len(g["finger_dofs"]))]
        return ContactModel(stiffness=self.stiffness, damping=self.damping, friction=self.friction,
                            slip_velocity=self.slip_velocity, pairs=pairs)

    # -- the run -----------------------------------------------------------------------------
    def fly(self, robot, gripper: Optional[str] = None) -> "ContactCaptureRun":
        """Fly the capture with ``robot``'s gripper (None: its only one) from its initial
        configuration at rest: the core's run with the free target, then the core's judgement."""
        from ..contact import grasp_outcome
        from ..model.robot import Robot
        from .simulation import simulate

        if not isinstance(robot, Robot):
            raise SpacearmTypeError(f"ContactCapture.fly needs a spacearm.Robot, got {type(robot).__name__}")
        g = self.gripper_of(robot, gripper)
        target = self.target()
        s0 = self.target_state(robot, g["name"])
        traj = simulate(robot, self.duration, dt=self.dt, record_every=self.record_every,
                        controller=self.controller(robot, g["name"]), contact=self.contact(robot, g["name"]),
                        target=target, target_state=s0)
        outcome = grasp_outcome(robot, target, traj, gripper=g["name"], handle="handle", window=self.window,
                                max_relative_spin=self.max_relative_spin, max_relative_speed=self.max_relative_speed,
                                max_offset=self.max_offset, touch_margin=self.touch_margin)
        return ContactCaptureRun(self, robot, target, traj, outcome)


@dataclasses.dataclass(frozen=True)
class ContactCaptureRun:
    """A flown [`ContactCapture`][spacearm.capture.ContactCapture]: the description, the robot,
    the target model, the run's [`Trajectory`][spacearm.Trajectory] (``traj["target"]``: the
    target's 13-state) and the core's [`GraspOutcome`][spacearm.contact.GraspOutcome]."""

    capture: ContactCapture
    robot: object
    target: object
    traj: object
    outcome: object

    @property
    def held(self) -> bool:
        return bool(self.outcome.held)

    def summary(self) -> str:
        o, c = self.outcome, self.capture
        touch = "never" if o.first_touch is None else f"at t = {o.first_touch:.3f} s"
        return "\n".join([
            f"capture on contact of a {c.target_mass:g} kg box spinning at {c.spin:g} rad/s by {self.robot.name}'s gripper "
            f"(offset {np.linalg.norm(c.offset) * 1e3:.1f} mm, attitude error {np.degrees(np.linalg.norm(c.attitude_error)):.2f} deg, "
            f"friction {c.friction:g}): {o.outcome.upper()}",
            f"  {o.reason}",
            f"  first finger on the handle {touch}; over the last {o.window:g} s: relative spin {o.relative_spin:.3e} rad/s, "
            f"relative speed {o.relative_speed:.3e} m/s, handle {1e3 * o.offset:.2f} mm from the grasp centre, "
            f"{o.fingers_touching} of {o.fingers} fingers on it",
        ])
