"""spacearm.mpc: the core's box-FDDP (crates/spacearm-core/src/optimal) against CasADi/IPOPT on
the same problem (the same RK4 step, spacearm.casadi.rk4_step; the same cost), the solution's
controls re-simulated by the native simulator, and the errors of bad input."""

import dataclasses
import math

import numpy as np
import pytest

import spacearm
import spacearm.mpc as mpc
from spacearm.errors import ArgumentError

HORIZON, DT = 10, 0.1
W_Q, W_QD, W_C, W_QT, W_QDT = 1.0, 0.1, 1e-3, 100.0, 10.0


def planar_problem(limit=math.inf):
    robot = spacearm.presets.planar4()
    goal = robot.initial_q + np.array([0.4, -0.3, 0.3, -0.2])
    problem = mpc.Problem(
        horizon=HORIZON, dt=DT,
        running=[mpc.JointCost(W_Q, goal, weight_qd=W_QD), mpc.ControlCost(W_C)],
        terminal=[mpc.JointCost(W_QT, goal, weight_qd=W_QDT)],
        control_limit=limit,
    )
    return robot, goal, problem


def ipopt_optimum(robot, goal, limit):
    """The same problem by single shooting on spacearm.casadi.rk4_step, IPOPT with the exact Hessian."""
    ca = pytest.importorskip("casadi")
    import spacearm.casadi as sc

    n = robot.n_dof
    step = sc.rk4_step(robot)
    taus = ca.MX.sym("tau", n, HORIZON)
    x, u = ca.DM(robot.neutral_configuration()), ca.DM(robot.zero_velocity())
    cost = 0
    for k in range(HORIZON):
        cost += DT * (0.5 * W_Q * ca.sumsqr(x[7:] - goal) + 0.5 * W_QD * ca.sumsqr(u[6:]) + 0.5 * W_C * ca.sumsqr(taus[:, k]))
        x, u = step(x, u, taus[:, k], ca.DM.zeros(6), DT)
    cost += 0.5 * W_QT * ca.sumsqr(x[7:] - goal) + 0.5 * W_QDT * ca.sumsqr(u[6:])
    solver = ca.nlpsol("s", "ipopt", {"x": ca.vec(taus), "f": cost},
                       {"print_time": False, "ipopt": {"print_level": 0, "sb": "yes", "tol": 1e-12, "max_iter": 200}})
    bound = limit if math.isfinite(limit) else ca.inf
    res = solver(x0=np.zeros(n * HORIZON), lbx=-bound, ubx=bound)
    assert solver.stats()["success"], solver.stats()["return_status"]
    return float(res["f"]), np.asarray(res["x"]).reshape(HORIZON, n)  # ca.vec is column-major: rows are knots


@pytest.mark.parametrize("limit", [math.inf, 0.5])
def test_fddp_optimum_equals_ipopt_and_resimulates(limit):
    robot, goal, problem = planar_problem(limit)
    sol = mpc.solve(robot, problem, tolerance=1e-20)
    assert sol.converged and sol.stop == "converged", sol.stop
    cost, tau = ipopt_optimum(robot, goal, limit)
    assert abs(sol.cost - cost) <= 1e-6 * cost, (sol.cost, cost)
    assert np.abs(sol.tau - tau).max() < 1e-6, np.abs(sol.tau - tau).max()
    if math.isfinite(limit):
        assert np.isclose(np.abs(sol.tau).max(), limit), "the bound binds"
    assert np.abs(sol.tau).max() > 0.1 and sol.iterations >= 1
    # The controls replayed by the native simulator give the solution's states.
    assert sol.resimulate(robot) < 1e-9
    assert sol.x.shape == (HORIZON + 1, robot.nx) and sol.u.shape == (HORIZON + 1, robot.nu)


