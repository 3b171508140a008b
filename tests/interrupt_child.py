"""The one harness of the Ctrl-C tests: run a Python child, wait for its "started" line, send it
SIGINT after ``delay`` seconds, and return what it printed, its exit status and how long it took
to answer."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from typing import NamedTuple


class Answer(NamedTuple):
    out: str
    err: str
    returncode: int
    waited: float  #: s from SIGINT to exit


def interrupt_child(code: str, delay: float, timeout: float = 60.0) -> Answer:
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "started"
        time.sleep(delay)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=timeout)
        waited = time.monotonic() - sent
    finally:
        child.kill()
    return Answer(out, err, child.returncode, waited)
