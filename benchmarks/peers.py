#!/usr/bin/env python
"""Time spacearm against Pinocchio and MuJoCo, from Python, on the same models, in one run.

Every figure is the time of ONE call as a Python user makes it (argument conversion, the
computation, the result array), the median over interleaved batches (``timeit`` with
``repeat``: in each round every candidate runs one batch, so slow phases of a noisy machine hit
them all alike). The ratio column is spacearm / peer: below 1 means spacearm is faster.

Before timing, each peer's result is converted to spacearm's conventions with
``spacearm.interop`` and compared with spacearm's (the ``check`` column: max relative
difference), so the table only ever compares calls that compute the same quantity.

    python benchmarks/peers.py                      # spatial6, planar4, random12
    python benchmarks/peers.py --models spatial6 --json peers.json
    python benchmarks/peers.py --quick              # fewer, shorter batches

See benchmarks/README.md for what each row includes.
"""

from __future__ import annotations

import os

# BLAS worker threads spin after each call and steal the cores this benchmark runs on; the
# numpy linear algebra timed here is 6×6 to 18×18, where they never help.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import datetime  # noqa: E402
import functools  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import timeit  # noqa: E402

import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm import interop  # noqa: E402

try:
    import pinocchio as pin
except ImportError:  # pragma: no cover - optional peer
    pin = None
try:
    import mujoco
except ImportError:  # pragma: no cover - optional peer
    mujoco = None

ENGINES = ("spacearm", "pinocchio", "mujoco")

# What each row times, per engine (printed under the table and stored in the JSON).
INCLUDES = {
    "H": {
        "spacearm": "Robot.mass_matrix(x): forward kinematics + CRBA, full symmetric (6+N)² array",
        "pinocchio": "pin.crba(model, data, q[, convention]): forward kinematics + CRBA",
        "mujoco": "mj_kinematics + mj_comPos + mj_makeM + mj_fullM (dense copy)",
    },
    "H paper form": {
        "spacearm": "Robot.mass_matrix(x, method='paper'): forward kinematics + Jacobian sums of eqs. 27-36",
    },
    "c": {
        "spacearm": "Robot.bias_forces(x, u): forward kinematics + RNEA at zero acceleration",
        "pinocchio": "pin.nonLinearEffects(model, data, q, v): forward kinematics + RNEA",
        "mujoco": "mj_kinematics + mj_comPos + mj_comVel + mj_rne(flg_acc=0)",
    },
    "inverse dynamics": {
        "spacearm": "Robot.inverse_dynamics(x, u, du): forward kinematics + RNEA",
        "pinocchio": "pin.rnea(model, data, q, v, a): forward kinematics + RNEA",
        "mujoco": "mj_inverse: the whole position and velocity pipeline + inverse dynamics",
    },
    "forward dynamics ABA": {
        "spacearm": "Robot.forward_dynamics(x, u, f): forward kinematics + ABA",
        "pinocchio": "pin.aba(model, data, q, v, tau[, convention]): forward kinematics + ABA",
        "mujoco": "mj_forward: whole pipeline (kinematics, CRB, LDLᵀ, bias, acceleration; energy flag off)",
    },
    "forward dynamics H route": {
        "spacearm": "Robot.forward_dynamics(..., method='mass_matrix'): FK + RNEA + CRBA + Cholesky",
        "pinocchio": "same quantity: pin.aba (fastest convention)",
        "mujoco": "same quantity: mj_forward",
    },
    "forward dynamics reduced": {
        "spacearm": "Robot.forward_dynamics(..., method='reduced'): FK + RNEA + CRBA + H*, Cholesky of H*",
        "pinocchio": "same quantity: pin.aba (fastest convention)",
        "mujoco": "same quantity: mj_forward",
    },
    "J*": {
        "spacearm": "Robot.generalized_jacobian(x): FK + base rows of H + closed-form H0⁻¹, end effector",
        "pinocchio": "pin.crba(WORLD) (also fills data.J) + pin.getFrameJacobian(LOCAL_WORLD_ALIGNED) + "
                     "numpy: J_m − J_0 · solve(H0, H0m)",
        "mujoco": "mj_kinematics + mj_comPos + mj_makeM + mj_fullM + mj_jacSite + numpy as for Pinocchio",
    },
    "H*": {
        "spacearm": "Robot.generalized_inertia(x): FK + CRBA + closed-form reduction",
        "pinocchio": "pin.crba(q[, convention]) + numpy: H_m − H0mᵀ · solve(H0, H0m)",
        "mujoco": "mj_kinematics + mj_comPos + mj_makeM + mj_fullM + numpy as for Pinocchio",
    },
}
OPS = list(INCLUDES)


