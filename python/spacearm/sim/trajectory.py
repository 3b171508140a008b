"""Simulation results: the [`Trajectory`][spacearm.Trajectory] that [`spacearm.simulate`][spacearm.simulate] returns.

A trajectory holds the recorded samples of one run (times, states, accelerations, applied and
commanded torques, base wrench, momenta, kinetic energy, system CM, end-effector pose,
reference and tracking error, reaction-wheel speeds, actuator saturation events) and the run's
description (``meta``: mode, integrator, step, controller, conserved quantities, step counts).

Conventions (``docs/conventions.md``): ``x = [r0, quat0 (x, y, z, w), q]``, ``u = [v0, w0, qd]`` with
``v0`` the base CM velocity and ``w0`` the base angular velocity, both in the inertial frame 𝒥;
``base_wrench = [F0, N0]`` in 𝒥; momenta ``P``, ``L_origin`` (about the origin of 𝒥) and
``L_com`` (about the system CM) in 𝒥. SI units throughout.

Output: [`Trajectory.save`][spacearm.Trajectory.save] / [`Trajectory.load`][spacearm.Trajectory.load] (``.npz``, the model embedded as
TOML so a loaded run can be plotted and animated), [`Trajectory.to_csv`][spacearm.Trajectory.to_csv] (one row per
sample, a header naming every column with its unit), [`Trajectory.plot`][spacearm.Trajectory.plot] (a multi-panel
PNG), [`Trajectory.animate`][spacearm.Trajectory.animate] (a 3-D GIF),
[`Trajectory.video`][spacearm.Trajectory.video] (an H.264 mp4) and
[`Trajectory.view`][spacearm.Trajectory.view] (the 3-D browser viewer, a self-contained HTML file or
a live view). Every file is written atomically.
"""

from __future__ import annotations

import json
import math
import os
from typing import Dict, Iterable, List, NamedTuple, Optional, Union

import numpy as np

from .._util.summary import controller_label
from .. import _core
from .._util.atomic import atomic_open
from .._util.npz import open_npz
from ..errors import ArgumentError, NotFoundError, ShapeError, SpacearmTypeError
from ..rotations import quat_multiply, quat_to_matrix

__all__ = ["Trajectory", "SaturationEvent", "SATURATION_KINDS", "euler_from_matrices"]

PathLike = Union[str, "os.PathLike[str]"]

#: ``saturation_kind`` codes of the simulation dict (docs/simulation.md).
SATURATION_KINDS = {0: "torque limit", 1: "speed limit", 2: "force limit"}

#: Format tag stored in saved files, checked by [`Trajectory.load`][spacearm.Trajectory.load].
FILE_FORMAT = "spacearm.Trajectory/1"

# Per-sample arrays: name -> (trailing shape as a function of N, W, n_ref; required?)
_REQUIRED = ("t", "x", "u")
_PER_SAMPLE = (
    "t", "x", "u", "du", "tau", "tau_cmd", "base_wrench", "P", "L_origin", "L_com", "energy", "com",
    "ee_position", "ee_quat", "reference", "tracking_error", "link_tracking_error", "wheel_speed", "cmg_measure", "cmg_envelope_fraction",
    "r_cm_eci", "v_cm_eci", "gravity_wrench", "contact_count", "contact_normal_force", "contact_work",
    "contact_impulse",
)
_EVENTS = ("saturation_t", "saturation_actuator", "saturation_kind")
# Dtypes of a run's records adopted without conversion (a run may record float32).
_FLOAT_DTYPES = (np.dtype(np.float64), np.dtype(np.float32))


class SaturationEvent(NamedTuple):
    """One step at which an actuator hit its limit."""

    t: float  #: time, s
    actuator: str  #: actuator name (a joint name, ``"thruster_force"``, …)
    kind: str  #: ``"torque limit"``, ``"speed limit"`` or ``"force limit"``


# ---------------------------------------------------------------------------------------------
# rotations of many samples at once
# ---------------------------------------------------------------------------------------------
def euler_from_matrices(r) -> np.ndarray:
    """Roll, pitch, yaw ``(K, 3)`` (rad) of rotation matrices, in the URDF convention
    ``R = Rz(yaw) Ry(pitch) Rx(roll)``; roll and yaw are unwrapped along the samples so a
    steady rotation gives a continuous curve."""
    r = np.asarray(r, dtype=float)
    roll = np.arctan2(r[..., 2, 1], r[..., 2, 2])
    pitch = -np.arcsin(np.clip(r[..., 2, 0], -1.0, 1.0))
    yaw = np.arctan2(r[..., 1, 0], r[..., 0, 0])
    out = np.stack([roll, pitch, yaw], axis=-1)
    if out.ndim == 2 and out.shape[0] > 1:
        out[:, 0] = np.unwrap(out[:, 0])
        out[:, 2] = np.unwrap(out[:, 2])
    return out


def _jsonable(value):
    """``meta`` values as plain JSON types (numpy scalars and arrays become numbers and lists)."""
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return str(value)


# The types of the meta keys this module and the viewer read, checked when a file is loaded.
_META_TYPES = {
    "mode": (str, type(None)), "controller": (str, type(None)), "tracking_error_kind": (str, type(None)),
    "robot": (str, type(None)), "conserved": list, "actuator_names": list, "wheel_dofs": list,
    "drift": dict, "drift_scales": dict,
}


