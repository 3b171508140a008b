"""Controllers, references and actuator limits for [`spacearm.simulate`][spacearm.simulate].

Every controller here is a description that the native simulator turns into a control law
evaluated at every integrator stage in Rust (no Python call per step), except
[`Callback`][spacearm.control.Callback], which calls a Python function at every stage and is correspondingly slower.
The equations, with the paper's numbers, are in ``docs/simulation-core.md``.

Joint-space controllers act on the **arm joints**: every joint that is not a reaction wheel
(wheels are what [`RobotBuilder.add_reaction_wheel`][spacearm.RobotBuilder.add_reaction_wheel] creates, or what ``simulate(wheels=...)``
names). Their references and per-joint gains therefore have one entry per arm joint — ``N``
for a robot without wheels. [`ComputedTorque`][spacearm.control.ComputedTorque] and
[`ResolvedMotionRate`][spacearm.control.ResolvedMotionRate] command the **actuated** arm joints
only (passive joints — slosh, hinged panels — get zero torque and are treated as measured drift;
docs/flexibility.md), so a computed-torque reference has one entry per actuated arm joint.
[`input_shaper`][spacearm.control.input_shaper] shapes a joint reference against a flexible mode.

>>> import spacearm
>>> from spacearm.control import ComputedTorque, QuinticJoint
>>> robot = spacearm.presets.planar4()
>>> q0 = robot.initial_q
>>> ref = QuinticJoint(q0, q0 + 0.3, t_start=0.0, t_end=2.0)
>>> traj = spacearm.simulate(robot, 2.5, controller=ComputedTorque(kp=100.0, kd=20.0, reference=ref))
"""

from __future__ import annotations

import math as _math
from dataclasses import dataclass as _dataclass
from typing import TYPE_CHECKING as _TYPE_CHECKING

import numpy as _np

from . import _core
from typing import ClassVar as _ClassVar

from ._util.arrays import number as _number, vector as _vector
from ._util.pickling import reduce_through_constructor as _reduce_through_constructor
from ._util.spec import check as _check, data as _spec_data
from .errors import ArgumentError as _ArgumentError

if _TYPE_CHECKING:  # the annotations' names (not evaluated at run time: no module-level name)
    from typing import Any, Callable, Optional, Sequence, Union

# The module exports its API only (__all__): every helper above is imported under a private name.
del annotations

__all__ = [
    "QuinticJoint",
    "SampledJoint",
    "CartesianLine",
    "FreeBodyPoint",
    "Thrusters",
    "JointPD",
    "ComputedTorque",
    "ResolvedMotionRate",
    "AttitudeControl",
    "CmgSteering",
    "BaseThrusterControl",
    "Combined",
    "CoordinatedFlying",
    "MPC",
    "MomentumDamping",
    "TorqueLimit",
    "Callback",
    "perturbed_model",
    "perturbed_cmgs",
    "inertia_scaled_gains",
    "InputShaper",
    "ShapedJoint",
    "input_shaper",
]


def _quintic(t, t_start: float, t_end: float):
    """Rest-to-rest quintic time scaling ``s = 10τ³ − 15τ⁴ + 6τ⁵`` and its derivatives: the
    core's (the one the native controllers follow), evaluated at each time of ``t``."""
    t = _np.asarray(t, dtype=float)
    s, sd, sdd = _core.quintic_scaling(_np.ascontiguousarray(t.reshape(-1)), float(t_start), float(t_end))
    return s.reshape(t.shape), sd.reshape(t.shape), sdd.reshape(t.shape)


# ---- references ------------------------------------------------------------------------------
class _JointReference:
    """A joint reference whose evaluator is the core's, made from its data (``_core.JointReference``,
    checked there)."""

    def __post_init__(self):
        object.__setattr__(self, "_core_ref", _core.JointReference.from_spec(_data(self)))

    def evaluate(self, t):
        """``(q, qd, qdd)`` at time(s) ``t``: what the controllers follow; each (n,) for a scalar
        ``t``, (len(t), n) for an array."""
        return _at_times(self._core_ref.evaluate, t)


@_dataclass(frozen=True)
class QuinticJoint(_JointReference):
    """Joint-space rest-to-rest quintic from ``q_start`` to ``q_goal`` over ``[t_start, t_end]``
    (one entry per arm joint); holds ``q_start`` before and ``q_goal`` after."""

    __reduce__ = _reduce_through_constructor  # unpickled through the validating constructor

    q_start: Sequence[float]
    q_goal: Sequence[float]
    t_start: float
    t_end: float

    _kind: _ClassVar[str] = "quintic"


