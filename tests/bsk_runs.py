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


def vscmg_run(robot, x0, u0, tau, dt, duration):
    """The hub and CMG cluster of ``robot`` (CMGs on the base only, no other links) as Basilisk's
    rigid hub (``spacecraft.Spacecraft``) carrying its ``vscmgStateEffector`` (the balanced-wheel
    model, ``VSCMGModel = 0``), run from ``(x0, u0)`` for ``duration`` s with constant joint torques
    ``tau`` (spacearm's dof order) by Basilisk's RK4 at ``dt``. The one conversion of conventions
    (docs/cmg.md, "Against Basilisk's VSCMG"):

    - the hub: ``mHub`` the base mass, ``IHubPntBc_B`` the base inertia, ``r_BcB_B = 0`` (spacearm's
      base frame is at the base CM, so Basilisk's point B is it); the initial ``r_CN_N``, ``v_CN_N``
      are the system CM's position and velocity (Basilisk starts from the system CM), ``σ_BN`` the
      MRP of ``[BN] = R0ᵀ`` and ``ω_BN_B = R0ᵀ ω0`` (spacearm's ``ω0`` is in 𝒥);
    - each CMG: ``ggHat_B`` the gimbal axis, ``gsHat0_B`` the spin axis at ``δ = 0``,
      ``gtHat0_B = ĝ × ŝ0`` (Basilisk turns ``ŝ = cos γ ŝ0 + sin γ t̂0``, so ``γ = δ``);
      ``IG1, IG2, IG3`` the gimbal's moments along ``(ŝ0, t̂0, ĝ)`` and ``IW1, IW2, IW3`` the
      rotor's (``IW1 = J_s``, ``IW2 = IW3 = J_t``); ``massG``, ``massW`` at ``rGB_B``, the gimbal
      joint (both CMs are there in spacearm's model);
    - the states: ``γ = δ``, ``γ̇ = δ̇``, and Basilisk's wheel speed ``Ω`` is the rotor's rate
      relative to its gimbal (``ω_W = ω_G + Ω ŝ``), spacearm's spin-joint rate as it is;
      ``u_g``, ``u_s`` the gimbal and spin joint torques.

    Every limit and friction of the effector is switched off. Returns spacearm's ``(x, u)`` at the
    end."""
    from Basilisk.architecture import messaging
    from Basilisk.simulation import spacecraft, vscmgStateEffector
    from Basilisk.utilities import RigidBodyKinematics as rbk
    from Basilisk.utilities import SimulationBaseClass, macros
    from scipy.spatial.transform import Rotation

    col = (lambda v: [[float(a)] for a in v])
    desc, cmgs = robot.description, robot.cmg_dofs
    assert robot.n_dof == 2 * len(cmgs), "Basilisk's VSCMG effector carries CMGs on a rigid hub: no other links"
    x0, u0, tau = (np.asarray(v, float) for v in (x0, u0, tau))
    eff = vscmgStateEffector.VSCMGStateEffector()
    for name, c in cmgs.items():
        gl, rl = desc.link(name), desc.link(name + "_rotor")
        assert gl.parent == "base" and not np.any(gl.com) and not np.any(rl.com) and not np.any(rl.origin)
        r_g = Rotation.from_quat(gl.rotation).as_matrix()  # gimbal frame in the base frame at δ = 0
        r_r = r_g @ Rotation.from_quat(rl.rotation).as_matrix()
        g, s = r_g @ gl.axis, r_r @ rl.axis
        t = np.cross(g, s)
        frame = np.column_stack([s, t, g])
        i_g, i_w = frame.T @ r_g @ gl.inertia @ r_g.T @ frame, frame.T @ r_r @ rl.inertia @ r_r.T @ frame
        # The balanced-wheel model takes principal moments along (ŝ, t̂, ĝ).
        assert np.abs(i_g - np.diag(np.diag(i_g))).max() < 1e-14 and np.abs(i_w - np.diag(np.diag(i_w))).max() < 1e-14
        v = messaging.VSCMGConfigMsgPayload()
        v.VSCMGModel = 0  # vscmgBalancedWheels
        v.rGB_B, v.gsHat0_B, v.gtHat0_B, v.ggHat_B = col(gl.origin), col(s), col(t), col(g)
        v.IG1, v.IG2, v.IG3 = (float(a) for a in np.diag(i_g))
        v.IW1, v.IW2, v.IW3 = (float(a) for a in np.diag(i_w))
        v.massG, v.massW = float(gl.mass), float(rl.mass)
        v.u_s_max = v.u_s_min = v.u_g_max = v.u_g_min = -1.0  # no torque limits
        v.u_s_f = v.u_g_f = 0.0  # no friction
        v.wheelLinearFrictionRatio = v.gimbalLinearFrictionRatio = v.gammaDot_max = -1.0
        v.Omega_max = 1e12  # the effector zeroes the wheel torque at |Ω| >= Omega_max
        v.gamma, v.gammaDot, v.Omega = float(x0[7 + c["gimbal"]]), float(u0[6 + c["gimbal"]]), float(u0[6 + c["rotor"]])
        eff.AddVSCMG(v)
    sc = spacecraft.Spacecraft()
    sc.addStateEffector(eff)
    sc.hub.mHub = float(desc.base.mass)
    sc.hub.r_BcB_B = col(np.zeros(3))
    sc.hub.IHubPntBc_B = np.asarray(desc.base.inertia, float).tolist()
    r0 = Rotation.from_quat(x0[3:7]).as_matrix()
    sc.hub.sigma_BNInit = col(rbk.C2MRP(r0.T))
    sc.hub.omega_BN_BInit = col(r0.T @ u0[3:6])
    sc.hub.r_CN_NInit = col(robot.center_of_mass(x0))
    sc.hub.v_CN_NInit = col(np.asarray(robot.momentum(x0, u0).P) / robot.total_mass)
    cmd = messaging.VSCMGArrayTorqueMsgPayload()
    cmd.gimbalTorque = [float(tau[c["gimbal"]]) for c in cmgs.values()]
    cmd.wheelTorque = [float(tau[c["rotor"]]) for c in cmgs.values()]
    msg = messaging.VSCMGArrayTorqueMsg().write(cmd)
    eff.cmdsInMsg.subscribeTo(msg)
    sim = SimulationBaseClass.SimBaseClass()
    sim.CreateNewProcess("hub").addTask(sim.CreateNewTask("dynamics", macros.sec2nano(dt)))
    sim.AddModelToTask("dynamics", eff)
    sim.AddModelToTask("dynamics", sc)
    sim.InitializeSimulation()
    sim.ConfigureStopTime(macros.sec2nano(duration))
    sim.ExecuteSimulation()
    state = (lambda name: np.array(sc.dynManager.getStateObject(name).getState(), float).ravel())
    r_nb = rbk.MRP2C(state(sc.hub.nameOfHubSigma)).T  # R0 = [NB]
    x, u = np.zeros(robot.nx), np.zeros(robot.nu)
    x[:3], x[3:7] = state(sc.hub.nameOfHubPosition), Rotation.from_matrix(r_nb).as_quat()
    u[:3], u[3:6] = state(sc.hub.nameOfHubVelocity), r_nb @ state(sc.hub.nameOfHubOmega)
    gimbal, rotor = (np.array([c[k] for c in cmgs.values()]) for k in ("gimbal", "rotor"))
    x[7 + gimbal], u[6 + gimbal] = state(eff.nameOfVSCMGGammasState), state(eff.nameOfVSCMGGammaDotsState)
    u[6 + rotor] = state(eff.nameOfVSCMGOmegasState)
    x[7 + rotor] = np.nan  # Basilisk's balanced wheel keeps no spin angle
    return x, u
