"""`spacearm simulate` and `spacearm demo`: the command builds the run it documents (checked
against the same run built with the Python API), writes every requested file, prints the
summary, and fails cleanly on bad arguments."""

import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

import spacearm
from spacearm import control
from spacearm.cli import main
from spacearm.cli.simulate import reaction_wheel_dofs
from spacearm.sim.trajectory import Trajectory


def test_simulate_computed_torque_writes_every_output(tmp_path, capsys):
    paths = {k: tmp_path / f"run.{k}" for k in ("npz", "csv", "png", "gif")}
    code = main(["simulate", "spatial6", "--controller", "computed-torque", "--duration", "1.0", "--dt", "0.002",
                 "--out", str(paths["npz"]), "--csv", str(paths["csv"]), "--plot", str(paths["png"]),
                 "--animate", str(paths["gif"]), "--frames", "3", "--no-progress"])
    assert code == 0
    text = capsys.readouterr().out
    for needle in ("mode floating", "controller: computed torque", "conservation (max relative drift): P",
                   "tracking error (joint): final", "saturation: none", "wrote trajectory", "wrote animation"):
        assert needle in text, needle
    traj = Trajectory.load(paths["npz"])
    # The documented default: a quintic from the initial q to q0 + 0.3 over 60 % of the run,
    # computed torque kp 25, kd 10. The same run through the Python API gives the same states.
    robot = spacearm.presets.spatial6()
    q0 = robot.initial_q
    ref = control.QuinticJoint(q0, q0 + 0.3, 0.0, 0.6)
    direct = spacearm.simulate(robot, 1.0, dt=0.002, controller=control.ComputedTorque(kp=25.0, kd=10.0, reference=ref))
    np.testing.assert_array_equal(traj.x, direct.x)
    np.testing.assert_allclose(traj.q[-1], q0 + 0.3, atol=1e-9)  # reached the goal
    assert traj.robot.describe() == robot.describe()
    with Image.open(paths["png"]) as im:
        assert im.format == "PNG"
    with Image.open(paths["gif"]) as im:
        assert im.n_frames == 3
    header = [l for l in paths["csv"].read_text().splitlines() if not l.startswith("#")][0]
    assert header.startswith("t [s],r0_x [m]")


def test_simulate_pd_with_target_and_initial_state(tmp_path, capsys):
    out = tmp_path / "pd.npz"
    code = main(["simulate", "planar4", "--controller", "pd", "--target", "0.5,-0.5,0.2,0.1", "--kp", "50", "--kd", "30",
                 "--duration", "0.5", "--move-time", "0.4", "--q0", "0.1,0.2,0.3,0.4", "--base-velocity", "0,0,0,0,0,0.1",
                 "--out", str(out), "--no-progress"])
    assert code == 0
    robot = spacearm.presets.planar4()
    x0 = robot.neutral_configuration([0.1, 0.2, 0.3, 0.4])
    u0 = np.zeros(robot.nu)
    u0[5] = 0.1
    ref = control.QuinticJoint([0.1, 0.2, 0.3, 0.4], [0.5, -0.5, 0.2, 0.1], 0.0, 0.4)
    direct = spacearm.simulate(robot, 0.5, x0=x0, u0=u0, controller=control.JointPD(kp=50.0, kd=30.0, reference=ref))
    np.testing.assert_array_equal(Trajectory.load(out).x, direct.x)
    assert "controller: joint PD" in capsys.readouterr().out


def test_zero_torque_run_reports_conservation(capsys):
    assert main(["simulate", "spatial6", "--duration", "2", "--qd0", "0.3,-0.2,0.4,0.5,-0.3,0.6", "--no-progress"]) == 0
    text = capsys.readouterr().out
    line = [l for l in text.splitlines() if "conservation" in l][0]
    values = dict(part.strip().split(" ") for part in line.split(":")[1].split(","))
    assert set(values) == {"P", "L_origin", "energy"}
    assert all(float(v) < 1e-9 for v in values.values())


