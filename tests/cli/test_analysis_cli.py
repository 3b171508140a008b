"""`spacearm analyze`: each analysis prints its numbers and writes its figure; bad input fails
cleanly."""

import re
import subprocess
import sys

import spacearm
from spacearm import analysis
from spacearm.cli import main


def run(*args):
    return subprocess.run([sys.executable, "-m", "spacearm", "analyze", *args], capture_output=True, text=True)


def test_singularities(tmp_path):
    out = run("planar4", "--singularities", "--resolution", "41", "--out", str(tmp_path / "s.png"), "--no-progress")
    assert out.returncode == 0, out.stderr
    rep = analysis.analyze(spacearm.presets.planar4())
    assert f"{rep.generalized.condition:.4g}" in out.stdout and f"{rep.fixed_base.condition:.4g}" in out.stdout
    assert re.search(r"41x41 = 1681 samples in [0-9.]+ s \([0-9]+ samples/s\)", out.stdout)
    assert (tmp_path / "s.png").stat().st_size > 10_000


def test_workspace_and_reactionless(tmp_path, monkeypatch, capsys):
    assert main(["analyze", "planar4", "--workspace", "--resolution", "7", "--out", str(tmp_path / "w.png"), "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert "reachable shell" in text and "3.607 m" in text and "fixed base" in text
    assert main(["analyze", "planar4", "--reactionless", "--out", str(tmp_path / "r.png"), "--no-progress"]) == 0
    text = capsys.readouterr().out
    lines = {line.split()[0]: line for line in text.splitlines() if line.startswith("  ")}
    rl = float(re.search(r"max ([0-9.e+-]+) rad", lines["reactionless"]).group(1))
    nv = float(re.search(r"max ([0-9.e+-]+) rad", lines["naive"]).group(1))
    assert rl < 1e-9 < 1e-2 < nv
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.png", "w.png"]


def test_errors_are_clean(tmp_path):
    out = run("planar4", "--workspace", "--resolution", "1", "--out", str(tmp_path / "w.png"))
    assert out.returncode == 2 and "resolution" in out.stderr and "Traceback" not in out.stderr
    out = run("planar4", "--singularities", "--joints", "1,9", "--out", str(tmp_path / "s.png"))
    assert out.returncode != 0 and "Traceback" not in out.stderr
    out = run("planar4", "--reactionless", "--target", "1,2", "--out", str(tmp_path / "r.png"))
    assert out.returncode == 2 and "--target" in out.stderr
    out = run("planar4", "--out", str(tmp_path / "x.png"))
    assert out.returncode == 2 and "one of the arguments" in out.stderr
    assert list(tmp_path.iterdir()) == []
