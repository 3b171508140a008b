"""Identities that tie spacearm's quantities to independent computations done here with numpy:
matrix inverses, linear solves, finite differences of kinematics, and momentum sums. Every
assertion compares against a reference whose magnitude is checked to be non-trivial, so none
of them can pass on an all-zero model."""

import numpy as np
import pytest

from conftest import random_state

SEEDS = [0, 1, 2, 3]


def rel(a, b):
    nb = np.linalg.norm(b)
    assert nb > 1e-6, "reference value is (nearly) zero: the comparison would prove nothing"
    return np.linalg.norm(np.asarray(a) - np.asarray(b)) / nb


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array([aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz])


def advance(x, xd0, qd, h):
    """Configuration after moving for time h at constant base twist and joint rates (the base
    rotation by the exponential map of w0 h, applied in the inertial frame)."""
    out = np.array(x, float)
    out[:3] += h * xd0[:3]
    w = xd0[3:6] * h
    angle = np.linalg.norm(w)
    dq = np.array([0, 0, 0, 1.0]) if angle == 0 else np.concatenate([np.sin(angle / 2) * w / angle, [np.cos(angle / 2)]])
    out[3:7] = quat_mul(dq, x[3:7])
    out[7:] += h * qd
    return out


@pytest.mark.parametrize("seed", SEEDS)
def test_schur_inverse_equals_numerical_inverse(any_robot, seed):
    x, _ = random_state(any_robot, seed)
    h0 = any_robot.mass_matrix(x)[:6, :6]
    assert rel(any_robot.base_inertia_inverse(x), np.linalg.inv(h0)) < 1e-10


@pytest.mark.parametrize("seed", SEEDS)
def test_generalized_inertia_from_blocks_and_spd(any_robot, seed):
    x, _ = random_state(any_robot, seed)
    h = any_robot.mass_matrix(x, method="paper")
    h0, h0m, hm = h[:6, :6], h[:6, 6:], h[6:, 6:]
    expected = hm - h0m.T @ np.linalg.solve(h0, h0m)
    hs = any_robot.generalized_inertia(x)
    assert rel(hs, expected) < 1e-10
    assert np.abs(hs - hs.T).max() < 1e-12 * np.abs(hs).max()
    assert np.linalg.eigvalsh(hs).min() > 0
    # Removing the base's freedom can only lower the inertia felt at the joints: Hm - H* ⪰ 0.
    assert np.linalg.eigvalsh(hm - hs).min() > -1e-10 * np.abs(hm).max()


@pytest.mark.parametrize("seed", SEEDS)
def test_crba_equals_paper_form(any_robot, seed):
    x, _ = random_state(any_robot, seed)
    assert rel(any_robot.mass_matrix(x, "crba"), any_robot.mass_matrix(x, "paper")) < 1e-12


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("method", ["aba", "mass_matrix", "reduced"])
def test_forward_dynamics_solves_the_eom(any_robot, seed, method):
    x, u = random_state(any_robot, seed)
    rng = np.random.default_rng(100 + seed)
    f = rng.uniform(-20, 20, any_robot.nu)
    du = any_robot.forward_dynamics(x, u, f, method=method)
    h = any_robot.mass_matrix(x, method="paper")
    c = any_robot.bias_forces(x, u)
    assert rel(du, np.linalg.solve(h, f - c)) < 1e-9
    # And inverse dynamics gives the force back.
    assert rel(any_robot.inverse_dynamics(x, u, du), f) < 1e-9


@pytest.mark.parametrize("seed", SEEDS)
def test_generalized_bias_from_blocks(any_robot, seed):
    x, u = random_state(any_robot, seed)
    h = any_robot.mass_matrix(x)
    c = any_robot.bias_forces(x, u)
    expected = c[6:] - h[:6, 6:].T @ np.linalg.solve(h[:6, :6], c[:6])
    assert rel(any_robot.generalized_bias(x, u), expected) < 1e-10


@pytest.mark.parametrize("seed", SEEDS)
def test_base_velocity_from_momentum_gives_that_momentum(any_robot, seed):
    x, u = random_state(any_robot, seed)
    rng = np.random.default_rng(200 + seed)
    qd = u[6:]
    P, L = rng.uniform(-30, 30, 3), rng.uniform(-30, 30, 3)
    xd0 = any_robot.base_velocity_from_momentum(x, qd, P=P, L=L)
    mom = any_robot.momentum(x, np.concatenate([xd0, qd]))
    assert rel(mom.P, P) < 1e-10
    assert rel(mom.L_origin, L) < 1e-10