# ---------------------------------------------------------------------------------------------
# models and states
# ---------------------------------------------------------------------------------------------
def random_arm(n: int, seed: int) -> spacearm.Robot:
    """A serial arm of ``n`` revolute joints with random axes, offsets and masses."""
    rng = np.random.default_rng(seed)
    b = spacearm.Robot.builder(f"random{n}", base_mass=400.0, base_inertia=[50.0, 60.0, 70.0])
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


MODELS = {
    "spatial6": spacearm.presets.spatial6,
    "planar4": spacearm.presets.planar4,
    "random12": lambda: random_arm(12, 7),
}


def state(robot):
    """The model's initial configuration with a drifting, tumbling base and every joint moving
    (the same state as the criterion benchmark)."""
    n = robot.n_dof
    k = np.arange(n)
    x = robot.neutral_configuration()
    u = np.concatenate([[0.05, -0.02, 0.01, 0.03, -0.04, 0.02], 0.3 * np.sin(1.0 + k)])
    du = np.concatenate([[0.01, 0.02, -0.01, 0.005, -0.01, 0.02], 0.5 * np.cos(2.0 + k)])
    f = np.concatenate([[1.0, -2.0, 0.5, 0.3, -0.2, 0.1], 2.0 * np.sin(3.0 + k)])
    return x, u, du, f


# ---------------------------------------------------------------------------------------------
# candidates: (op, engine, variant, timed callable, result in spacearm's conventions)
# ---------------------------------------------------------------------------------------------
def spacearm_candidates(robot, x, u, du, f):
    r = robot
    yield "H", "spacearm", "", functools.partial(r.mass_matrix, x), None
    yield "H paper form", "spacearm", "", functools.partial(r.mass_matrix, x, "paper"), None
    yield "c", "spacearm", "", functools.partial(r.bias_forces, x, u), None
    yield "inverse dynamics", "spacearm", "", functools.partial(r.inverse_dynamics, x, u, du), None
    yield "forward dynamics ABA", "spacearm", "", functools.partial(r.forward_dynamics, x, u, f), None
    yield ("forward dynamics H route", "spacearm", "",
           functools.partial(r.forward_dynamics, x, u, f, method="mass_matrix"), None)
    yield ("forward dynamics reduced", "spacearm", "",
           functools.partial(r.forward_dynamics, x, u, f, method="reduced"), None)
    yield "J*", "spacearm", "", functools.partial(r.generalized_jacobian, x), None
    yield "H*", "spacearm", "", functools.partial(r.generalized_inertia, x), None


def reduce_numpy(m):
    """(H0, H0m, Hm) of a full symmetric mass matrix."""
    return m[:6, :6], m[:6, 6:], m[6:, 6:]


