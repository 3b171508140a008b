"""The grasp impact: the impulse between the robot's gripper and a [`Target`][spacearm.Target],
and the inverse-inertia quantities it is made of.

Impulsive dynamics (positions fixed, velocities jump; finite forces contribute nothing over the
impact). A spatial impulse ``Λ = [f̂; n̂]`` (N·s, N·m·s, in 𝒥) acts on the robot at its grasp
point ``X`` and ``−Λ`` on the target's material point at ``X`` (the impulse is internal: robot +
target momentum is unchanged). With ``J = [J_0X, J_mX]`` the point Jacobian (eqs. 104–108) and
``H`` the mass matrix (eq. 36), the robot's jump is ``Δu = H⁻¹ Jᵀ Λ`` and the grasp point's
twist jumps by ``G_r Λ``, with the robot's *inverse inertia at the point*

    G_r = J H⁻¹ Jᵀ = J_0X H0⁻¹ J_0Xᵀ + J* H*⁻¹ J*ᵀ    (floating base; Yoshida et al. 2004)

(the second form from the Schur complement of ``H``: ``J*`` eq. 110, ``H*`` eq. 45). The target
gives ``G_t`` in the same way from its own (jointless) model. The relative twist
``v_rel = twist_robot(X) − twist_target(X)`` then jumps by ``(G_r + G_t) Λ``:

- ``kind="rigid"`` (plastic 6-D lock): ``v_rel⁺ = 0``, so ``Λ = −(G_r + G_t)⁻¹ v_rel⁻``;
- ``kind="point"`` (frictionless, normal ``n`` from the target into the robot, restitution
  ``e``): ``Λ = [λ n; 0]``, ``λ = −(1 + e) nᵀv_rel⁻ / (nᵀ (G_r + G_t)_vv n)`` when the bodies
  approach (``nᵀv_rel⁻ < 0``), else no impulse. ``1 / (nᵀ G_vv n)`` is Yoshida's virtual mass
  along ``n``.

``arm="locked"`` holds the joint rates through the impact: ``Δq̇ = 0``, only the base
coordinates jump (``Δẋ0 = H0⁻¹ J_0Xᵀ Λ``, ``G_r = J_0X H0⁻¹ J_0Xᵀ``). Impulsive joint torques do
the holding, the *locking impulses* ``τ̂ = H0mᵀ Δẋ0 − J_mXᵀ Λ`` (the joint rows of
``H Δu = Jᵀ Λ + [0; τ̂]``); they act between the links, so the momentum is unchanged. With the
arm at rest relative to the base the robot is one rigid body (the two-free-bodies case) and
``τ̂`` does no work; with moving joints it does work ``τ̂ᵀ q̇`` ([`GraspImpulse.locking_work`][spacearm.capture.GraspImpulse.locking_work],
either sign), which is not part of the energy the grasp dissipates.

Energy: over the impact the kinetic energy of robot + target changes by
``−energy_lost + locking_work``, with ``energy_lost = −Λᵀ (v_rel⁻ + v_rel⁺) / 2 ≥ 0`` the work
the contact impulses take out (``½ v_rel⁻ᵀ (G_r + G_t)⁻¹ v_rel⁻`` for the rigid lock,
``½ m_eff (1 − e²) (nᵀv_rel⁻)²`` for the point contact).

[`grasp_impulse`][spacearm.capture.grasp_impulse] is the core's (``spacearm_core::algorithms::impulse::grasp_impact``, built on
its ``impulse_dynamics``, the Pinocchio-shaped impulse dynamics of one model, also
``spacearm._core.impulse_dynamics``): this module converts the arguments; the result,
[`GraspImpulse`][spacearm.capture.GraspImpulse], is the extension's class (``spacearm._core.GraspImpulse``, frozen,
read-only arrays; its fields are documented in ``_core.pyi``).
"""

from __future__ import annotations

from typing import NamedTuple, Optional, Sequence

import numpy as np

from .. import _core
from .._core import GraspImpulse
from .._util.arrays import number, vector, vector3
from ..errors import ArgumentError, SingularError, SpacearmTypeError

__all__ = [
    "GraspImpulse",
    "MomentumSplit",
    "grasp_impulse",
    "inverse_inertia",
    "virtual_mass",
    "impulse_momentum_split",
    "KINDS",
]

#: The impact models of [`grasp_impulse`][spacearm.capture.grasp_impulse].
KINDS = ("rigid", "point")
ARMS = ("free", "locked")


