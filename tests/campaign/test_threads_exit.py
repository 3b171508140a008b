"""A threads-backend campaign that an exception leaves (Ctrl-C) ends its threads before it
returns: the interpreter then exits cleanly (it aborted with "FATAL: exception not rethrown"
when a daemon thread was still in a native rollout at exit; issue 26)."""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import time

import pytest

CHILD = textwrap.dedent("""
    import sys, threading
    import spacearm
    from spacearm.campaign import Scenario, run_campaign
    robot = spacearm.presets.spatial6()
    # long samples (20 s of simulated time at dt = 1e-3 each) in batches of 2 on 2 threads
    scenario = Scenario(duration=20.0, dt=1e-3, q_offset=0.3)
    print("started", flush=True)
    try:
        run_campaign(robot, 16, workers=2, backend="threads", batch_size=2, scenario=scenario, progress=False)
    except KeyboardInterrupt:
        alive = [t.name for t in threading.enumerate() if t.name.startswith("spacearm-campaign")]
        print("interrupted", alive, flush=True)
        sys.exit(130)
    print("finished", flush=True)
""")


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_an_interrupted_threads_campaign_ends_its_threads_and_exits_cleanly():
    child = subprocess.Popen([sys.executable, "-c", CHILD], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "started"
        time.sleep(1.5)  # inside the first batch's native rollouts
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=60)
        waited = time.monotonic() - sent
    finally:
        child.kill()
    assert "FATAL" not in err and child.returncode == 130, (child.returncode, err[-2000:])
    assert out.strip() == "interrupted []", out  # no campaign thread left running
    assert waited < 5.0, f"took {waited:.1f} s"
