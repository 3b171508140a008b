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


def _readme_workspace_command():
    import pathlib
    import shlex

    readme = pathlib.Path(__file__).resolve().parents[2] / "README.md"
    lines = [line for line in readme.read_text(encoding="utf-8").splitlines()
             if line.startswith("spacearm analyze ") and "--workspace" in line]
    assert len(lines) == 1, lines
    return shlex.split(lines[0].split("#")[0])[1:]


def _printed_shells(out):
    import re

    line = next(line for line in out.splitlines() if "path-dependent shells" in line)
    return [(float(a), float(b)) for a, b in re.findall(r"\[([-0-9.e]+), ([-0-9.e]+)\]", line.split(":", 1)[1])]


def test_the_readme_workspace_example_is_not_degenerate(tmp_path, capsys):
    # The README's `analyze ... --workspace` line, run as written (figure into tmp_path): every
    # path-dependent shell has width, nothing is reported degenerate, and a finer grid changes the
    # shells (a sampled answer that does not move with the sampling measured nothing).
    args = _readme_workspace_command()
    args[args.index("--out") + 1] = str(tmp_path / "ws.png")
    assert main(args + ["--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "degenerate" not in out
    shells = _printed_shells(out)
    assert len(shells) >= 2 and all(b > a for a, b in shells), shells
    res = args.index("--resolution") + 1
    coarser = list(args)
    coarser[res] = str(int(args[res]) - 1)
    assert main(coarser + ["--no-progress"]) == 0
    assert _printed_shells(capsys.readouterr().out) != shells
    assert (tmp_path / "ws.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_redundant_degenerate_workspace_says_why(tmp_path, capsys):
    # planar4's planar task (2 rows, 4 joints): 50,000 random samples meet no singular sample at
    # all (the singular set is thin), so the message must not promise that denser sampling helps.
    from spacearm import analysis

    ws = analysis.workspace(spacearm.presets.planar4(), random_samples=20000)
    assert ws.path_dependent == [] or all(b - a <= 0.0 for a, b in ws.path_dependent)
    assert main(["analyze", "planar4", "--workspace", "--resolution", "5", "--no-progress", "--out", str(tmp_path / "ws.png")]) == 0
    out = capsys.readouterr().out
    assert "The task is redundant (2 rows, 4 joints)" in out and "does not widen" in out
    assert "Denser samples" not in out