class MomentumSplit(NamedTuple):
    """Where an impulse's momentum goes, about the base CM (``[P; L_base]``, eq. 42):
    ``base + arm == total == J_0Xᵀ Λ``."""

    base: np.ndarray  #: H0 Δẋ0: momentum carried by the base's own jump (6)
    arm: np.ndarray  #: H0m Δq̇: the coupling momentum the joints take up (6)
    total: np.ndarray  #: the impulse's momentum about the base CM (6)
    base_jump_map: np.ndarray  #: B with Δẋ0 = B Λ (6×6); impulses in its null space leave the base still
    base_jump_singular_values: np.ndarray  #: of B: a zero one means a reaction-null impulse direction exists


def _robot_point(robot, x, point, grasp_offset):
    """``(body, offset)`` of the robot's grasp point: ``point`` moved by ``grasp_offset`` (in the
    gripper body's frame)."""
    body, offset = robot.resolve_point(point)
    return body, np.asarray(offset, dtype=float) + vector3(grasp_offset, "grasp_offset")


def _jacobian(robot, x, body, offset) -> np.ndarray:
    j0, jm = robot.point_jacobian(x, (body, offset))
    return np.hstack([j0, jm])


def _solve(matrix: np.ndarray, rhs: np.ndarray, what: str) -> np.ndarray:
    try:
        return np.linalg.solve(matrix, rhs)
    except np.linalg.LinAlgError:
        raise SingularError(f"{what} is singular") from None


def _mobility(robot, x, body, offset, arm: str, j=None, h=None):
    """``(J, M)``: the Jacobian of the point over the coordinates that may jump, and their mass
    matrix (all of ``u``; or the base's six with the arm locked). ``j`` and ``h``: the full
    point Jacobian and mass matrix when the caller has them."""
    j = _jacobian(robot, x, body, offset) if j is None else j
    h = robot.mass_matrix(x) if h is None else h
    if arm == "locked":
        return j[:, :6], h[:6, :6]
    return j, h


def inverse_inertia(robot, x, point=None, *, form: str = "mass_matrix", arm: str = "free") -> np.ndarray:
    """The inverse inertia ``G`` (6×6) at a point of ``robot``: an impulse ``Λ = [f̂; n̂]`` at
    the point changes its twist ``[v; ω]`` by ``G Λ``.

    ``form="mass_matrix"``: ``J H⁻¹ Jᵀ``; ``form="generalized"``: ``J_0X H0⁻¹ J_0Xᵀ + J* H*⁻¹ J*ᵀ``
    (floating base, Yoshida et al. 2004); the two are equal, computed independently.
    ``arm="locked"``: the joint rates held (``Δq̇ = 0``), ``J_0X H0⁻¹ J_0Xᵀ``. ``point``: as everywhere (name,
    body, ``(body, offset)``; default the end effector).
    """
    xv = vector(x, "x")
    body, offset = robot.resolve_point(point)
    if arm not in ARMS:
        raise ArgumentError(f"arm must be one of {list(ARMS)}, got {arm!r}")
    if form == "mass_matrix":
        j, m = _mobility(robot, xv, body, offset, arm)
        return j @ _solve(m, j.T, "the mass matrix")
    if form != "generalized":
        raise ArgumentError(f"form must be 'mass_matrix' or 'generalized', got {form!r}")
    j0, _ = robot.point_jacobian(xv, (body, offset))
    g = j0 @ robot.base_inertia_inverse(xv) @ j0.T
    if arm == "free" and robot.n_dof:
        js = robot.generalized_jacobian(xv, (body, offset))
        g = g + js @ _solve(robot.generalized_inertia(xv), js.T, "the generalized inertia H*")
    return g


def virtual_mass(robot, x, direction, point=None, *, arm: str = "free") -> float:
    """Yoshida's virtual mass of ``robot`` at ``point`` along ``direction`` (kg):
    ``1 / (nᵀ G_vv n)``, ``G_vv`` the translational block of [`inverse_inertia`][spacearm.capture.inverse_inertia]: the mass a
    collision along ``n`` at the point feels."""
    n = _unit(direction, "direction")
    g = inverse_inertia(robot, x, point, arm=arm)
    return float(1.0 / (n @ g[:3, :3] @ n))