@_dataclass(frozen=True)
class CartesianLine:
    """Straight-line path of a point from ``p_start`` to ``p_goal`` (m, in 𝒥) with quintic
    timing over ``[t_start, t_end]``. ``point``: the point that follows it (a point name, a
    body name, or ``(body, offset)``; default: the end effector)."""

    __reduce__ = _reduce_through_constructor  # unpickled through the validating constructor

    p_start: Sequence[float]
    p_goal: Sequence[float]
    t_start: float
    t_end: float
    point: Any = None

    _kind: _ClassVar[str] = "line"

    def __post_init__(self):
        _check("point_reference", self)

    def evaluate(self, t):
        """``(p, pd, pdd)`` at time(s) ``t``."""
        s, sd, sdd = _quintic(t, self.t_start, self.t_end)
        p_start, p_goal = _np.asarray(self.p_start, dtype=float), _np.asarray(self.p_goal, dtype=float)
        delta = p_goal - p_start
        s, sd, sdd = (_np.asarray(v)[..., None] for v in (s, sd, sdd))
        return p_start + s * delta, sd * delta, sdd * delta

@_dataclass(frozen=True)
class SampledJoint(_JointReference):
    """A sampled joint trajectory: knot times ``t`` (K ≥ 2, strictly increasing, s) and the
    positions ``q``, velocities ``qd`` and accelerations ``qdd`` at the knots, each (K, n).

    Between knots the reference is the quintic Hermite interpolant (position, velocity and
    acceleration matched at both ends of each interval, so all three are continuous; the core's
    ``JointReference.sampled``); before the first and after the last knot, that knot's values.
    A plan is tracked by [`ComputedTorque`][spacearm.control.ComputedTorque] through it ([`spacearm.plan`][spacearm.plan]). The values
    are checked by the core."""

    t: Any
    q: Any
    qd: Any
    qdd: Any

    _kind: _ClassVar[str] = "sampled"

@_dataclass(frozen=True)
class FreeBodyPoint:
    """A point fixed to a torque-free rigid body — the grasp point of a tumbling target — as a
    reference for [`ResolvedMotionRate`][spacearm.control.ResolvedMotionRate].

    ``inertia``: about the body's CM in its axes (3×3 or 3 principal moments, kg·m²);
    ``state``: the body's 13-state ``[r, quat [x, y, z, w], v, w]`` (in 𝒥) at simulation time 0;
    ``offset``: the point from the CM in body axes (m); ``step``: the attitude step (s) of the
    core's propagation (``spacearm_core::sim::free_body``: momentum conserved exactly, the
    attitude by RK4). ``point``: the robot's point that follows it (default: the end effector).
    ``orbit``: the run's [`Orbit`][spacearm.Orbit] (``state`` relative to its point at time 0,
    ECI axes; docs/orbit.md): the body then moves under gravity's tidal part (exact relative
    two-body + J2 acceleration) and turns under its gravity-gradient torque, both integrated by
    RK4 on the same grid; ``None``: torque-free.
    """

    inertia: Any
    state: Any
    offset: Any = (0.0, 0.0, 0.0)
    step: float = 1e-3
    point: Any = None
    orbit: Any = None

    _kind: _ClassVar[str] = "free_body"

    def __post_init__(self):
        object.__setattr__(self, "_core_ref", _core.FreeBodyReference.from_spec(_data(self)))

    def external_wrenches(self, t, mass: float) -> _np.ndarray:
        """The external wrench on the body of mass ``mass`` (kg) at the times ``t``, (len(t), 6):
        in orbit the tidal force (N) and its moment about the run's origin (N·m); zeros
        torque-free (the core's ``FreeBody::external_wrench``)."""
        return self._core_ref.external_wrenches(_np.atleast_1d(_np.asarray(t, dtype=float)), mass)

    def states(self, t) -> _np.ndarray:
        """The body's 13-states at time(s) ``t`` (s ≥ 0): (13,) for a scalar ``t``, (len(t), 13) for an array."""
        return _at_times(self._core_ref.states, t)

    def evaluate(self, t):
        """``(p, pd)`` of the point at time(s) ``t``, in 𝒥: each (3,) for a scalar ``t``, (len(t), 3) for an array."""
        return _at_times(self._core_ref.points, t)

