"""From a propellant tank to its slosh modes' equivalent mechanical model, and onto a
[`RobotBuilder`][spacearm.RobotBuilder] (docs/flexibility.md, "From a tank to the slosh
parameters"). The computations live once, in the core: the cylinder's closed form in
``crates/spacearm-core/src/model/slosh_tank.rs`` (Abramson, NASA SP-106, 1966, Table 6.1; Dodge,
SwRI 2000, §3.2), the sphere's Ritz–Trefftz solution in
``crates/spacearm-core/src/model/slosh_sphere.rs``; this module checks the arguments, calls the
core and adds the links."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from .. import _core
from .._util.arrays import number, vector
from ..errors import ArgumentError

TANKS = ("cylinder", "sphere")


@dataclass(frozen=True)
class SloshMode:
    """One slosh mode: ``mass`` (kg) at ``height`` (m above the liquid's CM, along the tank
    axis), natural ``frequency`` (rad/s) in the axial acceleration, the spring–mass model's
    ``stiffness`` (N/m) and the pendulum model's rod ``length`` (m; hinge at ``height + length``)."""

    mass: float
    height: float
    frequency: float
    stiffness: float
    length: float


@dataclass(frozen=True)
class SloshParameters:
    """The equivalent mechanical model of a tank's liquid (from
    [`slosh_parameters`][spacearm.slosh_parameters]): ``modes``, the fixed (non-sloshing)
    ``fixed_mass`` at ``fixed_height`` above the liquid's CM (so the model's CM is the liquid's),
    the ``damping_ratio`` given and the tank it came from. ``liquid_cm_height``: the liquid's CM
    above the tank's bottom (``fill_height / 2`` in a cylinder, ``h (8R − 3h) / (4 (3R − h))``
    above the bottom pole of a sphere; from the core), where ``add_to``'s ``center`` goes.
    ``fixed_inertia``: the fixed mass's moment of inertia ``I₀`` about a lateral axis through its
    CM (kg·m², the liquid's rigid-lid pitching inertia less the masses' ``m ℓ²``; from the core)
    for a cylinder, ``None`` for a sphere (not computed: docs/flexibility.md)."""

    tank: str
    radius: float
    fill_height: float
    liquid_mass: float
    axial_acceleration: float
    damping_ratio: float
    modes: tuple
    fixed_mass: float
    fixed_height: float
    liquid_cm_height: float
    fixed_inertia: Optional[float] = None

    def add_to(self, builder, name: str, *, parent: str = "base", center: Sequence[float] = (0.0, 0.0, 0.0),
               axis: Sequence[float] = (0.0, 0.0, 1.0), lateral: Optional[Sequence[float]] = None,
               model: str = "spring-mass", thrust: bool = False):
        """Add the modes (``name_1``, ``name_2``, …) with
        [`RobotBuilder.add_slosh`][spacearm.RobotBuilder.add_slosh] and the fixed mass
        (``name_fixed``: a point mass with the moment of inertia ``fixed_inertia`` about the
        lateral axes, none about the tank axis; a point mass where it is ``None``) with
        [`RobotBuilder.attach_payload`][spacearm.RobotBuilder.attach_payload]; returns ``builder``.

        ``center``: the liquid's CM in ``parent``'s frame (from its CM, m); ``axis``: the tank's
        axis from the bottom toward the free surface (the direction of the vehicle's axial
        acceleration); ``lateral``: the slosh direction of a spring–mass (perpendicular to
        ``axis``; default the parent axis nearest perpendicular). ``model``: ``"spring-mass"`` (at
        ``center + height·axis``, sliding along ``lateral``), ``"pendulum"`` (hinged at
        ``center + (height + length)·axis``, the bob hanging along ``-axis``, swinging along
        ``lateral``) or ``"spherical-pendulum"``. The dampers are ``2 ζ m ω`` (per joint, times
        ``length²`` for the pendulums).

        ``thrust``: how the vehicle's axial acceleration ``a`` acts on the modes
        (docs/flexibility.md, "Slosh under thrust: which model holds which moment").
        ``False`` (the default): the joint springs stand for it (``k = m ω²``, or ``m a L`` on a
        pendulum joint), for a simulation with no thrust force: the lateral forces and the
        clamped-tank frequencies are right, but the moment on the tank is ``k x ℓ`` (arm ``ℓ``),
        without the displaced weight ``m a x``, and the spring-mass and pendulum are the same
        model. ``True``: the in-field models, for a simulation that applies the thrust (``M a``
        along ``axis``, ``M`` the vehicle's mass) as a force on the vehicle: the pendulums get no
        joint spring (the vehicle's acceleration restores them, ``ω² = a/L`` on a clamped tank),
        the spring-mass keeps its spring and its joint carries the mass's axial inertia force;
        both then put the moment ``k x (ℓ + L)`` on the tank, the wall and bottom pressure moment
        of the potential flow."""
        if not isinstance(thrust, (bool, np.bool_)):
            raise ArgumentError(f"add_to: thrust must be True or False, got {thrust!r}")
        if model not in ("spring-mass", "pendulum", "spherical-pendulum"):
            raise ArgumentError(f"slosh model must be 'spring-mass', 'pendulum' or 'spherical-pendulum', got {model!r}")
        c = vector(center, "tank center", 3)
        e = vector(axis, "tank axis", 3)
        n = float(np.linalg.norm(e))
        if not (math.isfinite(n) and n > 1e-9):
            raise ArgumentError(f"the tank axis must be a finite non-zero vector, got {list(e)}")
        e = e / n
        if lateral is None:
            k = int(np.argmin(np.abs(e)))
            lat = np.eye(3)[k] - e[k] * e
        else:
            lat = vector(lateral, "tank lateral", 3)
            lat = lat - float(lat @ e) * e
        ln = float(np.linalg.norm(lat))
        if not ln > 1e-9:
            raise ArgumentError(f"the slosh direction 'lateral' must not be parallel to the tank axis, got {lateral}")
        lat = lat / ln
        for i, m in enumerate(self.modes, start=1):
            zeta, mode_name = self.damping_ratio, f"{name}_{i}"
            if model == "spring-mass":
                builder.add_slosh(mode_name, parent=parent, model=model, mass=m.mass, position=c + m.height * e, axis=lat,
                                  frequency=m.frequency, damping=2.0 * zeta * m.mass * m.frequency)
            else:
                # In the field (thrust=True) the vehicle's acceleration restores the bob: no spring.
                restoring = {"stiffness": 0.0} if thrust else {"frequency": m.frequency}
                builder.add_slosh(mode_name, parent=parent, model=model, mass=m.mass, position=c + (m.height + m.length) * e,
                                  axis=-e, length=m.length, hinge=np.cross(e, lat), **restoring,
                                  damping=2.0 * zeta * m.mass * m.length**2 * m.frequency)
        i0 = 0.0 if self.fixed_inertia is None else float(self.fixed_inertia)
        builder.attach_payload(f"{name}_fixed", body=parent, mass=self.fixed_mass, origin=c + self.fixed_height * e,
                               inertia=i0 * (np.eye(3) - np.outer(e, e)))
        return builder


