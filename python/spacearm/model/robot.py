"""The [`Robot`][spacearm.Robot]: a validated spacecraft-manipulator model and every quantity of the
Generalized Jacobian Matrix formulation.

Conventions (``docs/conventions.md``): SI units; vectors in the inertial frame
𝒥 unless a name says otherwise; configuration ``x = [r0 (3), quat0 (4, [x, y, z, w]), q (N)]``
with ``r0`` the base CM; generalized velocity ``u = [v0 (3), w0 (3), qd (N)]`` with ``v0`` the
base CM velocity and ``w0`` the base angular velocity, both in 𝒥; generalized force
``f = [F0 (3), N0 (3), tau (N)]`` (force at the base CM, torque about it, in 𝒥; joint torques).
EOM: ``H(x) du + c(x, u) = f + J^T w_ext``. Equation numbers refer to Wilde, Kwok Choon,
Grompone & Romano (2018), Front. Robot. AI 5:41 ("the paper").

Batches (``docs/batch.md``): every per-state method also takes a batch of states, ``x`` of shape
``(B, 7+N)`` (and ``u``, ``f``, ``tau``, ``du``, ``qd`` with ``B`` rows, or one row used for every
state), and returns its results with a leading axis of length ``B``; the rows are computed in
parallel in the extension with the GIL released, bit-identical to one call per state.
"""

from __future__ import annotations

import os
import sys
import warnings
from dataclasses import dataclass
from typing import NamedTuple, Sequence, Union

import numpy as np

from .. import _core
from .._util.arrays import finite, matrix3, number, quaternion, real_array, vector, vector3
from .description import ModelDescription
from ..errors import ArgumentError, NonPhysicalInertiaWarning, NotFoundError, ShapeError, SpacearmTypeError

__all__ = ["Robot", "ExternalWrench", "Kinematics", "Momentum", "InertiaBlocks", "ForwardDynamicsDerivatives", "Linearization", "PassiveModes"]

PointLike = Union[str, tuple, None]


@dataclass(frozen=True)
class ExternalWrench:
    """A force and torque, both in 𝒥, applied at a point fixed to a body.

    ``body`` is a body name or index (0 = base); ``offset`` is the application point in that
    body's frame (from its CM). Its generalized force is ``J_X^T [force; torque]``.
    """

    body: Union[str, int]
    force: Sequence[float] = (0.0, 0.0, 0.0)
    torque: Sequence[float] = (0.0, 0.0, 0.0)
    offset: Sequence[float] = (0.0, 0.0, 0.0)


class Kinematics(NamedTuple):
    """Forward kinematics, one row per body (row 0 = base)."""

    body_to_world: np.ndarray  #: (n_bodies, 3, 3) rotation of each body frame to 𝒥
    com_in_world: np.ndarray  #: (n_bodies, 3) CM positions r_i
    joint_position_in_world: np.ndarray  #: (n_bodies, 3) joint positions p_i (row 0: r0)
    joint_axis_in_world: np.ndarray  #: (n_bodies, 3) unit joint axes k_i (zero: base, fixed)


class Momentum(NamedTuple):
    """Linear momentum and angular momentum about three points (``docs/conventions.md``)."""

    P: np.ndarray  #: linear momentum, N·s
    L_origin: np.ndarray  #: about the origin of 𝒥 (conserved with no external wrench)
    L_base: np.ndarray  #: about the base CM (lower half of H0 xd0 + H0m qd, eq. 42)
    L_com: np.ndarray  #: about the system CM


class InertiaBlocks(NamedTuple):
    """The paper's inertia blocks (eqs. 27–36), in 𝒥 about the base CM."""

    M: float  #: total mass
    r_0g: np.ndarray  #: base CM to system CM
    H_S: np.ndarray  #: 3×3, eq. 29
    J_TS: np.ndarray  #: 3×N, eq. 32
    H_Sq: np.ndarray  #: 3×N, eq. 33
    H0: np.ndarray  #: 6×6 base inertia, eq. 30
    H0m: np.ndarray  #: 6×N coupling inertia, eq. 31
    Hm: np.ndarray  #: N×N manipulator inertia, eq. 34
    H: np.ndarray  #: (6+N)² full mass matrix, eq. 36


