"""Contacts between a model's collision shapes (docs/contact.md).

[`contacts`][spacearm.contact.contacts] finds, at one state, the pairs of collision geometries
(``role="collision"``: boxes, spheres, cylinders, capsules; docs/geometry.md) that touch,
interpenetrate or come within ``margin`` of each other. The narrow phase is the core's, on
parry (the rapier project's collision crate): the contact points on both surfaces, the unit
normal from the first shape to the second and the signed distance (negative: the depth of
interpenetration).

[`ContactModel`][spacearm.contact.ContactModel] is the compliant contact of a run:
``spacearm.simulate(robot, T, contact=ContactModel(stiffness=..., damping=..., friction=...,
pairs=[Pair("base", "hand")]))`` — a spring–dashpot normal force (Kelvin–Voigt or Hunt–Crossley)
with regularized Coulomb friction between the system's bodies, computed in the core at every
evaluation of the dynamics (docs/contact.md, "Contact dynamics").

[`solve_impact`][spacearm.contact.solve_impact] is the rigid frictional impact at one state:
the velocity jump ``u⁺ = u⁻ + H⁻¹ Jᵀ λ`` through point contacts with Coulomb friction and
Newton's restitution, the impulses ``λ`` solved on the Delassus operator ``G = J H⁻¹ Jᵀ`` by
proximal ADMM or projected Gauss–Seidel in the core (docs/contact.md, "Rigid frictional
impacts").

[`grasp_outcome`][spacearm.contact.grasp_outcome] judges, in the core, whether a gripper held,
let slip or missed a free target's handle in a run with contact (docs/contact.md, "The grasp's
outcome"). Rigid contact inside a run (``simulate``) is not built yet (docs/contact.md, "What is
not handled"); topology events (attach, release) are [`spacearm.events`][spacearm.events]
(docs/events.md).
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple, Optional, Sequence

from . import _core
from ._util.arrays import number
from .errors import SpacearmTypeError

__all__ = ["contacts", "Contact", "ContactModel", "GraspOutcome", "grasp_outcome", "Pair", "RigidImpact", "solve_impact"]


class Pair(NamedTuple):
    """Two bodies (every collision shape of each) or collision geometries that may touch, by name."""

    a: str
    b: str


@dataclasses.dataclass(frozen=True)
class ContactModel:
    """Compliant contact between bodies of the simulated system (the core's ``ContactSpec``,
    sim/contact.rs; every value is checked there). For each pair of collision shapes in
    interpenetration by ``δ`` at depth rate ``δ̇``:

    - ``law="kelvin_voigt"``: ``f_n = k δ^p + d δ̇`` (``damping`` is ``d``, N·s/m);
      ``law="hunt_crossley"``: ``f_n = k δ^p (1 + c δ̇)`` (``damping`` is ``c``, s/m);
      clamped at zero (no pull);
    - friction ``f_t = −μ f_n v_t / sqrt(|v_t|² + ε²)`` (``friction`` μ, ``slip_velocity`` ε).

    ``pairs``: a list of [`Pair`][spacearm.contact.Pair] (or 2-tuples) of body or collision
    geometry names; ``None``: every pair of bodies but a body and its parent. ``margin`` (m):
    the detection margin (a force needs interpenetration).

    ``kind``: ``"compliant"`` (the law above; ``stiffness`` required) or ``"rigid"``: rigid
    frictional contact solved every step on the Delassus operator (docs/contact.md, "Rigid
    contact in a run"; RK4 runs only), with ``friction`` μ, Newton's ``restitution`` e in
    [0, 1] (default 0), the cone ``solver`` ``"admm"`` (default) or ``"pgs"``, the
    position-error ``stabilization`` β in [0, 1] (default 0.2: a depth δ is pushed out at
    β δ / dt), the solver's ``tolerance`` (m/s, default 1e-10) and ``max_iterations`` (default
    1000); ``margin`` is then the distance at which points enter a step's problem, allowed to
    close their gap in the step. These five are refused with the compliant law, and
    ``stiffness`` and ``damping`` with the rigid one. One rigid impact at a state is
    [`solve_impact`][spacearm.contact.solve_impact].
    """

    stiffness: Optional[float] = None
    damping: float = 0.0
    friction: float = 0.0
    exponent: float = 1.0
    law: str = "kelvin_voigt"
    slip_velocity: float = 1e-3
    margin: float = 0.0
    pairs: Optional[Sequence[Sequence[str]]] = None
    kind: str = "compliant"
    restitution: Optional[float] = None
    solver: Optional[str] = None
    stabilization: Optional[float] = None
    tolerance: Optional[float] = None
    max_iterations: Optional[int] = None

#: A contact between two collision shapes at one state (the binding's class): ``geometries`` and
#: ``bodies`` (names, first and second shape), ``point_a``, ``point_b`` (3,) the closest or
#: deepest point of each surface in 𝒥, m; ``normal`` (3,) from the first shape to the second;
#: ``distance`` (m, < 0 interpenetrating).
Contact = _core.Contact


def contacts(robot, x, *, pairs: Optional[Sequence[tuple]] = None, margin: float = 0.0) -> list:
    """The contacts of state ``x`` between ``robot``'s collision shapes.

    ``pairs``: the pairs of bodies to test, as ``(name, name)``; default every pair of bodies
    but a body and its parent (they meet at their joint by construction). ``margin`` (m, >= 0):
    also report shapes at most this far apart (default 0: touching or interpenetrating). Pairs on
    one body are never tested. A mesh collision geometry is refused with an
    [`ArgumentError`][spacearm.ArgumentError] naming it (its vertices are not in the model).
    """
    from .model.robot import Robot

    if not isinstance(robot, Robot):
        raise SpacearmTypeError(f"contacts needs a spacearm.Robot, got {type(robot).__name__}")
    if pairs is not None:
        pairs = [(str(a), str(b)) for a, b in pairs]
    return _core.contacts(robot.core_model, x, pairs, number(margin, "margin"))


_find_contacts = contacts

#: The result of [`solve_impact`][spacearm.contact.solve_impact] (the binding's frozen class,
#: read-only arrays). Contact rows are each point's frame ``[t1, t2, n]``: ``impulse`` (k, 3)
#: N·s, ``impulse_world`` (k, 3) the impulse on each point's second body in 𝒥 (the first body
#: receives its opposite), ``velocity_before``/``velocity_after`` (k, 3) ``J u⁻`` and ``J u⁺``
#: (m/s), ``frames`` (k, 3, 3) the contact frames (columns ``t1, t2, n`` in 𝒥), ``jacobian``
#: (3k, 6+N), ``delassus`` (3k, 3k) ``G = J H⁻¹ Jᵀ``, ``u_after`` and ``du`` (6+N,); what the
#: solver reports: ``solver``, ``converged``, ``iterations``, ``residual`` (m/s, the larger of
#: ``dual_feasibility`` and ``complementarity``).
RigidImpact = _core.RigidImpact


def _impact_point(c, i: int) -> tuple:
    """``(body_a, body_b, point, normal)`` of a [`Contact`][spacearm.contact.Contact] (its
    normal, at the midpoint of its two surface points) or of a 4-tuple."""
    import numpy as np

    if isinstance(c, Contact):
        return c.bodies[0], c.bodies[1], 0.5 * (np.asarray(c.point_a) + np.asarray(c.point_b)), c.normal
    if isinstance(c, (tuple, list)) and len(c) == 4:
        return str(c[0]), str(c[1]), c[2], c[3]
    raise SpacearmTypeError(
        f"contact {i} must be a spacearm.contact.Contact or a tuple (body_a, body_b, point, normal), got {type(c).__name__}"
    )


def solve_impact(
    robot,
    x,
    u,
    contacts: Optional[Sequence] = None,
    *,
    friction=0.0,
    restitution: float = 0.0,
    solver: str = "admm",
    tolerance: float = 1e-10,
    max_iterations: int = 1000,
    proximal: float = 1e-8,
    pairs: Optional[Sequence[tuple]] = None,
    margin: float = 0.0,
) -> RigidImpact:
    """The rigid frictional impact of ``robot`` at ``(x, u)`` (docs/contact.md, "Rigid
    frictional impacts"): the velocity after the impact and the contact impulses.

    ``contacts``: the points that meet — [`Contact`][spacearm.contact.Contact] objects (the
    point midway between the two surface points, the contact's normal) or tuples ``(body_a,
    body_b, point, normal)`` (body names; the point and the unit normal from the first body
    towards the second, in 𝒥); ``None``: the contacts of ``x`` found by
    [`contacts`][spacearm.contact.contacts] with ``pairs`` and ``margin``. ``friction``:
    Coulomb's μ, one for all or one per contact. ``restitution``: Newton's ``e`` in [0, 1] on the
    points that approach. ``solver``: ``"admm"`` (proximal ADMM) or ``"pgs"`` (projected
    Gauss–Seidel), stopped when the residual is at most ``tolerance`` (m/s) or after
    ``max_iterations``; ``proximal``: ADMM's proximal weight relative to the largest eigenvalue of
    ``G``. A solver that stops at its limit is no error: the result says ``converged=False`` with
    the residual it reached. Every value is checked by the core.
    """
    from .model.robot import Robot

    if not isinstance(robot, Robot):
        raise SpacearmTypeError(f"solve_impact needs a spacearm.Robot, got {type(robot).__name__}")
    if contacts is None:
        contacts = _find_contacts(robot, x, pairs=pairs, margin=margin)
    points = [_impact_point(c, i) for i, c in enumerate(contacts)]
    if isinstance(friction, (int, float)) or getattr(friction, "ndim", None) == 0:
        mus = [number(friction, "friction")] * len(points)
    else:
        mus = [number(f, f"friction[{i}]") for i, f in enumerate(friction)]
        if len(mus) != len(points):
            from .errors import ArgumentError

            raise ArgumentError(f"friction has {len(mus)} values for {len(points)} contacts: give one for all or one per contact")
    return _core.rigid_impact(
        robot.core_model,
        x,
        u,
        [(a, b, p, n, mu) for (a, b, p, n), mu in zip(points, mus)],
        solver=str(solver),
        restitution=number(restitution, "restitution"),
        tolerance=number(tolerance, "tolerance"),
        max_iterations=int(max_iterations),
        proximal=number(proximal, "proximal"),
    )


#: The result of [`grasp_outcome`][spacearm.contact.grasp_outcome] (the binding's frozen class):
#: ``outcome`` ("held", "slipped" or "missed"), ``held``, ``reason`` (in words); the final
#: window's largest ``relative_spin`` (rad/s), ``relative_speed`` (m/s) and ``offset`` (m) of the
#: handle frame against the gripper's, its fewest ``fingers_touching`` of ``fingers``; over the
#: run ``first_touch`` (s, or None) and ``touching_samples``; ``window_start``,
#: ``window_samples`` and the thresholds used (``window``, ``max_relative_spin``,
#: ``max_relative_speed``, ``max_offset``, ``touch_margin``).
GraspOutcome = _core.GraspOutcome

#: The defaults of [`grasp_outcome`][spacearm.contact.grasp_outcome]'s thresholds (the core's
#: ``GraspThresholds``): window s, rad/s, m/s, m, m.
GRASP_THRESHOLDS = {"window": 0.5, "max_relative_spin": 0.005, "max_relative_speed": 0.005, "max_offset": 0.005, "touch_margin": 0.001}


def grasp_outcome(
    robot,
    target,
    traj,
    *,
    gripper: Optional[str] = None,
    handle: str = "handle",
    window: float = 0.5,
    max_relative_spin: float = 0.005,
    max_relative_speed: float = 0.005,
    max_offset: float = 0.005,
    touch_margin: float = 0.001,
) -> GraspOutcome:
    """Whether ``robot``'s gripper held, let slip or missed ``target``'s handle in ``traj`` (a
    run of ``spacearm.simulate(robot, ..., contact=..., target=target, target_state=...)``;
    docs/contact.md, "The grasp's outcome"). Judged in the core (``sim/grasp_outcome.rs``) from
    the recorded states: over the final ``window`` (s), a grasp is **held** when every finger
    stays within ``touch_margin`` (m) of the handle and the handle frame's angular velocity
    relative to the palm, its origin's velocity relative to the grasp centre
    ``<gripper>_center`` and its distance from it stay within ``max_relative_spin`` (rad/s),
    ``max_relative_speed`` (m/s) and ``max_offset`` (m); **missed** when no finger came within
    ``touch_margin`` of it in the run; **slipped** otherwise.

    ``gripper``: the palm's name (None: the robot's only gripper); ``handle``: the target's
    collision geometry grasped.
    """
    from .errors import ArgumentError
    from .model.robot import Robot

    for who, what in (("robot", robot), ("target", target)):
        if not isinstance(what, Robot):
            raise SpacearmTypeError(f"grasp_outcome needs {who} as a spacearm.Robot, got {type(what).__name__}")
    if gripper is None:
        names = [g["name"] for g in _core.grippers(robot.core_model)]
        if len(names) != 1:
            raise ArgumentError(f"robot '{robot.name}' has {len(names)} grippers {names}: name the one that grasps (gripper=...)")
        gripper = names[0]
    has = getattr(traj, "has", None)  # a spacearm.Trajectory (sim/ is a layer above this module)
    if not callable(has) or not has("target"):
        raise ArgumentError("grasp_outcome needs the Trajectory of a run with a free target (simulate(..., target=..., target_state=...))")
    return _core.grasp_outcome(
        robot.core_model,
        target.core_model,
        str(gripper),
        str(handle),
        traj.t,
        traj.x,
        traj.u,
        traj["target"],
        window=number(window, "window"),
        max_relative_spin=number(max_relative_spin, "max_relative_spin"),
        max_relative_speed=number(max_relative_speed, "max_relative_speed"),
        max_offset=number(max_offset, "max_offset"),
        touch_margin=number(touch_margin, "touch_margin"),
    )
