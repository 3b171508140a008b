"""CLI answers that mean what they say (issue 26, item 5): derive with nothing to write exits 2
before deriving; inspect asks for --end-effector when J* cannot be computed."""

from __future__ import annotations

import time

import spacearm
from spacearm.cli import main


def test_derive_with_nothing_to_write_exits_2_at_once(capsys):
    t = time.perf_counter()
    assert main(["derive", "spatial6"]) == 2
    assert time.perf_counter() - t < 5.0  # refused before the (minutes-long) derivation
    err = capsys.readouterr().err
    assert err.startswith("spacearm: error: nothing to write: give --latex, --python and/or --c")


def test_inspect_asks_for_an_end_effector_when_the_model_has_none(tmp_path, capsys):
    # the dual-arm model with no end effector named: two leaves, no choice made for the user
    text = spacearm.io.dumps_toml(spacearm.presets.dual_arm())
    lines = [line for line in text.splitlines() if not line.startswith("end_effector")]
    path = tmp_path / "two_arms.toml"
    path.write_text("\n".join(lines) + "\n")
    loaded = spacearm.io.load_toml(path)
    assert loaded.end_effector is None
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert "J* (generalized Jacobian, eq. 110): not computed" in out and "--end-effector POINT|LINK" in out
    parents = {link.parent for link in loaded.description.links}
    leaves = [link.name for link in loaded.description.links if link.name not in parents]
    assert len(leaves) == 2 and f"2 leaves ({', '.join(leaves)})" in out
    # named, J* is printed
    assert main(["inspect", str(path), "--end-effector", "left_tool"]) == 0
    assert "J* of 'left_tool'" in capsys.readouterr().out


def test_a_degenerate_workspace_is_said_in_words(tmp_path, capsys):
    # planar4 on a grid of 5: the singular samples are the folded and stretched configurations the
    # grid hits exactly, every path-dependent "shell" a single radius.
    assert main(["analyze", "planar4", "--workspace", "--resolution", "5", "--no-progress", "--out", str(tmp_path / "ws.png")]) == 0
    out = capsys.readouterr().out
    from spacearm import analysis

    ws = analysis.workspace(spacearm.presets.planar4(), resolution=5)
    zero = sum(1 for a, b in ws.path_dependent if b - a <= 0.0)
    assert zero > 0
    assert f"degenerate: {zero} of the {len(ws.path_dependent)} path-dependent shells have zero width" in out
