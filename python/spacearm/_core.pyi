"""Type stub of the private extension ``spacearm._core`` (PyO3). Users call
[`spacearm.Robot`][spacearm.Robot], which wraps ``Model``; this stub documents the boundary."""

from typing import Any, Callable, Optional, Sequence, Union, final

import numpy as np
import numpy.typing as npt
from typing_extensions import disjoint_base

_Vec = npt.NDArray[np.float64]
#: Inputs accept any array-like; a contiguous float64 1-D array is used without a copy.
_ArrayLike = Any
_Wrench = tuple[int, Sequence[float], Sequence[float], Sequence[float]]

__version__: str
__all__ = [
    "ArgumentError", "CentralBody", "Orbit", "OrbitalElements", "BaseDescription", "ControllerSpec", "CONTROLLER_KINDS", "CONTROLLER_ALIASES", "TASKS", "check_spec", "mpc_solve", "controller_kind",
    "ClosedChainResult", "ConservedDrift", "Contact", "contacts", "RigidImpact", "rigid_impact", "GraspOutcome", "grasp_outcome", "success_rate",
    "DLS_DEFAULTS", "Derivatives", "Detection", "DlsDefaults",
    "FreeBodyReference", "GraspImpulse", "INTEGRATORS", "ImpulseDynamics", "JacobianMeasures", "JointLimits", "JointReference",
    "LoopClosureTerms", 
    "LinkDescription", "MEMORY_LIMIT_BYTES", "MODEL_BOUNDS", "MODES", "Model", "ModelBounds", "MomentumSplit",
    "ModelBuilder", "ModelDescription", "ModelError", "ModelFileError", "NonFiniteError",
    "NotFoundError", "PASSIVE_TREATMENTS", "CONTROLLER_LABELS", "PointDescription", "GeometryDescription", "QUATERNION_TOLERANCE", "QuaternionError",
    "ReactionNullSpace", "ResourceLimitError", "RmrcMotion", "RmrcOptions", "RmrcRates",
    "RolloutBatch", "RunEvents", "RunMeta", "RunOptions", "RunRecords", "RunResult",
    "SIM_DEFAULTS", "ScanResult", "ShapeError", "SimDefaults", "SimulationError", "Simulator", "BatchSimulator",
    "SingularError", "SingularityReport", "SoftCaptureResult", "SpacearmError", "SpacearmTypeError", "Tape",
    "ThrusterLimits", "WorkspaceShells", "__version__", "analysis_damping",
    "analysis_detect", "analysis_integrate_prescribed", "analysis_joint_grid",
    "analysis_reach", "analysis_cmg_envelope", "analysis_cmg_singular_surfaces", "analysis_reaction_null_space", "analysis_rmrc_rates", "analysis_scan",
    "analysis_singularity", "batch_threads", "body_mass_properties_error", "box_of_moments", "check_grasp_handle", "GOAL_TOLERANCE", "MAX_HANDLE_RATIO",
    "conserved_drift", "default_wheel_dofs", "grasp_impact", "impulse_dynamics", "impulse_momentum_split", "joint_wrenches", "loop_closure", "model_from_dh", "model_from_toml",
    "model_to_toml", "perturbed", "perturbed_cmgs", "point_inverse_inertia", "preset", "quat_exp", "quat_from_matrix", "quat_from_rpy",
    "quat_log", "quat_multiply", "quat_to_matrix", "quintic_scaling", "rollout", "rotation_vector",
    "set_batch_threads", "simulate", "simulate_closed_chain", "skew", "slosh_links", "panel_parts", "beam_parts", "compliant_parts", "cmg_parts", "cmgs", "gripper_parts", "docking_parts", "grippers", "cmg_velocity",
    "cylinder_slosh", "sphere_slosh", "sphere_fill_height", "cylinder_fill_height", "model_attach_body", "model_attach_model",
    "model_remove_subtree", "InputShaper", "soft_capture", "virtual_mass",
    "CaptureRun", "run_capture", "check_capture", "MAX_CAPTURE_SAMPLES", "MAX_TURN_PER_SAMPLE", "CAPTURE_KINDS",
    "ERROR_KINDS",
]

# ---- exceptions (crates/spacearm-py/src/errors_py.rs; spacearm.errors re-exports them) ----------
class SpacearmError(Exception): ...
class ArgumentError(SpacearmError, ValueError): ...
class ModelError(SpacearmError, ValueError): ...
class ModelFileError(ModelError): ...
class NonFiniteError(SpacearmError, ValueError): ...
class NotFoundError(SpacearmError, KeyError, ValueError): ...
class QuaternionError(SpacearmError, ValueError): ...
class ResourceLimitError(SpacearmError, MemoryError): ...
class ShapeError(SpacearmError, ValueError): ...
class SimulationError(SpacearmError, RuntimeError): ...
class SingularError(SpacearmError, ArithmeticError): ...
#: The core's error kinds (crates/spacearm-core/src/error.rs, ErrorKind's table): each as its
#: name, its status code in the C ABI and the class it is raised as.
ERROR_KINDS: list[tuple[str, int, type[SpacearmError]]]
class SpacearmTypeError(SpacearmError, TypeError): ...

def preset(name: str, allow_nonphysical_inertia: bool = ...) -> Model: ...
def model_from_toml(text: str, source: str = ..., allow_nonphysical_inertia: bool = ...) -> Model: ...
def model_to_toml(model: Model) -> str: ...
def model_from_dh(
    convention: str,
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

def cylinder_slosh(radius: float, fill_height: float, liquid_mass: float, axial_acceleration: float, modes: int = 1) -> dict[str, Any]:
    """The equivalent mechanical model of the liquid in an upright flat-bottomed cylinder (Abramson 1966, Dodge 2000)."""

def sphere_slosh(radius: float, fill_height: float, liquid_mass: float, axial_acceleration: float, modes: int = 1) -> dict[str, Any]:
    """The equivalent mechanical model of the liquid in a spherical tank (a Ritz-Trefftz solution; same dict as cylinder_slosh)."""

def sphere_fill_height(radius: float, fill_fraction: float) -> float:
    """The fill height (m) of a sphere of ``radius`` holding ``fill_fraction`` of its volume."""

def cylinder_fill_height(tank_height: float, fill_fraction: float) -> float:
    """The fill height (m) of an upright cylinder of ``tank_height`` holding ``fill_fraction`` (in (0, 1)) of its height."""

def slosh_links(name: str, parent: str, model: str, mass: float, position: Sequence[float], axis: Sequence[float],
                hinge: Optional[Sequence[float]], length: Optional[float], stiffness: Optional[float],
                frequency: Optional[float], damping: float) -> list[tuple]: ...  # ModelBuilder.add_link arguments per link

# (links: ModelBuilder.add_link arguments per link, points: (name, body, offset), geometries: (name, body, size, origin, rotation, rgba))
def panel_parts(name: str, parent: str, hinge_position: Sequence[float], hinge_axis: Sequence[float],
                direction: Sequence[float], mass: float, size: Optional[Sequence[float]],
                inertia: Optional[Sequence[Sequence[float]]], com_distance: Optional[float], stiffness: Optional[float],
                frequency: Optional[float], damping: float, rest: float) -> tuple[list[tuple], list[tuple], list[tuple]]: ...
def beam_parts(name: str, parent: str, root_position: Sequence[float], axis: Sequence[float], length: float,
               segments: int, bending_axes: Optional[Sequence[Sequence[float]]], ei: Sequence[float], torsion: Optional[float], rho_a: float,
               rho_j: float, damping: Optional[float], damping_ratio: Optional[float]) -> tuple[list[tuple], list[tuple], list[tuple]]: ...
def compliant_parts(link: tuple[str, str, str, Sequence[float], Sequence[float], Sequence[float], Sequence[float], float,
                                Sequence[Sequence[float]], Optional[str], Optional[Sequence[float]]],
                    stiffness: float, rotor_inertia: float, damping: float,
                    gear_ratio: float) -> tuple[list[tuple], list[tuple], list[tuple]]: ...
def cmg_parts(spec: dict[str, Any], base: str) -> tuple[list[tuple], list[tuple], list[tuple]]: ...
def cmgs(model: Model) -> list[dict[str, Any]]: ...
def docking_parts(kind: str, spec: dict[str, Any]) -> tuple[list[tuple], list[tuple]]: ...
def gripper_parts(spec: dict[str, Any], base: str) -> tuple[list[tuple], list[tuple], list[tuple]]: ...
def grippers(model: Model) -> list[dict[str, Any]]: ...
def analysis_cmg_envelope(gimbals: Sequence[Sequence[float]], h: Sequence[float],
                          directions: Sequence[Sequence[float]]) -> list[list[float]]: ...
def analysis_cmg_singular_surfaces(gimbals: Sequence[Sequence[float]], h: Sequence[float],
                                   signs: Optional[Sequence[Sequence[float]]],
                                   directions: Sequence[Sequence[float]]) -> tuple[list[list[float]], list[list[float]], list[list[float]]]: ...
def cmg_velocity(model: Model, wheel_speed: Sequence[float]) -> list[float]: ...

# The core's model edits (model/edit.rs): a new Model each, the rest of the model bit for bit.
def model_attach_body(model: Model, name: str, parent: str, origin: Sequence[float], rotation: Sequence[float], mass: float,
                      inertia: Sequence[Sequence[float]], joint_type: str = ..., axis: Sequence[float] = ...,
                      com: Sequence[float] = ..., joint_name: Optional[str] = None, limits: Optional[Sequence[float]] = None,
                      dynamics: Optional[tuple[bool, float, float, float]] = None, model_name: Optional[str] = None) -> Model: ...
def model_attach_model(model: Model, other: Model, parent: str, origin: Sequence[float], rotation: Sequence[float], prefix: str,
                       base_link: Optional[str] = None, model_name: Optional[str] = None) -> Model: ...
def model_remove_subtree(model: Model, body: str, model_name: Optional[str] = None) -> Model: ...

@final
class ModelBuilder:
    def __new__(cls, name: str, base_name: str, base_mass: float, base_inertia: Sequence[Sequence[float]],
                 allow_nonphysical_inertia: bool = ...) -> ModelBuilder: ...
    @staticmethod
    def from_model(model: Model) -> ModelBuilder: ...
    def set_name(self, name: str) -> None: ...
    def set_allow_nonphysical_inertia(self, allow_nonphysical_inertia: bool) -> None: ...
    def clear_geometries(self) -> None: ...
    def remove_subtree(self, body: str) -> None: ...
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
        dynamics: Optional[tuple[bool, float, float, float]] = None,  # (actuated, stiffness, damping, rest)
    ) -> None: ...
    def add_point(self, name: str, body: str, offset: Sequence[float]) -> None: ...
    def add_geometry(
        self,
        body: str,
        role: str,
        shape: str,
        origin: Sequence[float],
        rotation: Sequence[float],
        size: Optional[Sequence[float]] = None,
        radius: Optional[float] = None,
        length: Optional[float] = None,
        file: Optional[str] = None,
        scale: Optional[Sequence[float]] = None,
        rgba: Optional[Sequence[float]] = None,
        name: Optional[str] = None,
    ) -> None: ...
    def set_end_effector(self, name: str) -> None: ...
    def set_initial_q(self, q: Sequence[float]) -> None: ...
    def build(self) -> Model: ...

