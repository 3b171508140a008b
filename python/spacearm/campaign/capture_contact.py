"""A capture-on-contact campaign (docs/campaigns.md, "A capture-on-contact campaign"): how often
does a gripper hold a tumbling handle when the approach is off?

Every sample flies one [`ContactCapture`][spacearm.capture.ContactCapture] — the robot's gripper
closing on a box's handle by the core's compliant contact, the outcome judged by the core
(``spacearm.contact.grasp_outcome``: held, slipped or missed) — with approach errors drawn from
[`ApproachErrors`][spacearm.campaign.ApproachErrors]: the handle's position offset from the grasp
centre, the target's attitude error about the handle, and its spin rate. The result is a
[`CaptureCampaignResult`][spacearm.campaign.CaptureCampaignResult] (a
[`CampaignResult`][spacearm.campaign.CampaignResult]: the same ``.npz`` file, resumable) whose
table has the **success rate** (the held fraction of the samples that ran) with its Wilson score
interval, computed by the core (``math/wilson.rs``).

Sample ``i`` draws its errors from ``numpy.random.default_rng([seed, i])``: a sample's draw
depends on the seed and its index only, so a resumed or reordered campaign draws the same.
"""

from __future__ import annotations

import dataclasses
import json
import time
from pathlib import Path
from typing import Callable, Optional, Union

import numpy as np

from .. import _core
from ..errors import ArgumentError, SpacearmError, SpacearmTypeError
from .._util.arrays import number
from .results import FAILED, OK, PENDING, CampaignResult

__all__ = ["ApproachErrors", "CaptureCampaignResult", "run_capture_campaign", "CAPTURE_PARAMETERS", "CAPTURE_METRICS",
           "OUTCOME_CODES"]

#: The drawn approach errors, the result's ``params`` columns: the handle's offset from the grasp
#: centre (m, 𝒥), the attitude error (rotation vector, rad, 𝒥), the spin rate (rad/s).
CAPTURE_PARAMETERS = ("offset_x", "offset_y", "offset_z", "attitude_x", "attitude_y", "attitude_z", "spin")

#: The result's ``metrics`` columns: ``outcome`` (``OUTCOME_CODES``), ``held`` (1 or 0) and the
#: outcome's numbers (docs/contact.md, "The grasp's outcome"; ``first_touch`` NaN when missed).
CAPTURE_METRICS = ("outcome", "held", "relative_spin", "relative_speed", "offset", "fingers_touching", "first_touch")

#: The ``outcome`` metric's codes.
OUTCOME_CODES = {"missed": 0.0, "slipped": 1.0, "held": 2.0}

_UNITS = {"offset_x": "m", "offset_y": "m", "offset_z": "m", "attitude_x": "rad", "attitude_y": "rad", "attitude_z": "rad",
          "spin": "rad/s", "relative_spin": "rad/s", "relative_speed": "m/s", "offset": "m", "first_touch": "s"}


@dataclasses.dataclass(frozen=True)
class ApproachErrors:
    """How a sample's approach errors are drawn: each component of the handle's offset from the
    grasp centre normal with standard deviation ``offset_sigma`` (m, in 𝒥), each component of the
    attitude error (a rotation vector about the handle's centre, in 𝒥) normal with
    ``attitude_sigma`` (rad), the spin rate uniform in ``[spin_low, spin_high]`` (rad/s) about the
    capture's ``spin_axis``."""

    offset_sigma: float = 0.0
    attitude_sigma: float = 0.0
    spin_low: float = 0.05
    spin_high: float = 0.05

    def __post_init__(self):
        for f in dataclasses.fields(self):
            object.__setattr__(self, f.name, number(getattr(self, f.name), f"ApproachErrors.{f.name}"))
        if self.offset_sigma < 0 or self.attitude_sigma < 0:
            raise ArgumentError(f"ApproachErrors: offset_sigma and attitude_sigma must be >= 0, got {self.offset_sigma}, "
                                f"{self.attitude_sigma}")
        if self.spin_high < self.spin_low:
            raise ArgumentError(f"ApproachErrors: spin_high {self.spin_high} must be >= spin_low {self.spin_low}")

    def draw(self, seed: int, index: int) -> dict:
        """Sample ``index``'s errors (``CAPTURE_PARAMETERS``), from ``default_rng([seed, index])``."""
        rng = np.random.default_rng([seed, index])
        offset = rng.normal(0.0, 1.0, 3) * self.offset_sigma
        attitude = rng.normal(0.0, 1.0, 3) * self.attitude_sigma
        spin = rng.uniform(self.spin_low, self.spin_high)
        return dict(zip(CAPTURE_PARAMETERS, [*offset, *attitude, spin]))

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


