"""Per-call cost of spacearm's Basilisk modules (spacearm.basilisk), against the scene's own step.

    PYTHONPATH=python python3 benchmarks/basilisk_module_cost.py

Interleaved repeats, medians: one ControllerModule.UpdateState (computed torque on spatial6: state
read, the core's law, 12 messages written), one GravityGradientModule.UpdateState (the core's tidal
torques, 7 messages), and one RK4 step of the MJScene alone (4 MuJoCo evaluations).
"""

from __future__ import annotations

import time

import numpy as np
from Basilisk.simulation import svIntegrators
from Basilisk.utilities import SimulationBaseClass, macros

import spacearm
from spacearm import basilisk as sb
from spacearm import control


def main(repeats: int = 7, calls: int = 400) -> None:
    robot = spacearm.presets.spatial6()
    scene, acts = sb.to_mjscene(robot)
    sim = SimulationBaseClass.SimBaseClass()
    sim.CreateNewProcess("p").addTask(sim.CreateNewTask("dynamics", macros.sec2nano(0.01)))
    sim.AddModelToTask("dynamics", scene)
    scene.setIntegrator(svIntegrators.svIntegratorRK4(scene))
    x0 = np.asarray(robot.neutral_configuration(), float)
    law = control.ComputedTorque(kp=16.0, kd=8.0, reference=control.QuinticJoint(x0[7:], x0[7:] + 0.4, 0.0, 2.0))
    module = sb.ControllerModule(robot, law, scene, acts)
    gradient = sb.GravityGradientModule(robot, scene, acts)
    # the scene stepped alone: another scene of the same robot, no module driving it
    plain, _ = sb.to_mjscene(robot)
    sim.AddModelToTask("dynamics", plain)
    plain.setIntegrator(svIntegrators.svIntegratorRK4(plain))
    sim.InitializeSimulation()
    sb.state_to_scene(robot, plain, x0, np.r_[np.zeros(6), np.full(robot.n_dof, 0.1)])
    x = x0.copy()
    x[:3] = [6878e3, 0.0, 0.0]
    sb.state_to_scene(robot, scene, x, np.zeros(robot.nu))
    module.Reset(0)
    stop = [0]

    def controller():
        module.UpdateState(10_000_000)

    def gravity():
        gradient.UpdateState(10_000_000)


    def scene_step():  # one RK4 step of the plain scene, called as Basilisk's task would
        stop[0] += 10_000_000
        plain.UpdateState(stop[0])

    results = {f.__name__: [] for f in (controller, gravity, scene_step)}
    for _ in range(repeats):
        for f in (controller, gravity, scene_step):
            t0 = time.perf_counter()
            for _ in range(calls):
                f()
            results[f.__name__].append((time.perf_counter() - t0) / calls)
    med = {k: float(np.median(v)) for k, v in results.items()}
    for k, v in med.items():
        print(f"{k:>11}: {v * 1e6:8.1f} µs per call ({v / med['scene_step']:.2f}× one scene RK4 step)")


if __name__ == "__main__":
    main()
