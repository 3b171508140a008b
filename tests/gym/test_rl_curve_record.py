"""The recorded Reach learning curve of docs/rl.md (benchmarks/rl_reach.py, not run here):
the figure the page shows exists, the JSON's curve rises, and the page's numbers are the JSON's.
Reads files only."""

import json
import re
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "rl.md"
CURVE = ROOT / "docs" / "figures" / "rl_reach_learning_curve.json"


def _record():
    return json.loads(CURVE.read_text())


def test_the_page_shows_the_recorded_figure():
    text = PAGE.read_text()
    assert "figures/rl_reach_learning_curve.png" in text
    png = ROOT / "docs" / "figures" / "rl_reach_learning_curve.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_recorded_curve_rises_above_the_zero_policy():
    rec = _record()
    ev = [c["eval"] for c in rec["curve"]]
    returns = np.array([e["mean_return"] for e in ev])
    success = np.array([e["success_rate"] for e in ev])
    zero = rec["baselines"]["zero"]
    # Iteration 0 is the damper, which at rest is the zero policy: the same return on the same goals.
    assert returns[0] == zero["mean_return"] and zero["success_rate"] == 0.0
    # The last ten iterations: well above the zero policy, and most goals reached.
    assert returns[-10:].mean() > zero["mean_return"] + 0.4 * abs(zero["mean_return"])
    assert success[-10:].mean() > 0.5
    assert np.all(np.diff([c["env_steps"] for c in rec["curve"]]) > 0)


def test_the_page_quotes_the_recorded_numbers():
    rec = _record()
    text = PAGE.read_text().replace("−", "-")
    returns = [c["eval"]["mean_return"] for c in rec["curve"]]
    quoted = {f"{returns[0]:.1f}", f"{np.mean(returns[-10:]):.1f}", f"{max(returns):.1f}", f"{returns[-1]:.1f}",
              f"{rec['baselines']['rmrc_naive']['mean_return']:.1f}", f"{rec['baselines']['rmrc_minimum_disturbance']['mean_return']:.1f}"}
    section = text[text.index("## A learning curve without PyTorch"):]
    missing = [q for q in quoted if not re.search(re.escape(q) + r"(?!\d)", section)]
    assert not missing, missing
