"""``spacearm capture``: the printed summary, the record file and its contents, figures, and clean
errors (``spacearm: error: ...``, exit 2)."""

from __future__ import annotations

import numpy as np
import pytest

from spacearm.cli import main

BASE = ["capture", "spatial6", "--target-mass", "50", "--target-inertia", "4,5,6", "--target-spin", "0,0,0.1",
        "--detumble-time", "4", "--max-joint-torque", "20"]


def test_floating_capture_summary_and_record(tmp_path, capsys):
    out = tmp_path / "cap.npz"
    fig = tmp_path / "cap.png"
    assert main(BASE + ["--mode", "floating", "--out", str(out), "--plot", str(fig)]) == 0
    text = capsys.readouterr().out
    for phrase in ("rigid grasp, floating mode", "impulse on the robot", "base jump", "peak grasp wrench",
                   "peak joint torque", "detumbled", "momentum drift"):
        assert phrase in text
    data = np.load(out)
    T = data["t"].size
    assert data["P"].shape == (T, 3) and data["L"].shape == (T, 3) and data["phase"].shape == (T,)
    assert data["impulse"].shape == (6,) and np.linalg.norm(data["impulse"]) > 0
    # floating mode: robot + target momentum is conserved through every phase
    scale = np.abs(data["L"]).max()
    assert np.abs(data["L"] - data["L"][0]).max() < 1e-8 * scale
    assert set(np.unique(data["phase"])) == {0, 1, 2, 3}
    assert fig.stat().st_size > 10_000


def test_flying_point_contact(capsys):
    assert main(BASE + ["--mode", "flying", "--kind", "point", "--restitution", "0.5", "--max-torque", "5"]) == 0
    text = capsys.readouterr().out
    assert "point grasp, flying mode" in text and "momentum change by the thrusters" in text


@pytest.mark.parametrize("extra, message", [
    (["--restitution", "2"], "--restitution must be in [0, 1]"),
    (["--target-at", "1,2"], "--target-at expects 3"),
    (["--target-at", "40,0,0"], "no handle that long"),  # the default handle: 37 m towards the gripper
    (["--target-at", "40,0,0", "--grasp-offset", "0.3,0,0"], "cannot reach the target"),
])
def test_errors_are_clean(extra, message, capsys):
    argv = BASE + extra + (["--approach-time", "0.5"] if "40,0,0" in extra else [])
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("spacearm: error:") and message in err
    assert "Traceback" not in err


def test_bad_target_inertia(capsys):
    argv = ["capture", "spatial6", "--target-mass", "50", "--target-inertia", "1,1,5"]
    assert main(argv) == 2
    assert "triangle" in capsys.readouterr().err
