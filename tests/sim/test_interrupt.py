"""Ctrl-C interrupts a DOPRI5 run promptly even on a dense output grid, where one adaptive step
covers thousands of output samples (signals are checked between samples too, not only between
steps); the command line answers Ctrl-C with one line and exit status 130."""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import time

import pytest

CHILD = textwrap.dedent("""
    import sys
    import spacearm
    robot = spacearm.presets.spatial6()
    u0 = [0.0] * 6 + [0.1] * 6
    print("started", flush=True)
    try:
        # 10^6 output samples (one right-hand side each), while the slow torque-free motion
        # and the loose tolerance let DOPRI5 cover the second in 7 steps: ~140,000 samples,
        # seconds of work, per step.
        spacearm.simulate(robot, 1.0, u0=u0, integrator="dopri5", dt=1e-6, rtol=1e-3, atol=1e-9)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
        sys.exit(130)
    print("finished", flush=True)
""")


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_ctrl_c_stops_a_dense_dopri5_run_promptly():
    child = subprocess.Popen([sys.executable, "-c", CHILD], stdout=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "started"
        time.sleep(0.3)  # the run takes about 1.5 s on this machine kind, unloaded
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, _ = child.communicate(timeout=120)
        waited = time.monotonic() - sent
    finally:
        child.kill()
    assert out.strip() == "interrupted", out
    assert child.returncode == 130
    assert waited < 3.0, f"took {waited:.1f} s to answer Ctrl-C"


def test_cli_answers_ctrl_c_in_one_line(monkeypatch, capsys):
    from spacearm import cli
    from spacearm.cli import inspect as cli_inspect

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli_inspect, "run", interrupted)
    assert cli.main(["inspect", "planar4"]) == 130
    assert capsys.readouterr().err == "spacearm: interrupted\n"
