"""spacearm.mpc's semi-implicit Euler discretization (``Problem(discretization="euler")``) and a
moving target in orbit (``FreeBodyPoint(orbit=...)`` as a point cost's target), docs/mpc.md.

The Euler step is checked against its definition written here in numpy on ``Robot.forward_dynamics``
(an independent implementation of the step: the solver's states are the replay of its
controls); its Jacobians are checked by finite differences in the core's tests
(optimal/euler.rs). The orbiting target is checked against the Clohessy–Wiltshire closed form:
a target placed by CW so that it reaches the end effector at a later time is reached by the plan."""

import numpy as np
import pytest

import spacearm
import spacearm.mpc as mpc
from spacearm.control import MPC, FreeBodyPoint
from spacearm.errors import ArgumentError


def _quat_exp_mul(phi, q):
    """``exp(φ/2) ⊗ q`` for ``[x, y, z, w]`` quaternions (a world-frame rotation by ``φ``)."""
    t = np.linalg.norm(phi)
    e = np.concatenate([np.sin(0.5 * t) / t * phi, [np.cos(0.5 * t)]]) if t > 0 else np.array([0.0, 0.0, 0.0, 1.0])
    ev, ew, qv, qw = e[:3], e[3], q[:3], q[3]
    return np.concatenate([ew * qv + qw * ev + np.cross(ev, qv), [ew * qw - ev @ qv]])


def euler_replay(robot, sol, mode):
    """The semi-implicit Euler step written out: ``u⁺ = u + h FD(x, u, S c)``, ``x⁺ = x ⊕ h u⁺``."""
    h, n = sol.problem.dt, robot.n_dof
    x, u = sol.x[0].copy(), sol.u[0].copy()
    worst = 0.0
    for k in range(sol.problem.horizon):
        a = robot.forward_dynamics(x, u, tau=sol.tau[k], base_wrench=sol.base_wrench[k])
        u = u + h * a
        x = np.concatenate([x[:3] + h * u[:3], _quat_exp_mul(h * u[3:6], x[3:7]), x[7:] + h * u[6:]])
        worst = max(worst, np.abs(x - sol.x[k + 1]).max(), np.abs(u - sol.u[k + 1]).max())
    assert n == sol.tau.shape[1]
    return worst


@pytest.mark.parametrize("mode", ["floating", "rotation-flying"])
def test_the_euler_solution_is_the_replay_of_its_controls_and_converges_to_rk4s(mode):
    robot = spacearm.presets.spatial6()
    n = robot.n_dof
    goal = robot.initial_q + np.array([0.2, -0.1, 0.15, 0.1, -0.2, 0.3])
    x0, u0 = robot.neutral_configuration(), robot.zero_velocity()
    u0[6:] = 0.1 * np.cos(np.arange(n))  # moving joints: the step's coupling terms act
    gaps = []
    for horizon, dt in ((20, 0.02), (40, 0.01)):  # the same 0.4 s, the step halved
        problems = {
            kind: mpc.Problem(horizon=horizon, dt=dt, mode=mode, discretization=kind,
                              running=[mpc.JointCost(10.0, goal, weight_qd=0.1), mpc.BaseAttitudeCost(1.0, rate_weight=1.0), mpc.ControlCost(1e-2)],
                              terminal=[mpc.JointCost(100.0, goal, weight_qd=1.0)], control_limit=5.0)
            for kind in ("rk4", "euler")
        }
        euler = mpc.solve(robot, problems["euler"], x0, u0)
        rk4 = mpc.solve(robot, problems["rk4"], x0, u0)
        assert euler.converged and rk4.converged
        assert problems["euler"].to_data()["discretization"] == "euler"
        # The solver's states are the Euler replay of its controls (ABA here, the derivative
        # routine's H⁻¹(f − c) in the solver: equal to rounding).
        assert euler_replay(robot, euler, mode) < 1e-9
        assert rk4.resimulate(robot) < 1e-9
        assert np.abs(euler.tau).max() > 0.1  # not a trivial plan
        # The Euler model is not the RK4 plant: re-simulated by the native RK4 simulator the
        # plan drifts (measured 2.7e-2 at 20 ms, in a joint rate).
        gaps.append((euler.resimulate(robot), abs(euler.cost - rk4.cost) / rk4.cost, np.abs(euler.x[-1] - rk4.x[-1]).max()))
    # First order: the plant drift and the distance to RK4's optimum (cost, measured 4.5 % at
    # 20 ms, and final state) halve with the step.
    for coarse, fine in zip(*gaps):
        assert 1e-4 < fine < coarse and 1.7 < coarse / fine < 2.3, gaps


