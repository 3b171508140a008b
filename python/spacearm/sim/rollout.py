"""Many simulations at once on native threads: [`rollout`][spacearm.rollout] and its result [`Rollouts`][spacearm.Rollouts].

Each rollout is the run [`spacearm.simulate`][spacearm.simulate] would make from its initial state, with its
own plant (the robot, or one perturbed model per rollout) and its own controller instance; the
rollouts run in parallel on the core's threads with the GIL released. A rollout's records are
bit-identical to ``simulate`` of the same inputs whatever the number of threads. A rollout that
fails (the motion diverges, a controller raises) is reported in [`Rollouts.ok`][spacearm.Rollouts.ok] and
[`Rollouts.reason`][spacearm.Rollouts.reason] and its rows are NaN; the others run on.

>>> import numpy as np, spacearm
>>> robot = spacearm.presets.spatial6()
>>> x0 = np.tile(robot.neutral_configuration(), (4, 1))
>>> u0 = np.zeros((4, robot.nu)); u0[:, 6:] = np.linspace(0.1, 0.4, 4)[:, None]
>>> runs = spacearm.rollout(robot, 0.5, x0, u0, dt=1e-3, record_every=50)
>>> runs["x"].shape, bool(runs.ok.all())
((4, 11, 13), True)
"""

from __future__ import annotations

from typing import List, Optional, Sequence

import numpy as np

from .._util.spec import controller_spec
from .. import _core
from .._util.arrays import real_array
from ..errors import ArgumentError, NotFoundError, ShapeError, SimulationError
from .simulation import DEFAULTS, _check_controller, _check_duration, _check_robot, _options, _warn_dropped

__all__ = ["rollout", "Rollouts"]


def _batch_size(x0, u0, plants, controller) -> int:
    """The number of rollouts: the leading axis of a 2-D ``x0`` or ``u0``, or the length of
    ``plants`` or of a list of controllers; every one given must agree."""
    sizes = {}
    for name, value in (("x0", x0), ("u0", u0)):
        if value is not None and value.ndim == 2:
            sizes[name] = value.shape[0]
    if plants is not None:
        sizes["plants"] = len(plants)
    if isinstance(controller, (list, tuple)):
        sizes["controller"] = len(controller)
    if not sizes:
        raise ShapeError("rollout needs a batch: x0 of shape (B, 7+N), u0 of shape (B, 6+N), B plants or B controllers")
    if len(set(sizes.values())) > 1:
        raise ShapeError(f"rollout: the batch sizes disagree: {', '.join(f'{k} {v}' for k, v in sizes.items())}")
    b = next(iter(sizes.values()))
    if b < 1:
        raise ShapeError("rollout needs at least one rollout (B >= 1)")
    return b


def _states(value, default, width: int, b: int, name: str) -> np.ndarray:
    """``value`` as a C-contiguous float64 ``(b, width)`` array: ``None`` → ``default`` on every
    row, one row → repeated, ``(b, width)`` → as given."""
    if value is None:
        value = default
    a = real_array(value, name)  # the one array check: complex, object and text arrays refused
    if a.ndim == 1:
        a = np.broadcast_to(a, (b, a.shape[0]))
    if a.ndim != 2 or a.shape[1] != width:
        raise ShapeError(f"{name} must have shape (B, {width}) or ({width},), got {a.shape}")
    return np.ascontiguousarray(a)


