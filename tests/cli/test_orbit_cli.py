"""`spacearm simulate --orbit circular:ALT_KM[,INC_DEG]`: the run it builds is the Python API's
orbital run (the system CM put on the orbit), the files include the LVLH figure, the trajectory
keeps its orbit through a save and load, and bad orbits are `spacearm: error:` with exit 2."""

import math
import re

import numpy as np
import pytest

import spacearm
from spacearm import control
from spacearm.cli import main
from spacearm.sim.trajectory import Trajectory


def test_simulate_in_orbit_is_the_python_run(tmp_path, capsys):
    out, png = tmp_path / "run.npz", tmp_path / "run.png"
    code = main(["simulate", "planar4", "--controller", "pd", "--duration", "0.5", "--dt", "0.01",
                 "--orbit", "circular:500,51.6", "--out", str(out), "--plot", str(png), "--no-progress"])
    assert code == 0
    text = capsys.readouterr().out
    assert "momentum balance in orbit" in text and "in orbit: a = 6878.1 km, i = 51.60 deg" in text
    assert (tmp_path / "run_lvlh.png").stat().st_size > 0
    traj = Trajectory.load(out)
    robot = spacearm.presets.planar4()
    x0 = robot.neutral_configuration()
    x0[:3] -= robot.center_of_mass(x0)
    orbit = spacearm.Orbit.circular(500e3, inclination=math.radians(51.6))
    np.testing.assert_allclose(traj.r_cm_eci[0], orbit.r0, atol=1e-6)
    assert traj.meta["orbit"]["gravity_gradient"] is True
    assert traj.attitude_lvlh().shape == (len(traj), 3, 3)
    assert np.allclose(traj.x[0], x0)


@pytest.mark.parametrize("value, needle", [
    ("geo:5", "circular:ALT_KM[,INC_DEG]"),
    ("circular:500,200", "inclination"),
    ("circular:-3", "altitude"),
    ("circular:", "circular:ALT_KM"),
])
def test_bad_orbits_are_cli_errors(value, needle, capsys):
    assert main(["simulate", "planar4", "--duration", "0.01", f"--orbit={value}", "--no-progress"]) == 2
    assert needle in capsys.readouterr().err


def test_capture_in_orbit_from_the_cli(tmp_path, capsys):
    """`spacearm capture --orbit`: the capture in orbit, floating and flying, with the balance,
    the record's orbital arrays and the figure with the LVLH panels."""
    out, png = tmp_path / "cap.npz", tmp_path / "cap.png"
    for mode in ("floating", "flying"):
        code = main(["capture", "spatial6", "--target-mass", "50", "--target-inertia", "4,5,6", "--target-spin", "0,0,0.1",
                     "--mode", mode, "--detumble-time", "2", "--max-joint-torque", "20", "--max-force", "10", "--max-torque", "5",
                     "--orbit", "circular:500,51.6", "--out", str(out)] + (["--plot", str(png)] if mode == "floating" else []))
        assert code == 0
        text = capsys.readouterr().out
        assert "in orbit: 500 km, 51.6 deg, gravity gradient on" in text
        assert "momentum balance of robot + target" in text
        data = np.load(out)
        # The start is given with the end (issue 37 item 4: only "final base attitude 51.89 deg
        # from LVLH" was printed, for a base that started 51.60 deg from LVLH). The start,
        # independently: the CLI starts the base aligned with ECI, so its angle from LVLH is
        # that of the LVLH frame of the initial orbital state.
        m = re.search(r"base attitude from LVLH ([0-9.]+) deg at the start, ([0-9.]+) deg at the end", text)
        assert m, text
        lvlh = spacearm.Orbit.lvlh_to_eci(data["r_cm_eci"][0], data["v_cm_eci"][0])
        assert np.allclose(data["x"][0, 3:7], [0, 0, 0, 1])
        start = np.degrees(np.arccos(np.clip(0.5 * (np.trace(lvlh) - 1.0), -1.0, 1.0)))
        assert float(m.group(1)) == pytest.approx(start, abs=1e-3 + 1e-4 * start)
        assert data["r_cm_eci"].shape == (len(data["t"]), 3) and data["target_lvlh"].shape == (len(data["t"]), 6)
    assert png.stat().st_size > 0


def test_capture_target_lvlh_needs_an_orbit(capsys):
    code = main(["capture", "spatial6", "--target-mass", "50", "--target-inertia", "4,5,6", "--target-lvlh", "0,1,0"])
    assert code == 2
    assert "--target-lvlh needs --orbit" in capsys.readouterr().err


def test_campaign_in_orbit_from_the_cli(tmp_path, capsys):
    out = tmp_path / "c.npz"
    code = main(["campaign", "planar4", "--samples", "2", "--workers", "0", "--duration", "0.1", "--dt", "0.01",
                 "--orbit", "circular:500", "--out", str(out), "--no-progress"])
    assert code == 0
    from spacearm.campaign.spec import CampaignSpec
    from spacearm.campaign.scenario import Scenario

    sc = Scenario(orbit=spacearm.Orbit.circular(500e3))
    back = CampaignSpec.from_json(CampaignSpec("", 1, scenario=sc).to_json()).scenario
    assert back == sc and back.orbit_model().period == pytest.approx(spacearm.Orbit.circular(500e3).period, rel=1e-12)


def test_the_orbit_pages_capture_command_detumbles(capsys):
    # The command of docs/orbit.md, as written there (issue 37 item 4: it ended "detumbled: not
    # within the run"); its detumble time as the page states it.
    import shlex
    from pathlib import Path

    page = (Path(__file__).resolve().parents[2] / "docs" / "orbit.md").read_text(encoding="utf-8")
    (line,) = [ln for ln in page.splitlines() if ln.startswith("spacearm capture ") and "--orbit" in ln]
    assert main(shlex.split(line)[1:]) == 0
    text = capsys.readouterr().out
    m = re.search(r"detumbled: ([0-9.]+) s after the detumble starts", text)
    assert m, text
    assert f"`detumbled: {m.group(1)} s after the detumble starts`" in page