@_dataclass(frozen=True)
class InputShaper:
    """A ZV or ZVD input shaper (Singer & Seering 1990) designed for the mode of natural
    ``frequency`` (rad/s) and ``damping`` ratio (0 ≤ ζ < 1): impulses ``amplitudes`` at
    ``times`` (the core's ``control/shaping.rs``). [`shape`][spacearm.control.InputShaper.shape]
    convolves a joint reference with them; the shaped move is ``times[-1]`` longer. Build one
    with [`input_shaper`][spacearm.control.input_shaper]."""

    kind: str
    frequency: float
    damping: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "_core_shaper", _core.InputShaper.from_spec(_data(self)))

    @property
    def amplitudes(self) -> _np.ndarray:
        """The impulse amplitudes (sum 1)."""
        return self._core_shaper.amplitudes

    @property
    def times(self) -> _np.ndarray:
        """The impulse times, s (the first 0)."""
        return self._core_shaper.times

    def residual_vibration(self, frequency: float, damping: float = 0.0) -> float:
        r"""Singer & Seering's residual vibration $V(\omega, \zeta) = e^{-\zeta\omega t_N}\sqrt{C^2 + S^2}$
        of the mode ``(frequency, damping)``: its amplitude after the shaper's last impulse (at
        $t_N$) relative to that of one unit impulse applied at $t_N$; 0 at the design mode. For
        ``damping = 0`` this is also the ratio to the unshaped move (a unit impulse at 0); for
        $\zeta > 0$ that ratio is $V e^{\zeta\omega t_N}$."""
        return self._core_shaper.residual_vibration(frequency, damping)

    def shape(self, reference) -> "ShapedJoint":
        """The shaped joint reference ``sum_i A_i r(t - t_i)`` of ``reference`` (a
        [`QuinticJoint`][spacearm.control.QuinticJoint] or a [`SampledJoint`][spacearm.control.SampledJoint])."""
        return ShapedJoint(reference, self)


def input_shaper(kind: str, *, frequency: float, damping: float = 0.0) -> InputShaper:
    """The ``"zv"`` or ``"zvd"`` [`InputShaper`][spacearm.control.InputShaper] for the mode of
    natural ``frequency`` (rad/s) and ``damping`` ratio, e.g. the first flexible mode from
    [`Robot.natural_frequencies`][spacearm.Robot.natural_frequencies]."""
    return InputShaper(kind, frequency, damping)


@_dataclass(frozen=True)
class ShapedJoint(_JointReference):
    """A joint reference convolved with an [`InputShaper`][spacearm.control.InputShaper]:
    ``q_s(t) = sum_i A_i q(t - t_i)`` (and so its rates), evaluated in the core."""

    reference: Any
    shaper: InputShaper

    _kind: _ClassVar[str] = "shaped"

def _at_times(evaluate, t):
    """``evaluate`` (a core reference's, which takes an array of times) at time(s) ``t``: one
    row per time for an array ``t``, the row itself for a scalar ``t`` (the one shape rule of
    every reference's ``evaluate``)."""
    times = _np.asarray(t, dtype=float)
    out = evaluate(_np.atleast_1d(times).reshape(-1))
    if times.ndim == 0:
        return tuple(a[0] for a in out) if isinstance(out, tuple) else out[0]
    return out


def _data(obj):
    """The core's data of a reference or shaper (``spacearm._util.spec``)."""
    return _spec_data(obj, [], type(obj).__name__)


# ---- actuators -------------------------------------------------------------------------------
@_dataclass(frozen=True)
class Thrusters:
    """Base thruster limits per axis of 𝒥: ``|F0_i| <= max_force`` (N) and ``|N0_i| <= max_torque``
    (N·m); a number applies to all three axes, ``inf`` means no limit. A command beyond a
    limit is clamped and recorded as a saturation event (kind 2)."""

    max_force: Union[float, Sequence[float]] = float("inf")
    max_torque: Union[float, Sequence[float]] = float("inf")

    def __post_init__(self):
        _check("thrusters", self)


# ---- controllers -----------------------------------------------------------------------------
class _Controller:
    """A native control law: a dataclass whose fields are the core's spec of kind ``_kind``
    (``control/spec.rs``), checked by the core when it is made."""

    _kind: _ClassVar[str]

    def __post_init__(self):
        _check("controller", self)


