"""spacearm.mpc.crocoddyl_action_model: a Crocoddyl differential action model backed by
spacearm's forward dynamics and analytic derivatives. Runs only where crocoddyl is importable
(it is not installed with the main environment: benchmarks/mpc_crocoddyl.py says how).

Checks: the state's and the model's Jacobians against Crocoddyl's finite differences; the
optimum of Crocoddyl's FDDP on spacearm's model against spacearm's native FDDP on the same
problem (the same dynamics, two RK4 discretizations of it) and against Crocoddyl's FDDP on
Pinocchio's free-flyer model of the robot (independent dynamics), to 1e-6."""

import numpy as np
import pytest

crocoddyl = pytest.importorskip("crocoddyl")

import spacearm  # noqa: E402
import spacearm.mpc as mpc  # noqa: E402
from spacearm.errors import ArgumentError  # noqa: E402
from spacearm.mpc.crocoddyl import make_state  # noqa: E402

HORIZON, DT = 10, 0.05
W_U, W_Q, W_QD = 1e-2, 100.0, 10.0


def moving_state(robot, seed=0):
    rng = np.random.default_rng(seed)
    z = np.concatenate([robot.neutral_configuration(), robot.zero_velocity()])
    z[7:7 + robot.n_dof] += rng.uniform(-0.3, 0.3, robot.n_dof)
    z[7 + robot.n_dof:] = rng.uniform(-0.2, 0.2, 6 + robot.n_dof)
    return z


def test_the_state_and_model_jacobians_match_finite_differences():
    robot = spacearm.presets.spatial6()
    state = make_state(robot)
    z0 = moving_state(robot)
    z1 = state.integrate(z0, np.random.default_rng(1).uniform(-0.4, 0.4, state.ndx))
    assert np.abs(state.integrate(z0, state.diff(z0, z1)) - z1).max() < 1e-12
    numdiff = crocoddyl.StateNumDiff(state)
    for which in (crocoddyl.Jcomponent.first, crocoddyl.Jcomponent.second):
        assert np.abs(state.Jdiff(z0, z1, which) - numdiff.Jdiff(z0, z1, which)).max() < 1e-6
        dz = state.diff(z0, z1)
        assert np.abs(state.Jintegrate(z0, dz, which) - numdiff.Jintegrate(z0, dz, which)).max() < 1e-6
    # The model's Fx, Fu against central differences of its xout in the tangent coordinates (the
    # RK integrator's own Jacobians are Crocoddyl's, with its first-stage approximation).
    dam = mpc.crocoddyl_action_model(robot, state=state)
    data = dam.createData()
    tau = np.random.default_rng(2).uniform(-1.0, 1.0, robot.n_dof)
    dam.calc(data, z0, tau)
    dam.calcDiff(data, z0, tau)
    fx, fu = data.Fx.copy(), data.Fu.copy()
    assert np.abs(fx).max() > 1.0 and np.abs(fu).max() > 1.0

    def xout(z, c):
        dam.calc(data, z, c)
        return data.xout.copy()

    eps = 1e-5
    for i in range(state.ndx):
        dz = np.zeros(state.ndx)
        dz[i] = eps
        col = (xout(state.integrate(z0, dz), tau) - xout(state.integrate(z0, -dz), tau)) / (2 * eps)
        assert np.abs(col - fx[:, i]).max() < 1e-7 * np.abs(fx).max(), i
    for i in range(robot.n_dof):
        dc = np.zeros(robot.n_dof)
        dc[i] = eps
        col = (xout(z0, tau + dc) - xout(z0, tau - dc)) / (2 * eps)
        assert np.abs(col - fu[:, i]).max() < 1e-7 * np.abs(fu).max(), i
    model = crocoddyl.IntegratedActionModelRK(dam, crocoddyl.RKType.four, DT)
    a = model.createData()
    model.calc(a, z0, tau)
    # The RK4 step of Crocoddyl on this model is spacearm's simulator step to the difference of
    # the two RK4 schemes (Lie-group stages against the quaternion's ambient stages; |ω0| ≤ 0.35 rad/s here).
    from spacearm.sim.simulator import Simulator

    sim = Simulator(robot, dt=DT, mode="floating")
    sim.reset(z0[:7 + robot.n_dof], z0[7 + robot.n_dof:])
    gap = np.abs(state.diff(sim.step(tau), a.xnext))
    assert gap.max() < 1e-6 and gap[12:].max() < 1e-8, gap  # measured 1.9e-7 rad (attitude), 6e-10 (rates)


