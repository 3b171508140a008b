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
evaluation of the dynamics (docs/contact.md, "Contact dynamics"). Rigid (complementarity)
contact and impulses at contact are not built yet (docs/contact.md, "What is not handled");
topology events (attach, release) are [`spacearm.events`][spacearm.events] (docs/events.md).
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple, Optional, Sequence

from . import _core
from ._util.arrays import number
from .errors import SpacearmTypeError

__all__ = ["contacts", "Contact", "ContactModel", "Pair"]


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
    """

    stiffness: float
    damping: float = 0.0
    friction: float = 0.0
    exponent: float = 1.0
    law: str = "kelvin_voigt"
    slip_velocity: float = 1e-3
    margin: float = 0.0
    pairs: Optional[Sequence[Sequence[str]]] = None

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
