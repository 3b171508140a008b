"""A flexible-plant recipe for campaigns: a propellant tank and a hinged panel whose fill
fraction, slosh frequency and damping, and panel stiffness are drawn per sample.

[`Flexibility`][spacearm.campaign.Flexibility] is carried by a [`Scenario`][spacearm.campaign.Scenario]. Every sample's plant is the
nominal robot (with the sample's inertia errors, [`Perturbations`][spacearm.campaign.Perturbations]) plus the tank's
equivalent mechanical model ([`spacearm.slosh_parameters`][spacearm.slosh_parameters] at the drawn fill fraction,
added with ``SloshParameters.add_to``) and the panel ([`RobotBuilder.add_panel`][spacearm.RobotBuilder.add_panel] with the
drawn stiffness), rebuilt by the builder in the worker. The controller is designed on the
*nominal* flexible model (every distribution at its ``nominal`` value) with
``ComputedTorque(passive="frozen")``: the rigid lumped model, the fuel and the panel locked at rest.

The values of sample ``i`` are drawn from ``numpy.random.SeedSequence(seed, spawn_key=(i, 1))``
(the inertia errors use ``spawn_key=(i,)``), in the order of
[`Flexibility.names`][spacearm.campaign.Flexibility.names], one draw per parameter whether it varies or not: reproducible,
independent of the workers, and a campaign without flexibility draws exactly what it drew before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import ClassVar, Dict, Optional, Tuple, Union

import numpy as np

from ..errors import ArgumentError, SpacearmError
from ..model.slosh import TANKS
from .._util.pickling import reduce_through_constructor as _reduce_through_constructor

__all__ = ["Fixed", "Uniform", "Normal", "LogNormal", "Tank", "Panel", "Flexibility", "FLEX_PARAMETER_UNITS", "FLEX_PARAMETER_DOMAINS"]

#: The unit of each flexibility parameter (a result file's extra ``params`` columns).
FLEX_PARAMETER_UNITS = {
    "fill_fraction": "-",
    "slosh_frequency_scale": "-",
    "slosh_damping_ratio": "-",
    "panel_stiffness": "N·m/rad",
}


def _finite(value, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)) or not math.isfinite(value):
        raise ArgumentError(f"{what} must be a finite number, got {value!r}")
    return float(value)


class _Distribution:
    """What the four distributions share: each field a finite number (named ``Class.field`` in the
    error), ``_check`` for the distribution's own rule, unpickled through the validating
    constructor, and ``to_dict`` as ``{"kind": _kind, <fields>}``."""

    __reduce__ = _reduce_through_constructor  # unpickled through the validating constructor

    _kind: ClassVar[str]

    def __post_init__(self):
        for f in fields(self):
            object.__setattr__(self, f.name, _finite(getattr(self, f.name), f"{type(self).__name__}.{f.name}"))
        self._check()

    def _check(self) -> None:
        """The distribution's own rule on its (finite) fields."""

    def _nonnegative(self, name: str) -> None:
        value = getattr(self, name)
        if value < 0:
            raise ArgumentError(f"{type(self).__name__}.{name} must be >= 0, got {value}")

    def to_dict(self) -> dict:
        return {"kind": self._kind, **{f.name: getattr(self, f.name) for f in fields(self)}}


@dataclass(frozen=True)
class Fixed(_Distribution):
    """Always ``value`` (the nominal value too)."""

    value: float

    _kind: ClassVar[str] = "fixed"

    @property
    def nominal(self) -> float:
        return self.value

    def sample(self, z: float, u: float) -> float:
        return self.value

    def support(self) -> Tuple[float, bool, float, bool]:
        """``(low, low attained, high, high attained)``: the bounds of a draw."""
        return (self.value, True, self.value, True)


