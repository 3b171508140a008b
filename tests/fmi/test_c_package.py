"""``spacearm.c`` and ``python -m spacearm.c`` (docs/c-api.md, "Getting the library"): the
header, library, pkg-config and CMake files of the C library in an installation, and flags a C
compiler builds with.

Each build compiles crates/spacearm-c/examples/example.c with the system compiler and runs it; its
printed diagonal of H* must equal ``Robot.generalized_inertia`` of the Python extension (a program
that linked nothing, or read the wrong buffers, fails). The layout a wheel ships is staged here by
the script scripts/build-wheels.sh uses (scripts/stage-c-prefix.sh) into a temporary folder that
stands for ``spacearm/c/`` of an installation; the wheel itself is checked by
scripts/new-user-check.sh (CI): its file list, and an FMU exported there that FMPy validates
and runs.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import spacearm
import spacearm.c
from spacearm.c.__main__ import main
from spacearm.errors import MissingDependencyError

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "crates" / "spacearm-c" / "examples" / "example.c"

needs_cc = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc) on this machine")


def build_and_run(flags, out: Path) -> str:
    """Compile the C example with ``flags`` into the folder ``out`` and run it; its stdout."""
    out.mkdir(parents=True, exist_ok=True)
    exe = out / "example"
    subprocess.run(["cc", "-std=c11", str(EXAMPLE), *flags, "-lm", "-o", str(exe)], check=True)
    # No LD_LIBRARY_PATH: the run-time path the flags recorded must find the library.
    run_env = {k: v for k, v in os.environ.items() if k != "LD_LIBRARY_PATH"}
    return subprocess.run([str(exe)], check=True, stdout=subprocess.PIPE, text=True, env=run_env).stdout


def assert_example_output(out: str) -> None:
    """The example's H* diagonal (spatial6 at its initial configuration, 4 decimals) against the
    Python extension's."""
    line = re.search(r"H\* of 6 joints, diagonal:(.*)", out)
    assert line, out
    printed = np.array([float(v) for v in line.group(1).split()])
    robot = spacearm.presets.spatial6()
    want = np.diag(robot.generalized_inertia(robot.neutral_configuration()))
    assert np.all(np.abs(want) > 1e-3)  # a non-trivial H*: an all-zero print cannot pass
    assert np.allclose(printed, want, rtol=0, atol=0.6e-4), (printed, want)


@pytest.fixture
def installed(tmp_path, monkeypatch):
    """``spacearm.c`` as in a wheel's installation: its PREFIX a staged layout, no source checkout
    beside it, no SPACEARM_C_LIBRARY."""
    prefix = tmp_path / "site" / "spacearm" / "c"
    subprocess.run(["bash", str(ROOT / "scripts" / "stage-c-prefix.sh"), str(prefix), str(spacearm.c.library_path().parent)],
                   check=True)
    monkeypatch.delenv("SPACEARM_C_LIBRARY", raising=False)
    monkeypatch.setattr(spacearm.c, "PREFIX", prefix)
    monkeypatch.setattr(spacearm.c, "_CHECKOUT_HEADER", tmp_path / "no-checkout" / "spacearm.h")
    monkeypatch.setattr(spacearm.c, "_CHECKOUT_LIBRARY", tmp_path / "no-checkout" / spacearm.c.LIBRARY_NAME)
    return prefix


@needs_cc
def test_python_m_spacearm_c_flags_build_the_example(tmp_path):
    out = subprocess.run([sys.executable, "-m", "spacearm.c", "--cflags", "--libs"], check=True, stdout=subprocess.PIPE,
                         text=True).stdout
    assert out.count("\n") == 1  # one line, as pkg-config prints them
    flags = out.split()
    assert f"-I{spacearm.c.include_dir()}" in flags and "-lspacearm_c" in flags
    assert_example_output(build_and_run(flags, tmp_path / "flags"))


def test_the_path_options_print_one_line_each(capsys):
    assert main(["--library", "--include-dir", "--lib-dir"]) == 0
    lines = capsys.readouterr().out.splitlines()
    # In the order of the option table, whatever the order on the command line.
    assert lines == [str(spacearm.c.include_dir()), str(spacearm.c.lib_dir()), str(spacearm.c.library_path())]
    assert (Path(lines[0]) / "spacearm.h").is_file() and Path(lines[2]).is_file()


