"""`spacearm simulate --orbit circular:ALT_KM[,INC_DEG]`: the run it builds is the Python API's
orbital run (the system CM put on the orbit), the files include the LVLH figure, the trajectory
keeps its orbit through a save and load, and bad orbits are `spacearm: error:` with exit 2."""

import math

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