@_dataclass(frozen=True)
class JointPD(_Controller):
    """Joint PD on the arm joints: ``tau = kp (q_ref - q) + kd (qd_ref - qd)``.

    ``kp``, ``kd``: one gain or one per actuated arm joint (N·m/rad, N·m·s/rad). ``reference``: a
    [`QuinticJoint`][spacearm.control.QuinticJoint] or a constant set point (one entry per actuated arm joint,
    [`Robot.actuated_arm_dofs`][spacearm.Robot.actuated_arm_dofs]). Only the **actuated** arm joints are
    commanded: a passive joint (slosh, panel, a compliant joint's deflection; docs/flexibility.md)
    gets exactly zero torque and is left out of the tracking error. On a rigid model every arm
    joint is actuated.
    """

    _kind: _ClassVar[str] = "joint_pd"

    kp: Any
    kd: Any
    reference: Any


@_dataclass(frozen=True)
class ComputedTorque(_Controller):
    """Computed torque on the reduced equations of motion (paper eqs. 112–115):
    ``tau = H* (qdd_ref + kd (qd_ref - qd) + kp (q_ref - q)) + c*``.

    ``H*``, ``c*`` come from ``model`` (a [`Robot`][spacearm.Robot] with the plant's joints; see
    [`perturbed_model`][spacearm.control.perturbed_model]) or, by default, from the plant itself. With the exact model the
    arm follows the reference to integration accuracy. When combined with a base controller
    ([`Combined`][spacearm.control.Combined]), the wheel torques and base wrench it commands are compensated exactly
    (the ``H0m^T H0^-1 F_b`` term of the flying-regime reduced EOM).

    Only the **actuated** arm joints are commanded (``reference`` and the gains have one entry per
    actuated arm joint; a passive joint gets zero torque, docs/flexibility.md). ``passive``:
    ``"drift"`` (default) measures the passive coordinates and realizes the commanded
    accelerations of the actuated joints exactly through the coupling (collocated partial
    feedback linearization, Spong 1994); ``"frozen"`` designs the controller on the rigid model,
    the passive joints locked at their rest position with zero rate (it does not see the fuel and
    panels move: the model error of the flexibility risk study).
    """

    _kind: _ClassVar[str] = "computed_torque"

    kp: Any
    kd: Any
    reference: Any
    model: Any = None
    passive: str = "drift"


@_dataclass(frozen=True)
class ResolvedMotionRate(_Controller):
    """Resolved-motion-rate control of a point through the generalized Jacobian ``J*``
    (paper eq. 110) with damped least squares.

    Joint-rate command (``strategy="naive"``): ``qd_cmd = J^T (J J^T + lambda^2 E)^-1 (v_d - v_drift)``,
    ``v_d = pd_ref + gain (p_ref - p)`` on the translational rows, with ``J`` the task rows of
    ``J*`` over the arm joints and ``v_drift`` the point twist that the system momentum and the
    wheels produce: the solver of [`spacearm.analysis.rmrc_rates`][spacearm.analysis.rmrc_rates], run natively. Damped least squares per singular
    direction (docs/singularities.md): a direction of singular value ``sigma`` gets
    ``lambda^2 = max_damping^2 (1 - (sigma / threshold)^2)`` when ``sigma < threshold``, else 0 —
    the same law and defaults as [`spacearm.analysis`][spacearm.analysis]. The joints follow ``qd_cmd`` through the reduced EOM:
    ``tau = H* velocity_gain (qd_cmd - qd) + c*``.

    ``reference_cartesian``: a [`CartesianLine`][spacearm.control.CartesianLine], a [`FreeBodyPoint`][spacearm.control.FreeBodyPoint] (a point on
    a tumbling body: the capture approach) or a [`SampledJoint`][spacearm.control.SampledJoint] of three coordinates (a
    sampled path of the point in 𝒥); ``gain`` (1/s); ``max_damping`` (m, the
    largest lambda); ``threshold`` (m, where damping starts); ``velocity_gain`` (1/s);
    ``point``: overrides the reference's point (default: the end effector);
    ``max_joint_rate`` (rad/s): ``qd_cmd`` is scaled as a whole so that no entry exceeds it
    (the point keeps its direction; default no cap).

    ``task`` and ``strategy`` as in [`spacearm.analysis.rmrc_rates`][spacearm.analysis.rmrc_rates] (the same solver):
    ``task`` a name of [`spacearm.analysis.TASKS`][spacearm.analysis.TASKS] (``"position"``, the default: the
    translational rows; ``"planar"``, ``"planar_pose"``, ``"orientation"``, ``"full"``), ``"auto"``
    or a list of rows 0-5 (angular rows hold the orientation of the point's body at the start);
    ``strategy``: ``"naive"`` (default), ``"reactionless"`` (the arm moves in the reaction null
    space: no base rotation from the arm) or ``"minimum_disturbance"`` (task first, then as little
    base rotation as its null space allows).
    """

    _kind: _ClassVar[str] = "resolved_motion_rate"

    reference_cartesian: Any
    gain: float
    max_damping: float = _core.DLS_DEFAULTS.max_damping
    point: Any = None
    threshold: float = _core.DLS_DEFAULTS.threshold
    velocity_gain: float = 50.0
    max_joint_rate: float = float("inf")
    task: Any = "position"
    strategy: str = "naive"