def pinocchio_candidates(robot, x, u, du, f):
    model = interop.to_pinocchio(robot)
    data = model.createData()
    q, v = interop.to_pinocchio_state(robot, x, u)
    tau = interop.to_pinocchio_force(robot, x, f)
    a = interop.to_pinocchio_acceleration(robot, x, u, du)
    frame = model.getFrameId(robot.end_effector)
    conventions = {"LOCAL": pin.Convention.LOCAL, "WORLD": pin.Convention.WORLD}

    for name, conv in conventions.items():
        yield ("H", "pinocchio", name, functools.partial(pin.crba, model, data, q, conv),
               lambda conv=conv: interop.mass_matrix_from_pinocchio(robot, x, pin.crba(model, data, q, conv)))
    yield ("c", "pinocchio", "", functools.partial(pin.nonLinearEffects, model, data, q, v),
           lambda: interop.bias_from_pinocchio(robot, x, u, pin.nonLinearEffects(model, data, q, v).copy(),
                                               pin.crba(model, data, q)))
    yield ("inverse dynamics", "pinocchio", "", functools.partial(pin.rnea, model, data, q, v, a),
           lambda: interop.from_pinocchio_force(robot, x, pin.rnea(model, data, q, v, a)))
    for op in ("forward dynamics ABA", "forward dynamics H route", "forward dynamics reduced"):
        for name, conv in conventions.items():
            yield (op, "pinocchio", name, functools.partial(pin.aba, model, data, q, v, tau, conv),
                   lambda conv=conv: interop.acceleration_from_pinocchio(robot, x, u, pin.aba(model, data, q, v, tau, conv)))

    def jstar():
        m = pin.crba(model, data, q, pin.Convention.WORLD)  # fills data.J too
        j = pin.getFrameJacobian(model, data, frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        return j[:, 6:] - j[:, :6] @ np.linalg.solve(m[:6, :6], m[:6, 6:])

    yield "J*", "pinocchio", "WORLD", jstar, jstar

    for name, conv in conventions.items():
        def hstar(conv=conv):
            h0, h0m, hm = reduce_numpy(pin.crba(model, data, q, conv))
            return hm - h0m.T @ np.linalg.solve(h0, h0m)

        yield "H*", "pinocchio", name, hstar, hstar


def mujoco_candidates(robot, x, u, du, f):
    m = interop.to_mujoco(robot)
    # interop enables the energy computation (for tests); time the dynamics alone.
    m.opt.enableflags &= ~int(mujoco.mjtEnableBit.mjENBL_ENERGY)
    d = mujoco.MjData(m)
    qpos, qvel = interop.to_mujoco_state(robot, x, u)
    d.qpos[:] = qpos
    d.qvel[:] = qvel
    d.qfrc_applied[:] = interop.to_mujoco_force(robot, x, f)
    qacc_inverse = interop.to_mujoco_acceleration(robot, x, du)
    d_inv = mujoco.MjData(m)
    d_inv.qpos[:] = qpos
    d_inv.qvel[:] = qvel
    d_inv.qacc[:] = qacc_inverse
    nv = m.nv
    dense = np.zeros((nv, nv))
    bias = np.zeros(nv)
    jacp = np.zeros((3, nv))
    jacr = np.zeros((3, nv))
    site = m.site(robot.end_effector).id

    def full_m():
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        mujoco.mj_makeM(m, d)
        mujoco.mj_fullM(m, d, dense)
        return dense

    def rne():
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        mujoco.mj_comVel(m, d)
        mujoco.mj_rne(m, d, 0, bias)
        return bias

    def forward():
        mujoco.mj_forward(m, d)
        return d.qacc

    def inverse():
        mujoco.mj_inverse(m, d_inv)
        return d_inv.qfrc_inverse

    def jstar():
        full_m()
        mujoco.mj_jacSite(m, d, jacp, jacr, site)
        j = np.vstack([jacp, jacr])
        return j[:, 6:] - j[:, :6] @ np.linalg.solve(dense[:6, :6], dense[:6, 6:])

    def hstar():
        h0, h0m, hm = reduce_numpy(full_m())
        return hm - h0m.T @ np.linalg.solve(h0, h0m)

    yield "H", "mujoco", "", full_m, lambda: interop.mass_matrix_from_mujoco(robot, x, full_m().copy())
    yield "c", "mujoco", "", rne, lambda: interop.bias_from_mujoco(robot, x, rne().copy())
    yield "inverse dynamics", "mujoco", "", inverse, lambda: interop.from_mujoco_force(robot, x, inverse().copy())
    for op in ("forward dynamics ABA", "forward dynamics H route", "forward dynamics reduced"):
        yield op, "mujoco", "", forward, lambda: interop.acceleration_from_mujoco(robot, x, forward().copy())
    yield "J*", "mujoco", "", jstar, jstar
    yield "H*", "mujoco", "", hstar, hstar


# ---------------------------------------------------------------------------------------------
# timing
# ---------------------------------------------------------------------------------------------
def calibrate(fn, target: float) -> int:
    """Calls per batch so that one batch lasts about ``target`` seconds."""
    timer = timeit.Timer(fn)
    n = 1
    while True:
        t = timer.timeit(n)
        if t >= target / 5 or n >= 10_000_000:
            return max(1, int(n * target / max(t, 1e-9)))
        n *= 5


def time_interleaved(fns, repeat: int, target: float):
    """Per-call times (s) of every callable: ``repeat`` rounds, one batch of each per round."""
    timers = [timeit.Timer(fn) for fn in fns]
    numbers = [calibrate(fn, target) for fn in fns]
    samples = [[] for _ in fns]
    for _ in range(repeat):
        for timer, number, out in zip(timers, numbers, samples):
            out.append(timer.timeit(number) / number)
    return samples, numbers


def rel_diff(a, b) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-300))


