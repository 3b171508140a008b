"""spacearm's control laws as Basilisk flight software (spacearm.basilisk.ControllerModule): the
core's law, sampled and held at the module's task rate, in Basilisk's MJScene against spacearm's
own sample-and-hold run of the same law (Simulator.command, then RK4 steps with the command
held)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("Basilisk.simulation.mujoco")

import spacearm  # noqa: E402
from spacearm import control  # noqa: E402
from spacearm.errors import ArgumentError  # noqa: E402
from bsk_runs import held_run, rel, scene_run, tumbling_start  # noqa: E402

DT, FSW_DT, T = 0.01, 0.05, 3.0
HOLD = 5


@pytest.fixture(scope="module")
def robot():
    return spacearm.presets.spatial6()



def test_computed_torque_in_basilisk_matches_spacearm_sample_and_hold(robot):
    """Computed torque on H* (paper eqs. 112–115), a quintic joint move of 0.4 rad in 2 s: the
    module at 20 Hz in Basilisk (RK4 at 0.01 s) against spacearm's run of the same law held over
    the same five steps. The two differ only by their integrators' step errors: measured 1e-12
    (x) and 1.2e-10 (u) relative, while each is 3e-9 (u) off the dt/4 solution; asserted below
    the issue's 1e-9 and below the step error."""
    x0, u0 = tumbling_start(robot)
    law = control.ComputedTorque(kp=16.0, kd=8.0, reference=control.QuinticJoint(
        q_start=x0[7:], q_goal=x0[7:] + 0.4, t_start=0.0, t_end=2.0))
    xb, ub, _, _, extras = scene_run(robot, x0, u0, DT, T, controller=law, fsw_dt=FSW_DT)
    samples = int(round(T / FSW_DT))
    xs, us = held_run(robot, law, x0, u0, DT, HOLD, samples)
    xf, uf = held_run(robot, law, x0, u0, DT / 4, 4 * HOLD, samples)
    np.testing.assert_allclose(xb[7:], x0[7:] + 0.4, atol=1e-3)  # the arm got there
    assert rel(xb, xs) < 1e-9 and rel(ub, us) < 1e-9
    assert rel(ub, us) < rel(us, uf)  # within spacearm's own step error
    tau, _ = extras["controller"].last_command
    assert np.max(np.abs(tau)) > 0  # the module commanded torques


def test_reactionless_rmrc_leaves_the_base_still_in_basilisk(robot):
    """Reactionless resolved-motion-rate control (the arm in the reaction null space) as a
    module: the end effector rises 10 cm while the base, at rest, turns less than 1 % of the
    naive strategy's rotation (spacearm alone, continuous: 2.7e-5 against 3.5e-2 rad); the
    trajectory matches spacearm's sample-and-hold run."""
    x0 = np.asarray(robot.neutral_configuration(), float)
    u0 = np.zeros(robot.nu)
    p0 = robot.point_position(x0)
    turns = {}
    for strategy in ("naive", "reactionless"):
        law = control.ResolvedMotionRate(control.CartesianLine(p0, p0 + [0.0, 0.0, 0.1], 0.0, 2.0), gain=2.0,
                                         strategy=strategy, velocity_gain=10.0)
        xb, ub, _, _, _ = scene_run(robot, x0, u0, DT, 2.5, controller=law, fsw_dt=FSW_DT)
        xs, us = held_run(robot, law, x0, u0, DT, HOLD, 50)
        assert rel(xb, xs) < 1e-9
        assert np.linalg.norm(robot.point_position(xb) - p0 - [0.0, 0.0, 0.1]) < 5e-3
        turns[strategy] = 2 * np.arccos(min(1.0, abs(np.dot(xb[3:7], x0[3:7]))))
    print(turns)
    assert turns["naive"] > 1e-2
    assert turns["reactionless"] < 1e-2 * turns["naive"]


def test_a_law_that_does_not_fit_is_refused_when_the_module_is_made(robot):
    """The core's setup checks run in the module's constructor (inside Basilisk's Reset, SWIG
    would turn them into a bare RuntimeError): a wheel law in the wrong mode, a flying mode on a
    scene without base actuators."""
    from spacearm import basilisk as sb

    x0 = np.asarray(robot.neutral_configuration(), float)
    scene, acts = sb.to_mjscene(robot, base_actuators=False)
    with pytest.raises(ArgumentError, match="rotation-floating"):
        sb.ControllerModule(robot, control.AttitudeControl(quat_ref=[0, 0, 0, 1], kp=50.0, kd=200.0), scene, acts)
    pd = control.JointPD(kp=10.0, kd=5.0, reference=x0[7:])
    with pytest.raises(ArgumentError, match="no base actuators"):
        sb.ControllerModule(robot, pd, scene, acts, mode="flying")


def _with_wheels():
    b = spacearm.presets.spatial6().to_builder("spatial6_wheels")
    for k, axis in enumerate(np.eye(3)):
        b.add_reaction_wheel(axis, 0.8, position=[0.0, 0.0, 0.2 * k], name=f"rw{k + 1}")
    return b.build()