# ---- the model's description (crates/spacearm-py/src/description_py.rs) ---------------------
# The public types (spacearm.ModelDescription etc. are these classes). Frozen snapshots built
# once per model: every attribute read hands out the same object, and the arrays are read-only.
# Frames and units: docs/conventions.md ("A model's frames, concretely").

@final
class BaseDescription:
    """The spacecraft base (body 0). Its frame has its origin at the base CM."""

    @property
    def name(self) -> str:
        """The base's name."""
    @property
    def mass(self) -> float:
        """Mass, kg."""
    @property
    def inertia(self) -> _Vec:
        """(3, 3) kg·m², read-only: inertia about the base CM, in base-frame axes."""

@final
class JointLimits:
    """A joint's limits. ``lower``/``upper``: position bounds (rad for a revolute joint, m for a
    prismatic one); ``velocity``: speed bound (rad/s or m/s); ``effort``: torque (N·m) or force
    (N) bound. An absent bound is infinite (``-inf`` for ``lower``, ``inf`` for the others)."""

    @property
    def lower(self) -> float:
        """Lower position bound, rad or m; ``-inf`` when unbounded."""
    @property
    def upper(self) -> float:
        """Upper position bound, rad or m; ``inf`` when unbounded."""
    @property
    def velocity(self) -> float:
        """Speed bound, rad/s or m/s; ``inf`` when unbounded."""
    @property
    def effort(self) -> float:
        """Effort bound, N·m or N; ``inf`` when unbounded."""
    def to_list(self) -> list[float]:
        """``[lower, upper, velocity, effort]``, the order of [`Robot.describe`][spacearm.Robot.describe]."""

@final
class LinkDescription:
    """One link (a body other than the base; the k-th link is body k + 1) and the joint that
    connects it to its parent. The link frame has its origin at the link's CM; at ``q = 0`` its
    axes are those of the parent frame rotated by ``rotation``."""

    @property
    def name(self) -> str:
        """The link's name."""
    @property
    def parent(self) -> str:
        """Name of the parent body (the base's name for a link on the base)."""
    @property
    def parent_index(self) -> int:
        """Body index of the parent (0 = base)."""
    @property
    def joint(self) -> str:
        """Name of the joint."""
    @property
    def type(self) -> str:
        """``"revolute"``, ``"prismatic"`` or ``"fixed"``."""
    @property
    def origin(self) -> _Vec:
        """(3,) m, read-only: joint position in the parent frame, measured from the parent's CM."""
    @property
    def rotation(self) -> _Vec:
        """(4,) ``[x, y, z, w]`` unit quaternion, read-only: link frame in the parent frame at q = 0."""
    @property
    def axis(self) -> _Vec:
        """(3,) read-only: unit joint axis in the link frame (unused by a fixed joint: as given, or z if given zero)."""
    @property
    def com(self) -> _Vec:
        """(3,) m, read-only: the link's CM measured from the joint, in the link frame."""
    @property
    def mass(self) -> float:
        """Mass, kg."""
    @property
    def inertia(self) -> _Vec:
        """(3, 3) kg·m², read-only: about the link's CM in link-frame axes."""
    @property
    def limits(self) -> JointLimits:
        """The joint's limits."""
    @property
    def dof(self) -> Optional[int]:
        """Index of the joint's coordinate in ``q``; ``None`` for a fixed joint."""
    @property
    def actuated(self) -> bool:
        """Whether a motor drives the joint (``False``: a passive joint, docs/flexibility.md)."""
    @property
    def stiffness(self) -> float:
        """Joint spring stiffness, N·m/rad (revolute) or N/m (prismatic); 0: none."""
    @property
    def damping(self) -> float:
        """Joint damping, N·m·s/rad (revolute) or N·s/m (prismatic); 0: none."""
    @property
    def rest(self) -> float:
        """The spring's rest coordinate, rad or m."""

@final
class PointDescription:
    """A named point fixed to a body (an end effector, a grasp point)."""

    @property
    def name(self) -> str:
        """The point's name."""
    @property
    def body(self) -> str:
        """Name of the body carrying the point."""
    @property
    def body_index(self) -> int:
        """Index of the body carrying the point (0 = base)."""
    @property
    def offset(self) -> _Vec:
        """(3,) m, read-only: from the body's CM, in the body frame."""

@final
class GeometryDescription:
    """A visual or collision shape fixed to a body (docs/geometry.md), placed in the body frame
    (origin at the body's CM) by ``origin`` and ``rotation``; the keys of other shape kinds are
    ``None``."""

    @property
    def name(self) -> str:
        """The geometry's name."""
    @property
    def body(self) -> str:
        """Name of the body it is fixed to."""
    @property
    def body_index(self) -> int:
        """Index of that body (0 = base)."""
    @property
    def role(self) -> str:
        """``"visual"`` or ``"collision"``."""
    @property
    def shape(self) -> str:
        """``"box"``, ``"cylinder"``, ``"sphere"``, ``"capsule"`` or ``"mesh"``."""
    @property
    def size(self) -> Optional[_Vec]:
        """(3,) m, read-only: a box's full side lengths."""
    @property
    def radius(self) -> Optional[float]:
        """m: the radius of a sphere, cylinder or capsule."""
    @property
    def length(self) -> Optional[float]:
        """m: the length of a cylinder or of a capsule's cylinder part (along z)."""
    @property
    def file(self) -> Optional[str]:
        """A mesh's file, as the model states it."""
    @property
    def scale(self) -> Optional[_Vec]:
        """(3,) read-only: a mesh's scale along its x, y, z."""
    @property
    def origin(self) -> _Vec:
        """(3,) m, read-only: the geometry frame's origin in the body frame, from its CM."""
    @property
    def rotation(self) -> _Vec:
        """(4,) read-only: unit quaternion ``[x, y, z, w]`` of the geometry frame in the body frame."""
    @property
    def rgba(self) -> _Vec:
        """(4,) read-only: red, green, blue, alpha in [0, 1]."""

@final
class ModelDescription:
    """A whole model: base, links in tree order (a parent before its children; link ``i`` is
    body ``i + 1``), named points, end effector and initial joint coordinates
    (what [`Robot.description`][spacearm.Robot.description] and ``Model.describe()`` return)."""

    @property
    def name(self) -> str:
        """The model's name."""
    @property
    def base(self) -> BaseDescription:
        """The base (body 0)."""
    @property
    def links(self) -> tuple[LinkDescription, ...]:
        """The links in tree order: link k is body k + 1."""
    @property
    def points(self) -> tuple[PointDescription, ...]:
        """The named points in the order they were added."""
    @property
    def geometries(self) -> tuple[GeometryDescription, ...]:
        """The visual and collision shapes in the order they were added."""
    @property
    def end_effector(self) -> Optional[str]:
        """Name of the end-effector point, or ``None``."""
    @property
    def initial_q(self) -> _Vec:
        """(N,) read-only: initial joint coordinates (rad or m per joint type)."""
    def link(self, name: str) -> LinkDescription:
        """The link called ``name`` (raises [`NotFoundError`][spacearm.NotFoundError] if there is none)."""
    def point(self, name: str) -> PointDescription:
        """The point called ``name`` (raises [`NotFoundError`][spacearm.NotFoundError] if there is none)."""
    def to_dict(self) -> dict[str, Any]:
        """The plain-data form, exactly as [`Robot.describe`][spacearm.Robot.describe] returns it (a new dict at each call)."""

