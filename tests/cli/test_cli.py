"""The command line: `spacearm inspect` prints what it promises and fails cleanly."""

import subprocess
import sys

import numpy as np

import spacearm


def run(*args):
    return subprocess.run([sys.executable, "-m", "spacearm", *args], capture_output=True, text=True)


def test_inspect_spatial6_prints_summary_and_matrices():
    out = run("inspect", "spatial6")
    assert out.returncode == 0, out.stderr
    text = out.stdout
    assert "model 'spatial6': 7 bodies, N = 6 joint DOF, total mass 545 kg" in text
    for name in ("H0 (base inertia", "H* (generalized inertia", "J* of 'end_effector'", "condition number"):
        assert name in text
    # The printed end-effector position is the library's.
    robot = spacearm.presets.spatial6()
    ee = robot.point_position(robot.neutral_configuration())
    assert f"end-effector position: [{', '.join(f'{v:.6g}' for v in ee)}]" in text


def test_inspect_at_given_q():
    out = run("inspect", "planar4", "--q", "0.1,0.2,0.3,0.4")
    assert out.returncode == 0, out.stderr
    assert "q = [0.1, 0.2, 0.3, 0.4]" in out.stdout
    robot = spacearm.presets.planar4()
    hs = robot.generalized_inertia(robot.neutral_configuration([0.1, 0.2, 0.3, 0.4]))
    assert f"{hs[0, 0]:11.4g}" in out.stdout


def test_inspect_errors_are_clean():
    out = run("inspect", "no-such-model")
    assert out.returncode == 2
    assert "neither a preset" in out.stderr and "Traceback" not in out.stderr
    out = run("inspect", "planar4", "--q", "1,2")
    assert out.returncode == 2
    assert "--q expects 4 comma-separated numbers (one per joint of 'planar4'; rad, or m for prismatic joints), got 2" in out.stderr
    out = run("inspect", "planar4", "--q", "1,x,3,4")
    assert out.returncode == 2 and "--q expects 4 comma-separated numbers" in out.stderr and "'x' is not a number" in out.stderr


def test_cli_main_in_process(capsys):
    from spacearm.cli import main

    assert main(["inspect", "planar4"]) == 0
    assert np.isfinite(float(capsys.readouterr().out.split("total mass ")[1].split(" kg")[0]))
