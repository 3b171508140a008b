"""Type stub of the private extension ``spacearm._core`` (PyO3). Users call
:class:`spacearm.Robot`, which wraps :class:`Model`; this stub documents the boundary."""

from typing import Any, Callable, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

Vec = npt.NDArray[np.float64]
#: Inputs accept any array-like; a contiguous float64 1-D array is used without a copy.
ArrayLike = Any
Wrench = tuple[int, Sequence[float], Sequence[float], Sequence[float]]

__version__: str

def preset(name: str, allow_nonphysical_inertia: bool = ...) -> Model: ...
def model_from_toml(text: str, source: str, allow_nonphysical_inertia: bool = ...) -> Model: ...
def model_to_toml(model: Model) -> str: ...
def model_from_classic_dh(
    name: str,
    base_name: str,
    base_mass: float,
    base_inertia: Sequence[Sequence[float]],
    rows: Sequence[tuple],
    joint1_origin: Sequence[float],
    joint1_rotation: Sequence[float],
    tool_offset: Sequence[float],
    tip_point: Optional[str],
    initial_q: Optional[Sequence[float]] = None,
) -> Model: ...
def model_from_paper_dh(
    name: str,
    base_name: str,
    base_mass: float,
    base_inertia: Sequence[Sequence[float]],
    rows: Sequence[tuple],
    joint1_origin: Sequence[float],
    joint1_rotation: Sequence[float],
    tool_offset: Sequence[float],
    tip_point: Optional[str],
    initial_q: Optional[Sequence[float]] = None,
) -> Model: ...

class ModelBuilder:
    def __init__(self, name: str, base_name: str, base_mass: float, base_inertia: Sequence[Sequence[float]],
                 allow_nonphysical_inertia: bool = ...) -> None: ...
    def add_link(
        self,
        name: str,
        parent: str,
        joint_type: str,
        origin: Sequence[float],
        rotation: Sequence[float],
        axis: Sequence[float],
        com: Sequence[float],
        mass: float,
        inertia: Sequence[Sequence[float]],
        joint_name: Optional[str] = None,
        limits: Optional[Sequence[float]] = None,
    ) -> None: ...
    def add_point(self, name: str, body: str, offset: Sequence[float]) -> None: ...
    def set_end_effector(self, name: str) -> None: ...
    def set_initial_q(self, q: Sequence[float]) -> None: ...
    def build(self) -> Model: ...

# ---- the model's description (crates/spacearm-py/src/description_py.rs) ---------------------
# Frozen snapshots; every array attribute is a new array at each access. Frames and units:
# docs/conventions.md ("A model's frames, concretely").

class BaseInfo:
    """The spacecraft base (body 0); its frame has its origin at the base CM."""

    name: str
    mass: float  # kg
    inertia: Vec  # (3, 3) kg·m², about the base CM in base-frame axes

class JointLimitsInfo:
    """A joint's limits; absent bounds are infinite."""

    lower: float  # rad or m; -inf when unbounded
    upper: float  # rad or m; inf when unbounded
    velocity: float  # rad/s or m/s; inf when unbounded
    effort: float  # N·m or N; inf when unbounded

class LinkInfo:
    """One link (the k-th is body k + 1) and the joint to its parent; its frame has its origin at its CM."""

    name: str
    parent: str  # the parent body's name
    parent_index: int  # the parent body's index (0 = base)
    joint: str
    type: str  # "revolute", "prismatic" or "fixed"
    origin: Vec  # (3,) m, joint position in the parent frame, from the parent's CM
    rotation: Vec  # (4,) [x, y, z, w], link frame in the parent frame at q = 0
    axis: Vec  # (3,) unit joint axis in the link frame
    com: Vec  # (3,) m, the link's CM from its joint, in the link frame
    mass: float  # kg
    inertia: Vec  # (3, 3) kg·m², about the link's CM in link-frame axes
    limits: JointLimitsInfo
    dof: Optional[int]  # index in q; None for a fixed joint

class PointInfo:
    """A named point fixed to a body."""

    name: str
    body: str  # the carrying body's name
    body_index: int  # the carrying body's index (0 = base)
    offset: Vec  # (3,) m, from the body's CM in the body frame