def test_the_native_law_runs_the_euler_model_on_the_rk4_plant():
    robot = spacearm.presets.planar4()
    goal = robot.initial_q + np.array([0.4, -0.3, 0.3, -0.2])
    problem = mpc.Problem(horizon=10, dt=0.05, discretization="euler",
                          running=[mpc.JointCost(1.0, goal, weight_qd=0.1), mpc.ControlCost(1e-3)],
                          terminal=[mpc.JointCost(100.0, goal, weight_qd=10.0)], control_limit=20.0)
    traj = spacearm.simulate(robot, 2.0, dt=0.01, controller=MPC(problem, max_iterations=5))
    first = mpc.solve(robot, problem, max_iterations=5)
    assert np.array_equal(traj["tau_cmd"][0], first.tau[0])  # the first sample is a one-off solve
    assert np.abs(traj.x[-1, 7:] - goal).max() < 1e-2


def test_an_unknown_discretization_is_refused():
    with pytest.raises(ArgumentError, match="euler"):
        mpc.Problem(horizon=2, dt=0.1, terminal=[mpc.JointCost(1.0, [0.0] * 4)], discretization="midpoint")


def test_the_plan_reaches_an_orbiting_target_where_clohessy_wiltshire_puts_it():
    robot = spacearm.presets.spatial6()
    x0, u0 = robot.neutral_configuration(), robot.zero_velocity()
    orbit = spacearm.Orbit.circular(500e3, inclination=0.9, raan=0.3)
    n = orbit.mean_motion
    body, offset = robot.resolve_point(None)
    t_end = 300.0  # the time the plan ends, s (its knot 0 at t_end - 2 s)
    # Where the end effector goes in the run frame (a little away from where it is), in the LVLH
    # of the orbit's point O at t_end; a target at rest in LVLH at t = 0 is there at t_end when
    # (CW, zero initial rate) x = (4 − 3c) x0, y = y0 + 6 (s − n t) x0, z = c z0.
    aim = robot.point_position(x0) + np.array([0.03, -0.02, 0.02])
    r_o, v_o = orbit.propagate([t_end])
    rel_end = orbit.run_to_lvlh([t_end], np.zeros((1, 6)), np.concatenate([aim, np.zeros(3)])[None, :])[0]
    c, s = np.cos(n * t_end), np.sin(n * t_end)
    x0_l = rel_end[0] / (4.0 - 3.0 * c)
    rel0 = np.array([x0_l, rel_end[1] - 6.0 * (s - n * t_end) * x0_l, rel_end[2] / c, 0.0, 0.0, 0.0])
    assert np.abs(orbit.clohessy_wiltshire(rel0, [t_end])[0, :3] - rel_end[:3]).max() < 1e-9
    start = np.asarray(orbit.lvlh_to_run(rel0))
    state = np.concatenate([start[:3], [0.0, 0.0, 0.0, 1.0], start[3:6], [0.0, 0.0, 0.0]])
    orbiting = FreeBodyPoint([3.0, 4.0, 5.0], state, step=0.01, orbit=orbit)
    drifting = FreeBodyPoint([3.0, 4.0, 5.0], state, step=0.01)
    # The core's propagation (what the cost reads) against CW, along the way.
    times = np.linspace(0.0, t_end, 7)
    cw = orbit.clohessy_wiltshire(rel0, times)
    expected = np.array([orbit.lvlh_to_run(r, t=t)[:3] for r, t in zip(cw, times)])
    assert np.abs(orbiting.evaluate(times)[0] - expected).max() < 1e-5
    assert np.linalg.norm(drifting.evaluate(t_end)[0] - aim) > 0.1  # the tidal motion matters here
    for target, reach in ((orbiting, True), (drifting, False)):
        problem = mpc.Problem(horizon=10, dt=0.2, start_time=t_end - 2.0, running=[mpc.ControlCost(1e-3)],
                              terminal=[mpc.PointCost(body, target, weight=1e4, offset=offset)])
        assert ("orbit" in problem.to_data()["terminal"][0]["target"]) is reach
        sol = mpc.solve(robot, problem, x0, u0, max_iterations=50)
        miss = np.linalg.norm(robot.point_position(sol.x[-1]) - aim)
        assert bool(miss < 2e-3) == reach, (reach, miss)  # measured 2.8e-7 m when it reaches