class CaptureCampaignResult(CampaignResult):
    """A [`CampaignResult`][spacearm.campaign.CampaignResult] of a capture-on-contact campaign
    (module docs), with the success rate and its Wilson interval."""

    def outcomes(self) -> np.ndarray:
        """The outcome of every sample: "held", "slipped", "missed", "failed" or "pending"."""
        names = {v: k for k, v in OUTCOME_CODES.items()}
        col = self.metrics[:, self.metric_names.index("outcome")]
        return np.array([names[c] if s == OK else ("failed" if s == FAILED else "pending") for s, c in zip(self.status, col)])

    def success_rate(self, z: float = 1.959963984540054, mask: Optional[np.ndarray] = None):
        """``(rate, low, high)``: the held fraction of the samples that ran (within ``mask`` over
        them, if given) and its Wilson score interval at ``z`` (default 95 %), by the core."""
        held = self.metric("held")
        if mask is not None:
            held = held[np.asarray(mask, dtype=bool)]
        return _core.success_rate(int(np.sum(held == 1.0)), int(held.size), float(z))

    def table(self, percentiles=(50, 90, 99)) -> str:
        """The success rate with its 95 % Wilson interval and the outcome counts, then a Markdown
        table of each number's distribution over the samples that ran."""
        out = self.outcomes()
        counts = {k: int(np.sum(out == k)) for k in ("held", "slipped", "missed")}
        lines = ["| success rate (held) | 95 % Wilson interval | held | slipped | missed |", "|---|---|---|---|---|"]
        if self.n_ok:
            rate, low, high = self.success_rate()
            lines.append(f"| {rate:.3f} | [{low:.3f}, {high:.3f}] | {counts['held']} | {counts['slipped']} | {counts['missed']} |")
        else:
            lines.append("| – | – | 0 | 0 | 0 |")
        head = "| number [unit] | " + " | ".join(f"p{p:g}" for p in percentiles) + " | max | mean |"
        lines += ["", head, "|" + "---|" * (len(percentiles) + 3)]
        for name in ("relative_spin", "relative_speed", "offset", "first_touch"):
            v = self.metric(name)
            v = v[np.isfinite(v)]
            cells = ["–"] * (len(percentiles) + 2) if v.size == 0 else (
                [f"{x:.4g}" for x in np.percentile(v, percentiles)] + [f"{v.max():.4g}", f"{v.mean():.4g}"])
            lines.append(f"| {name} [{_UNITS[name]}] | " + " | ".join(cells) + " |")
        lines.append(f"\n{self.n_ok} samples ran, {self.n_failed} failed, {self.n_pending} not run.")
        return "\n".join(lines)

    def by(self, parameter: str, bins: int = 5):
        """The success rate in ``bins`` equal bins of ``parameter`` (a ``CAPTURE_PARAMETERS``
        name, or ``"offset"``: the norm of the drawn offset; ``"attitude"``: of the attitude
        error) over the samples that ran: ``(centres, rate, low, high, counts)``; a bin without
        samples has NaN rates."""
        if parameter == "offset":
            values = np.linalg.norm(np.column_stack([self.parameter(p) for p in CAPTURE_PARAMETERS[:3]]), axis=1)
        elif parameter == "attitude":
            values = np.linalg.norm(np.column_stack([self.parameter(p) for p in CAPTURE_PARAMETERS[3:6]]), axis=1)
        else:
            values = self.parameter(parameter)
        if values.size == 0:
            raise ArgumentError("no sample of this campaign ran: there is no success rate to bin")
        lo, hi = float(values.min()), float(values.max())
        edges = np.linspace(lo, hi if hi > lo else lo + 1.0, bins + 1)
        which = np.clip(np.searchsorted(edges, values, side="right") - 1, 0, bins - 1)
        rows = []
        for b in range(bins):
            m = which == b
            rows.append(self.success_rate(mask=m) + (int(m.sum()),) if m.any() else (np.nan, np.nan, np.nan, 0))
        r = np.array(rows, dtype=float)
        return 0.5 * (edges[:-1] + edges[1:]), r[:, 0], r[:, 1], r[:, 2], r[:, 3].astype(int)

    def figure(self, parameter: str = "spin", bins: int = 5):
        """The success rate against ``parameter`` with its Wilson intervals, and each sample's
        outcome (a matplotlib ``Figure``)."""
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt

        centres, rate, low, high, counts = self.by(parameter, bins)
        fig, ax = plt.subplots(figsize=(6.4, 4.0))
        ok = np.isfinite(rate)
        yerr = np.maximum([rate[ok] - low[ok], high[ok] - rate[ok]], 0.0)
        ax.errorbar(centres[ok], rate[ok], yerr=yerr, fmt="o-", capsize=4,
                    label="held fraction, 95 % Wilson interval")
        for c, r, n in zip(centres[ok], rate[ok], counts[ok]):
            ax.annotate(f"n={n}", (c, r), textcoords="offset points", xytext=(4, 6), fontsize=8)
        unit = _UNITS.get(parameter, "m" if parameter == "offset" else "rad" if parameter == "attitude" else "")
        ax.set_xlabel(f"{parameter} [{unit}]")
        ax.set_ylabel("success rate")
        ax.set_ylim(-0.05, 1.05)
        ax.set_title(f"capture on contact: {self.n_ok} samples")
        ax.legend(loc="best", fontsize=8)
        fig.tight_layout()
        return fig

    def plot(self, path, parameter: str = "spin", bins: int = 5) -> Path:
        """[`figure`][spacearm.campaign.CaptureCampaignResult.figure] written to ``path`` (atomically)."""
        from ..viz.figures import plot_to

        return Path(plot_to(path, lambda: self.figure(parameter, bins), dpi=110))