def _read_meta(path, raw) -> dict:
    """The ``__meta__`` of a trajectory file: a JSON object whose known keys have their types
    (``_META_TYPES``; ``wheel_dofs`` integers, ``conserved`` and ``actuator_names`` strings),
    else an [`ArgumentError`][spacearm.ArgumentError] naming the file (not a JSON traceback)."""
    if raw is None:
        return {}
    try:
        meta = json.loads(str(raw))
    except (ValueError, RecursionError) as exc:
        raise ArgumentError(f"{path}: the trajectory's __meta__ is not valid JSON ({type(exc).__name__}: "
                            f"{str(exc)[:120]}): a damaged or edited file") from None
    if not isinstance(meta, dict):
        raise ArgumentError(f"{path}: the trajectory's __meta__ must be a JSON object, got a {type(meta).__name__}")
    for key, types in _META_TYPES.items():
        if key in meta and not isinstance(meta[key], types):
            raise ArgumentError(f"{path}: the trajectory's __meta__['{key}'] has the wrong type "
                                f"({type(meta[key]).__name__}): a damaged or edited file")
    items = {"conserved": str, "actuator_names": str, "wheel_dofs": int}
    for key, kind in items.items():
        bad = [v for v in meta.get(key) or [] if not isinstance(v, kind) or isinstance(v, bool)]
        if bad:
            raise ArgumentError(f"{path}: the trajectory's __meta__['{key}'] must hold {kind.__name__} values, got "
                                f"{type(bad[0]).__name__}: a damaged or edited file")
    return meta


