"""What a campaign's report reads off its samples: the rank correlation of a metric with each
perturbed parameter, and the axis labels (the figure itself is ``spacearm.viz.campaign``)."""

from __future__ import annotations

from typing import NamedTuple, Optional, Sequence


import numpy as np

from ..errors import ArgumentError, CampaignError, NotFoundError

from .cmg import CMG_PARAMETER_UNITS
from .flexibility import FLEX_PARAMETER_UNITS
from .perturbation import PARAMETER_UNITS
from .scenario import METRIC_UNITS

__all__ = ["axis_label", "rank_correlation", "ReportRow", "report_rows"]


def axis_label(name: str) -> str:
    """``name [unit]`` for a campaign parameter or metric."""
    unit = PARAMETER_UNITS.get(name) or FLEX_PARAMETER_UNITS.get(name) or CMG_PARAMETER_UNITS.get(name) or METRIC_UNITS.get(name)
    return f"{name} [{unit}]" if unit else name


def rank_correlation(a: np.ndarray, b: np.ndarray) -> float:
    """Spearman's rank correlation of two samples (NaN if either is constant)."""
    if a.size < 3 or np.ptp(a) == 0 or np.ptp(b) == 0:
        return float("nan")
    ra = np.argsort(np.argsort(a)).astype(float)
    rb = np.argsort(np.argsort(b)).astype(float)
    return float(np.corrcoef(ra, rb)[0, 1])


class ReportRow(NamedTuple):
    """One metric of the report: its samples and its strongest driver."""

    name: str
    label: str  #: "name [unit]"
    unit: str
    values: np.ndarray
    driver: Optional[str]  #: the parameter with the largest |Spearman ρ| (None: none varies)
    driver_label: str
    driver_values: Optional[np.ndarray]
    rho: float


def report_rows(result, metrics: Optional[Sequence[str]] = None) -> list:
    """The rows of a campaign's report: for each metric (default: those that vary, and
    ``tracking_error_max`` always) its samples and the parameter it correlates with most
    (Spearman's ρ). Drawn by ``spacearm.viz.campaign.campaign_figure``."""
    # Before any reduction over the samples: with none that ran, every array below is empty.
    if result.n_ok == 0:
        raise CampaignError(f"no sample of this campaign ran successfully ({result.n_failed} failed, "
                            f"{result.n_pending} not run): there is nothing to plot")
    if metrics is not None:
        unknown = [m for m in metrics if m not in result.metric_names]
        if unknown:
            raise NotFoundError(f"unknown metric(s) {', '.join(map(repr, unknown))}; the metrics are "
                                f"{', '.join(result.metric_names)}")
        names = list(metrics)
        if not names:
            raise ArgumentError("metrics must name at least one metric (or be None for the default)")
    else:
        names = [m for m in result.metric_names if np.ptp(result.metric(m)) > 0 or m == "tracking_error_max"]
    rows = []
    for name in names:
        values = result.metric(name)
        scores = {p: rank_correlation(result.parameter(p), values) for p in result.param_names}
        scores = {p: s for p, s in scores.items() if np.isfinite(s)}
        driver = max(scores, key=lambda p: abs(scores[p])) if scores else None
        rows.append(ReportRow(name, axis_label(name), METRIC_UNITS.get(name, ""), values, driver,
                              axis_label(driver) if driver else "", result.parameter(driver) if driver else None,
                              scores[driver] if driver else float("nan")))
    return rows
