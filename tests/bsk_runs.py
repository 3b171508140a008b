"""Basilisk runs shared by tests/basilisk (one place for the simulation boilerplate)."""

from __future__ import annotations

import numpy as np

from spacearm import basilisk as sb


def scene_run(robot, x0, u0, dt, duration, *, torques=None, controller=None, fsw_dt=None, modules=(), setup=None,
              **scene_options):
    """Run ``robot``'s MJScene from ``(x0, u0)`` for ``duration`` s with Basilisk's RK4 at ``dt``;
    ``torques``: constant joint torques (N) on the actuated joints; ``controller``: a
    spacearm.control law as a ControllerModule in a flight-software task of period ``fsw_dt``
    (it runs after the scene at each of its ticks); ``setup(scene, actuators)`` returns models
    for the scene's dynamics task. Returns ``(x, u, scene, actuators, extras)``."""
    from Basilisk.architecture import messaging
    from Basilisk.simulation import svIntegrators
    from Basilisk.utilities import SimulationBaseClass, macros

    scene, acts = sb.to_mjscene(robot, **scene_options)
    sim = SimulationBaseClass.SimBaseClass()
    proc = sim.CreateNewProcess("spacearm")
    proc.addTask(sim.CreateNewTask("dynamics", macros.sec2nano(dt)), 100)
    sim.AddModelToTask("dynamics", scene)
    scene.setIntegrator(svIntegrators.svIntegratorRK4(scene))
    keep = []
    if torques is not None:
        for dof, name in acts.joints:
            msg = messaging.SingleActuatorMsg()
            msg.write(messaging.SingleActuatorMsgPayload(input=float(torques[dof])))
            scene.getSingleActuator(name).actuatorInMsg.subscribeTo(msg)
            keep.append(msg)
    extras = {}
    if setup is not None:
        extras = setup(scene, acts)
        for model in extras.get("dynamics", ()):
            scene.AddModelToDynamicsTask(model)
    module = None
    if controller is not None:
        proc.addTask(sim.CreateNewTask("fsw", macros.sec2nano(fsw_dt)), 50)
        module = sb.ControllerModule(robot, controller, scene, acts)
        sim.AddModelToTask("fsw", module)
        extras["controller"] = module
    sim.InitializeSimulation()
    sb.state_to_scene(robot, scene, x0, u0)
    if module is not None:
        module.Reset(0)
    sim.ConfigureStopTime(macros.sec2nano(duration))
    sim.ExecuteSimulation()
    x, u = sb.state_from_scene(robot, scene)
    extras["keep"] = keep
    return x, u, scene, acts, extras


def held_run(robot, controller, x0, u0, dt, hold_steps, samples, mode="floating"):
    """spacearm's own sample-and-hold run: the law evaluated by the core (``Simulator.command``)
    at ``t_k = k·hold_steps·dt``, held over ``hold_steps`` RK4 steps of spacearm's integrator."""
    import spacearm

    law = spacearm.Simulator(robot, controller=controller, mode=mode)
    law.reset(x0, u0)
    plant = spacearm.Simulator(robot, dt=dt, mode=mode)
    plant.reset(x0, u0)
    for k in range(samples):
        tau, wrench = law.command(k * hold_steps * dt, plant.x, plant.u)
        plant.step(tau, n=hold_steps, base_wrench=wrench)
    return plant.x, plant.u


def tumbling_start(robot):
    """The neutral configuration with the base tumbling slowly, everything else at rest."""
    x0 = np.asarray(robot.neutral_configuration(), float)
    u0 = np.zeros(robot.nu)
    u0[3:6] = [0.01, -0.02, 0.03]
    return x0, u0


def rel(a, b) -> float:
    """``‖a − b‖∞ / ‖b‖∞``."""
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b))) / np.max(np.abs(b)))
