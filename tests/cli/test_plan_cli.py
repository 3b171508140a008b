"""`spacearm plan`: the command plans what the Python API plans (same arrays in the file),
reports the re-simulation, writes the figure, and fails cleanly on bad arguments."""

import numpy as np
import pytest

import spacearm
from spacearm.cli import main

pytest.importorskip("casadi")


def test_plan_writes_the_plan_and_the_figure(tmp_path, capsys):
    robot = spacearm.presets.planar4()
    target = robot.point_position(robot.neutral_configuration()) + np.array([-0.2, 0.3, 0.0])
    out, png = tmp_path / "plan.npz", tmp_path / "plan.png"
    code = main(["plan", "planar4", "--to", ",".join(repr(float(v)) for v in target), "--duration", "2", "--nodes", "8",
                 "--out", str(out), "--plot", str(png)])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert "IPOPT iteration" in captured.err  # the progress indication
    for needle in ("IPOPT: Solve_Succeeded", "re-simulation", "wrote"):
        assert needle in captured.out, needle
    from spacearm.plan import point_to_point

    direct = point_to_point(robot, target, duration=2.0, nodes=8)
    with np.load(out) as data:
        np.testing.assert_allclose(data["x"], direct.x, atol=1e-9)
        np.testing.assert_allclose(data["tau"], direct.tau, atol=1e-6)
        np.testing.assert_allclose(robot.point_position(data["x"][-1]), target, atol=1e-6)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("argv, needle", [
    (["plan", "planar4", "--to", "1,2", "--out", "p.npz"], "--to expects 3"),
    (["plan", "planar4", "--to", "3.4,0.3,0", "--out", "p.txt"], ".npz"),
    (["plan", "planar4", "--to", "3.4,0.3,0", "--nodes", "1", "--out", "p.npz"], "nodes"),
    (["plan", "planar4", "--to", "3.4,0.3,0", "--effort-limit", "1,2", "--out", "p.npz"], "--effort-limit"),
    # issue 26: refused before any solve, with the reason
    (["plan", "planar4", "--to=20,0,0", "--out", "p.npz"], "out of reach"),
    (["plan", "planar4", "--to=3.46,0.3,0.5", "--out", "p.npz"], "off the plane"),
    (["plan", "planar4", "--to=3.4,0.3,0", "--max-iter=-1", "--out", "p.npz"], "max_iter"),
    (["plan", "planar4", "--to=3.4,0.3,0", "--nodes=1000000", "--out", "p.npz"], "nodes must be between"),
])
def test_bad_arguments_exit_2_without_a_file(argv, needle, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("spacearm: error:") and needle in err, err
    assert not list(tmp_path.iterdir())


def test_a_plan_that_fails_its_check_exits_2_without_a_file(tmp_path, monkeypatch, capsys):
    # IPOPT solves it, its re-simulation refutes it (tests/plan/test_plan_checks.py, coarse_plan).
    monkeypatch.chdir(tmp_path)
    robot = spacearm.presets.planar4()
    target = robot.point_position(robot.neutral_configuration()) + np.array([-0.25, 0.35, 0.0])
    code = main(["plan", "planar4", "--to", ",".join(repr(float(v)) for v in target), "--duration", "3", "--nodes", "3",
                 "--substeps", "1", "--out", "p.npz", "--plot", "p.png"])
    captured = capsys.readouterr()
    assert code == 2
    assert "IPOPT: Solve_Succeeded" in captured.out and "re-simulation" in captured.out
    last = captured.err.strip().splitlines()[-1]  # after the progress lines
    assert last.startswith("spacearm: error: no plan:") and "re-simulat" in last, captured.err
    assert "Warning" not in captured.err
    assert not list(tmp_path.iterdir())


def test_the_help_says_what_the_transcription_does(capsys):
    # The plan's torque is a first-order hold (plan/problem.py, docs/optimal-control.md);
    # the help said "constant on each" knot interval (issue 37 item 6).
    with pytest.raises(SystemExit):
        main(["plan", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "linear between knots" in text
    assert "constant on each" not in text