def slosh_parameters(tank: str = "cylinder", *, radius: float, axial_acceleration: float,
                     fill_height: Optional[float] = None, fill_fraction: Optional[float] = None,
                     tank_height: Optional[float] = None, propellant_mass: Optional[float] = None,
                     density: Optional[float] = None, modes: int = 1, damping_ratio: float = 0.0) -> SloshParameters:
    """The equivalent mechanical model of the liquid in a tank (docs/flexibility.md).

    ``tank="cylinder"``: an upright circular cylinder of ``radius`` (m) with a flat bottom
    (Abramson 1966, Table 6.1; Dodge 2000, §3.2). The fill is ``fill_height`` (m) or
    ``fill_fraction`` of ``tank_height``; the liquid's mass is ``propellant_mass`` (kg) or
    ``density`` (kg/m³) times ``π R² h``. ``modes``: how many antisymmetric modes (1 to 5).

    ``tank="sphere"``: a spherical tank of ``radius`` (m), computed by a Ritz–Trefftz method in
    the core (checked against McIver 1989: ω²R/a = 1.5602 half full). The fill is
    ``fill_height`` (m above the bottom pole, below 2R) or ``fill_fraction`` of the sphere's
    volume (then ``tank_height`` is not needed; if given it must equal 2R); the liquid's mass is
    ``propellant_mass`` or ``density`` times the cap volume ``π h² (3R − h)/3``. ``modes``: 1 to
    3. ``fill_height`` in the result is above the bottom pole; the modes' heights are above the
    liquid's CM.

    ``axial_acceleration`` (m/s², > 0) is the vehicle's acceleration along the tank axis during
    the phase studied (thrust / mass): the frequencies scale as its square root, and in coasting
    flight (0) the model does not apply (the liquid is held by surface tension).
    ``damping_ratio``: the modes' viscous damping ratio ζ (not part of the inviscid solution;
    from tests, of the order of 0.001–0.01 for smooth walls).
    """
    if tank not in TANKS:
        raise ArgumentError(f"slosh_parameters: tank must be one of {TANKS}, got {tank!r}")
    r = number(radius, "radius")
    if not (math.isfinite(r) and r > 0.0):
        raise ArgumentError(f"slosh_parameters: radius must be finite and > 0 (m), got {r}")
    if (fill_height is None) == (fill_fraction is None):
        what = "fill_fraction (of the sphere's volume)" if tank == "sphere" else "fill_fraction (with tank_height)"
        raise ArgumentError(f"slosh_parameters: give fill_height or {what}, one of them")
    if tank == "sphere" and tank_height is not None:
        th = number(tank_height, "tank_height")
        if not abs(th - 2.0 * r) <= 1e-9 * r:
            raise ArgumentError(
                f"slosh_parameters: a spherical tank's height is its diameter 2R = {2.0 * r} m; tank_height={th} "
                "contradicts it (leave tank_height out for a sphere)")
    if fill_fraction is not None:
        f = number(fill_fraction, "fill_fraction")
        if not 0.0 < f <= 1.0:
            raise ArgumentError(f"slosh_parameters: fill_fraction must be in (0, 1], got {f}")
        if tank == "sphere":
            h = _core.sphere_fill_height(r, f)
        else:
            if tank_height is None:
                raise ArgumentError("slosh_parameters: fill_fraction needs tank_height (m)")
            h = _core.cylinder_fill_height(number(tank_height, "tank_height"), f)
    else:
        h = number(fill_height, "fill_height")
    if (propellant_mass is None) == (density is None):
        raise ArgumentError("slosh_parameters: give propellant_mass or density, one of them")
    if propellant_mass is not None:
        mass = number(propellant_mass, "propellant_mass")
    else:
        volume = math.pi * h * h * (3.0 * r - h) / 3.0 if tank == "sphere" else math.pi * r * r * h
        mass = number(density, "density") * volume
    zeta = number(damping_ratio, "damping_ratio")
    if not 0.0 <= zeta < 1.0:
        raise ArgumentError(f"slosh_parameters: damping_ratio must be in [0, 1), got {zeta}")
    if isinstance(modes, bool) or not isinstance(modes, (int, np.integer)):
        raise ArgumentError(f"slosh_parameters: modes must be an integer, got {modes!r}")
    if int(modes) < 1:
        raise ArgumentError(f"slosh_parameters: modes must be >= 1, got {modes}")
    solve = _core.sphere_slosh if tank == "sphere" else _core.cylinder_slosh
    out = solve(r, h, mass, number(axial_acceleration, "axial_acceleration"), int(modes))
    return SloshParameters(
        tank=tank, radius=out["radius"], fill_height=out["fill_height"], liquid_mass=out["liquid_mass"],
        axial_acceleration=out["axial_acceleration"], damping_ratio=zeta, modes=tuple(SloshMode(**m) for m in out["modes"]),
        fixed_mass=out["fixed_mass"], fixed_height=out["fixed_height"], liquid_cm_height=out["liquid_cm_height"],
        fixed_inertia=out["fixed_inertia"],
    )
