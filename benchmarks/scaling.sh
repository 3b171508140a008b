#!/usr/bin/env bash
# Thread scaling of the batch entry points on one machine: rollouts (spacearm.rollout, and
# mujoco.rollout side by side when MuJoCo is installed) at 1, 2, 4, 8, 16 threads, then batch
# forward dynamics (Robot.forward_dynamics with a leading batch axis) when that API exists.
# Needs Python with numpy and spacearm installed (a wheel is enough); MuJoCo and Pinocchio are
# optional peers: missing ones are skipped with a note. Under 4 minutes on a 16-core machine.
#
#   bash benchmarks/scaling.sh                 # threads 1,2,4,8,16
#   THREADS=1,2 bash benchmarks/scaling.sh     # a smaller machine
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
THREADS=${THREADS:-1,2,4,8,16}

echo "== machine"
"$PY" -c "import os, platform; print(platform.platform(), '|', os.cpu_count(), 'logical CPUs | Python', platform.python_version())"
"$PY" -c "import spacearm, numpy; print('spacearm', spacearm.__version__, 'from', spacearm.__file__, '| numpy', numpy.__version__)"
for peer in mujoco pinocchio; do
  "$PY" -c "import $peer" 2>/dev/null && echo "peer $peer: installed" || echo "peer $peer: not installed (its columns are skipped)"
done

echo
echo "== rollouts: B = 256 x 500 RK4 steps (0.5 s at 1 kHz), free-floating, zero torque"
timeout 200 "$PY" benchmarks/rollout.py --threads "$THREADS" --batch 256 --repeat 3 --sizes 6,24

echo
echo "== batch forward dynamics: 10,000 states, N = 6 and 30 (rayon's pool sized by RAYON_NUM_THREADS)"
for t in ${THREADS//,/ }; do
  RAYON_NUM_THREADS=$t timeout 60 "$PY" - "$t" <<'PYEOF' || echo "threads $t: batch forward dynamics run failed or timed out"
import sys, time
import numpy as np
import spacearm
sys.path.insert(0, "benchmarks")
from peers import random_arm

threads = int(sys.argv[1])
for n in (6, 30):
    robot = spacearm.presets.spatial6() if n == 6 else random_arm(n, seed=n)
    rng = np.random.default_rng(0)
    b = 10_000
    x = np.tile(robot.neutral_configuration(), (b, 1)); x[:, 7:] = rng.uniform(-1, 1, (b, n))
    u = rng.uniform(-0.3, 0.3, (b, robot.nu)); f = rng.uniform(-1, 1, (b, robot.nu))
    try:
        robot.forward_dynamics(x[:2], u[:2], f[:2])
    except Exception as exc:  # the batch API is not in this build
        print(f"threads {threads}, N = {n}: no batch forward dynamics in this build ({type(exc).__name__}: {exc})"[:200])
        continue
    times = []
    for _ in range(7):
        t0 = time.perf_counter(); robot.forward_dynamics(x, u, f); times.append(time.perf_counter() - t0)
    m = float(np.median(times))
    print(f"threads {threads:2d}, N = {n:2d}: {1e3 * m:8.2f} ms per 10,000 states = {1e6 * m / b:.3f} us per state")
PYEOF
done
