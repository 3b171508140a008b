"""The capture target: a free rigid body ([`Target`][spacearm.Target]).

State layout (13): ``[position (3), quaternion [x, y, z, w] (4), CM velocity in 𝒥 (3),
angular velocity in 𝒥 (3)]``. That is exactly a spacearm configuration ``x`` (7) followed by a
generalized velocity ``u`` (6) of a robot with no joints, and a Target is built as one: its
mass properties pass the same model rules as every robot's base (one definition of each rule),
and its momentum, point Jacobians and dynamics under a wrench come from the same core. Grasp
points are offsets from the target's CM in its own axes.

The general case, a whole spacearm model as the target (a second spacecraft with appendages),
is [`Target.from_robot`][spacearm.capture.Target.from_robot]: its state is that model's ``[x, u]``, its grasp points are the
model's named points, and the impact, the soft capture and the point-contact sequence work on it
unchanged; only the rigid attachment as a payload needs a rigid target.
"""

from __future__ import annotations

from typing import Mapping, NamedTuple, Optional, Sequence, Union

import numpy as np

import math

from .. import _core
from .._util.arrays import matrix3, number, quaternion, vector, vector3
from ..control import FreeBodyPoint, SampledJoint
from ..errors import ArgumentError, ModelError, NonFiniteError, NotFoundError, QuaternionError, ResourceLimitError, ShapeError, SpacearmTypeError
from ..model.robot import Robot
from ..rotations import quat_from_matrix
from ..sim.simulation import simulate

__all__ = ["Target", "TargetState"]

class TargetState(NamedTuple):
    """A target's state split into its parts (all in 𝒥)."""

    position: np.ndarray  #: CM position, m
    quaternion: np.ndarray  #: attitude [x, y, z, w] (target axes -> 𝒥)
    velocity: np.ndarray  #: CM velocity, m/s
    angular_velocity: np.ndarray  #: rad/s


def _box_of_moments(mass: float, inertia) -> dict:
    """The uniform box of the target's principal moments (the core's ``box_of_moments``),
    turned onto its principal axes."""
    moments, axes = np.linalg.eigh(np.asarray(inertia, dtype=float))
    if np.linalg.det(axes) < 0:
        axes[:, 2] = -axes[:, 2]
    size = _core.box_of_moments(float(mass), [float(m) for m in moments])
    return {"shape": "box", "size": size, "rotation": quat_from_matrix(axes), "rgba": (0.6, 0.65, 0.75, 1.0)}


