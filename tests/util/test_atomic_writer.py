"""The one atomic writer (spacearm._util.atomic): every writer gives its file the mode of a
normal file, errors name the target, and the temporaries of a killed writer are removed on the
next write to the same path (a real SIGKILL, bounded in time)."""

from __future__ import annotations

import os
import signal
import stat
import subprocess
import sys
import textwrap

import pytest

import spacearm
from spacearm._util import atomic
from spacearm.io import model_file, urdf_export


def _mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


@pytest.fixture
def umask_027():
    old = os.umask(0o027)
    try:
        yield 0o640  # what open(path, "w") gives a new file under this umask
    finally:
        os.umask(old)


def _writers(tmp_path):
    robot = spacearm.presets.planar4()
    traj = spacearm.simulate(robot, 0.01, dt=1e-3)
    yield "toml", lambda p: model_file.save_toml(robot, p)
    yield "urdf", lambda p: urdf_export.save_urdf(robot, p)
    yield "npz", lambda p: traj.save(p)
    yield "csv", lambda p: traj.to_csv(p)
    yield "txt", lambda p: atomic.write_text(p, "generated code\n")


def test_every_writer_gives_a_normal_file_mode(tmp_path, umask_027):
    # The reference is the file system itself: a file created by plain open() under this umask.
    reference = tmp_path / "plain"
    with open(reference, "w") as f:
        f.write("x")
    assert _mode(reference) == umask_027
    for ext, write in _writers(tmp_path):
        path = tmp_path / f"out.{ext}"
        write(path)
        assert _mode(path) == _mode(reference), ext
        # Rewriting a file keeps its mode, as rewriting it in place would.
        os.chmod(path, 0o600)
        write(path)
        assert _mode(path) == 0o600, ext
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []


def test_new_file_mode_matches_open(tmp_path):
    probe = tmp_path / "probe"
    probe.write_text("x")
    assert atomic.new_file_mode() == _mode(probe)


@pytest.mark.parametrize("problem", ["missing directory", "directory in the way", "parent is a file"])
def test_errors_name_the_target(tmp_path, problem):
    target = {"missing directory": tmp_path / "nope" / "a.csv",
              "directory in the way": tmp_path / "dir.toml",
              "parent is a file": tmp_path / "file" / "a.csv"}[problem]
    (tmp_path / "dir.toml").mkdir()
    (tmp_path / "file").write_text("x")
    with pytest.raises(OSError) as info:
        atomic.write_text(target, "x")
    assert info.value.filename == os.fspath(target)
    assert not target.is_file()


