"""A simulation stepped from Python: [`Simulator`][spacearm.Simulator], the building block of RL environments
and MPC loops.

The stepping runs the native RK4 loop of [`spacearm.simulate`][spacearm.simulate] (one code path in the core),
so stepping a simulator ``n`` times of ``dt`` records exactly what ``simulate`` records for a
duration of ``n·dt``. Between steps, a joint torque (and a base wrench) can be held over the
next steps, added to the controller's command.

>>> import spacearm
>>> robot = spacearm.presets.spatial6()
>>> sim = spacearm.Simulator(robot, dt=1e-3, record_every=10)
>>> sim.reset(robot.neutral_configuration(), robot.zero_velocity())
>>> for _ in range(100):
...     state = sim.step(tau=[0.1, 0, 0, 0, 0, 0])
>>> round(sim.time, 9), sim.trajectory()["x"].shape
(0.1, (11, 13))
"""

from __future__ import annotations

from typing import Optional

import numpy as np

from .._util.spec import controller_spec
from .. import _core
from .._util.arrays import count
from ..errors import ArgumentError
from .simulation import DEFAULTS, _check_controller, _check_robot, _options

__all__ = ["Simulator"]


class Simulator:
    """Step ``robot`` under ``controller`` with RK4 steps of ``dt``.

    Parameters
    ----------
    robot : Robot
        The plant.
    mode, dt, wheels, thrusters, joint_limits
        As for [`spacearm.simulate`][spacearm.simulate].
    integrator : str
        ``"rk4"`` (the only one a step-by-step simulation supports: an adaptive step has no
        fixed grid to stop on; use [`spacearm.simulate`][spacearm.simulate] for ``"dopri5"``).
    controller : spacearm.control controller, optional
        Evaluated at every integrator stage; ``None``: zero torques. Each [`reset`][spacearm.Simulator.reset] starts
        a fresh instance.
    record_every : int, optional
        Record every k-th step for [`trajectory`][spacearm.Simulator.trajectory]; ``None`` (default): record nothing (the
        fastest stepping).
    record_dtype : str
        ``"float64"`` or ``"float32"`` for [`trajectory`][spacearm.Simulator.trajectory]'s arrays.
    orbit, gravity_gradient
        As for [`spacearm.simulate`][spacearm.simulate] (docs/orbit.md).
    contact : spacearm.contact.ContactModel, optional
        As for [`spacearm.simulate`][spacearm.simulate] (docs/contact.md, "Contact dynamics").

    Notes
    -----
    Call [`reset`][spacearm.Simulator.reset] before the first [`step`][spacearm.Simulator.step]. A failed step (the motion diverged)
    raises [`SimulationError`][spacearm.SimulationError] and leaves the simulator needing a reset.
    """

    def __init__(
        self,
        robot,
        *,
        mode: str = DEFAULTS["mode"],
        integrator: str = DEFAULTS["integrator"],
        dt: float = DEFAULTS["dt"],
        controller=None,
        wheels=None,
        thrusters=None,
        joint_limits: bool = DEFAULTS["joint_limits"],
        record_every: Optional[int] = None,
        record_dtype: str = "float64",
        orbit=None,
        gravity_gradient: Optional[bool] = None,
        contact=None,
    ):
        _check_robot(robot, "Simulator")
        _check_controller(controller)
        if integrator != "rk4":
            raise ArgumentError(f"Simulator steps with integrator 'rk4' only (got {integrator!r}); use spacearm.simulate for 'dopri5'")
        if record_every is not None:
            record_every = count(record_every, "record_every")
        options = _options(
            robot, mode=mode, integrator=integrator, dt=dt, rtol=DEFAULTS["rtol"], atol=DEFAULTS["atol"], wheels=wheels,
            thrusters=thrusters, record_every=1, joint_limits=joint_limits, max_steps=DEFAULTS["max_steps"], record_dtype=record_dtype,
            orbit=orbit, gravity_gradient=gravity_gradient, contact=contact,
        )
        spec = None if controller is None else controller_spec(controller)
        self._robot = robot
        self._what = (mode, float(dt), "no controller" if controller is None else type(controller).__name__)
        self._core = _core.Simulator(robot.core_model, options, spec, None if record_every is None else int(record_every))
        # The step itself, bound once: each call goes straight to the core.
        self.step = self._core.step

    def __repr__(self) -> str:
        mode, dt, controller = self._what
        try:
            where = f"t = {self._core.time:.6g} s after {self._core.n_steps} steps"
        except ArgumentError:  # not reset yet
            where = "not reset yet"
        return f"<Simulator of {self._robot.name!r}: {mode} mode, RK4 dt = {dt:g} s, {controller}; {where}>"

    def reset(self, x0=None, u0=None) -> None:
        """Start at ``t = 0`` from ``x0`` (default: the neutral configuration) and ``u0``
        (default: zero), with empty records and a fresh controller."""
        self._core.reset(self._robot.neutral_configuration() if x0 is None else x0, self._robot.zero_velocity() if u0 is None else u0)

    def step(self, tau=None, n: Optional[int] = None, base_wrench=None) -> np.ndarray:  # replaced per instance by the core's method
        """Advance ``n`` steps of ``dt`` (an int >= 1; ``None``: one) with ``tau`` (N joint
        torques) and ``base_wrench`` (``[F0, N0]`` in 𝒥, as the mode allows) added to the
        controller's command over these steps (``None``: nothing added), and return the new
        state ``[x; u]`` (length 13+2N; a new array, as [`state`][spacearm.Simulator.state]).
        Steps land on ``t = i·dt``. The records the steps would add are admitted first
        (``ResourceLimitError``); Ctrl-C stops a long call within 0.1 s, the steps taken so far
        kept.

        Used without Gym, this is the whole loop of a learning environment or a hardware
        test: ``state = sim.step(tau)`` once per control period."""
        return self._core.step(tau, n, base_wrench)

    def command(self, t: float, x, u):
        """The command the plant applies at ``(t, x, u)``, without stepping: ``(tau, base_wrench)``
        (N joint torques; ``[F0, N0]`` at the base CM in 𝒥), the controller's law (plus the
        input of the last [`step`][spacearm.Simulator.step]) through the actuator limits and the
        mode's mask, as at every stage of a step. The controller keeps its internal state across
        calls: a flight-software loop samples the law this way
        (``spacearm.basilisk.ControllerModule``, docs/basilisk.md). Needs a
        [`reset`][spacearm.Simulator.reset] first."""
        return self._core.command(t, x, u)

    @property
    def time(self) -> float:
        """The current time, s."""
        return self._core.time

    @property
    def state(self) -> np.ndarray:
        """The current state ``[x; u]`` (length 13+2N; a new array)."""
        return self._core.state

    @property
    def x(self) -> np.ndarray:
        """The current configuration ``[r0, quat0, q]``."""
        return self._core.state[: self._robot.nx]

    @property
    def u(self) -> np.ndarray:
        """The current velocity ``[v0, w0, qd]``."""
        return self._core.state[self._robot.nx :]

    @property
    def n_steps(self) -> int:
        """Steps taken since the last reset."""
        return self._core.n_steps

    def trajectory(self):
        """The records so far, the current state as the last sample, as a
        [`Trajectory`][spacearm.Trajectory] (the simulation goes on unchanged). Without
        ``record_every`` it holds only the current state."""
        from .trajectory import Trajectory

        result = self._core.result()
        data = {**result.records.to_dict(), **result.events.to_dict()}
        meta = result.meta.to_dict()
        meta["duration"] = float(data["t"][-1])
        meta["robot"] = self._robot.name
        return Trajectory._adopt(self._robot, data, meta)
