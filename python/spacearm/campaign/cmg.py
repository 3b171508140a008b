"""Control-moment gyros as uncertain inputs of a campaign (docs/campaigns.md, "CMG parameters").

[`CmgUncertainty`][spacearm.campaign.CmgUncertainty] is carried by a [`Scenario`][spacearm.campaign.Scenario] whose nominal
model has CMGs ([`Robot.cmg_dofs`][spacearm.Robot.cmg_dofs], docs/cmg.md). Per sample it draws

- ``cmg_wheel_speed`` (rad/s): every rotor's initial speed, the run's initial condition
  ``u0 = plant.cmg_velocity(cmg_wheel_speed)`` (a rotor's speed is state, not a model parameter);
- ``cmg_rotor_inertia_scale``: every rotor's inertia tensor times it (``J_s`` and ``J_t``);
- ``cmg_gimbal_misalignment`` (rad): every CMG unit turned by this angle about its own spin axis
  at zero gimbal angle ``ŝ₀``, so its gimbal axis leans by exactly that angle toward
  ``−ĝ × ŝ₀`` and stays perpendicular to the spin axis (a mounting error of the gimbal bearing).

The plant edit is the core's ([`spacearm.control.perturbed_cmgs`][spacearm.control.perturbed_cmgs],
``control/mismatch.rs``), applied after the inertia errors and the payload; the controller is
built on the nominal model, whose rotors spin at the nominal wheel speed in no model: only the
plant's initial state carries the speed. The values of sample ``i`` are drawn from
``numpy.random.SeedSequence(seed, spawn_key=(i, 2))`` (the inertia errors use ``(i,)``, a
flexibility recipe ``(i, 1)``), one ``z`` and one ``u`` per name in order, so a campaign without
CMG uncertainty draws exactly what it drew before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Dict, Tuple

import numpy as np

from ..errors import ArgumentError
from .flexibility import Distribution, Fixed, _distribution
from .._util.pickling import reduce_through_constructor as _reduce_through_constructor

__all__ = ["CmgUncertainty", "CMG_PARAMETER_UNITS"]

#: The unit of each CMG parameter (a result file's extra ``params`` columns).
CMG_PARAMETER_UNITS = {
    "cmg_wheel_speed": "rad/s",
    "cmg_rotor_inertia_scale": "-",
    "cmg_gimbal_misalignment": "rad",
}

_NAMES = tuple(CMG_PARAMETER_UNITS)


@dataclass(frozen=True)
class CmgUncertainty:
    """The distributions of the CMG parameters of every sample's plant (module docs): each a
    number or a distribution ([`Fixed`][spacearm.campaign.Fixed], [`Uniform`][spacearm.campaign.Uniform],
    [`Normal`][spacearm.campaign.Normal], [`LogNormal`][spacearm.campaign.LogNormal]).
    ``wheel_speed`` (rad/s, default 0), ``rotor_inertia_scale`` (> 0, default 1),
    ``gimbal_misalignment`` (rad, default 0)."""

    __reduce__ = _reduce_through_constructor  # unpickled through the validating constructor

    wheel_speed: Distribution = field(default_factory=lambda: Fixed(0.0))
    rotor_inertia_scale: Distribution = field(default_factory=lambda: Fixed(1.0))
    gimbal_misalignment: Distribution = field(default_factory=lambda: Fixed(0.0))

    def __post_init__(self):
        for key in ("wheel_speed", "rotor_inertia_scale", "gimbal_misalignment"):
            object.__setattr__(self, key, _distribution(getattr(self, key), f"CmgUncertainty.{key}"))
        lo, lo_at, _, _ = self.rotor_inertia_scale.support()
        if lo < 0 or (lo == 0 and lo_at):
            raise ArgumentError(f"CmgUncertainty.rotor_inertia_scale: {self.rotor_inertia_scale!r} can draw a scale <= 0; "
                                "use a LogNormal (median 1) or a Uniform of positive bounds")

    @property
    def names(self) -> Tuple[str, ...]:
        """The parameters drawn: the result file's extra ``params`` columns."""
        return _NAMES

    def nominal(self) -> Dict[str, float]:
        return {name: getattr(self, name[4:]).nominal for name in _NAMES}

    def draw(self, seed: int, index: int) -> Dict[str, float]:
        """The parameters of sample ``index`` of the campaign seeded ``seed``: for each name, in
        order, one ``z ~ N(0, 1)`` and one ``u ~ U(0, 1)`` from ``SeedSequence(seed, spawn_key=(index, 2))``."""
        rng = np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=(int(index), 2)))
        values = {}
        for name in _NAMES:
            z, u = float(rng.standard_normal()), float(rng.uniform())
            values[name] = float(getattr(self, name[4:]).sample(z, u))
        return values

    @staticmethod
    def check(robot):
        """``robot``'s CMGs ([`Robot.cmg_dofs`][spacearm.Robot.cmg_dofs]); an `ArgumentError` if it has none."""
        cmgs = robot.cmg_dofs
        if not cmgs:
            raise ArgumentError("CmgUncertainty needs a model with CMGs (RobotBuilder.add_cmg, TOML [[cmg]]); "
                                "this one has none")
        return cmgs

    def apply(self, robot, values: Dict[str, float]):
        """``robot`` with its CMGs' rotor inertias scaled and its units misaligned by ``values``
        (the core's ``perturbed_cmgs``); ``robot`` itself at scale 1 and angle 0."""
        from ..control import perturbed_cmgs

        cmgs = self.check(robot)
        scale, angle = values["cmg_rotor_inertia_scale"], values["cmg_gimbal_misalignment"]
        if scale == 1.0 and angle == 0.0:
            return robot
        tilts = [angle * np.asarray(c["spin_axis"], dtype=float) for c in cmgs.values()] if angle != 0.0 else None
        return perturbed_cmgs(robot, scale, tilts)

    @staticmethod
    def initial_velocity(robot, values: Dict[str, float]) -> np.ndarray:
        """The plant's initial ``u``: every rotor at ``cmg_wheel_speed``, everything else at rest."""
        speed = values["cmg_wheel_speed"]
        if not math.isfinite(speed):
            raise ArgumentError(f"cmg_wheel_speed must be finite, got {speed}")
        return np.asarray(robot.cmg_velocity(speed), dtype=float)

    def to_dict(self) -> dict:
        return {k: getattr(self, k).to_dict() for k in ("wheel_speed", "rotor_inertia_scale", "gimbal_misalignment")}

    @classmethod
    def from_dict(cls, d: dict) -> "CmgUncertainty":
        return cls(**d)
