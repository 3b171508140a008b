"""A threads-backend campaign that an exception leaves (Ctrl-C) ends its threads before it
returns: the interpreter then exits cleanly (it aborted with "FATAL: exception not rethrown"
when a daemon thread was still in a native rollout at exit; issue 26)."""

from __future__ import annotations

import sys
import textwrap

import pytest
from interrupt_child import interrupt_child

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
    a = interrupt_child(CHILD, 1.5)  # inside the first batch's native rollouts
    assert "FATAL" not in a.err and a.returncode == 130, (a.returncode, a.err[-2000:])
    assert a.out.strip() == "interrupted []", a.out  # no campaign thread left running
    assert a.waited < 5.0, f"took {a.waited:.1f} s"