def test_disk_full_during_write_leaves_nothing(tmp_path, monkeypatch):
    target = tmp_path / "a.csv"
    target.write_text("old")

    def full(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(atomic.os, "fsync", full)
    with pytest.raises(OSError) as info:
        atomic.write_text(target, "new")
    assert info.value.errno == 28 and info.value.filename == os.fspath(target)
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["a.csv"]


NAMED_WRITER = textwrap.dedent("""
    import sys, time
    from spacearm._util.atomic import atomic_path
    with atomic_path(sys.argv[1], suffix=".gif") as tmp:
        open(tmp, "wb").write(b"GIF89a" * 1000)
        print("writing", flush=True)
        time.sleep(60)
""")

# The real `simulate --out/--csv` of the issue, stopped (by a slow fsync) after its data is
# written and before it is put in place: the moment a SIGKILL used to leave a hidden file.
SIMULATE = textwrap.dedent("""
    import os, sys, time
    def stalled(fd):
        print("writing", flush=True)
        time.sleep(60)
    os.fsync = stalled
    from spacearm.cli import main
    main(["simulate", "planar4", "--duration", "0.05", "--no-progress", sys.argv[1], sys.argv[2]])
""")


def _start(code, *args):
    child = subprocess.Popen([sys.executable, "-c", code, *map(str, args)], stdout=subprocess.PIPE, text=True)
    for line in child.stdout:  # blocks until the data is being written (the CLI prints first)
        if line.strip() == "writing":
            return child
    child.kill()
    raise AssertionError(f"the writer ended before writing (exit status {child.wait()})")


def _kill(child):
    try:
        os.kill(child.pid, signal.SIGKILL)
        child.wait(timeout=10)
    finally:
        child.kill()


def _hidden(directory):
    return sorted(p.name for p in directory.iterdir() if p.name.startswith("."))


def _unnamed_files_link(directory) -> bool:
    """Whether this system gives atomic_open its unnamed files (O_TMPFILE, then linked)."""
    fd = atomic._open_unnamed(directory)
    if fd is None:
        return False
    try:
        probe = directory / "probe"
        linked = atomic._link_unnamed(fd, probe)
        if linked:
            probe.unlink()
        return linked
    finally:
        os.close(fd)


@pytest.mark.parametrize("option", ["--out", "--csv"])
def test_a_simulate_killed_while_writing_leaves_no_hidden_file(tmp_path, option):
    target = tmp_path / ("run.npz" if option == "--out" else "run.csv")
    unnamed = _unnamed_files_link(tmp_path)
    child = _start(SIMULATE, option, target)
    _kill(child)
    assert not target.exists()  # the interrupted write never produced a partial target
    if unnamed:
        # Linux O_TMPFILE: the data had no name; nothing at all is left.
        assert list(tmp_path.iterdir()) == []
    else:  # a named temporary, swept by the next write into the directory
        assert len(_hidden(tmp_path)) == 1 and _hidden(tmp_path)[0].startswith(f"{atomic.TEMPORARY_PREFIX}{child.pid}-")
        atomic.write_text(tmp_path / "other.txt", "x\n")
        assert _hidden(tmp_path) == []
    # and the same command, not interrupted, writes a complete file that loads
    from spacearm.cli import main

    assert main(["simulate", "planar4", "--duration", "0.05", "--no-progress", option, str(target)]) == 0
    assert _hidden(tmp_path) == []
    if option == "--out":
        assert spacearm.Trajectory.load(target).t.shape == (51,)
    else:
        assert len([line for line in target.read_text().splitlines() if not line.startswith("#")]) == 52  # header + 51 samples


def test_atomic_open_uses_unnamed_files_on_linux(tmp_path):
    # On Linux (CI) the file-object writer must take the O_TMPFILE path, not the named fallback.
    if not sys.platform.startswith("linux"):
        pytest.skip("O_TMPFILE is Linux's")
    assert _unnamed_files_link(tmp_path)
    with atomic.atomic_open(tmp_path / "a.csv") as f:
        f.write("t\n")
        assert _hidden(tmp_path) == [] and list(tmp_path.iterdir()) == []
    assert (tmp_path / "a.csv").read_text() == "t\n"
    with atomic.atomic_open(tmp_path / "a.csv") as f:  # over an existing target
        f.write("u\n")
    assert (tmp_path / "a.csv").read_text() == "u\n" and [p.name for p in tmp_path.iterdir()] == ["a.csv"]


def test_named_temporaries_of_a_killed_writer_are_swept_on_the_next_write_to_the_directory(tmp_path):
    target = tmp_path / "run.gif"
    killed = _start(NAMED_WRITER, target)
    _kill(killed)
    stale = _hidden(tmp_path)
    assert len(stale) == 1 and stale[0].startswith(f"{atomic.TEMPORARY_PREFIX}{killed.pid}-") and stale[0].endswith("-run.gif.gif")
    assert not target.exists()
    # A write of another file into the same directory (here by a writer that stays alive) removes
    # the dead writer's temporary; a live writer's temporary is left alone.
    live = _start(NAMED_WRITER, tmp_path / "live.gif")
    try:
        left = _hidden(tmp_path)
        assert len(left) == 1 and left[0].startswith(f"{atomic.TEMPORARY_PREFIX}{live.pid}-")
        atomic.write_text(tmp_path / "other.txt", "t,x\n0,1\n")
        assert _hidden(tmp_path) == left
    finally:
        _kill(live)
    with atomic.atomic_path(target, suffix=".gif") as tmp:
        tmp.write_bytes(b"GIF89a")
    assert _hidden(tmp_path) == [] and target.read_bytes() == b"GIF89a"


def test_temporaries_of_earlier_versions_are_still_swept(tmp_path):
    # `.<name>.<pid>.<random><suffix>`, the names before `.spacearm-tmp-`: a dead writer's goes.
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    pid = int(dead.stdout)
    old = tmp_path / f".run.csv.{pid}.abc123.csv"
    old.write_text("partial")
    atomic.write_text(tmp_path / "run.csv", "t\n")
    assert _hidden(tmp_path) == []


@pytest.mark.parametrize("missing", ["O_TMPFILE", "linking"])
def test_the_fallbacks_write_the_same_files(tmp_path, monkeypatch, missing, umask_027):
    # Without O_TMPFILE (another system): a named temporary; without a way to link the unnamed
    # file (no /proc links, no AT_EMPTY_PATH): its bytes copied into a named temporary.
    if missing == "O_TMPFILE":
        monkeypatch.setattr(atomic, "_open_unnamed", lambda directory: None)
    else:
        monkeypatch.setattr(atomic, "_link_unnamed", lambda fd, destination: False)
    for ext, write in _writers(tmp_path):
        path = tmp_path / f"out.{ext}"
        write(path)
        assert _mode(path) == umask_027, ext
        write(path)
    assert _hidden(tmp_path) == []
    assert spacearm.Trajectory.load(tmp_path / "out.npz").t.shape == (11,)
    assert (tmp_path / "out.txt").read_text() == "generated code\n"


def test_a_truncated_npz_is_a_clear_error(tmp_path):
    robot = spacearm.presets.planar4()
    path = tmp_path / "run.npz"
    spacearm.simulate(robot, 0.05, dt=1e-3).save(path)
    data = path.read_bytes()
    for cut in (len(data) // 2, len(data) - 10, 30):
        bad = tmp_path / f"cut{cut}.npz"
        bad.write_bytes(data[:cut])
        with pytest.raises(spacearm.ArgumentError, match="not a spacearm trajectory file"):
            spacearm.Trajectory.load(bad)
    # The untouched file still loads: 0.05 s at 1 ms is 51 samples.
    assert spacearm.Trajectory.load(path).t.shape == (51,)
