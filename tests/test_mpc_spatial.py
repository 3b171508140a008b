"""spacearm.mpc on a spatial case against CasADi/IPOPT (issue 36: "the DDP optimum equals the
CasADi/IPOPT optimum of the same problem to 1e-6, for a planar and a spatial case"; the planar
case is tests/test_mpc.py). spatial6 floating free, 8 knots of 0.1 s: reach a point 11 cm away
with the end effector while the base's angular velocity is penalized (the reactionless
objective) and the joint torques are bounded by 2 N·m (the bound binds). IPOPT solves the same
problem by multiple shooting on spacearm.casadi.rk4_step (the core's RK4 step replayed as CasADi
expressions), exact Hessian, tol 1e-12: an independent optimizer on an independent derivative
(CasADi's AD of the step, not the core's analytic derivatives)."""

import numpy as np
import pytest

import spacearm
import spacearm.mpc as mpc

ca = pytest.importorskip("casadi")

HORIZON, DT, LIMIT = 8, 0.1, 2.0
W_C, W_RATE, W_POINT, W_QD = 1e-2, 10.0, 1e3, 1.0


def test_fddp_optimum_equals_ipopt_on_spatial6_with_a_binding_torque_bound():
    import spacearm.casadi as sc

    robot = spacearm.presets.spatial6()
    x0 = np.asarray(robot.neutral_configuration(), float)
    u0 = np.asarray(robot.zero_velocity(), float)
    tip = robot.n_bodies - 1
    target = robot.point_position(x0, (tip, [0.0, 0.0, 0.0])) + [0.05, -0.05, 0.08]
    problem = mpc.Problem(
        horizon=HORIZON, dt=DT,
        running=[mpc.ControlCost(W_C), mpc.BaseAttitudeCost(0.0, rate_weight=W_RATE)],
        terminal=[mpc.PointCost(tip, target, weight=W_POINT), mpc.JointCost(0.0, x0[7:], weight_qd=W_QD)],
        control_limit=LIMIT,
    )
    sol = mpc.solve(robot, problem, tolerance=1e-20)
    assert sol.converged, sol.stop

    n, nx, nu = robot.n_dof, robot.nx, robot.nu
    step = sc.rk4_step(robot)
    point = sc.point_position(robot, point=(tip, [0.0, 0.0, 0.0]))
    opti = ca.Opti()
    x, u, tau = opti.variable(nx, HORIZON + 1), opti.variable(nu, HORIZON + 1), opti.variable(n, HORIZON)
    opti.subject_to(x[:, 0] == x0)
    opti.subject_to(u[:, 0] == u0)
    cost = 0
    for k in range(HORIZON):
        cost += DT * (0.5 * W_C * ca.sumsqr(tau[:, k]) + 0.5 * W_RATE * ca.sumsqr(u[3:6, k]))
        x_next, u_next = step(x[:, k], u[:, k], tau[:, k], ca.DM.zeros(6), DT)
        opti.subject_to(x[:, k + 1] == x_next)
        opti.subject_to(u[:, k + 1] == u_next)
    cost += 0.5 * W_POINT * ca.sumsqr(point(x[:, HORIZON]) - target) + 0.5 * W_QD * ca.sumsqr(u[6:, HORIZON])
    opti.minimize(cost)
    opti.subject_to(opti.bounded(-LIMIT, ca.vec(tau), LIMIT))
    for k in range(HORIZON + 1):
        opti.set_initial(x[:, k], x0)
        opti.set_initial(u[:, k], u0)
    opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes", "tol": 1e-12, "max_iter": 200})
    best = opti.solve()
    assert best.stats()["success"], best.stats()["return_status"]
    ipopt_cost, ipopt_tau = float(best.value(cost)), np.asarray(best.value(tau)).T

    # measured: 1.2e-8 (cost, relative), 9.7e-8 N·m (controls)
    assert abs(sol.cost - ipopt_cost) <= 1e-6 * ipopt_cost, (sol.cost, ipopt_cost)
    assert np.abs(sol.tau - ipopt_tau).max() < 1e-6, np.abs(sol.tau - ipopt_tau).max()
    assert np.isclose(np.abs(sol.tau).max(), LIMIT), "the bound binds"
    assert np.linalg.norm(sol.x[-1, :3] - x0[:3]) > 0 and np.abs(sol.u[1:, 3:6]).max() > 0  # the base does move
    assert sol.resimulate(robot) < 1e-9
