"""Simulation of a spacecraft-manipulator system: [`simulate`][spacearm.simulate].

The whole loop — integrator, maneuvering mode, actuator limits, controller, recording — runs in
the Rust core (``spacearm_core::simulate``); this module checks and converts the arguments and
wraps the records in a [`Trajectory`][spacearm.Trajectory]. Integrators, modes, actuators
and controllers are described with their equations in ``docs/simulation-core.md``.

>>> import spacearm
>>> robot = spacearm.presets.spatial6()
>>> u0 = robot.zero_velocity(); u0[6:] = 0.2        # joints moving, base at rest
>>> traj = spacearm.simulate(robot, 2.0, u0=u0)     # free-floating, zero torques, RK4
>>> traj.meta["conserved"]
['P', 'L_origin', 'energy']
"""

from __future__ import annotations

import warnings
from typing import Callable, Optional, Sequence, Union

import numpy as np

from .._util.spec import controller_spec, data as spec_data
from .. import _core
from .._util.arrays import count, number, vector
from ..control import Thrusters, _Controller
from ..errors import ArgumentError, NotFoundError
from .events import stop_data

__all__ = ["simulate", "MODES", "INTEGRATORS", "DEFAULTS", "RECORD_DTYPES"]

#: The maneuvering modes (paper Table 1), as the core names them.
MODES = tuple(_core.MODES)
#: The integrators, as the core names them.
INTEGRATORS = tuple(_core.INTEGRATORS)
#: The simulation defaults (mode, integrator, dt, rtol, atol, record_every, joint_limits,
#: max_steps): the core's, read here so that the signatures below cannot drift from them.
DEFAULTS = dict(_core.SIM_DEFAULTS)


def _wheel_dofs(robot, wheels) -> Optional[list]:
    """Wheel joints given by joint name, link name or dof index → dof indices."""
    if wheels is None:
        return None
    if isinstance(wheels, (str, int, np.integer)):
        wheels = [wheels]
    links = robot.description.links
    out = []
    for w in wheels:
        if isinstance(w, (int, np.integer)) and not isinstance(w, bool):
            if not 0 <= int(w) < robot.n_dof:
                raise NotFoundError(f"wheel dof {w} does not exist (the robot has dofs 0..{robot.n_dof - 1})")
            out.append(int(w))
            continue
        if not isinstance(w, str):
            raise ArgumentError(f"wheels are joint names, link names or dof indices, got {w!r}")
        match = [link for link in links if w in (link.joint, link.name)]
        if not match:
            joints = [link.joint for link in links if link.dof is not None]
            raise NotFoundError(f"no joint or link named '{w}' for a reaction wheel; the joints are {joints}")
        if match[0].dof is None:
            raise ArgumentError(f"wheel '{w}' is on a fixed joint; a reaction wheel needs a revolute joint")
        out.append(match[0].dof)
    return out


def _progress_callable(progress):
    """``progress``: False/None, True (a tqdm bar) or a callable(fraction); returns
    ``(callable or None, closer)``."""
    if progress is None or progress is False:
        return None, lambda: None
    if progress is True:
        from tqdm.auto import tqdm

        bar = tqdm(total=1000, desc="simulate", unit="‰", leave=False)
        state = {"n": 0}

        def update(fraction: float) -> None:
            n = int(round(1000 * fraction))
            if n > state["n"]:
                bar.update(n - state["n"])
                state["n"] = n

        return update, bar.close
    if callable(progress):
        return progress, lambda: None
    raise ArgumentError(f"progress must be True, False or a callable(fraction), got {progress!r}")


#: The dtypes a run can record in (``record_dtype``); the time ``t`` is always float64.
RECORD_DTYPES = ("float64", "float32")


def _check_robot(robot, what: str):
    from ..model.robot import Robot

    if not isinstance(robot, Robot):
        raise ArgumentError(f"{what} needs a spacearm.Robot, got {type(robot).__name__}")


def _check_duration(duration) -> float:
    try:
        return float(duration)
    except (TypeError, ValueError) as exc:
        raise ArgumentError(f"duration must be a number of seconds, got {duration!r}") from exc