def rollout(
    robot,
    duration: float,
    x0=None,
    u0=None,
    *,
    controller=None,
    plants: Optional[Sequence] = None,
    mode: str = DEFAULTS["mode"],
    integrator: str = DEFAULTS["integrator"],
    dt: float = DEFAULTS["dt"],
    rtol: float = DEFAULTS["rtol"],
    atol: float = DEFAULTS["atol"],
    wheels=None,
    thrusters=None,
    joint_limits: bool = DEFAULTS["joint_limits"],
    max_steps: int = DEFAULTS["max_steps"],
    record_every: int = DEFAULTS["record_every"],
    record_dtype: str = "float64",
    threads: Optional[int] = None,
    orbit=None,
    gravity_gradient: Optional[bool] = None,
    stop=None,
) -> "Rollouts":
    """Simulate ``B`` rollouts of ``robot`` for ``duration`` seconds on native threads.

    Parameters
    ----------
    robot : Robot
        The nominal plant (and the plant of every rollout when ``plants`` is not given).
    duration : float
        Simulated time of each rollout, s.
    x0 : array (B, 7+N) or (7+N,), optional
        Initial configurations (one row is used for every rollout; default: the neutral one).
    u0 : array (B, 6+N) or (6+N,), optional
        Initial velocities (default: zero).
    controller : controller or list of B controllers, optional
        One [`spacearm.control`][spacearm.control] controller for every rollout (each rollout runs its own
        instance of it), or one per rollout (per-rollout gains or references). ``None``: zero
        torques. A [`Callback`][spacearm.control.Callback] works but runs its Python function under
        the GIL, so its rollouts do not run in parallel.
    plants : list of B Robots, optional
        One plant per rollout, e.g. models perturbed with
        [`spacearm.control.perturbed_model`][spacearm.control.perturbed_model]; they must have the robot's joints.
    mode, integrator, dt, rtol, atol, wheels, thrusters, joint_limits, max_steps, record_every, record_dtype, orbit, gravity_gradient
        As for [`spacearm.simulate`][spacearm.simulate], the same for every rollout. ``record_every`` (RK4)
        and ``record_dtype="float32"`` keep the records small: with ``record_every`` at least
        the number of steps only the initial and final samples are kept.
    threads : int, optional
        Number of threads (default: one per core).
    stop : threading.Event, optional
        Setting it stops the rollouts within 0.1 s (a ``SimulationError``): how a rollout running
        on another thread is stopped (Ctrl-C stops one on the main thread by itself).

    Returns
    -------
    Rollouts
        Records with a leading rollout axis, and each rollout's status.

    Raises
    ------
    ArgumentError, ShapeError, NonFiniteError, QuaternionError
        Bad options or initial states (an initial state's error names its rollout). A rollout
        that fails while running raises nothing: see [`Rollouts.ok`][spacearm.Rollouts.ok].
    """
    _check_robot(robot, "rollout")
    duration = _check_duration(duration)
    options = _options(
        robot, mode=mode, integrator=integrator, dt=dt, rtol=rtol, atol=atol, wheels=wheels, thrusters=thrusters,
        record_every=record_every, joint_limits=joint_limits, max_steps=max_steps, record_dtype=record_dtype,
        orbit=orbit, gravity_gradient=gravity_gradient,
    )
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or threads < 1):
        raise ArgumentError(f"threads must be None or an integer >= 1, got {threads!r}")
    x0_in = None if x0 is None else np.asarray(x0)
    u0_in = None if u0 is None else np.asarray(u0)
    if plants is not None and not isinstance(plants, (list, tuple)):
        raise ArgumentError(f"plants must be a list of spacearm.Robot (one per rollout), got {type(plants).__name__}")
    b = _batch_size(x0_in, u0_in, plants, controller)
    x0 = _states(x0, robot.neutral_configuration(), robot.nx, b, "x0")
    u0 = _states(u0, robot.zero_velocity(), robot.nu, b, "u0")
    models = [robot.core_model]
    if plants is not None:
        for i, p in enumerate(plants):
            _check_robot(p, f"rollout: plants[{i}]")
            if p.n_dof != robot.n_dof:
                raise ShapeError(f"plants[{i}] has N = {p.n_dof} joints but the robot has N = {robot.n_dof}")
        models = [p.core_model for p in plants]
    if isinstance(controller, (list, tuple)):
        for i, c in enumerate(controller):
            _check_controller(c, f"controller[{i}]")
        specs = [controller_spec(c) for c in controller]
    else:
        _check_controller(controller)
        specs = None if controller is None else controller_spec(controller)
    if stop is not None and not callable(getattr(stop, "is_set", None)):
        raise ArgumentError(f"stop must be None or an object with is_set() (a threading.Event), got {type(stop).__name__}")
    batch = _core.rollout(models, x0, u0, duration, options, specs, None if threads is None else int(threads), stop)
    meta = [None if m is None else m.to_dict() for m in batch.meta]
    for m in meta:
        if m is not None:
            m["duration"] = duration
            m["robot"] = robot.name
    first = next((m for m in meta if m is not None), None)
    if first is not None:
        _warn_dropped(first, stacklevel=2)
    return Rollouts(robot, plants, batch, meta)


