"""Basilisk modules (``sysModel.SysModel`` subclasses) running spacearm's core: a control law as
flight software ([`ControllerModule`][spacearm.basilisk.ControllerModule]) and the per-body
gravity-gradient torque an ``MJScene`` lacks ([`GravityGradientModule`][spacearm.basilisk.GravityGradientModule]).

Importing this module imports Basilisk (``pip install "spacearm[basilisk]"``); ``spacearm.basilisk``
imports it on first use of either name.
"""

from __future__ import annotations

import numpy as np

from ..errors import ArgumentError, SpacearmTypeError
from ..model.robot import Robot
from ..orbit import CentralBody, Orbit
from ..sim.simulator import Simulator
from . import _bsk
from .scene import ActuatorMap, state_from_scene

__all__ = ["ControllerModule", "GravityGradientModule"]

_sys_model = _bsk.sys_model()
_messaging = _bsk.messaging()
_NANO = 1e-9
#: The modes whose base wrench is always zero (docs/modes.md): no base actuators needed.
_NO_THRUSTERS = ("floating", "rotation-floating")


def _check(robot, actuators):
    if not isinstance(robot, Robot):
        raise SpacearmTypeError(f"a spacearm.Robot is needed, got {type(robot).__name__}")
    if not isinstance(actuators, ActuatorMap):
        raise SpacearmTypeError("actuators must be the ActuatorMap of spacearm.basilisk.to_mjscene(robot), "
                                f"got {type(actuators).__name__}")


class ControllerModule(_sys_model.SysModel):
    """A spacearm control law as a Basilisk flight-software module.

    ``controller`` is any native law of [`spacearm.control`][spacearm.control] (the same object a
    [`spacearm.simulate`][spacearm.simulate] run takes: one run description, the core's
    ``ControllerSpec``); ``mode``, ``wheels``, ``thrusters``, ``joint_limits`` as for
    ``simulate``. At every call of its task (``UpdateState``, at the task's rate) the module
    reads the scene's state ([`state_from_scene`][spacearm.basilisk.state_from_scene]), asks the
    core for the command at ``(t, x, u)`` (``Simulator.command``: the law, the actuator limits and
    the mode's mask, as inside a spacearm run) and writes it to one ``SingleActuatorMsg`` per
    actuator of ``actuators`` (``actuatorOutMsgs[name]``, subscribed here to the scene's
    actuators): the command is held until the next call (sample and hold at the task rate).
    ``t`` is the simulation time minus ``t_start`` (s). ``orbit`` (a [`spacearm.Orbit`][spacearm.Orbit]):
    the scene flies in ECI and the law sees the state relative to the orbit's point O at the
    simulation time (the orbit's epoch is the scene's time 0, whatever ``t_start``),
    as in a spacearm orbital run (a Cartesian reference, a momentum, an LVLH attitude are then
    relative to O). Put the module in a task that runs after
    the scene's (a lower priority, or added after it), so that it reads the state at its own
    time. ``last_command`` holds the last ``(tau, base_wrench)``. A law that does not fit the
    plant or the mode is refused here, when the module is made; an error inside Basilisk's
    ``Reset`` or ``UpdateState`` reaches the caller as SWIG's ``RuntimeError``, the spacearm
    message printed above it.
    """

    def __init__(self, robot, controller, scene, actuators, *, mode: str = "floating", wheels=None,
                 thrusters=None, joint_limits: bool = False, t_start: float = 0.0, orbit=None):
        super().__init__()
        _check(robot, actuators)
        if controller is None:
            raise ArgumentError("ControllerModule needs a spacearm.control controller (got None)")
        self.ModelTag = "spacearmController"
        self.robot, self.scene, self.actuators = robot, scene, actuators
        self.t_start = float(t_start)
        # The core evaluates the law: a Simulator's plant, never stepped (dt plays no part).
        if orbit is not None and not isinstance(orbit, Orbit):
            raise SpacearmTypeError(f"orbit must be a spacearm.Orbit, got {type(orbit).__name__}")
        self.orbit = orbit
        self._sim = Simulator(robot, controller=controller, mode=mode, wheels=wheels, thrusters=thrusters,
                              joint_limits=joint_limits, orbit=orbit)
        # The core's setup checks (law against plant and mode) here, not inside Basilisk's Reset
        # (where SWIG would turn them into a bare RuntimeError).
        self._sim.reset(robot.neutral_configuration(), robot.zero_velocity())
        if mode not in _NO_THRUSTERS and not actuators.base:
            raise ArgumentError(f"mode {mode!r} commands a base wrench but the scene has no base actuators: "
                                "make it with to_mjscene(robot, base_actuators=True)")
        self.actuatorOutMsgs = {}
        for name in actuators.names:
            msg = _messaging.SingleActuatorMsg()
            msg.write(_messaging.SingleActuatorMsgPayload(input=0.0))
            self.actuatorOutMsgs[name] = msg
        self.connect()
        self.last_command = (np.zeros(robot.n_dof), np.zeros(6))

    def connect(self) -> None:
        """Subscribe the scene's actuators to this module's messages (done when it is made; call
        it again to hand the actuators back to this module after another took them: a phase
        switch, with Basilisk's ``disableTask`` / ``enableTask`` on the modules' tasks)."""
        for name, msg in self.actuatorOutMsgs.items():
            self.scene.getSingleActuator(name).actuatorInMsg.subscribeTo(msg)

    def state(self, CurrentSimNanos):
        """The law's time and state at ``CurrentSimNanos``: ``t`` (s from ``t_start``) and the
        scene's ``(x, u)``, relative to the orbit's point O at the scene's time with ``orbit`` (the frame of
        spacearm's orbital runs, docs/orbit.md: the scene's base position is then in ECI)."""
        t = CurrentSimNanos * _NANO - self.t_start
        x, u = state_from_scene(self.robot, self.scene)
        if self.orbit is not None:  # O where it is now: the orbit's clock is the scene's, not the law's
            (r_o,), (v_o,) = self.orbit.propagate([CurrentSimNanos * _NANO])
            x[:3] -= r_o
            u[:3] -= v_o
        return t, x, u

    def Reset(self, CurrentSimNanos):
        """A fresh controller from the scene's state (its internal state, e.g. a held orientation, starts again)."""
        _, x, u = self.state(CurrentSimNanos)
        self._sim.reset(x, u)

    def UpdateState(self, CurrentSimNanos):
        t, x, u = self.state(CurrentSimNanos)
        tau, wrench = self._sim.command(t, x, u)
        if not self.actuators.base and np.any(wrench != 0.0):
            raise ArgumentError("the controller commands a base wrench but the scene has no base actuators: "
                                "make it with to_mjscene(robot, base_actuators=True)")
        for dof, name in self.actuators.joints:
            self.actuatorOutMsgs[name].write(_messaging.SingleActuatorMsgPayload(input=float(tau[dof])), CurrentSimNanos, self.moduleID)
        for k, name in enumerate(self.actuators.base):
            self.actuatorOutMsgs[name].write(_messaging.SingleActuatorMsgPayload(input=float(wrench[k])), CurrentSimNanos, self.moduleID)
        self.last_command = (tau, wrench)


