"""Model options shared by every subcommand that takes MODEL, number lists, negative values.

The real arm is the UR5 of ``example-robot-data`` (a test extra) mounted on the shipped
the shipped ``spacecraft_bus`` (``spacearm.examples``). What the CLI prints is checked against the library
API called directly (``load_urdf`` with the same options, ``generalized_jacobian`` at an
explicitly constructed point), not against the CLI's own code path.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import spacearm
from spacearm.cli import main
from spacearm.cli.numbers import CliError, attach_negative_values, parse_numbers
from spacearm.io.model_file import dumps_toml
from spacearm.io.urdf import load_urdf

from robot_data import robot_urdf

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUS = str(spacearm.examples.path("spacecraft_bus"))
AT = (0.6, 0.0, 0.0, 0.0, 0.0, 0.0)
Q = np.array([-0.4, -1.1, 1.3, -0.7, 0.5, 0.3])  # a generic UR5 configuration, negative first value


@pytest.fixture(scope="module")
def ur5() -> str:
    return robot_urdf("ur_description/urdf/ur5_robot.urdf")


def mounted_ur5(path, **options) -> spacearm.Robot:
    """The same model through the library API (not the CLI's loader)."""
    return load_urdf(path, mount_on=spacearm.io.load_toml(BUS), at=AT, **options)


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "spacearm", *args], capture_output=True, text=True, timeout=300)


def printed_matrix(text: str, title_start: str) -> np.ndarray:
    """The matrix `inspect` printed under the line starting with ``title_start``."""
    lines = text.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith(title_start))
    rows, cols = (int(v) for v in lines[i].rsplit("(", 1)[1].rstrip(")").split("x"))
    return np.array([[float(v) for v in lines[i + 1 + r].split()] for r in range(rows)])


def assert_printed_close(printed, expected):
    """`inspect` prints 4 significant digits."""
    assert printed.shape == expected.shape
    assert np.allclose(printed, expected, rtol=1e-3, atol=1e-4 * np.abs(expected).max())


# ---------------------------------------------------------------------------------------------
# the shipped spacecraft bus
# ---------------------------------------------------------------------------------------------
def test_spacecraft_bus_is_the_documented_box():
    bus = spacearm.io.load_toml(BUS)
    assert bus.n_dof == 0 and bus.body_names == ["bus"] and bus.total_mass == 500.0
    inertia = np.asarray(bus.describe()["base"]["inertia"])
    # Principal moments of a uniform 1.2 x 1.1 x 1.0 m box, m (b^2 + c^2) / 12 (the file's comment).
    box = 500.0 / 12.0 * np.array([1.1**2 + 1.0**2, 1.2**2 + 1.0**2, 1.2**2 + 1.1**2])
    assert np.allclose(np.diag(inertia), box, atol=1e-3)
    assert np.all(np.linalg.eigvalsh(inertia) > 0)


# ---------------------------------------------------------------------------------------------
# inspect: the README's mounted-arm line, --end-effector, negative lists
# ---------------------------------------------------------------------------------------------
def test_readme_mounted_ur5_line_runs(ur5):
    out = run_cli("inspect", ur5, "--mount-on", BUS, "--at", "0.6,0,0,0,0,0")
    assert out.returncode == 0, out.stderr
    robot = mounted_ur5(ur5)
    assert f"total mass {robot.total_mass:.6g} kg" in out.stdout and "N = 6 joint DOF" in out.stdout
    h0 = robot.inertia_blocks(robot.neutral_configuration()).H0
    assert_printed_close(printed_matrix(out.stdout, "H0 (base inertia"), h0)


