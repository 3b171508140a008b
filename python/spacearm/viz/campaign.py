"""The figure of a campaign (``campaign_figure``): the distribution of each metric and its
strongest driver, drawn from the rows ``spacearm.campaign.report.report_rows`` computes."""

from __future__ import annotations

import numpy as np

from .figures import new_figure

__all__ = ["campaign_figure"]


def campaign_figure(rows, n_ok: int, n_failed: int):
    """The campaign's matplotlib ``Figure``: for each row, the metric's histogram (dashed: the
    90th percentile) and a scatter against the parameter with the largest |Spearman ρ|; axes
    labelled with units."""
    fig = new_figure(figsize=(10, 2.6 * len(rows) + 0.4))
    axes = fig.subplots(len(rows), 2, squeeze=False)
    for ax, row in zip(axes, rows):
        values = row.values
        ax[0].hist(values, bins=min(40, max(5, values.size // 5)), color="#4477aa")
        ax[0].set_xlabel(row.label)
        ax[0].set_ylabel("samples")
        p90 = np.percentile(values, 90)
        ax[0].axvline(p90, color="#cc3311", ls="--", lw=1)
        ax[0].set_title(f"{row.name}: median {np.median(values):.3g}, p90 {p90:.3g} {row.unit}", fontsize=9)
        if row.driver is not None:
            ax[1].scatter(row.driver_values, values, s=6, color="#228833")
            ax[1].set_xlabel(row.driver_label)
            ax[1].set_ylabel(row.label)
            ax[1].set_title(f"strongest driver: {row.driver} (Spearman ρ = {row.rho:+.2f})", fontsize=9)
        else:
            ax[1].set_axis_off()
    fig.suptitle(f"inertia-uncertainty campaign: {n_ok} samples ({n_failed} failed)")
    return fig
