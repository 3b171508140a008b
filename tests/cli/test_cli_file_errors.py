"""Every file-system error a user can cause reaches the command line as one line,
``spacearm: error: ...`` with exit status 2, naming the path: never a traceback.

Real conditions where the test machine allows them (a missing output directory, a directory
where a file is expected, a truncated result file); the others (a read-only directory, a full
disk) by making the writer's system call fail with their errno, in process, since tests may
run as root (which ignores permissions) and without a tiny file system."""

from __future__ import annotations

import errno
import os
import subprocess
import sys

import numpy as np
import pytest

from spacearm._util import atomic
from spacearm.cli import main


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "spacearm", *args], capture_output=True, text=True, cwd=cwd,
                          timeout=300)


def assert_clean_error(out, *fragments):
    assert out.returncode == 2, (out.returncode, out.stderr)
    assert out.stderr.startswith("spacearm: error: ") and "Traceback" not in out.stderr, out.stderr
    assert out.stderr.count("\n") == 1, out.stderr
    for fragment in fragments:
        assert fragment in out.stderr, out.stderr


def test_missing_output_directory_is_refused_before_the_run(tmp_path):
    out = run("simulate", "planar4", "--duration", "0.01", "--csv", str(tmp_path / "nodir" / "run.csv"))
    assert_clean_error(out, "nodir/run.csv", "does not exist")
    assert not (tmp_path / "nodir").exists()


def test_output_that_is_a_directory(tmp_path):
    (tmp_path / "run.npz").mkdir()
    out = run("simulate", "planar4", "--duration", "0.01", "--out", str(tmp_path / "run.npz"))
    assert_clean_error(out, "run.npz", "is a directory")


def test_model_path_that_is_a_directory(tmp_path):
    (tmp_path / "arm.toml").mkdir()
    out = run("inspect", str(tmp_path / "arm.toml"))
    assert_clean_error(out, "arm.toml", "Is a directory")


def test_truncated_campaign_file(tmp_path):
    path = tmp_path / "c.npz"
    np.savez_compressed(path, index=np.arange(100), status=np.zeros(100, np.uint8), params=np.zeros((100, 4)))
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    out = run("campaign", "planar4", "--samples", "2", "--workers", "0", "--no-progress", "--out", str(path))
    assert_clean_error(out, "c.npz", "not a spacearm campaign file")
    assert path.read_bytes() == data[: len(data) // 2]  # left as it was


@pytest.mark.parametrize("code,reason", [(errno.EACCES, "Permission denied"), (errno.EROFS, "Read-only file system")])
def test_unwritable_directory(tmp_path, monkeypatch, capsys, code, reason):
    def refuse(*args, **kwargs):
        raise OSError(code, os.strerror(code), kwargs.get("dir"))

    def refuse_unnamed(directory):  # open(dir, O_TMPFILE) fails as the kernel would
        raise OSError(code, os.strerror(code))

    monkeypatch.setattr(atomic.tempfile, "mkstemp", refuse)
    monkeypatch.setattr(atomic, "_open_unnamed", refuse_unnamed)
    target = tmp_path / "run.csv"
    assert main(["simulate", "planar4", "--duration", "0.01", "--no-progress", "--csv", str(target)]) == 2
    err = capsys.readouterr().err
    assert err == f"spacearm: error: cannot use '{target}': {reason}\n"
    assert list(tmp_path.iterdir()) == []


def test_disk_full(tmp_path, monkeypatch, capsys):
    def full(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(atomic.os, "fsync", full)
    out_npz = tmp_path / "run.npz"
    assert main(["simulate", "planar4", "--duration", "0.01", "--no-progress", "--out", str(out_npz)]) == 2
    err = capsys.readouterr().err
    assert err == f"spacearm: error: cannot use '{out_npz}': No space left on device\n"
    assert list(tmp_path.iterdir()) == []  # no partial file, no temporary


@pytest.mark.parametrize("command", [
    ["capture", "spatial6", "--target-mass", "50", "--target-inertia", "4,5,6", "--out", "{d}/cap.npz", "--plot", "{d}/cap.xyz"],
    ["analyze", "planar4", "--workspace", "--no-progress", "--out", "{d}/ws.npz"],
    ["simulate", "planar4", "--duration", "0.05", "--no-progress", "--out", "{d}/run.npz", "--plot", "{d}/run.xyz"],
])
def test_a_figure_format_that_cannot_be_written_is_refused_before_the_run(tmp_path, capsys, command):
    # issue 26: `capture --plot x.xyz` wrote its record, then failed on the figure; `analyze --out
    # x.npz` computed the workspace first. Now: exit 2 before any work, and no file at all.
    args = [a.format(d=tmp_path) for a in command]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith("spacearm: error: cannot write a figure as '.") and "the formats are" in err and ".png" in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("token", ["--duration=--", "--dt=--", "--duration=-"])
def test_an_option_given_dashes_for_a_value_is_a_clean_error(token):
    # issue 26: `--opt=--` (argparse reads it as an empty list before Python 3.12) ended in a
    # ValueError traceback from the command.
    out = run("simulate", "planar4", token)
    assert_clean_error(out, f"argument {token.split('=')[0]}: expected a value, got '{token.split('=')[1]}'")