@pytest.mark.parametrize("end_effector", ["tool0", "wrist_2_link", "ur_wrist_2_link"])
def test_end_effector_of_a_mounted_urdf_sets_the_jacobian_point(ur5, end_effector, capsys):
    args = ["inspect", ur5, "--mount-on", BUS, "--at", "0.6,0,0,0,0,0", "--prefix", "ur_",
            "--end-effector", end_effector, "--q", ",".join(str(float(v)) for v in Q)]
    assert main(args) == 0
    text = capsys.readouterr().out
    robot = mounted_ur5(ur5, prefix="ur_")  # no end effector: the UR5 has several leaf links
    assert robot.end_effector is None
    x = robot.neutral_configuration(Q)
    link = end_effector.removeprefix("ur_")
    if link == "tool0":  # welded by a fixed joint: a named point of the model
        point = "ur_tool0"
    else:  # a moving link: its URDF frame origin, the joint, at -com from the link CM
        desc = next(d for d in robot.describe()["links"] if d["name"] == "ur_" + link)
        point = ("ur_" + link, -np.asarray(desc["com"]))
    js = robot.generalized_jacobian(x, point=point)
    assert_printed_close(printed_matrix(text, "J* of "), js)
    p = robot.point_position(x, point)
    printed_p = np.array([float(v) for v in text.split("end-effector position: [")[1].split("]")[0].split(",")])
    assert np.allclose(printed_p, p, atol=1e-5)


def test_end_effector_choice_changes_the_point(ur5, capsys):
    jacobians = {}
    for ee in ("tool0", "wrist_1_link"):
        assert main(["inspect", ur5, "--mount-on", BUS, "--end-effector", ee, "--q", "-0.4,-1.1,1.3,-0.7,0.5,0.3"]) == 0
        jacobians[ee] = printed_matrix(capsys.readouterr().out, "J* of ")
    assert np.abs(jacobians["tool0"] - jacobians["wrist_1_link"]).max() > 0.05


def test_end_effector_of_a_preset_body_is_its_cm(capsys):
    robot = spacearm.presets.spatial6()
    assert main(["inspect", "spatial6", "--end-effector", "link3", "--q", "-0.3,0.5,-1.2,0.2,0.4,-0.1"]) == 0
    text = capsys.readouterr().out
    x = robot.neutral_configuration([-0.3, 0.5, -1.2, 0.2, 0.4, -0.1])
    # A body name as a point is its CM in the library (body frames sit at the CM).
    assert_printed_close(printed_matrix(text, "J* of 'link3_cm'"), robot.generalized_jacobian(x, point="link3"))
    assert_printed_close(printed_matrix(text, "H* (generalized"), robot.generalized_inertia(x))


def test_end_effector_point_keeps_the_rest_of_the_model():
    from spacearm.cli import load_model

    original = spacearm.presets.dual_arm()
    right = load_model("dual_arm", end_effector="right_tool")
    assert right.end_effector == "right_tool" and original.end_effector == "left_tool"
    assert dumps_toml(right).replace('"right_tool"', '"left_tool"', 1) == dumps_toml(original)
    x = original.neutral_configuration()
    assert np.array_equal(right.generalized_jacobian(x), original.generalized_jacobian(x, "right_tool"))


def test_inspect_negative_q_and_at(ur5, capsys):
    assert main(["inspect", "planar4", "--q", "-1,2,-0.5,0.25"]) == 0
    assert "q = [-1, 2, -0.5, 0.25]" in capsys.readouterr().out
    h0 = {}
    for at in (["--at", "-0.6,0,0.1,0,0,0"], ["--at=-0.6,0,0.1,0,0,0"]):
        assert main(["inspect", ur5, "--mount-on", BUS, *at]) == 0
        h0[at[0]] = printed_matrix(capsys.readouterr().out, "H0 (base inertia")
    robot = load_urdf(ur5, mount_on=spacearm.io.load_toml(BUS), at=(-0.6, 0, 0.1, 0, 0, 0))
    expected = robot.inertia_blocks(robot.neutral_configuration()).H0
    assert_printed_close(h0["--at"], expected)
    assert np.array_equal(h0["--at"], h0["--at=-0.6,0,0.1,0,0,0"])