def run_model(name: str, repeat: int, target: float, engines):
    robot = MODELS[name]()
    x, u, du, f = state(robot)
    reference = {
        "H": lambda: robot.mass_matrix(x),
        "H paper form": lambda: robot.mass_matrix(x),
        "c": lambda: robot.bias_forces(x, u),
        "inverse dynamics": lambda: robot.inverse_dynamics(x, u, du),
        "forward dynamics ABA": lambda: robot.forward_dynamics(x, u, f),
        "forward dynamics H route": lambda: robot.forward_dynamics(x, u, f),
        "forward dynamics reduced": lambda: robot.forward_dynamics(x, u, f),
        "J*": lambda: robot.generalized_jacobian(x),
        "H*": lambda: robot.generalized_inertia(x),
    }
    candidates = list(spacearm_candidates(robot, x, u, du, f))
    if "pinocchio" in engines:
        candidates += list(pinocchio_candidates(robot, x, u, du, f))
    if "mujoco" in engines:
        candidates += list(mujoco_candidates(robot, x, u, du, f))

    rows = []
    for op, engine, variant, fn, result in candidates:
        # spacearm's own routes are checked against the ABA / CRBA results they must equal.
        value = fn() if result is None else result()
        rows.append({"model": name, "n_dof": robot.n_dof, "op": op, "engine": engine, "variant": variant,
                     "includes": INCLUDES[op].get(engine, ""), "check": rel_diff(value, reference[op]())})

    samples, numbers = time_interleaved([c[3] for c in candidates], repeat, target)
    for row, s, number in zip(rows, samples, numbers):
        q1, med, q3 = np.percentile(s, [25, 50, 75])
        row.update(median_s=float(med), q1_s=float(q1), q3_s=float(q3), calls_per_batch=number, batches=repeat)
    return robot, rows


# ---------------------------------------------------------------------------------------------
# report
# ---------------------------------------------------------------------------------------------
def best(rows, op, engine):
    """The fastest variant of ``engine`` for ``op`` (Pinocchio: LOCAL or WORLD convention)."""
    cands = [r for r in rows if r["op"] == op and r["engine"] == engine]
    return min(cands, key=lambda r: r["median_s"]) if cands else None


def fmt_us(row) -> str:
    if row is None:
        return "—"
    tag = {"LOCAL": " L", "WORLD": " W"}.get(row["variant"], "")
    return f"{row['median_s'] * 1e6:7.2f}{tag:2s}"


def print_table(robot, rows, engines, out=sys.stdout):
    p = functools.partial(print, file=out)
    p(f"\n{robot.name}: N = {robot.n_dof} joints, 6+N = {robot.nu} (per-call median, µs; ratio = spacearm / peer)")
    head = f"{'operation':26s} {'spacearm':>10s}"
    for e in engines[1:]:
        head += f" {e:>11s} {'ratio':>6s}"
    head += f" {'check':>8s}"
    p(head)
    p("-" * len(head))
    for op in OPS:
        s = best(rows, op, "spacearm")
        line = f"{op:26s} {fmt_us(s):>10s}"
        worst_check = max(r["check"] for r in rows if r["op"] == op)
        for e in engines[1:]:
            peer = best(rows, op, e)
            ratio = "—" if peer is None else f"{s['median_s'] / peer['median_s']:.2f}"
            line += f" {fmt_us(peer):>11s} {ratio:>6s}"
        line += f" {worst_check:8.1e}"
        p(line)


