#!/usr/bin/env python
"""Time batch rollouts: ``spacearm.rollout`` against ``mujoco.rollout`` at equal threads.

B rollouts of a free-floating arm (zero gravity, zero torque, every joint spinning from a
different initial velocity), RK4 at 1 kHz, the same model exported to MJCF with
``spacearm.interop``. Each figure is the wall time of one call from Python, the median over
``--repeat`` rounds; in each round every candidate runs once at every thread count
(interleaved, so a slow phase of the machine hits all alike). Throughput is steps per second
(B × steps / time); ratio = spacearm / MuJoCo time, below 1 spacearm is faster; speed-up is
against the same candidate at 1 thread.

Candidates:

- ``spacearm rec``: ``spacearm.rollout`` recording every step (state, accelerations, torques,
  base wrench, momenta, energy, CM, end-effector pose: 76 values a step at N = 6);
- ``spacearm final``: the same, ``record_every`` = the number of steps (initial and final
  samples only: what a Monte Carlo study keeps);
- ``mujoco``: ``mujoco.rollout.rollout`` with one ``MjData`` per thread, which records the
  full physics state every step (it has no lighter mode).

Before timing, the final states are compared (``check``: max |Δ[x; u]| after mapping MuJoCo's
state with ``spacearm.interop``): both integrate the same ODE with RK4 and the same step, so
they agree to rounding.

    python benchmarks/rollout.py                         # N = 6 and 24, threads 1,2 (< 60 s)
    python benchmarks/rollout.py --threads 1,2,4,8,16 --batch 256
    python benchmarks/rollout.py --no-peer               # spacearm only (MuJoCo not needed)
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm import interop  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peers import random_arm  # noqa: E402

try:
    import mujoco
    from mujoco import rollout as mj_rollout
except ImportError:  # pragma: no cover - the peer is optional
    mujoco = None


def initial_states(robot, b: int, seed: int = 0):
    """B states at the neutral configuration, joints spinning at random rates, base at rest."""
    rng = np.random.default_rng(seed)
    x0 = np.tile(robot.neutral_configuration(), (b, 1))
    u0 = np.zeros((b, robot.nu))
    u0[:, 6:] = rng.uniform(-0.5, 0.5, (b, robot.n_dof))
    return x0, u0


class MujocoRollouts:
    """``mujoco.rollout`` of the exported model from the same B states."""

    def __init__(self, robot, x0, u0, dt: float, steps: int, max_threads: int):
        self.model = interop.to_mujoco(robot)
        self.model.opt.timestep = dt
        self.model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
        self.model.opt.gravity[:] = 0.0
        self.data = [mujoco.MjData(self.model) for _ in range(max_threads)]
        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        self.size = mujoco.mj_stateSize(self.model, spec)
        self.state0 = np.empty((len(x0), self.size))
        d = self.data[0]
        for i, (x, u) in enumerate(zip(x0, u0)):
            d.qpos[:], d.qvel[:] = interop.to_mujoco_state(robot, x, u)
            mujoco.mj_getState(self.model, d, self.state0[i], spec)
        self.steps = steps
        self.robot = robot

    def run(self, threads: int):
        state, _ = mj_rollout.rollout(self.model, self.data[:threads], self.state0, nstep=self.steps)
        return state

    def final(self, state):
        """The final ``[x; u]`` of each rollout in spacearm's conventions."""
        nq, nv = self.model.nq, self.model.nv
        out = []
        for s in state[:, -1, :]:
            qpos, qvel = s[1 : 1 + nq], s[1 + nq : 1 + nq + nv]  # FULLPHYSICS: time, qpos, qvel, ...
            x, u = interop.from_mujoco_state(self.robot, qpos, qvel)
            out.append(np.r_[x, u])
        return np.array(out)


def table(rows, header):
    widths = [max(len(str(r[i])) for r in rows + [header]) for i in range(len(header))]
    line = "  ".join(h.ljust(w) for h, w in zip(header, widths))
    print(line)
    print("-" * len(line))
    for r in rows:
        print("  ".join(str(c).ljust(w) for c, w in zip(r, widths)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--threads", default="1,2", help="comma-separated thread counts (default 1,2)")
    parser.add_argument("--batch", type=int, default=32, help="rollouts per call (default 32)")
    parser.add_argument("--duration", type=float, default=0.5, help="simulated seconds per rollout (default 0.5)")
    parser.add_argument("--dt", type=float, default=1e-3, help="RK4 step (default 1 ms)")
    parser.add_argument("--repeat", type=int, default=5, help="rounds (median; default 5)")
    parser.add_argument("--sizes", default="6,24", help="N of the arms: 6 is spatial6, others random arms (default 6,24)")
    parser.add_argument("--no-peer", action="store_true", help="time spacearm only")
    args = parser.parse_args()
    threads = [int(t) for t in args.threads.split(",")]
    use_peer = mujoco is not None and not args.no_peer
    steps = int(round(args.duration / args.dt))
    print(f"spacearm {spacearm.__version__}" + (f", MuJoCo {mujoco.__version__}" if use_peer else ", MuJoCo not timed"))
    print(f"{platform.processor() or platform.machine()}, {os.cpu_count()} logical CPUs, Python {platform.python_version()}")
    print(f"B = {args.batch} rollouts x {steps} RK4 steps of {args.dt:g} s, zero torque, free-floating; median of {args.repeat} rounds")
    if mujoco is None and not args.no_peer:
        print("note: MuJoCo is not installed; spacearm only (pip install mujoco for the comparison)")
    for n in (int(s) for s in args.sizes.split(",")):
        robot = spacearm.presets.spatial6() if n == 6 else random_arm(n, seed=n)
        x0, u0 = initial_states(robot, args.batch)
        candidates = {
            "spacearm rec": lambda t: spacearm.rollout(robot, args.duration, x0, u0, dt=args.dt, threads=t),
            "spacearm final": lambda t: spacearm.rollout(robot, args.duration, x0, u0, dt=args.dt, threads=t, record_every=steps),
        }
        check = ""
        if use_peer:
            mj = MujocoRollouts(robot, x0, u0, args.dt, steps, max(threads))
            candidates["mujoco"] = mj.run
            ours = spacearm.rollout(robot, args.duration, x0, u0, dt=args.dt, record_every=steps).final_state()
            check = f"; check max |d[x; u]| vs MuJoCo = {np.max(np.abs(ours - mj.final(mj.run(1)))):.1e}"
        times = {(c, t): [] for c in candidates for t in threads}
        for _ in range(args.repeat):
            for t in threads:
                for c, f in candidates.items():
                    t0 = time.perf_counter()
                    f(t)
                    times[(c, t)].append(time.perf_counter() - t0)
        med = {k: float(np.median(v)) for k, v in times.items()}
        print(f"\nN = {n} ({robot.name}){check}")
        rows = []
        for t in threads:
            for c in candidates:
                m = med[(c, t)]
                ratio = f"{m / med[('mujoco', t)]:.2f}" if use_peer and c != "mujoco" else ""
                rows.append([t, c, f"{1e3 * m:.1f}", f"{args.batch * steps / m / 1e6:.3f}", f"{med[(c, threads[0])] / m:.2f}", ratio])
        table(rows, ["threads", "candidate", "ms/call", "M steps/s", f"speed-up vs {threads[0]}", "ratio vs mujoco"])


if __name__ == "__main__":
    main()
