"""Figures of a campaign: the distribution of each metric and its strongest driver."""

from __future__ import annotations

from pathlib import Path
from typing import Optional, Sequence

import numpy as np

from .._util.atomic import atomic_path
from ..errors import ArgumentError, CampaignError, NotFoundError
from .perturbation import PARAMETER_UNITS
from .scenario import METRIC_UNITS

__all__ = ["campaign_figure", "plot_campaign", "rank_correlation"]


def _label(name: str) -> str:
    """``name [unit]`` for a campaign parameter or metric."""
    unit = PARAMETER_UNITS.get(name) or METRIC_UNITS.get(name)
    return f"{name} [{unit}]" if unit else name


def rank_correlation(a: np.ndarray, b: np.ndarray) -> float:
    """Spearman's rank correlation of two samples (NaN if either is constant)."""
    if a.size < 3 or np.ptp(a) == 0 or np.ptp(b) == 0:
        return float("nan")
    ra = np.argsort(np.argsort(a)).astype(float)
    rb = np.argsort(np.argsort(b)).astype(float)
    return float(np.corrcoef(ra, rb)[0, 1])


def campaign_figure(result, metrics: Optional[Sequence[str]] = None):
    """The campaign's matplotlib ``Figure`` (Agg canvas, no pyplot): for each metric, its
    histogram (dashed: the 90th percentile) and a scatter against the parameter with the
    largest |Spearman ρ|; axes labelled with units. ``metrics``: which (default: those that
    vary, and ``tracking_error_max`` always)."""
    from .._util.optional import require

    FigureCanvasAgg = require("matplotlib.backends.backend_agg", "campaign figures").FigureCanvasAgg
    Figure = require("matplotlib.figure", "campaign figures").Figure

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
    fig = Figure(figsize=(10, 2.6 * len(names) + 0.4), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(len(names), 2, squeeze=False)
    for row, name in zip(axes, names):
        values = result.metric(name)
        unit = METRIC_UNITS.get(name, "")
        row[0].hist(values, bins=min(40, max(5, values.size // 5)), color="#4477aa")
        row[0].set_xlabel(_label(name))
        row[0].set_ylabel("samples")
        p90 = np.percentile(values, 90)
        row[0].axvline(p90, color="#cc3311", ls="--", lw=1)
        row[0].set_title(f"{name}: median {np.median(values):.3g}, p90 {p90:.3g} {unit}", fontsize=9)
        scores = {p: rank_correlation(result.parameter(p), values) for p in result.param_names}
        scores = {p: s for p, s in scores.items() if np.isfinite(s)}
        if scores:
            driver = max(scores, key=lambda p: abs(scores[p]))
            row[1].scatter(result.parameter(driver), values, s=6, color="#228833")
            row[1].set_xlabel(_label(driver))
            row[1].set_ylabel(_label(name))
            row[1].set_title(f"strongest driver: {driver} (Spearman ρ = {scores[driver]:+.2f})", fontsize=9)
        else:
            row[1].set_axis_off()
    fig.suptitle(f"inertia-uncertainty campaign: {result.n_ok} samples ({result.n_failed} failed)")
    return fig


def plot_campaign(result, path, metrics: Optional[Sequence[str]] = None) -> Path:
    """Write :func:`campaign_figure` to ``path`` as PNG (atomically)."""
    fig = campaign_figure(result, metrics)
    path = Path(path)
    with atomic_path(path, suffix=".png") as tmp:
        fig.savefig(tmp, format="png", dpi=110)
    return path