@final
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
    initial_q: _Vec
    body_of_dof: list[int]
    actuated_dofs: list[bool]
    def body_index(self, name: str) -> int: ...
    def point(self, name: str) -> tuple[int, list[float]]: ...
    def describe(self) -> ModelDescription: ...
    def joint_types(self) -> list[str]: ...
    # Every method below takes one state (1-D arrays) or a batch (a 2-D x, one state per row;
    # the other vectors with as many rows or one row for all) and then returns its results with
    # a leading axis of length B (crates/spacearm-py/src/batch.rs).
    def __reduce__(self) -> tuple: ...
    def to_toml(self) -> str:
        """The model as the text of a model file (bit-exact)."""
    def check_configuration(self, x: _ArrayLike) -> None: ...
    # The per-state methods return arrays (a tuple of them where named below), the fastest form for
    # the one-state path and the batch axis alike; the public Robot methods wrap them in NamedTuples.
    def forward_kinematics(self, x: _ArrayLike) -> tuple[_Vec, _Vec, _Vec, _Vec]: ...  # (body_to_world (nb,3,3), com_in_world (nb,3), joint_position_in_world (nb,3), joint_axis_in_world (nb,3))
    def point_position(self, x: _ArrayLike, body: int, offset: _Vec) -> _Vec: ...
    # The core's recursions recorded on a tape (spacearm_core::taped) for spacearm.casadi to replay.
    def tape(self, function: str, body: Optional[int] = None, offset: Optional[_ArrayLike] = None) -> Tape: ...
    def point_jacobians(self, x: _ArrayLike, body: int, offset: _Vec) -> tuple[_Vec, _Vec]: ...
    def link_jacobians(self, x: _ArrayLike, body: int) -> tuple[_Vec, _Vec]: ...
    def inertia_blocks(self, x: _ArrayLike) -> tuple: ...  # (M, r_0g, H_S, J_TS, H_Sq, H0, H0m, Hm, H): spacearm.InertiaBlocks
    def mass_matrix_crba(self, x: _ArrayLike) -> _Vec: ...
    def mass_matrix_paper(self, x: _ArrayLike) -> _Vec: ...
    def base_inertia_inverse(self, x: _ArrayLike) -> _Vec: ...
    def bias_forces(self, x: _ArrayLike, u: _ArrayLike) -> _Vec: ...
    def inverse_dynamics(self, x: _ArrayLike, u: _ArrayLike, du: _ArrayLike, wrenches: Optional[list[_Wrench]] = None) -> _Vec: ...
    def forward_dynamics(self, x: _ArrayLike, u: _ArrayLike, f: _ArrayLike, wrenches: Optional[list[_Wrench]], method: str) -> _Vec: ...
    def forward_dynamics_tau(self, x: _ArrayLike, u: _ArrayLike, tau: Optional[_ArrayLike], base_wrench: Optional[_ArrayLike], wrenches: Optional[list[_Wrench]], method: str) -> _Vec: ...
    def generalized_inertia(self, x: _ArrayLike) -> _Vec: ...
    def generalized_bias(self, x: _ArrayLike, u: _ArrayLike) -> _Vec: ...
    def generalized_jacobian(self, x: _ArrayLike, body: int, offset: _Vec) -> _Vec: ...
    def point_twist(self, x: _ArrayLike, qd: _ArrayLike, body: int, offset: _Vec, linear: _ArrayLike, angular_origin: _ArrayLike) -> _Vec: ...
    def momentum_twist(self, x: _ArrayLike, body: int, offset: _Vec, linear: _ArrayLike, angular_origin: _ArrayLike) -> _Vec: ...
    def base_velocity_from_momentum(self, x: _ArrayLike, qd: _ArrayLike, linear: _ArrayLike, angular_origin: _ArrayLike) -> _Vec: ...
    def momentum(self, x: _ArrayLike, u: _ArrayLike) -> tuple[_Vec, _Vec, _Vec, _Vec]: ...  # (P, L_origin, L_base, L_com), each (3,) in 𝒥
    def kinetic_energy(self, x: _ArrayLike, u: _ArrayLike) -> Union[float, _Vec]: ...
    def momentum_scales(self, x: _ArrayLike, u: _ArrayLike) -> npt.NDArray[np.float64]: ...
    def center_of_mass(self, x: _ArrayLike) -> _Vec: ...
    def passive_forces(self, x: _ArrayLike, u: _ArrayLike) -> _Vec: ...  # (6+N,): [0 (6); -k (q - rest) - c qd]
    def spring_energy(self, x: _ArrayLike) -> Union[float, _Vec]: ...
    def passive_modes(self, x: _ArrayLike, held: bool) -> tuple[list[int], _Vec, _Vec, _Vec]: ...  # (dofs, frequencies, damping_ratios, shapes)

# ---- the core's rules and defaults (crates/spacearm-py/src/rules_py.rs, rule_tables_py.rs) -----
# The tables are frozen instances with typed attributes; each is also a read-only mapping of its
# field names (keys(), t[name], dict(t), **t, == a dict).

@final
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
    def __getitem__(self, key: str, /) -> Any: ...

@final
class ModelBounds:
    """The physical bounds of every model (docs/model-format.md, rules 10-11)."""

    min_mass: float  # kg, smallest non-zero body mass
    max_mass: float  # kg
    max_length: float  # m, largest |component| of a joint origin, CM or point offset
    max_inertia_entry: float  # kg·m², largest |inertia entry|
    def keys(self) -> list[str]: ...
    def __getitem__(self, key: str, /) -> float: ...

@final
class DlsDefaults:
    """The default damped-least-squares law (math/dls.rs)."""

    threshold: float  # ε, size of the singular region (units of σ)
    max_damping: float  # λ_max, damping at the singularity (units of σ)
    def keys(self) -> list[str]: ...
    def __getitem__(self, key: str, /) -> float: ...

MODES: list[str]
INTEGRATORS: list[str]
PASSIVE_TREATMENTS: list[str]  # how computed torque treats passive joints: "drift", "frozen"
CONTROLLER_LABELS: dict[str, str]  # the words a person reads for each controller name of the records
SIM_DEFAULTS: SimDefaults
MODEL_BOUNDS: ModelBounds
DLS_DEFAULTS: DlsDefaults
QUATERNION_TOLERANCE: float
MEMORY_LIMIT_BYTES: int
GOAL_TOLERANCE: float    # m: RMRC ends farther than this from its reference with its damping active -> unreachable
MAX_HANDLE_RATIO: float  # a target grasp point at most this many body sizes from the body's CM
def quintic_scaling(t: _Vec, t_start: float, t_end: float) -> tuple[_Vec, _Vec, _Vec]: ...
def box_of_moments(mass: float, moments: Sequence[float]) -> list[float]: ...
def body_mass_properties_error(
    who: str, mass: float, inertia: Sequence[Sequence[float]], *, triangle_inequality: bool = True
) -> Optional[tuple[str, str]]: ...  # None, or ("mass" | "inertia", the core's message naming `who`)

# ---- rotation helpers (crates/spacearm-py/src/rotations_py.rs; the core's math/rotations.rs) ------
# Float64 arrays of one item or (B, ...) rows of them; only the shape is checked here (a
# ShapeError): spacearm.rotations checks finiteness, unit norm and rotation matrices first.
# Quaternions [x, y, z, w], scalar last.
def quat_multiply(a: _Vec, b: _Vec) -> _Vec: ...  # (4,)/(B, 4) each; one row pairs with every row
def quat_to_matrix(q: _Vec) -> _Vec: ...  # (4,) -> (3, 3), (B, 4) -> (B, 3, 3); each q divided by its norm
def quat_from_matrix(r: _Vec) -> _Vec: ...  # (3, 3) -> (4,), (B, 3, 3) -> (B, 4); Shepperd, w >= 0
def rotation_vector(r: _Vec) -> _Vec: ...  # (3, 3) -> (3,), (B, 3, 3) -> (B, 3); log(R), |theta| <= pi
def quat_exp(theta: _Vec) -> _Vec: ...  # (3,) -> (4,), (B, 3) -> (B, 4)
def quat_log(q: _Vec) -> _Vec: ...  # (4,) -> (3,), (B, 4) -> (B, 3); normalized first
def skew(v: _Vec) -> _Vec: ...  # (3,) -> (3, 3), (B, 3) -> (B, 3, 3)
def quat_from_rpy(roll: float, pitch: float, yaw: float) -> _Vec: ...  # Rz(yaw) Ry(pitch) Rx(roll)

def set_batch_threads(threads: Optional[int] = None) -> None: ...
def batch_threads() -> int: ...