def impulse_momentum_split(robot, x, impulse, point=None) -> MomentumSplit:
    """How an impulse ``Λ`` at ``point`` (6, ``[f̂; n̂]`` in 𝒥) divides between the base and the
    arm: the base's jump ``Δẋ0`` carries ``H0 Δẋ0``, the joints' jump ``Δq̇`` the coupling
    momentum ``H0m Δq̇`` (impedance matching, Yoshida et al. 2004). The base is undisturbed by
    impulses in the null space of ``B`` (``Δẋ0 = B Λ``): the reaction null space at impact
    (Nenchev & Yoshida 1999)."""
    xv = vector(x, "x")
    lam = vector(impulse, "impulse", 6)
    body, offset = robot.resolve_point(point)
    j = _jacobian(robot, xv, body, offset)
    h = robot.mass_matrix(xv)
    response = _solve(h, j.T, "the mass matrix")  # H⁻¹ Jᵀ
    du = response @ lam
    base = h[:6, :6] @ du[:6]
    arm = h[:6, 6:] @ du[6:]
    b = response[:6, :]
    return MomentumSplit(base, arm, j[:, :6].T @ lam, b, np.linalg.svd(b, compute_uv=False))


def _unit(value, name: str) -> np.ndarray:
    n = vector3(value, name)
    norm = np.linalg.norm(n)
    if not np.isfinite(norm) or norm < 1e-12:
        raise ArgumentError(f"{name} must be a non-zero finite 3-vector, got {n}")
    return n / norm


def _check_target(target):
    if not (hasattr(target, "check_state") and hasattr(target, "body")):
        raise SpacearmTypeError(f"target must be a spacearm.Target, got {type(target).__name__}")


def grasp_impulse(
    robot,
    x,
    u,
    target,
    target_state,
    *,
    point=None,
    grasp: Optional[str] = None,
    grasp_offset: Sequence[float] = (0.0, 0.0, 0.0),
    restitution: float = 0.0,
    kind: str = "rigid",
    normal: Optional[Sequence[float]] = None,
    arm: str = "free",
) -> GraspImpulse:
    """The impact between the robot's grasp point and a target (module docstring for the equations).

    Parameters
    ----------
    robot, x, u
        The robot and its state just before the impact.
    target, target_state
        A [`Target`][spacearm.Target] and its state (13 numbers; ``[x, u]`` of a jointed
        target's model, [`Target.from_robot`][spacearm.capture.Target.from_robot]).
    point
        The robot's grasp point (default: the end effector); ``grasp_offset`` moves it, in the
        gripper body's frame (m).
    grasp
        The target's grasp point name (default: its first): the body hit is its body; it also
        gives ``gap`` and, with ``kind="point"``, the default normal (from that body's CM to the
        grasp point).
    restitution
        ``e`` in [0, 1] (``kind="point"``; a rigid lock is plastic).
    kind
        ``"rigid"`` (6-D plastic lock) or ``"point"`` (frictionless contact along ``normal``).
    normal
        Contact normal in 𝒥, from the target into the robot (default: from the target's CM to
        its grasp point).
    arm
        ``"free"`` (the joint rates jump too) or ``"locked"`` (the joint rates held through the
        impact by locking impulses, ``Δq̇ = 0``: module docstring).

    Returns
    -------
    GraspImpulse
        Its ``energy_lost`` is the energy the grasp dissipates (≥ 0, to rounding), its
        ``locking_work`` the work of the locking impulses (0 with ``arm="free"``): the kinetic
        energy of robot + target after the impact is the one before ``− energy_lost +
        locking_work``.
    """
    _check_target(target)
    if kind not in KINDS:
        raise ArgumentError(f"kind must be one of {list(KINDS)}, got {kind!r}")
    if arm not in ARMS:
        raise ArgumentError(f"arm must be one of {list(ARMS)}, got {arm!r}")
    e = number(restitution, "restitution")
    if not 0.0 <= e <= 1.0:
        raise ArgumentError(f"restitution must be in [0, 1], got {e}")
    if kind == "rigid" and e != 0.0:
        raise ArgumentError(f"a rigid grasp is plastic (restitution 0); restitution {e} needs kind='point'")
    xv = vector(x, "x", robot.nx)
    uv = vector(u, "u", robot.nu)
    s = target.check_state(target_state)
    body, offset = _robot_point(robot, xv, point, grasp_offset)
    t_body, t_offset = target.point(grasp)
    tx, tu = target.xu(s)
    n = None if normal is None or kind != "point" else vector3(normal, "normal")
    # The impulse, both jumps, G_r, G_t, the energy and the locking work: the core's
    # algorithms/impulse.rs (grasp_impact, on its impulse dynamics).
    return _core.grasp_impact(robot.core_model, xv, uv, int(body), np.asarray(offset, dtype=float), target.body.core_model, tx, tu,
                              int(t_body), np.asarray(t_offset, dtype=float), kind=kind, restitution=e, normal=n, arm=arm)