class ModelInfo:
    """What Model.describe() returns: the whole model as the core holds it."""

    name: str
    base: BaseInfo
    links: tuple[LinkInfo, ...]  # tree order: link k is body k + 1
    points: tuple[PointInfo, ...]
    end_effector: Optional[str]
    initial_q: Vec  # (N,) rad or m per joint type

class Model:
    name: str
    n_dof: int
    n_bodies: int
    total_mass: float
    allows_nonphysical_inertia: bool
    inertia_warnings: list[str]
    body_names: list[str]
    point_names: list[str]
    end_effector: Optional[str]
    initial_q: Vec
    body_of_dof: list[int]
    def body_index(self, name: str) -> int: ...
    def point(self, name: str) -> tuple[int, list[float]]: ...
    def describe(self) -> ModelInfo: ...
    def joint_types(self) -> list[str]: ...
    # Every method below takes one state (1-D arrays) or a batch (a 2-D x, one state per row;
    # the other vectors with as many rows or one row for all) and then returns its results with
    # a leading axis of length B (crates/spacearm-py/src/batch.rs).
    def __reduce__(self) -> tuple: ...
    def check_configuration(self, x: ArrayLike) -> None: ...
    # The per-state methods return arrays (a tuple of them where named below), the fastest form for
    # the one-state path and the batch axis alike; the public Robot methods wrap them in NamedTuples.
    def forward_kinematics(self, x: ArrayLike) -> tuple[Vec, Vec, Vec, Vec]: ...  # (body_to_world (nb,3,3), com_in_world (nb,3), joint_position_in_world (nb,3), joint_axis_in_world (nb,3))
    def point_position(self, x: ArrayLike, body: int, offset: Vec) -> Vec: ...
    def point_jacobians(self, x: ArrayLike, body: int, offset: Vec) -> tuple[Vec, Vec]: ...
    def link_jacobians(self, x: ArrayLike, body: int) -> tuple[Vec, Vec]: ...
    def inertia_blocks(self, x: ArrayLike) -> tuple: ...  # (M, r_0g, H_S, J_TS, H_Sq, H0, H0m, Hm, H): spacearm.InertiaBlocks
    def mass_matrix_crba(self, x: ArrayLike) -> Vec: ...
    def mass_matrix_paper(self, x: ArrayLike) -> Vec: ...
    def base_inertia_inverse(self, x: ArrayLike) -> Vec: ...
    def bias_forces(self, x: ArrayLike, u: ArrayLike) -> Vec: ...
    def inverse_dynamics(self, x: ArrayLike, u: ArrayLike, du: ArrayLike, wrenches: Optional[list[Wrench]] = None) -> Vec: ...
    def forward_dynamics(self, x: ArrayLike, u: ArrayLike, f: ArrayLike, wrenches: Optional[list[Wrench]], method: str) -> Vec: ...
    def forward_dynamics_tau(self, x: ArrayLike, u: ArrayLike, tau: Optional[ArrayLike], base_wrench: Optional[ArrayLike], wrenches: Optional[list[Wrench]], method: str) -> Vec: ...
    def generalized_inertia(self, x: ArrayLike) -> Vec: ...
    def generalized_bias(self, x: ArrayLike, u: ArrayLike) -> Vec: ...
    def generalized_jacobian(self, x: ArrayLike, body: int, offset: Vec) -> Vec: ...
    def point_twist(self, x: ArrayLike, qd: ArrayLike, body: int, offset: Vec, linear: ArrayLike, angular_origin: ArrayLike) -> Vec: ...
    def momentum_twist(self, x: ArrayLike, body: int, offset: Vec, linear: ArrayLike, angular_origin: ArrayLike) -> Vec: ...
    def base_velocity_from_momentum(self, x: ArrayLike, qd: ArrayLike, linear: ArrayLike, angular_origin: ArrayLike) -> Vec: ...
    def momentum(self, x: ArrayLike, u: ArrayLike) -> tuple[Vec, Vec, Vec, Vec]: ...  # (P, L_origin, L_base, L_com), each (3,) in 𝒥
    def kinetic_energy(self, x: ArrayLike, u: ArrayLike) -> Union[float, Vec]: ...
    def center_of_mass(self, x: ArrayLike) -> Vec: ...

