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
from spacearm.errors import ArgumentError, MissingDependencyError, SpacearmTypeError
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
    start = {f"reference[{k + 1}]": v for k, v in enumerate(q_ref)}
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
    with pytest.raises(ArgumentError, match="callback"):
        spacearm.fmi.export(robot, tmp_path / "a.fmu", controller=Callback(lambda t, x, u: np.zeros(4)))
    with pytest.raises(ArgumentError, match="controller"):
        spacearm.fmi.export(robot, tmp_path / "a.fmu", controller="pd")
    # A law the mode cannot run: the core's message, at export.
    with pytest.raises(ArgumentError, match="rotation-floating"):
        spacearm.fmi.export(robot, tmp_path / "a.fmu", controller=spacearm.control.AttitudeControl([0, 0, 0, 1], kp=1.0, kd=1.0))
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
    assert np.allclose([starts[f"reference[{k}]"] for k in range(1, 7)], spacearm.presets.spatial6().initial_q)
    # The names of the core: computed-torque and ct are computed_torque; other laws go through export().
    assert main(["fmu", "spatial6", "--out", str(out), "--controller", "computed-torque", "--kp", "4", "--kd", "4"]) == 0
    with zipfile.ZipFile(out) as z:
        assert b'kind = "computed_torque"' in z.read("resources/options.toml")


def test_the_fmu_command_answers_bad_options_in_one_line(tmp_path, capsys):
    from spacearm.cli import main

    assert main(["fmu", "spatial6", "--out", str(tmp_path / "a.fmu"), "--kp", "3"]) == 2
    assert "spacearm: error: --kp needs --controller joint_pd or computed_torque" in capsys.readouterr().err
    assert main(["fmu", "spatial6", "--out", str(tmp_path / "a.fmu"), "--controller", "pid"]) == 2
    assert "unknown controller 'pid'" in capsys.readouterr().err
    assert main(["fmu", "spatial6", "--out", str(tmp_path / "a.fmu"), "--controller", "attitude"]) == 2
    assert "spacearm.fmi.export" in capsys.readouterr().err
    assert main(["fmu", "spatial6", "--out", str(tmp_path / "a.fmu"), "--controller", "ct", "--kp", "1,2", "--kd", "1"]) == 2
    assert "kp" in capsys.readouterr().err
    assert main(["fmu", "spatial6", "--out", str(tmp_path / "a.fmu"), "--dt", "1e300"]) == 2
    assert "spacearm: error: dt must be between" in capsys.readouterr().err
    assert not (tmp_path / "a.fmu").exists()


# ---- issue 38: bounded steps, checked options and tokens ----

MAX_STEPS_PER_CALL = 1_000_000  # SPACEARM_MAX_STEPS_PER_CALL of crates/spacearm-c/include/spacearm.h


def test_the_header_states_the_cap_this_file_uses():
    header = open(os.path.join(ROOT, "crates", "spacearm-c", "include", "spacearm.h")).read()
    assert f"#define SPACEARM_MAX_STEPS_PER_CALL {MAX_STEPS_PER_CALL}\n" in header


def slave(path, version: int, token=None):
    """An FMPy co-simulation instance of the FMU at ``path`` (not yet instantiated)."""
    from fmpy.fmi2 import FMU2Slave
    from fmpy.fmi3 import FMU3Slave

    md = fmpy.read_model_description(str(path))
    cls = FMU3Slave if version == 3 else FMU2Slave
    return cls(guid=md.guid if token is None else token, unzipDirectory=fmpy.extract(str(path)),
               modelIdentifier=md.coSimulation.modelIdentifier, instanceName="t")


def fmi2_callbacks(fmu, messages: list):
    """FMI 2 callbacks whose logger appends ``(status, message)`` to ``messages`` (kept alive by
    ``fmu``)."""
    import ctypes

    from fmpy.fmi2 import fmi2CallbackFunctions, defaultCallbacks

    # The FMU calls the (variadic) logger with the format "%s" and the message as the next
    # argument: declare that argument to read it (the same registers on the platforms tested).
    logger_type = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_char_p,
                                   ctypes.c_char_p)
    logger = logger_type(lambda env, name, status, category, fmt, message: messages.append((status, message.decode())))
    callbacks = fmi2CallbackFunctions()
    callbacks.logger = ctypes.cast(logger, type(defaultCallbacks.logger))
    callbacks.allocateMemory = defaultCallbacks.allocateMemory
    callbacks.freeMemory = defaultCallbacks.freeMemory
    fmu._keep_logger = logger  # alive as long as the instance
    return callbacks


