"""FMI co-simulation units (docs/fmi.md), imported by FMPy (a maintained FMU importer, the
independent side of these checks): FMPy's validation passes, and ``fmpy.simulate_fmu`` of the FMU
equals ``spacearm.simulate`` of the same model and inputs, for FMI 3 and FMI 2, for spatial6 and
for the UR5 of example-robot-data mounted on the shipped example bus (``spacearm.examples.path("spacecraft_bus")``).

The reference run applies the same held inputs through a [`Callback`][spacearm.control.Callback]
(or the same native controller), with the FMU's RK4 step; the FMU's outputs at every
communication point must equal the recorded states and derived quantities to 1e-9 (relative to
each quantity's scale): the same integrator on the same model, so anything more is a defect.
"""

from __future__ import annotations

import os

import numpy as np
import pytest

import spacearm
import spacearm.fmi
from spacearm.control import Callback, JointPD
from spacearm.errors import ArgumentError, MissingDependencyError
from spacearm.io.urdf import load_urdf

from robot_data import robot_urdf

fmpy = pytest.importorskip("fmpy", reason="FMPy (a test extra) validates and runs the FMUs")
from fmpy.validation import validate_fmu  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUS = str(spacearm.examples.path("spacecraft_bus"))
DT = 2e-3
OUTPUT = 0.01


def columns(result, group: str, n: int) -> np.ndarray:
    return np.column_stack([result[f"{group}[{k}]"] for k in range(1, n + 1)])


def fmu_run(path, robot, duration, tau, wrench=None, start=None):
    """Simulate the FMU with FMPy with constant inputs; the result's structured array."""
    names = [f"tau[{k}]" for k in range(1, robot.n_dof + 1)] + ([f"base_wrench[{k}]" for k in range(1, 7)] if wrench is not None else [])
    values = list(tau) + (list(wrench) if wrench is not None else [])
    signal = np.array([(0.0, *values), (duration, *values)], dtype=[("time", float)] + [(n, float) for n in names])
    return fmpy.simulate_fmu(str(path), stop_time=duration, step_size=OUTPUT, output_interval=OUTPUT, input=signal,
                             start_values=start or {}, fmi_type="CoSimulation")


def assert_same(result, traj, robot):
    """The FMU's outputs at its communication points against the simulation's records there."""
    every = int(round(OUTPUT / DT))
    keep = slice(None, None, every)
    assert np.allclose(result["time"], traj.t[keep], rtol=0, atol=1e-12)
    n = robot.n_dof
    fmu_x = np.hstack([columns(result, "r0", 3), columns(result, "quat0", 4), columns(result, "q", n)])
    fmu_u = np.hstack([columns(result, "v0", 3), columns(result, "w0", 3), columns(result, "qd", n)])
    pairs = [(fmu_x, traj.x[keep]), (fmu_u, traj.u[keep]), (columns(result, "P", 3), traj.P[keep]),
             (columns(result, "L", 3), traj.L_origin[keep])]
    if traj.has("ee_position"):
        pairs += [(columns(result, "ee_position", 3), traj.ee_position[keep]), (columns(result, "ee_quat", 4), traj.ee_quat[keep])]
    for got, want in pairs:
        scale = max(1.0, np.abs(want).max())
        assert np.abs(got - want).max() <= 1e-9 * scale, np.abs(got - want).max()
    # The run moved: a frozen FMU would not pass.
    assert np.abs(traj.u[-1] - traj.u[0]).max() > 1e-3


@pytest.fixture(scope="module")
def ur5_on_bus() -> spacearm.Robot:
    return load_urdf(robot_urdf("ur_description/urdf/ur5_robot.urdf"), mount_on=spacearm.io.load_toml(BUS), at=(0.6, 0, 0, 0, 0, 0))


@pytest.mark.parametrize("version", [3, 2])
def test_spatial6_fmu_matches_simulate(tmp_path, version):
    robot = spacearm.presets.spatial6()
    path = spacearm.fmi.export(robot, tmp_path / "s6.fmu", dt=DT, fmi_version=version)
    assert validate_fmu(str(path)) == []
    tau = np.array([2.0, -1.5, 1.0, 0.5, -0.3, 0.2])
    u0 = np.concatenate([[0.01, -0.02, 0.0, 0.01, 0.02, -0.01], np.full(6, 0.05)])
    start = {f"u0[{k + 1}]": v for k, v in enumerate(u0)}
    duration = 0.2
    result = fmu_run(path, robot, duration, tau, start=start)
    traj = spacearm.simulate(robot, duration, dt=DT, u0=u0, controller=Callback(lambda t, x, u: tau))
    assert_same(result, traj, robot)