@needs_cc
def test_an_installed_layout_builds_through_the_flags_and_pkg_config(installed, tmp_path):
    assert spacearm.c.library_path() == installed / "lib" / spacearm.c.LIBRARY_NAME
    assert spacearm.c.include_dir() == installed / "include"
    assert (spacearm.c.pkg_config_path() / "spacearm.pc").is_file()
    assert (spacearm.c.cmake_dir() / "spacearm-config.cmake").is_file()
    flags = spacearm.c.cflags() + spacearm.c.libs()
    assert_example_output(build_and_run(flags, tmp_path / "flags"))
    if shutil.which("pkg-config"):
        env = dict(os.environ, PKG_CONFIG_PATH=str(spacearm.c.pkg_config_path()))
        pc = subprocess.run(["pkg-config", "--cflags", "--libs", "spacearm"], check=True, stdout=subprocess.PIPE,
                            text=True, env=env).stdout.split()
        assert_example_output(build_and_run(pc, tmp_path / "pc"))


def test_a_checkout_build_comes_before_a_staged_copy(installed, monkeypatch, tmp_path):
    # A source checkout: its target/release/ library wins over the folder's (older) staged copy.
    checkout_lib = tmp_path / "checkout" / spacearm.c.LIBRARY_NAME
    checkout_lib.parent.mkdir()
    checkout_lib.write_bytes(b"")
    header = tmp_path / "checkout" / "spacearm.h"
    header.write_text("")
    monkeypatch.setattr(spacearm.c, "_CHECKOUT_HEADER", header)
    monkeypatch.setattr(spacearm.c, "_CHECKOUT_LIBRARY", checkout_lib)
    assert spacearm.c.library_path() == checkout_lib
    # Not built there yet: the staged copy.
    checkout_lib.unlink()
    assert spacearm.c.library_path() == installed / "lib" / spacearm.c.LIBRARY_NAME


def test_spacearm_c_library_names_a_file(installed, monkeypatch, tmp_path):
    other = tmp_path / "custom_name.so"
    shutil.copy(installed / "lib" / spacearm.c.LIBRARY_NAME, other)
    monkeypatch.setenv("SPACEARM_C_LIBRARY", str(other))
    assert spacearm.c.library_path() == other
    assert spacearm.c.libs()[-1] == str(other.resolve())  # not -lspacearm_c, which would miss it
    monkeypatch.setenv("SPACEARM_C_LIBRARY", str(tmp_path / "nowhere.so"))
    with pytest.raises(MissingDependencyError, match="SPACEARM_C_LIBRARY is .*nowhere.so"):
        spacearm.c.library_path()


def test_an_installation_without_the_library_says_how_to_get_it(installed, capsys):
    shutil.rmtree(installed / "lib")
    shutil.rmtree(installed / "include")
    with pytest.raises(MissingDependencyError, match="not in this installation; install a spacearm wheel"):
        spacearm.c.library_path()
    with pytest.raises(MissingDependencyError, match="spacearm.h"):
        spacearm.c.include_dir()
    with pytest.raises(MissingDependencyError, match="spacearm.pc"):
        spacearm.c.pkg_config_path()
    # The FMU export reads the same answer.
    with pytest.raises(MissingDependencyError, match="libspacearm_c"):
        spacearm.fmi.library_path()
    assert main(["--cflags", "--libs"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("python -m spacearm.c: error: the spacearm C library")


def test_a_checkout_has_no_pkg_config_file_and_says_what_to_use(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(spacearm.c, "PREFIX", tmp_path)  # nothing staged
    if not spacearm.c._CHECKOUT_HEADER.is_file():
        pytest.skip("not run from a source checkout")
    assert main(["--cmake-dir"]) == 2
    assert "--cflags --libs" in capsys.readouterr().err


def test_no_option_is_an_error(capsys):
    assert main([]) == 2
    assert "give at least one option" in capsys.readouterr().err
