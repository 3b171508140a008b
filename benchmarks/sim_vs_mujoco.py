#!/usr/bin/env python
"""Time a whole simulation: spacearm.simulate against MuJoCo's RK4, same model, one run.

spatial6 (the paper's case study 2), 10 s at 1 kHz with RK4 (10,000 steps, 40,000 dynamics
evaluations), base free-floating, zero gravity. Each figure is the wall time of one complete
run from Python, the median of ``--repeat`` runs (runs of the candidates interleaved, so a slow
phase of the machine hits all alike). Ratio = spacearm / MuJoCo: below 1, spacearm is faster.

Rows (what each side does is printed with the table):

1. ``PD to a set point`` — both loops native, no Python per step. spacearm: ``simulate`` with
   ``control.JointPD`` (constant reference; per-joint gains 4 rad/s on the diagonal of H*) evaluated in Rust at every RK4 stage, recording
   every step (state, accelerations, torques, momenta, energy, CM, end-effector pose).
   MuJoCo: ``mujoco.rollout`` (C++ loop of ``mj_step``) of the exported model with a
   ``<position kp kv>`` actuator per joint (the same PD law, evaluated at every RK4 stage),
   recording the state every step.
2. ``computed torque`` — spacearm: ``control.ComputedTorque`` on the reduced EOM (paper eqs.
   112–115), a quintic joint maneuver, all in Rust at every stage. MuJoCo has no such
   controller; the fastest fair way from Python is computed in the loop: (a) once per step,
   held over the step (``qfrc_applied`` before ``mj_step``: 10,000 Python evaluations), and
   (b) at every RK4 stage like spacearm (``mjcb_control``: 40,000 Python evaluations). Both use
   ``mj_fullM`` and ``qfrc_bias`` for ``H*`` and ``c*`` (which do not depend on the base
   velocity coordinates) and numpy solves.

Before timing, the final states are compared (``check``: max |Δx|, |Δu| after mapping MuJoCo's
state with ``spacearm.interop``): row 1 and row 2(b) integrate the same ODE with the same step,
so they agree to the integrators' truncation difference; 2(a) holds the torque over each step,
a different (sampled-data) law, so it differs at the 1e-4 level.

    python benchmarks/sim_vs_mujoco.py              # 5 repeats
    python benchmarks/sim_vs_mujoco.py --repeat 9 --duration 10
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import time  # noqa: E402
import xml.etree.ElementTree as ET  # noqa: E402

import numpy as np  # noqa: E402

import spacearm  # noqa: E402
from spacearm import control, interop  # noqa: E402

try:
    import mujoco
    from mujoco import rollout as mj_rollout
except ImportError:  # pragma: no cover - the peer is optional
    mujoco = None

KP_CT, KD_CT = 25.0, 10.0  # 1/s^2, 1/s


def mujoco_pd_model(robot, dt, kp, kd):
    """The exported MJCF plus a position actuator per joint: ``τ = kp (ctrl − q) − kv q̇``."""
    root = ET.fromstring(interop.to_mjcf(robot))
    act = ET.SubElement(root, "actuator")
    for link in robot.describe()["links"]:
        if link["type"] != "fixed":
            j = int(link["dof"])
            ET.SubElement(act, "position", joint=link["joint"], kp=repr(float(kp[j])), kv=repr(float(kd[j])))
    model = mujoco.MjModel.from_xml_string(ET.tostring(root, encoding="unicode"))
    model.opt.timestep = dt
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    return model


def reduced_terms(model, data, n, make_m=False):
    """``H*`` and ``c*`` from MuJoCo's ``M`` and ``qfrc_bias`` at the current state.
    ``make_m``: build ``M`` first (``mj_makeM``) — inside the control callback, which MuJoCo
    calls after the velocity stage but before the acceleration stage that builds ``M``."""
    if make_m:
        mujoco.mj_makeM(model, data)
    m = np.empty((model.nv, model.nv))
    mujoco.mj_fullM(model, data, m)
    m00, m0m, mmm = m[:6, :6], m[:6, 6:], m[6:, 6:]
    c = data.qfrc_bias
    x = np.linalg.solve(m00, np.column_stack([m0m, c[:6]]))
    return mmm - m0m.T @ x[:, :n], c[6:] - m0m.T @ x[:, n]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per candidate (median; default 5)")
    parser.add_argument("--duration", type=float, default=10.0, help="simulated seconds (default 10)")
    parser.add_argument("--dt", type=float, default=1e-3, help="RK4 step (default 1 ms)")
    args = parser.parse_args()
    if mujoco is None:
        raise SystemExit("MuJoCo is not installed: pip install mujoco")

    robot = spacearm.presets.spatial6()
    n = robot.n_dof
    x0 = robot.neutral_configuration()
    u0 = np.zeros(robot.nu)
    q_goal = robot.initial_q + np.array([0.6, -0.4, 0.5, 0.8, -0.6, 0.5])
    steps = int(round(args.duration / args.dt))
    order = interop.engine_dof_order(robot)
    assert np.array_equal(order, np.arange(n))  # serial chain: engine order = spacearm order

    # ---- row 1: PD to a set point ---------------------------------------------------------
    # Per-joint gains: 4 rad/s, critically damped, on the diagonal of H* (control.inertia_scaled_gains).
    from spacearm.control import inertia_scaled_gains

    kp_pd, kd_pd = inertia_scaled_gains(robot, x0, list(range(n)))
    pd = control.JointPD(kp=kp_pd, kd=kd_pd, reference=q_goal)

    def sa_pd():
        return spacearm.simulate(robot, args.duration, x0=x0, u0=u0, dt=args.dt, controller=pd)

    mj_pd_model = mujoco_pd_model(robot, args.dt, kp_pd, kd_pd)
    mj_pd_data = mujoco.MjData(mj_pd_model)
    qpos0, qvel0 = interop.to_mujoco_state(robot, x0, u0)
    mj_pd_data.qpos[:], mj_pd_data.qvel[:] = qpos0, qvel0
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.empty(mujoco.mj_stateSize(mj_pd_model, spec))
    mujoco.mj_getState(mj_pd_model, mj_pd_data, state0, spec)
    ctrl = np.tile(q_goal[order], (steps, 1))

    def mj_pd():
        state, _ = mj_rollout.rollout(mj_pd_model, mj_pd_data, state0, ctrl, nstep=steps)
        return state

    # ---- row 2: computed torque -----------------------------------------------------------
    ref = control.QuinticJoint(robot.initial_q, q_goal, 0.0, 0.8 * args.duration)
    ct = control.ComputedTorque(kp=KP_CT, kd=KD_CT, reference=ref)

    def sa_ct():
        return spacearm.simulate(robot, args.duration, x0=x0, u0=u0, dt=args.dt, controller=ct)

    mj_model = interop.to_mujoco(robot)
    mj_model.opt.timestep = args.dt
    mj_model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    mj_data = mujoco.MjData(mj_model)

    def ct_torque(d, make_m=False):
        q_ref, qd_ref, qdd_ref = ref.evaluate(d.time)
        hs, cs = reduced_terms(mj_model, d, n, make_m)
        return hs @ (qdd_ref + KD_CT * (qd_ref - d.qvel[6:]) + KP_CT * (q_ref - d.qpos[7:])) + cs

    def mj_reset():
        mujoco.mj_resetData(mj_model, mj_data)
        mj_data.qpos[:], mj_data.qvel[:] = qpos0, qvel0

    def mj_ct_step():
        mj_reset()
        for _ in range(steps):
            mujoco.mj_forward(mj_model, mj_data)  # M, qfrc_bias at the step's start
            mj_data.qfrc_applied[6:] = ct_torque(mj_data)
            mujoco.mj_step(mj_model, mj_data)
        return mj_data.qpos.copy(), mj_data.qvel.copy()

    def stage_control(m, d):
        # Called by mj_forwardSkip at every RK4 stage after the velocity stage: qfrc_bias is
        # that of the stage's state; M is built here (mj_makeM) from the stage's kinematics.
        d.qfrc_applied[6:] = ct_torque(d, make_m=True)

    def mj_ct_stage():
        mj_reset()
        mujoco.set_mjcb_control(stage_control)
        try:
            for _ in range(steps):
                mujoco.mj_step(mj_model, mj_data)
        finally:
            mujoco.set_mjcb_control(None)
        return mj_data.qpos.copy(), mj_data.qvel.copy()

    # ---- checks ---------------------------------------------------------------------------
    def diff(traj, qpos, qvel):
        x, u = interop.from_mujoco_state(robot, qpos, qvel)
        return float(np.max(np.abs(traj.x[-1] - x))), float(np.max(np.abs(traj.u[-1] - u)))

    nq = mj_pd_model.nq
    st = mj_pd()[0, -1]
    check_pd = diff(sa_pd(), st[1:1 + nq], st[1 + nq:1 + nq + mj_pd_model.nv])
    traj_ct = sa_ct()
    check_step = diff(traj_ct, *mj_ct_step())
    check_stage = diff(traj_ct, *mj_ct_stage())

    # ---- timing ---------------------------------------------------------------------------
    candidates = {"sa_pd": sa_pd, "mj_pd": mj_pd, "sa_ct": sa_ct, "mj_ct_step": mj_ct_step, "mj_ct_stage": mj_ct_stage}
    times = {k: [] for k in candidates}
    for _ in range(args.repeat):
        for k, f in candidates.items():
            t0 = time.perf_counter()
            f()
            times[k].append(time.perf_counter() - t0)
    med = {k: float(np.median(v)) for k, v in times.items()}

    print(f"spatial6, {args.duration:g} s at dt = {args.dt:g} s RK4 ({steps} steps), median of {args.repeat} runs "
          f"(ratio = spacearm / MuJoCo)")
    load = ", ".join(f"{v:.2f}" for v in os.getloadavg()) if hasattr(os, "getloadavg") else "n/a"
    print(f"spacearm {spacearm.__version__}, mujoco {mujoco.__version__}, numpy {np.__version__}, "
          f"Python {platform.python_version()}, {platform.machine()}, {os.cpu_count()} CPUs, load average {load}")
    print(f"{'run':<44}{'spacearm s':>12}{'MuJoCo s':>12}{'ratio':>8}   check max|dx|, max|du| (final state)")
    rows = (("1  PD to a set point (both native)", "sa_pd", "mj_pd", check_pd),
            ("2a computed torque (MuJoCo: Python per step)", "sa_ct", "mj_ct_step", check_step),
            ("2b computed torque (MuJoCo: Python per stage)", "sa_ct", "mj_ct_stage", check_stage))
    for label, a, b, (dx, du) in rows:
        print(f"{label:<44}{med[a]:>12.4f}{med[b]:>12.4f}{med[a] / med[b]:>8.3f}   {dx:.1e}, {du:.1e}")
    print()
    print("spacearm: Rust loop, controller at every RK4 stage, records every step (state, du, tau, momenta, energy,")
    print("          CM, end-effector pose); 1: JointPD; 2: ComputedTorque on H*, c* (eqs. 112-115).")
    print("MuJoCo:   1: mujoco.rollout (C++ mj_step loop), position actuators kp/kv, state recorded every step;")
    print("          2a: Python loop mj_forward + numpy CT + mj_step, torque held over each step;")
    print("          2b: Python loop of mj_step, CT in mjcb_control at every RK4 stage (the same law as spacearm).")


if __name__ == "__main__":
    main()