# ---------------------------------------------------------------------------------------------
# the other subcommands take the same model options
# ---------------------------------------------------------------------------------------------
def test_simulate_mounted_ur5_rmrc(ur5, tmp_path, capsys):
    out = tmp_path / "run.npz"
    goal = "0.75,0.25,-0.05"  # negative last value: a list starting positive needs no help
    assert main(["simulate", ur5, "--mount-on", BUS, "--at", "0.6,0,0,0,0,0", "--prefix", "ur_", "--end-effector", "tool0",
                 "--controller", "rmrc", "--q0", "-0.4,-1.1,1.3,-0.7,0.5,0.3", "--target", goal, "--duration", "0.1",
                 "--dt", "0.002", "--out", str(out), "--no-progress"]) == 0
    assert "simulation of 'ur5' (N = 6)" in capsys.readouterr().out
    robot = mounted_ur5(ur5, prefix="ur_", end_effector="tool0")
    x = np.load(out)["x"]
    assert np.allclose(x[0], robot.neutral_configuration(Q))  # --q0 with a negative first value
    assert robot.total_mass > 500.0 and x.shape[1] == 7 + 6


def test_simulate_without_end_effector_names_the_option(ur5, capsys):
    assert main(["simulate", ur5, "--mount-on", BUS, "--controller", "rmrc", "--duration", "0.1", "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "has none: name one with --end-effector" in err and "tool0" in err


def test_analyze_mounted_ur5_singularities(ur5, tmp_path, capsys):
    pytest.importorskip("matplotlib")
    assert main(["analyze", ur5, "--mount-on", BUS, "--at", "0.6,0,0,0,0,0", "--end-effector", "tool0", "--singularities",
                 "--resolution", "3", "--q", "-0.4,-1.1,1.3,-0.7,0.5,0.3", "--out", str(tmp_path / "s.png"), "--no-progress"]) == 0
    text = capsys.readouterr().out
    robot = mounted_ur5(ur5)
    js = robot.generalized_jacobian(robot.neutral_configuration(Q), point="tool0")[:3]  # task rows: position
    line = next(line for line in text.splitlines() if "J* (free floating)" in line)
    printed = np.array([float(v) for v in line.split("[")[1].split("]")[0].split(",")])
    assert np.allclose(printed, np.linalg.svd(js, compute_uv=False), rtol=1e-3)
    assert (tmp_path / "s.png").stat().st_size > 0


def test_analyze_reactionless_negative_target(capsys, tmp_path):
    pytest.importorskip("matplotlib")
    assert main(["analyze", "planar4", "--reactionless", "--target", "-0.3,0.3,0", "--duration", "1",
                 "--out", str(tmp_path / "r.png"), "--no-progress"]) == 0
    text = capsys.readouterr().out
    robot = spacearm.presets.planar4()
    target = robot.point_position(robot.neutral_configuration()) + np.array([-0.3, 0.3, 0.0])
    assert f"target {np.array2string(target, precision=4)} m" in text


def test_campaign_workers_get_the_mounted_model(ur5, tmp_path, capsys):
    from spacearm.campaign import CampaignResult

    out = tmp_path / "c.npz"
    assert main(["campaign", ur5, "--mount-on", BUS, "--at", "0.6,0,0,0,0,0", "--prefix", "ur_", "--end-effector", "tool0",
                 "--samples", "2", "--workers", "0", "--duration", "0.1", "--dt", "0.01", "--payload-mass-max", "1",
                 "--out", str(out), "--no-progress"]) == 0
    assert "2 samples ran, 0 failed" in capsys.readouterr().out
    in_process = CampaignResult.load(out)
    spec = json.loads(in_process.spec_json)
    robot = mounted_ur5(ur5, prefix="ur_", end_effector="tool0")
    assert spec["model_toml"] == dumps_toml(robot)
    # The worker threads rebuild the model from the spec alone: the same samples give the same metrics.
    assert main(["campaign", ur5, "--mount-on", BUS, "--at", "0.6,0,0,0,0,0", "--prefix", "ur_", "--end-effector", "tool0",
                 "--samples", "2", "--workers", "2", "--duration", "0.1", "--dt", "0.01", "--payload-mass-max", "1",
                 "--out", str(tmp_path / "c2.npz"), "--no-progress"]) == 0
    assert "backend threads, 2 worker(s)" in capsys.readouterr().out
    with np.load(out) as a, np.load(tmp_path / "c2.npz") as b:
        assert np.array_equal(a["metrics"], b["metrics"], equal_nan=True) and np.isfinite(a["metrics"]).all()


def test_derive_mounted_urdf(tmp_path, capsys):
    pytest.importorskip("sympy")
    arm = tmp_path / "arm.urdf"
    arm.write_text("""<robot name="arm">
  <link name="base"><inertial><mass value="2"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="upper"><inertial><origin xyz="0.2 0 0"/><mass value="3"/>
    <inertia ixx="0.01" iyy="0.05" izz="0.05" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="tip"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
  <joint name="tip_joint" type="fixed"><parent link="upper"/><child link="tip"/><origin xyz="0.4 0 0"/></joint>
</robot>""")
    py = tmp_path / "arm_eom.py"
    assert main(["derive", str(arm), "--mount-on", BUS, "--at=-0.6,0,0,0,0,3.14159", "--prefix", "a_",
                 "--end-effector", "upper", "--python", str(py), "--include", "J_star"]) == 0
    assert "NumPy" in capsys.readouterr().out
    import importlib.util

    spec = importlib.util.spec_from_file_location("arm_eom", py)
    eom = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(eom)
    # The library on the same URDF; --end-effector upper is the 'upper' link frame origin (its joint),
    # a point that exists only because of the option (derive writes J* of every point).
    robot = load_urdf(arm, mount_on=spacearm.io.load_toml(BUS), at=(-0.6, 0, 0, 0, 0, 3.14159), prefix="a_")
    assert robot.body_names == ["bus", "a_base", "a_upper"] and robot.end_effector == "a_tip"  # the only leaf, by default
    com = np.asarray(robot.describe()["links"][1]["com"])
    for q in (-0.7, 1.2):
        x = robot.neutral_configuration([q], r0=(0.3, -0.2, 0.1), quat0=(0.1, -0.2, 0.3, 0.9273618495495703))
        js = robot.generalized_jacobian(x, point=("a_upper", -com))
        # (the generated module returns a one-column matrix as a vector)
        assert np.allclose(eom.J_star_a_upper_frame(x), js[:, 0], rtol=1e-10, atol=1e-12)


# ---------------------------------------------------------------------------------------------
# bad values: exit 2, "spacearm: error: ...", no traceback
# ---------------------------------------------------------------------------------------------
def test_bad_model_options_exit_2(ur5):
    cases = [
        (("inspect", ur5, "--mount-on", BUS, "--at", "0.6,0,0"),
         "--at expects 6 comma-separated numbers (x,y,z,roll,pitch,yaw; m, rad), got 3 in '0.6,0,0'"),
        (("inspect", ur5, "--mount-on", BUS, "--at", "-0.6,0,0,0,nan,0"), "'nan' is not finite"),
        (("inspect", ur5, "--at", "0.6,0,0,0,0,0"), "--at needs --mount-on"),
        (("inspect", "planar4", "--prefix", "a_"), "--prefix applies to URDF models (.urdf files) only"),
        (("inspect", "planar4", "--mimic", "independent", "--at", "1,2"), "--at, --mimic apply to URDF models"),
        (("inspect", ur5, "--mount-on", "no_such_bus.toml"), "--mount-on: 'no_such_bus.toml' is neither a preset"),
        (("inspect", "no_such_arm.urdf", "--prefix", "a_"), "'no_such_arm.urdf' is neither a preset"),
        (("inspect", ur5, "--end-effector", "nowhere"), "--end-effector must name a point or a body/link"),
        (("inspect", ur5, "--base-link", "nowhere"), "--base-link 'nowhere' is not a link of the URDF"),
        (("inspect", ur5, "--mount-on", str(spacearm.examples.path("spatial6"))), "--prefix arm_"),  # UR5 link 'base' clashes
        (("analyze", "planar4", "--singularities", "--joints", "1.5,2", "--out", "x.png"), "'1.5' is not an integer"),
        (("simulate", "planar4", "--q0", "-1,x,0,0"), "--q0 expects 4 comma-separated numbers"),
    ]
    for args, message in cases:
        out = run_cli(*args)
        assert out.returncode == 2, (args, out.stderr)
        assert out.stderr.startswith("spacearm: error: ") and message in out.stderr, (args, out.stderr)
        assert "Traceback" not in out.stderr


def test_mimic_advice_names_the_cli_option(capsys):
    panda = robot_urdf("panda_description/urdf/panda.urdf")
    assert main(["inspect", panda]) == 2
    assert "pass --mimic independent" in capsys.readouterr().err
    assert main(["inspect", panda, "--mimic", "independent", "--end-effector", "panda_hand"]) == 0
    assert "J* of 'panda_hand'" in capsys.readouterr().out


# ---------------------------------------------------------------------------------------------
# the number-list parser and the negative-value rewrite
# ---------------------------------------------------------------------------------------------
def test_parse_numbers():
    assert np.array_equal(parse_numbers(" -0.3, 0.3 ,0,", "--t", 3, "dx,dy,dz", "m"), [-0.3, 0.3, 0.0])
    assert np.array_equal(parse_numbers("1e-3,-2E2", "--t", None, "values", "m"), [1e-3, -200.0])
    joints = parse_numbers("3,5", "--joints", 2, "joints", "dimensionless", integer=True)
    assert joints.dtype.kind == "i" and list(joints) == [3, 5]
    for text, count, message in [("1,2", 3, "expects 3 comma-separated numbers (dx,dy,dz; m), got 2 in '1,2'"),
                                 ("1,,2", 3, "an empty entry"), ("", 3, "an empty entry"), ("1,inf,2", 3, "'inf' is not finite"),
                                 ("1;2;3", 3, "'1;2;3' is not a number")]:
        with pytest.raises(CliError) as info:
            parse_numbers(text, "--t", count, "dx,dy,dz", "m")
        assert str(info.value).startswith("--t expects 3") and message in str(info.value)
    assert issubclass(CliError, spacearm.errors.ArgumentError) and issubclass(CliError, spacearm.SpacearmError)


def test_attach_negative_values():
    argv = ["analyze", "planar4", "--target", "-0.3,0.3,0", "--q", "-1", "--at=-1,0", "--kp", "5", "--", "--x", "-1"]
    assert attach_negative_values(argv) == ["analyze", "planar4", "--target=-0.3,0.3,0", "--q=-1", "--at=-1,0",
                                            "--kp", "5", "--", "--x", "-1"]
    assert attach_negative_values(["--t", "-.5,1", "--u", "-x"]) == ["--t=-.5,1", "--u", "-x"]


def test_attached_form_parses_where_plain_argparse_may_not():
    """Why attach_negative_values exists: argparse of Python 3.11 reads '-0.3,0.3,0' as an option
    (newer releases use a looser negative-number rule and accept it); the attached form works."""
    import argparse

    parser = argparse.ArgumentParser(exit_on_error=False)
    parser.add_argument("--target")
    if sys.version_info < (3, 12):  # later releases (with backports) changed the rule
        with pytest.raises((argparse.ArgumentError, SystemExit)):
            parser.parse_args(["--target", "-0.3,0.3,0"])
    assert parser.parse_args(attach_negative_values(["--target", "-0.3,0.3,0"])).target == "-0.3,0.3,0"
    assert parser.parse_args(attach_negative_values(["--target", "-1e-3"])).target == "-1e-3"
