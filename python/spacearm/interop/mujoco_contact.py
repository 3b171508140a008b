"""spacearm's compliant contact in MuJoCo's terms (docs/contact.md, "In MuJoCo"): the contact
law's parameters as a ``<pair>``'s ``solref``, ``solimp``, ``friction`` and ``condim``, the
named pairs of a [`ContactModel`][spacearm.contact.ContactModel] as pairs of MJCF geoms, a free
target as a free MJCF body, and its 13-state as MuJoCo's ``qpos``/``qvel`` — what
[`to_mjcf`][spacearm.interop.to_mjcf] writes with ``contact=`` and ``target=``.

The map (its derivation and why it is approximate: docs/contact.md). MuJoCo's soft contact sets
the acceleration of the contact's normal coordinate, not a force: with impedance ``D`` and
``solref = (−K, −B)`` (its "direct" form) the constraint's acceleration is
``δ̈ = −D (B δ̇ + K δ) + (1 − D) a₀`` (``a₀``: the acceleration without the contact). spacearm's
Kelvin–Voigt law is a force, ``m_eff δ̈ = −(k δ + d δ̇)`` on the contact's effective mass
``m_eff = 1 / (n̂ᵀ G n̂)`` (``G``: the Delassus operator at the contact). So

    solref = (−k / m_eff, −d / m_eff),   solimp = (D, D, width, 0.5, 2) with D = IMPEDANCE,

the same law while ``m_eff`` stays at its value at the onset and ``D → 1``; ``friction`` μ is
Coulomb's in both, spacearm's regularized below the slip velocity ε (``condim`` 3, elliptic
cones; 1 without friction).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from typing import Dict, List, Optional, Tuple

import numpy as np

from .._util.arrays import vector
from ..errors import ArgumentError, NotFoundError

__all__ = ["mujoco_contact_parameters", "IMPEDANCE", "target_qpos_qvel"]

#: MuJoCo's impedance ``D`` of the mapped contacts, constant over the depth (``solimp``'s
#: ``dmin = dmax``): its largest, ``mjMAXIMP``. The acceleration MuJoCo's contact lets through,
#: ``(1 − D) a₀``, is then a ten-thousandth of the free one.
IMPEDANCE = 0.9999


def mujoco_contact_parameters(contact, effective_mass: float) -> Dict[str, str]:
    """The ``<pair>`` attributes (``solref``, ``solimp``, ``friction``, ``condim``, ``margin``)
    of MuJoCo's soft contact that follow ``contact`` (a
    [`ContactModel`][spacearm.contact.ContactModel], Kelvin–Voigt with exponent 1) at a contact of
    effective mass ``effective_mass`` (kg: ``1 / (n̂ᵀ G n̂)``, the mass the contact's normal
    coordinate sees; a ball on a free ball, their reduced mass). Module docs for the map;
    the Hunt–Crossley law and an exponent other than 1 (not linear in the depth) have no
    counterpart in MuJoCo's contact and are refused with an
    [`ArgumentError`][spacearm.ArgumentError]."""
    k, d = contact.stiffness, float(contact.damping)
    if contact.kind != "compliant" or k is None:
        raise ArgumentError("MJCF contact export needs a compliant ContactModel with a stiffness")
    if contact.law != "kelvin_voigt" or float(contact.exponent) != 1.0:
        raise ArgumentError(
            f"MJCF contact export maps the Kelvin–Voigt law with exponent 1 only (MuJoCo's soft contact is linear in the "
            f"depth and its rate); got law={contact.law!r}, exponent={contact.exponent}: not implemented")
    m = float(effective_mass)
    if not (math.isfinite(m) and m > 0):
        raise ArgumentError(f"effective_mass must be a finite mass > 0 kg (the contact's 1 / (n·G n)), got {effective_mass!r}")
    if not (math.isfinite(k) and k > 0 and math.isfinite(d) and d >= 0):
        raise ArgumentError(f"contact stiffness must be > 0 and damping >= 0, got {k} and {d}")
    mu = float(contact.friction)
    out = {
        "solref": f"{-k / m!r} {-d / m!r}",
        "solimp": f"{IMPEDANCE!r} {IMPEDANCE!r} 0.001 0.5 2",
        "condim": "3" if mu > 0 else "1",
        "margin": repr(float(contact.margin)),
    }
    if mu > 0:
        out["friction"] = f"{mu!r} {mu!r} 0 0 0"
    return out


def _collision_geoms(model, prefix_body: Optional[str] = None) -> List[Tuple[str, str, int, int]]:
    """(geometry name, body name, body index, parent body index) of ``model``'s collision shapes."""
    names = list(model.body_names)
    parents = [-1] + [link.parent_index for link in model.description.links]
    out = []
    for g in model.description.geometries:
        if g.role == "collision":
            out.append((g.name, prefix_body or names[g.body_index], g.body_index, parents[g.body_index]))
    return out