class Rollouts:
    """The records of ``B`` rollouts (what [`rollout`][spacearm.rollout] returns).

    ``runs[name]`` (or ``runs.x``, ``runs.t``, ...) is the record ``name`` of
    [`spacearm.simulate`][spacearm.simulate] with a leading rollout axis: ``(B, K, ...)``, NaN rows for a
    rollout that failed. [`ok`][spacearm.Rollouts.ok] and [`reason`][spacearm.Rollouts.reason] say which failed and why;
    [`trajectory`][spacearm.Rollouts.trajectory] gives one rollout as a [`Trajectory`][spacearm.Trajectory]. The arrays are
    read-only.
    """

    def __init__(self, robot, plants, batch, meta: List[Optional[dict]]):
        self._robot = robot
        self._plants = plants
        self._ok = np.asarray(batch.ok, dtype=bool)
        self._reason = list(batch.reason)
        self._error_class = list(batch.error_class)
        self._events = [None if e is None else e.to_dict() for e in batch.events]
        self._meta = meta
        data = batch.records.to_dict()
        for a in data.values():
            a.setflags(write=False)
        self._ok.setflags(write=False)
        self._data = data

    def __setstate__(self, state: dict) -> None:
        """Unpickling: the fields a pickle carries are checked as a run makes them (one entry per
        rollout everywhere, the records' shapes), so a tampered pickle is an ``ArgumentError``."""
        def bad(msg):
            raise ArgumentError(f"not a valid Rollouts: {msg}")

        if not isinstance(state, dict) or not {"_robot", "_plants", "_ok", "_reason", "_error_class", "_events", "_meta", "_data"} <= set(state):
            bad("a pickle carries its robot, plants, ok, reason, error_class, events, meta and records")
        ok, data = state["_ok"], state["_data"]
        if not (isinstance(ok, np.ndarray) and ok.dtype == bool and ok.ndim == 1):
            bad("ok must be a 1-D bool array")
        b = ok.shape[0]
        for key in ("_reason", "_error_class", "_events", "_meta"):
            if not (isinstance(state[key], list) and len(state[key]) == b):
                bad(f"{key[1:]} must be a list of one entry per rollout ({b})")
        if state["_plants"] is not None and not (isinstance(state["_plants"], list) and len(state["_plants"]) == b):
            bad(f"plants must be None or one per rollout ({b})")
        if not (isinstance(data, dict) and {"t", "x", "u"} <= set(data) and all(isinstance(a, np.ndarray) for a in data.values())):
            bad("the records must be a dict of arrays with t, x and u")
        t, x, u = data["t"], data["x"], data["u"]
        if t.ndim != 2 or t.shape[0] != b or x.ndim != 3 or x.shape[:2] != t.shape or x.shape[2] < 7 or u.shape != t.shape + (x.shape[2] - 1,):
            bad(f"t, x and u must have shapes (B, K), (B, K, 7+N) and (B, K, 6+N) with B = {b}, got {t.shape}, {x.shape}, {u.shape}")
        if any(a.shape[:1] != (b,) for a in data.values()):
            bad(f"every record must have one row per rollout ({b})")
        for a in (*data.values(), ok):
            a.setflags(write=False)
        self.__dict__.update(state)

    def __len__(self) -> int:
        return len(self._ok)

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self._data[name]
        except KeyError:
            raise NotFoundError(f"the rollouts have no '{name}' record; they have {', '.join(sorted(self._data))}") from None

    def __getattr__(self, name: str) -> np.ndarray:
        if name.startswith("_"):
            raise AttributeError(name)
        try:
            return self._data[name]
        except KeyError:
            raise AttributeError(f"'Rollouts' has no attribute or record '{name}'") from None

    @property
    def keys(self) -> List[str]:
        """Names of the records."""
        return sorted(self._data)

    @property
    def ok(self) -> np.ndarray:
        """``(B,)`` booleans: whether each rollout ran to the end."""
        return self._ok

    @property
    def reason(self) -> List[Optional[str]]:
        """Why each rollout failed (the error message), ``None`` for those that did not."""
        return list(self._reason)

    @property
    def error_class(self) -> List[Optional[str]]:
        """The [`spacearm.errors`][spacearm.errors] class of each failure (``"SimulationError"``, ...), or ``None``."""
        return list(self._error_class)

    @property
    def meta(self) -> List[Optional[dict]]:
        """Each rollout's description (as ``Trajectory.meta``), ``None`` for a failed one."""
        return [None if m is None else dict(m) for m in self._meta]

    @property
    def saturation_count(self) -> np.ndarray:
        """``(B,)`` number of saturation onsets of each rollout (-1 for a failed one)."""
        return np.array([-1 if e is None else len(e["saturation_t"]) for e in self._events], dtype=np.int64)

    def final_state(self) -> np.ndarray:
        """``(B, 13+2N)`` ``[x; u]`` of each rollout at the end (NaN for a failed one)."""
        return np.concatenate([self._data["x"][:, -1, :], self._data["u"][:, -1, :]], axis=1)

    def raise_failures(self) -> None:
        """Raise [`SimulationError`][spacearm.SimulationError] listing the failed rollouts, if any."""
        failed = np.flatnonzero(~self._ok)
        if failed.size:
            lines = [f"rollout {i}: {self._reason[i]}" for i in failed[:10]]
            more = f" (and {failed.size - 10} more)" if failed.size > 10 else ""
            raise SimulationError(f"{failed.size} of {len(self)} rollouts failed{more}:\n" + "\n".join(lines))

    def trajectory(self, i: int):
        """Rollout ``i`` as a [`Trajectory`][spacearm.Trajectory] (its plant as the robot); raises
        [`SimulationError`][spacearm.SimulationError] with its reason if it failed."""
        from .trajectory import Trajectory

        if isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not -len(self) <= i < len(self):
            raise ArgumentError(f"rollout index must be an integer in [0, {len(self)}), got {i!r}")
        i = int(i) % len(self)
        if not self._ok[i]:
            raise SimulationError(f"rollout {i} failed: {self._reason[i]}")
        data = {k: v[i] for k, v in self._data.items()}
        data.update(self._events[i])
        robot = self._robot if self._plants is None else self._plants[i]
        return Trajectory._adopt(robot, data, self._meta[i])

    def __repr__(self) -> str:
        k = self._data["t"].shape[1]
        return f"<Rollouts: {len(self)} rollouts of {k} samples, {int(self._ok.sum())} ok>"