def instantiate(fmu, version: int, messages: list) -> None:
    """Instantiate with a logger that appends ``(status, message)`` to ``messages``."""
    if version == 3:
        fmu.instantiate(logMessage=lambda env, status, category, message: messages.append((status, message.decode())))
    else:
        fmu.instantiate(callbacks=fmi2_callbacks(fmu, messages))


@pytest.mark.parametrize("version", [3, 2])
def test_instantiation_checks_the_token(tmp_path, version):
    path = spacearm.fmi.export(spacearm.presets.planar4(), tmp_path / "p4.fmu", dt=DT, fmi_version=version)
    other = "{00000000-0000-0000-0000-000000000000}"
    messages: list = []
    with pytest.raises(Exception, match="instantiate"):
        instantiate(slave(path, version, token=other), version, messages)
    assert any(status == 3 and other in m and ("instantiationToken" if version == 3 else "guid") in m for status, m in messages), messages
    messages.clear()
    fmu = slave(path, version)
    instantiate(fmu, version, messages)
    assert not [m for status, m in messages if status == 3], messages
    fmu.freeInstance()


@pytest.mark.parametrize("version", [3, 2])
def test_instantiation_for_what_the_unit_does_not_run_is_null_with_a_logged_message(tmp_path, version):
    import ctypes
    import pathlib

    path = spacearm.fmi.export(spacearm.presets.planar4(), tmp_path / "p4.fmu", dt=DT, fmi_version=version)
    fmu = slave(path, version)
    messages: list = []
    if version == 3:
        # Event mode (the unit declares hasEventMode=false).
        with pytest.raises(Exception, match="instantiate"):
            fmu.instantiate(eventModeUsed=True, logMessage=lambda env, status, category, message: messages.append((status, message.decode())))
        expected = "no event mode"
    else:
        # Model exchange (fmi2ModelExchange = 0; the unit is co-simulation only).
        resources = pathlib.Path(fmu.unzipDirectory, "resources").as_uri().encode()
        component = fmu.fmi2Instantiate(b"t", 0, fmu.guid.encode(), resources, ctypes.byref(fmi2_callbacks(fmu, messages)), 0, 0)
        assert not component
        expected = "co-simulation only"
    assert any(status == 3 and expected in m for status, m in messages), messages


@pytest.mark.parametrize("version", [3, 2])
def test_a_communication_step_of_more_than_the_cap_is_refused_before_any_step(tmp_path, version):
    from fmpy.fmi1 import FMICallException

    path = spacearm.fmi.export(spacearm.presets.planar4(), tmp_path / "p4.fmu", dt=DT, fmi_version=version)
    fmu = slave(path, version)
    messages: list = []
    instantiate(fmu, version, messages)
    if version == 2:
        fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    # One RK4 step more than the cap (an exact multiple of dt), then a step that would saturate
    # the step count (1e300 / dt): both refused at once, the FMU still at t = 0.
    for h in ((MAX_STEPS_PER_CALL + 1) * DT, 1e300):
        messages.clear()
        with pytest.raises(FMICallException):
            fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=h)
        assert any(status == 3 and "SPACEARM_MAX_STEPS_PER_CALL" in m for status, m in messages), messages
    fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=DT)
    vr = next(v.valueReference for v in fmpy.read_model_description(str(path)).modelVariables if v.name == "time")
    assert (fmu.getFloat64 if version == 3 else fmu.getReal)([vr]) == [DT]
    fmu.terminate()
    fmu.freeInstance()


def test_export_refuses_option_values_out_of_range_or_of_the_wrong_type(tmp_path):
    robot = spacearm.presets.planar4()
    out = tmp_path / "a.fmu"
    for dt in (1e300, 1e-300, 1e-7, 11.0, float("nan"), float("inf"), 0.0, -1e-3):
        with pytest.raises(ArgumentError, match="dt"):
            spacearm.fmi.export(robot, out, dt=dt)
    for dt in (True, "0.001", 1e-3 + 0j, None):
        with pytest.raises(SpacearmTypeError, match="dt"):
            spacearm.fmi.export(robot, out, dt=dt)
    for joint_limits in ("no", 1, None):
        with pytest.raises(SpacearmTypeError, match="joint_limits"):
            spacearm.fmi.export(robot, out, joint_limits=joint_limits)
    with pytest.raises(SpacearmTypeError, match="stop_time"):
        spacearm.fmi.export(robot, out, stop_time=True)
    with pytest.raises(ArgumentError, match="stop_time"):
        spacearm.fmi.export(robot, out, stop_time=-1.0)
    with pytest.raises(ArgumentError, match="fmi_version"):
        spacearm.fmi.export(robot, out, fmi_version=True)
    assert not out.exists()
    # The bounds themselves are accepted.
    for dt in (1e-6, 10.0, np.float64(2e-3)):
        spacearm.fmi.export(robot, out, dt=dt, joint_limits=np.bool_(False))