class Target:
    """A free rigid body to capture.

    Parameters
    ----------
    mass : float
        kg (> 0).
    inertia : 3 numbers or 3×3
        About the CM, in the target's axes (kg·m²); the same physical rules as a robot body
        (positive definite, triangle inequality) apply.
    name : str, optional
        Default ``"target"``.
    grasp_points : mapping name -> offset, or a sequence of offsets, optional
        Offsets from the CM in the target's axes (m). A sequence gets the names ``grasp0``,
        ``grasp1``, ...; default: one point ``"grasp"`` at the CM. Each at most
        ``MAX_HANDLE_RATIO`` (2) times the target's size ``√(1.5 tr(I) / m)`` from the CM
        (farther: ``ArgumentError``; docs/capture.md, "Grasps that are refused").
    shape : mapping, optional
        The target's visual shape: the keyword arguments of
        [`RobotBuilder.add_geometry`][spacearm.RobotBuilder.add_geometry] but the body (``{"shape": "cylinder",
        "radius": 0.5, "length": 1.2}``; docs/geometry.md). Default: the uniform box with the
        target's principal moments, along its principal axes. It carries no mass.
    """

    def __init__(self, mass: float, inertia, *, name: Optional[str] = None,
                 grasp_points: Union[Mapping[str, Sequence[float]], Sequence[Sequence[float]], None] = None,
                 shape: Optional[Mapping] = None):
        self.name = "target" if name is None else str(name)
        mass = number(mass, "target mass")
        try:
            builder = Robot.builder(self.name, base_mass=mass, base_inertia=inertia, base_name=self.name)
        except ModelError as exc:
            raise ModelError(f"target '{self.name}': {exc}") from None
        if grasp_points is None:
            grasp_points = {"grasp": (0.0, 0.0, 0.0)}
        elif not isinstance(grasp_points, Mapping):
            pts = list(grasp_points)
            if pts and np.ndim(pts[0]) == 0:  # one offset given flat
                pts = [pts]
            grasp_points = {f"grasp{i}": p for i, p in enumerate(pts)}
        if not grasp_points:
            raise ArgumentError(f"target '{self.name}' needs at least one grasp point")
        self.grasp_points = {}
        for key, offset in grasp_points.items():
            off = vector3(offset, f"target grasp point '{key}'")  # finite, or a NonFiniteError naming it
            self.grasp_points[str(key)] = off
            builder.add_point(str(key), body=self.name, offset=off)
        if shape is None:
            shape = _box_of_moments(mass, matrix3(inertia, "target inertia"))
        elif not isinstance(shape, Mapping) or "shape" not in shape:
            raise ArgumentError(f"target '{self.name}': shape must be a mapping with a 'shape' key and the "
                                f"add_geometry keywords, e.g. {{'shape': 'sphere', 'radius': 0.5}}; got {shape!r}")
        shape = dict(shape)
        try:
            builder.add_geometry(self.name, shape.pop("shape"), **shape)
        except TypeError as exc:
            raise ArgumentError(f"target '{self.name}': shape: {exc}") from None
        try:
            #: The target as a spacearm model with no joints: state ``[x (7), u (6)]``.
            self.body = builder.build()
        except ModelError as exc:
            raise ModelError(f"target '{self.name}': {exc}") from None
        for key, off in self.grasp_points.items():
            try:  # the handle-length rule of the grasp impact (the core's), before any run
                _core.check_grasp_handle(self.body.core_model, 0, off)
            except ArgumentError as exc:
                raise ArgumentError(f"target '{self.name}', grasp point '{key}': {exc}") from None
        self.mass = mass
        base = self.body.description.base
        #: Inertia about the CM in target axes (3×3; ``None`` for a jointed target).
        self.inertia = np.array(base.inertia, dtype=float).reshape(3, 3)
        self._grasp = {key: (0, off) for key, off in self.grasp_points.items()}

    @classmethod
    def from_robot(cls, robot, *, name: Optional[str] = None) -> "Target":
        """A whole spacearm model as the target. Its state is ``np.concatenate([x, u])`` of the
        model; its grasp points are the model's named points (offsets in their bodies' frames);
        ``mass`` is its total mass and ``inertia`` is ``None``."""
        if not isinstance(robot, Robot):
            raise ArgumentError(f"Target.from_robot needs a spacearm.Robot, got {type(robot).__name__}")
        if not robot.point_names:
            raise ArgumentError(f"model '{robot.name}' has no named point to grasp; add one with RobotBuilder.add_point")
        self = cls.__new__(cls)
        self.name = robot.name if name is None else str(name)
        self.body = robot
        self.mass = robot.total_mass
        self.inertia = None
        self._grasp = {p: robot.resolve_point(p) for p in robot.point_names}
        self.grasp_points = {p: np.array(off) for p, (_, off) in self._grasp.items()}
        return self

    @property
    def is_rigid(self) -> bool:
        """Whether the target is one rigid body (a jointed model is not)."""
        return self.body.n_dof == 0

    @property
    def state_size(self) -> int:
        """13 for a rigid target; ``7 + N + 6 + N`` for a model."""
        return self.body.nx + self.body.nu

    def xu(self, state):
        """The state split as the target model's ``(x, u)``."""
        s = np.asarray(state, dtype=float)
        return s[: self.body.nx], s[self.body.nx:]

    def __repr__(self) -> str:
        return f"<Target '{self.name}': {self.mass:.6g} kg, grasp points {list(self.grasp_points)}>"

    # ---- states ---------------------------------------------------------------------------
    def state(self, position=(0.0, 0.0, 0.0), quaternion=(0.0, 0.0, 0.0, 1.0), velocity=(0.0, 0.0, 0.0),
              angular_velocity=(0.0, 0.0, 0.0)) -> np.ndarray:
        """The 13-vector ``[position, quaternion, velocity, angular_velocity]`` (all in 𝒥) of a
        rigid target (a jointed one: ``np.concatenate([x, u])`` of its model)."""
        if not self.is_rigid:
            raise ArgumentError(f"target '{self.name}' is a jointed model: its state is np.concatenate([x, u]) of that model")
        return np.concatenate([vector3(position, "target position"), _quat(quaternion),
                               vector3(velocity, "target velocity"), vector3(angular_velocity, "target angular velocity")])

    def state_in_orbit(self, orbit, relative, *, center=None, quaternion=(0.0, 0.0, 0.0, 1.0),
                       angular_velocity=(0.0, 0.0, 0.0)) -> np.ndarray:
        """The 13-state, in an orbital run's frame (relative to the orbit's point at time 0, ECI
        axes; docs/orbit.md), of a rigid target whose CM is at ``relative`` in LVLH:
        ``[x radial, y along-track, z orbit normal, ẋ, ẏ, ż]`` (m, and its rate seen in the
        rotating LVLH, m/s) about ``center`` (the chaser's system CM as a run state ``[position,
        velocity]`` (6), e.g. ``robot.center_of_mass(x0)`` and ``P / M``; default the orbit's
        point). ``orbit.safety_ellipse(...)`` gives a drift-free relative state; a V-bar placement
        is ``[0, d, 0, 0, 0, 0]``, an R-bar one ``[d, 0, 0, 0, 0, 0]``. ``quaternion`` and
        ``angular_velocity`` (inertial) are in ECI axes (𝒥). The conversion is the core's
        (``Orbit::lvlh_to_run``)."""
        from ..orbit import Orbit

        if not isinstance(orbit, Orbit):
            raise ArgumentError(f"orbit must be a spacearm.Orbit, got {type(orbit).__name__}")
        if not self.is_rigid:
            raise ArgumentError(f"target '{self.name}' is a jointed model: only a rigid target is placed in LVLH")
        rel = vector(relative, "relative state (LVLH)", 6)
        c = np.zeros(6) if center is None else vector(center, "center (run state of the chaser's CM)", 6)
        run = orbit.lvlh_to_run(rel, center=c)
        q = _quat(quaternion)
        w = vector3(angular_velocity, "target angular velocity")
        return np.concatenate([run[:3], q, run[3:], w])

    def check_state(self, state) -> np.ndarray:
        """``state`` as a checked float array (length 13 for a rigid target; the quaternion normalized)."""
        s = vector(state, "target_state")
        if s.size != self.state_size:
            layout = ("[position, quaternion xyzw, velocity, angular velocity]" if self.is_rigid
                      else f"[x, u] of model '{self.body.name}'")
            raise ShapeError(f"target_state has length {self.state_size} ({layout}), got {s.size}")
        if not np.all(np.isfinite(s)):
            raise NonFiniteError(f"target_state must be finite, got {s}")
        s = s.copy()
        s[3:7] = _quat(s[3:7])
        return s

    @staticmethod
    def split(state) -> TargetState:
        s = np.asarray(state, dtype=float)
        return TargetState(s[0:3], s[3:7], s[7:10], s[10:13])

    def point(self, grasp: Optional[str] = None):
        """``(body, offset)`` of a grasp point for [`body`][spacearm.capture.target.Target.body] (default: the first one)."""
        if grasp is None:
            grasp = next(iter(self._grasp))
        if grasp not in self._grasp:
            raise NotFoundError(f"target '{self.name}' has no grasp point '{grasp}'; it has {list(self._grasp)}")
        return self._grasp[grasp]

    def rotation(self, state) -> np.ndarray:
        """Target (base) axes -> 𝒥 (3×3)."""
        return self.body.forward_kinematics(self.xu(state)[0]).body_to_world[0]

    def material_point(self, state, point_in_world, grasp: Optional[str] = None):
        """``(body, offset)`` of the material point of the grasp point's body that is at
        ``point_in_world`` (m, 𝒥)."""
        body, _ = self.point(grasp)
        kin = self.body.forward_kinematics(self.xu(state)[0])
        return body, kin.body_to_world[body].T @ (np.asarray(point_in_world, dtype=float) - kin.com_in_world[body])

    def grasp_position(self, state, grasp: Optional[str] = None) -> np.ndarray:
        """World position of a grasp point."""
        return self.body.point_position(self.xu(state)[0], self.point(grasp))

    def grasp_velocity(self, state, grasp: Optional[str] = None) -> np.ndarray:
        """World velocity of a grasp point."""
        x, u = self.xu(state)
        j0, jm = self.body.point_jacobian(x, self.point(grasp))
        return (j0 @ u[:6] + jm @ u[6:])[:3]

    def momentum(self, state):
        """[`spacearm.Momentum`][spacearm.Momentum] of the target (``P``, ``L_origin``, ...)."""
        return self.body.momentum(*self.xu(state))

    def kinetic_energy(self, state) -> float:
        return self.body.kinetic_energy(*self.xu(state))

    # ---- motion -----------------------------------------------------------------------------
    def _check_step(self, dt: float, what: str = "dt") -> float:
        if isinstance(dt, (bool, np.bool_)):
            raise SpacearmTypeError(f"{what} must be a number of seconds, got the bool {dt!r}")
        dt = number(dt, what)
        if not (math.isfinite(dt) and dt > 0):
            raise ArgumentError(f"{what} must be finite and > 0, got {dt}")
        return dt

    def free_body(self, state, grasp: Optional[str] = None, *, step: float = 1e-3, point=None, orbit=None) -> FreeBodyPoint:
        """The rigid target in ``state`` (at simulation time 0) as a [`FreeBodyPoint`][spacearm.control.FreeBodyPoint]
        of its grasp point: the reference [`capture`][spacearm.capture.capture] hands the native
        resolved-motion-rate controller, and the core's propagation of the target
        (``spacearm_core::sim::free_body``; attitude step ``step``, s). ``point``: the robot's
        point that follows it. ``orbit``: the run's orbit (the state relative to its point at
        time 0): the target drifts under gravity's tidal part and tumbles under its own gravity
        gradient (docs/orbit.md)."""
        if not self.is_rigid:
            raise ArgumentError(f"target '{self.name}' is a jointed model: its motion is not a free rigid body; use Target.trajectory")
        _, offset = self.point(grasp)
        return FreeBodyPoint(self.inertia, self.check_state(state), offset=offset, step=self._check_step(step, "step"), point=point,
                             orbit=orbit)

    def trajectory(self, state, duration: float, dt: float):
        """``(t, states)`` of the torque-free target from ``state`` on the grid ``0, dt, ...,
        duration``: a rigid target by the core's free-body propagation (attitude step ``dt / 2``),
        a jointed one by ``spacearm.simulate`` (free-floating, zero joint torques, adaptive DOPRI5)."""
        s = self.check_state(state)
        duration, dt = number(duration, "duration"), self._check_step(dt)
        if not (duration >= 0 and math.isfinite(duration)):
            raise ArgumentError(f"duration must be finite and >= 0, got {duration}")
        if self.is_rigid:
            n = round(duration / dt)
            if (n + 1) * self.state_size * 8 > _core.MEMORY_LIMIT_BYTES:
                raise ResourceLimitError(f"a trajectory of {n + 1:.3e} samples (duration {duration:g} s / dt {dt:g} s) needs more "
                                         f"than the {_core.MEMORY_LIMIT_BYTES / 2**30:g} GiB allowed (spacearm._core.MEMORY_LIMIT_BYTES); "
                                         "raise dt or shorten the duration")
            n = int(n)
            t = np.arange(n + 1) * dt
            return t, self.free_body(s, step=0.5 * dt).states(t)
        x, u = self.xu(s)
        traj = simulate(self.body, max(duration, dt), x0=x, u0=u, integrator="dopri5", rtol=1e-11, atol=1e-13, dt=dt)
        return traj.t, np.hstack([traj.x, traj.u])

    def grasp_path(self, state, duration: float, dt: float, grasp: Optional[str] = None) -> SampledJoint:
        """The grasp point's path in 𝒥 over ``[0, duration]`` as a sampled reference (positions,
        velocities and, by central differences of the velocities, accelerations on the grid
        ``dt``): how the native RMRC follows a jointed target."""
        t, S = self.trajectory(state, duration, dt)
        nx = self.body.nx
        pt = self.point(grasp)
        p = self.body.point_position(S[:, :nx], pt)
        j0, jm = self.body.point_jacobian(S[:, :nx], pt)
        u = S[:, nx:]
        v = (np.einsum("bij,bj->bi", j0, u[:, :6]) + np.einsum("bij,bj->bi", jm, u[:, 6:]))[:, :3]
        a = np.gradient(v, t, axis=0) if len(t) > 2 else np.zeros_like(v)
        return SampledJoint(t, p, v, a)

    def propagate(self, state, duration: float, *, dt: float = 1e-3) -> np.ndarray:
        """The torque-free state after ``duration`` seconds (a jointed target: free-floating with
        zero joint torques, by ``spacearm.simulate`` with DOPRI5).

        A rigid target moves by the core's free-body propagation
        (``spacearm_core::sim::free_body``): the CM at constant velocity and the angular momentum
        ``L`` in 𝒥 constant, the attitude integrated by RK4 under ``ω = R I⁻¹ Rᵀ L`` with
        ``n = ceil(duration / dt)`` equal steps, so ``P`` and ``L`` are conserved exactly and only
        the attitude carries integration error.
        """
        s = self.check_state(state)
        duration = number(duration, "duration")
        dt = self._check_step(dt)
        if not (duration >= 0 and math.isfinite(duration)):
            raise ArgumentError(f"duration must be finite and >= 0, got {duration}")
        if duration == 0:
            return s
        if not self.is_rigid:  # a jointed model: free-floating with zero torques, adaptive DOPRI5
            x, u = self.xu(s)
            traj = simulate(self.body, duration, x0=x, u0=u, integrator="dopri5", rtol=1e-11, atol=1e-13, dt=duration)
            return np.concatenate([traj.x[-1], traj.u[-1]])
        n = max(1, int(np.ceil(duration / dt)))
        return self.free_body(s, step=duration / n).states([duration])[0]


def _quat(value) -> np.ndarray:
    """The target's attitude quaternion by the rule of every configuration's quaternion (the
    core's): finite, of unit norm within ``_core.QUATERNION_TOLERANCE`` (1e-6), then normalized
    exactly; anything else is a [`QuaternionError`][spacearm.errors.QuaternionError] (a NaN one a
    [`NonFiniteError`][spacearm.errors.NonFiniteError])."""
    q = quaternion(value, "target quaternion")
    if not np.all(np.isfinite(q)):
        raise NonFiniteError(f"target quaternion must be finite, got {q}")
    norm = float(np.linalg.norm(q))
    if not abs(norm - 1.0) <= _core.QUATERNION_TOLERANCE:
        raise QuaternionError(f"target quaternion must be a unit quaternion [x, y, z, w] (|q| = 1 within "
                              f"{_core.QUATERNION_TOLERANCE:g}), got norm {norm:.6g}; the identity attitude is [0, 0, 0, 1]")
    return q / norm