# ---------------------------------------------------------------------------------------------
# the trajectory
# ---------------------------------------------------------------------------------------------
class Trajectory:
    """The recorded samples of one simulation run.

    Built by [`spacearm.simulate`][spacearm.simulate] (or [`load`][spacearm.Trajectory.load]); ``data`` maps the names of
    ``docs/simulation.md`` (``t``, ``x``, ``u``, ``du``, ``tau``, …) to numpy arrays with one
    row per sample, ``meta`` describes the run. ``robot`` (the simulated
    [`Robot`][spacearm.Robot]) is needed by [`animate`][spacearm.Trajectory.animate], the CSV column names and the
    momentum scales of [`drift`][spacearm.Trajectory.drift]; a trajectory without it still gives every recorded array.

    The arrays are read-only views: copy them (``np.array(traj.q)``) to modify.
    """

    def __init__(self, robot=None, data: Optional[dict] = None, meta: Optional[dict] = None):
        self._init(robot, data, meta, copy=True)

    def __reduce__(self):
        # Unpickled through the constructor: a tampered pickle's arrays pass the same shape
        # checks as a caller's (docs/batch.md, "Pickling").
        return (Trajectory, (self._robot, dict(self._data), self._meta))

    @classmethod
    def _adopt(cls, robot, data: dict, meta: dict) -> "Trajectory":
        """A trajectory that takes the arrays of a run as they are (read-only views, no copy):
        for the simulation entry points, whose arrays nobody else holds."""
        traj = cls.__new__(cls)
        traj._init(robot, data, meta, copy=False)
        return traj

    def _init(self, robot, data, meta, copy: bool) -> None:
        if data is None:
            raise SpacearmTypeError("Trajectory needs data: a dict of per-sample arrays with at least t, x and u")
        if not isinstance(data, dict):
            raise SpacearmTypeError(f"Trajectory data must be a dict of arrays, got {type(data).__name__}")
        missing = [k for k in _REQUIRED if k not in data]
        if missing:
            raise ShapeError(f"Trajectory data lacks {', '.join(missing)} (needs at least t, x and u)")
        arrays = {}
        for key, value in data.items():
            integer = key in ("saturation_actuator", "saturation_kind")
            if not copy and isinstance(value, np.ndarray) and value.dtype in ((np.dtype(np.int64),) if integer else _FLOAT_DTYPES):
                # A view: its own read-only flag, the run's memory (float32 records stay float32).
                a = value.view()
            else:
                try:
                    a = np.array(value, dtype=np.int64 if integer else float)
                except (TypeError, ValueError) as exc:
                    raise ShapeError(f"Trajectory data '{key}' must be a numeric array") from exc
            a.setflags(write=False)
            arrays[str(key)] = a
        t, x, u = arrays["t"], arrays["x"], arrays["u"]
        if t.ndim != 1:
            raise ShapeError(f"Trajectory data 't' must be 1-D (K samples), got shape {t.shape}")
        k = t.shape[0]
        if x.ndim != 2 or x.shape[0] != k or x.shape[1] < 7:
            raise ShapeError(f"Trajectory data 'x' must have shape (K, 7+N) with K = {k}, got {x.shape}")
        n = x.shape[1] - 7
        if u.shape != (k, 6 + n):
            raise ShapeError(f"Trajectory data 'u' must have shape (K, 6+N) = {(k, 6 + n)}, got {u.shape}")
        if robot is not None and robot.n_dof != n:
            raise ShapeError(f"Trajectory data has N = {n} joints but the robot '{robot.name}' has N = {robot.n_dof}")
        for key in _PER_SAMPLE:
            if key in arrays and arrays[key].shape[:1] != (k,):
                raise ShapeError(f"Trajectory data '{key}' must have one row per sample (K = {k}), got shape {arrays[key].shape}")
        lengths = {arrays[e].shape for e in _EVENTS if e in arrays}
        if len(lengths) > 1 or any(len(s) != 1 for s in lengths):
            raise ShapeError("Trajectory data saturation_t, saturation_actuator and saturation_kind must be 1-D of one length")
        self._robot = robot
        self._data = arrays
        self._meta = dict(meta or {})
        self._n = n

    # ---- raw access ------------------------------------------------------------------------
    @property
    def robot(self):
        """The simulated [`Robot`][spacearm.Robot] (``None`` if unknown)."""
        return self._robot

    @property
    def meta(self) -> dict:
        """The run's description (a copy): mode, integrator, dt, controller, conserved, …"""
        return json.loads(json.dumps(_jsonable(self._meta)))

    @property
    def keys(self) -> List[str]:
        """Names of the recorded arrays."""
        return sorted(self._data)

    def has(self, key: str) -> bool:
        """Whether the array ``key`` was recorded (e.g. ``"ee_position"``, ``"wheel_speed"``)."""
        return key in self._data

    def __getitem__(self, key: str) -> np.ndarray:
        try:
            return self._data[key]
        except KeyError:
            raise NotFoundError(f"this trajectory has no '{key}' data; it has {', '.join(self.keys)}") from None

    def _get(self, key: str, why: str) -> np.ndarray:
        if key not in self._data:
            raise NotFoundError(f"this trajectory has no '{key}' data ({why})")
        return self._data[key]

    def __len__(self) -> int:
        return self._data["t"].shape[0]

    def __repr__(self) -> str:
        name = self._robot.name if self._robot is not None else "?"
        return (f"<Trajectory '{name}' {self._meta.get('mode', '?')}: {len(self)} samples, "
                f"t = {self.t[0]:.6g}..{self.t[-1]:.6g} s, N = {self._n}>")

    # ---- samples -----------------------------------------------------------------------------
    @property
    def n_dof(self) -> int:
        return self._n

    @property
    def n_samples(self) -> int:
        return len(self)

    @property
    def duration(self) -> float:
        """Time span of the recorded samples, s."""
        return float(self.t[-1] - self.t[0])

    @property
    def t(self) -> np.ndarray:
        """Sample times ``(K,)``, s."""
        return self._data["t"]

    @property
    def x(self) -> np.ndarray:
        """Configurations ``(K, 7+N)``: ``[r0, quat0, q]``."""
        return self._data["x"]

    @property
    def u(self) -> np.ndarray:
        """Generalized velocities ``(K, 6+N)``: ``[v0, w0, qd]``."""
        return self._data["u"]

    @property
    def du(self) -> np.ndarray:
        """Generalized accelerations ``(K, 6+N)``: ``[dv0, dw0, qdd]``."""
        return self._get("du", "accelerations were not recorded")

    def state(self, k: int):
        """``(x, u)`` of sample ``k`` (negative counts from the end)."""
        return np.array(self.x[k]), np.array(self.u[k])

    @property
    def q(self) -> np.ndarray:
        """Joint coordinates ``(K, N)`` (rad, or m for prismatic joints)."""
        return self.x[:, 7:]

    @property
    def qd(self) -> np.ndarray:
        """Joint velocities ``(K, N)``."""
        return self.u[:, 6:]

    @property
    def qdd(self) -> np.ndarray:
        """Joint accelerations ``(K, N)``."""
        return self.du[:, 6:]

    @property
    def base_position(self) -> np.ndarray:
        """Base CM position ``r0`` ``(K, 3)`` in 𝒥, m."""
        return self.x[:, :3]

    @property
    def base_quat(self) -> np.ndarray:
        """Base attitude ``(K, 4)``, unit quaternions ``[x, y, z, w]`` (base frame to 𝒥)."""
        return self.x[:, 3:7]

    @property
    def base_rotation(self) -> np.ndarray:
        """Base attitude ``R0`` ``(K, 3, 3)`` (base-frame vectors to 𝒥)."""
        q = self.base_quat
        return quat_to_matrix(q / np.linalg.norm(q, axis=1, keepdims=True))  # records: unit to their precision

    @property
    def base_euler(self) -> np.ndarray:
        """Base roll, pitch, yaw ``(K, 3)``, rad (``R0 = Rz(yaw) Ry(pitch) Rx(roll)``, unwrapped)."""
        return euler_from_matrices(self.base_rotation)

    @property
    def base_rotation_angle(self) -> np.ndarray:
        r"""Angle ``(K,)`` (rad, in $[0, \pi]$) of the base rotation since the first sample,
        $R_0(t)\, R_0(t_0)^T$: how far the base has turned, whatever the axis. Computed from the
        relative quaternion as $2 \operatorname{atan2}(\lVert \text{vector part} \rVert, \lvert \text{scalar part} \rvert)$, accurate for small
        angles too."""
        q = self.base_quat / np.linalg.norm(self.base_quat, axis=1, keepdims=True)
        q0 = q[0] * np.array([-1.0, -1.0, -1.0, 1.0])  # conjugate of the first attitude
        rel = quat_multiply(q, q0)  # q ⊗ q0*
        return 2.0 * np.arctan2(np.linalg.norm(rel[:, :3], axis=1), np.abs(rel[:, 3]))

    @property
    def base_velocity(self) -> np.ndarray:
        """Base CM velocity ``v0`` ``(K, 3)`` in 𝒥, m/s."""
        return self.u[:, :3]

    @property
    def base_angular_velocity(self) -> np.ndarray:
        """Base angular velocity ``w0`` ``(K, 3)`` in 𝒥, rad/s."""
        return self.u[:, 3:6]

    @property
    def base_angular_velocity_in_base(self) -> np.ndarray:
        r"""Base angular velocity in the base frame $R_0^T \omega_0$ ``(K, 3)``, rad/s."""
        return np.einsum("kji,kj->ki", self.base_rotation, self.base_angular_velocity)

    # ---- forces --------------------------------------------------------------------------
    @property
    def tau(self) -> np.ndarray:
        """Joint forces actually applied (after saturation) ``(K, N)``, N·m or N."""
        return self._get("tau", "joint forces were not recorded")

    @property
    def tau_cmd(self) -> np.ndarray:
        """Joint forces commanded by the controller ``(K, N)``, before saturation."""
        return self._get("tau_cmd", "commanded joint forces were not recorded")

    @property
    def base_wrench(self) -> np.ndarray:
        """Base wrench ``[F0, N0]`` actually applied ``(K, 6)`` in 𝒥 (zero in floating modes)."""
        return self._get("base_wrench", "the base wrench was not recorded")

    # ---- momenta, energy, CM ---------------------------------------------------------------
    @property
    def P(self) -> np.ndarray:
        """Linear momentum ``(K, 3)``, N·s."""
        return self._get("P", "momentum was not recorded")

    @property
    def L_origin(self) -> np.ndarray:
        """Angular momentum about the origin of 𝒥 ``(K, 3)``, N·m·s."""
        return self._get("L_origin", "momentum was not recorded")

    @property
    def L_com(self) -> np.ndarray:
        """Angular momentum about the system CM ``(K, 3)``, N·m·s."""
        return self._get("L_com", "momentum was not recorded")

    @property
    def energy(self) -> np.ndarray:
        """Kinetic energy ``(K,)``, J."""
        return self._get("energy", "energy was not recorded")

    @property
    def com(self) -> np.ndarray:
        """System CM ``r_g`` ``(K, 3)`` in 𝒥, m."""
        return self._get("com", "the system CM was not recorded")

    # ---- end effector, tracking, wheels ----------------------------------------------------
    @property
    def ee_position(self) -> np.ndarray:
        """End-effector position ``(K, 3)`` in 𝒥, m."""
        return self._get("ee_position", "the robot has no end effector")

    @property
    def ee_quat(self) -> np.ndarray:
        """End-effector attitude ``(K, 4)`` ``[x, y, z, w]`` (the frame of its link)."""
        return self._get("ee_quat", "the robot has no end effector")

    @property
    def reference(self) -> np.ndarray:
        """The controller's reference ``(K, n_ref)``: joint angles or a Cartesian point."""
        return self._get("reference", "the controller tracks no reference")

    @property
    def tracking_error(self) -> np.ndarray:
        """Tracking error ``(K,)``: ``|q_ref − q|`` (rad) or ``|p_ref − p|`` (m), see
        [`tracking_error_kind`][spacearm.Trajectory.tracking_error_kind]."""
        return self._get("tracking_error", "the controller tracks no reference")

    @property
    def link_tracking_error(self) -> np.ndarray:
        """With compliant joints (docs/flexibility.md) under a joint-space controller: the links'
        tracking error ``(K,)``, ``|q_ref − (θ + δ)|`` (rad), each compliant joint's deflection
        ``δ`` added to its motor angle ``θ``; [`tracking_error`][spacearm.Trajectory.tracking_error]
        is the motors' ``|q_ref − θ|``. Recorded by the core only then."""
        return self._get("link_tracking_error", "no compliant joint is tracked by a joint-space controller")

    @property
    def tracking_error_kind(self) -> Optional[str]:
        """``"joint"`` (rad), ``"cartesian"`` (m) or ``None``."""
        return self._meta.get("tracking_error_kind")

    @property
    def wheel_speed(self) -> np.ndarray:
        """Reaction-wheel speeds ``(K, W)``, rad/s (relative to the base)."""
        return self._get("wheel_speed", "the run had no reaction wheels")

    @property
    def cmg_measure(self) -> np.ndarray:
        """``(K,)`` the CMG cluster's singularity measure ``m = det(A Aᵀ)/h̄⁶`` per sample (0 at a
        singular state; docs/cmg.md); recorded when every CMG of the robot is on its base."""
        return self._get("cmg_measure", "the robot has no control-moment gyros on its base")

    @property
    def cmg_envelope_fraction(self) -> np.ndarray:
        """``(K,)`` the fraction of the CMG cluster's momentum envelope used, ``|H|/σ(Ĥ)`` (1 at
        saturation; docs/cmg.md)."""
        return self._get("cmg_envelope_fraction", "the robot has no control-moment gyros on its base")

    @property
    def r_cm_eci(self) -> np.ndarray:
        """An orbital run's system CM in ECI ``(K, 3)``, m: the orbit's point plus [`com`][spacearm.Trajectory.com]
        (docs/orbit.md)."""
        return self._get("r_cm_eci", "the run was not in orbit (simulate(..., orbit=spacearm.Orbit...))")

    @property
    def v_cm_eci(self) -> np.ndarray:
        """An orbital run's system CM velocity in ECI ``(K, 3)``, m/s."""
        return self._get("v_cm_eci", "the run was not in orbit (simulate(..., orbit=spacearm.Orbit...))")

    @property
    def gravity_wrench(self) -> np.ndarray:
        """An orbital run's total tidal wrench ``(K, 6)``: force (N) and torque about the origin
        of the run's frame (N·m), zeros with ``gravity_gradient=False``."""
        return self._get("gravity_wrench", "the run was not in orbit (simulate(..., orbit=spacearm.Orbit...))")

    @property
    def contact_count(self) -> np.ndarray:
        """With contact: the number of contacts touching or interpenetrating ``(K,)`` (docs/contact.md);
        rigid contact: the points that took a normal impulse in the step before the sample."""
        return self._get("contact_count", "the run had no contact (simulate(..., contact=spacearm.contact.ContactModel(...)))")

    @property
    def contact_normal_force(self) -> np.ndarray:
        """With contact: the sum of the contacts' normal forces ``(K,)``, N; rigid contact: the
        last step's normal impulses over its length, ``Σ λ_n / dt``."""
        return self._get("contact_normal_force", "the run had no contact (simulate(..., contact=spacearm.contact.ContactModel(...)))")

    @property
    def contact_work(self) -> np.ndarray:
        """With contact: the work of the contact forces on the system since ``t = 0`` ``(K,)``, J
        (their power integrated with the motion): ``energy − contact_work`` is conserved
        where the energy is."""
        return self._get("contact_work", "the run had no contact (simulate(..., contact=spacearm.contact.ContactModel(...)))")

    @property
    def contact_forces(self) -> np.ndarray:
        """With contact: one row per contact that exerts a force at a sample ``(R, 13)``,
        ``[k, body_a, body_b, point (3), normal (3), f_n, force (3)]``: the sample's index, the
        two bodies (a free target is body ``nb``, one past the robot's), the point where the
        forces act and the unit normal from ``body_a`` towards ``body_b`` in 𝒥 (m), the normal
        force (N) and the total force on ``body_b`` (normal plus friction, N, in 𝒥; ``body_a``
        feels its opposite). The rows of sample ``k``: [`contacts_at`][spacearm.Trajectory.contacts_at]."""
        return self._get("contact_forces", "the run had no contact (simulate(..., contact=spacearm.contact.ContactModel(...)))")

    def contacts_at(self, k: int) -> np.ndarray:
        """The rows of [`contact_forces`][spacearm.Trajectory.contact_forces] of sample ``k``
        ``(contact_count[k], 13)`` (negative ``k`` counts from the end)."""
        rows = self.contact_forces
        n = len(self)
        if not -n <= int(k) < n:
            raise ArgumentError(f"contacts_at: sample {k} is out of range for a trajectory of {n} samples")
        k = int(k) % n
        return rows[rows[:, 0] == k]

    @property
    def contact_impulse(self) -> np.ndarray:
        """With rigid contact: the sum since ``t = 0`` of the impulses received by the second
        body of each contact point ``(K, 3)``, in 𝒥, N·s (the first body received the opposite;
        docs/contact.md, "Rigid contact in a run")."""
        return self._get("contact_impulse", "the run had no rigid contact (simulate(..., contact=spacearm.contact.ContactModel(kind=\"rigid\")))")

    def attitude_lvlh(self) -> np.ndarray:
        """The base attitude relative to the LVLH frame of the system CM's orbit, ``(K, 3, 3)``
        rotation matrices base → LVLH (LVLH: x radial, y along-track, z orbit normal;
        docs/orbit.md). Orbital runs only."""
        from ..orbit import attitude_lvlh

        return attitude_lvlh(self.r_cm_eci, self.v_cm_eci, self.x[:, 3:7])

    def plot_lvlh(self, path: Optional[PathLike] = None):
        """The base attitude relative to LVLH against time in orbits (orbital runs;
        docs/orbit.md), written to ``path`` if given (extra ``plot``)."""
        from ..viz.orbit import plot_lvlh_attitude

        self.r_cm_eci  # an orbital run, or a clear error
        return plot_lvlh_attitude(self, path)

    @property
    def saturation_events(self) -> List[SaturationEvent]:
        """Every step at which an actuator hit its limit, in time order."""
        if "saturation_t" not in self._data:
            return []
        names = self._meta.get("actuator_names") or []
        out = []
        for t, a, kind in zip(self._data["saturation_t"], self._data["saturation_actuator"], self._data["saturation_kind"]):
            a = int(a)
            name = names[a] if 0 <= a < len(names) else f"actuator {a}"
            out.append(SaturationEvent(float(t), name, SATURATION_KINDS.get(int(kind), f"kind {int(kind)}")))
        return out

    def saturation_counts(self) -> Dict[str, int]:
        """Number of saturated steps per ``"actuator (kind)"``."""
        counts: Dict[str, int] = {}
        for e in self.saturation_events:
            key = f"{e.actuator} ({e.kind})"
            counts[key] = counts.get(key, 0) + 1
        return counts

    # ---- metadata shortcuts ------------------------------------------------------------------
    @property
    def mode(self) -> Optional[str]:
        return self._meta.get("mode")

    @property
    def conserved(self) -> List[str]:
        """Names of the quantities the run conserves (among ``P``, ``L_origin``, ``L_com``,
        ``energy``): those of its mode, none in an orbital run with the gravity gradient, whose
        tidal wrenches change the momenta (see [`balanced`][spacearm.Trajectory.balanced])."""
        return list(self._meta.get("conserved") or [])

    @property
    def balanced(self) -> List[str]:
        """In an orbital run with the gravity gradient, the momenta whose balance the simulator
        checked: their change equals the time integral of the recorded tidal wrench, and
        ``meta["drift"]`` holds the largest relative residual of that balance (docs/orbit.md);
        empty otherwise."""
        return list(self._meta.get("balanced") or [])

    # ---- names and units ----------------------------------------------------------------------
    def joint_names(self) -> List[str]:
        """Name of each degree of freedom (``q1``… without a robot)."""
        if self._robot is None:
            return [f"q{i + 1}" for i in range(self._n)]
        return self._robot.joint_names

    def _joint_is_prismatic(self) -> List[bool]:
        if self._robot is None:
            return [False] * self._n
        flags = [False] * self._n
        for link in self._robot.description.links:
            if link.type == "prismatic":
                flags[link.dof] = True
        return flags

    # ---- conservation ----------------------------------------------------------------------
    def drift_scale(self, name: str) -> float:
        """The magnitude against which [`drift`][spacearm.Trajectory.drift] measures deviations of ``name``, when the
        initial value is smaller (e.g. zero momentum): the core's drift scale
        ([`Robot.momentum_scales`][spacearm.Robot.momentum_scales], the sums over the bodies of their own contributions'
        norms), its largest value over the recorded states — what the simulator records as
        ``meta["drift_scales"]``. ``energy`` → the largest mechanical energy (kinetic plus the joint springs'). Without a robot the
        momentum scales are 0.
        """
        columns = {"P": 0, "L_origin": 1, "L_com": 2, "energy": 3}
        if name not in columns:
            raise NotFoundError(f"no drift scale for '{name}'; expected one of P, L_origin, L_com, energy")
        if name == "energy" and (self._robot is None or not (self.has("x") and self.has("u"))):
            return float(np.max(np.abs(self.energy))) if self.has("energy") else 0.0
        if self._robot is None or not (self.has("x") and self.has("u")):
            return 0.0
        return float(np.max(self._robot.momentum_scales(self.x, self.u)[:, columns[name]]))

    def drift(self, names: Optional[Iterable[str]] = None, scale: Optional[Dict[str, float]] = None) -> Dict[str, float]:
        r"""Largest relative deviation of each quantity from its value at the first sample.

        $\text{drift}[\text{name}] = \max_k \lVert v_k - v_0 \rVert / \max(\lVert v_0 \rVert, \text{scale})$ over the recorded samples (the
        simulator's definition, ``docs/simulation-core.md``). ``scale`` is, unless given
        (``scale={"P": 1.0}``): the simulator's own scale for the quantities its mode conserves
        (``meta["drift_scales"]``: the running maximum of the bodies' individual
        contributions, which only the simulator sees), so that for a simulated run this equals
        ``meta["drift"]``; otherwise [`drift_scale`][spacearm.Trajectory.drift_scale]. ``names`` defaults to the quantities
        the run's mode conserves ([`conserved`][spacearm.Trajectory.conserved]); for those the result is the integration
        error, for the others the physical change.
        """
        names = self.conserved if names is None else list(names)
        scale = dict(scale or {})
        recorded_scales = self._meta.get("drift_scales") or {}
        out = {}
        for name in names:
            v = np.asarray(self[name], dtype=float)
            v = v.reshape(v.shape[0], -1)
            if name in scale:
                s = float(scale[name])
            elif name in recorded_scales:
                s = float(recorded_scales[name])
            else:
                s = self.drift_scale(name)
            out[name] = _core.conserved_drift(np.ascontiguousarray(v), s)
        return out

    # ---- text ------------------------------------------------------------------------------
    def summary(self) -> str:
        """A few lines for a human: the run, conservation, tracking, saturation, final state."""
        m = self._meta
        name = self._robot.name if self._robot is not None else "?"
        lines = [f"simulation of '{name}' (N = {self._n}): mode {m.get('mode', '?')}, "
                 f"controller: {controller_label(m.get('controller'))}, integrator {m.get('integrator', '?')}"]
        step = f"dt = {m['dt']:g} s" if "dt" in m else ""
        if m.get("integrator") == "dopri5":
            step = f"rtol = {m.get('rtol', float('nan')):g}, atol = {m.get('atol', float('nan')):g}, output every {m.get('dt', float('nan')):g} s"
        counts = ", ".join(f"{v} {k.replace('n_', '').replace('_', ' ')}" for k, v in
                           ((k, m[k]) for k in ("n_steps", "n_rejected", "n_rhs_evals") if k in m))
        lines.append("; ".join(p for p in (f"  t = {self.t[0]:g} .. {self.t[-1]:g} s, {len(self)} samples", step, counts) if p))
        conserved = [c for c in self.conserved if self.has(c)]
        balanced = [c for c in self.balanced if isinstance(m.get("drift"), dict) and c in m["drift"]]
        if balanced:
            d = m["drift"]
            lines.append("  momentum balance in orbit (max relative residual of change = integral of the tidal wrench; "
                         "not conserved): " + ", ".join(f"{k} {d[k]:.3g}" for k in balanced))
        elif conserved:
            # The simulator's figures when it gave them (its scale: the bodies' summed
            # contributions), else this class's recomputation from the samples.
            d = m.get("drift") if isinstance(m.get("drift"), dict) and set(conserved) <= set(m["drift"]) else self.drift(conserved)
            lines.append("  conservation (max relative drift): " + ", ".join(f"{k} {d[k]:.3g}" for k in conserved))
        elif m.get("mode"):
            lines.append(f"  conservation: mode {m['mode']} conserves none of P, L, energy")
        if m.get("orbit"):
            o = m["orbit"]
            lines.append(f"  in orbit: a = {o['elements']['a'] / 1e3:.1f} km, i = {math.degrees(o['elements']['i']):.2f} deg, "
                         f"period {o['period']:.0f} s, J2 {'on' if o['j2'] else 'off'}, gravity gradient "
                         f"{'on' if o['gravity_gradient'] else 'off'}")
        if self.has("com"):
            lines.append(f"  system CM moved {np.max(np.linalg.norm(self.com - self.com[0], axis=1)):.3g} m (max)")
        lines.append(f"  base: moved {np.linalg.norm(self.base_position[-1] - self.base_position[0]):.4g} m, "
                     f"turned {np.degrees(self.base_rotation_angle[-1]):.4g} deg (final vs initial)")
        if self.has("tracking_error"):
            unit = {"joint": "rad", "cartesian": "m"}.get(self.tracking_error_kind or "", "")
            e = self.tracking_error
            lines.append(f"  tracking error ({self.tracking_error_kind or '?'}): final {e[-1]:.3g} {unit}, max {np.max(e):.3g} {unit}")
        if self.has("link_tracking_error"):
            e = self.link_tracking_error
            lines.append(f"  link tracking error (motor + deflection): final {e[-1]:.3g} rad, max {np.max(e):.3g} rad")
        goal = m.get("goal")
        if goal and goal["unreachable"]:
            lines.append(f"  GOAL OUT OF REACH: the point stopped {goal['distance']:.3g} m short with the task Jacobian nearly "
                         f"singular (smallest singular value {goal['sigma_min']:.3g}); choose a reachable goal")
        if self.has("ee_position"):
            p = self.ee_position[-1]
            lines.append(f"  end effector final position [{', '.join(f'{v:.4g}' for v in p)}] m")
        if self.has("wheel_speed"):
            ws = np.max(np.abs(self.wheel_speed), axis=0)
            lines.append("  wheel max |speed| [rad/s]: " + ", ".join(f"{v:.4g}" for v in ws))
        if self.has("tau"):
            # One figure per joint kind, each in its own unit (torque of revolute joints, force
            # of prismatic ones); a run without its robot cannot tell them apart.
            tau = np.abs(np.asarray(self.tau, dtype=float)).reshape(len(self), -1)
            if self._robot is None:
                lines.append(f"  max |tau| {np.max(tau) if tau.size else 0.0:.4g} (N m for revolute, N for prismatic joints)")
            elif tau.shape[1]:
                prismatic = np.array(self._joint_is_prismatic(), dtype=bool)
                kinds = (("torque", ~prismatic, "N m"), ("force", prismatic, "N"))
                parts = [f"max |{what}| {np.max(tau[:, cols]) if tau.shape[0] else 0.0:.4g} {unit}"
                         for what, cols, unit in kinds if cols.any()]
                lines.append("  joint " + ", ".join(parts))
        counts_sat = self.saturation_counts()
        if counts_sat:
            lines.append(f"  saturation: {len(self.saturation_events)} events: "
                         + ", ".join(f"{k} x{v}" for k, v in sorted(counts_sat.items())))
        else:
            lines.append("  saturation: none")
        return "\n".join(lines)

    # ---- files -----------------------------------------------------------------------------
    def save(self, path: PathLike) -> str:
        """Write the trajectory to ``path`` as a compressed ``.npz`` (atomically): every
        recorded array under its own name, ``meta`` as JSON and the model as TOML text (so
        [`load`][spacearm.Trajectory.load] can rebuild it). Returns the path."""
        payload = {k: np.asarray(v) for k, v in self._data.items()}
        payload["__format__"] = np.array(FILE_FORMAT)
        payload["__meta__"] = np.array(json.dumps(_jsonable(self._meta), allow_nan=True))
        if self._robot is not None:
            from ..io.model_file import dumps_toml

            payload["__model_toml__"] = np.array(dumps_toml(self._robot))
        with atomic_open(path, "wb", suffix=".npz") as f:
            np.savez_compressed(f, **payload)
        return str(path)

    @classmethod
    def load(cls, path: PathLike, robot=None) -> "Trajectory":
        """Read a file written by [`save`][spacearm.Trajectory.save]. The robot is rebuilt from the embedded model
        unless ``robot`` is given (it must have the same number of joints)."""
        with open_npz(path, "spacearm trajectory") as files:
            files = dict(files)
        fmt = str(files.pop("__format__", ""))
        if fmt != FILE_FORMAT:
            raise ArgumentError(f"{path}: not a spacearm trajectory file (format tag {fmt!r}, expected {FILE_FORMAT!r})")
        meta = _read_meta(path, files.pop("__meta__", None))
        model = files.pop("__model_toml__", None)
        if robot is None and model is not None:
            from ..io.model_file import loads_toml

            robot = loads_toml(str(model), source=f"{path} (embedded model)")
        return cls(robot=robot, data=files, meta=meta)

    def columns(self) -> List[tuple]:
        """The CSV columns: ``(name, unit, values (K,))`` in file order."""
        names = self.joint_names()
        prismatic = self._joint_is_prismatic()
        pos = ["m" if p else "rad" for p in prismatic]
        vel = ["m/s" if p else "rad/s" for p in prismatic]
        acc = ["m/s^2" if p else "rad/s^2" for p in prismatic]
        frc = ["N" if p else "N m" for p in prismatic]
        xyz = ("x", "y", "z")
        cols = [("t", "s", self.t)]

        def add(prefix, arr, labels, units):
            for j, (lab, unit) in enumerate(zip(labels, units)):
                cols.append((f"{prefix}{lab}", unit, arr[:, j]))

        add("r0_", self.x[:, :3], xyz, ["m"] * 3)
        add("quat0_", self.x[:, 3:7], ("x", "y", "z", "w"), ["1"] * 4)
        add("q_", self.q, names, pos)
        add("v0_", self.u[:, :3], xyz, ["m/s"] * 3)
        add("w0_", self.u[:, 3:6], xyz, ["rad/s"] * 3)
        add("qd_", self.qd, names, vel)
        if self.has("du"):
            add("dv0_", self.du[:, :3], xyz, ["m/s^2"] * 3)
            add("dw0_", self.du[:, 3:6], xyz, ["rad/s^2"] * 3)
            add("qdd_", self.qdd, names, acc)
        if self.has("tau"):
            add("tau_", self.tau, names, frc)
        if self.has("tau_cmd"):
            add("tau_cmd_", self.tau_cmd, names, frc)
        if self.has("base_wrench"):
            add("F0_", self.base_wrench[:, :3], xyz, ["N"] * 3)
            add("N0_", self.base_wrench[:, 3:], xyz, ["N m"] * 3)
        for key, unit in (("P", "N s"), ("L_origin", "N m s"), ("L_com", "N m s")):
            if self.has(key):
                add(f"{key}_", self[key], xyz, [unit] * 3)
        if self.has("energy"):
            cols.append(("energy", "J", self.energy))
        if self.has("com"):
            add("com_", self.com, xyz, ["m"] * 3)
        if self.has("ee_position"):
            add("ee_", self.ee_position, xyz, ["m"] * 3)
        if self.has("ee_quat"):
            add("ee_quat_", self.ee_quat, ("x", "y", "z", "w"), ["1"] * 4)
        if self.has("reference"):
            ref = self.reference.reshape(len(self), -1)
            kind = self.tracking_error_kind
            if kind == "joint" and ref.shape[1] == self._n:
                add("q_ref_", ref, names, pos)
            elif kind == "cartesian" and ref.shape[1] == 3:
                add("ee_ref_", ref, xyz, ["m"] * 3)
            else:
                add("ref_", ref, [str(i + 1) for i in range(ref.shape[1])], ["1"] * ref.shape[1])
        if self.has("tracking_error"):
            unit = {"joint": "rad", "cartesian": "m"}.get(self.tracking_error_kind or "", "1")
            cols.append(("tracking_error", unit, self.tracking_error))
        if self.has("link_tracking_error"):
            cols.append(("link_tracking_error", "rad", self.link_tracking_error))
        if self.has("wheel_speed"):
            ws = self.wheel_speed.reshape(len(self), -1)
            dofs = list(self._meta.get("wheel_dofs") or [])
            labels = [names[d] if len(dofs) == ws.shape[1] and 0 <= d < self._n else str(i + 1) for i, d in
                      enumerate(dofs if len(dofs) == ws.shape[1] else range(ws.shape[1]))]
            add("wheel_speed_", ws, labels, ["rad/s"] * ws.shape[1])
        for key in ("cmg_measure", "cmg_envelope_fraction"):
            if self.has(key):
                cols.append((key, "1", self[key]))
        return cols

    def to_csv(self, path: PathLike) -> str:
        """Write one row per sample to ``path`` (atomically). Lines starting with ``#``
        describe the run (read them with ``comment="#"``); the header row names every column
        with its unit in brackets, e.g. ``q_joint1 [rad]``; numbers are written with 17
        significant digits (exact round trip). Saturation events are summarized in the
        comments (the ``.npz`` of [`save`][spacearm.Trajectory.save] keeps each one). Returns the path."""
        cols = self.columns()
        header = ",".join(f"{n} [{u}]" for n, u, _ in cols)
        table = np.column_stack([c for _, _, c in cols])
        with atomic_open(path, "w", suffix=".csv") as f:
            for line in self.summary().splitlines():
                f.write(f"# {line}\n")
            meta = {k: v for k, v in _jsonable(self._meta).items() if k != "actuator_names"}
            f.write(f"# meta: {json.dumps(meta, allow_nan=True)}\n")
            f.write(header + "\n")
            np.savetxt(f, table, delimiter=",", fmt="%.17g")
        return str(path)

    # ---- figures -----------------------------------------------------------------------------
    def plot(self, path: Optional[PathLike] = None, **kwargs):
        """A multi-panel figure of the run (joints and reference, base attitude and position,
        conservation, torques and wheel speeds, tracking error); written as PNG to ``path`` if
        given. Returns the matplotlib ``Figure``. See ``spacearm.viz.plotting.plot_trajectory``."""
        from ..viz.plotting import plot_trajectory

        return plot_trajectory(self, path, **kwargs)

    def animate(self, path: PathLike, **kwargs) -> str:
        """A 3-D GIF of the base (box) and the arm (segments joint to joint). Needs the robot.
        See ``spacearm.viz.animation.animate_trajectory`` for the options."""
        from ..viz.animation import animate_trajectory

        return animate_trajectory(self, path, **kwargs)

    def video(self, path: PathLike, *, width: int = 1280, height: int = 720, fps: int = 30, renderer: str = "auto",
              speed: float = 1.0, camera=None, trail: bool = True, progress=None):
        """Write an H.264 ``.mp4`` of the run, rendered offscreen, atomically; returns the
        ``spacearm.viz.video.Video`` (its ``path``, the ``renderer`` that drew it, ``frames``, ...).

        ``width`` × ``height`` pixels (even), ``fps`` frames per second, ``speed`` times real
        time (each frame shows the recorded sample nearest its time). ``renderer``: ``"mujoco"``
        (MuJoCo's offscreen renderer of the MJCF export: needs mujoco and EGL or OSMesa),
        ``"matplotlib"`` (the 3-D drawing of [`animate`][spacearm.Trajectory.animate]) or
        ``"auto"`` (MuJoCo where it can, else matplotlib). ``camera``: MuJoCo's free camera
        (``lookat``, ``distance``, ``azimuth``, ``elevation``; default: the whole run in view).
        ``trail``: the end-effector path so far. ``progress``: a bar (default: renders of 100
        frames or more). Needs the extra ``video`` (imageio-ffmpeg's ffmpeg). docs/video.md."""
        from ..viz.video import trajectory_video

        return trajectory_video(self, path, width=width, height=height, fps=fps, renderer=renderer, speed=speed,
                                camera=camera, trail=trail, progress=progress)
    def view(self, path: Optional[PathLike] = None, *, fps: float = 30.0, open: Optional[bool] = None, **kwargs):
        """The run in the 3-D browser viewer (meshcat, the ``view`` extra; docs/viewer.md).

        With ``path``: writes one self-contained ``.html`` file (opened from ``file://``, no
        server) and returns the path; ``open=True`` also opens it in the web browser. Without a
        path: serves the scene live and returns the ``meshcat.Visualizer`` (opened in the browser
        unless ``open=False``). ``fps``: key frames per second of the run. Needs the robot. Other
        options (``geometry``, ``momentum``, ``path``, ``frames``, ...): see
        ``spacearm.viz.viewer.trajectory_scene``."""
        from ..viz.viewer import trajectory_scene, view

        return view(trajectory_scene(self, fps=fps, **kwargs), path, open=open)