@_dataclass(frozen=True)
class AttitudeControl(_Controller):
    """Base attitude control with reaction wheels (mode ``"rotation-floating"``).

    PD on the attitude error quaternion ``q_e = q0 ⊗ q_ref^-1`` (in 𝒥): the base torque wanted
    is ``N = -kp e - kd w0`` with ``e = 2 sign(w_e) v_e`` (``v_e``, ``w_e``: vector and scalar
    parts of ``q_e``); the wheels, whose motor torques ``tau_W`` push the base with
    ``-sum tau_j k_j``, get ``tau_W = -A^+ N`` with ``A = [k_1 ... k_W]`` the wheel axes in 𝒥 and
    ``A^+`` its Moore–Penrose pseudo-inverse. ``quat_ref``: ``[x, y, z, w]`` or a scipy
    ``Rotation``; ``kp`` (N·m/rad),
    ``kd`` (N·m·s/rad). ``orbit``: the run's [`Orbit`][spacearm.Orbit]: hold ``quat_ref`` (base →
    LVLH) relative to its LVLH frame, which turns at the orbit rate: ``q_ref(t) = q_LVLH(t) ⊗
    quat_ref`` and ``N = -kp e - kd (w0 - w_LVLH)`` (docs/orbit.md).
    """

    _kind: _ClassVar[str] = "attitude"

    quat_ref: Sequence[float]
    kp: float
    kd: float
    orbit: Any = None


@_dataclass(frozen=True)
class CmgSteering(_Controller):
    """Base attitude control with the robot's control-moment gyros (mode ``"rotation-floating"``;
    docs/cmg.md, the core's ``control/cmg_steering.rs``).

    The base torque wanted is the attitude PD of [`AttitudeControl`][spacearm.control.AttitudeControl],
    ``N = -kp e - kd w0``; the cluster gives the base ``-A(δ) δ̇`` (columns ``h_i (ĝ_i × ŝ_i)``),
    so the gimbal rates commanded are ``δ̇_c = A# (-N)`` with the singularity-robust inverse
    ``A# = Aᵀ (A Aᵀ + λ E)⁻¹``, ``λ = lambda0 h̄² exp(-mu m)`` (Bedrossian; ``m = det(A Aᵀ)/h̄⁶``,
    ``lambda0 = 0``: the pseudo-inverse), scaled into the gimbal-rate limits; each gimbal motor
    follows with the rate loop ``τ = rate_gain · I_g (δ̇_c - δ̇)``. The rotors and arm joints get
    no torque: combine with an arm law through [`Combined`][spacearm.control.Combined].

    ``dither`` ``ε0 > 0`` (``< 0.5``; needs ``lambda0 > 0``) makes it Wie's generalized SR
    inverse ``Aᵀ (A Aᵀ + λ W(t))⁻¹``, ``W`` with the off-diagonal dithers
    ``ε0 sin(dither_frequency · t + φ_i)``, ``φ = (0, π/2, π)``: it leaves a singular state even
    when commanded exactly along its singular direction. ``null_gain`` ``k > 0`` (rad/s) adds the
    null motion ``k (E - A⁺A) ∇√m``, which turns the gimbals toward a larger singularity measure
    without changing the cluster's momentum (docs/cmg.md, "Steering").

    ``wheel_weight`` ``W_s0 > 0`` (a cluster of variable-speed CMGs) steers the gimbal rates and
    the wheel accelerations together, ``[δ̇; Ω̇] = W Qᵀ (Q W Qᵀ)⁻¹ (-N)`` with ``Q = [A  B]``
    (``B``'s columns ``J_s ŝ_i``) and the wheel weights ``W_s0 exp(-wheel_mu m)`` (Schaub, Vadali &
    Junkins 1998): far from a singular state the wheels rest, near one they give the torque the
    gimbals cannot; each wheel motor gets ``J_s Ω̇``. It replaces the SR inverse (no dither)
    (docs/cmg.md, "VSCMG steering").

    ``unload_gain`` ``k > 0`` (1/s; mode ``"rotation-flying"`` or ``"flying"``) unloads the cluster
    with the thrusters: while on, they apply the base torque ``N_u = -k (H - unload_goal)``
    (``H = Σ h_i ŝ_i``, N·m·s in 𝒥; through the run's thruster limits) and the cluster is steered to
    give ``N - N_u``, so the attitude stays held while ``H`` decays to the goal. It switches on
    when the envelope fraction reaches ``unload_above`` and off when it falls to ``unload_below``,
    at the start of each step (docs/cmg.md, "Momentum unloading"); the applied torque is the
    ``base_wrench`` record.
    """

    _kind: _ClassVar[str] = "cmg_steering"

    quat_ref: Sequence[float]
    kp: float
    kd: float
    lambda0: float = 0.01
    mu: float = 10.0
    rate_gain: float = 50.0
    dither: float = 0.0
    dither_frequency: float = 1.5707963267948966
    null_gain: float = 0.0
    wheel_weight: float = 0.0
    wheel_mu: float = 10.0
    unload_gain: float = 0.0
    unload_above: float = 0.8
    unload_below: float = 0.2
    unload_goal: Sequence[float] = (0.0, 0.0, 0.0)