# ---- the core's rules and defaults (crates/spacearm-py/src/rules_py.rs, rule_tables_py.rs) -----
# The tables are frozen instances with typed attributes; each is also a read-only mapping of its
# field names (keys(), t[name], dict(t), **t, == a dict).

class SimDefaults:
    """The simulation defaults (SimOptions::default())."""

    mode: str  # one of MODES
    integrator: str  # one of INTEGRATORS
    dt: float  # s: the RK4 step, the DOPRI5 output interval
    rtol: float  # DOPRI5 relative tolerance
    atol: float  # DOPRI5 absolute tolerance
    record_every: int  # RK4: keep every k-th step
    joint_limits: bool  # whether the joints' effort and velocity limits apply
    max_steps: int  # largest number of attempted DOPRI5 steps
    def keys(self) -> list[str]: ...
    def __getitem__(self, key: str) -> Any: ...

class ModelBounds:
    """The physical bounds of every model (docs/model-format.md, rules 10-11)."""

    min_mass: float  # kg, smallest non-zero body mass
    max_mass: float  # kg
    max_length: float  # m, largest |component| of a joint origin, CM or point offset
    max_inertia_entry: float  # kg·m², largest |inertia entry|
    def keys(self) -> list[str]: ...
    def __getitem__(self, key: str) -> float: ...

class DlsDefaults:
    """The default damped-least-squares law (math/dls.rs)."""

    threshold: float  # ε, size of the singular region (units of σ)
    max_damping: float  # λ_max, damping at the singularity (units of σ)
    def keys(self) -> list[str]: ...
    def __getitem__(self, key: str) -> float: ...

MODES: list[str]
INTEGRATORS: list[str]
SIM_DEFAULTS: SimDefaults
MODEL_BOUNDS: ModelBounds
DLS_DEFAULTS: DlsDefaults
QUATERNION_TOLERANCE: float
MEMORY_LIMIT_BYTES: int
def quintic_scaling(t: Vec, t_start: float, t_end: float) -> tuple[Vec, Vec, Vec]: ...
def body_mass_properties_error(
    who: str, mass: float, inertia: Sequence[Sequence[float]], *, triangle_inequality: bool = True
) -> Optional[tuple[str, str]]: ...  # None, or ("mass" | "inertia", the core's message naming `who`)

def set_batch_threads(threads: Optional[int] = None) -> None: ...
def batch_threads() -> int: ...

# ---- analysis (crates/spacearm-py/src/analysis_py.rs; results: analysis_results_py.rs) ------------
# The results are frozen classes named after the core's types (spacearm_core::analysis); every
# array attribute hands out the same numpy array on each read. Task Jacobians: rows are the task
# rows of the point twist [v; w] in the inertial frame, columns the joint rates.
class JacobianMeasures:
    """Singular-value measures of one task Jacobian (m task rows, N joints)."""

    @property
    def jacobian(self) -> Vec: ...  # (m, N)
    @property
    def singular_values(self) -> Vec: ...  # (min(m, N),), decreasing
    @property
    def condition(self) -> float: ...  # sigma_max / sigma_min (inf at a singularity)
    @property
    def manipulability(self) -> float: ...  # product of the singular values
    @property
    def task_directions(self) -> Vec: ...  # (m, min(m, N)) left singular vectors; the last is the worst
    @property
    def joint_directions(self) -> Vec: ...  # (N, N) right singular vectors; beyond the rank: null space

class SingularityAnalysis:
    """The task rows of J* (free-floating, eq. 110) and of J_m (base fixed, eq. 106) at one configuration."""

    @property
    def generalized(self) -> JacobianMeasures: ...
    @property
    def fixed_base(self) -> JacobianMeasures: ...

class Detection:
    """What the singularity detector tells a resolved-motion-rate controller."""

    @property
    def sigma_min(self) -> float: ...
    @property
    def condition(self) -> float: ...
    @property
    def damping(self) -> float: ...  # recommended lambda of the DLS inverse
    @property
    def near_singular(self) -> bool: ...  # sigma_min < threshold

