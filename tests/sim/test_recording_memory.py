"""Recording without a second copy: the records of a run go to numpy as they are, so the peak
memory of a run is about the size of its records (not twice), decimation keeps a 10^6-step run
small, and float32 records halve it. Measured as the growth of the process's peak resident set
(resource.getrusage maxrss) in a fresh interpreter, one run after another."""

import json
import os
import subprocess
import sys

import pytest

resource = pytest.importorskip("resource")

SCRIPT = r"""
import json, resource, sys
import numpy as np
import spacearm

def peak_mb():
    kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return kb / 1024.0 if sys.platform != "darwin" else kb / 2**20

robot = spacearm.presets.spatial6()
u0 = robot.zero_velocity(); u0[6:] = 0.3
spacearm.simulate(robot, 0.01, u0=u0)            # everything imported and warmed up
out = {"base": peak_mb()}
# 10^6 steps recorded every 100.
traj = spacearm.simulate(robot, 1000.0, u0=u0, dt=1e-3, record_every=100)
out["long_samples"] = len(traj)
out["long_bytes"] = sum(traj[k].nbytes for k in traj.keys)
del traj
out["after_long"] = peak_mb()
# 10^5 steps recorded every step: the records dominate.
traj = spacearm.simulate(robot, 100.0, u0=u0, dt=1e-3)
out["full_bytes"] = sum(traj[k].nbytes for k in traj.keys)
out["after_full"] = peak_mb()
del traj
traj = spacearm.simulate(robot, 100.0, u0=u0, dt=1e-3, record_dtype="float32")
out["f32_bytes"] = sum(traj[k].nbytes for k in traj.keys)
print(json.dumps(out))
"""


def test_peak_memory_is_the_records_not_twice():
    env = dict(os.environ)
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    env["PYTHONPATH"] = os.path.join(root, "python") + os.pathsep + env.get("PYTHONPATH", "")
    proc = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, timeout=600, env=env)
    assert proc.returncode == 0, proc.stderr
    m = json.loads(proc.stdout.strip().splitlines()[-1])
    mb = 2.0**20
    # 10^6 steps every 100: 10^4 + 1 samples, far under 100 MB in all.
    assert m["long_samples"] == 10_001
    assert m["after_long"] - m["base"] < 100.0
    # 10^5 samples of about 600 B: ~60 MB of records; the peak grows by about that, not twice.
    full = m["full_bytes"] / mb
    assert full > 40.0
    growth = m["after_full"] - m["base"]
    assert growth < 1.3 * full, (growth, full)
    # float32: half the bytes, the time excepted.
    assert m["f32_bytes"] < 0.55 * m["full_bytes"]