def _check_controller(controller, what: str = "controller"):
    if controller is not None and not isinstance(controller, _Controller):
        raise ArgumentError(
            f"{what} must be None or a spacearm.control controller (JointPD, ComputedTorque, ..., Callback), got {type(controller).__name__}"
        )


def _recorded_floating_run(robot, controller, integrator, dt, rtol, atol):
    """``(options, controller spec)`` of a floating-mode run recording every step, ``atol``
    defaulting to ``rtol * 1e-2`` (the soft capture's and the closed chain's runs)."""
    _check_controller(controller)
    rtol = number(rtol, "rtol")
    atol = rtol * 1e-2 if atol is None else number(atol, "atol")
    options = _options(robot, mode="floating", integrator=integrator, dt=dt, rtol=rtol, atol=atol, wheels=None, thrusters=None,
                       record_every=1, joint_limits=DEFAULTS["joint_limits"], max_steps=DEFAULTS["max_steps"], record_dtype="float64")
    return options, None if controller is None else controller_spec(controller)


def _options(robot, *, mode, integrator, dt, rtol, atol, wheels, thrusters, record_every, joint_limits, max_steps, record_dtype,
             progress=None, orbit=None, gravity_gradient=None, stop=None, contact=None) -> _core.RunOptions:
    """The options of the core's simulation entry points (``_core.simulate``, ``_core.rollout``,
    ``_core.Simulator``), every value checked; ``progress``: None or a callable(fraction)."""
    # The names of mode and integrator, record_dtype and the numbers are judged by the core
    # (RunOptions: "mode must be one of [...]", ...).
    if thrusters is not None and not isinstance(thrusters, Thrusters):
        raise ArgumentError(f"thrusters must be a spacearm.control.Thrusters, got {type(thrusters).__name__}")
    record_every, max_steps = count(record_every, "record_every"), count(max_steps, "max_steps")
    from ..contact import ContactModel

    if contact is not None and not isinstance(contact, ContactModel):
        raise ArgumentError(f"contact must be a spacearm.contact.ContactModel, got {type(contact).__name__}")
    return _core.RunOptions(
        mode=mode,
        integrator=integrator,
        dt=float(dt) if isinstance(dt, (int, float, np.floating, np.integer)) else dt,
        rtol=rtol,
        atol=atol,
        record_every=int(record_every),
        wheels=_wheel_dofs(robot, wheels),
        thrusters=None if thrusters is None else _core.ThrusterLimits.from_spec(spec_data(thrusters, [], "thrusters")),
        joint_limits=bool(joint_limits),
        max_steps=int(max_steps),
        progress=progress,
        record_dtype=record_dtype,
        orbit=orbit,
        gravity_gradient=gravity_gradient,
        stop=stop_data(stop) if stop is not None else None,
        contact=None if contact is None else spec_data(contact, [], "contact"),
    )


def orbit_meta(options: _core.RunOptions) -> dict:
    """The orbit of a run for ``Trajectory.meta`` (plain data, JSON): the body's constants, J2
    on or off, the gravity gradient, the ECI state and osculating elements at t = 0."""
    orbit = options.orbit
    el = orbit.elements()
    return {
        "mu": orbit.body.mu, "radius": orbit.body.radius, "j2_coefficient": orbit.body.j2, "j2": orbit.j2,
        "gravity_gradient": options.gravity_gradient, "r0_eci": orbit.r0.tolist(), "v0_eci": orbit.v0.tolist(),
        "elements": {"a": el.a, "e": el.e, "i": el.i, "raan": el.raan, "argp": el.argp, "true_anomaly": el.true_anomaly},
        "period": orbit.period, "mean_motion": orbit.mean_motion,
    }


def _warn_dropped(meta: dict, stacklevel: int) -> None:
    """Warn that the run's mode dropped part of the commanded base wrench, if it did."""
    dropped = meta["dropped_base_wrench"]
    if dropped["count"]:
        warnings.warn(
            f"mode '{meta['mode']}' does not allow part of the base wrench the controller commanded; it was dropped in "
            f"{dropped['count']} evaluations (largest dropped norm {dropped['max_norm']:.3g}); see meta['dropped_base_wrench']",
            RuntimeWarning,
            stacklevel=stacklevel + 1,
        )