@dataclass(frozen=True)
class Uniform(_Distribution):
    """Uniform on ``[low, high]``; nominal value the midpoint."""

    low: float
    high: float

    _kind: ClassVar[str] = "uniform"

    def _check(self) -> None:
        if not self.low <= self.high:
            raise ArgumentError(f"Uniform needs low <= high, got low={self.low}, high={self.high}")

    @property
    def nominal(self) -> float:
        return 0.5 * (self.low + self.high)

    def sample(self, z: float, u: float) -> float:
        return self.low + (self.high - self.low) * u

    def support(self) -> Tuple[float, bool, float, bool]:
        """``(low, low attained, high, high attained)``: the bounds of a draw."""
        return (self.low, True, self.high, True)


@dataclass(frozen=True)
class Normal(_Distribution):
    """Normal with ``mean`` and standard deviation ``std``; nominal value the mean."""

    mean: float
    std: float

    _kind: ClassVar[str] = "normal"

    def _check(self) -> None:
        self._nonnegative("std")

    @property
    def nominal(self) -> float:
        return self.mean

    def sample(self, z: float, u: float) -> float:
        return self.mean + self.std * z

    def support(self) -> Tuple[float, bool, float, bool]:
        """``(low, low attained, high, high attained)``: unbounded unless ``std`` is 0."""
        return (self.mean, True, self.mean, True) if self.std == 0 else (-math.inf, False, math.inf, False)


@dataclass(frozen=True)
class LogNormal(_Distribution):
    """``median · exp(sigma z)``, ``z ~ N(0, 1)``: always of the median's sign; nominal value the median."""

    median: float
    sigma: float

    _kind: ClassVar[str] = "lognormal"

    def _check(self) -> None:
        self._nonnegative("sigma")

    @property
    def nominal(self) -> float:
        return self.median

    def sample(self, z: float, u: float) -> float:
        return self.median * math.exp(self.sigma * z)

    def support(self) -> Tuple[float, bool, float, bool]:
        """``(low, low attained, high, high attained)``: from 0 (never drawn) to infinity, of the
        median's sign (the median itself if ``sigma`` is 0)."""
        if self.sigma == 0 or self.median == 0:
            return (self.median, True, self.median, True)
        return (0.0, False, math.inf, False) if self.median > 0 else (-math.inf, False, 0.0, False)


Distribution = Union[Fixed, Uniform, Normal, LogNormal]

#: Where each flexibility parameter must lie, ``(low, low included, high, high included)``: a
#: distribution that can draw outside is refused when the Flexibility is made (every such
#: sample's plant would be refused). The tank's own rules (a full cylinder does not slosh, the
#: shallowest fill of ``spacearm._core``'s slosh models) are checked by building the tank at the
#: ends of the fill's range.
FLEX_PARAMETER_DOMAINS = {
    "fill_fraction": (0.0, False, 1.0, False),
    "slosh_frequency_scale": (0.0, False, math.inf, False),
    "slosh_damping_ratio": (0.0, True, 1.0, False),
    "panel_stiffness": (0.0, False, math.inf, False),
}


def _interval(lo: float, lo_in: bool, hi: float, hi_in: bool) -> str:
    return f"{'[' if lo_in else '('}{lo:g}, {hi:g}{']' if hi_in else ')'}"


def _check_support(name: str, dist: "Distribution") -> None:
    lo, lo_at, hi, hi_at = dist.support()
    d_lo, lo_in, d_hi, hi_in = FLEX_PARAMETER_DOMAINS[name]
    low_ok = lo > d_lo or (lo == d_lo and (lo_in or not lo_at))
    high_ok = hi < d_hi or (hi == d_hi and (hi_in or not hi_at))
    if not (low_ok and high_ok):
        raise ArgumentError(
            f"Flexibility.{name}: {dist!r} draws values in {_interval(lo, lo_at, hi, hi_at)}, outside {name}'s "
            f"{_interval(d_lo, lo_in, d_hi, hi_in)}: every sample drawn there would fail; use a distribution whose "
            f"values all lie in {_interval(d_lo, lo_in, d_hi, hi_in)} (a Uniform or a Fixed value)")