# ---- analysis (crates/spacearm-py/src/analysis_py.rs; results: analysis_results_py.rs) ------------
# The results are frozen classes named after the core's types (spacearm_core::analysis) and are
# the public types (spacearm.analysis.JacobianMeasures, SingularityReport, Detection,
# ReactionNullSpace are these classes; spacearm.analysis.Motion subclasses RmrcMotion); every
# array attribute hands out the same numpy array on each read. Task Jacobians: rows are the task
# rows of the point twist [v; w] in the inertial frame, columns the joint rates.
@final
class JacobianMeasures:
    """Singular-value measures of one task Jacobian (m task rows, N joints)."""

    @property
    def jacobian(self) -> _Vec:
        """(m, N): the task rows analysed."""
    @property
    def singular_values(self) -> _Vec:
        """(min(m, N),): decreasing."""
    @property
    def sigma_min(self) -> float:
        """The smallest singular value (NaN when there are none)."""
    @property
    def condition(self) -> float:
        """σ_max / σ_min (inf at a singularity)."""
    @property
    def manipulability(self) -> float:
        """Yoshikawa's Π σ_i."""
    @property
    def task_directions(self) -> _Vec:
        """(m, min(m, N)) left singular vectors; the last is the worst task direction."""
    @property
    def joint_directions(self) -> _Vec:
        """(N, N) right singular vectors; the columns beyond the rank span the null space."""

@final
class SingularityReport:
    """``J*`` (free-floating, zero momentum; eq. 110) and ``J_m`` (base held fixed; eq. 106) at one configuration."""

    @property
    def generalized(self) -> JacobianMeasures:
        """Measures of the task rows of ``J*``."""
    @property
    def fixed_base(self) -> JacobianMeasures:
        """Measures of the task rows of ``J_m``."""
    @property
    def task(self) -> tuple[int, ...]:
        """The twist rows analysed (0-5 of ``[v; w]``)."""

@final
class Detection:
    """What the singularity detector tells a resolved-motion-rate controller."""

    @property
    def sigma_min(self) -> float:
        """Smallest singular value of the task rows of ``J*``."""
    @property
    def condition(self) -> float:
        """σ_max / σ_min."""
    @property
    def damping(self) -> float:
        """Recommended λ of the DLS inverse."""
    @property
    def near_singular(self) -> bool:
        """σ_min < ε."""

@final
class ScanResult:
    """A joint-space scan of M samples: one entry per sample in each column."""

    @property
    def sigma_min_generalized(self) -> _Vec: ...  # (M,)
    @property
    def sigma_max_generalized(self) -> _Vec: ...  # (M,)
    @property
    def manipulability_generalized(self) -> _Vec: ...  # (M,)
    @property
    def det_generalized(self) -> _Vec: ...  # (M,), NaN unless the task is square
    @property
    def sigma_min_fixed(self) -> _Vec: ...  # (M,)
    @property
    def manipulability_fixed(self) -> _Vec: ...  # (M,)
    @property
    def det_fixed(self) -> _Vec: ...  # (M,), NaN unless the task is square
    @property
    def point_from_base(self) -> _Vec: ...  # (M, 3) m, base frame
    @property
    def point_from_com(self) -> _Vec: ...  # (M, 3) m, base frame

@disjoint_base
class WorkspaceShells:
    """Radial description of the workspaces, m. Constructing one computes the shells of a scan;
    ``spacearm.analysis.Workspace`` subclasses it (the samples, timing and figure)."""

    def __new__(cls, sigma_min_generalized: Sequence[float], det_generalized: Sequence[float], point_from_com: _Vec,
                point_from_base: _Vec, singular_threshold: float, radial_resolution: float,
                grid: Optional[tuple[int, int]] = None) -> WorkspaceShells: ...

    @property
    def reachable(self) -> tuple[float, float]: ...  # (R_min, R_max) about the system CM
    @property
    def fixed_base(self) -> tuple[float, float]: ...  # (min, max) from the base CM, base fixed
    @property
    def singular_radii(self) -> _Vec: ...  # (K,), sorted
    @property
    def path_dependent(self) -> list[tuple[float, float]]: ...
    @property
    def path_independent(self) -> list[tuple[float, float]]: ...
    @property
    def radial_resolution(self) -> float: ...

@final
class Tape:
    """A function of the equations of motion recorded by the core (spacearm_core::taped): node i
    is ops[i] on the nodes args[i] (operands first), an input (args[i, 0]) or a constant
    (constants[args[i, 0]]). Codes: 0 input, 1 constant, 2 add, 3 sub, 4 mul, 5 div, 6 atan2,
    16 neg, 17 sqrt, 18 sin, 19 cos, 20 tan, 21 asin, 22 acos, 23 atan, 24 exp, 25 ln, 26 abs."""

    @property
    def ops(self) -> npt.NDArray[np.uint8]: ...  # (n,)
    @property
    def args(self) -> npt.NDArray[np.uint32]: ...  # (n, 2)
    @property
    def constants(self) -> _Vec: ...
    @property
    def outputs(self) -> npt.NDArray[np.uint32]: ...  # the node of each output value, column-major
    @property
    def n_inputs(self) -> int: ...
    @property
    def inputs(self) -> list[tuple[str, int]]: ...  # (name, length), in order
    @property
    def outputs_shapes(self) -> list[tuple[str, int, int]]: ...  # (name, rows, columns), in order

@final
class ReactionNullSpace:
    """Joint rates that leave the base attitude (``"angular"``) or the whole base (``"full"``)
    undisturbed, with zero system momentum (N joints)."""

    @property
    def base_motion_map(self) -> _Vec:
        """Rows of −H0⁻¹ H0m: joint rates → base angular velocity (3, N) or twist (6, N)."""
    @property
    def singular_values(self) -> _Vec:
        """Of the map, decreasing."""
    @property
    def rank(self) -> int:
        """Numerical rank of the map."""
    @property
    def basis(self) -> _Vec:
        """(N, N − rank): orthonormal basis of the null space."""
    @property
    def dimension(self) -> int:
        """N − rank, the columns of ``basis``."""
    @property
    def projector(self) -> _Vec:
        """(N, N): orthogonal projector onto the null space."""

@final
class RmrcRates:
    """One evaluation of the resolved-motion-rate law (what ``spacearm.analysis.rmrc_rates`` returns)."""

    @property
    def qd(self) -> _Vec:
        """(N,) joint rates, rad/s (m/s for a prismatic joint)."""
    @property
    def sigma_min(self) -> float:
        """σ_min of the (projected) task Jacobian."""
    @property
    def damping(self) -> float:
        """Damping λ of the DLS inverse used."""
    @property
    def base_angular_velocity(self) -> _Vec:
        """(3,) rad/s in 𝒥: the base angular velocity these rates produce (zero momentum)."""

@disjoint_base
class RmrcMotion:
    """A closed-loop point-to-point motion at its K+1 time nodes. Constructing one runs the
    motion; ``spacearm.analysis.Motion`` subclasses it (the figure)."""

    def __new__(cls, model: Model, x0: _ArrayLike, body: int, offset: _ArrayLike, target: _ArrayLike, duration: float,
                settle: float, dt: float, options: RmrcOptions) -> RmrcMotion: ...
    @property
    def robot_name(self) -> str:
        """Name of the model moved."""
    @property
    def strategy(self) -> str:
        """``"naive"``, ``"reactionless"`` or ``"minimum_disturbance"``."""
    @property
    def target(self) -> _Vec:
        """(3,) m in 𝒥: the point's target."""
    @property
    def times(self) -> _Vec:
        """(K+1,) s."""
    @property
    def x(self) -> _Vec:
        """(K+1, 7+N) configurations."""
    @property
    def qd(self) -> _Vec:
        """(K+1, N) joint rates."""
    @property
    def point_position(self) -> _Vec:
        """(K+1, 3) m in 𝒥."""
    @property
    def sigma_min(self) -> _Vec:
        """(K+1,) σ_min of the (projected) task Jacobian."""
    @property
    def damping(self) -> _Vec:
        """(K+1,) damping λ used."""
    @property
    def attitude_change(self) -> _Vec:
        """(K+1,) rad: base rotation angle from the start."""
    @property
    def max_attitude_change(self) -> float:
        """The largest of ``attitude_change``, rad."""
    @property
    def final_position_error(self) -> float:
        """m: the point's distance from the target at the end (linear task rows)."""

# ---- contact dynamics (crates/spacearm-py/src/contact_py.rs; spacearm_core::algorithms::impulse) --------
@final
class ImpulseDynamics:
    """The velocity jump of an impact through a contact Jacobian (Pinocchio's impulseDynamics)."""

    @property
    def u_after(self) -> _Vec: ...  # (6+N,)
    @property
    def du(self) -> _Vec: ...  # (6+N,) H^-1 J^T Lambda, zero on locked coordinates
    @property
    def impulse(self) -> _Vec: ...  # (m,) Lambda
    @property
    def delassus(self) -> _Vec: ...  # (m, m) J H^-1 J^T over the mobile coordinates
    @property
    def locking_impulse(self) -> _Vec: ...  # (N,) the joint impulses holding locked joints

