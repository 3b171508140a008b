"""The capture-on-contact campaign (docs/campaigns.md, "A capture-on-contact campaign";
spacearm.campaign.capture_contact): each sample's outcome is the one its capture gives when flown
alone, the success rate and its Wilson interval are the closed form's (and the core's), the draw
depends on the seed and the index only, a result file resumes, and ``spacearm campaign
--capture-contact`` prints the success-rate table; the CLI capture on contact exits 0 on a held
grasp and 1 on a missed one."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import spacearm
from spacearm import _core
from spacearm.campaign import ApproachErrors, CaptureCampaignResult, run_capture_campaign
from spacearm.campaign.capture_contact import CAPTURE_PARAMETERS
from spacearm.capture import ContactCapture
from spacearm.errors import ArgumentError

ROBOT = spacearm.io.load_toml(spacearm.examples.path("gripper_servicer"))
SHORT = ContactCapture(duration=1.0)  # the window: its last 0.5 s


def wilson(k: int, n: int, z: float = 1.959963984540054):
    """The Wilson score interval, written out here: the roots p of (k/n − p)² = z² p (1 − p) / n."""
    p = k / n
    a = 1 + z * z / n
    b = -(2 * p + z * z / n)
    c = p * p
    disc = math.sqrt(max(b * b - 4 * a * c, 0.0))
    return p, (-b - disc) / (2 * a), (-b + disc) / (2 * a)


def test_the_wilson_interval_is_the_closed_form():
    for k, n in [(0, 5), (2, 5), (5, 5), (13, 40)]:
        r = _core.success_rate(k, n)
        assert np.allclose(r, wilson(k, n), atol=1e-14, rtol=0), (k, n, r)
    with pytest.raises(ArgumentError, match="at least one trial"):
        _core.success_rate(0, 0)


def test_each_sample_is_its_capture_flown_alone_and_the_rate_counts_them(tmp_path):
    errors = ApproachErrors(offset_sigma=0.003, spin_low=0.05, spin_high=3.0)
    out = tmp_path / "c.npz"
    res = run_capture_campaign(ROBOT, 4, seed=3, errors=errors, capture=SHORT, out=out)
    assert isinstance(res, CaptureCampaignResult) and res.n_ok == 4
    outcomes = res.outcomes()
    for i in range(4):
        p = errors.draw(3, i)
        assert np.array_equal(res.params[i], [p[k] for k in CAPTURE_PARAMETERS])
        alone = SHORT.replace(offset=tuple(p[k] for k in CAPTURE_PARAMETERS[:3]), spin=p["spin"]).fly(ROBOT)
        assert outcomes[i] == alone.outcome.outcome
        assert res.metrics[i, res.metric_names.index("relative_spin")] == alone.outcome.relative_spin
    held = int(np.sum(outcomes == "held"))
    assert np.allclose(res.success_rate(), wilson(held, 4), atol=1e-14)
    table = res.table()
    rate, low, high = wilson(held, 4)
    assert f"| {rate:.3f} | [{low:.3f}, {high:.3f}] |" in table
    # The file resumes: nothing left to run, the same numbers read back.
    again = run_capture_campaign(ROBOT, 4, seed=3, errors=errors, capture=SHORT, out=out)
    assert again.run["samples_run"] == 0 and np.array_equal(again.metrics, res.metrics)
    with pytest.raises(ArgumentError, match="different campaign"):
        run_capture_campaign(ROBOT, 4, seed=4, errors=errors, capture=SHORT, out=out)


def test_a_target_far_off_is_always_missed_and_a_slow_one_on_centre_held():
    far = run_capture_campaign(ROBOT, 2, errors=ApproachErrors(offset_sigma=1.0), capture=SHORT.replace(duration=0.7, window=0.2))
    # 1 m per axis: the 0.12 m fingers cannot reach a handle that far (with probability ~1; these draws are > 0.3 m).
    assert np.all(np.linalg.norm(far.params[:, :3], axis=1) > 0.3)
    assert list(far.outcomes()) == ["missed", "missed"] and far.success_rate()[0] == 0.0
    held = run_capture_campaign(ROBOT, 1, capture=ContactCapture())
    assert list(held.outcomes()) == ["held"]


def test_the_draw_depends_on_seed_and_index_only_and_bad_input_is_named():
    e = ApproachErrors(offset_sigma=0.01, attitude_sigma=0.1, spin_low=0.0, spin_high=1.0)
    assert e.draw(7, 2) == e.draw(7, 2) and e.draw(7, 2) != e.draw(7, 3) and e.draw(7, 2) != e.draw(8, 2)
    with pytest.raises(ArgumentError, match="spin_high"):
        ApproachErrors(spin_low=1.0, spin_high=0.5)
    with pytest.raises(ArgumentError, match="grippers"):
        run_capture_campaign(spacearm.presets.planar4(), 1)


def test_the_cli_campaign_prints_the_success_rate(tmp_path, capsys):
    from spacearm.cli import main

    argv = ["campaign", "gripper_servicer", "--capture-contact", "--samples", "2", "--duration", "1.0", "--spin", "0.05,2",
            "--out", str(tmp_path / "c.npz"), "--no-progress", "--plot", str(tmp_path / "c.png")]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "| success rate (held) | 95 % Wilson interval |" in text and (tmp_path / "c.png").stat().st_size > 0
    res = CaptureCampaignResult.load(tmp_path / "c.npz")
    rate, low, high = res.success_rate()
    assert f"| {rate:.3f} | [{low:.3f}, {high:.3f}] |" in text
    assert main(argv[:-2] + ["--scheduler", "tcp://x:1"]) == 2
    assert "spacearm: error: --scheduler" in capsys.readouterr().err


def test_the_cli_capture_on_contact_exits_0_when_held_and_1_when_missed(capsys):
    from spacearm.cli import main

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main(["capture", "gripper_servicer", "--contact"]) == 0
    text = capsys.readouterr()
    assert "HELD" in text.out and text.err == ""
    assert main(["capture", "gripper_servicer", "--contact", "--offset", "0,0.3,0", "--duration", "1"]) == 1
    text = capsys.readouterr()
    assert "MISSED" in text.out and "no finger came within" in text.out and "Traceback" not in text.err
    assert main(["capture", "gripper_servicer", "--contact", "--target-inertia", "1,1,1"]) == 2
    assert "--target-inertia" in capsys.readouterr().err
    assert main(["capture", "planar4", "--contact"]) == 2
    assert "grippers" in capsys.readouterr().err
    assert main(["capture", "planar4"]) == 2
    assert "--target-mass" in capsys.readouterr().err


def test_the_nominal_placement_is_docs_contact_example_and_errors_move_it_as_stated():
    from spacearm.rotations import quat_to_matrix

    s = ContactCapture(spin=0.05).target_state(ROBOT)
    # docs/contact.md's hand-placed state: CM 1.35 m out along x, axes along 𝒥's, spinning about y.
    assert np.allclose(s, [1.35, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0.05, 0], atol=1e-15)
    c = ROBOT.point_position(ROBOT.neutral_configuration(), "hand_center")
    s = ContactCapture(spin=0.2, offset=(0.0, 0.01, -0.02), attitude_error=(0.1, -0.2, 0.3)).target_state(ROBOT)
    R = quat_to_matrix(s[3:7])
    assert np.allclose(s[:3] + R @ [-0.29, 0, 0], c + [0.0, 0.01, -0.02], atol=1e-15)  # the handle's centre moved by the offset
    assert np.isclose(np.linalg.norm(s[10:13]), 0.2) and np.allclose(R.T @ s[10:13], [0, 0.2, 0], atol=1e-15)  # about the handle
    angle = np.degrees(np.arccos((np.trace(R) - 1) / 2))
    assert np.isclose(angle, np.degrees(np.linalg.norm([0.1, -0.2, 0.3])))  # the nominal attitude is the identity