@pytest.mark.parametrize("args, message", [
    (["--controller", "pd", "--target", "1,2"], "--target expects 6 comma-separated numbers (joint goal, one per arm joint of 'spatial6'; rad, or m for prismatic joints), got 2"),
    (["--controller", "pd", "--target", "1,x,3"], "'x' is not a number"),
    (["--duration", "-1"], "--duration must be > 0 s"),
    (["--dt", "0"], "--dt must be > 0 s"),
    (["--q0", "1,2"], "--q0 expects 6 comma-separated numbers (one per joint of 'spatial6'; rad, or m for prismatic joints), got 2"),
    (["--controller", "attitude"], "needs reaction wheels, but 'spatial6' has none"),
])
def test_bad_arguments_fail_cleanly(args, message, capsys):
    # argparse keeps the last of a repeated option, so args override the base ones.
    assert main(["simulate", "spatial6", "--duration", "0.1", "--no-progress", *args]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_unknown_model_and_controller_choice():
    out = subprocess.run([sys.executable, "-m", "spacearm", "simulate", "no-such-model"], capture_output=True, text=True)
    assert out.returncode == 2 and "neither a preset" in out.stderr and "Traceback" not in out.stderr
    out = subprocess.run([sys.executable, "-m", "spacearm", "simulate", "planar4", "--controller", "magic"],
                         capture_output=True, text=True)
    assert out.returncode == 2 and "invalid choice" in out.stderr


def test_progress_bar_on_request(capsys):
    assert main(["simulate", "planar4", "--duration", "0.2", "--progress"]) == 0
    assert "%" in capsys.readouterr().err


def test_reaction_wheel_detection_matches_the_simulator():
    b = spacearm.Robot.builder("rw", base_mass=100.0, base_inertia=[10, 12, 14])
    b.add_link("arm", parent="base", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.3, 0, 0), mass=5.0, inertia=[0.01, 0.2, 0.2])
    b.add_reaction_wheel((1, 0, 0), rotor_inertia=0.02)
    b.add_reaction_wheel((0, 1, 1), rotor_inertia=0.02, position=(0.1, 0.0, 0.0))
    # A rotor-like link whose CM is off its axis is not a wheel.
    b.add_link("offset_rotor", parent="base", axis=(0, 0, 1), origin=(0.0, 0.3, 0.0), com=(0.05, 0, 0), mass=1.0, inertia=[0.01, 0.01, 0.02])
    robot = b.build()
    assert reaction_wheel_dofs(robot) == [1, 2]
    traj = spacearm.simulate(robot, 0.01)
    assert traj.meta["wheel_dofs"] == [1, 2]


def test_demo_writes_its_figures(tmp_path, capsys):
    assert main(["demo", "--out-dir", str(tmp_path / "demo"), "--no-animation"]) == 0
    text = capsys.readouterr().out
    names = sorted(p.name for p in (tmp_path / "demo").iterdir())
    assert names == ["spatial6_computed_torque.npz", "spatial6_computed_torque.png", "spatial6_torque_free.png"]
    for name in names:
        assert str(tmp_path / "demo" / name) in text
    assert "spatial 6-DOF example" in text and "system CM moved" in text
    traj = Trajectory.load(tmp_path / "demo" / "spatial6_computed_torque.npz")
    # The maneuver really happened and the base reacted while the system CM stayed put.
    assert np.max(np.abs(traj.q[-1] - traj.q[0])) > 0.5
    assert traj.base_rotation_angle[-1] > np.radians(1.0)
    assert np.max(np.linalg.norm(traj.com - traj.com[0], axis=1)) < 1e-9


