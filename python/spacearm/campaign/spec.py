"""The definition of a campaign: what every worker needs to run any of its samples.

A [`CampaignSpec`][spacearm.campaign.CampaignSpec] is plain data (the nominal model as TOML text, the perturbation
distributions, the scenario, the sample count and the seed), so it pickles to processes and Dask
workers and its JSON form identifies the campaign in the result file: a checkpoint is resumed
only by the campaign that wrote it.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

from ..errors import ArgumentError
from .perturbation import PARAMETER_NAMES, Perturbations
from .scenario import Scenario
from .._util.pickling import reduce_through_constructor as _reduce_through_constructor

__all__ = ["CampaignSpec"]


@dataclass(frozen=True)
class CampaignSpec:
    """``model_toml``: the nominal robot ([`spacearm.io.model_file.dumps_toml`][spacearm.io.dumps_toml]), exactly as it
    was loaded: a URDF arm mounted on a spacecraft, its prefix and its chosen end effector (the
    CLI's model options) are all in the text, so workers need nothing else to rebuild it;
    ``samples``: how many; ``seed``: the campaign's seed (sample ``i`` draws from
    ``SeedSequence(seed, spawn_key=(i,))``)."""

    __reduce__ = _reduce_through_constructor  # unpickled through the validating constructor

    model_toml: str
    samples: int
    seed: int = 0
    perturbations: Perturbations = field(default_factory=Perturbations)
    scenario: Scenario = field(default_factory=Scenario)

    def __post_init__(self):
        if not isinstance(self.samples, int) or isinstance(self.samples, bool) or self.samples < 1:
            raise ArgumentError(f"the number of samples must be an integer >= 1, got {self.samples!r}")
        if not isinstance(self.seed, int) or isinstance(self.seed, bool) or self.seed < 0:
            raise ArgumentError(f"the seed must be an integer >= 0, got {self.seed!r}")

    @property
    def param_names(self):
        """The columns of the result's ``params``: [`PARAMETER_NAMES`][spacearm.campaign.perturbation.PARAMETER_NAMES], then
        the scenario's [`Flexibility.names`][spacearm.campaign.Flexibility.names] if it has a flexibility recipe, then
        [`CmgUncertainty.names`][spacearm.campaign.CmgUncertainty.names] if it has CMG uncertainty."""
        flex, cmg = self.scenario.flexibility, self.scenario.cmg
        return PARAMETER_NAMES + (() if flex is None else flex.names) + (() if cmg is None else cmg.names)

    def draw(self, index: int):
        """Every parameter of sample ``index``: its inertia errors and its flexible-plant values."""
        params = self.perturbations.draw(self.seed, index)
        if self.scenario.flexibility is not None:
            params.update(self.scenario.flexibility.draw(self.seed, index))
        if self.scenario.cmg is not None:
            params.update(self.scenario.cmg.draw(self.seed, index))
        return params

    def to_json(self) -> str:
        return json.dumps(
            {
                "model_toml": self.model_toml,
                "samples": self.samples,
                "seed": self.seed,
                "perturbations": self.perturbations.to_dict(),
                "scenario": self.scenario.to_dict(),
            },
            sort_keys=True,
        )

    @classmethod
    def from_json(cls, text: str) -> "CampaignSpec":
        d = json.loads(text)
        scenario = dict(d["scenario"])
        for key in ("q_goal", "orbit"):
            if scenario.get(key) is not None:
                scenario[key] = tuple(scenario[key])
        return cls(d["model_toml"], int(d["samples"]), int(d["seed"]), Perturbations(**d["perturbations"]),
                   Scenario(**scenario))