def test_flying_point_and_attitude_costs_with_thrusters():
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    tip = robot.n_bodies - 1
    target = robot.point_position(x0, (tip, [0.0, 0.0, 0.0])) + [0.05, -0.05, 0.05]
    problem = mpc.Problem(
        horizon=8, dt=0.05, mode="flying",
        running=[mpc.ControlCost(1e-3), mpc.BaseAttitudeCost(10.0, rate_weight=1.0)],
        terminal=[mpc.PointCost(tip, target, weight=1e3), mpc.BaseAttitudeCost(100.0)],
        control_limit=50.0,
    )
    sol = mpc.solve(robot, problem)
    assert sol.converged, sol.stop
    # The point moved most of the way (a cost trade-off with the effort and the attitude).
    reached = robot.point_position(sol.x[-1], (tip, [0.0, 0.0, 0.0]))
    assert np.linalg.norm(reached - target) < 0.5 * np.linalg.norm(target - robot.point_position(x0, (tip, [0.0, 0.0, 0.0])))
    assert sol.controls.shape == (8, robot.n_dof + 6)
    assert np.abs(sol.base_wrench).max() > 1e-6, "the thrusters are used"
    assert sol.resimulate(robot) < 1e-9
    # A warm start from the solution converges at once.
    again = mpc.solve(robot, problem, warm_start=sol)
    assert again.converged and again.steps <= 1


def test_limits_are_reported():
    robot, _, problem = planar_problem()
    sol = mpc.solve(robot, problem, max_iterations=1)
    assert (sol.stop, sol.converged, sol.iterations) == ("iteration_limit", False, 1)
    sol = mpc.solve(robot, problem, time_limit=1e-12)
    assert sol.stop == "time_limit"


@pytest.mark.parametrize(
    "kwargs, words",
    [
        (dict(horizon=0, dt=0.1, running=[mpc.ControlCost(1.0)]), "horizon"),
        (dict(horizon=5, dt=-0.1, running=[mpc.ControlCost(1.0)]), "dt"),
        (dict(horizon=5, dt=0.1, mode="hovering", running=[mpc.ControlCost(1.0)]), "mode"),
    ],
)
def test_bad_problems_are_refused_when_made(kwargs, words):
    with pytest.raises(ArgumentError, match=words):
        mpc.Problem(**kwargs)


def test_bad_input_against_the_model_is_refused():
    robot = spacearm.presets.planar4()
    with pytest.raises(ArgumentError, match="translation-flying"):
        mpc.solve(robot, mpc.Problem(horizon=3, dt=0.1, mode="translation-flying", running=[mpc.ControlCost(1.0)]))
    with pytest.raises(ArgumentError, match="reference"):
        mpc.solve(robot, mpc.Problem(horizon=3, dt=0.1, running=[mpc.JointCost(1.0, [0.0, 0.0])]))
    with pytest.raises(ArgumentError, match="terminal"):
        mpc.solve(robot, mpc.Problem(horizon=3, dt=0.1, terminal=[mpc.ControlCost(1.0)]))
    with pytest.raises(spacearm.errors.ShapeError):
        mpc.solve(robot, mpc.Problem(horizon=3, dt=0.1, running=[mpc.ControlCost(1.0)]), x0=[0.0, 1.0])


def test_wrong_types_are_refused():
    robot = spacearm.presets.planar4()
    with pytest.raises(spacearm.errors.SpacearmTypeError, match="cost terms"):
        mpc.Problem(horizon=3, dt=0.1, running=[{"kind": "control", "weights": 1.0}])
    problem = mpc.Problem(horizon=3, dt=0.1, running=[mpc.ControlCost(1.0)])
    with pytest.raises(spacearm.errors.SpacearmTypeError, match="warm_start"):
        mpc.solve(robot, problem, warm_start="previous")
    with pytest.raises(spacearm.errors.SpacearmTypeError, match="Problem"):
        mpc.solve(robot, problem.to_data())


# ---- the native law (spacearm.control.MPC, ControllerSpec kind "mpc") ---------------------------
from spacearm.control import MPC  # noqa: E402
from spacearm.errors import SimulationError  # noqa: E402

LAW_DT, SIM_DT = 0.05, 0.01  # the law's sample period and the RK4 step (5 steps per sample)


def law_problem():
    robot = spacearm.presets.planar4()
    goal = robot.initial_q + np.array([0.4, -0.3, 0.3, -0.2])
    problem = mpc.Problem(horizon=10, dt=LAW_DT, running=[mpc.JointCost(W_Q, goal, weight_qd=W_QD), mpc.ControlCost(W_C)],
                          terminal=[mpc.JointCost(W_QT, goal, weight_qd=W_QDT)], control_limit=20.0)
    return robot, goal, problem