@final
class GraspImpulse:
    """The impact between a robot's grasp point and a target model (every vector in the inertial
    frame): what ``grasp_impact`` and ``spacearm.capture.grasp_impulse`` return, the public
    ``spacearm.capture.GraspImpulse``. Frozen; the arrays are read-only."""

    @property
    def kind(self) -> str:
        """``"rigid"`` (6-D plastic lock) or ``"point"`` (frictionless contact)."""
    @property
    def du(self) -> _Vec:
        """(6+N,) the robot's velocity jump ``[Δv0, Δω0, Δq̇]``."""
    @property
    def target_dtwist(self) -> _Vec:
        """The target's jump of its model's u: ``[v; ω]`` (CM velocity, angular velocity; 6) of a rigid target."""
    @property
    def impulse(self) -> _Vec:
        """(6,) ``Λ = [f̂; n̂]`` on the robot at the grasp point, N s, N m s; the target gets ``−Λ``."""
    @property
    def point(self) -> _Vec:
        """(3,) the grasp point X (the robot's point), m."""
    @property
    def gap(self) -> float:
        """m: distance from X to the target's grasp point (zero for a perfect approach)."""
    @property
    def u_after(self) -> _Vec:
        """(6+N,) the robot's velocity after the impact."""
    @property
    def target_state_after(self) -> _Vec:
        """The target's state after the impact: its x followed by its u after."""
    @property
    def relative_twist_before(self) -> _Vec:
        """(6,) the gripper's twist at X minus the target's twist at X, before the impact."""
    @property
    def relative_twist_after(self) -> _Vec:
        """(6,) the relative twist at X after the impact (zero for a rigid lock)."""
    @property
    def G_robot(self) -> _Vec:
        """(6, 6) the robot's inverse inertia at X (the base's alone with ``arm="locked"``)."""
    @property
    def G_target(self) -> _Vec:
        """(6, 6) the target's inverse inertia at X."""
    @property
    def energy_lost(self) -> float:
        """J: the energy the grasp dissipates, ``−Λᵀ(v_rel⁻ + v_rel⁺)/2`` (>= 0 to rounding; excludes ``locking_work``)."""
    @property
    def locking_work(self) -> float:
        """J: the work ``τ̂ᵀq̇`` of the locking joint impulses (either sign; 0 with ``arm="free"``)."""
    @property
    def target_u_after(self) -> _Vec:
        """The target's velocity after the impact (its model's u; the tail of ``target_state_after``)."""
    @property
    def normal(self) -> _Vec | None:
        """(3,) the unit contact normal of a point contact, or None."""
    @property
    def locking_impulse(self) -> _Vec:
        """(N,) the locking joint impulses ``τ̂`` (zeros with ``arm="free"``)."""

@final
class MomentumSplit:
    """Where an impulse's momentum goes, about the base CM ([P; L_base]): base + arm == total."""

    @property
    def base(self) -> _Vec: ...  # (6,) H0 dx0
    @property
    def arm(self) -> _Vec: ...  # (6,) H0m dq
    @property
    def total(self) -> _Vec: ...  # (6,) J_0X^T Lambda
    @property
    def base_jump_map(self) -> _Vec: ...  # (6, 6) B, dx0 = B Lambda
    @property
    def base_jump_singular_values(self) -> _Vec: ...  # (6,) of B, largest first

def point_inverse_inertia(model: Model, x: _ArrayLike, body: int, offset: _ArrayLike, arm: str = "free") -> _Vec: ...
def virtual_mass(model: Model, x: _ArrayLike, body: int, offset: _ArrayLike, direction: _ArrayLike, arm: str = "free") -> float: ...
def joint_wrenches(model: Model, x: _Vec, u: _Vec, du: _Vec, body: int) -> _Vec: ...
def impulse_momentum_split(model: Model, x: _ArrayLike, body: int, offset: _ArrayLike, impulse: _ArrayLike) -> MomentumSplit: ...
def impulse_dynamics(model: Model, x: _ArrayLike, u_before: _ArrayLike, jacobian: _Vec, restitution: float = 0.0,
                     arm: str = "free") -> ImpulseDynamics: ...
def grasp_impact(robot: Model, x: _ArrayLike, u: _ArrayLike, body: int, offset: _ArrayLike, target: Model, x_target: _ArrayLike,
                 u_target: _ArrayLike, target_body: int, target_offset: _ArrayLike, *, kind: str = "rigid", restitution: float = 0.0,
                 normal: _ArrayLike | None = None, arm: str = "free", capture_tolerance: float = 0.01) -> GraspImpulse: ...
def check_grasp_handle(model: Model, body: int, offset: _ArrayLike) -> None: ...

@final
class SoftCaptureResult:
    """A soft capture run by the core (spacearm_core::sim::soft_capture): the robot's and the target's runs."""

    @property
    def robot(self) -> RunResult: ...
    @property
    def target(self) -> RunResult: ...
    @property
    def wrench(self) -> _Vec: ...  # (K, 6) [f; n] on the robot at its grasp point
    @property
    def stiffness(self) -> float: ...  # N/m
    @property
    def damping(self) -> float: ...  # N s/m
    @property
    def rotational_stiffness(self) -> float: ...  # N m/rad
    @property
    def rotational_damping(self) -> float: ...  # N m s/rad
    @property
    def drift_linear(self) -> float: ...
    @property
    def drift_angular(self) -> float: ...

# ---- the capture mission (crates/spacearm-py/src/capture_py.rs; core sim/capture.rs) -------------
MAX_CAPTURE_SAMPLES: int  # the most samples a capture may record over its phases
MAX_TURN_PER_SAMPLE: float  # rad: the largest turn of the target between two samples
CAPTURE_KINDS: list[str]  # the grasp models: rigid, point, soft

@final
class CaptureRun:
    """The capture mission run by the core (spacearm_core::sim::capture::run_capture): the phases end to end."""

    @property
    def t(self) -> _Vec: ...  # (T,) s
    @property
    def phase(self) -> _Vec: ...  # (T,) int64: 0 approach, 1 capture, 2 post-capture, 3 detumble
    @property
    def x(self) -> _Vec: ...  # (T, 7+N)
    @property
    def u(self) -> _Vec: ...  # (T, 6+N)
    @property
    def tau(self) -> _Vec: ...  # (T, N)
    @property
    def base_wrench(self) -> _Vec: ...  # (T, 6)
    @property
    def target(self) -> _Vec: ...  # (T, 13)
    @property
    def P(self) -> _Vec: ...  # (T, 3) robot + target
    @property
    def L(self) -> _Vec: ...  # (T, 3) robot + target, about the origin
    @property
    def grasp_wrench(self) -> _Vec: ...  # (T, 6)
    @property
    def impact(self) -> GraspImpulse: ...
    @property
    def captured(self) -> Model | None: ...
    @property
    def captured_state(self) -> tuple[_Vec, _Vec] | None: ...
    @property
    def captured_names(self) -> tuple[str, str] | None: ...  # (payload, gripper)
    @property
    def time_to_detumble(self) -> float: ...
    @property
    def residual_spin(self) -> float: ...
    @property
    def drift_p(self) -> float: ...
    @property
    def drift_l(self) -> float: ...
    @property
    def drift_scales(self) -> tuple[float, float]: ...
    @property
    def approach_end(self) -> float: ...
    @property
    def ledger(self) -> str: ...  # "conservation" or "balance" (in orbit)
    @property
    def external_wrench(self) -> _Vec | None: ...  # in orbit: (T, 6)
    @property
    def external_impulse(self) -> _Vec | None: ...  # in orbit: (T, 6)
    @property
    def r_cm_eci(self) -> _Vec | None: ...  # in orbit: (T, 3)
    @property
    def v_cm_eci(self) -> _Vec | None: ...  # in orbit: (T, 3)
    @property
    def target_lvlh(self) -> _Vec | None: ...  # in orbit: (T, 6)

def run_capture(model: Model, x0: _ArrayLike, u0: _ArrayLike, target: Model, spec: dict[str, Any]) -> CaptureRun: ...
def check_capture(model: Model, x0: _ArrayLike, u0: _ArrayLike, target: Model, spec: dict[str, Any]) -> None: ...

def soft_capture(robot: Model, x: _ArrayLike, u: _ArrayLike, body: int, offset: _ArrayLike, target: Model, x_target: _ArrayLike,
                 u_target: _ArrayLike, target_body: int, target_offset: _ArrayLike, duration: float, options: RunOptions,
                 controller_spec: ControllerSpec | None = None, *, frequency: float = 3.0, damping_ratio: float = 0.7,
                 stiffness: float | None = None, damping: float | None = None, rotational_stiffness: float | None = None,
                 rotational_damping: float | None = None) -> SoftCaptureResult: ...

@final
class ClosedChainResult:
    """A closed chain run by the core (spacearm_core::sim::closed_chain)."""

    @property
    def run(self) -> RunResult: ...
    @property
    def constraint_wrench(self) -> _Vec: ...  # (K, 6) lambda on frame b at its origin
    @property
    def pose_error(self) -> _Vec: ...  # (K, 6) [position (m); rotation (rad)]

@final
class LoopClosureTerms:
    """J_c and the exact J_c-dot u of a loop closure at one state."""

    @property
    def jacobian(self) -> _Vec: ...  # (6, 6+N)
    @property
    def jdot_u(self) -> _Vec: ...  # (6,)