class ScanResult:
    """A joint-space scan of M samples: one entry per sample in each column."""

    @property
    def sigma_min_generalized(self) -> Vec: ...  # (M,)
    @property
    def sigma_max_generalized(self) -> Vec: ...  # (M,)
    @property
    def manipulability_generalized(self) -> Vec: ...  # (M,)
    @property
    def det_generalized(self) -> Vec: ...  # (M,), NaN unless the task is square
    @property
    def sigma_min_fixed(self) -> Vec: ...  # (M,)
    @property
    def manipulability_fixed(self) -> Vec: ...  # (M,)
    @property
    def det_fixed(self) -> Vec: ...  # (M,), NaN unless the task is square
    @property
    def point_from_base(self) -> Vec: ...  # (M, 3) m, base frame
    @property
    def point_from_com(self) -> Vec: ...  # (M, 3) m, base frame

class WorkspaceShells:
    """Radial description of the workspaces, m."""

    @property
    def reachable(self) -> tuple[float, float]: ...  # (R_min, R_max) about the system CM
    @property
    def fixed_base(self) -> tuple[float, float]: ...  # (min, max) from the base CM, base fixed
    @property
    def singular_radii(self) -> Vec: ...  # (K,), sorted
    @property
    def path_dependent(self) -> list[tuple[float, float]]: ...
    @property
    def path_independent(self) -> list[tuple[float, float]]: ...
    @property
    def radial_resolution(self) -> float: ...

class ReactionNullSpace:
    """The reaction null space at one configuration (N joints)."""

    @property
    def base_motion_map(self) -> Vec: ...  # (3, N) angular or (6, N) full rows of -H0^-1 H0m
    @property
    def singular_values(self) -> Vec: ...  # decreasing
    @property
    def rank(self) -> int: ...
    @property
    def basis(self) -> Vec: ...  # (N, N - rank), orthonormal
    @property
    def projector(self) -> Vec: ...  # (N, N)

class RmrcRates:
    """One evaluation of the resolved-motion-rate law."""

    @property
    def qd(self) -> Vec: ...  # (N,)
    @property
    def sigma_min(self) -> float: ...
    @property
    def damping(self) -> float: ...
    @property
    def base_angular_velocity(self) -> Vec: ...  # (3,) rad/s, inertial frame

class RmrcMotion:
    """A closed-loop point-to-point motion at its K+1 time nodes."""

    @property
    def times(self) -> Vec: ...  # (K+1,) s
    @property
    def x(self) -> Vec: ...  # (K+1, 7+N)
    @property
    def qd(self) -> Vec: ...  # (K+1, N)
    @property
    def point_position(self) -> Vec: ...  # (K+1, 3) m, inertial frame
    @property
    def sigma_min(self) -> Vec: ...  # (K+1,)
    @property
    def damping(self) -> Vec: ...  # (K+1,)
    @property
    def attitude_change(self) -> Vec: ...  # (K+1,) rad
    @property
    def final_position_error(self) -> float: ...  # m

def analysis_singularity(m: Model, x: ArrayLike, body: int, offset: Vec, rows: list[int]) -> SingularityAnalysis: ...
def analysis_detect(m: Model, x: ArrayLike, body: int, offset: Vec, rows: list[int], threshold: float, max_damping: float) -> Detection: ...
def analysis_damping(sigma_min: float, threshold: float, max_damping: float) -> float: ...
def analysis_joint_grid(lower: Sequence[float], upper: Sequence[float], resolution: int) -> Vec: ...
def analysis_scan(m: Model, samples: Vec, body: int, offset: Vec, rows: list[int]) -> ScanResult: ...
def analysis_shells(sigma_min_generalized: Sequence[float], det_generalized: Sequence[float], point_from_com: Vec, point_from_base: Vec, singular_threshold: float, radial_resolution: float, grid: Optional[tuple[int, int]] = None) -> WorkspaceShells: ...
def analysis_reaction_null_space(m: Model, x: ArrayLike, which: str, tolerance: float) -> ReactionNullSpace: ...
def analysis_integrate_prescribed(m: Model, x0: ArrayLike, dt: float, q_half: Vec, qd_half: Vec, linear_momentum: Vec, angular_momentum: Vec) -> Vec: ...
class RmrcOptions:
    """The options of the resolved-motion-rate law, keyword-only, checked when built."""
    def __init__(self, *, rows: list[int], threshold: float, max_damping: float, gain: float = 0.0, strategy: str = "naive",
                 manipulability_gain: float = 0.0, joint_limit_gain: float = 0.0) -> None: ...