def _warn_unreachable(meta: dict, stacklevel: int) -> None:
    """Warn that a point controller (RMRC) stopped short of its goal with its damping active:
    ``meta["goal"]["unreachable"]`` (docs/singularities.md, "Goals out of reach")."""
    goal = meta.get("goal")
    if goal and goal["unreachable"]:
        warnings.warn(
            f"the controller's goal is out of reach: the point ended {goal['distance']:.4g} m from its reference with the task "
            f"Jacobian nearly singular (smallest singular value {goal['sigma_min']:.3g}, damped least squares active); "
            "see meta['goal']",
            RuntimeWarning,
            stacklevel=stacklevel + 1,
        )


def _warn_passive_commanded(robot, data: dict, meta: dict, stacklevel: int) -> None:
    """Flag and warn when the controller commanded a torque on a passive joint (which has no
    motor, so the torque was not applied; docs/flexibility.md): ``meta["passive_joints_commanded"]``
    lists those joints (empty when none)."""
    passive = np.flatnonzero(~robot.actuated_dofs)
    tau_cmd = data.get("tau_cmd")
    names = []
    if passive.size and tau_cmd is not None:
        joint_names = [link.joint for link in robot.description.links if link.type != "fixed"]
        names = [joint_names[d] for d in passive if np.any(np.asarray(tau_cmd)[:, d] != 0.0)]
    meta["passive_joints_commanded"] = names
    if names:
        warnings.warn(
            f"the controller commanded torque on the passive joints {names}, which have no motor: it was not applied "
            "(the records' tau is zero there, tau_cmd keeps the command); see meta['passive_joints_commanded']",
            RuntimeWarning,
            stacklevel=stacklevel + 1,
        )


def _second_system(target, target_state):
    """The second system of a run as the core takes it: ``(core model or None, state or None)``."""
    from ..model.robot import Robot

    # a spacearm.Target carries its rigid model as .body (read by attribute: capture imports
    # this module)
    if not isinstance(target, Robot) and isinstance(getattr(target, "body", None), Robot):
        target = target.body
    if target is not None and not isinstance(target, Robot):
        raise ArgumentError(f"target must be a spacearm.Target or a rigid spacearm.Robot (the second system), got {type(target).__name__}")
    state = None if target_state is None else vector(target_state, "target_state")
    return None if target is None else target.core_model, state


def _events_data(events):
    """The topology events as the core's plain data (None: no events)."""
    if events is None:
        return None
    from ..events import events_data

    return events_data(events)