def print_notes(engines, out=sys.stdout):
    p = functools.partial(print, file=out)
    p("\nWhat each call includes (every call starts from the configuration, i.e. runs forward kinematics):")
    for op in OPS:
        p(f"  {op}")
        for e in engines:
            if e in INCLUDES[op]:
                p(f"    {e:10s} {INCLUDES[op][e]}")
    p("  L / W: Pinocchio's LOCAL / WORLD convention, whichever was faster (both are in the JSON).")
    p("  check: max relative difference of the peer's result, mapped to spacearm's conventions by")
    p("  spacearm.interop, from spacearm's (for spacearm's own routes: from its ABA / CRBA results).")


def meta(args, engines, overhead_s):
    return {
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "command": " ".join([os.path.basename(sys.executable)] + sys.argv),
        "python": platform.python_version(),
        "platform": platform.platform(),
        "machine": platform.machine(),
        "cpu_count": os.cpu_count(),
        "numpy": np.__version__,
        "spacearm": getattr(spacearm, "__version__", "dev"),
        "pinocchio": pin.__version__ if "pinocchio" in engines else None,
        "mujoco": mujoco.__version__ if "mujoco" in engines else None,
        "repeat": args.repeat,
        "batch_seconds": args.batch,
        "harness_overhead_s": overhead_s,
        "blas_threads": os.environ.get("OPENBLAS_NUM_THREADS"),
        # Other work on the machine inflates every figure; ratios suffer less (interleaving).
        "load_average_1_5_15min": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--models", default="spatial6,planar4,random12",
                    help=f"comma-separated, from {', '.join(MODELS)} (default: all)")
    ap.add_argument("--repeat", type=int, default=15, help="interleaved rounds (batches per candidate), default 15")
    ap.add_argument("--batch", type=float, default=0.02, help="seconds per batch, default 0.02")
    ap.add_argument("--quick", action="store_true", help="5 rounds of 5 ms batches (a rough look)")
    ap.add_argument("--json", metavar="PATH", help="also write every measurement and its context here")
    args = ap.parse_args(argv)
    if args.quick:
        args.repeat, args.batch = 5, 0.005
    names = [m.strip() for m in args.models.split(",") if m.strip()]
    unknown = [m for m in names if m not in MODELS]
    if unknown:
        ap.error(f"unknown model(s) {unknown}; choose from {list(MODELS)}")
    engines = [e for e in ENGINES if e == "spacearm" or (e == "pinocchio" and pin) or (e == "mujoco" and mujoco)]
    for e in ENGINES:
        if e not in engines:
            print(f"note: {e} is not installed; its columns are left out", file=sys.stderr)

    # Cost of the timing harness itself (calling an empty function), included in every figure.
    empty = functools.partial(int)
    overhead = float(np.median(time_interleaved([empty], args.repeat, args.batch)[0][0]))

    all_rows = []
    for name in names:
        robot, rows = run_model(name, args.repeat, args.batch, engines)
        print_table(robot, rows, engines)
        all_rows += rows
    print_notes(engines)
    print(f"\nHarness overhead (an empty call), included in every figure: {overhead * 1e9:.0f} ns. "
          f"{args.repeat} rounds of {args.batch * 1e3:.0f} ms batches per candidate.")
    if hasattr(os, "getloadavg"):
        print(f"Load average at the end (1 min): {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs "
              "(other work inflates absolute figures; compare ratios).")
    bad = [r for r in all_rows if r["check"] > 1e-9]
    if bad:
        print("\nWARNING: results differ (check > 1e-9):", file=sys.stderr)
        for r in bad:
            print(f"  {r['model']} {r['op']} {r['engine']} {r['variant']}: {r['check']:.1e}", file=sys.stderr)
    if args.json:
        with open(args.json + ".tmp", "w") as fh:
            json.dump({"meta": meta(args, engines, overhead), "results": all_rows}, fh, indent=1)
        os.replace(args.json + ".tmp", args.json)
        print(f"wrote {args.json}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