def test_the_laws_first_control_is_a_one_off_solve_and_it_is_held_between_samples():
    robot, goal, problem = law_problem()
    traj = spacearm.simulate(robot, 0.3, dt=SIM_DT, controller=MPC(problem, max_iterations=5))
    one = mpc.solve(robot, problem, max_iterations=5)
    # The same problem from the same state through another door (spacearm.mpc.solve): the same numbers.
    assert np.array_equal(traj["tau_cmd"][0], one.tau[0]), (traj["tau_cmd"][0], one.tau[0])
    assert np.abs(one.tau[0]).max() > 1.0
    # Sample and hold: constant over each sample period of 5 steps, a new solve at each instant.
    tau = traj["tau_cmd"][:30]
    for k in range(6):
        assert np.array_equal(tau[5 * k:5 * k + 5], np.repeat(tau[5 * k][None], 5, axis=0)), k
        if k:
            assert not np.array_equal(tau[5 * k], tau[5 * k - 1]), k
    # The solve at each later sample starts from the measured state: the one-off solve from the
    # state at t = 0.05 s, warm started from the first solution shifted by a knot, agrees.
    x1, u1 = traj.x[5], traj.u[5]
    shifted = dataclasses.replace(one, x=np.vstack([one.x[1:], one.x[-1:]]), u=np.vstack([one.u[1:], one.u[-1:]]),
                                  controls=np.vstack([one.controls[1:], one.controls[-1:]]))
    again = mpc.solve(robot, problem, x1, u1, warm_start=shifted, max_iterations=5)
    assert np.array_equal(traj["tau_cmd"][5], again.tau[0])
    assert traj["solve_iterations"][5] == again.iterations and traj["solve_cost"][5] == again.cost


def test_closed_loop_tracking_reaches_the_goal_in_free_floating():
    robot, goal, problem = law_problem()
    traj = spacearm.simulate(robot, 3.0, dt=SIM_DT, controller=MPC(problem, max_iterations=10))
    assert np.abs(traj.x[-1, 7:] - goal).max() < 1e-3, traj.x[-1, 7:] - goal
    assert np.abs(traj.u[-1, 6:]).max() < 1e-2
    assert np.abs(traj.x[0, 7:] - goal).max() > 0.2  # it had somewhere to go
    # Free floating: the joint torques are internal, the momentum stays zero while the base turns.
    assert np.abs(traj["P"]).max() < 1e-5 and np.abs(traj["L_com"]).max() < 1e-5  # RK4 rounding of large torques
    assert np.abs(traj.x[-1, 3:7] - traj.x[0, 3:7]).max() > 1e-3
    # Every sample's solve recorded: converged, with iterations, cost falling towards the goal.
    assert set(np.unique(traj["solve_converged"])) <= {0.0, 1.0} and traj["solve_converged"].mean() > 0.9
    assert traj["solve_iterations"].min() >= 1 and np.all(traj["solve_time"] > 0)
    assert traj["solve_cost"][-1] < 1e-3 * traj["solve_cost"][0]


@pytest.mark.parametrize("kwargs, words", [
    ({"max_iterations": 0}, "max_iterations"),
    ({"horizon": 0}, "horizon"),
    ({"dt": -0.1}, "dt"),
    ({"time_limit": 0.0}, "time_limit"),
])
def test_bad_law_specs_are_refused_when_made(kwargs, words):
    _, _, problem = law_problem()
    with pytest.raises(ArgumentError, match=words):
        MPC(problem, **kwargs)


def test_bad_laws_are_refused_against_the_run():
    robot, goal, problem = law_problem()
    with pytest.raises(ArgumentError, match="mode"):
        spacearm.simulate(robot, 0.1, dt=SIM_DT, mode="flying", controller=MPC(problem))
    wrong = mpc.Problem(horizon=5, dt=LAW_DT, running=[mpc.JointCost(1.0, [0.0, 0.0])])
    with pytest.raises(ArgumentError, match="reference"):
        spacearm.simulate(robot, 0.1, dt=SIM_DT, controller=MPC(wrong))
    # A step that overshoots the sample instants (DOPRI5's, or an RK4 step longer than dt).
    with pytest.raises(SimulationError, match="divides the law's dt"):
        spacearm.simulate(robot, 0.2, dt=0.08, controller=MPC(problem))
    with pytest.raises(ArgumentError):
        MPC({"horizon": 5})
