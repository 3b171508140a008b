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


WRITER = textwrap.dedent("""
    import sys, time
    from spacearm._util.atomic import atomic_open
    with atomic_open(sys.argv[1], "w", suffix=".csv") as f:
        f.write("t,x\\n" * 1000)
        f.flush()
        print("writing", flush=True)
        time.sleep(60)
""")


def _start_writer(target):
    child = subprocess.Popen([sys.executable, "-c", WRITER, str(target)], stdout=subprocess.PIPE, text=True)
    line = child.stdout.readline()  # blocks until the temporary exists
    assert line.strip() == "writing"
    return child


def _temporaries(directory, name):
    return sorted(p.name for p in directory.iterdir() if p.name.startswith(f".{name}."))


def test_temporaries_of_a_killed_writer_are_removed_on_the_next_write(tmp_path):
    target = tmp_path / "run.csv"
    killed = _start_writer(target)
    try:
        os.kill(killed.pid, signal.SIGKILL)
        killed.wait(timeout=10)
    finally:
        killed.kill()
    stale = _temporaries(tmp_path, "run.csv")
    assert len(stale) == 1 and f".{killed.pid}." in stale[0]
    assert not target.exists()  # the interrupted write never produced a partial target
    # The next write to the path (here another writer, which then stays alive) removes the
    # dead writer's temporary; a live writer's temporary is left alone.
    live = _start_writer(target)
    try:
        assert _temporaries(tmp_path, "run.csv") != stale
        assert len(_temporaries(tmp_path, "run.csv")) == 1
        atomic.write_text(target, "t,x\n0,1\n")
        left = _temporaries(tmp_path, "run.csv")
        assert len(left) == 1 and f".{live.pid}." in left[0]
        assert target.read_text() == "t,x\n0,1\n"
    finally:
        live.kill()
        live.wait(timeout=10)
    atomic.write_text(target, "again\n")
    assert _temporaries(tmp_path, "run.csv") == []


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
