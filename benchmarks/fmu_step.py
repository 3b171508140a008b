#!/usr/bin/env python
"""The FMU against spacearm.simulate (docs/fmi.md): how closely an FMU run matches, and what
one RK4 step costs through each.

Match: ``fmpy.simulate_fmu`` of the FMU of spatial6 (floating, constant torques, a moving start)
and of the UR5 of example-robot-data on the example bus ``spacearm.examples.path("spacecraft_bus")`` (flying, torques
and a base wrench) against ``spacearm.simulate`` of the same model and inputs (the inputs held by
a ``control.Callback``), FMI 3 and FMI 2: the largest difference of the state over the run.

Cost per RK4 step, spatial6, interleaved rounds, medians and ratios:

- ``fmu doStep (FMPy)``: one ``fmi3DoStep`` of one RK4 step called through FMPy's ctypes wrapper,
  with the ``fmi3SetFloat64`` of the six torques and the ``fmi3GetFloat64`` of every output that
  a co-simulation master makes at each communication point;
- ``fmu doStep x100 (FMPy)``: a communication step of 100 RK4 steps (the per-call cost spread);
- ``simulate``: ``spacearm.simulate`` of ``--steps`` steps with no controller, divided by the steps;
- ``Simulator.step``: ``spacearm.Simulator.step(tau)``, one step per call.

    python benchmarks/fmu_step.py             # needs fmpy, the C library (scripts/c-tests.sh) and example-robot-data
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

import spacearm
import spacearm.fmi
from spacearm.control import Callback

ROOT = Path(__file__).resolve().parent.parent
DT = 2e-3


def columns(result, group, n):
    return np.column_stack([result[f"{group}[{k}]"] for k in range(1, n + 1)])


def match(robot, path, duration, tau, wrench=None, x0=None, u0=None, mode="floating"):
    import fmpy

    names = [f"tau[{k}]" for k in range(1, robot.n_dof + 1)] + ([f"base_wrench[{k}]" for k in range(1, 7)] if wrench is not None else [])
    values = list(tau) + (list(wrench) if wrench is not None else [])
    signal = np.array([(0.0, *values), (duration, *values)], dtype=[("time", float)] + [(n, float) for n in names])
    x0 = robot.neutral_configuration() if x0 is None else x0
    u0 = robot.zero_velocity() if u0 is None else u0
    start = {**{f"x0[{k + 1}]": v for k, v in enumerate(x0)}, **{f"u0[{k + 1}]": v for k, v in enumerate(u0)}}
    res = fmpy.simulate_fmu(str(path), stop_time=duration, step_size=DT, output_interval=DT, input=signal, start_values=start,
                            fmi_type="CoSimulation")
    law = (lambda t, x, u: (tau, wrench)) if wrench is not None else (lambda t, x, u: tau)
    traj = spacearm.simulate(robot, duration, dt=DT, x0=x0, u0=u0, mode=mode, controller=Callback(law))
    n = robot.n_dof
    fx = np.hstack([columns(res, "r0", 3), columns(res, "quat0", 4), columns(res, "q", n)])
    fu = np.hstack([columns(res, "v0", 3), columns(res, "w0", 3), columns(res, "qd", n)])
    return np.abs(fx - traj.x).max(), np.abs(fu - traj.u).max(), len(traj.t)


def step_costs(robot, directory, rounds, steps):
    from fmpy import extract, read_model_description
    from fmpy.fmi3 import FMU3Slave

    path = spacearm.fmi.export(robot, directory / "cost.fmu", dt=DT, fmi_version=3)
    md = read_model_description(str(path))
    unzipped = extract(str(path))
    fmu = FMU3Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier, instanceName="cost")
    vr = {v.name: v.valueReference for v in md.modelVariables}
    tau_vr = [vr[f"tau[{k}]"] for k in range(1, robot.n_dof + 1)]
    out_vr = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    tau = np.linspace(-1.0, 1.0, robot.n_dof) * 0.1
    fmu.instantiate()
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    sim = spacearm.Simulator(robot, dt=DT)
    sim.reset()
    state = {"t": 0.0}

    def fmu_step(k):
        t0 = time.perf_counter()
        for _ in range(k):
            fmu.setFloat64(tau_vr, list(tau))
            fmu.doStep(state["t"], DT)
            state["t"] += DT
            fmu.getFloat64(out_vr)
        return (time.perf_counter() - t0) / k

    def fmu_block():
        t0 = time.perf_counter()
        fmu.setFloat64(tau_vr, list(tau))
        fmu.doStep(state["t"], 100 * DT)
        state["t"] += 100 * DT
        fmu.getFloat64(out_vr)
        return (time.perf_counter() - t0) / 100

    def simulate():
        t0 = time.perf_counter()
        spacearm.simulate(robot, steps * DT, dt=DT)
        return (time.perf_counter() - t0) / steps

    def simulator_step(k):
        t0 = time.perf_counter()
        for _ in range(k):
            sim.step(tau)
        return (time.perf_counter() - t0) / k

    rows = {"fmu doStep (FMPy)": [], "fmu doStep x100 (FMPy)": [], "simulate": [], "Simulator.step": []}
    for _ in range(rounds):
        rows["fmu doStep (FMPy)"].append(fmu_step(200))
        rows["fmu doStep x100 (FMPy)"].append(fmu_block())
        rows["simulate"].append(simulate())
        rows["Simulator.step"].append(simulator_step(200))
    fmu.terminate()
    fmu.freeInstance()
    return {k: statistics.median(v) for k, v in rows.items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--steps", type=int, default=2000, help="steps of each spacearm.simulate run")
    args = parser.parse_args()
    s6 = spacearm.presets.spatial6()
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        print("match, fmpy.simulate_fmu vs spacearm.simulate (largest difference over the run):")
        cases = [("spatial6, floating", s6, dict(duration=1.0, tau=[2.0, -1.5, 1.0, 0.5, -0.3, 0.2],
                                                  u0=np.concatenate([[0.01, -0.02, 0, 0.01, 0.02, -0.01], np.full(6, 0.05)])))]
        try:
            from spacearm.io.urdf import load_urdf
            from importlib import metadata

            urdf = Path(str(metadata.distribution("example-robot-data").locate_file(
                "cmeel.prefix/share/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf")))
            ur5 = load_urdf(str(urdf), mount_on=spacearm.io.load_toml(spacearm.examples.path("spacecraft_bus")), at=(0.6, 0, 0, 0, 0, 0))
            x0 = ur5.neutral_configuration()
            x0[7:] = [-0.4, -1.1, 1.3, -0.7, 0.5, 0.3]
            cases.append(("UR5 on the bus, flying", ur5, dict(duration=1.0, tau=[1.0, -2.0, 1.5, 0.4, -0.2, 0.1],
                                                               wrench=[5.0, -3.0, 2.0, 0.5, -0.4, 0.3], x0=x0, mode="flying")))
        except Exception as exc:  # noqa: BLE001 - a missing optional package only loses its row
            print(f"  (UR5 row skipped: {exc})")
        for label, robot, kw in cases:
            for version in (3, 2):
                path = spacearm.fmi.export(robot, d / f"m{version}.fmu", dt=DT, fmi_version=version, mode=kw.get("mode", "floating"))
                dx, du, samples = match(robot, path, **kw)
                print(f"  {label:24s} FMI {version}: max |x diff| {dx:.2e}, max |u diff| {du:.2e} over {samples} samples "
                      f"({kw['duration']:g} s, RK4 {DT:g} s)")
        costs = step_costs(s6, d, args.rounds, args.steps)
    print(f"\ncost per RK4 step, spatial6 ({args.rounds} interleaved rounds, medians):")
    base = costs["simulate"]
    for name, v in costs.items():
        print(f"  {name:24s} {v * 1e6:8.2f} µs   {v / base:6.2f} x simulate")


if __name__ == "__main__":
    main()
