"""A real headless browser for the tests: Chromium, run as a subprocess on a local file.

CI installs Debian's ``chromium`` (``.ci/run``) and sets ``SPACEARM_REQUIRE_BROWSER=1``, so a
browser test there fails when Chromium is missing instead of skipping; on a developer's machine
without Chromium the tests skip with the reason.

Two views of a page are used: the DOM after its scripts ran (``--dump-dom``, with a virtual-time
budget so that timers and module scripts settle) and a PNG screenshot at a fixed window size.
Both load ``file://`` URLs with no network.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import List, Optional

import pytest

_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


def find_chromium() -> Optional[str]:
    """The Chromium executable ($SPACEARM_CHROMIUM, else the first of the usual names on PATH)."""
    explicit = os.environ.get("SPACEARM_CHROMIUM")
    if explicit:
        return explicit
    for name in _NAMES:
        found = shutil.which(name)
        if found:
            return found
    return None


def require_chromium() -> str:
    """The executable, or skip (fail under SPACEARM_REQUIRE_BROWSER=1, as in CI)."""
    exe = find_chromium()
    if exe is None:
        message = "no Chromium on PATH (Debian: apt-get install chromium; or set SPACEARM_CHROMIUM)"
        if os.environ.get("SPACEARM_REQUIRE_BROWSER") == "1":
            pytest.fail(message + ", and SPACEARM_REQUIRE_BROWSER=1 requires it")
        pytest.skip(message)
    return exe


def _run(args: List[str], timeout: float) -> subprocess.CompletedProcess:
    exe = require_chromium()
    with tempfile.TemporaryDirectory(prefix="spacearm-chromium-") as profile:
        cmd = [
            exe,
            "--headless=new",
            "--no-sandbox",  # CI runs as root
            "--disable-gpu",
            "--use-gl=swiftshader",
            "--enable-unsafe-swiftshader",  # WebGL through the CPU renderer
            "--no-first-run",
            "--disable-extensions",
            "--disable-background-networking",
            "--allow-file-access-from-files",
            f"--user-data-dir={profile}",
            *args,
        ]
        return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)


def url_of(path) -> str:
    return Path(path).resolve().as_uri()


def dump_dom(path, *, budget_ms: int = 5000, timeout: float = 120.0, extra: List[str] = ()) -> str:
    """The page's DOM (serialized HTML) after its scripts have run for ``budget_ms`` of virtual
    time; ``extra``: more Chromium switches (``--disable-webgl``)."""
    proc = _run([*extra, f"--virtual-time-budget={budget_ms}", "--dump-dom", url_of(path)], timeout)
    if proc.returncode != 0 or not proc.stdout.strip():
        raise AssertionError(f"chromium --dump-dom failed ({proc.returncode}): {proc.stderr[-2000:]}")
    return proc.stdout


def screenshot(path, png, *, width: int = 1280, height: int = 800, budget_ms: int = 5000, timeout: float = 120.0) -> Path:
    """A PNG screenshot of the page at ``width`` × ``height`` after ``budget_ms`` of virtual time."""
    png = Path(png)
    proc = _run(
        [f"--virtual-time-budget={budget_ms}", f"--window-size={width},{height}", f"--screenshot={png}", url_of(path)],
        timeout,
    )
    if proc.returncode != 0 or not png.is_file() or png.stat().st_size == 0:
        raise AssertionError(f"chromium --screenshot failed ({proc.returncode}): {proc.stderr[-2000:]}")
    return png