@_dataclass(frozen=True)
class BaseThrusterControl(_Controller):
    """Base regulation by thrusters in the flying modes, each part only where the mode allows
    it: the system CM position by a force through the CM (``"translation-flying"``,
    ``"flying"``), the base attitude by a torque (``"rotation-flying"``, ``"flying"``).

    Force ``F0 = M (kp_position (com_ref - r_g) - kd_position P / M)`` — the system CM then obeys
    ``e'' + kd e' + kp e = 0`` exactly, whatever the arm does; torque ``N0 = -kp_attitude e -
    kd_attitude w0`` (``e`` as in [`AttitudeControl`][spacearm.control.AttitudeControl]). ``com_ref`` (m, in 𝒥) and
    ``quat_ref`` (``[x, y, z, w]`` or a scipy ``Rotation``) default to the initial CM and attitude. Gains:
    ``kp_position`` (1/s²), ``kd_position`` (1/s), ``kp_attitude`` (N·m/rad), ``kd_attitude``
    (N·m·s/rad). Combine with an arm controller through [`Combined`][spacearm.control.Combined].
    ``orbit``: the run's [`Orbit`][spacearm.Orbit]: hold the attitude relative to its LVLH frame
    (``quat_ref`` base → LVLH, default the initial one relative to LVLH), with the LVLH rate as
    the rate reference (docs/orbit.md).
    """

    _kind: _ClassVar[str] = "base_thrusters"

    com_ref: Any = None
    quat_ref: Any = None
    kp_position: float = 1.0
    kd_position: float = 2.0
    kp_attitude: float = 0.0
    kd_attitude: float = 0.0
    orbit: Any = None


def inertia_scaled_gains(robot, x, joints, natural_frequency: float = 4.0, damping_ratio: float = 1.0):
    """Per-joint PD gains ``(kp, kd)`` for [`JointPD`][spacearm.control.JointPD] or [`ComputedTorque`][spacearm.control.ComputedTorque]-style
    loops, scaled to the inertia each joint drives: ``kp_j = ω² H*_jj``, ``kd_j = 2 ζ ω H*_jj``
    from the diagonal of the generalized inertia ``H*`` (eq. 45) at ``x``, so that each joint
    alone would respond like a mass-spring-damper of natural frequency ``ω`` (rad/s) and damping
    ratio ``ζ``. Scaling keeps a light wrist joint from making the closed loop stiff (a fixed
    ``kd`` over a 0.005 kg·m² wrist gives a pole at ``kd/I``, far beyond what a 1 ms RK4 step
    integrates). ``joints``: indices of the joints to return gains for (N·m/rad, N·m·s/rad)."""
    w, zeta = _number(natural_frequency, "natural_frequency"), _number(damping_ratio, "damping_ratio")
    if not (0 < w < _math.inf and 0 <= zeta < _math.inf):
        raise _ArgumentError(f"inertia_scaled_gains needs a finite natural_frequency > 0 and a finite damping_ratio >= 0, "
                             f"got {w} and {zeta}")
    h = _np.diag(robot.generalized_inertia(x))[list(joints)]
    return w**2 * h, 2.0 * zeta * w * h


