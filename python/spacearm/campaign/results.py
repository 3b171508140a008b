"""The result of a campaign: one row per sample, in one ``.npz`` file written atomically.

File layout (``numpy.load(path)`` reads it without spacearm):

====================  =====================================================================
``index``             (n,) sample indices 0 … n−1
``status``            (n,) 0 = not run yet, 1 = ok, 2 = failed
``params``            (n, p) the sampled inertia errors, then any flexible-plant values
                      (columns ``param_names``); drawn before
                      the run, so present for failed samples too
``metrics``           (n, m) the run's metrics (columns ``metric_names``), NaN unless ok
``error``             (n,) the failure message of failed samples ('' otherwise)
``seconds``           (n,) wall time of each sample on its worker
``spec_json``         the campaign's definition (model TOML, perturbations, scenario, seed)
``run_json``          how it ran: backend, workers, elapsed seconds, samples per second
====================  =====================================================================

A partly run file is a checkpoint: [`spacearm.campaign.run_campaign`][spacearm.campaign.run_campaign] with the same
``out`` runs only the samples whose status is 0 (or failed, with ``retry_failed``). Status 2 is
for samples that failed for their own reasons; a sample the back end lost (a broken pool, a lost
worker) is never recorded, so it stays 0 and a rerun runs it.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Dict, Optional, Sequence

import numpy as np

from .._util.atomic import atomic_open
from .._util.npz import open_npz
from ..errors import ArgumentError, NotFoundError

__all__ = ["CampaignResult", "PENDING", "OK", "FAILED"]

#: The status of a sample not run yet ([`CampaignResult`][spacearm.campaign.CampaignResult]'s ``status``).
PENDING = 0
#: The status of a sample that ran.
OK = 1
#: The status of a sample that failed (its message is kept).
FAILED = 2

# Earlier versions recorded a sample lost to the back end as failed, with one of these prefixes
# (a sample's own failure message starts with its exception's class name, which has no space);
# such samples never ran, so [`CampaignResult.load`][spacearm.campaign.CampaignResult.load] reads them back as pending.
_LOST_PREFIXES = ("worker failed: ", "dask task failed: ")


class CampaignResult:
    """Per-sample parameters, metrics and failures of a campaign (see the module docs)."""

    def __init__(self, spec_json: str, param_names: Sequence[str], metric_names: Sequence[str], n: int):
        self.spec_json = spec_json
        self.param_names = tuple(param_names)
        self.metric_names = tuple(metric_names)
        self.index = np.arange(n)
        self.status = np.zeros(n, dtype=np.uint8)
        self.params = np.full((n, len(self.param_names)), np.nan)
        self.metrics = np.full((n, len(self.metric_names)), np.nan)
        self.error = np.array([""] * n, dtype=object)
        self.seconds = np.full(n, np.nan)
        self.run: Dict[str, object] = {}

    # -- checks ------------------------------------------------------------------------------
    def _validate(self) -> "CampaignResult":
        """Check that every field holds what a campaign writes (shapes, dtypes, statuses, the
        failure messages of failed samples): a tampered pickle or file is an ``ArgumentError``
        naming the field, never a result whose tables and plots are silently wrong."""
        def bad(msg):
            raise ArgumentError(f"not a valid CampaignResult: {msg}")

        if not isinstance(self.spec_json, str):
            bad(f"spec_json must be the campaign's JSON text, got {type(self.spec_json).__name__}")
        try:
            spec = json.loads(self.spec_json)
        except ValueError as exc:
            bad(f"spec_json is not JSON ({exc})")
        if not isinstance(spec, dict):
            bad("spec_json must hold a JSON object")
        for key in ("param_names", "metric_names"):
            names = getattr(self, key)
            if not (isinstance(names, tuple) and all(isinstance(v, str) for v in names) and len(set(names)) == len(names)):
                bad(f"{key} must be distinct names, got {names!r}")
        n = self.index.shape[0] if isinstance(self.index, np.ndarray) else -1
        if not (isinstance(self.index, np.ndarray) and self.index.ndim == 1 and np.array_equal(self.index, np.arange(n))):
            bad("index must be 0 … n−1")
        shapes = {"status": (n,), "params": (n, len(self.param_names)), "metrics": (n, len(self.metric_names)), "error": (n,),
                  "seconds": (n,)}
        for key, shape in shapes.items():
            arr = getattr(self, key)
            if not isinstance(arr, np.ndarray) or arr.shape != shape:
                bad(f"{key} must be an array of shape {shape}, got {getattr(arr, 'shape', type(arr).__name__)}")
        if self.status.dtype != np.uint8 or not np.isin(self.status, (PENDING, OK, FAILED)).all():
            bad(f"status must hold {PENDING} (not run), {OK} (ok) or {FAILED} (failed) as uint8, got {np.unique(self.status)}")
        for key in ("params", "metrics", "seconds"):
            if getattr(self, key).dtype != np.float64:
                bad(f"{key} must be float64, got {getattr(self, key).dtype}")
        if np.any(self.seconds[~np.isnan(self.seconds)] < 0):
            bad("seconds must be >= 0 (or NaN for a sample not run)")
        if not all(isinstance(e, str) for e in self.error):
            bad("error must hold strings")
        failed = self.status == FAILED
        if any(not self.error[i] for i in np.flatnonzero(failed)):
            bad("a failed sample must keep its message")
        if not isinstance(self.run, dict):
            bad(f"run must be a dict, got {type(self.run).__name__}")
        return self

    def __reduce__(self):
        # Unpickled through the constructor and _validate: a tampered pickle is refused.
        state = {k: getattr(self, k) for k in ("status", "params", "metrics", "error", "seconds", "run")}
        return (_restore, (self.spec_json, self.param_names, self.metric_names, self.n_samples, state))

    # -- filling -----------------------------------------------------------------------------
    def record(self, index: int, params: Dict[str, float], metrics: Optional[Dict[str, float]],
               error: str = "", seconds: float = float("nan")) -> None:
        """Store sample ``index``: its metrics if it ran, else its failure message."""
        self.params[index] = [params[k] for k in self.param_names]
        self.seconds[index] = seconds
        if metrics is None:
            self.status[index] = FAILED
            self.metrics[index] = np.nan
            self.error[index] = error or "failed without a message"
        else:
            self.status[index] = OK
            self.metrics[index] = [metrics[k] for k in self.metric_names]
            self.error[index] = ""

    # -- views -------------------------------------------------------------------------------
    @property
    def n_samples(self) -> int:
        return int(self.index.shape[0])

    @property
    def n_ok(self) -> int:
        return int(np.sum(self.status == OK))

    @property
    def n_failed(self) -> int:
        return int(np.sum(self.status == FAILED))

    @property
    def n_pending(self) -> int:
        return int(np.sum(self.status == PENDING))

    def metric(self, name: str) -> np.ndarray:
        """The values of metric ``name`` over the samples that ran."""
        if name not in self.metric_names:
            raise NotFoundError(f"unknown metric {name!r}; the metrics are {', '.join(self.metric_names)}")
        return self.metrics[self.status == OK, self.metric_names.index(name)]

    def parameter(self, name: str, ok_only: bool = True) -> np.ndarray:
        if name not in self.param_names:
            raise NotFoundError(f"unknown parameter {name!r}; the parameters are {', '.join(self.param_names)}")
        column = self.params[:, self.param_names.index(name)]
        return column[self.status == OK] if ok_only else column

    def failures(self) -> Dict[int, str]:
        """Sample index → failure message."""
        return {int(i): str(self.error[i]) for i in np.flatnonzero(self.status == FAILED)}

    def table(self, percentiles=(50, 90, 99)) -> str:
        """A Markdown table of each metric's distribution over the samples that ran, each metric
        with its unit (``tracking_error_max [rad]``)."""
        from .report import axis_label

        head = "| metric [unit] | " + " | ".join(f"p{p:g}" for p in percentiles) + " | max | mean |"
        rows = [head, "|" + "---|" * (len(percentiles) + 3)]
        for name in self.metric_names:
            v = self.metric(name)
            if v.size == 0:
                cells = ["–"] * (len(percentiles) + 2)
            else:
                cells = [f"{x:.4g}" for x in np.percentile(v, percentiles)] + [f"{v.max():.4g}", f"{v.mean():.4g}"]
            rows.append(f"| {axis_label(name)} | " + " | ".join(cells) + " |")
        rows.append(f"\n{self.n_ok} samples ran, {self.n_failed} failed, {self.n_pending} not run.")
        return "\n".join(rows)

    def __repr__(self) -> str:
        return (f"<CampaignResult: {len(self.index)} samples ({self.n_ok} ok, {self.n_failed} failed, {self.n_pending} not run), "
                f"parameters {list(self.param_names)}, metrics {list(self.metric_names)}>")

    def summary(self) -> str:
        lines = [self.table()]
        if self.run:
            r = self.run
            lines.append(f"backend {r.get('backend')}, {r.get('workers')} worker(s): {r.get('samples_run')} samples "
                         f"in {r.get('elapsed_s', float('nan')):.3g} s = {r.get('samples_per_s', float('nan')):.3g} samples/s")
        return "\n".join(lines)

    # -- files -------------------------------------------------------------------------------
    def save(self, path) -> Path:
        """Write the result to ``path`` (.npz) atomically: a temporary file, then a rename."""
        path = Path(path)
        if path.suffix != ".npz":
            raise ArgumentError(f"campaign results are saved as .npz, got '{path}'")
        with atomic_open(path, "wb", suffix=".tmp.npz") as f:
            np.savez(
                f,
                index=self.index,
                status=self.status,
                params=self.params,
                param_names=np.array(self.param_names),
                metrics=self.metrics,
                metric_names=np.array(self.metric_names),
                error=np.array([str(e) for e in self.error], dtype=str),
                seconds=self.seconds,
                spec_json=np.array(self.spec_json),
                run_json=np.array(json.dumps(self.run)),
            )
        return path

    @classmethod
    def load(cls, path) -> "CampaignResult":
        """Read a result (or checkpoint) written by [`save`][spacearm.campaign.CampaignResult.save] (samples an earlier version
        recorded as failed because the back end lost them come back pending)."""
        with open_npz(Path(path), "spacearm campaign") as f:
            missing = {"index", "status", "params", "metrics", "spec_json"} - set(f.files)
            if missing:
                raise ArgumentError(f"'{path}' is not a spacearm campaign file: no {', '.join(sorted(missing))}")
            result = cls(str(f["spec_json"]), [str(s) for s in f["param_names"]], [str(s) for s in f["metric_names"]],
                         int(f["index"].shape[0]))
            result.status = f["status"].astype(np.uint8)
            result.params = f["params"].astype(float)
            result.metrics = f["metrics"].astype(float)
            result.error = np.array([str(e) for e in f["error"]], dtype=object)
            result.seconds = f["seconds"].astype(float)
            result.run = json.loads(str(f["run_json"]))
        lost = (result.status == FAILED) & np.array([e.startswith(_LOST_PREFIXES) for e in result.error], dtype=bool)
        result.status[lost] = PENDING
        result.error[lost] = ""
        return result._validate()

    def figure(self, metrics: Optional[Sequence[str]] = None):
        """The figure of [`plot`][spacearm.campaign.CampaignResult.plot] as a matplotlib ``Figure``, not written anywhere."""
        from ..viz.campaign import campaign_figure
        from .report import report_rows

        return campaign_figure(report_rows(self, metrics), self.n_ok, self.n_failed)

    def plot(self, path, metrics: Optional[Sequence[str]] = None) -> Path:
        """A histogram of each metric, and each metric against the parameter that explains it
        best (largest |Spearman rank correlation|, stated in the panel title), written to
        ``path`` in the format its suffix names (atomically)."""
        from ..viz.figures import plot_to

        return Path(plot_to(path, lambda: self.figure(metrics), dpi=110))


def _restore(spec_json, param_names, metric_names, n, state) -> CampaignResult:
    """A pickled [`CampaignResult`][spacearm.campaign.CampaignResult], rebuilt by its constructor and checked."""
    from .._util.arrays import integer

    result = CampaignResult(spec_json, param_names, metric_names, integer(n, "the number of samples"))
    if not isinstance(state, dict) or set(state) != {"status", "params", "metrics", "error", "seconds", "run"}:
        raise ArgumentError("not a valid CampaignResult: a pickle carries status, params, metrics, error, seconds and run")
    for key, value in state.items():
        setattr(result, key, value)
    return result._validate()