_KINDS = {cls._kind: cls for cls in (Fixed, Uniform, Normal, LogNormal)}


def _distribution(value, what: str) -> Distribution:
    if isinstance(value, _Distribution):
        return value
    if isinstance(value, dict):
        d = dict(value)
        kind = d.pop("kind", None)
        if kind not in _KINDS:
            raise ArgumentError(f"{what}: unknown distribution kind {kind!r}; one of {', '.join(_KINDS)}")
        return _KINDS[kind](**d)
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return Fixed(value)
    raise ArgumentError(f"{what} must be a number or a distribution (Fixed, Uniform, Normal, LogNormal), got {value!r}")


def _vec3(value, what: str) -> Tuple[float, float, float]:
    a = np.asarray(value, dtype=float)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ArgumentError(f"{what} must be 3 finite numbers, got {value!r}")
    return tuple(float(v) for v in a)


@dataclass(frozen=True)
class Tank:
    """A propellant tank on the nominal model, of the shapes of
    [`spacearm.slosh_parameters`][spacearm.slosh_parameters]: ``shape="cylinder"`` (upright,
    flat-bottomed; ``fill_fraction`` is of its ``height``) or ``"sphere"`` (``height`` is its
    diameter, ``2 * radius``; ``fill_fraction`` is of its volume). ``radius``, ``height`` (m), the
    liquid's ``density`` (kg/m³; its mass follows the fill), ``axial_acceleration`` (m/s²),
    ``modes`` slosh modes. ``bottom``: the centre of the tank's bottom (a sphere's bottom pole) in
    ``parent``'s frame (from its CM); ``axis``: toward the free surface; ``lateral``: the slosh
    direction; ``model``: as ``SloshParameters.add_to``. Its bodies are named ``name_1``, …,
    ``name_fixed``."""

    __reduce__ = _reduce_through_constructor  # unpickled through the validating constructor

    radius: float
    height: float
    density: float
    axial_acceleration: float
    bottom: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    axis: Tuple[float, float, float] = (0.0, 0.0, 1.0)
    lateral: Optional[Tuple[float, float, float]] = None
    parent: str = "base"
    model: str = "pendulum"
    modes: int = 1
    name: str = "fuel"
    shape: str = "cylinder"

    def __post_init__(self):
        for key in ("radius", "height", "density", "axial_acceleration"):
            v = _finite(getattr(self, key), f"Tank.{key}")
            if v <= 0:
                raise ArgumentError(f"Tank.{key} must be > 0, got {v}")
            object.__setattr__(self, key, v)
        object.__setattr__(self, "bottom", _vec3(self.bottom, "Tank.bottom"))
        object.__setattr__(self, "axis", _vec3(self.axis, "Tank.axis"))
        if self.lateral is not None:
            object.__setattr__(self, "lateral", _vec3(self.lateral, "Tank.lateral"))
        if self.model not in ("spring-mass", "pendulum", "spherical-pendulum"):
            raise ArgumentError(f"Tank.model must be 'spring-mass', 'pendulum' or 'spherical-pendulum', got {self.model!r}")
        if self.shape not in TANKS:
            raise ArgumentError(f"Tank.shape must be one of {TANKS}, got {self.shape!r}")
        if self.shape == "sphere" and not abs(self.height - 2.0 * self.radius) <= 1e-9 * self.radius:
            raise ArgumentError(f"Tank: a spherical tank's height is its diameter 2 * radius = {2.0 * self.radius} m, "
                                f"got height={self.height}")

    def slosh_parameters(self, fill_fraction: float, *, frequency_scale: float = 1.0, damping_ratio: float = 0.0):
        """The tank's [`SloshParameters`][spacearm.SloshParameters] at ``fill_fraction``, every
        mode's frequency times ``frequency_scale`` (the axial acceleration times its square; the
        masses, heights and lengths unchanged), with ``damping_ratio``."""
        from ..model.slosh import slosh_parameters

        if not frequency_scale > 0:
            raise ArgumentError(f"slosh_frequency_scale must be > 0, got {frequency_scale}")
        # Frequencies scale as sqrt(a) in the core's formulas with every mass and height fixed:
        # the frequency times `scale` is the acceleration times scale².
        return slosh_parameters(self.shape, radius=self.radius, fill_fraction=fill_fraction, tank_height=self.height,
                                density=self.density, axial_acceleration=self.axial_acceleration * frequency_scale**2,
                                modes=self.modes, damping_ratio=damping_ratio)

    def to_dict(self) -> dict:
        """Plain data (no ``shape`` key for a cylinder, so a spec is what it was before spheres)."""
        d = {k: getattr(self, k) for k in self.__dataclass_fields__}
        if self.shape == "cylinder":
            del d["shape"]
        return d