def analysis_rmrc_rates(m: Model, x: ArrayLike, body: int, offset: Vec, desired_twist: Vec, options: RmrcOptions) -> RmrcRates: ...
def analysis_move_to(m: Model, x0: ArrayLike, body: int, offset: Vec, target: Vec, duration: float, settle: float, dt: float, options: RmrcOptions) -> RmrcMotion: ...
# ---- simulation inputs (crates/spacearm-py/src/sim_options_py.rs, controller_spec_py.rs) ------
# Frozen, keyword-only; checked when built; an unknown keyword is an ArgumentError.
class ThrusterLimits:
    """Base thruster limits per axis of the inertial frame (> 0; inf: no limit)."""
    def __init__(self, *, max_force: ArrayLike, max_torque: ArrayLike) -> None: ...
    @property
    def max_force(self) -> Vec:
        """Shape (3,), N."""
    @property
    def max_torque(self) -> Vec:
        """Shape (3,), N·m."""

class RunOptions:
    """The options of simulate, rollout and Simulator; a keyword left out or None keeps the
    core's default (SIM_DEFAULTS)."""
    def __init__(
        self,
        *,
        mode: Optional[str] = None,
        integrator: Optional[str] = None,
        dt: Optional[float] = None,
        rtol: Optional[float] = None,
        atol: Optional[float] = None,
        record_every: Optional[int] = None,
        wheels: Optional[Sequence[int]] = None,
        thrusters: Optional[ThrusterLimits] = None,
        joint_limits: Optional[bool] = None,
        max_steps: Optional[int] = None,
        progress: Optional[Callable[[float], Any]] = None,
        record_dtype: Optional[str] = None,
    ) -> None: ...
    @property
    def mode(self) -> str: ...
    @property
    def integrator(self) -> str: ...
    @property
    def dt(self) -> float:
        """s (RK4 step; DOPRI5 output interval)."""
    @property
    def rtol(self) -> float: ...
    @property
    def atol(self) -> float: ...
    @property
    def record_every(self) -> int: ...
    @property
    def wheels(self) -> Optional[list[int]]:
        """Reaction-wheel dofs; None: those the model's structure shows."""
    @property
    def thrusters(self) -> Optional[ThrusterLimits]: ...
    @property
    def joint_limits(self) -> bool: ...
    @property
    def max_steps(self) -> int: ...
    @property
    def progress(self) -> Optional[Callable[[float], Any]]: ...
    @property
    def record_dtype(self) -> str:
        """"float64" or "float32"."""

class JointReference:
    """A joint-space reference of the arm joints: a rest-to-rest quintic or a constant."""
    @staticmethod
    def quintic(*, q_start: ArrayLike, q_goal: ArrayLike, t_start: float, t_end: float) -> JointReference: ...
    @staticmethod
    def constant(*, q: ArrayLike) -> JointReference: ...
    @property
    def kind(self) -> str:
        """"quintic" or "constant"."""
    @property
    def q_start(self) -> Vec:
        """Shape (n,), rad or m (a constant's set point)."""
    @property
    def q_goal(self) -> Vec:
        """Shape (n,), rad or m (a constant's set point)."""
    @property
    def t_start(self) -> Optional[float]:
        """s; None for a constant."""
    @property
    def t_end(self) -> Optional[float]:
        """s; None for a constant."""

class CartesianReference:
    """A straight line of a point in the inertial frame with quintic timing."""
    def __init__(self, *, p_start: ArrayLike, p_goal: ArrayLike, t_start: float, t_end: float) -> None: ...
    @property
    def p_start(self) -> Vec:
        """Shape (3,), m, inertial frame."""
    @property
    def p_goal(self) -> Vec:
        """Shape (3,), m, inertial frame."""
    @property
    def t_start(self) -> float: ...
    @property
    def t_end(self) -> float: ...

class ZeroTorqueSpec:
    """No control: zero joint torques, no base wrench."""
    def __init__(self) -> None: ...

class JointPdSpec:
    """Joint PD on the arm joints."""
    def __init__(self, *, kp: Sequence[float], kd: Sequence[float], reference: JointReference) -> None: ...
    kp: list[float]  # N·m/rad, one or one per arm joint (read-only)
    kd: list[float]  # N·m·s/rad (read-only)
    @property
    def reference(self) -> JointReference: ...

