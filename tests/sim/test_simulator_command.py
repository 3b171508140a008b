"""Simulator.command: a control law's command at a state measured elsewhere, without stepping (the
core's Plant::apply_command, what every evaluation of the dynamics applies first; used by
spacearm.basilisk's flight-software module). Checked against what a spacearm.simulate run
records, through the limits and the mode's mask, and for bad input."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm import control
from spacearm.errors import ArgumentError, NonFiniteError, QuaternionError, ShapeError
from bsk_runs import tumbling_start


@pytest.fixture(scope="module")
def robot():
    return spacearm.presets.spatial6()



def test_command_is_what_a_run_applies(robot):
    """The law at the first and the last sample of a simulate run, evaluated by command on the
    recorded states: the torques the run recorded (computed torque: a law with internal
    dependence on t and the state only)."""
    x0, u0 = tumbling_start(robot)
    law = control.ComputedTorque(kp=16.0, kd=8.0, reference=control.QuinticJoint(x0[7:], x0[7:] + 0.4, 0.0, 2.0))
    run = spacearm.simulate(robot, 0.5, x0=x0, u0=u0, controller=law, dt=0.01, integrator="rk4")
    sim = spacearm.Simulator(robot, controller=law)
    sim.reset(x0, u0)
    tau, wrench = sim.command(0.0, x0, u0)
    assert np.max(np.abs(tau)) > 1e-2
    np.testing.assert_allclose(tau, run.tau[0], rtol=1e-14, atol=1e-14)
    assert np.array_equal(wrench, np.zeros(6))
    tau_end, _ = sim.command(float(run.t[-1]), run.x[-1], run.u[-1])
    assert np.max(np.abs(run.tau[-1])) > 1.0
    np.testing.assert_allclose(tau_end, run.tau[-1], rtol=1e-12, atol=1e-12)


def test_command_goes_through_the_limits_and_the_mask(robot):
    """An effort limit clamps the command (the law asks for more); in the rotation-flying mode a
    thruster law's torque is kept and its force masked."""
    b = spacearm.Robot.builder("limited", 100.0, [10.0, 12.0, 14.0])
    b.add_link("a", joint="revolute", axis=[0, 0, 1], origin=[0.5, 0, 0], com=[0.2, 0, 0], mass=5.0,
               inertia=[0.1, 0.1, 0.1], limits={"effort": 3.0})
    b.add_link("b", parent="a", joint="revolute", axis=[0, 1, 0], origin=[0.4, 0, 0], com=[0.2, 0, 0], mass=2.0,
               inertia=[0.05, 0.05, 0.05], limits={"effort": 7.0})
    limited = b.build()
    xl, ul = np.asarray(limited.neutral_configuration(), float), np.zeros(limited.nu)
    commands = []
    for kp in (1.0, 1e4):  # 1 rad of error: 1 N·m, within the limits; 1e4 N·m, beyond them
        sim = spacearm.Simulator(limited, controller=control.JointPD(kp=kp, kd=0.0, reference=xl[7:] + 1.0))
        sim.reset(xl, ul)
        commands.append(sim.command(0.0, xl, ul)[0])
    np.testing.assert_allclose(commands[0], [1.0, 1.0], rtol=1e-14)
    np.testing.assert_array_equal(commands[1], [3.0, 7.0])
    x0, u0 = tumbling_start(robot)
    damping = control.MomentumDamping(time_constant=1.0)
    flying = spacearm.Simulator(robot, controller=damping, mode="rotation-flying")
    flying.reset(x0, u0)
    _, wrench = flying.command(0.0, x0, u0)
    assert np.max(np.abs(wrench[3:])) > 0 and np.array_equal(wrench[:3], np.zeros(3))


def test_command_refuses_bad_input(robot):
    x0, u0 = tumbling_start(robot)
    sim = spacearm.Simulator(robot, controller=control.JointPD(kp=10.0, kd=5.0, reference=x0[7:]))
    with pytest.raises(ArgumentError, match="reset"):
        sim.command(0.0, x0, u0)
    sim.reset(x0, u0)
    with pytest.raises(ShapeError, match="x must have length 7"):
        sim.command(0.0, x0[:5], u0)
    with pytest.raises(ShapeError, match="u must have length 6"):
        sim.command(0.0, x0, u0[:3])
    with pytest.raises(ArgumentError, match="t must be finite"):
        sim.command(float("nan"), x0, u0)
    bad = x0.copy()
    bad[3:7] *= 2.0
    with pytest.raises(QuaternionError, match="unit quaternion"):
        sim.command(0.0, bad, u0)
    with pytest.raises(NonFiniteError, match="^u must be finite"):
        sim.command(0.0, x0, np.full(robot.nu, np.inf))