def loop_closure(model: Model, x: _ArrayLike, u: _ArrayLike, body_a: int, offset_a: _ArrayLike, body_b: int,
                 offset_b: _ArrayLike) -> LoopClosureTerms: ...
def simulate_closed_chain(model: Model, x0: _ArrayLike, u0: _ArrayLike, duration: float, body_a: int, offset_a: _ArrayLike,
                          body_b: int, offset_b: _ArrayLike, options: RunOptions, controller_spec: ControllerSpec | None = None, *,
                          stabilization: float = 20.0) -> ClosedChainResult: ...

def analysis_singularity(m: Model, x: _ArrayLike, body: int, offset: _Vec, rows: list[int]) -> SingularityReport: ...
def analysis_detect(m: Model, x: _ArrayLike, body: int, offset: _Vec, rows: list[int], threshold: float, max_damping: float) -> Detection: ...
def analysis_damping(sigma_min: float, threshold: float, max_damping: float) -> float: ...
def analysis_joint_grid(lower: Sequence[float], upper: Sequence[float], resolution: int) -> _Vec: ...
def analysis_scan(m: Model, samples: _Vec, body: int, offset: _Vec, rows: list[int]) -> ScanResult: ...
def analysis_reaction_null_space(m: Model, x: _ArrayLike, which: str, tolerance: float) -> ReactionNullSpace: ...
def analysis_reach(m: Model, x: _ArrayLike, u: _ArrayLike, body: int, offset: _Vec,
                   duration: float) -> tuple[_Vec, float | None, tuple[_Vec, _Vec] | None]: ...
def analysis_integrate_prescribed(m: Model, x0: _ArrayLike, dt: float, q_half: _Vec, qd_half: _Vec, linear_momentum: _Vec, angular_momentum: _Vec) -> _Vec: ...
@final
class RmrcOptions:
    """The options of the resolved-motion-rate law, keyword-only, checked when built."""
    def __new__(cls, *, rows: list[int], threshold: float, max_damping: float, gain: float = 0.0, strategy: str = "naive",
                 manipulability_gain: float = 0.0, joint_limit_gain: float = 0.0) -> RmrcOptions: ...
def analysis_rmrc_rates(m: Model, x: _ArrayLike, body: int, offset: _Vec, desired_twist: _Vec, options: RmrcOptions) -> RmrcRates: ...
# ---- simulation inputs (crates/spacearm-py/src/sim_options_py.rs, controller_spec_py.rs) ------
# A run's controller, references, shapers and thruster limits are the core's serde data
# (crates/spacearm-core/src/control/spec.rs): plain dicts, lists and numbers tagged by "kind".
_SpecData = Any

@final
class ControllerSpec:
    """A native control law as the core's data (control/spec.rs), checked when made; externals:
    the Python callables of its ``kind = "external"`` controllers, by index."""
    def __new__(cls, data: _SpecData, externals: Sequence[Callable[[float, _Vec, _Vec], Any]] = ...) -> ControllerSpec: ...
    @property
    def kind(self) -> str:
        """A name of CONTROLLER_KINDS."""
    def to_data(self) -> _SpecData:
        """The spec as plain data."""
    def to_toml(self) -> str:
        """The spec as the TOML text of a [controller] table (the C stepper's and the FMUs' options)."""

def check_spec(family: str, data: _SpecData) -> None:
    """Check the data of a "controller", "joint_reference", "point_reference", "shaper", "thrusters", "stop",
    "mpc_problem" or "mpc_options" spec."""
def mpc_solve(model: Model, problem: _SpecData, x0: _ArrayLike, u0: _ArrayLike, options: _SpecData,
              states: _ArrayLike | None = None, controls: _ArrayLike | None = None) -> dict[str, Any]:
    """One solve of the core's FDDP (spacearm.mpc.solve)."""
def controller_kind(name: str) -> str:
    """The controller kind a name means (a kind, its hyphenated spelling, or an alias)."""
CONTROLLER_KINDS: list[str]
CONTROLLER_ALIASES: dict[str, str]
TASKS: list[tuple[str, list[int]]]

@final
class ThrusterLimits:
    """Base thruster limits per axis of the inertial frame (> 0; inf: no limit)."""
    @staticmethod
    def from_spec(data: _SpecData) -> ThrusterLimits:
        """From {max_force, max_torque}: one number for the three axes, or three."""
    @property
    def max_force(self) -> _Vec:
        """Shape (3,), N."""
    @property
    def max_torque(self) -> _Vec:
        """Shape (3,), N·m."""

@final
class RunOptions:
    """The options of simulate, rollout and Simulator; a keyword left out or None keeps the
    core's default (SIM_DEFAULTS)."""
    def __new__(
        cls,
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
        orbit: Optional[Orbit] = None,
        gravity_gradient: Optional[bool] = None,
        stop: Optional[Sequence[_SpecData]] = None,
        contact: Optional[_SpecData] = None,
    ) -> RunOptions: ...
    @property
    def contact(self) -> Optional[_SpecData]:
        """The run's contact as data (sim/contact.rs ContactSpec), or None."""
    @property
    def orbit(self) -> Optional[Orbit]: ...
    @property
    def gravity_gradient(self) -> bool: ...
    @property
    def stop(self) -> _SpecData:
        """The stop conditions' data (sim/events.rs; empty: the run goes its duration)."""
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

@final
class JointReference:
    """The evaluator of a joint-space reference of the arm joints (a quintic, a constant, a
    sampled trajectory or an input-shaped one), built from its spec data."""
    @staticmethod
    def from_spec(data: _SpecData) -> JointReference: ...
    def evaluate(self, t: _ArrayLike) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """(q, qd, qdd) at each time, each (T, n)."""
    @property
    def kind(self) -> str:
        """"quintic", "constant", "sampled" or "shaped"."""
    @property
    def q_start(self) -> _Vec:
        """Shape (n,), rad or m (a constant's set point)."""
    @property
    def q_goal(self) -> _Vec:
        """Shape (n,), rad or m (a constant's set point)."""
    @property
    def t_start(self) -> Optional[float]:
        """s; None for a constant."""
    @property
    def t_end(self) -> Optional[float]:
        """s; None for a constant."""

@final
class FreeBodyReference:
    """A point on a rigid body moving freely (a tumbling capture target), propagated by the core."""
    @staticmethod
    def from_spec(data: _SpecData) -> FreeBodyReference: ...
    def states(self, t: _ArrayLike) -> npt.NDArray[np.float64]:
        """The body's 13-states at the times t, (T, 13)."""
    def points(self, t: _ArrayLike) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """The point's positions and velocities at the times t, each (T, 3)."""
    def external_wrenches(self, t: _ArrayLike, mass: float) -> npt.NDArray[np.float64]:
        """The tidal force and its moment about the run's origin at the times t, (T, 6)."""
    @property
    def in_orbit(self) -> bool: ...

@final
class InputShaper:
    """A ZV or ZVD input shaper (Singer & Seering 1990), built from its spec data."""
    @staticmethod
    def from_spec(data: _SpecData) -> InputShaper: ...
    @property
    def kind(self) -> str: ...
    @property
    def frequency(self) -> float: ...
    @property
    def damping(self) -> float: ...
    @property
    def amplitudes(self) -> npt.NDArray[np.float64]: ...
    @property
    def times(self) -> npt.NDArray[np.float64]: ...
    def residual_vibration(self, frequency: float, damping: float = 0.0) -> float: ...

# ---- simulation (crates/spacearm-py/src/simulate_py.rs) --------------------------------------
# ---- results of a run (crates/spacearm-py/src/records_py.rs) ------------------------------------
#: A recorded array: float64, or float32 when the run asked for it (``t`` is always float64).
_Record = npt.NDArray[Any]

