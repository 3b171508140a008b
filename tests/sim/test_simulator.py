"""spacearm.Simulator against spacearm.simulate: stepping n·dt records what simulate records for
that duration (bit for bit), a torque held over each step equals a Callback controller
commanding it, step(n) equals n single steps, and bad use is named."""

import numpy as np
import pytest

import spacearm
from spacearm import errors
from spacearm.control import Callback, ComputedTorque, QuinticJoint


@pytest.fixture(scope="module")
def robot():
    return spacearm.presets.spatial6()


def start(robot):
    x0 = robot.neutral_configuration(r0=(0.5, 0.0, -1.0))
    u0 = np.r_[0.02, -0.01, 0.03, 0.05, -0.08, 0.1, 0.3 * np.sin(np.arange(1, robot.n_dof + 1))]
    return x0, u0


def test_stepping_records_what_simulate_records(robot):
    x0, u0 = start(robot)
    q0 = x0[7:]
    ctrl = ComputedTorque(30.0, 10.0, QuinticJoint(q0, q0 + 0.4, 0.0, 0.2))
    # 300 · 1e-3 == 0.3 exactly in floating point: simulate's last step lands where the
    # simulator's does.
    n, dt = 300, 1e-3
    assert n * dt == 0.3
    expected = spacearm.simulate(robot, 0.3, x0=x0, u0=u0, dt=dt, controller=ctrl, record_every=7)
    sim = spacearm.Simulator(robot, dt=dt, controller=ctrl, record_every=7)
    sim.reset(x0, u0)
    for i in range(n):
        sim.step()
        if i == 150:
            # Looking at the records mid-run changes nothing that follows.
            mid = sim.trajectory()
            assert mid.t[-1] == pytest.approx(0.151)
    assert sim.n_steps == n and sim.time == n * dt
    traj = sim.trajectory()
    assert sorted(traj.keys) == sorted(expected.keys)
    for key in expected.keys:
        np.testing.assert_array_equal(traj[key], expected[key], err_msg=key)
    assert traj.meta["drift"] == expected.meta["drift"]
    np.testing.assert_array_equal(sim.state, np.r_[expected.x[-1], expected.u[-1]])
    # A reset starts over (fresh controller, empty records).
    sim.reset(x0, u0)
    sim.step(n=n)
    np.testing.assert_array_equal(sim.trajectory().x, expected.x)


def test_a_held_torque_equals_a_controller_commanding_it(robot):
    x0, u0 = start(robot)
    rng = np.random.default_rng(3)
    taus = rng.uniform(-0.5, 0.5, (4, robot.n_dof))
    wrenches = rng.uniform(-2.0, 2.0, (4, 6))
    dt = 2e-3
    sim = spacearm.Simulator(robot, dt=dt, mode="flying")
    sim.reset(x0, u0)
    x, u = x0, u0
    for tau, wrench in zip(taus, wrenches):
        # The same input over 10 steps: a Callback commanding it, from where the last block ended.
        ctrl = Callback(lambda t, x_, u_, tau=tau, wrench=wrench: (tau, wrench))
        block = spacearm.simulate(robot, 10 * dt, x0=x, u0=u, dt=dt, mode="flying", controller=ctrl, record_every=10)
        x, u = block.x[-1], block.u[-1]
        sim.step(tau=tau, n=10, base_wrench=wrench)
        # Equal up to the rounding of the step times (i·dt − (i−1)·dt is dt within an ulp).
        np.testing.assert_allclose(sim.state, np.r_[x, u], rtol=0, atol=1e-12)
    # The input moved the base (the comparison is not that of two runs at rest).
    assert np.linalg.norm(sim.x[:3] - x0[:3]) > 1e-6


def test_step_n_equals_n_steps_and_zero_input_equals_none(robot):
    x0, u0 = start(robot)
    a = spacearm.Simulator(robot, dt=1e-3)
    b = spacearm.Simulator(robot, dt=1e-3)
    a.reset(x0, u0)
    b.reset(x0, u0)
    a.step(n=25)
    for _ in range(25):
        b.step(tau=np.zeros(robot.n_dof))
    np.testing.assert_array_equal(a.state, b.state)
    assert a.time == b.time == 25 * 1e-3
    np.testing.assert_array_equal(a.x, a.state[:13])
    # Without record_every the trajectory holds the current state only.
    assert len(a.trajectory()) == 1


def test_bad_use_is_named(robot):
    sim = spacearm.Simulator(robot, dt=1e-3)
    with pytest.raises(errors.ArgumentError, match="reset"):
        sim.step()
    sim.reset()
    with pytest.raises(errors.ShapeError, match="tau"):
        sim.step(tau=[1.0, 2.0])
    with pytest.raises(errors.NonFiniteError, match="tau"):
        sim.step(tau=[np.nan] * robot.n_dof)
    with pytest.raises(errors.ArgumentError, match="rk4"):
        spacearm.Simulator(robot, integrator="dopri5")
    with pytest.raises(errors.QuaternionError):
        sim.reset(np.r_[0, 0, 0, 0, 0, 0, 2.0, np.zeros(robot.n_dof)], robot.zero_velocity())
    with pytest.raises(errors.ArgumentError, match="record_every"):
        spacearm.Simulator(robot, record_every=0)
    # A diverging step raises and then asks for a reset.
    wild = spacearm.Simulator(robot, dt=0.5)
    wild.reset(u0=np.r_[np.zeros(6), np.full(robot.n_dof, 50.0)])
    with pytest.raises(errors.SimulationError):
        for _ in range(200):
            wild.step(tau=np.full(robot.n_dof, 1e6))
    with pytest.raises(errors.SimulationError, match="reset"):
        wild.step()


def test_step_returns_the_new_state_that_scipy_integration_reaches():
    """``Simulator.step`` returns ``[x; u]`` after the steps: it is ``state`` and it matches an
    independent integration of ``Robot.forward_dynamics`` by scipy (DOP853, the quaternion
    rate ½ ω ⊗ q with ω in 𝒥) under the same held torque."""
    from scipy.integrate import solve_ivp

    from spacearm.rotations import quat_multiply

    robot = spacearm.presets.planar4()
    tau = np.array([2.0, -1.0, 0.5, 0.3])
    sim = spacearm.Simulator(robot, dt=1e-3)
    sim.reset()
    first = sim.step(tau)
    assert first.shape == (robot.nx + robot.nu,)
    np.testing.assert_array_equal(first, sim.state)
    state = sim.step(tau, n=199)
    np.testing.assert_array_equal(state, sim.state)
    nx = robot.nx

    def rate(_t, s):
        x, u = s[:nx].copy(), s[nx:]
        x[3:7] /= np.linalg.norm(x[3:7])
        dquat = 0.5 * quat_multiply(np.r_[u[3:6], 0.0], x[3:7])
        return np.concatenate([u[:3], dquat, u[6:], robot.forward_dynamics(x, u, tau=tau)])

    s0 = np.concatenate([robot.neutral_configuration(), robot.zero_velocity()])
    ref = solve_ivp(rate, (0.0, 0.2), s0, method="DOP853", rtol=1e-12, atol=1e-12).y[:, -1]
    assert np.abs(state[7:nx] - s0[7:nx]).max() > 1e-3  # the arm moved
    np.testing.assert_allclose(state, ref, atol=1e-9)