def _laws():
    """(name, robot maker, law maker(robot, x0), mode, initial base rate): one case per family of
    native laws: wheels, thrusters, coordinated flying, input shaping."""
    def attitude(robot, x0):
        return control.AttitudeControl(quat_ref=[0.0, 0.0, 0.0, 1.0], kp=40.0, kd=200.0)

    def detumble(robot, x0):
        # the arm held by computed torque (H*-scaled gains: stable at the 20 Hz hold)
        return control.Combined(arm=control.ComputedTorque(kp=4.0, kd=4.0, reference=x0[7:]),
                                base=control.MomentumDamping(time_constant=2.0))

    def coordinated(robot, x0):
        p0 = robot.point_position(x0)
        return control.CoordinatedFlying(control.CartesianLine(p0, p0 + [0.0, 0.0, 0.1], 0.0, 2.0), kp_ee=4.0, kd_ee=4.0,
                                         kp_base=1.0, kd_base=2.0)

    def shaped(robot, x0):
        ref = control.ShapedJoint(control.QuinticJoint(x0[7:], x0[7:] + 0.2, 0.0, 1.5), control.input_shaper("zv", frequency=3.0))
        return control.ComputedTorque(kp=16.0, kd=8.0, reference=ref)

    return [("attitude_wheels", _with_wheels, attitude, "rotation-floating"),
            ("detumble_thrusters", spacearm.presets.spatial6, detumble, "rotation-flying"),
            ("coordinated_flying", spacearm.presets.spatial6, coordinated, "flying"),
            ("input_shaping", spacearm.presets.spatial6, shaped, "floating")]


@pytest.mark.parametrize("name, make_robot, make_law, mode", _laws(), ids=[c[0] for c in _laws()])
def test_every_law_family_runs_as_a_module(name, make_robot, make_law, mode):
    """Wheels, thrusters, coordinated flying and input shaping as Basilisk modules (20 Hz, 2 s,
    a base tumbling at first) against spacearm's sample-and-hold run of the same law: the same
    trajectory to 1e-9 relative (the integrators' difference, as above), and a law that acts
    (the torques it commanded are not all zero)."""
    robot = make_robot()
    x0 = np.asarray(robot.neutral_configuration(), float)
    x0[3:7] = [0.05, -0.03, 0.02, 1.0] / np.linalg.norm([0.05, -0.03, 0.02, 1.0])
    u0 = np.zeros(robot.nu)
    u0[3:6] = [0.01, -0.02, 0.015]
    law = make_law(robot, x0)
    duration = 2.0
    from spacearm import basilisk as sb

    module_box = {}

    def run():
        from Basilisk.simulation import svIntegrators
        from Basilisk.utilities import SimulationBaseClass, macros

        scene, acts = sb.to_mjscene(robot)
        sim = SimulationBaseClass.SimBaseClass()
        proc = sim.CreateNewProcess("p")
        proc.addTask(sim.CreateNewTask("dynamics", macros.sec2nano(DT)), 100)
        proc.addTask(sim.CreateNewTask("fsw", macros.sec2nano(FSW_DT)), 50)
        sim.AddModelToTask("dynamics", scene)
        scene.setIntegrator(svIntegrators.svIntegratorRK4(scene))
        module = sb.ControllerModule(robot, law, scene, acts, mode=mode)
        sim.AddModelToTask("fsw", module)
        sim.InitializeSimulation()
        sb.state_to_scene(robot, scene, x0, u0)
        module.Reset(0)
        sim.ConfigureStopTime(macros.sec2nano(duration))
        sim.ExecuteSimulation()
        module_box["m"] = module
        return sb.state_from_scene(robot, scene)

    x_b, u_b = run()
    x_s, u_s = held_run(robot, law, x0, u0, DT, HOLD, int(round(duration / FSW_DT)), mode=mode)
    print(name, rel(x_b, x_s), rel(u_b, u_s))
    assert rel(x_b, x_s) < 1e-9 and rel(u_b, u_s) < 1e-9
    tau, wrench = module_box["m"].last_command
    assert np.max(np.abs(np.concatenate([tau, wrench]))) > 0


def test_a_module_started_late_sees_the_state_relative_to_where_o_is_now(robot):
    """With ``orbit`` and ``t_start``, the law's clock starts at ``t_start`` but the orbit's point O
    is where it is at the scene's time: a module made at 10 s reads the scene's ECI state minus
    O's position and velocity at 10 s (not at 0 s, which is 76 km and 80 m/s away)."""
    from Basilisk.simulation import svIntegrators
    from Basilisk.utilities import SimulationBaseClass, macros

    from spacearm import basilisk as sb

    orbit = spacearm.Orbit.circular(500e3, inclination=0.9)
    scene, actuators = sb.to_mjscene(robot)
    sim = SimulationBaseClass.SimBaseClass()
    sim.CreateNewProcess("p").addTask(sim.CreateNewTask("dynamics", macros.sec2nano(DT)))
    sim.AddModelToTask("dynamics", scene)
    scene.setIntegrator(svIntegrators.svIntegratorRK4(scene))
    module = sb.ControllerModule(robot, control.MomentumDamping(time_constant=3.0), scene, actuators,
                                 mode="rotation-flying", orbit=orbit, t_start=10.0)
    sim.InitializeSimulation()
    x0 = np.asarray(robot.neutral_configuration(), float)
    (r10,), (v10,) = orbit.propagate([10.0])
    offset_x = np.r_[r10, np.zeros(robot.nx - 3)]
    offset_u = np.r_[v10, np.zeros(robot.nu - 3)]
    sb.state_to_scene(robot, scene, x0 + offset_x, robot.zero_velocity() + offset_u)
    t, x, u = module.state(macros.sec2nano(10.0))
    assert t == 0.0
    assert np.allclose(x[:3], x0[:3], rtol=0, atol=1e-8) and np.allclose(u[:3], 0.0, rtol=0, atol=1e-11)
    assert np.linalg.norm(r10 - orbit.propagate([0.0])[0][0]) > 7e4  # the two clocks would disagree
