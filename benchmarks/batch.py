#!/usr/bin/env python
"""Batch forward dynamics and per-call overhead: spacearm against Pinocchio and MuJoCo at equal
threads, interleaved, medians and ratios.

Two tables:

1. **Per call** (one state, N = 2 and N = 6): ``Robot.forward_dynamics(x, u, tau=tau)`` (the
   public method), the extension method alone (``robot._m.forward_dynamics_tau``), and the
   native time of one state, measured as a one-thread batch of the same states divided by its
   size (the kernel with no Python in between). ``overhead`` is public / native.
2. **Batch**: forward dynamics of ``--states`` states (default 10,000) at N = 6 and N = 30 on
   ``--threads`` threads: ``Robot.forward_dynamics(xs, us, fs)`` (rows on rayon, GIL
   released) against ``pin.abaInParallel`` (Pinocchio's batched ABA, the same threads) and
   ``mujoco.rollout`` of one step (MuJoCo's batched entry point; it also integrates the step,
   so it does a little more than forward dynamics) with one MjData per thread. Ratios are
   spacearm / peer: below 1 means spacearm is faster.

Every figure is the median of ``--repeat`` interleaved rounds (each round runs every candidate
once, so slow phases of a shared machine hit them all alike). Before timing, Pinocchio's batch
result is converted to spacearm's conventions and compared (``check``: max relative difference).

    python benchmarks/batch.py                  # 2 threads, 10,000 states
    python benchmarks/batch.py --threads 16     # on a 16-core machine
    python benchmarks/batch.py --quick          # fewer states and rounds
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm import _core, interop  # noqa: E402

try:
    import pinocchio as pin
except ImportError:  # pragma: no cover - optional peer
    pin = None
try:
    import mujoco
    from mujoco import rollout as mj_rollout
except ImportError:  # pragma: no cover - optional peer
    mujoco = None


def serial_arm(n: int, seed: int = 7) -> spacearm.Robot:
    """A serial arm of ``n`` revolute joints with random axes, offsets and masses."""
    rng = np.random.default_rng(seed)
    b = spacearm.Robot.builder(f"arm{n}", base_mass=400.0, base_inertia=[50.0, 60.0, 70.0])
    parent = "base"
    for i in range(n):
        mass = float(rng.uniform(1.0, 10.0))
        b.add_link(f"link{i + 1}", parent=parent, axis=tuple(rng.normal(size=3)),
                   origin=tuple(rng.uniform(-0.5, 0.5, 3)), com=tuple(rng.uniform(-0.3, 0.3, 3)),
                   mass=mass, inertia=list(mass * rng.uniform(0.010, 0.015, 3)), rpy=tuple(rng.uniform(-1, 1, 3)))
        parent = f"link{i + 1}"
    b.add_point("tip", body=parent, offset=(0.1, 0.0, 0.0))
    b.set_end_effector("tip")
    return b.build()


def robot_of(n: int) -> spacearm.Robot:
    """The preset spatial6 at N = 6, a random serial arm otherwise."""
    return spacearm.presets.spatial6() if n == 6 else serial_arm(n)


def states(robot, count: int, seed: int = 0):
    """``count`` random states: attitude, joint angles, velocities and forces of order one."""
    rng = np.random.default_rng(seed)
    quat = rng.normal(size=(count, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    xs = np.concatenate([rng.uniform(-1, 1, (count, 3)), quat, rng.uniform(-np.pi, np.pi, (count, robot.n_dof))], axis=1)
    us = rng.normal(scale=0.3, size=(count, robot.nu))
    fs = rng.normal(size=(count, robot.nu))
    return xs, us, fs


def interleaved(fns: dict, repeat: int) -> dict:
    """Median seconds per call of each callable over ``repeat`` interleaved rounds."""
    samples = {k: [] for k in fns}
    for fn in fns.values():
        fn()  # warm up (thread pools, caches)
    for _ in range(repeat):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            samples[k].append(time.perf_counter() - t0)
    return {k: statistics.median(v) for k, v in samples.items()}


def per_call(n: int, repeat: int) -> dict:
    robot = robot_of(n)
    xs, us, fs = states(robot, 2000, seed=1)
    taus = np.ascontiguousarray(fs[:, 6:])
    x, u, tau = xs[0], us[0], taus[0]
    calls = 2000

    def public():
        for _ in range(calls):
            robot.forward_dynamics(x, u, tau=tau)

    def extension():
        m = robot._m
        for _ in range(calls):
            m.forward_dynamics_tau(x, u, tau)

    def native():
        robot.forward_dynamics(xs, us, tau=taus)

    _core.set_batch_threads(1)
    try:
        t = interleaved({"public": public, "extension": extension, "native": native}, repeat)
    finally:
        _core.set_batch_threads(None)
    out = {k: v / calls for k, v in t.items()}
    out["overhead"] = out["public"] / out["native"]
    return out


def batch(n: int, count: int, threads: int, repeat: int) -> dict:
    robot = robot_of(n)
    xs, us, fs = states(robot, count, seed=2)
    fns = {"spacearm": lambda: robot.forward_dynamics(xs, us, fs)}
    check = {}
    if pin is not None:
        model = interop.to_pinocchio(robot)
        pool = pin.ModelPool(model, threads)
        qv = [interop.to_pinocchio_state(robot, xs[i], us[i]) for i in range(count)]
        q = np.asfortranarray(np.array([a for a, _ in qv]).T)
        v = np.asfortranarray(np.array([b for _, b in qv]).T)
        tau = np.asfortranarray(np.array([interop.to_pinocchio_force(robot, xs[i], fs[i]) for i in range(count)]).T)
        a_out = np.zeros((model.nv, count), order="F")
        fns["pinocchio"] = lambda: pin.abaInParallel(threads, pool, q, v, tau, a_out)
        fns["pinocchio"]()
        ours = robot.forward_dynamics(xs[:50], us[:50], fs[:50])
        theirs = np.array([interop.acceleration_from_pinocchio(robot, xs[i], us[i], a_out[:, i]) for i in range(50)])
        check["pinocchio"] = float(np.abs(ours - theirs).max() / np.abs(theirs).max())
    if mujoco is not None:
        m = interop.to_mujoco(robot)
        m.opt.enableflags &= ~int(mujoco.mjtEnableBit.mjENBL_ENERGY)
        datas = [mujoco.MjData(m) for _ in range(threads)]
        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        d0 = datas[0]
        initial = np.zeros((count, mujoco.mj_stateSize(m, spec)))
        for i in range(count):
            qpos, qvel = interop.to_mujoco_state(robot, xs[i], us[i])
            d0.qpos[:], d0.qvel[:] = qpos, qvel
            mujoco.mj_getState(m, d0, initial[i], spec)
        runner = mj_rollout.Rollout(nthread=threads) if hasattr(mj_rollout, "Rollout") else None
        if runner is not None:
            fns["mujoco"] = lambda: runner.rollout(m, datas, initial, nstep=1)
        else:  # pragma: no cover - older MuJoCo
            fns["mujoco"] = lambda: mj_rollout.rollout(m, datas, initial, nstep=1)
    _core.set_batch_threads(threads)
    try:
        t = interleaved(fns, repeat)
    finally:
        _core.set_batch_threads(None)
    return {"per_state": {k: v / count for k, v in t.items()}, "check": check}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--threads", type=int, default=2, help="threads for every batch (default 2)")
    p.add_argument("--states", type=int, default=10_000, help="states per batch (default 10,000)")
    p.add_argument("--repeat", type=int, default=9, help="interleaved rounds (default 9)")
    p.add_argument("--quick", action="store_true", help="2,000 states, 5 rounds")
    args = p.parse_args(argv)
    if args.quick:
        args.states, args.repeat = 2000, 5
    if args.threads < 1:
        p.error("--threads must be >= 1")

    print(f"spacearm {spacearm.__version__}, pinocchio {pin.__version__ if pin else '-'}, mujoco {mujoco.__version__ if mujoco else '-'}; "
          f"{os.cpu_count()} CPUs; medians of {args.repeat} interleaved rounds\n")
    print("Per call, one state (1 thread), forward dynamics with tau=:")
    print(f"{'N':>4} {'public µs':>10} {'extension µs':>13} {'native µs':>10} {'public/native':>14}")
    for n in (2, 6):
        r = per_call(n, args.repeat)
        print(f"{n:>4} {r['public'] * 1e6:>10.3f} {r['extension'] * 1e6:>13.3f} {r['native'] * 1e6:>10.3f} {r['overhead']:>14.2f}")

    print(f"\nBatch forward dynamics, {args.states} states, {args.threads} threads (µs per state):")
    print(f"{'N':>4} {'spacearm':>9} {'pinocchio':>10} {'mujoco':>9} {'sa/pin':>7} {'sa/mj':>7} {'check pin':>10}")
    for n in (6, 30):
        r = batch(n, args.states, args.threads, args.repeat)
        ps = r["per_state"]
        sa = ps["spacearm"]
        pin_t, mj_t = ps.get("pinocchio"), ps.get("mujoco")
        fmt = lambda v: f"{v * 1e6:.3f}" if v else "-"  # noqa: E731
        ratio = lambda v: f"{sa / v:.2f}" if v else "-"  # noqa: E731
        print(f"{n:>4} {fmt(sa):>9} {fmt(pin_t):>10} {fmt(mj_t):>9} {ratio(pin_t):>7} {ratio(mj_t):>7} "
              f"{r['check'].get('pinocchio', float('nan')):>10.1e}")
    print("\nmujoco: rollout of one step per state (forward dynamics and the integration of the step).")
    return 0


if __name__ == "__main__":
    sys.exit(main())