@pytest.mark.parametrize("version", [3, 2])
def test_ur5_on_the_bus_flying_fmu_matches_simulate(tmp_path, ur5_on_bus, version):
    robot = ur5_on_bus
    path = spacearm.fmi.export(robot, tmp_path / "ur5.fmu", mode="flying", dt=DT, fmi_version=version)
    assert validate_fmu(str(path)) == []
    tau = np.array([1.0, -2.0, 1.5, 0.4, -0.2, 0.1])
    wrench = np.array([5.0, -3.0, 2.0, 0.5, -0.4, 0.3])
    x0 = robot.neutral_configuration()
    x0[7:] = [-0.4, -1.1, 1.3, -0.7, 0.5, 0.3]
    start = {f"x0[{k + 1}]": v for k, v in enumerate(x0)}
    duration = 0.2
    result = fmu_run(path, robot, duration, tau, wrench=wrench, start=start)
    traj = spacearm.simulate(robot, duration, dt=DT, x0=x0, mode="flying", controller=Callback(lambda t, x, u: (tau, wrench)))
    assert_same(result, traj, robot)


def test_native_controller_in_the_fmu_with_its_set_point_a_parameter(tmp_path):
    robot = spacearm.presets.spatial6()
    q0 = robot.initial_q
    exported = JointPD(kp=2.0, kd=0.5, reference=q0)
    path = spacearm.fmi.export(robot, tmp_path / "pd.fmu", controller=exported, dt=DT, fmi_version=3)
    assert validate_fmu(str(path)) == []
    q_ref = q0 + np.array([0.2, -0.1, 0.15, 0.1, -0.2, 0.3])
    start = {f"q_ref[{k + 1}]": v for k, v in enumerate(q_ref)}
    duration = 0.2
    result = fmu_run(path, robot, duration, np.zeros(6), start=start)
    traj = spacearm.simulate(robot, duration, dt=DT, controller=JointPD(kp=2.0, kd=0.5, reference=q_ref))
    assert_same(result, traj, robot)


def test_a_communication_step_that_is_not_a_multiple_of_the_rk4_step_is_an_error(tmp_path):
    path = spacearm.fmi.export(spacearm.presets.planar4(), tmp_path / "p4.fmu", dt=DT)
    with pytest.raises(Exception, match="DoStep|failed|Error"):
        fmpy.simulate_fmu(str(path), stop_time=0.01, output_interval=0.0015, fmi_type="CoSimulation")


def test_export_errors(tmp_path, monkeypatch):
    robot = spacearm.presets.planar4()
    with pytest.raises(ArgumentError, match="fmi_version"):
        spacearm.fmi.export(robot, tmp_path / "a.fmu", fmi_version=1)
    with pytest.raises(ArgumentError, match="mode"):
        spacearm.fmi.export(robot, tmp_path / "a.fmu", mode="hovering")
    from spacearm.control import QuinticJoint
    with pytest.raises(ArgumentError, match="constant set point"):
        spacearm.fmi.export(robot, tmp_path / "a.fmu", controller=JointPD(1.0, 1.0, QuinticJoint(robot.initial_q, robot.initial_q, 0, 1)))
    monkeypatch.setenv("SPACEARM_C_LIBRARY", str(tmp_path / "nowhere.so"))
    with pytest.raises(MissingDependencyError, match="SPACEARM_C_LIBRARY"):
        spacearm.fmi.export(robot, tmp_path / "a.fmu")
    assert not (tmp_path / "a.fmu").exists()


def test_the_fmu_command_writes_an_fmu_with_the_controller_parameters(tmp_path):
    import xml.etree.ElementTree as ET
    import zipfile

    from spacearm.cli import main

    out = tmp_path / "s6.fmu"
    assert main(["fmu", "spatial6", "--out", str(out), "--fmi-version", "2", "--controller", "pd", "--kp", "3", "--kd", "1",
                 "--mode", "flying"]) == 0
    assert validate_fmu(str(out)) == []
    with zipfile.ZipFile(out) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
        assert z.read("resources/model.toml").decode() == spacearm.io.dumps_toml(spacearm.presets.spatial6())
    assert root.get("fmiVersion") == "2.0"
    starts = {v.get("name"): float(v.find("Real").get("start")) for v in root.iter("ScalarVariable") if v.find("Real").get("start")}
    assert starts["kp[1]"] == 3.0 and starts["kd[6]"] == 1.0 and "base_wrench[6]" in starts
    assert np.allclose([starts[f"q_ref[{k}]"] for k in range(1, 7)], spacearm.presets.spatial6().initial_q)


def test_the_fmu_command_answers_bad_options_in_one_line(tmp_path, capsys):
    from spacearm.cli import main

    assert main(["fmu", "spatial6", "--out", str(tmp_path / "a.fmu"), "--kp", "3"]) == 2
    assert "spacearm: error: --kp needs --controller pd or ct" in capsys.readouterr().err
    assert main(["fmu", "spatial6", "--out", str(tmp_path / "a.fmu"), "--controller", "ct", "--kp", "1,2", "--kd", "1"]) == 2
    assert "kp" in capsys.readouterr().err
    assert not (tmp_path / "a.fmu").exists()