def contact_pairs(robot, contact, target=None) -> List[Tuple[str, str]]:
    """The MJCF geom pairs of ``contact.pairs`` (robot bodies or collision geometries, and, with a
    ``target`` model, ``"target"``, its name or its geometries); ``None``: every pair of robot
    bodies but parent–child, and every robot shape with every target shape (as the core's
    run, docs/contact.md)."""
    geoms = _collision_geoms(robot)
    tgeoms = _collision_geoms(target) if target is not None else []
    tnames = {"target", target.name, target.body_names[0]} if target is not None else set()

    def resolve(name: str) -> List[Tuple[str, int]]:
        if name in tnames:
            return [(g, -2) for g, *_ in tgeoms]
        own = [(g, b) for g, body, b, _ in geoms if body == name or g == name]
        own += [(g, -2) for g, *_ in tgeoms if g == name]
        if not own:
            raise NotFoundError(f"contact pair: no body or collision geometry named '{name}' (MJCF export)")
        return own

    out: List[Tuple[str, str]] = []
    if contact.pairs is None:
        for i, (g, _, b, p) in enumerate(geoms):
            for h, _, c, q in geoms[i + 1:]:
                if b != c and p != c and q != b:
                    out.append((g, h))
        out += [(g, h) for g, *_ in geoms for h, *_ in tgeoms]
        return out
    for a, b in contact.pairs:
        for g, bg in resolve(str(a)):
            for h, bh in resolve(str(b)):
                if bg == bh:
                    raise ArgumentError(f"contact pair ('{a}', '{b}'): both shapes are on one body")
                out.append((g, h))
    return out


def write_contact(root: ET.Element, robot, contact, target, effective_mass) -> None:
    """The ``<contact>`` of ``root``: a ``<pair>`` per admitted geom pair with the mapped law
    (``effective_mass``: one mass for every pair, or ``{(geom_a, geom_b): mass}``)."""
    pairs = contact_pairs(robot, contact, target)
    if not pairs:
        raise ArgumentError("MJCF contact export: no pair of collision geometries to write")
    el = ET.SubElement(root, "contact")
    for g, h in pairs:
        if isinstance(effective_mass, dict):
            m = effective_mass.get((g, h), effective_mass.get((h, g)))
            if m is None:
                raise ArgumentError(f"effective_mass has no mass for the pair ('{g}', '{h}'); it has {list(effective_mass)}")
        else:
            m = effective_mass
        ET.SubElement(el, "pair", name=f"{g}__{h}", geom1=g, geom2=h, **mujoco_contact_parameters(contact, m))


def target_qpos_qvel(target_state) -> Tuple[np.ndarray, np.ndarray]:
    """A free target's 13-state ``[r, quat xyzw, v, ω]`` (docs/contact.md; ω in 𝒥) as MuJoCo's
    free joint's ``qpos = [r, w, x, y, z]`` and ``qvel = [v, Rᵀ ω]`` (angular velocity in body
    axes)."""
    from ..rotations import quat_to_matrix

    s = vector(target_state, "target_state", 13)
    q = s[3:7] / np.linalg.norm(s[3:7])
    return (np.concatenate([s[:3], [q[3]], q[:3]]),
            np.concatenate([s[7:10], quat_to_matrix(q).T @ s[10:13]]))