@_dataclass(frozen=True)
class Combined(_Controller):
    """An arm controller and a base controller together: the base controller (e.g.
    [`AttitudeControl`][spacearm.control.AttitudeControl]) runs first, then the arm controller, which sees its command."""

    _kind: _ClassVar[str] = "combined"

    arm: Any
    base: Any


@_dataclass(frozen=True)
class CoordinatedFlying(_Controller):
    """Coordinated base-and-arm control in the ``"flying"`` mode: the end effector follows
    ``ee_reference`` while the base holds ``base_pose_ref``.

    Base (acceleration level): ``xdd0_des = [kp_base (r_ref - r0) - kd_base v0; -kp_base e -
    kd_base w0]`` (``e`` the attitude error of [`AttitudeControl`][spacearm.control.AttitudeControl]). End effector:
    ``a_des = pdd_ref + kd_ee (pd_ref - pd) + kp_ee (p_ref - p)``, realized by the joint
    accelerations ``qdd = J^+ (a_des - J_0X xdd0_des - b)`` (``J``: translational joint-side
    point Jacobian of the arm, damped least squares as in [`ResolvedMotionRate`][spacearm.control.ResolvedMotionRate]; ``b``:
    the velocity-product acceleration of the point). Forces: the base wrench ``F_b = H0 xdd0 +
    H0m qdd + c0`` and the joint torques from the flying-regime reduced EOM
    ``tau = H* qdd + c* + H0m^T H0^-1 F_b``.

    Only the **actuated** arm joints are commanded. On a plant with passive joints (zero torque
    there) the law is the collocated partial feedback linearization of docs/flexibility.md: the
    passive accelerations follow from their rows of the equations of motion, and ``J`` becomes
    ``J_A - J_P H_PP^-1 H_PA`` (the passive joints' drift leaves the right-hand side), so the
    end-effector and base errors still obey ``e'' + kd e' + kp e = 0`` with the exact model.

    ``base_pose_ref``: ``(r0, quat [x, y, z, w] or scipy Rotation)``, or ``None`` to hold the initial pose.
    Gains are acceleration-level (1/s², 1/s). ``point``: overrides the reference's point.
    """

    _kind: _ClassVar[str] = "coordinated_flying"

    ee_reference: CartesianLine
    base_pose_ref: Any = None
    kp_ee: float = 100.0
    kd_ee: float = 20.0
    kp_base: float = 25.0
    kd_base: float = 10.0
    point: Any = None
    max_damping: float = _core.DLS_DEFAULTS.max_damping
    threshold: float = _core.DLS_DEFAULTS.threshold


@_dataclass(frozen=True)
class MomentumDamping(_Controller):
    """Damp the system momentum with the base thrusters (flying modes; the detumbling law):
    ``F0 = -P / time_constant`` and ``N0 = -L_G / time_constant - (r0 - r_g) x F0`` (``L_G``
    about the system CM ``r_g``), each limited in norm to ``max_force`` (N) / ``max_torque``
    (N·m). Unsaturated, both momenta decay as ``exp(-t / time_constant)`` whatever the arm does.
    ``model``: the law's model of the plant (e.g. the captured system with an estimated target;
    default the plant). Compose with an arm controller through [`Combined`][spacearm.control.Combined]."""

    _kind: _ClassVar[str] = "momentum_damping"

    time_constant: float
    max_force: float = float("inf")
    max_torque: float = float("inf")
    model: Any = None


@_dataclass(frozen=True)
class MPC(_Controller):
    """Receding-horizon model-predictive control (docs/mpc.md, "The native law"): at every
    sample instant ``k * dt`` the [`spacearm.mpc.Problem`][spacearm.mpc.Problem] ``problem`` is
    solved from the measured state by the core's box-FDDP over ``horizon`` steps of ``dt``
    seconds (absent: the problem's own), warm started from the previous solution shifted by one
    knot, within ``max_iterations`` iterations and ``time_limit`` seconds (``None``: no time
    limit, and the run is deterministic); its first control is held until the next instant.

    The problem's mode must be the run's. Run it with ``integrator="rk4"`` and a step ``dt``
    that divides the law's. Each sample's ``solve_time`` (s), ``solve_iterations``,
    ``solve_cost`` and ``solve_converged`` are in ``traj.records``.
    """

    _kind: _ClassVar[str] = "mpc"

    problem: Any
    horizon: Any = None
    dt: Any = None
    max_iterations: int = 10
    time_limit: Any = None


