"""Inertia-uncertainty campaigns: how much does an inertia error cost?

A Monte Carlo study: every sample flies the same manoeuvre ([`Scenario`][spacearm.campaign.Scenario]) on a plant whose
base mass and inertia, link masses, sloshed propellant and payload differ from the nominal model
the controller uses ([`Perturbations`][spacearm.campaign.Perturbations]), and records tracking error, base attitude
excursion and actuator saturation. Samples run in parallel as batches of native rollouts on
threads (or on worker processes, or on a Dask cluster given its scheduler address); results go to one ``.npz`` file written atomically, which
is also the checkpoint a rerun resumes from. Failed samples are recorded, not fatal.

>>> import spacearm
>>> from spacearm.campaign import run_campaign, Scenario
>>> result = run_campaign(spacearm.presets.planar4(), samples=8, workers=0, progress=False,
...                       scenario=Scenario(duration=1.0, dt=5e-3))   # doctest: +SKIP
>>> print(result.table())                                             # doctest: +SKIP

[`run_capture_campaign`][spacearm.campaign.run_capture_campaign] is the other kind: captures on
contact over drawn approach errors, with the success rate as a column.

Docs: ``docs/campaigns.md``.
"""

from .capture_contact import ApproachErrors, CaptureCampaignResult, run_capture_campaign
from .cmg import CmgUncertainty
from .executor import run_campaign
from .flexibility import Fixed, Flexibility, LogNormal, Normal, Panel, Tank, Uniform
from .perturbation import PARAMETER_NAMES, PARAMETER_UNITS, Perturbations
from .results import FAILED, OK, PENDING, CampaignResult
from .scenario import METRIC_NAMES, METRIC_UNITS, Scenario, evaluate
from .spec import CampaignSpec

__all__ = [
    "run_campaign",
    "run_capture_campaign",
    "ApproachErrors",
    "CaptureCampaignResult",
    "CampaignSpec",
    "CampaignResult",
    "Perturbations",
    "Scenario",
    "Flexibility",
    "CmgUncertainty",
    "Tank",
    "Panel",
    "Fixed",
    "Uniform",
    "Normal",
    "LogNormal",
    "evaluate",
    "PARAMETER_NAMES",
    "PARAMETER_UNITS",
    "METRIC_NAMES",
    "METRIC_UNITS",
    "OK",
    "FAILED",
    "PENDING",
]