class ComputedTorqueSpec:
    """Computed torque on the reduced equations of motion (paper eqs. 112-115)."""
    def __init__(self, *, kp: Sequence[float], kd: Sequence[float], reference: JointReference, model: Optional[Model] = None) -> None: ...
    kp: list[float]  # 1/s², one or one per arm joint (read-only)
    kd: list[float]  # 1/s (read-only)
    @property
    def reference(self) -> JointReference: ...
    @property
    def has_model(self) -> bool:
        """Whether the controller has a model of its own (else the plant's)."""

class RmrcSpec:
    """Resolved-motion-rate control of a point through J* (paper eq. 110), damped least squares."""
    def __init__(self, *, reference: CartesianReference, gain: float, max_damping: float, threshold: float, velocity_gain: float,
                 body: int, offset: ArrayLike) -> None: ...
    gain: float  # 1/s (read-only)
    max_damping: float  # m, the largest damping λ_max (read-only)
    threshold: float  # m (read-only)
    velocity_gain: float  # 1/s (read-only)
    body: int  # (read-only)
    @property
    def reference(self) -> CartesianReference: ...
    @property
    def offset(self) -> Vec:
        """Shape (3,), m, in the body's frame."""

class CoordinatedFlyingSpec:
    """Coordinated base-and-arm control in the flying mode."""
    def __init__(self, *, reference: CartesianReference, body: int, offset: ArrayLike, kp_ee: float, kd_ee: float, kp_base: float,
                 kd_base: float, max_damping: float, threshold: float, base_position: Optional[ArrayLike] = None,
                 base_quat: Optional[ArrayLike] = None) -> None: ...
    body: int  # (read-only)
    max_damping: float  # m, the largest damping λ_max (read-only)
    threshold: float  # m (read-only)
    @property
    def reference(self) -> CartesianReference: ...
    @property
    def offset(self) -> Vec:
        """Shape (3,), m, in the body's frame."""
    @property
    def base_position(self) -> Optional[Vec]:
        """Shape (3,), m, inertial frame; None: the initial one."""
    @property
    def base_quat(self) -> Optional[Vec]:
        """Shape (4,), [x, y, z, w]; None: the initial one."""
    @property
    def kp_ee(self) -> float: ...
    @property
    def kd_ee(self) -> float: ...
    @property
    def kp_base(self) -> float: ...
    @property
    def kd_base(self) -> float: ...

class BaseThrustersSpec:
    """Base regulation by thrusters (system CM position, base attitude)."""
    def __init__(self, *, kp_position: float, kd_position: float, kp_attitude: float, kd_attitude: float,
                 com_ref: Optional[ArrayLike] = None, quat_ref: Optional[ArrayLike] = None) -> None: ...
    kp_position: float  # 1/s² (read-only)
    kd_position: float  # 1/s (read-only)
    kp_attitude: float  # N·m/rad (read-only)
    kd_attitude: float  # N·m·s/rad (read-only)
    @property
    def com_ref(self) -> Optional[Vec]:
        """Shape (3,), m, inertial frame; None: the initial CM."""
    @property
    def quat_ref(self) -> Optional[Vec]:
        """Shape (4,), [x, y, z, w]; None: the initial attitude."""

class AttitudeSpec:
    """Base attitude control with reaction wheels."""
    def __init__(self, *, quat_ref: ArrayLike, kp: float, kd: float) -> None: ...
    kp: float  # N·m/rad (read-only)
    kd: float  # N·m·s/rad (read-only)
    @property
    def quat_ref(self) -> Vec:
        """Shape (4,), [x, y, z, w]."""

ControllerSpec = Union[ZeroTorqueSpec, JointPdSpec, ComputedTorqueSpec, RmrcSpec, CoordinatedFlyingSpec, BaseThrustersSpec, AttitudeSpec,
                       "CombinedSpec", "CallbackSpec"]

class CombinedSpec:
    """An arm controller and a base controller; the base runs first."""
    def __init__(self, *, arm: ControllerSpec, base: ControllerSpec) -> None: ...
    arm: ControllerSpec  # (read-only)
    base: ControllerSpec  # (read-only)

