"""Random inertia errors of the plant: what the campaign samples.

A mission's controller is built on a *nominal* model; the spacecraft actually flying differs from
it by the propellant used, fuel that has sloshed to one side of its tank, a payload of uncertain
mass, and plain measurement error. [`Perturbations`][spacearm.campaign.Perturbations] describes those errors as distributions;
[`Perturbations.draw`][spacearm.campaign.Perturbations.draw] turns a sample index into one concrete set of parameters, reproducibly
and independently of how many workers run the campaign (each sample has its own random stream,
``numpy.random.SeedSequence(seed, spawn_key=(index,))``).

Scale factors are log-normal (``exp(σ z)``, ``z ~ N(0, 1)``): always positive, median 1, and a
relative error of about ``σ`` for small ``σ`` — a normal scale could draw a negative mass, and
clipping it would silently change the distribution.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Dict

import numpy as np

from ..errors import ArgumentError
from .._util.pickling import reduce_through_constructor as _reduce_through_constructor

__all__ = ["Perturbations", "PARAMETER_NAMES", "PARAMETER_UNITS"]

#: The parameters every sample draws, in the order of the result file's ``params`` columns.
PARAMETER_NAMES = (
    "base_mass_scale",
    "base_inertia_scale",
    "link_mass_scale",
    "slosh_fraction",
    "slosh_offset_x",
    "slosh_offset_y",
    "slosh_offset_z",
    "payload_mass",
)

#: The unit of each parameter ("-" for the dimensionless scales and fractions), for labels.
PARAMETER_UNITS = {
    "base_mass_scale": "-",
    "base_inertia_scale": "-",
    "link_mass_scale": "-",
    "slosh_fraction": "-",
    "slosh_offset_x": "m",
    "slosh_offset_y": "m",
    "slosh_offset_z": "m",
    "payload_mass": "kg",
}


@dataclass(frozen=True)
class Perturbations:
    """Distributions of the plant's inertia errors relative to the nominal model.

    - ``base_mass_sigma``: log-std of the base mass scale (0.05 ≈ 5 %).
    - ``base_inertia_sigma``: log-std of the base inertia scale (the whole tensor scales).
    - ``link_mass_sigma``: log-std of one scale applied to every link's mass and inertia.
    - ``slosh_fraction_max``: a fraction ``U(0, max)`` of the base mass sits off the base CM,
      like propellant gathered at one side of a tank (the base CM moves with it).
    - ``slosh_offset``: distance (m) of that mass from the nominal base CM, in a direction
      uniform on the sphere (base frame).
    - ``payload_mass_max``: a point payload ``U(0, max)`` kg rigidly held at the end effector.
    """

    __reduce__ = _reduce_through_constructor  # unpickled through the validating constructor

    base_mass_sigma: float = 0.05
    base_inertia_sigma: float = 0.10
    link_mass_sigma: float = 0.02
    slosh_fraction_max: float = 0.05
    slosh_offset: float = 0.5
    payload_mass_max: float = 0.0

    def __post_init__(self):
        for name, value in asdict(self).items():
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise ArgumentError(f"Perturbations.{name} must be a finite number >= 0, got {value!r}")
        if self.slosh_fraction_max >= 1:
            raise ArgumentError(f"Perturbations.slosh_fraction_max must be < 1 (a fraction of the base mass), "
                                f"got {self.slosh_fraction_max}")

    def draw(self, seed: int, index: int) -> Dict[str, float]:
        """The parameters of sample ``index`` of the campaign seeded ``seed``."""
        rng = np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=(int(index),)))
        z = rng.standard_normal(3)
        direction = rng.standard_normal(3)
        direction /= np.linalg.norm(direction)
        fraction = rng.uniform(0.0, self.slosh_fraction_max) if self.slosh_fraction_max > 0 else 0.0
        payload = rng.uniform(0.0, self.payload_mass_max) if self.payload_mass_max > 0 else 0.0
        offset = self.slosh_offset * direction
        return {
            "base_mass_scale": float(np.exp(self.base_mass_sigma * z[0])),
            "base_inertia_scale": float(np.exp(self.base_inertia_sigma * z[1])),
            "link_mass_scale": float(np.exp(self.link_mass_sigma * z[2])),
            "slosh_fraction": float(fraction),
            "slosh_offset_x": float(offset[0]),
            "slosh_offset_y": float(offset[1]),
            "slosh_offset_z": float(offset[2]),
            "payload_mass": float(payload),
        }

    def to_dict(self) -> dict:
        return asdict(self)