@final
class RunRecords:
    """The recorded samples of a run, one row per sample: ``(K, ...)`` for one run, ``(B, K, ...)``
    in a ``RolloutBatch``. Vectors in the inertial frame, SI units. ``t``, ``x``, ``u`` are
    always there; a record the run did not make is ``None``; ``fields`` names those it made."""
    @property
    def fields(self) -> tuple[str, ...]: ...
    def to_dict(self) -> dict[str, _Record]: ...  # {name: array} for each of fields, no copy
    t: _Record                              # (K,) sample times, s (float64)
    x: _Record                              # (K, 7+N) [r0, quat0 (x, y, z, w), q]
    u: _Record                              # (K, 6+N) [v0, w0, qd]
    du: Optional[_Record]                   # (K, 6+N) accelerations
    tau: Optional[_Record]                  # (K, N) applied joint torques, N·m (N prismatic)
    tau_cmd: Optional[_Record]              # (K, N) commanded joint torques, before the limits
    base_wrench: Optional[_Record]          # (K, 6) applied [F0, N0] at the base CM, N, N·m
    P: Optional[_Record]                    # (K, 3) linear momentum, kg·m/s
    L_origin: Optional[_Record]             # (K, 3) angular momentum about the origin, kg·m²/s
    L_com: Optional[_Record]                # (K, 3) angular momentum about the system CM, kg·m²/s
    energy: Optional[_Record]               # (K,) mechanical energy (kinetic + joint springs), J
    com: Optional[_Record]                  # (K, 3) system CM, m
    ee_position: Optional[_Record]          # (K, 3) end-effector position, m (robots with an end effector)
    ee_quat: Optional[_Record]              # (K, 4) end-effector attitude [x, y, z, w]
    reference: Optional[_Record]            # (K, R) the controller's reference
    tracking_error: Optional[_Record]       # (K,) |reference − actual|, rad or m (RunMeta.tracking_error_kind)
    link_tracking_error: Optional[_Record]  # (K,) compliant joints, joint controller: |q_ref − (θ + δ)|, rad
    attitude_error: Optional[_Record]       # (K,) base attitude error of an attitude controller, rad
    wheel_speed: Optional[_Record]          # (K, W) reaction-wheel speeds, rad/s (RunMeta.wheel_dofs)
    solve_time: Optional[_Record]           # (K,) MPC law: wall-clock time of the solve behind the held command, s
    solve_iterations: Optional[_Record]     # (K,) MPC law: that solve's iterations
    solve_cost: Optional[_Record]           # (K,) MPC law: that solve's cost
    solve_converged: Optional[_Record]      # (K,) MPC law: 1 if that solve converged, else 0
    cmg_measure: Optional[_Record]          # (K,) CMGs on the base: the cluster's singularity measure det(A Aᵀ)/h̄⁶
    cmg_envelope_fraction: Optional[_Record]  # (K,) CMGs on the base: fraction of the momentum envelope used, |H|/σ(Ĥ)
    r_cm_eci: Optional[_Record]             # (K, 3) orbital runs: system CM in ECI, m (float64)
    v_cm_eci: Optional[_Record]             # (K, 3) orbital runs: system CM velocity in ECI, m/s (float64)
    gravity_wrench: Optional[_Record]       # (K, 6) orbital runs: total tidal [force; torque about the origin], N, N·m
    contact_count: Optional[_Record]        # (K,) with contact: contacts touching or interpenetrating
    contact_normal_force: Optional[_Record] # (K,) with contact: sum of the normal forces, N
    contact_work: Optional[_Record]         # (K,) with contact: work of the contact forces since t = 0, J
    contact_forces: Optional[_Record]       # (R, 13) with contact: per acting contact per sample [k, body_a, body_b, p, n, f_n, f on body_b]
    contact_impulse: Optional[_Record]      # (K, 3) rigid contact: impulses received by the second bodies since t = 0, N·s

@final
class RunEvents:
    """The saturation onsets of a run (E events, in time order)."""
    saturation_t: npt.NDArray[np.float64]        # (E,) start of the step in which it began, s
    saturation_actuator: npt.NDArray[np.int64]   # (E,) dof 0..N, then thruster channels N..N+6
    saturation_kind: npt.NDArray[np.int64]       # (E,) 0 joint torque, 1 joint speed, 2 thruster
    def to_dict(self) -> dict[str, npt.NDArray[Any]]: ...  # the three arrays by name, no copy

@final
class ConservedDrift:
    """The drift of one quantity the run's mode conserves."""
    quantity: str    # "P", "L_origin", "L_com" or "energy"
    drift: float     # largest deviation from the initial value / max(|initial|, scale)
    scale: float     # the magnitude the drift is measured against (the quantity's unit)

@final
class RunMeta:
    """The description of a run."""
    mode: str
    integrator: str
    dt: float
    rtol: float
    atol: float
    controller: str
    drift: list[ConservedDrift]            # one per conserved quantity (per balanced one when balance), in the mode's order
    balance: bool                          # drift holds balance residuals: an orbital run with the gravity gradient
    stop: Optional[tuple[int, str, float, float]]  # the stop condition that ended the run: (index, kind, t, value); None: its duration
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
    goal_distance: float | None            # RMRC at the final sample: |p_ref - p|, m
    goal_sigma_min: float | None           # ... the smallest singular value of its task Jacobian
    goal_unreachable: bool | None          # ... stopped short with its damping active
    # The run-description dict of docs/simulation.md (Trajectory.meta less duration and robot).
    def to_dict(self) -> dict[str, Any]: ...

@final
class RunResult:
    """One run (what [`simulate`][spacearm.simulate] and ``Simulator.result`` return)."""
    records: RunRecords
    events: RunEvents
    meta: RunMeta
    # A run with a free target or topology events: target (K, 13), attached (K,), phase (K,),
    # ledger_momentum (K, 6), ledger_energy (K,), event_* (E, ...), event_body, final_model.
    topology: Optional[dict[str, Any]]

@final
class RolloutBatch:
    """B rollouts (what [`rollout`][spacearm.rollout] returns); a failed rollout has NaN rows and ``None``
    meta and events."""
    records: RunRecords                    # (B, K, ...); only t, x, u when every rollout failed
    ok: npt.NDArray[np.bool_]              # (B,)
    reason: list[Optional[str]]            # the error message of each failed rollout
    error_class: list[Optional[str]]       # its spacearm.errors class name
    meta: list[Optional[RunMeta]]
    events: list[Optional[RunEvents]]

def simulate(
    model: Model,
    x0: _ArrayLike,
    u0: _ArrayLike,
    duration: float,
    options: RunOptions,
    controller_spec: Optional[ControllerSpec] = None,
    events: Optional[Any] = None,
    target: Optional[Model] = None,
    target_state: Optional[_ArrayLike] = None,
) -> RunResult:
    """Run the native simulation loop (None: no control), the core's one entry: the robot alone,
    a free ``target`` at ``target_state`` (13) in the loop of the options' contact, topology
    ``events`` (the core's ``TopologyEvent`` as plain data; docs/events.md), or both. Runs without
    the GIL; the records are handed to numpy without a copy. Returns the records, saturation
    onsets and description of the run; with a second system its rows, the ledger and the events
    as ``RunResult.topology``."""
    ...

def rollout(
    models: list[Model],
    x0: _Vec,
    u0: _Vec,
    duration: float,
    options: RunOptions,
    controllers: Optional[Union[ControllerSpec, list[ControllerSpec]]] = None,
    threads: Optional[int] = None,
    stop: Optional[Any] = None,
) -> RolloutBatch:
    """Run B rollouts on native threads without the GIL (crates/spacearm-py/src/rollout_py.rs).
    ``models``: one model or one per rollout; ``x0`` (B, 7+N), ``u0`` (B, 6+N) float64;
    ``options`` as for [`simulate`][spacearm.simulate] (``progress`` ignored); ``controllers``: one spec (a
    controller built per rollout) or a list of B. Returns the records with a leading B axis (NaN rows for
    a failed rollout) and each rollout's status, description and saturation onsets."""
    ...

@final
class Simulator:
    """RK4 stepping of a plant from Python (crates/spacearm-py/src/simulator_py.rs)."""

    def __new__(cls, model: Model, options: RunOptions, controller_spec: Optional[ControllerSpec] = None, record_every: Optional[int] = None) -> Simulator: ...
    def reset(self, x0: _ArrayLike, u0: _ArrayLike) -> None: ...
    def step(self, tau: Optional[_ArrayLike] = None, n: Optional[int] = None, base_wrench: Optional[_ArrayLike] = None) -> _Vec: ...
    def command(self, t: float, x: _ArrayLike, u: _ArrayLike) -> tuple[_Vec, _Vec]: ...
    @property
    def time(self) -> float: ...
    @property
    def state(self) -> _Vec: ...
    @property
    def n_steps(self) -> int: ...
    def result(self) -> RunResult: ...

@final
class BatchSimulator:
    """B plants stepped one call at a time on native threads, the GIL released
    (crates/spacearm-py/src/batch_simulator_py.rs over sim/batch_stepper.rs)."""

    def __new__(cls, models: list[Model], x0: _ArrayLike, u0: _ArrayLike, options: RunOptions, threads: Optional[int] = None) -> BatchSimulator: ...
    @staticmethod
    def admit(model: Model, copies: int) -> None: ...
    def __len__(self) -> int: ...
    def reset(self, index: int, x0: _ArrayLike, u0: _ArrayLike, model: Optional[Model] = None) -> None: ...
    def step(self, tau: _ArrayLike, base_wrench: Optional[_ArrayLike] = None, n: int = 1) -> npt.NDArray[np.float64]: ...
    @property
    def states(self) -> npt.NDArray[np.float64]: ...
    @property
    def times(self) -> _Vec: ...
    @property
    def n_steps(self) -> list[int]: ...

def perturbed(
    model: Model,
    base_mass_scale: float,
    base_inertia_scale: float,
    link_mass_scale: float,
    slosh_fraction: float,
    slosh_offset: _ArrayLike,
    slosh_removed: bool,
) -> Model: ...
def perturbed_cmgs(model: Model, rotor_inertia_scale: float, tilts: Sequence[Sequence[float]]) -> Model: ...
def default_wheel_dofs(model: Model) -> list[int]: ...
def conserved_drift(values: npt.NDArray[np.float64], scale: float) -> float:
    """max_k |v_k - v_0| / max(|v_0|, scale)."""