class CallbackSpec:
    """A Python controller fn(t, x, u) -> tau or (tau, base_wrench), called at every stage."""
    def __init__(self, *, fn: Callable[[float, Vec, Vec], Any]) -> None: ...
    fn: Callable[[float, Vec, Vec], Any]  # (read-only)

# ---- simulation (crates/spacearm-py/src/simulate_py.rs) --------------------------------------
# ---- results of a run (crates/spacearm-py/src/records_py.rs) ------------------------------------
#: A recorded array: float64, or float32 when the run asked for it (``t`` is always float64).
Record = npt.NDArray[Any]

class RunRecords:
    """The recorded samples of a run, one row per sample: ``(K, ...)`` for one run, ``(B, K, ...)``
    in a :class:`RolloutBatch`. Vectors in the inertial frame, SI units. ``t``, ``x``, ``u`` are
    always there; a record the run did not make is ``None``; ``fields`` names those it made."""
    @property
    def fields(self) -> tuple[str, ...]: ...
    t: Record                              # (K,) sample times, s (float64)
    x: Record                              # (K, 7+N) [r0, quat0 (x, y, z, w), q]
    u: Record                              # (K, 6+N) [v0, w0, qd]
    du: Optional[Record]                   # (K, 6+N) accelerations
    tau: Optional[Record]                  # (K, N) applied joint torques, N·m (N prismatic)
    tau_cmd: Optional[Record]              # (K, N) commanded joint torques, before the limits
    base_wrench: Optional[Record]          # (K, 6) applied [F0, N0] at the base CM, N, N·m
    P: Optional[Record]                    # (K, 3) linear momentum, kg·m/s
    L_origin: Optional[Record]             # (K, 3) angular momentum about the origin, kg·m²/s
    L_com: Optional[Record]                # (K, 3) angular momentum about the system CM, kg·m²/s
    energy: Optional[Record]               # (K,) kinetic energy, J
    com: Optional[Record]                  # (K, 3) system CM, m
    ee_position: Optional[Record]          # (K, 3) end-effector position, m (robots with an end effector)
    ee_quat: Optional[Record]              # (K, 4) end-effector attitude [x, y, z, w]
    reference: Optional[Record]            # (K, R) the controller's reference
    tracking_error: Optional[Record]       # (K,) |reference − actual|, rad or m (RunMeta.tracking_error_kind)
    attitude_error: Optional[Record]       # (K,) base attitude error of an attitude controller, rad
    wheel_speed: Optional[Record]          # (K, W) reaction-wheel speeds, rad/s (RunMeta.wheel_dofs)

class RunEvents:
    """The saturation onsets of a run (E events, in time order)."""
    saturation_t: npt.NDArray[np.float64]        # (E,) start of the step in which it began, s
    saturation_actuator: npt.NDArray[np.int64]   # (E,) dof 0..N, then thruster channels N..N+6
    saturation_kind: npt.NDArray[np.int64]       # (E,) 0 joint torque, 1 joint speed, 2 thruster

class ConservedDrift:
    """The drift of one quantity the run's mode conserves."""
    quantity: str    # "P", "L_origin", "L_com" or "energy"
    drift: float     # largest deviation from the initial value / max(|initial|, scale)
    scale: float     # the magnitude the drift is measured against (the quantity's unit)

class RunMeta:
    """The description of a run."""
    mode: str
    integrator: str
    dt: float
    rtol: float
    atol: float
    controller: str
    drift: list[ConservedDrift]            # one per conserved quantity, in the mode's order
    n_steps: int
    n_rejected: int
    n_rhs_evals: int
    actuator_names: list[str]              # the name of each RunEvents.saturation_actuator index
    wheel_dofs: list[int]
    tracking_error_kind: Optional[str]
    record_every: int
    record_dtype: str                      # "float64" or "float32"
    joint_limits: bool
    dropped_base_wrench_max_norm: float    # largest commanded base-wrench part the mode dropped
    dropped_base_wrench_count: int         # evaluations that commanded one

class RunResult:
    """One run (what :func:`simulate` and :meth:`Simulator.result` return)."""
    records: RunRecords
    events: RunEvents
    meta: RunMeta