def run_capture_campaign(
    robot,
    samples: int,
    *,
    seed: int = 0,
    errors: Optional[ApproachErrors] = None,
    capture=None,
    gripper: Optional[str] = None,
    out: Optional[Union[str, Path]] = None,
    resume: bool = True,
    progress: Union[bool, Callable[[int, int], None]] = False,
) -> CaptureCampaignResult:
    """Fly ``samples`` captures on contact of ``capture`` (a
    [`ContactCapture`][spacearm.capture.ContactCapture]; default its defaults) with ``robot``'s
    gripper, each with approach errors drawn from ``errors`` (module docs), one after the other in
    this thread. With ``out`` (.npz) the result is written at the end (and resumed from if it
    holds this campaign). A sample whose run fails (a diverged state, a refused value) is recorded
    as failed with its message."""
    from ..sim.contact_capture import ContactCapture
    from ..io.model_file import dumps_toml
    from ..model.robot import Robot
    from .executor import _progress

    if not isinstance(robot, Robot):
        raise SpacearmTypeError(f"run_capture_campaign needs a spacearm.Robot, got {type(robot).__name__}")
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 1:
        raise ArgumentError(f"samples must be an integer >= 1, got {samples!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ArgumentError(f"seed must be an integer >= 0, got {seed!r}")
    errors = ApproachErrors() if errors is None else errors
    capture = ContactCapture() if capture is None else capture
    if not isinstance(errors, ApproachErrors):
        raise SpacearmTypeError(f"errors must be a spacearm.campaign.ApproachErrors, got {type(errors).__name__}")
    if not isinstance(capture, ContactCapture):
        raise SpacearmTypeError(f"capture must be a spacearm.capture.ContactCapture, got {type(capture).__name__}")
    gripper = ContactCapture.gripper_of(robot, gripper)["name"]  # refused here, not in every sample
    spec_json = json.dumps({"kind": "capture_contact", "model_toml": dumps_toml(robot), "gripper": gripper,
                            "samples": int(samples), "seed": int(seed), "errors": errors.to_dict(),
                            "capture": capture.to_dict()}, sort_keys=True)
    out = Path(out) if out is not None else None
    if out is not None and out.suffix != ".npz":
        raise ArgumentError(f"out must be a .npz path, got '{out}'")
    result = None
    if out is not None and out.exists() and resume:
        loaded = CaptureCampaignResult.load(out)
        if loaded.spec_json != spec_json:
            raise ArgumentError(f"'{out}' holds a different campaign; choose another output path, or overwrite it "
                                "(resume=False; on the command line --no-resume)")
        result = loaded
    if result is None:
        result = CaptureCampaignResult(spec_json, CAPTURE_PARAMETERS, CAPTURE_METRICS, int(samples))
    pending = [int(i) for i in result.index[result.status == PENDING]]
    bar = _progress(int(samples), int(samples) - len(pending), progress)
    start = time.perf_counter()
    done = 0
    try:
        for i in pending:
            params = errors.draw(int(seed), i)
            t0 = time.perf_counter()
            try:
                run = capture.replace(offset=tuple(params[k] for k in CAPTURE_PARAMETERS[:3]),
                                      attitude_error=tuple(params[k] for k in CAPTURE_PARAMETERS[3:6]),
                                      spin=params["spin"]).fly(robot, gripper)
            except SpacearmError as exc:
                result.record(i, params, None, f"{type(exc).__name__}: {exc}", time.perf_counter() - t0)
            else:
                o = run.outcome
                metrics = {"outcome": OUTCOME_CODES[o.outcome], "held": 1.0 if o.held else 0.0,
                           "relative_spin": o.relative_spin, "relative_speed": o.relative_speed, "offset": o.offset,
                           "fingers_touching": float(o.fingers_touching),
                           "first_touch": np.nan if o.first_touch is None else o.first_touch}
                result.record(i, params, metrics, "", time.perf_counter() - t0)
            done += 1
            bar.update(1)
    finally:
        bar.close()
        elapsed = time.perf_counter() - start
        result.run = {"backend": "in-process", "workers": 0, "scheduler": None, "samples_run": done, "samples_lost": 0,
                      "elapsed_s": elapsed, "samples_per_s": done / elapsed if elapsed > 0 else float("nan")}
        if out is not None:
            result.save(out)
    return result