@final
class Derivatives:
    """Exact derivatives of one model (analytic recursions for the dynamics Jacobians,
    forward-mode dual numbers for the others, and for ``dual=True``); tensors of partials have
    the derivative index last. Tangent coordinates ``[dr0, dtheta, dq]``."""

    def __new__(cls, model: Model) -> Derivatives: ...
    def mass_matrix_partials(self, x: _ArrayLike) -> npt.NDArray[np.float64]: ...
    def mass_matrix_derivative(self, x: _ArrayLike, u: _ArrayLike) -> _Vec: ...
    def generalized_inertia_partials(self, x: _ArrayLike) -> npt.NDArray[np.float64]: ...
    def generalized_inertia_derivative(self, x: _ArrayLike, u: _ArrayLike) -> _Vec: ...
    def generalized_jacobian_partials(self, x: _ArrayLike, body: int, offset: _ArrayLike) -> npt.NDArray[np.float64]: ...
    def generalized_jacobian_derivative(self, x: _ArrayLike, u: _ArrayLike, body: int, offset: _ArrayLike) -> _Vec: ...
    def forward_dynamics_derivatives(
        self, x: _ArrayLike, u: _ArrayLike, f: _ArrayLike, wrenches: Optional[list[_Wrench]] = None, dual: bool = False
    ) -> tuple[_Vec, _Vec, _Vec]: ...
    def forward_dynamics_derivatives_tau(
        self,
        x: _ArrayLike,
        u: _ArrayLike,
        tau: Optional[_ArrayLike] = None,
        base_wrench: Optional[_ArrayLike] = None,
        wrenches: Optional[list[_Wrench]] = None,
        dual: bool = False,
    ) -> tuple[_Vec, _Vec, _Vec]: ...
    def inverse_dynamics_partials(
        self, x: _ArrayLike, u: _ArrayLike, du: _ArrayLike, wrenches: Optional[list[_Wrench]] = None, dual: bool = False
    ) -> tuple[_Vec, _Vec]: ...
    def linearize(self, x: _ArrayLike, u: _ArrayLike, f: _ArrayLike, joints_only: bool, dual: bool = False) -> tuple[_Vec, _Vec]: ...

# --- orbits (orbit_py.rs; docs/orbit.md) ---

@final
class CentralBody:
    """A central body's gravity constants: mu (m^3/s^2), equatorial radius (m), J2."""
    def __new__(cls, *, mu: float, radius: float, j2: float) -> CentralBody: ...
    @staticmethod
    def earth() -> CentralBody: ...
    @property
    def mu(self) -> float: ...
    @property
    def radius(self) -> float: ...
    @property
    def j2(self) -> float: ...

@final
class OrbitalElements:
    """Osculating two-body elements: a (m), e, i, raan, argp, true_anomaly (rad)."""
    @property
    def a(self) -> float: ...
    @property
    def e(self) -> float: ...
    @property
    def i(self) -> float: ...
    @property
    def raan(self) -> float: ...
    @property
    def argp(self) -> float: ...
    @property
    def true_anomaly(self) -> float: ...

@final
class Orbit:
    """An orbit: central body, J2 on or off, ECI state at t = 0."""
    @staticmethod
    def circular(
        altitude: float,
        *,
        inclination: float = 0.0,
        raan: float = 0.0,
        arg_latitude: float = 0.0,
        body: str | CentralBody | None = None,
        j2: bool = False,
    ) -> Orbit: ...
    @staticmethod
    def from_elements(
        a: float,
        e: float,
        i: float,
        raan: float,
        argp: float,
        true_anomaly: float,
        *,
        body: str | CentralBody | None = None,
        j2: bool = False,
    ) -> Orbit: ...
    @staticmethod
    def from_state(r: _ArrayLike, v: _ArrayLike, *, body: str | CentralBody | None = None, j2: bool = False) -> Orbit: ...
    @property
    def body(self) -> CentralBody: ...
    @property
    def j2(self) -> bool: ...
    @property
    def r0(self) -> _Vec: ...
    @property
    def v0(self) -> _Vec: ...
    def elements(self) -> OrbitalElements: ...
    @property
    def mean_motion(self) -> float: ...
    @property
    def period(self) -> float: ...
    def j2_secular_rates(self) -> tuple[float, float]: ...
    def propagate(self, times: _ArrayLike, *, rtol: float = 1e-12) -> tuple[_Vec, _Vec]: ...
    @staticmethod
    def lvlh_to_eci(r: _ArrayLike, v: _ArrayLike) -> _Vec: ...
    def relative_motion(self, rel0: _ArrayLike, times: _ArrayLike, *, rtol: float = 1e-12) -> _Vec: ...
    def clohessy_wiltshire(self, rel0: _ArrayLike, times: _ArrayLike) -> _Vec: ...
    def safety_ellipse(self, radial: float, *, cross_track: float = 0.0, along_track: float = 0.0) -> _Vec: ...
    def lvlh_to_run(self, rel: _ArrayLike, *, center: _ArrayLike | None = None, t: float = 0.0) -> _Vec: ...
    def run_to_lvlh(self, t: _ArrayLike, center: _ArrayLike, points: _ArrayLike) -> _Vec: ...
    def tidal_torques(self, model: Union[Model, Any], x: _ArrayLike, *, t: float = 0.0) -> tuple[_Vec, _Vec, _Vec]: ...

# ---- collision detection (crates/spacearm-py/src/collision_py.rs; spacearm_core::collision) --------
@final
class Contact:
    """A contact between two collision shapes at one state, in the inertial frame."""

    @property
    def geometries(self) -> tuple[str, str]: ...
    @property
    def bodies(self) -> tuple[str, str]: ...
    @property
    def point_a(self) -> _Vec: ...
    @property
    def point_b(self) -> _Vec: ...
    @property
    def normal(self) -> _Vec: ...
    @property
    def distance(self) -> float: ...

def contacts(model: Model, x: _ArrayLike, pairs: Optional[Sequence[tuple[str, str]]] = None, margin: float = 0.0) -> list[Contact]: ...

@final
class RigidImpact:
    """The velocity jump of a rigid frictional impact (docs/contact.md, "Rigid frictional impacts")."""

    @property
    def u_after(self) -> _Vec: ...  # (6+N,)
    @property
    def du(self) -> _Vec: ...  # (6+N,) H^-1 J^T lambda
    @property
    def impulse(self) -> _Vec: ...  # (k, 3) [t1, t2, n] of each contact frame
    @property
    def impulse_world(self) -> _Vec: ...  # (k, 3) on each second body, in the inertial frame
    @property
    def velocity_before(self) -> _Vec: ...  # (k, 3) J u-
    @property
    def velocity_after(self) -> _Vec: ...  # (k, 3) J u+
    @property
    def frames(self) -> _Vec: ...  # (k, 3, 3) columns t1, t2, n
    @property
    def jacobian(self) -> _Vec: ...  # (3k, 6+N)
    @property
    def delassus(self) -> _Vec: ...  # (3k, 3k) J H^-1 J^T
    @property
    def solver(self) -> str: ...
    @property
    def converged(self) -> bool: ...
    @property
    def iterations(self) -> int: ...
    @property
    def residual(self) -> float: ...
    @property
    def dual_feasibility(self) -> float: ...
    @property
    def complementarity(self) -> float: ...

@final
class GraspOutcome:
    """Whether a gripper held, slipped or missed a target's handle (docs/contact.md, "The grasp's outcome")."""

    @property
    def outcome(self) -> str: ...  # "held", "slipped" or "missed"
    @property
    def held(self) -> bool: ...
    @property
    def reason(self) -> str: ...
    @property
    def relative_spin(self) -> float: ...  # rad/s, the window's largest
    @property
    def relative_speed(self) -> float: ...  # m/s
    @property
    def offset(self) -> float: ...  # m
    @property
    def fingers_touching(self) -> int: ...
    @property
    def fingers(self) -> int: ...
    @property
    def first_touch(self) -> Optional[float]: ...
    @property
    def touching_samples(self) -> int: ...
    @property
    def window_start(self) -> float: ...
    @property
    def window_samples(self) -> int: ...
    @property
    def window(self) -> float: ...
    @property
    def max_relative_spin(self) -> float: ...
    @property
    def max_relative_speed(self) -> float: ...
    @property
    def max_offset(self) -> float: ...
    @property
    def touch_margin(self) -> float: ...

def grasp_outcome(
    robot: Model,
    target: Model,
    gripper: str,
    handle: str,
    t: _ArrayLike,
    x: _ArrayLike,
    u: _ArrayLike,
    target_state: _ArrayLike,
    *,
    window: float = 0.5,
    max_relative_spin: float = 0.005,
    max_relative_speed: float = 0.005,
    max_offset: float = 0.005,
    touch_margin: float = 0.001,
) -> GraspOutcome: ...
def success_rate(successes: int, trials: int, z: float = 1.959963984540054) -> tuple[float, float, float]: ...

def rigid_impact(
    model: Model,
    x: _ArrayLike,
    u_before: _ArrayLike,
    points: Sequence[tuple[str, str, _ArrayLike, _ArrayLike, float]],
    *,
    solver: str = "admm",
    restitution: float = 0.0,
    tolerance: float = 1e-10,
    max_iterations: int = 1000,
    proximal: float = 1e-8,
) -> RigidImpact: ...