class RolloutBatch:
    """B rollouts (what :func:`rollout` returns); a failed rollout has NaN rows and ``None``
    meta and events."""
    records: RunRecords                    # (B, K, ...); only t, x, u when every rollout failed
    ok: npt.NDArray[np.bool_]              # (B,)
    reason: list[Optional[str]]            # the error message of each failed rollout
    error_class: list[Optional[str]]       # its spacearm.errors class name
    meta: list[Optional[RunMeta]]
    events: list[Optional[RunEvents]]

def simulate(
    model: Model,
    x0: ArrayLike,
    u0: ArrayLike,
    duration: float,
    options: RunOptions,
    controller_spec: Optional[ControllerSpec] = None,
) -> RunResult:
    """Run the native simulation loop (None: no control). Runs without the GIL; the records are
    handed to numpy without a copy. Returns the records, saturation onsets and description of the run."""
    ...

def rollout(
    models: list[Model],
    x0: Vec,
    u0: Vec,
    duration: float,
    options: RunOptions,
    controllers: Optional[Union[ControllerSpec, list[ControllerSpec]]] = None,
    threads: Optional[int] = None,
) -> RolloutBatch:
    """Run B rollouts on native threads without the GIL (crates/spacearm-py/src/rollout_py.rs).
    ``models``: one model or one per rollout; ``x0`` (B, 7+N), ``u0`` (B, 6+N) float64;
    ``options`` as for :func:`simulate` (``progress`` ignored); ``controllers``: one spec (a
    controller built per rollout) or a list of B. Returns the records with a leading B axis (NaN rows for
    a failed rollout) and each rollout's status, description and saturation onsets."""
    ...

class Simulator:
    """RK4 stepping of a plant from Python (crates/spacearm-py/src/simulator_py.rs)."""

    def __init__(self, model: Model, options: RunOptions, controller_spec: Optional[ControllerSpec] = None, record_every: Optional[int] = None) -> None: ...
    def reset(self, x0: ArrayLike, u0: ArrayLike) -> None: ...
    def step(self, tau: Optional[ArrayLike] = None, n: int = 1, base_wrench: Optional[ArrayLike] = None) -> None: ...
    @property
    def time(self) -> float: ...
    @property
    def state(self) -> Vec: ...
    @property
    def n_steps(self) -> int: ...
    def result(self) -> RunResult: ...

def perturbed(
    model: Model,
    base_mass_scale: float,
    base_inertia_scale: float,
    link_mass_scale: float,
    slosh_fraction: float,
    slosh_offset: ArrayLike,
    slosh_removed: bool,
) -> Model: ...
def default_wheel_dofs(model: Model) -> list[int]: ...
class Derivatives:
    """Exact derivatives of one model (analytic recursions for the dynamics Jacobians,
    forward-mode dual numbers for the others, and for ``dual=True``); tensors of partials have
    the derivative index last. Tangent coordinates ``[dr0, dtheta, dq]``."""

    def __init__(self, model: Model) -> None: ...
    def mass_matrix_partials(self, x: ArrayLike) -> npt.NDArray[np.float64]: ...
    def mass_matrix_derivative(self, x: ArrayLike, u: ArrayLike) -> Vec: ...
    def generalized_inertia_partials(self, x: ArrayLike) -> npt.NDArray[np.float64]: ...
    def generalized_inertia_derivative(self, x: ArrayLike, u: ArrayLike) -> Vec: ...
    def generalized_jacobian_partials(self, x: ArrayLike, body: int, offset: ArrayLike) -> npt.NDArray[np.float64]: ...
    def generalized_jacobian_derivative(self, x: ArrayLike, u: ArrayLike, body: int, offset: ArrayLike) -> Vec: ...
    def forward_dynamics_derivatives(
        self, x: ArrayLike, u: ArrayLike, f: ArrayLike, wrenches: Optional[list[Wrench]] = None, dual: bool = False
    ) -> tuple[Vec, Vec, Vec]: ...
    def inverse_dynamics_partials(
        self, x: ArrayLike, u: ArrayLike, du: ArrayLike, wrenches: Optional[list[Wrench]] = None, dual: bool = False
    ) -> tuple[Vec, Vec]: ...
    def linearize(self, x: ArrayLike, u: ArrayLike, f: ArrayLike, joints_only: bool, dual: bool = False) -> tuple[Vec, Vec]: ...