def _frozen(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


class Robot:
    """A spacecraft base carrying a tree of links (one or more arms).

    Build one with [`Robot.builder`][spacearm.Robot.builder], a preset from [`spacearm.presets`][spacearm.presets], or a loader of
    [`spacearm.io`][spacearm.io] (``load_toml``, ``loads_toml``, ``load_urdf``, ``robot_from_dh``: they
    live in ``io/``, a layer above this one, which imports nothing from above). A ``Robot`` is
    immutable; its methods are functions of the state passed in.
    """

    def __init__(self, core_model: "_core.Model"):
        if not isinstance(core_model, _core.Model):
            raise SpacearmTypeError("Robot is built with Robot.builder(), spacearm.presets, or spacearm.io "
                                    "(load_toml, loads_toml, load_urdf, robot_from_dh)")
        self._m = core_model
        # Named points resolved once (the model is immutable): name or None -> (body, offset).
        self._points = {}
        # The repr, made once: it must work even while a call into the extension holds the
        # model (an error message that shows a Robot passed where an array was expected).
        self._repr = (f"<Robot '{core_model.name}': {core_model.n_bodies} bodies, N = {core_model.n_dof}, "
                      f"total mass {core_model.total_mass:.6g} kg>")

    # ---- construction -------------------------------------------------------------------
    @staticmethod
    def builder(name: str, base_mass: float, base_inertia, base_name: str = "base", *, allow_nonphysical_inertia: bool = False):
        """Start building a model: see [`spacearm.model.builder.RobotBuilder`][spacearm.RobotBuilder]."""
        from .builder import RobotBuilder

        return RobotBuilder(name, base_mass, base_inertia, base_name=base_name, allow_nonphysical_inertia=allow_nonphysical_inertia)

    def to_builder(self, name=None):
        """A [`RobotBuilder`][spacearm.RobotBuilder] holding this model exactly, to edit
        (add or remove bodies, attach a payload) and build into a new Robot; this one is unchanged."""
        from .builder import RobotBuilder

        return RobotBuilder.from_robot(self, name=name)

    # ---- editing (the core's model/edit.rs: one validation, the rest of the model bit for bit) --
    def attach_body(self, name: str, *, body: str, mass: float, inertia=(0.0, 0.0, 0.0), origin=(0.0, 0.0, 0.0),
                    rotation=None, rpy=None, joint: str = "fixed", axis=(0.0, 0.0, 1.0), com=(0.0, 0.0, 0.0),
                    joint_name=None, limits=None, actuated: bool = True, stiffness: float = 0.0, damping: float = 0.0,
                    rest: float = 0.0, model_name=None) -> "Robot":
        """A new Robot: this one with the body ``name`` attached to ``body``; this one is unchanged.

        By default a rigid payload (``joint="fixed"``): its CM at ``origin`` in ``body``'s frame
        (from its CM, m), its axes at ``rotation`` (quaternion ``[x, y, z, w]`` or scipy
        ``Rotation``) or ``rpy``, ``inertia`` about its CM in its own axes (3×3 or the diagonal;
        default 0, a point mass). With ``joint="revolute"`` or ``"prismatic"`` the joint sits at
        ``origin`` about or along ``axis`` and the CM is at ``com`` from it; ``limits``,
        ``actuated``, ``stiffness``, ``damping``, ``rest`` as in
        [`RobotBuilder.add_link`][spacearm.RobotBuilder.add_link] (a new joint's initial ``q``
        is its ``rest``). Every other body, joint, point, shape and initial ``q`` is kept bit for
        bit. ``model_name`` renames the result.
        """
        from .builder import RobotBuilder, frame_rotation, link_limits

        who = f"link '{name}'"
        dynamics = RobotBuilder._joint_dynamics(name, actuated, stiffness, damping, rest)
        core = _core.model_attach_body(
            self._m, str(name), str(body), list(vector(origin, f"{who} origin", 3)), list(frame_rotation(rotation, rpy, who)),
            number(mass, f"{who} mass"), matrix3(inertia, f"{who} inertia"),
            joint_type=str(joint), axis=list(vector(axis, f"{who} axis", 3)), com=list(vector(com, f"{who} com", 3)),
            joint_name=None if joint_name is None else str(joint_name), limits=link_limits(name, limits), dynamics=dynamics,
            model_name=None if model_name is None else str(model_name))
        return self._edited(core)

    def attach(self, other: "Robot", *, body: str, origin=(0.0, 0.0, 0.0), rotation=None, rpy=None,
               prefix: Union[str, None] = None, name: Union[str, None] = None, model_name=None) -> "Robot":
        """A new Robot: this one with the whole model ``other`` attached to ``body``; both are unchanged.

        ``other``'s base becomes the link ``name`` (default ``<prefix><other's base name>``) on a
        fixed joint, its CM at ``origin`` and its axes at ``rotation`` (or ``rpy``) in ``body``'s
        frame; its links follow with their joints, limits, passive dynamics and initial ``q``
        (appended to this one's), its points and shapes ride along, every name it brings
        prefixed by ``prefix`` (default ``"<other's name>_"``) so that nothing clashes; its end
        effector is not carried (this model keeps its own). This model's part is kept bit for
        bit. A rigid grasp is this edit ([`attach_target`][spacearm.capture.attach_target]).
        """
        if not isinstance(other, Robot):
            raise SpacearmTypeError(f"attach needs a spacearm.Robot to attach, got {type(other).__name__}")
        from .builder import frame_rotation

        prefix = f"{other.name}_" if prefix is None else str(prefix)
        core = _core.model_attach_model(
            self._m, other._m, str(body), list(vector(origin, "attach origin", 3)),
            list(frame_rotation(rotation, rpy, f"link '{other.name if name is None else name}'")), prefix,
            base_link=None if name is None else str(name), model_name=None if model_name is None else str(model_name))
        return self._edited(core)

    def remove_subtree(self, body: str, *, model_name=None) -> "Robot":
        """A new Robot: this one without the link ``body``, every link below it, and the points
        and shapes on them (the end effector too when it is one of them); the other links keep
        their order, parts and initial ``q`` bit for bit. The base cannot be removed
        (``ModelError``); an unknown name is a ``ModelError`` listing the links."""
        core = _core.model_remove_subtree(self._m, str(body), model_name=None if model_name is None else str(model_name))
        return self._edited(core)

    def _edited(self, core_model) -> "Robot":
        """The Robot of an edit of this one, warning about the bodies it added that break the
        triangle inequality (this model's own warnings were given when it was made)."""
        robot = Robot(core_model)
        known = set(self.inertia_warnings)
        return warn_nonphysical_inertia(robot, [w for w in robot.inertia_warnings if w not in known])

    # ---- description --------------------------------------------------------------------
    @property
    def core_model(self) -> "_core.Model":
        """The extension's model (``spacearm._core.Model``) this Robot wraps: the one accessor
        for the package's modules that hand the model to a core function or spec
        (``_core.simulate``, ``_core.Simulator``, the analyses, ``_core.model_to_toml``);
        ``Robot(robot.core_model)`` is an equal Robot. Everything else goes through the Robot's
        own methods.

        A read-only property rather than a function in ``model/``: the handle is what a Robot
        is made of (the constructor's one argument, what a pickle carries), the core's Model is
        immutable (no method changes it), so handing it out cannot change the Robot, and one
        named property is easy to find and to grep for (``tests/test_import_graph.py`` refuses
        ``._m`` outside ``model/``)."""
        return self._m

    @property
    def name(self) -> str:
        return self._m.name

    @property
    def n_dof(self) -> int:
        """Number of joint degrees of freedom ``N``."""
        return self._m.n_dof

    @property
    def n_bodies(self) -> int:
        """Number of bodies including the base."""
        return self._m.n_bodies

    @property
    def nx(self) -> int:
        """Length of the configuration ``x``: ``7 + N``."""
        return 7 + self._m.n_dof

    @property
    def nu(self) -> int:
        """Length of the generalized velocity ``u``: ``6 + N``."""
        return 6 + self._m.n_dof

    @property
    def actuated_dofs(self) -> np.ndarray:
        """``(N,)`` bool: whether each joint coordinate has a motor (``False``: a passive joint,
        which the simulator gives no torque; docs/flexibility.md)."""
        return np.array(self._m.actuated_dofs, dtype=bool)

    @property
    def total_mass(self) -> float:
        return self._m.total_mass

    @property
    def allows_nonphysical_inertia(self) -> bool:
        """Whether the model was loaded with ``allow_nonphysical_inertia=True`` (inertias that
        break the triangle inequality accepted; edited copies keep the choice)."""
        return self._m.allows_nonphysical_inertia

    @property
    def inertia_warnings(self) -> list:
        """One message per body whose inertia breaks the triangle inequality (empty unless
        the model was loaded with ``allow_nonphysical_inertia=True``)."""
        return list(self._m.inertia_warnings)

    @property
    def body_names(self) -> list:
        return list(self._m.body_names)

    @property
    def point_names(self) -> list:
        return list(self._m.point_names)

    @property
    def end_effector(self):
        """Name of the end-effector point, or ``None``."""
        return self._m.end_effector

    @property
    def initial_q(self) -> np.ndarray:
        return self._m.initial_q

    @property
    def joint_types(self) -> list:
        """Joint type of each LINK, in link order (length ``n_bodies - 1``), fixed joints
        included: ``"revolute"``, ``"prismatic"`` or ``"fixed"``. It does not line up with ``q``
        when the model has fixed joints; for one entry per degree of freedom use
        [`dof_types`][spacearm.Robot.dof_types] and [`joint_names`][spacearm.Robot.joint_names]."""
        return list(self._m.joint_types())

    @property
    def joint_names(self) -> list:
        """Name of the joint of each degree of freedom, in ``q`` order (length ``N``; fixed
        joints excluded): ``q[k]``, ``qd[k]`` and ``tau[k]`` belong to ``joint_names[k]``."""
        return [name for name, _ in self._dofs()]

    @property
    def dof_types(self) -> list:
        """Type of each degree of freedom, in ``q`` order (length ``N``): ``"revolute"`` (rad,
        N·m) or ``"prismatic"`` (m, N). Unlike [`joint_types`][spacearm.Robot.joint_types], fixed joints are excluded."""
        return [kind for _, kind in self._dofs()]

    def _dofs(self) -> tuple:
        """``(joint name, joint type)`` of each degree of freedom in ``q`` order, read once from
        the model's description (the model is immutable)."""
        dofs = self.__dict__.get("_dof_joints")
        if dofs is None:
            links = sorted((link for link in self.description.links if link.dof is not None), key=lambda link: link.dof)
            dofs = self._dof_joints = tuple((link.joint, link.type) for link in links)
        return dofs

    @property
    def wheel_dofs(self) -> list:
        """The degrees of freedom the simulation treats as reaction wheels by default (the
        core's rule: a revolute joint on the base whose link has no children and a rotor
        symmetric about the axis, i.e. what [`RobotBuilder.add_reaction_wheel`][spacearm.RobotBuilder.add_reaction_wheel] creates)."""
        return sorted(int(d) for d in _core.default_wheel_dofs(self._m))

    @property
    def cmg_dofs(self) -> dict:
        """The control-moment gyros of the model (docs/cmg.md; the core's ``model/cmg.rs``
        recognizes what [`RobotBuilder.add_cmg`][spacearm.RobotBuilder.add_cmg] and TOML ``[[cmg]]`` make), by name in
        link order: each a dict with ``gimbal`` and ``rotor`` (their degrees of freedom in ``q``),
        ``gimbal_axis`` and ``spin_axis`` (parent frame, at zero gimbal angle), ``rotor_inertia``
        (kg·m²), ``variable_speed`` (the rotor has a motor), ``max_gimbal_rate`` and
        ``max_wheel_speed`` (rad/s, ``inf`` when unlimited)."""
        out = {}
        for c in _core.cmgs(self._m):
            out[c["name"]] = {
                "gimbal": int(c["gimbal_dof"]), "rotor": int(c["rotor_dof"]),
                "gimbal_axis": np.array(c["gimbal_axis"]), "spin_axis": np.array(c["spin_axis"]),
                "rotor_inertia": float(c["rotor_inertia"]), "variable_speed": bool(c["variable_speed"]),
                "max_gimbal_rate": float(c["max_gimbal_rate"]), "max_wheel_speed": float(c["max_wheel_speed"]),
            }
        return out

    def cmg_velocity(self, wheel_speed) -> np.ndarray:
        """The generalized velocity ``u`` (``6 + n``) with every CMG rotor spinning at
        ``wheel_speed`` rad/s (one number, or one per CMG in [`cmg_dofs`][spacearm.Robot.cmg_dofs] order) and everything
        else at rest: the ``u0`` of a run (a rotor's speed is state, not a model parameter,
        docs/cmg.md)."""
        speeds = np.atleast_1d(np.asarray(wheel_speed, dtype=float)).ravel()
        return np.array(_core.cmg_velocity(self._m, [float(v) for v in speeds]))

    @property
    def arm_dofs(self) -> list:
        """Every degree of freedom that is not a default reaction wheel ([`wheel_dofs`][spacearm.Robot.wheel_dofs]) nor
        a CMG's gimbal or rotor ([`cmg_dofs`][spacearm.Robot.cmg_dofs]), in ``q`` order: the joints the arm controllers
        of [`spacearm.control`][spacearm.control] act on."""
        wheels = set(self.wheel_dofs) | {d for c in self.cmg_dofs.values() for d in (c["gimbal"], c["rotor"])}
        return [d for d in range(self.n_dof) if d not in wheels]

    @property
    def actuated_arm_dofs(self) -> list:
        """The [`arm_dofs`][spacearm.Robot.arm_dofs] that have a motor ([`actuated_dofs`][spacearm.Robot.actuated_dofs]), in ``q`` order:
        the joints a joint reference of [`JointPD`][spacearm.control.JointPD] or [`ComputedTorque`][spacearm.control.ComputedTorque] has
        one entry for (the passive joints are not commanded, docs/flexibility.md)."""
        actuated = self.actuated_dofs
        return [d for d in self.arm_dofs if actuated[d]]

    @property
    def body_of_dof(self) -> list:
        """Body index moved by each degree of freedom."""
        return list(self._m.body_of_dof)

    @property
    def description(self) -> ModelDescription:
        """The model's parameters, typed, with each field's frame and unit
        ([`ModelDescription`][spacearm.ModelDescription]); built once (the model is immutable)."""
        desc = self.__dict__.get("_description")
        if desc is None:
            desc = self._description = self._m.describe()
        return desc

    def describe(self) -> dict:
        """The model as plain Python data (base, links in tree order, points): a new dict at
        each call. [`description`][spacearm.Robot.description] is the typed form of the same data."""
        return self.description.to_dict()

    def body_index(self, body: Union[str, int]) -> int:
        """Index of a body given by name or index (0 = base); a bool or any other type is a
        [`SpacearmTypeError`][spacearm.errors.SpacearmTypeError] (``True`` is not body 1)."""
        if isinstance(body, (bool, np.bool_)) or not isinstance(body, (str, int, np.integer)):
            raise SpacearmTypeError(f"body must be a body name (str) or index (int), got {type(body).__name__} {body!r:.60}")
        if isinstance(body, (int, np.integer)):
            if not 0 <= int(body) < self.n_bodies:
                raise NotFoundError(f"body index {body} does not exist (the model has bodies 0..{self.n_bodies - 1})")
            return int(body)
        return self._m.body_index(str(body))

    def resolve_point(self, point: PointLike = None) -> tuple:
        """``(body index, offset)`` of a point, the form every point-taking core call uses:
        ``None`` (the end effector), a point name, a body name (its CM: zero offset), or
        ``(body, offset)`` with ``offset`` in the body's frame from its CM (m). A named point's
        offset is resolved once and returned read-only. Unknown names raise [`NotFoundError`][spacearm.NotFoundError]."""
        return self._point(point)

    def _point(self, point: PointLike):
        """Resolve a point: ``None`` (end effector), a point name, or ``(body, offset)``."""
        if point is None or type(point) is str:
            cached = self._points.get(point)
            if cached is None:
                cached = self._points[point] = self._resolve_point(point)
            return cached
        return self._resolve_point(point)

    def _resolve_point(self, point: PointLike):
        if point is None:
            if self.end_effector is None:
                raise NotFoundError("the model has no end effector; pass a point name or (body, offset)")
            point = self.end_effector
        if isinstance(point, str):
            if point in self._m.point_names:
                body, off = self._m.point(point)
                return body, _frozen(np.asarray(off, dtype=float))
            return self.body_index(point), _frozen(np.zeros(3))
        if isinstance(point, (tuple, list)) and len(point) == 2:
            return self.body_index(point[0]), vector3(point[1], "point offset")
        raise ShapeError(f"a point is a point name, a body name, or (body, offset), got {point!r}")

    def _data(self) -> str:
        """The model as the text of a model file: how a controller's own model travels in a run's
        description (``spacearm._util.spec``; bit-exact)."""
        return self._m.to_toml()

    def __reduce__(self):
        # Pickled through the extension's model (its TOML text, floats in shortest round-trip
        # form: bit-exact); caches are rebuilt on demand.
        return (Robot, (self._m,))

    def __repr__(self) -> str:
        return self._repr

    # ---- states ---------------------------------------------------------------------------
    def neutral_configuration(self, q=None, r0=(0.0, 0.0, 0.0), quat0=(0.0, 0.0, 0.0, 1.0)) -> np.ndarray:
        """Configuration ``x = [r0, quat0, q]``; ``q`` defaults to the model's initial angles.

        ``quat0`` is the base attitude, a quaternion ``[x, y, z, w]`` or a
        ``scipy.spatial.transform.Rotation``."""
        qv = self.initial_q if q is None else vector(q, "q", self.n_dof)
        x = np.concatenate([vector(r0, "r0", 3), quaternion(quat0, "quat0"), qv])
        self._m.check_configuration(x)  # finite values, unit quaternion: the core's one rule
        return x

    def zero_velocity(self) -> np.ndarray:
        """``u = 0`` (length ``6 + N``)."""
        return np.zeros(self.nu)

    # Vector arguments (x, u, du, f, tau, qd...) go to the extension unconverted: it uses a 1-D
    # contiguous float64 array in place, copies the rows of a 2-D one (a batch), and converts
    # anything else under the argument's name (real numbers only), so a Python-side conversion
    # first would only repeat the work.

    # ---- kinematics ----------------------------------------------------------------------
    def forward_kinematics(self, x) -> Kinematics:
        """Poses of every body CM frame, joint positions and joint axes in 𝒥 (paper §2)."""
        return Kinematics(*self._m.forward_kinematics(x))

    def point_position(self, x, point: PointLike = None) -> np.ndarray:
        """Position in 𝒥 of a point (default: the end effector)."""
        body, off = self._point(point)
        return self._m.point_position(x, body, off)

    def point_jacobian(self, x, point: PointLike = None):
        r"""Point Jacobians $(J_{0X}, J_{mX})$ (6×6, 6×N; eqs. 104–108) of a point: its twist
        $[v_X; \omega]$ in 𝒥 is $J_{0X}\,\dot x_0 + J_{mX}\,\dot q$."""
        body, off = self._point(point)
        return self._m.point_jacobians(x, body, off)

    def link_jacobians(self, x, body):
        """$(J_{Ti}, J_{Ri})$ (3×N each; eqs. 20–21) of the CM of ``body``."""
        return self._m.link_jacobians(x, self.body_index(body))

    # ---- inertia ---------------------------------------------------------------------------
    def inertia_blocks(self, x) -> InertiaBlocks:
        """``H0``, ``H0m``, ``Hm`` and their parts by the paper's Jacobian sums (eqs. 27–36)."""
        return InertiaBlocks(*self._m.inertia_blocks(x))

    def mass_matrix(self, x, method: str = "crba") -> np.ndarray:
        """Generalized mass matrix $H(x)$ ((6+N)², eq. 36).

        ``method="crba"`` (composite-rigid-body algorithm, Featherstone §6.2) or ``"paper"``
        (the Jacobian sums of eqs. 27–36); the two are independent computations.
        """
        if method == "crba":
            return self._m.mass_matrix_crba(x)
        if method == "paper":
            return self._m.mass_matrix_paper(x)
        raise ArgumentError(f"method must be 'crba' or 'paper', got {method!r}")

    def base_inertia_inverse(self, x) -> np.ndarray:
        """$H_0^{-1}$ by the closed-form Schur complement (eqs. 52–61)."""
        return self._m.base_inertia_inverse(x)

    # ---- dynamics --------------------------------------------------------------------------
    def bias_forces(self, x, u) -> np.ndarray:
        """Bias vector $c(x, u)$ (velocity-product terms; no gravity in orbit) by RNEA."""
        return self._m.bias_forces(x, u)

    def _wrenches(self, wrenches):
        if not wrenches:
            return None
        out = []
        for w in wrenches:
            if not isinstance(w, ExternalWrench):
                raise SpacearmTypeError(f"wrenches must be spacearm.ExternalWrench objects, got {type(w).__name__}")
            out.append((
                self.body_index(w.body),
                list(vector3(w.offset, "wrench offset")),
                list(vector3(w.force, "wrench force")),
                list(vector3(w.torque, "wrench torque")),
            ))
        return out

    def passive_forces(self, x, u) -> np.ndarray:
        r"""The joints' passive generalized force $Q = [0_6;\ -K (q - q_\text{rest}) - C \dot q]$
        (``6+N``; MuJoCo's ``qfrc_passive``), which every forward dynamics adds to the applied
        force: $H \dot u + c = f + Q$ (docs/flexibility.md)."""
        return self._m.passive_forces(x, u)

    def spring_energy(self, x) -> float:
        r"""The joint springs' potential energy $\tfrac12 \sum_j k_j (q_j - q_{\text{rest},j})^2$, J (the simulation
        records' ``energy`` is the kinetic energy plus this)."""
        return self._m.spring_energy(x)

    def natural_frequencies(self, x=None, *, actuated: str = "held") -> "PassiveModes":
        r"""The small oscillations of the joints' springs about the configuration ``x`` (default:
        the neutral configuration): the modes of $K v = \omega^2 H^*(q)\, v$ (docs/flexibility.md,
        "Natural frequencies"), ascending. ``actuated="held"``: the motors hold the actuated
        joints still and only the passive joints move; ``"free"``: every joint moves (an unsprung
        one is a mode at 0 rad/s). Exact small-oscillation frequencies where ``q`` is an
        equilibrium (the springs at ``rest``); equal there to the linearization's
        ([`linearize`][spacearm.Robot.linearize]) eigenvalues $\pm i\omega$ without damping."""
        if actuated not in ("held", "free"):
            raise ArgumentError(f"actuated must be 'held' or 'free', got {actuated!r}")
        x = self.neutral_configuration() if x is None else x
        dofs, w, zeta, shapes = self._m.passive_modes(x, actuated == "held")
        return PassiveModes(np.asarray(dofs, dtype=int), w, zeta, shapes)

    def inverse_dynamics(self, x, u, du, wrenches=None) -> np.ndarray:
        r"""Generalized force $f = H \dot u + c - Q_\text{passive} - J^T w_\text{ext}$ producing ``du`` $= \dot u$ (RNEA,
        Featherstone §5.3; ``Q_passive``: [`passive_forces`][spacearm.Robot.passive_forces])."""
        return self._m.inverse_dynamics(x, u, du, None if wrenches is None else self._wrenches(wrenches))

    def forward_dynamics(self, x, u, f=None, *, tau=None, base_wrench=None, wrenches=None, method: str = "aba") -> np.ndarray:
        r"""State derivative ``du`` $= \dot u = [\dot v_0; \dot\omega_0; \ddot q]$ under generalized force ``f``.

        Give either ``f = [F0, N0, tau]`` or ``tau`` (joint torques, default zero) and
        optionally ``base_wrench = [F0, N0]`` (default zero: free-floating); the two forms give
        bit-identical results, each in one call to the extension (which assembles ``f`` from
        the parts; ``benchmarks/forward_dynamics_forms.py`` times both).
        ``method``: ``"aba"`` (O(N) articulated-body algorithm), ``"mass_matrix"``
        ($H^{-1}(f + Q + J^T w - c)$) or ``"reduced"`` ($\ddot q = H^{*-1}(\tau + Q_m - c^* - H_{0m}^T H_0^{-1} F_b)$,
        the reduction of eqs. 39–50, ``docs/physics.md``; no external wrenches). Every method adds
        the joints' springs and dampers, ``Q`` = [`passive_forces`][spacearm.Robot.passive_forces] (docs/flexibility.md).
        """
        # One native call per form and method: x, u and the force arrays go to the extension
        # unconverted (see _x above); it checks them in the order force, x, u.
        ext = None if wrenches is None else self._wrenches(wrenches)
        if f is None:
            return self._m.forward_dynamics_tau(x, u, tau, base_wrench, ext, method)
        if tau is not None or base_wrench is not None:
            raise _both_force_forms()
        return self._m.forward_dynamics(x, u, f, ext, method)

    # ---- generalized (reduced) quantities ------------------------------------------------
    def generalized_inertia(self, x) -> np.ndarray:
        """Generalized inertia matrix $H^* = H_m - H_{0m}^T H_0^{-1} H_{0m}$ (N×N, eq. 45)."""
        return self._m.generalized_inertia(x)

    def generalized_bias(self, x, u) -> np.ndarray:
        """Generalized bias $c^* = c_m - H_{0m}^T H_0^{-1} c_0$ (N) at the state ``(x, u)``."""
        return self._m.generalized_bias(x, u)

    def generalized_jacobian(self, x, point: PointLike = None) -> np.ndarray:
        r"""Generalized Jacobian $J^* = J_{mX} - J_{0X} H_0^{-1} H_{0m}$ (6×N, eq. 110) of a point
        (default: the end effector). With zero momentum the point twist is $J^* \dot q$."""
        body, off = self._point(point)
        return self._m.generalized_jacobian(x, body, off)

    def point_twist(self, x, qd, point: PointLike = None, P=(0.0, 0.0, 0.0), L=(0.0, 0.0, 0.0)) -> np.ndarray:
        r"""Twist $[v_X; \omega]$ of a point when the joints move at ``qd`` $= \dot q$ and the system has
        linear momentum ``P`` and angular momentum ``L`` about the origin of 𝒥:
        $J^* \dot q + J_{0X} H_0^{-1} M_0$ (the non-zero-momentum GJM)."""
        body, off = self._point(point)
        return self._m.point_twist(x, qd, body, off, P, L)

    def base_velocity_from_momentum(self, x, qd, P=(0.0, 0.0, 0.0), L=(0.0, 0.0, 0.0)) -> np.ndarray:
        r"""Base velocity $[v_0; \omega_0] = H_0^{-1} (M_0 - H_{0m} \dot q)$ (eqs. 43, 109) that gives the system
        linear momentum ``P`` and angular momentum ``L`` about the origin of 𝒥."""
        return self._m.base_velocity_from_momentum(x, qd, P, L)

    # ---- momentum, energy, CM ------------------------------------------------------------
    def momentum(self, x, u) -> Momentum:
        """Linear momentum and angular momentum about the origin, base CM and system CM."""
        return Momentum(*self._m.momentum(x, u))

    def kinetic_energy(self, x, u) -> float:
        r"""$T = \tfrac12 \sum_i (m_i \lVert v_i \rVert^2 + \omega_i^T I_i \omega_i)$ (equal to $\tfrac12 u^T H u$, eq. 27)."""
        return self._m.kinetic_energy(x, u)

    def momentum_scales(self, x, u) -> np.ndarray:
        r"""The magnitudes against which the drift of the momenta and the energy is measured, per
        state: ``(T, 4)`` columns $\sum_i m_i (\lVert v_{0i} \rVert + \lVert \omega_i \times (r_i - r_0) \rVert)$ (the two terms of
        $p_i$, $v_{0i}$ the velocity of body $i$'s point at the base CM), $\sum_i (\lVert r_i \times p_i \rVert + \lVert I_i \omega_i \rVert)$ about the origin, the
        same about the system CM, and the kinetic plus spring energy (sums over the bodies of their own
        contributions' norms: the core's drift scales, docs/simulation-core.md). ``x`` (T, 7+N)
        and ``u`` (T, 6+N) give ``(T, 4)``; one state, ``x`` (7+N,) and ``u`` (6+N,), gives
        ``(4,)``; like every per-state method it takes a batch with one row of either used for
        every state (docs/batch.md)."""
        return self._m.momentum_scales(x, u)

    def center_of_mass(self, x) -> np.ndarray:
        """System CM $r_g$ in 𝒥."""
        return self._m.center_of_mass(x)

    # ---- exact derivatives (docs/derivatives.md) -----------------------------------------
    # Tangent coordinates of the configuration (the conventions contract): dx = [dr0 (3),
    # dtheta (3), dq (N)], dtheta a rotation increment about the axes of 𝒥, R0 <- exp(dtheta^) R0.
    # The time derivative of x in these coordinates is u. Tensors of partials put the derivative
    # index LAST: out[i, j, k] = d X[i, j] / d x_k. Computed in the Rust core: the forward- and
    # inverse-dynamics Jacobians by analytic recursions, the others by forward-mode automatic
    # differentiation (dual numbers) of the same algorithms; all exact to rounding.
    def _derivatives(self):
        d = self.__dict__.get("_deriv_core")
        if d is None:
            d = self._deriv_core = _core.Derivatives(self._m)
        return d

    def _force(self, f, tau, base_wrench) -> np.ndarray:
        """``f = [F0, N0, tau]`` from ``f`` or from ``tau`` and ``base_wrench`` (zero default),
        one row or a batch of rows (either part may be one row for all)."""
        if f is None:
            t = np.zeros(self.n_dof) if tau is None else real_array(tau, "tau")
            b = np.zeros(6) if base_wrench is None else real_array(base_wrench, "base_wrench")
            for arr, name, width in ((t, "tau", self.n_dof), (b, "base_wrench", 6)):
                if arr.ndim not in (1, 2) or arr.shape[-1] != width:
                    raise ShapeError(f"{name} must have length {width} (or shape (B, {width}) for a batch), got shape {arr.shape}")
                finite(arr, name)  # named here: the core would name the f they are joined into
            if t.ndim == 1 and b.ndim == 1:
                return np.concatenate([b, t])
            lead = t.shape[0] if t.ndim == 2 else b.shape[0]
            if t.ndim == 2 and b.ndim == 2 and t.shape[0] != b.shape[0]:
                raise ShapeError(f"tau has {t.shape[0]} rows but base_wrench has {b.shape[0]}")
            return np.concatenate([np.broadcast_to(b, (lead, 6)), np.broadcast_to(t, (lead, self.n_dof))], axis=1)
        if tau is not None or base_wrench is not None:
            raise _both_force_forms()
        return f

    def configuration_plus(self, x, dx) -> np.ndarray:
        r"""$x \oplus \delta x$ for a tangent increment ``dx`` $= \delta x = [\delta r_0; \delta\theta; \delta q]$ (length 6+N):
        $r_0 + \delta r_0$, $R_0 \leftarrow \exp([\delta\theta]_\times) R_0$ (rotation about the axes of 𝒥), $q + \delta q$."""
        from .tangent import configuration_plus

        return configuration_plus(x, dx, self.n_dof)

    def configuration_difference(self, x1, x0) -> np.ndarray:
        r"""The tangent increment ``dx`` $= \delta x$ (length 6+N) with $x_0 \oplus \delta x = x_1$
        (see [`configuration_plus`][spacearm.Robot.configuration_plus]; the attitude part is $\log(R_1 R_0^T)$)."""
        from .tangent import configuration_difference

        return configuration_difference(x1, x0, self.n_dof)

    def mass_matrix_partials(self, x) -> np.ndarray:
        """``dH/dx_k`` for the 6+N tangent coordinates: array of shape (6+N, 6+N, 6+N) with
        ``out[:, :, k] = dH/dx_k`` (derivative index last).

        ``H`` (eq. 36) is referred to the base CM, so the ``dr0`` slices ``k = 0..3`` are
        exactly zero; ``k = 3..6`` are the attitude partials, ``k >= 6`` the joint partials.
        """
        return self._derivatives().mass_matrix_partials(x)

    def mass_matrix_derivative(self, x, u) -> np.ndarray:
        r"""Time derivative $\dot H = \sum_k \frac{\partial H}{\partial x_k} u_k$ ((6+N)², symmetric) of the mass matrix
        along the generalized velocity ``u`` (the tangent velocity of ``x``)."""
        return self._derivatives().mass_matrix_derivative(x, u)

    def generalized_inertia_partials(self, x) -> np.ndarray:
        """``dH*/dq_k``: array of shape (N, N, N), ``out[:, :, k] = dH*/dq_k``.

        ``H*`` (eq. 45) depends on the joint coordinates only (it is invariant under rigid
        motions of the whole system), so there are no base slices.
        """
        return self._derivatives().generalized_inertia_partials(x)

    def generalized_inertia_derivative(self, x, u) -> np.ndarray:
        r"""Time derivative $\dot H^* = \sum_k \frac{\partial H^*}{\partial q_k} \dot q_k$ (N×N) at the state ``(x, u)``."""
        return self._derivatives().generalized_inertia_derivative(x, u)

    def generalized_jacobian_partials(self, x, point: PointLike = None) -> np.ndarray:
        """``dJ*/dx_k`` of a point (default: the end effector) for the 6+N tangent coordinates:
        array of shape (6, N, 6+N), ``out[:, :, k] = dJ*/dx_k``. ``J*`` (eq. 110) is expressed
        in 𝒥 and turns with the base attitude (slices ``k = 3..6``); the ``dr0`` slices are zero."""
        body, off = self._point(point)
        return self._derivatives().generalized_jacobian_partials(x, body, off)

    def generalized_jacobian_derivative(self, x, u, point: PointLike = None) -> np.ndarray:
        r"""Time derivative $\dot J^* = \sum_k \frac{\partial J^*}{\partial x_k} u_k$ (6×N) of a point's generalized
        Jacobian along ``u``; e.g. the point's acceleration with zero momentum is
        $J^* \ddot q + \dot J^* \dot q$."""
        body, off = self._point(point)
        return self._derivatives().generalized_jacobian_derivative(x, u, body, off)

    @staticmethod
    def _dual(method: str) -> bool:
        """``True`` for ``method="dual"`` (the dual-number oracle), ``False`` for ``"analytic"``."""
        if method not in ("analytic", "dual"):
            raise ArgumentError(f"method must be 'analytic' or 'dual', got {method!r}")
        return method == "dual"

    def forward_dynamics_derivatives(self, x, u, f=None, *, tau=None, base_wrench=None, wrenches=None,
                                     method: str = "analytic") -> "ForwardDynamicsDerivatives":
        r"""Jacobians of forward dynamics $\dot u = \mathrm{FD}(x, u, f)$: ``(ddu_dx, ddu_du, ddu_df)``,
        each (6+N)².

        ``ddu_dx`` is with respect to the tangent coordinates ``[dr0, dtheta, dq]`` (its ``dr0``
        columns are zero); ``ddu_df`` $= H^{-1}$. From $\mathrm{ID}(x, u, \mathrm{FD}(x, u, f)) = f$:
        ``ddu_dx`` $= -H^{-1} \partial\mathrm{ID}/\partial x$, ``ddu_du`` $= -H^{-1} \partial\mathrm{ID}/\partial u$ (Carpentier & Mansard 2018). Give ``f``
        or ``tau`` and ``base_wrench`` as in [`forward_dynamics`][spacearm.Robot.forward_dynamics]. ``wrenches``
        ([`spacearm.ExternalWrench`][spacearm.ExternalWrench]) keep their force and torque fixed in 𝒥 while their
        point moves with its body. ``method="analytic"`` (default) uses the analytic partials of
        inverse dynamics; ``"dual"`` the dual-number route (slower; the test oracle).
        """
        # The common calls (no wrenches, analytic) skip the general argument handling: at small
        # N the Python layer is a visible part of the cost. Each form is one native call; the
        # tau/base_wrench form has the extension assemble f (bit-identical results; it checks
        # tau, then base_wrench, then x and u; benchmarks/fd_derivatives_forms.py times both).
        if wrenches is None and method == "analytic":
            d = self.__dict__.get("_deriv_core") or self._derivatives()
            if f is None:
                return _tuple_new(ForwardDynamicsDerivatives, d.forward_dynamics_derivatives_tau(x, u, tau, base_wrench))
            if tau is None and base_wrench is None:
                return _tuple_new(ForwardDynamicsDerivatives, d.forward_dynamics_derivatives(x, u, f))
        dual = self._dual(method)
        ext = None if wrenches is None else self._wrenches(wrenches)
        if f is None:
            return ForwardDynamicsDerivatives(*self._derivatives().forward_dynamics_derivatives_tau(x, u, tau, base_wrench, ext, dual))
        if tau is not None or base_wrench is not None:
            raise _both_force_forms()
        return ForwardDynamicsDerivatives(*self._derivatives().forward_dynamics_derivatives(x, u, f, ext, dual))

    def inverse_dynamics_partials(self, x, u, du, wrenches=None, *, method: str = "analytic") -> "InverseDynamicsPartials":
        r"""Partials of inverse dynamics $f = \mathrm{ID}(x, u, \dot u) = H \dot u + c - J^T w_\text{ext}$:
        ``(df_dx, df_du)``, each (6+N)², ``x`` in the tangent coordinates ``[dr0, dtheta, dq]``
        (the ``dr0`` columns are zero); ``df/d(du)`` is [`mass_matrix`][spacearm.Robot.mass_matrix]. External
        ``wrenches`` keep their force and torque fixed in 𝒥 while their point moves with its body.
        Analytic recursions of Carpentier & Mansard (2018) in spacearm's frames
        (docs/derivatives.md); ``method="dual"`` for the dual-number route.
        """
        dual = self._dual(method)
        ext = None if wrenches is None else self._wrenches(wrenches)
        return InverseDynamicsPartials(*self._derivatives().inverse_dynamics_partials(x, u, du, ext, dual))

    def linearize(self, x, u, f=None, *, tau=None, base_wrench=None, inputs: str = "joints",
                  method: str = "analytic") -> "Linearization":
        r"""Linearization $\dot{\delta z} = A\, \delta z + B\, \delta f$ of the state equation $\dot z = [u; \mathrm{FD}(x, u, f)]$
        about ``(x, u, f)``, in the tangent state $\delta z = [\delta x\ (6+N); \delta u\ (6+N)]$.

        $A = \begin{bmatrix} \Omega & E \\ \partial\dot u/\partial x & \partial\dot u/\partial u \end{bmatrix}$ (2(6+N) square) with $\Omega = \operatorname{blkdiag}(0, [\omega_0]_\times, 0)$
        (from $R_0 = \exp([\delta\theta]_\times) R_{0,\text{ref}}$: $\dot{\delta\theta} = \delta\omega_0 + \omega_0 \times \delta\theta$), and
        $B = \begin{bmatrix} 0 \\ H^{-1}\ \text{columns} \end{bmatrix}$: ``inputs="joints"`` gives the N joint-torque columns
        (free-floating control), ``inputs="all"`` the 6+N columns of ``f = [F0, N0, tau]``.
        Apply a state increment with [`configuration_plus`][spacearm.Robot.configuration_plus]. ``method`` as in
        [`forward_dynamics_derivatives`][spacearm.Robot.forward_dynamics_derivatives].
        """
        if f is not None and tau is None and base_wrench is None and inputs == "joints" and method == "analytic":
            d = self.__dict__.get("_deriv_core") or self._derivatives()
            return _tuple_new(Linearization, d.linearize(x, u, f, True))  # the common call, direct
        if inputs not in ("joints", "all"):
            raise ArgumentError(f"inputs must be 'joints' or 'all', got {inputs!r}")
        dual = self._dual(method)
        a, b = self._derivatives().linearize(x, u, self._force(f, tau, base_wrench), inputs == "joints", dual)
        return Linearization(a, b)


def _both_force_forms() -> ArgumentError:
    """The error of a call given ``f`` and ``tau``/``base_wrench`` too (the forms of the
    generalized force of ``forward_dynamics``, ``forward_dynamics_derivatives``, ``linearize``);
    raised by the caller, whose check stays inline on the hot path."""
    return ArgumentError("give either f or tau/base_wrench, not both")


#: Builds a NamedTuple from the core's plain tuple in C (its generated ``__new__`` is a Python
#: function, a third of a microsecond per call on the fast paths above).
_tuple_new = tuple.__new__


class ForwardDynamicsDerivatives(NamedTuple):
    r"""Jacobians of forward dynamics $\dot u = \mathrm{FD}(x, u, f)$ (see [`Robot.forward_dynamics_derivatives`][spacearm.Robot.forward_dynamics_derivatives])."""

    ddu_dx: np.ndarray  #: (6+N)², with respect to the tangent coordinates [dr0, dtheta, dq]
    ddu_du: np.ndarray  #: (6+N)², with respect to the generalized velocity u
    ddu_df: np.ndarray  #: (6+N)², $H^{-1}$: with respect to the generalized force f


class InverseDynamicsPartials(NamedTuple):
    r"""Partials of inverse dynamics $f = \mathrm{ID}(x, u, \dot u)$ (see [`Robot.inverse_dynamics_partials`][spacearm.Robot.inverse_dynamics_partials])."""

    df_dx: np.ndarray  #: (6+N)², with respect to the tangent coordinates [dr0, dtheta, dq]
    df_du: np.ndarray  #: (6+N)², with respect to the generalized velocity u


class PassiveModes(NamedTuple):
    """The modes of [`Robot.natural_frequencies`][spacearm.Robot.natural_frequencies], ascending in frequency."""

    dofs: np.ndarray  #: the joint coordinates that move (the passive ones, or all)
    frequencies: np.ndarray  #: undamped natural frequencies $\omega$, rad/s
    damping_ratios: np.ndarray  #: modal damping ratios $\zeta = v^T C v / (2\omega)$
    shapes: np.ndarray  #: N × modes, column i mode i's joint displacement, $v^T H^* v = 1$


class Linearization(NamedTuple):
    """``(A, B)`` of the linearized state equation (see [`Robot.linearize`][spacearm.Robot.linearize])."""

    A: np.ndarray  #: 2(6+N) square
    B: np.ndarray  #: 2(6+N) × N (inputs="joints") or 2(6+N) × (6+N) (inputs="all")


def warn_nonphysical_inertia(robot: Robot, messages=None) -> Robot:
    """Issue one [`NonPhysicalInertiaWarning`][spacearm.errors.NonPhysicalInertiaWarning] per body of ``robot``
    whose inertia breaks the triangle inequality (loaded under ``allow_nonphysical_inertia``),
    and return ``robot``. Every loading door calls it; the warnings point at the first line
    outside the spacearm package (the user's call), however deep the door. ``messages``: only
    these of its warnings (an edit's new bodies)."""
    messages = robot.inertia_warnings if messages is None else messages
    if not messages:
        return robot
    package = os.path.dirname(sys.modules[__name__.partition(".")[0]].__file__)
    frame, level = sys._getframe(1), 2  # level 1 is this function, 2 its caller
    while frame.f_back is not None and frame.f_code.co_filename.startswith(package):
        frame, level = frame.f_back, level + 1
    for message in messages:
        warnings.warn(message, NonPhysicalInertiaWarning, stacklevel=level)
    return robot