class GravityGradientModule(_sys_model.SysModel):
    """The gravity-gradient (tidal) torque on every body of a spacearm scene, from spacearm's core.

    Basilisk's ``NBodyGravity`` applies gravity at each body's CM (the forces, tidal part
    included) but no torque about it; this module adds, for each body ``i``, the torque about
    its CM of the tidal field of a central body of ``mu`` (m³/s², default Earth's): the core's
    ``Orbit.tidal_torques`` (``docs/orbit.md``: $\\tau_i = \\frac{3\\mu}{|r|^5}\\, r \\times I_i r$ to
    first order, $r$ the system CM's position from the central body's centre, $I_i$ the body's
    inertia in 𝒥), through a torque actuator on the body's origin site (its CM: the scene of
    [`to_mjscene`][spacearm.basilisk.to_mjscene]) in body axes. The scene's base position must
    then be relative to the central body's centre (ECI). Add it to the scene's dynamics task
    (``scene.AddModelToDynamicsTask(module)``): it runs at every integrator stage. The scene
    keeps only a C++ pointer to it, so keep a Python reference to the module for as long as the
    scene runs (one created inline in that call is freed at once and the scene crashes later).
    The torques of the last call are in ``torques`` (n_bodies, 3), in 𝒥.
    """

    def __init__(self, robot, scene, actuators, *, mu: float = None):
        super().__init__()
        _check(robot, actuators)
        self.ModelTag = "spacearmGravityGradient"
        self.robot, self.scene = robot, scene
        self.mu = CentralBody.earth().mu if mu is None else float(mu)
        if not (np.isfinite(self.mu) and self.mu > 0):
            raise ArgumentError(f"mu must be finite and > 0 (m^3/s^2), got {mu}")
        self._body = CentralBody(mu=self.mu, radius=1.0, j2=0.0)
        self.torqueOutMsgs = {}
        self._bodies = []
        for b, name in actuators.bodies:
            body = scene.getBody(name)
            act = scene.addTorqueActuator(f"{name}_gravity_gradient", body.getOrigin())
            msg = _messaging.TorqueAtSiteMsg()
            msg.write(_messaging.TorqueAtSiteMsgPayload())
            act.torqueInMsg.subscribeTo(msg)
            self.torqueOutMsgs[name] = msg
            self._bodies.append((b, name))
        self.torques = np.zeros((len(robot.body_names), 3))

    def torques_at(self, x, u=None) -> np.ndarray:
        """The core's tidal torques about each body's CM (n_bodies, 3), in 𝒥, at the scene
        configuration ``x`` (``x[:3]`` from the central body's centre; ``u`` plays no part)."""
        x = np.asarray(x, dtype=float)
        r_cm = self.robot.center_of_mass(x)
        # The core's tidal field at r_cm (Orbit.tidal_torques at t = 0 reads only the orbit's
        # position): an orbit through r_cm with the circular speed, whatever the scene's velocity.
        axis = np.eye(3)[int(np.argmin(np.abs(r_cm)))]
        along = np.cross(r_cm, axis)
        v_circ = np.sqrt(self.mu / np.linalg.norm(r_cm)) * along / np.linalg.norm(along)
        orbit = Orbit.from_state(r_cm, v_circ, body=self._body)
        x_rel = x.copy()
        x_rel[:3] -= r_cm  # the run's frame: origin at the orbit's point O, here the system CM
        wrenches, _, _ = orbit.tidal_torques(self.robot.core_model, x_rel, t=0.0)
        return wrenches[:, 3:]

    def UpdateState(self, CurrentSimNanos):
        x, u = state_from_scene(self.robot, self.scene)
        self.torques = self.torques_at(x, u)
        rotations = self.robot.forward_kinematics(x).body_to_world
        for b, name in self._bodies:
            torque_in_body = rotations[b].T @ self.torques[b]
            self.torqueOutMsgs[name].write(_messaging.TorqueAtSiteMsgPayload(torque_S=[float(v) for v in torque_in_body]),
                                           CurrentSimNanos, self.moduleID)
