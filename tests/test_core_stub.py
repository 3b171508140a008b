"""``python/spacearm/_core.pyi`` declares the extension exactly: mypy's stubtest imports the
compiled module and compares every class, function, signature, property and exported name with
the stub (constructors as ``__new__``, frozen classes ``@final``, the exception classes with their
builtin bases, ``__all__`` the runtime's). A binding added, renamed or given a new argument
without its stub fails here."""

import subprocess
import sys

import pytest


def test_stub_matches_the_extension():
    pytest.importorskip("mypy", reason="mypy (test extra) runs stubtest")
    proc = subprocess.run([sys.executable, "-m", "mypy.stubtest", "spacearm._core"], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-6000:] + proc.stderr[-2000:]
    assert "Success" in proc.stdout