@_dataclass(frozen=True)
class TorqueLimit(_Controller):
    """Another controller's joint torques clamped to ``±limit`` on every joint (N·m; N for
    prismatic joints), inside the loop (the simulation's own effort limits apply on top)."""

    _kind: _ClassVar[str] = "torque_limit"

    controller: Any
    limit: float


@_dataclass(frozen=True)
class Callback(_Controller):
    """A Python controller ``fn(t, x, u) -> tau`` (length N, every joint including wheels) or
    ``-> (tau, base_wrench)`` (``[F0, N0]`` in 𝒥, applied as the mode allows).

    Called at every integrator stage (four times per RK4 step), so it is far slower than the
    native controllers; an exception it raises stops the run and propagates unchanged. As the
    arm of a [`Combined`][spacearm.control.Combined], its ``tau`` replaces every joint torque, wheels included.
    """

    _kind: _ClassVar[str] = "external"

    fn: Callable


def perturbed_model(
    robot,
    base_mass_scale: float = 1.0,
    base_inertia_scale: float = 1.0,
    link_mass_scale: float = 1.0,
    slosh_fraction: float = 0.0,
    slosh_offset: Sequence[float] = (0.0, 0.0, 0.0),
    slosh_removed: bool = False,
):
    """A copy of ``robot`` with mass-property errors, for a controller's model
    ([`ComputedTorque`][spacearm.control.ComputedTorque] ``model=``).

    The base mass and inertia are scaled by ``base_mass_scale`` and ``base_inertia_scale``;
    every link's mass and inertia by ``link_mass_scale``. Then a fraction ``slosh_fraction``
    (in [0, 1)) of the base mass, taken as a point mass at the base CM (fuel), is moved to
    ``slosh_offset`` (base frame, m) — the base CM shifts by ``slosh_fraction * slosh_offset``
    and the inertia about it changes by the parallel-axis theorem — or, with
    ``slosh_removed=True``, is missing from the model. The joint geometry is unchanged.
    """
    from .model.robot import Robot

    if not isinstance(robot, Robot):
        raise _ArgumentError(f"perturbed_model needs a spacearm.Robot, got {type(robot).__name__}")
    m = _core.perturbed(
        robot.core_model,
        _number(base_mass_scale, "base_mass_scale"),  # the scales' and the fraction's ranges: the core's
        _number(base_inertia_scale, "base_inertia_scale"),  # (control/mismatch.rs)
        _number(link_mass_scale, "link_mass_scale"),
        _number(slosh_fraction, "slosh_fraction"),
        slosh_offset,  # the binding's 3-vector, named in its errors
        bool(slosh_removed),
    )
    return Robot(m)


def perturbed_cmgs(robot, rotor_inertia_scale: float = 1.0, tilts: Optional[Sequence[Sequence[float]]] = None):
    """A copy of ``robot`` whose control-moment gyros ([`Robot.cmg_dofs`][spacearm.Robot.cmg_dofs], docs/cmg.md) differ
    from the nominal ones: every rotor's inertia tensor scaled by ``rotor_inertia_scale`` (``J_s``
    and ``J_t`` together), and CMG ``i``'s whole unit — gimbal axis, spin axis and both bodies —
    turned about its gimbal joint by the rotation vector ``tilts[i]`` (parent frame, rad; one per
    CMG in ``cmg_dofs`` order, or ``None``): a mounting misalignment. The core's
    ``control/mismatch.rs::perturbed_cmgs``; everything else is the model's."""
    from .model.robot import Robot

    if not isinstance(robot, Robot):
        raise _ArgumentError(f"perturbed_cmgs needs a spacearm.Robot, got {type(robot).__name__}")
    rows = [] if tilts is None else [[float(v) for v in _vector(t, f"tilts[{i}]", 3)] for i, t in enumerate(tilts)]
    return Robot(_core.perturbed_cmgs(robot.core_model, _number(rotor_inertia_scale, "rotor_inertia_scale"), rows))
