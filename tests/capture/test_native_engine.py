"""The capture, detumble and plan laws run in the core: each native piece against an
independent computation (scipy's integrator on Euler's equations, closed-form momentum decay, a
Python implementation of the same control law, an exact polynomial)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import spacearm
from spacearm import control
from spacearm.capture import capture, detumble
from capture_oracles import hold_torque
from spacearm.rotations import quat_to_matrix

MODELS = Path(spacearm.examples.path("spatial6")).parent  # the shipped model files


def _euler_rhs(inertia):
    inv = np.linalg.inv(inertia)

    def rhs(_t, y):
        q, w = y[:4] / np.linalg.norm(y[:4]), y[4:]  # w in body axes
        x, yy, z, s = q
        a, b, c = w
        qd = 0.5 * np.array([s * a + yy * c - z * b, s * b + z * a - x * c, s * c + x * b - yy * a, -x * a - yy * b - z * c])
        return np.r_[qd, inv @ (-np.cross(w, inertia @ w))]

    return rhs


def test_free_body_matches_eulers_equations_integrated_by_scipy():
    inertia = np.array([[4.0, 0.2, 0.0], [0.2, 5.0, -0.1], [0.0, -0.1, 6.0]])
    target = spacearm.Target(50.0, inertia, grasp_points={"h": (0.4, -0.1, 0.2)})
    q0 = np.array([0.1, -0.2, 0.3, 0.9])
    q0 /= np.linalg.norm(q0)
    w0 = np.array([0.3, -0.5, 0.8])
    s0 = target.state(position=(1.0, 2.0, -0.5), quaternion=q0, velocity=(0.1, 0.0, -0.2), angular_velocity=w0)
    R0 = quat_to_matrix(q0)
    sol = solve_ivp(_euler_rhs(inertia), (0.0, 4.0), np.r_[q0, R0.T @ w0], rtol=1e-12, atol=1e-13, dense_output=True)
    times = np.array([0.0, 0.7, 2.3, 4.0])
    states = target.free_body(s0, "h", step=1e-3).states(times)
    for t, s in zip(times, states):
        y = sol.sol(t)
        q_ref = y[:4] / np.linalg.norm(y[:4])
        R = quat_to_matrix(q_ref)
        assert np.allclose(s[:3], s0[:3] + t * s0[7:10], atol=1e-14)
        assert min(np.abs(s[3:7] - q_ref).max(), np.abs(s[3:7] + q_ref).max()) < 1e-9
        assert np.allclose(s[10:13], R @ y[4:], atol=1e-9)
    # Target.propagate is the same core propagation
    assert np.allclose(target.propagate(s0, 2.3, dt=1e-3)[3:7], states[2, 3:7], atol=1e-11)
    # the grasp point's velocity is the derivative of its position
    ref = target.free_body(s0, "h", step=1e-3)
    p, v = ref.evaluate([1.0 - 1e-5, 1.0, 1.0 + 1e-5])
    assert np.allclose((p[2] - p[0]) / 2e-5, v[1], atol=1e-8)


def test_momentum_damping_decays_the_momenta_exponentially():
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    u0 = robot.zero_velocity()
    u0[:6] = [0.05, -0.02, 0.01, 0.02, -0.03, 0.04]
    u0[6:] = 0.1
    tau_d = 2.0
    traj = spacearm.simulate(robot, 3.0, x0=x0, u0=u0, mode="flying", controller=control.MomentumDamping(tau_d),
                             integrator="dopri5", rtol=1e-11, atol=1e-13, dt=0.1)
    m = robot.momentum(traj.x, traj.u)
    decay = np.exp(-traj.t / tau_d)[:, None]
    assert np.allclose(m.P, m.P[0] * decay, atol=1e-9 * np.abs(m.P[0]).max())
    assert np.allclose(m.L_com, m.L_com[0] * decay, atol=1e-9 * np.abs(m.L_com[0]).max())
    with pytest.raises(spacearm.ArgumentError, match="flying"):
        spacearm.simulate(robot, 0.1, controller=control.MomentumDamping(tau_d))


def test_native_detumble_equals_the_python_law_in_floating_mode():
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    u0 = robot.zero_velocity()
    u0[3:6] = [0.01, 0.02, -0.03]
    u0[6:] = [0.2, -0.1, 0.15, 0.05, -0.2, 0.1]
    q_hold = x0[7:] + 0.05
    run = detumble(robot, x0, u0, 2.0, q_hold=q_hold, kp=1.5, kd=2.5, max_joint_torque=3.0, rtol=None, dt=0.01)
    law = control.Callback(lambda t, x, u: hold_torque(robot, x, u, q_hold, 1.5, 2.5, 3.0))
    ref = spacearm.simulate(robot, 2.0, x0=x0, u0=u0, dt=0.01, controller=law)
    assert np.abs(run.trajectory.x - ref.x).max() < 1e-11
    assert np.abs(run.trajectory.tau - ref.tau).max() < 1e-9


def test_computed_torque_follows_a_sampled_polynomial_exactly():
    robot = spacearm.presets.planar4()
    q0 = robot.initial_q
    c = np.array([0.3, -0.2, 0.1, 0.25])

    def f(t):  # a quintic in t per joint: the Hermite interpolant reproduces it exactly
        return q0 + c * (t**3 - 0.4 * t**4 + 0.05 * t**5), c * (3 * t**2 - 1.6 * t**3 + 0.25 * t**4), c * (6 * t - 4.8 * t**2 + t**3)

    knots = np.linspace(0.0, 2.0, 7)
    q, qd, qdd = (np.array([f(t)[i] for t in knots]) for i in range(3))
    ref = control.SampledJoint(knots, q, qd, qdd)
    t = np.array([0.13, 0.91, 1.77])
    for got, want in zip(ref.evaluate(t), (np.array([f(tt)[i] for tt in t]) for i in range(3))):
        assert np.allclose(got, want, atol=1e-12)
    traj = spacearm.simulate(robot, 2.0, dt=0.005, controller=control.ComputedTorque(kp=100.0, kd=20.0, reference=ref))
    want = np.array([f(tt)[0] for tt in traj.t])
    assert np.abs(traj.x[:, 7:] - want).max() < 1e-8


def test_capture_approach_gives_the_reaction_wheels_no_torque():
    robot = spacearm.io.load_toml(MODELS / "spatial6_wheels.toml")
    x = robot.neutral_configuration()
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    s = target.state(position=robot.point_position(x) + np.array([0.6, 0.0, 0.0]), angular_velocity=(0.0, 0.0, 0.1))
    res = capture(robot, target, s, detumble_time=2.0, post_time=0.5)
    approach = res.phase == 0
    assert robot.wheel_dofs == [6, 7, 8]
    assert np.abs(res.tau[approach][:, robot.wheel_dofs]).max() == 0.0
    assert np.abs(res.tau[approach][:, robot.arm_dofs]).max() > 1e-3  # the arm does move
    assert res.impact.gap < 0.01