def problems(robot, mode="floating", discretization="rk4"):
    """The same problem three ways (benchmarks/mpc_crocoddyl.py)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    try:
        import mpc_crocoddyl
    finally:
        sys.path.pop(0)
    return mpc_crocoddyl.Case(robot, HORIZON, DT, mode, discretization)


def test_the_optimum_agrees_with_spacearms_fddp_and_with_pinocchios_model():
    pytest.importorskip("pinocchio")
    case = problems(spacearm.presets.spatial6())
    cost_c, q_c, tau_c, _, _ = case.spacearm()
    cost_b, q_b, tau_b, _, _ = case.crocoddyl(case.spa)
    cost_a, q_a, tau_a, _, _ = case.crocoddyl(case.pin)
    assert cost_c > 1e-3  # a problem with somewhere to go
    for cost, q, tau in ((cost_b, q_b, tau_b), (cost_a, q_a, tau_a)):
        assert abs(cost - cost_c) < 1e-6 * cost_c, (cost, cost_c)
        assert np.abs(q - q_c).max() < 1e-6 and np.abs(tau - tau_c).max() < 1e-6 * np.abs(tau_c).max()


@pytest.mark.parametrize("mode", ["rotation-flying", "flying"])
def test_base_actuation_agrees_with_pinocchios_free_flyer_and_spacearms_fddp(mode):
    """The base torque (rotation-flying) or wrench (flying) as controls, in 𝒥: the model's Fu
    against central differences, and the optimum against spacearm's FDDP and against Crocoddyl
    on Pinocchio's free flyer actuated by that wrench turned into the base frame."""
    pytest.importorskip("pinocchio")
    robot = spacearm.presets.spatial6()
    state = make_state(robot)
    dam = mpc.crocoddyl_action_model(robot, state=state, mode=mode)
    nc = robot.n_dof + (3 if mode == "rotation-flying" else 6)
    assert dam.nu == nc
    data = dam.createData()
    z0 = moving_state(robot)
    c = np.random.default_rng(3).uniform(-1.0, 1.0, nc)
    dam.calcDiff(data, z0, c)
    fu = data.Fu.copy()

    def xout(c):
        dam.calc(data, z0, c)
        return data.xout.copy()

    for i in range(nc):
        dc = np.zeros(nc)
        dc[i] = 1e-5
        col = (xout(c + dc) - xout(c - dc)) / 2e-5
        assert np.abs(col - fu[:, i]).max() < 1e-7 * np.abs(fu).max(), i
    case = problems(robot, mode)
    cost_c, q_c, u_c, _, _ = case.spacearm()
    cost_b, q_b, u_b, _, _ = case.crocoddyl(case.spa)
    cost_a, q_a, u_a, _, _ = case.crocoddyl(case.pin)
    assert cost_c > 1e-3 and np.abs(u_c[:, robot.n_dof:]).max() > 1e-3  # the base actuation is used
    for cost, q, u in ((cost_b, q_b, u_b), (cost_a, q_a, u_a)):
        assert abs(cost - cost_c) < 1e-6 * cost_c, (cost, cost_c)
        assert np.abs(q - q_c).max() < 1e-6 and np.abs(u - u_c).max() < 1e-6 * np.abs(u_c).max()


def test_the_euler_optimum_is_crocoddyls_integrated_euler_on_spacearms_model():
    """spacearm's Problem(discretization="euler") is Crocoddyl's IntegratedActionModelEuler on the
    same state manifold (an independent implementation of the step and of its Jacobians): the
    same optimum to rounding and the solvers' tolerances."""
    case = problems(spacearm.presets.spatial6(), "rotation-flying", "euler")
    cost_c, q_c, u_c, _, _ = case.spacearm()
    cost_b, q_b, u_b, _, _ = case.crocoddyl(case.spa)
    assert cost_c > 1e-3
    # The same model: the optimal costs agree to rounding (measured 4e-14 relative). The
    # trajectories agree to the solvers' stopping tests: the control Hessian h w_u = 5e-4 makes
    # a predicted decrease of 1e-14 a step of ~5e-6 (measured 2.2e-6 rad, 1.6e-6 N·m).
    assert abs(cost_b - cost_c) < 1e-12 * cost_c, (cost_b, cost_c)
    assert np.abs(q_b - q_c).max() < 1e-5 and np.abs(u_b - u_c).max() < 1e-6 * np.abs(u_c).max()
    # Not the RK4 optimum: the discretizations differ at this step.
    cost_rk4 = problems(spacearm.presets.spatial6(), "rotation-flying").spacearm()[0]
    assert abs(cost_rk4 - cost_c) > 1e-4 * cost_c


def test_unsupported_options_are_refused():
    robot = spacearm.presets.spatial6()
    with pytest.raises(ArgumentError, match="not implemented"):
        mpc.crocoddyl_action_model(robot, mode="translation-flying")
    with pytest.raises(ArgumentError, match="CostModelSum"):
        mpc.crocoddyl_action_model(robot, costs=object())