@dataclass(frozen=True)
class Panel:
    """A hinged panel ([`RobotBuilder.add_panel`][spacearm.RobotBuilder.add_panel]): a uniform plate of
    ``size = (length, width, thickness)`` and ``mass`` on a hinge at ``hinge_position`` about
    ``hinge_axis``, extending along ``direction``; ``damping`` (N·m·s/rad). Its stiffness is drawn."""

    __reduce__ = _reduce_through_constructor  # unpickled through the validating constructor

    hinge_position: Tuple[float, float, float]
    hinge_axis: Tuple[float, float, float]
    direction: Tuple[float, float, float]
    mass: float
    size: Tuple[float, float, float]
    damping: float = 0.0
    parent: str = "base"
    name: str = "panel"

    def __post_init__(self):
        for key in ("hinge_position", "hinge_axis", "direction", "size"):
            object.__setattr__(self, key, _vec3(getattr(self, key), f"Panel.{key}"))
        object.__setattr__(self, "mass", _finite(self.mass, "Panel.mass"))
        object.__setattr__(self, "damping", _finite(self.damping, "Panel.damping"))

    def to_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


@dataclass(frozen=True)
class Flexibility:
    """The flexible parts of every sample's plant and the distributions of their parameters.

    ``tank`` (a [`Tank`][spacearm.campaign.Tank]) with ``fill_fraction`` (in (0, 1): of a
    cylinder's height, of a sphere's volume),
    ``slosh_frequency_scale`` (every mode's frequency times it, as an axial acceleration times
    its square would do; the masses, heights and pendulum lengths unchanged, the springs stiffer) and ``slosh_damping_ratio`` (ζ of every mode);
    ``panel`` (a [`Panel`][spacearm.campaign.Panel]) with ``panel_stiffness`` (N·m/rad). Each is a number or a
    distribution ([`Fixed`][spacearm.campaign.Fixed], [`Uniform`][spacearm.campaign.Uniform],
    [`Normal`][spacearm.campaign.Normal], [`LogNormal`][spacearm.campaign.LogNormal]); the controller's model uses their
    ``nominal`` values.
    """

    __reduce__ = _reduce_through_constructor  # unpickled through the validating constructor

    tank: Optional[Tank] = None
    fill_fraction: Distribution = field(default_factory=lambda: Fixed(0.5))
    slosh_frequency_scale: Distribution = field(default_factory=lambda: Fixed(1.0))
    slosh_damping_ratio: Distribution = field(default_factory=lambda: Fixed(0.0))
    panel: Optional[Panel] = None
    panel_stiffness: Distribution = field(default_factory=lambda: Fixed(10.0))

    def __post_init__(self):
        if isinstance(self.tank, dict):
            object.__setattr__(self, "tank", Tank(**self.tank))
        if isinstance(self.panel, dict):
            object.__setattr__(self, "panel", Panel(**self.panel))
        if self.tank is not None and not isinstance(self.tank, Tank):
            raise ArgumentError(f"Flexibility.tank must be a spacearm.campaign.Tank, got {type(self.tank).__name__}")
        if self.panel is not None and not isinstance(self.panel, Panel):
            raise ArgumentError(f"Flexibility.panel must be a spacearm.campaign.Panel, got {type(self.panel).__name__}")
        if self.tank is None and self.panel is None:
            raise ArgumentError("Flexibility needs a tank, a panel or both")
        for key in ("fill_fraction", "slosh_frequency_scale", "slosh_damping_ratio", "panel_stiffness"):
            object.__setattr__(self, key, _distribution(getattr(self, key), f"Flexibility.{key}"))
        for key in self.names:
            _check_support(key, getattr(self, key))
        if self.tank is not None:
            # The tank at the ends of the fill's range, by the core's slosh rules.
            lo, _, hi, _ = self.fill_fraction.support()
            for fill in sorted({lo, hi}):
                try:
                    self.tank.slosh_parameters(fill, frequency_scale=self.slosh_frequency_scale.nominal,
                                               damping_ratio=self.slosh_damping_ratio.nominal)
                except SpacearmError as exc:
                    raise type(exc)(f"Flexibility.fill_fraction: {self.fill_fraction!r} draws the fill {fill:g}, which the "
                                    f"tank refuses: {exc}") from None

    @property
    def names(self) -> Tuple[str, ...]:
        """The parameters drawn (the result file's extra ``params`` columns): those of the tank
        (``fill_fraction``, ``slosh_frequency_scale``, ``slosh_damping_ratio``) if there is one,
        ``panel_stiffness`` if there is a panel."""
        names = ()
        if self.tank is not None:
            names += ("fill_fraction", "slosh_frequency_scale", "slosh_damping_ratio")
        if self.panel is not None:
            names += ("panel_stiffness",)
        return names

    def nominal(self) -> Dict[str, float]:
        """The nominal value of every parameter (the controller's model)."""
        return {name: getattr(self, name).nominal for name in self.names}

    def draw(self, seed: int, index: int) -> Dict[str, float]:
        """The parameters of sample ``index`` of the campaign seeded ``seed``: for each name, in
        order, one ``z ~ N(0, 1)`` and one ``u ~ U(0, 1)`` from ``SeedSequence(seed, spawn_key=(index, 1))``."""
        rng = np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=(int(index), 1)))
        values = {}
        for name in self.names:
            z, u = float(rng.standard_normal()), float(rng.uniform())
            values[name] = float(getattr(self, name).sample(z, u))
        return values

    def apply(self, robot, values: Dict[str, float]):
        """``robot`` with the tank and the panel added through its builder, with ``values``
        (a [`draw`][spacearm.campaign.Flexibility.draw] or [`nominal`][spacearm.campaign.Flexibility.nominal])."""
        builder = robot.to_builder()
        if self.tank is not None:
            t = self.tank
            params = t.slosh_parameters(values["fill_fraction"], frequency_scale=values["slosh_frequency_scale"],
                                        damping_ratio=values["slosh_damping_ratio"])
            center = np.asarray(t.bottom) + np.asarray(t.axis) / np.linalg.norm(t.axis) * params.liquid_cm_height
            params.add_to(builder, t.name, parent=t.parent, center=center, axis=t.axis, lateral=t.lateral, model=t.model)
        if self.panel is not None:
            p = self.panel
            builder.add_panel(p.name, parent=p.parent, hinge_position=p.hinge_position, hinge_axis=p.hinge_axis,
                              direction=p.direction, mass=p.mass, size=p.size, stiffness=values["panel_stiffness"],
                              damping=p.damping)
        return builder.build()

    def to_dict(self) -> dict:
        return {
            "tank": None if self.tank is None else self.tank.to_dict(),
            "panel": None if self.panel is None else self.panel.to_dict(),
            **{k: getattr(self, k).to_dict() for k in ("fill_fraction", "slosh_frequency_scale", "slosh_damping_ratio",
                                                       "panel_stiffness")},
        }

    @classmethod
    def from_dict(cls, d: dict) -> "Flexibility":
        return cls(**d)
