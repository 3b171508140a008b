"""Figures of a campaign: the distribution of each metric and its strongest driver."""

from __future__ import annotations

from pathlib import Path
from typing import Optional, Sequence

import numpy as np

from .._atomic import atomic_path
from ..errors import ArgumentError

__all__ = ["plot_campaign", "rank_correlation"]

_UNITS = {
    "tracking_error_max": "rad",
    "tracking_error_rms": "rad",
    "tracking_error_final": "rad",
    "attitude_excursion_max": "deg",
    "base_displacement_max": "m",
    "saturation_events": "count",
}


def rank_correlation(a: np.ndarray, b: np.ndarray) -> float:
    """Spearman's rank correlation of two samples (NaN if either is constant)."""
    if a.size < 3 or np.ptp(a) == 0 or np.ptp(b) == 0:
        return float("nan")
    ra = np.argsort(np.argsort(a)).astype(float)
    rb = np.argsort(np.argsort(b)).astype(float)
    return float(np.corrcoef(ra, rb)[0, 1])


def plot_campaign(result, path, metrics: Optional[Sequence[str]] = None) -> Path:
    from .._optional import require

    require("matplotlib", "campaign figures").use("Agg")
    plt = require("matplotlib.pyplot", "campaign figures")

    path = Path(path)
    names = list(metrics) if metrics is not None else [m for m in result.metric_names if np.ptp(result.metric(m)) > 0
                                                       or m == "tracking_error_max"]
    if result.n_ok == 0:
        raise ArgumentError("no sample of this campaign ran successfully: nothing to plot")
    fig, axes = plt.subplots(len(names), 2, figsize=(10, 2.6 * len(names)), squeeze=False)
    for row, name in zip(axes, names):
        values = result.metric(name)
        unit = _UNITS.get(name, "")
        row[0].hist(values, bins=min(40, max(5, values.size // 5)), color="#4477aa")
        row[0].set_xlabel(f"{name} [{unit}]")
        row[0].set_ylabel("samples")
        p90 = np.percentile(values, 90)
        row[0].axvline(p90, color="#cc3311", ls="--", lw=1)
        row[0].set_title(f"{name}: median {np.median(values):.3g}, p90 {p90:.3g} {unit}", fontsize=9)
        scores = {p: rank_correlation(result.parameter(p), values) for p in result.param_names}
        scores = {p: s for p, s in scores.items() if np.isfinite(s)}
        if scores:
            driver = max(scores, key=lambda p: abs(scores[p]))
            row[1].scatter(result.parameter(driver), values, s=6, color="#228833")
            row[1].set_xlabel(driver)
            row[1].set_ylabel(f"{name} [{unit}]")
            row[1].set_title(f"strongest driver: {driver} (Spearman ρ = {scores[driver]:+.2f})", fontsize=9)
        else:
            row[1].set_axis_off()
    fig.suptitle(f"inertia-uncertainty campaign: {result.n_ok} samples ({result.n_failed} failed)")
    fig.tight_layout()
    try:
        with atomic_path(path, suffix=".png") as tmp:
            fig.savefig(tmp, dpi=110)
    finally:
        plt.close(fig)
    return path