@pytest.mark.parametrize("seed", SEEDS)
def test_momentum_and_energy_equal_mass_matrix_products(any_robot, seed):
    x, u = random_state(any_robot, seed)
    h = any_robot.mass_matrix(x, method="paper")
    hu = h @ u
    mom = any_robot.momentum(x, u)
    assert rel(np.concatenate([mom.P, mom.L_base]), hu[:6]) < 1e-12
    r0, rg = x[:3], any_robot.center_of_mass(x)
    assert rel(mom.L_origin, mom.L_base + np.cross(r0, mom.P)) < 1e-12
    assert rel(mom.L_com, mom.L_base + np.cross(r0 - rg, mom.P)) < 1e-12
    assert any_robot.kinetic_energy(x, u) == pytest.approx(0.5 * u @ hu, rel=1e-12)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("with_momentum", [False, True])
def test_generalized_jacobian_against_finite_differences(any_robot, seed, with_momentum):
    """J* qd (+ the momentum term) is the velocity of the point when the base moves as momentum
    conservation dictates: compare with central differences of the point's position."""
    x, u = random_state(any_robot, seed)
    rng = np.random.default_rng(300 + seed)
    qd = u[6:]
    P, L = (rng.uniform(-20, 20, 3), rng.uniform(-20, 20, 3)) if with_momentum else (np.zeros(3), np.zeros(3))
    xd0 = any_robot.base_velocity_from_momentum(x, qd, P=P, L=L)
    twist = any_robot.point_twist(x, qd, P=P, L=L)
    if not with_momentum:
        assert rel(twist, any_robot.generalized_jacobian(x) @ qd) < 1e-14
    h = 1e-6
    v_fd = (any_robot.point_position(advance(x, xd0, qd, h)) - any_robot.point_position(advance(x, xd0, qd, -h))) / (2 * h)
    assert rel(twist[:3], v_fd) < 1e-7
    # Angular rows: the end-effector body's angular velocity from finite differences of its rotation.
    body = any_robot.describe()["points"][any_robot.point_names.index(any_robot.end_effector)][1]
    b = any_robot.body_index(body)
    r_plus = any_robot.forward_kinematics(advance(x, xd0, qd, h)).body_to_world[b]
    r_minus = any_robot.forward_kinematics(advance(x, xd0, qd, -h)).body_to_world[b]
    r_dot = (r_plus - r_minus) / (2 * h)
    r = any_robot.forward_kinematics(x).body_to_world[b]
    w_skew = r_dot @ r.T
    w_fd = np.array([w_skew[2, 1], w_skew[0, 2], w_skew[1, 0]])
    assert rel(twist[3:], w_fd) < 1e-7


@pytest.mark.parametrize("seed", SEEDS)
def test_point_jacobians_against_finite_differences(any_robot, seed):
    """[J_0X, J_mX] u is the point velocity for an arbitrary (not momentum-conserving) motion."""
    x, u = random_state(any_robot, seed)
    j0, jm = any_robot.point_jacobian(x)
    twist = j0 @ u[:6] + jm @ u[6:]
    h = 1e-6
    v_fd = (any_robot.point_position(advance(x, u[:6], u[6:], h)) - any_robot.point_position(advance(x, u[:6], u[6:], -h))) / (2 * h)
    assert rel(twist[:3], v_fd) < 1e-7


@pytest.mark.parametrize("seed", SEEDS)
def test_zero_torque_floating_keeps_momentum_rate_zero(any_robot, seed):
    """With no base wrench and no external wrench, dP/dt = 0 and dL_origin/dt = 0: checked by
    finite differences of the momentum along the state derivative (not by the EOM alone)."""
    x, u = random_state(any_robot, seed)
    rng = np.random.default_rng(400 + seed)
    tau = rng.uniform(-5, 5, any_robot.n_dof)
    du = any_robot.forward_dynamics(x, u, tau=tau)
    h = 1e-6
    m_plus = any_robot.momentum(advance(x, u[:6], u[6:], h), u + h * du)
    m_minus = any_robot.momentum(advance(x, u[:6], u[6:], -h), u - h * du)
    scale = np.linalg.norm(any_robot.momentum(x, u).P) + 1.0
    assert np.linalg.norm(m_plus.P - m_minus.P) / (2 * h) < 1e-5 * scale
    assert np.linalg.norm(m_plus.L_origin - m_minus.L_origin) / (2 * h) < 1e-4 * (np.linalg.norm(x[:3]) + 1) * scale
    # A base force changes P at exactly that rate.
    F = np.array([3.0, -2.0, 1.0])
    du_f = any_robot.forward_dynamics(x, u, tau=tau, base_wrench=np.concatenate([F, np.zeros(3)]))
    m_plus = any_robot.momentum(advance(x, u[:6], u[6:], h), u + h * du_f)
    m_minus = any_robot.momentum(advance(x, u[:6], u[6:], -h), u - h * du_f)
    assert rel((m_plus.P - m_minus.P) / (2 * h), F) < 1e-6