def simulate(
    robot,
    duration: float,
    *,
    x0: Optional[Sequence[float]] = None,
    u0: Optional[Sequence[float]] = None,
    mode: str = DEFAULTS["mode"],
    integrator: str = DEFAULTS["integrator"],
    dt: float = DEFAULTS["dt"],
    rtol: float = DEFAULTS["rtol"],
    atol: float = DEFAULTS["atol"],
    controller=None,
    wheels=None,
    thrusters: Optional[Thrusters] = None,
    record_every: int = DEFAULTS["record_every"],
    progress: Union[bool, Callable[[float], None]] = False,
    joint_limits: bool = DEFAULTS["joint_limits"],
    max_steps: int = DEFAULTS["max_steps"],
    record_dtype: str = "float64",
    orbit=None,
    gravity_gradient: Optional[bool] = None,
    stop=None,
    contact=None,
    events=None,
    target=None,
    target_state=None,
):
    """Simulate ``robot`` for ``duration`` seconds and return a [`Trajectory`][spacearm.Trajectory].

    Parameters
    ----------
    robot : Robot
        The plant.
    duration : float
        Simulated time, s (> 0).
    x0, u0 : array, optional
        Initial configuration ``[r0, quat0 (x, y, z, w), q]`` and velocity ``[v0, w0, qd]``
        (default: ``robot.neutral_configuration()`` and zero). Any momentum is allowed.
    mode : str
        ``"floating"`` (no base actuation), ``"rotation-floating"`` (reaction wheels),
        ``"rotation-flying"`` (base torque only), ``"translation-flying"`` (base force through
        the system CM), ``"flying"`` (full base wrench). The mode decides which base-wrench
        components reach the plant and which momenta are conserved (``meta["conserved"]``,
        with their drift in ``meta["drift"]``). Components a mode does not allow are dropped,
        counted in ``meta["dropped_base_wrench"]`` and warned about.
    integrator : str
        ``"rk4"`` (fixed step ``dt``) or ``"dopri5"`` (adaptive Dormand–Prince 5(4) with
        ``rtol``/``atol``; ``dt`` is then the output interval, filled by dense output).
    controller : spacearm.control controller, optional
        ``None``: zero torques. See [`spacearm.control`][spacearm.control].
    wheels : list of joint names, link names or dof indices, optional
        The reaction wheels (default: every symmetric rotor on a revolute joint of the base,
        i.e. what ``RobotBuilder.add_reaction_wheel`` creates). Their torque and speed limits
        are the joints' effort and velocity limits.
    thrusters : spacearm.control.Thrusters, optional
        Base force and torque limits (flying modes).
    record_every : int
        RK4: keep every k-th step (the final state is always kept).
    progress : bool or callable
        ``True`` for a tqdm progress bar, or a callable receiving the completed fraction.
        Ctrl-C interrupts a run.
    joint_limits : bool
        Whether the joints' effort and velocity limits apply (default ``True``; position
        limits are not enforced).
    max_steps : int
        DOPRI5 step budget.
    record_dtype : str
        ``"float64"`` (default) or ``"float32"``: the dtype of the recorded arrays (half the
        memory; the time ``t`` stays float64). The run itself is float64 either way.
    orbit : spacearm.Orbit, optional
        Run in orbit (docs/orbit.md): the origin of the run's frame follows ``orbit`` (point
        mass, two-body + J2) with ECI's axes; ``x``, ``u`` stay relative to it (start with the
        system CM at the origin and zero momentum for the CM to ride the orbit; an offset or a
        momentum puts the CM on a neighbouring orbit, its relative motion in ``com``). Adds the
        records ``r_cm_eci``, ``v_cm_eci``, ``gravity_wrench`` and ``meta["orbit"]``.
    gravity_gradient : bool, optional
        With ``orbit``: whether the tidal force and torque act on every body (default ``True``).
        The mode's conserved momenta are then monitored as balances (``meta["drift"]``: the
        residual of change = integral of the tidal wrenches).
    stop : StopAtTime, StopAtGap, StopAtRecord or a list of them, optional
        Conditions that end the run early ([`spacearm.sim.events`][spacearm.sim.events]): the
        core locates the first event within its step and stops there; the last sample is the
        event's, and ``meta["stop"]`` holds ``{"condition", "kind", "t", "value"}`` (``None``
        when the run reached ``duration``). A point controller's goal is judged only at a
        run's natural end (no "out of reach" warning after an event stop).
    contact : spacearm.contact.ContactModel, optional
        Compliant contact between the system's bodies (docs/contact.md, "Contact dynamics"):
        spring–dashpot normal forces and regularized Coulomb friction at every interpenetrating
        pair of collision shapes. Adds the records ``contact_count``, ``contact_normal_force``,
        ``contact_work`` and ``meta["contact"]``; the energy's drift is then that of the ledger
        ``energy − contact_work``. ``ContactModel(kind="rigid")``: rigid frictional contact
        solved every step on the Delassus operator (docs/contact.md, "Rigid contact in a run";
        RK4 only), which records ``contact_impulse`` too.
    events : spacearm.events.Attach, spacearm.events.Detach or a list of them, optional
        Topology events (docs/events.md): weld the free target to the robot, release a rigid
        link, in list order, each continuing the run in one trajectory with robot + target
        momentum continuous. With ``contact`` too, the flying target is in the loop of contact
        and a threshold ``Attach`` is the grasp on contact (docs/events.md, "Events with
        contact"). Adds the records ``target`` (K, 13), ``attached`` (K,), ``phase`` (K,: the
        events that have happened), ``ledger_momentum`` (K, 6), ``ledger_energy`` (K,), the
        ``event_*`` arrays (one row per event that happened) and ``meta["events"]``.
    target : spacearm.Target or spacearm.Robot, optional
        The second system, a rigid target (its grasp points, or the model's named points, are the
        points ``Attach(grasp=...)`` names). With ``contact``: a free target in the loop of
        contact (docs/contact.md, "Contact with a free target"), integrated with the robot, its
        collision shapes touching it; contact pairs name it ``"target"`` (or its geometries).
        Without ``events`` it needs ``contact``. Adds the records of ``events`` (none happen
        without them: ``meta["events"]`` is empty); the drifts of a run without events are
        robot + target's.
    target_state : array_like (13,), optional
        Its state ``[r, quat (x, y, z, w), v, ω]`` at t = 0 (CM, attitude, CM velocity and
        angular velocity in the inertial frame).

    Returns
    -------
    Trajectory
        The recorded run.

    Raises
    ------
    ArgumentError
        Bad options (an ``ArgumentError`` is a ``ValueError``).
    ShapeError, NonFiniteError, QuaternionError
        Bad initial states.
    NotFoundError
        Unknown wheels.
    SimulationError
        The motion diverges or the adaptive step collapses.

    Notes
    -----
    Saturation is never silent: a torque, speed or thruster limit hit is clamped physically
    (``tau`` against ``tau_cmd`` in the records) and its onset recorded as an event
    (``saturation_t``, ``saturation_actuator`` indexing ``meta["actuator_names"]``,
    ``saturation_kind`` 0 torque, 1 speed, 2 thruster).
    """
    _check_robot(robot, "simulate")
    duration = _check_duration(duration)
    option_args = dict(
        mode=mode, integrator=integrator, dt=dt, rtol=rtol, atol=atol, wheels=wheels, thrusters=thrusters,
        record_every=record_every, joint_limits=joint_limits, max_steps=max_steps, record_dtype=record_dtype,
        orbit=orbit, gravity_gradient=gravity_gradient, stop=stop, contact=contact,
    )
    options = _options(robot, **option_args)
    x0 = robot.neutral_configuration() if x0 is None else vector(x0, "x0")
    u0 = robot.zero_velocity() if u0 is None else vector(u0, "u0")
    _check_controller(controller)
    callback, close = _progress_callable(progress)
    spec = None if controller is None else controller_spec(controller)
    try:
        if callback is not None:
            # The options were checked first, before the progress callable (maybe a bar) was
            # made; they are built again with it.
            options = _options(robot, **option_args, progress=callback)
        # The core's one entry decides the loop (sim/run.rs): the robot alone, a free target in
        # the loop of contact, topology events, or both.
        model, state = _second_system(target, target_state)
        result = _core.simulate(robot.core_model, x0, u0, duration, options, spec, _events_data(events), model, state)
    finally:
        close()
    # The typed run result as the public plain form: the records and saturation onsets as one
    # dict of its arrays (no copy), the description as the meta dict (Trajectory's own form, as
    # Trajectory.load gives it back from a file; plain data, so a Trajectory pickles).
    data = {**result.records.to_dict(), **result.events.to_dict()}
    meta = result.meta.to_dict()
    meta["duration"] = duration
    meta["robot"] = robot.name
    if orbit is not None:
        meta["orbit"] = orbit_meta(options)
    if contact is not None:
        meta["contact"] = options.contact
    topology = result.topology
    if topology is not None:
        # a second system: its rows (K, ...) and ledger, and the events that happened
        topology = dict(topology)
        bodies = topology.pop("event_body")
        topology.pop("final_model")
        meta["events"] = [
            {"event": int(i), "kind": ("attach", "detach")[int(k)], "t": float(t), "body": b}
            for i, k, t, b in zip(topology["event_index"], topology["event_kind"], topology["event_t"], bodies)
        ]
        data.update(topology)
    _warn_dropped(meta, stacklevel=2)
    _warn_unreachable(meta, stacklevel=2)
    _warn_passive_commanded(robot, data, meta, stacklevel=2)
    from .trajectory import Trajectory

    return Trajectory._adopt(robot, data, meta)