def test_rmrc_and_coordinated_reach_the_cartesian_goal(tmp_path, capsys):
    robot = spacearm.presets.spatial6()
    p0 = robot.point_position(robot.neutral_configuration())
    goal = p0 + [0.1, 0.2, -0.15]
    target = ",".join(f"{v:.10g}" for v in goal)
    for name in ("rmrc", "coordinated"):
        out = tmp_path / f"{name}.npz"
        assert main(["simulate", "spatial6", "--controller", name, "--target", target, "--duration", "2",
                     "--move-time", "1.5", "--dt", "0.002", "--out", str(out), "--no-progress"]) == 0
        traj = Trajectory.load(out)
        assert traj.mode == ("floating" if name == "rmrc" else "flying")
        assert traj.tracking_error_kind == "cartesian"
        np.testing.assert_allclose(traj.ee_position[-1], goal, atol=2e-3)  # 2 s, gain 2/s: settled to mm
        base_moved = np.max(np.linalg.norm(traj.base_position - traj.base_position[0], axis=1))
        if name == "rmrc":  # floating: the base reacts
            assert base_moved > 1e-3 and np.max(np.linalg.norm(traj.com - traj.com[0], axis=1)) < 1e-9
        else:  # flying: thrusters hold the base pose
            assert base_moved < 1e-3 and np.degrees(traj.base_rotation_angle.max()) < 0.5
    capsys.readouterr()


def test_attitude_control_with_wheels_holds_the_base(tmp_path, capsys):
    d = spacearm.presets.spatial6().describe()
    b = spacearm.Robot.builder("s6rw", base_mass=d["base"]["mass"], base_inertia=d["base"]["inertia"])
    for link in d["links"]:
        b.add_link(link["name"], parent=link["parent"], axis=link["axis"], origin=link["origin"], com=link["com"],
                   mass=link["mass"], inertia=link["inertia"], joint_name=link["joint"])
    for axis in np.eye(3):
        b.add_reaction_wheel(axis, rotor_inertia=0.2, max_torque=40.0, max_speed=400.0)
    b.add_point("tip", body="link6", offset=(0.1, 0, 0))
    b.set_end_effector("tip")
    b.set_initial_q(list(d["initial_q"]) + [0, 0, 0])
    model = tmp_path / "s6rw.toml"
    spacearm.io.model_file.save_toml(b.build(), model)
    turned = {}
    for ctrl in ("computed-torque", "attitude"):
        out = tmp_path / f"{ctrl}.npz"
        assert main(["simulate", str(model), "--controller", ctrl, "--target", "0.5,1.0,-1.2,0.4,1.2,0.4",
                     "--duration", "4", "--move-time", "3", "--dt", "0.002", "--out", str(out), "--no-progress"]) == 0
        traj = Trajectory.load(out)
        turned[ctrl] = np.degrees(traj.base_rotation_angle.max())
        assert traj.meta["wheel_dofs"] == [6, 7, 8]
        assert traj.drift(["P", "L_origin"])["L_origin"] < 1e-9  # wheels are internal
    # Idle wheels: the base turns freely; attitude control: the wheels take the momentum.
    assert turned["computed-torque"] > 5.0
    assert turned["attitude"] < 0.25 * turned["computed-torque"]
    assert "rotation-floating" in capsys.readouterr().out


def test_attitude_control_from_the_wheeled_example_model_file(capsys):
    # The example model file's three wheels are found by the simulator (symmetric rotors on the
    # base); their 2 N m limit saturates, which the summary reports, while the arm still tracks.
    from pathlib import Path

    model = spacearm.examples.path("spatial6_wheels")
    robot = spacearm.io.load_toml(model)
    assert spacearm._core.default_wheel_dofs(robot.core_model) == [6, 7, 8]
    assert main(["simulate", str(model), "--controller", "attitude", "--duration", "2", "--dt", "0.002",
                 "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert "torque limit" in text and "wheel1_joint" in text
    err = float(text.split("tracking error (joint): final ")[1].split()[0])
    assert err < 1e-8
