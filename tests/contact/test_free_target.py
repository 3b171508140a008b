"""Contact with a free target in the loop (docs/contact.md, "Contact with a free target"; the
core's sim/free_target.rs): the target's 13-state integrated with the robot's, the contact
forces equal and opposite on both. Checked against what the run did not compute: robot + target
momentum summed here from the robot's recorded momentum and the target's mass and inertia, the
linear impact's closed form with the reduced mass, and a torque-free rigid body integrated here
by scipy."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import spacearm
from spacearm.contact import ContactModel, Pair
from spacearm.errors import ArgumentError, ShapeError

I_T = np.diag([0.08, 0.1, 0.12])


def ball_robot(M: float = 100.0, arm: bool = True) -> spacearm.Robot:
    """A floating base with a ball (radius 0.3) at its CM; with ``arm`` a hinged link whose tip
    ball (0.1) sweeps the space beside it."""
    b = spacearm.RobotBuilder("bus", M, np.eye(3) * 0.4 * M * 0.09)
    b.add_geometry("base", "sphere", role="collision", radius=0.3)
    if arm:
        b.add_link("l1", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.3, 0, 0), mass=3.0,
                   inertia=np.diag([0.02, 0.1, 0.1]))
        b.add_geometry("l1", "sphere", role="collision", radius=0.1, origin=(0.3, 0.0, 0.0))
    return b.build()


def ball_target(m: float = 2.0, radius: float = 0.2, name: str = "target") -> spacearm.Robot:
    b = spacearm.RobotBuilder(name, m, I_T, base_name=name)
    b.add_geometry(name, "sphere", role="collision", radius=radius, name="shell")
    return b.build()


def state(r, v, w=(0.0, 0.0, 0.0), quat=(0.0, 0.0, 0.0, 1.0)):
    return np.concatenate([r, quat, v, w]).astype(float)


def target_momentum(s: np.ndarray, m: float, inertia: np.ndarray):
    """P, L about the origin and kinetic energy of the rigid body at each 13-state row."""
    R = Rotation.from_quat(s[:, 3:7]).as_matrix()
    r, v, w = s[:, 0:3], s[:, 7:10], s[:, 10:13]
    Iw = np.einsum("kij,jl,kml->kim", R, inertia, R)
    spin = np.einsum("kij,kj->ki", Iw, w)
    p = m * v
    return p, np.cross(r, p) + spin, 0.5 * (m * (v * v).sum(1) + (w * spin).sum(1))


def test_momentum_of_robot_and_target_is_kept_through_an_oblique_frictional_contact(tmp_path):
    robot, m = ball_robot(), 2.0
    # The target, spinning, comes at the arm's tip ball off its line of centres: the contact
    # pushes and rubs (friction), turning both.
    u0 = robot.zero_velocity()
    u0[5], u0[6] = 0.02, 0.4
    s0 = state([0.8, 0.4, 0.03], [0.0, -0.5, 0.0], [0.3, -0.2, 0.5])
    contact = ContactModel(stiffness=2e4, damping=30.0, friction=0.4, slip_velocity=1e-2, pairs=[Pair("l1", "target")])
    traj = spacearm.simulate(robot, 0.6, u0=u0, dt=1e-4, record_every=5, contact=contact, target=ball_target(m), target_state=s0)
    s = traj["target"]
    assert s.shape == (traj.t.size, 13)
    p_t, l_t, e_t = target_momentum(s, m, I_T)
    P, L = traj.P + p_t, traj.L_origin + l_t
    on = traj.contact_normal_force > 0
    assert 20 < on.sum() < traj.t.size - 20, "the target touched the arm for a while, and left it"
    # The contact changed both: the target's momentum by a fair part of itself.
    assert np.linalg.norm(p_t[-1] - p_t[0]) > 0.3 * np.linalg.norm(p_t[0])
    assert np.linalg.norm(l_t[-1] - l_t[0]) > 0.1 * np.abs(l_t).max()
    scale_p = np.abs(traj.P).max() + np.abs(p_t).max()
    scale_l = np.abs(traj.L_origin).max() + np.abs(l_t).max()
    assert np.abs(P - P[0]).max() < 1e-12 * scale_p
    assert np.abs(L - L[0]).max() < 1e-12 * scale_l
    # The ledger records are these sums; the drifts are robot + target's.
    np.testing.assert_allclose(traj["ledger_momentum"], np.hstack([P, L]), rtol=0, atol=1e-13 * max(scale_p, scale_l))
    assert traj.meta["drift"]["P"] < 1e-12 and traj.meta["drift"]["L_origin"] < 1e-12
    # Energy: (robot + target) − contact work is kept; the work is the dissipated energy.
    np.testing.assert_allclose(traj["ledger_energy"], traj.energy + e_t, rtol=1e-13)
    ledger = traj.energy + e_t - traj.contact_work
    assert traj.contact_work[-1] < -1e-3 * ledger[0]
    assert np.ptp(ledger) < 1e-9 * ledger[0]
    assert traj.meta["drift"]["energy"] < 1e-9
    # The target's records save and load with the run.
    traj.save(tmp_path / "run.npz")
    back = spacearm.Trajectory.load(tmp_path / "run.npz")
    np.testing.assert_array_equal(back["target"], s)
    np.testing.assert_array_equal(back["ledger_momentum"], traj["ledger_momentum"])


@pytest.mark.parametrize("integrator", ["rk4", "dopri5"])
def test_a_ball_target_hitting_a_ball_on_a_heavy_base_has_the_closed_form_restitution_and_contact_time(integrator):
    M, m, k, v0, t0, dt = 1e4, 1.0, 1e4, 0.5, 0.0100137, 2e-5
    m_r = M * m / (M + m)
    d = 2.0 * 0.2 * math.sqrt(k * m_r)  # ζ = 0.2
    robot = ball_robot(M, arm=False)
    # The target's ball (0.2) comes along −x at v0 to the base's (0.3): they touch at t0, within
    # a step (the onset is located).
    s0 = state([0.5 + v0 * t0, 0.0, 0.0], [-v0, 0.0, 0.0])
    contact = ContactModel(stiffness=k, damping=d)
    traj = spacearm.simulate(robot, 0.06, dt=dt, integrator=integrator, rtol=1e-11, atol=1e-13, contact=contact,
                             target=ball_target(m), target_state=s0)
    w = math.sqrt(k / m_r)
    zeta = d / (2.0 * math.sqrt(k * m_r))
    wd = w * math.sqrt(1.0 - zeta * zeta)
    t_c = (math.pi - 2.0 * math.asin(zeta)) / wd
    e = math.exp(-zeta * w * t_c)
    s = traj["target"]
    gap = s[:, 0] - traj.x[:, 0]  # centre distance; 0.5 at touch
    rate = s[:, 7] - traj.u[:, 0]
    tol = 2e-7 if integrator == "rk4" else 5e-9
    assert rate[-1] / v0 == pytest.approx(e, rel=tol)
    raw = k * (0.5 - gap) + d * (-rate)
    i = int(np.flatnonzero((traj.t > t0 + 0.5 * t_c) & (raw <= 0.0))[0])
    t_end = traj.t[i - 1] + (traj.t[i] - traj.t[i - 1]) * raw[i - 1] / (raw[i - 1] - raw[i])
    assert t_end - t0 == pytest.approx(t_c, rel=1e-6)
    # Equal and opposite: the base got the impulse the target lost.
    assert M * traj.u[-1, 0] == pytest.approx(-m * (s[-1, 7] + v0), rel=1e-9)
    # Central: no turning.
    assert np.abs(s[:, 10:]).max() == 0.0 and np.abs(traj.u[:, 3:6]).max() < 1e-15


def torque_free(s0: np.ndarray, inertia: np.ndarray, t: np.ndarray) -> np.ndarray:
    """A torque-free rigid body by scipy (quaternion and Euler's equations in body axes)."""
    inv = np.linalg.inv(inertia)
    R0 = Rotation.from_quat(s0[3:7])
    wb0 = R0.inv().apply(s0[10:13])

    def f(_, y):
        q, wb = y[:4], y[4:]
        x, yq, z, ww = q
        # q̇ = ½ q ⊗ [ω_body; 0] (Hamilton, [x, y, z, w])
        Om = np.array([[0, wb[2], -wb[1], wb[0]], [-wb[2], 0, wb[0], wb[1]], [wb[1], -wb[0], 0, wb[2]], [-wb[0], -wb[1], -wb[2], 0]])
        return np.concatenate([0.5 * Om @ q, inv @ (-np.cross(wb, inertia @ wb))])

    sol = solve_ivp(f, (0, t[-1]), np.concatenate([s0[3:7], wb0]), t_eval=t, rtol=1e-12, atol=1e-14, method="DOP853")
    q = sol.y[:4].T / np.linalg.norm(sol.y[:4].T, axis=1)[:, None]
    w = Rotation.from_quat(q).apply(sol.y[4:].T)
    r = s0[:3] + np.outer(t, s0[7:10])
    return np.hstack([r, q, np.tile(s0[7:10], (t.size, 1)), w])


def test_without_touching_the_target_flies_torque_free():
    robot = ball_robot()
    q0 = Rotation.from_euler("xyz", [0.3, -0.2, 0.5]).as_quat()
    s0 = state([3.0, -2.0, 0.5], [0.1, 0.0, -0.05], [0.8, -1.2, 1.5], q0)
    contact = ContactModel(stiffness=1e4, pairs=[Pair("base", "target")])
    traj = spacearm.simulate(robot, 2.0, dt=1e-3, contact=contact, target=ball_target(), target_state=s0)
    s = traj["target"]
    assert np.all(traj.contact_count == 0)
    ref = torque_free(s0, I_T, traj.t)
    sign = np.sign((s[:, 3:7] * ref[:, 3:7]).sum(1))[:, None]
    np.testing.assert_allclose(s[:, 3:7], sign * ref[:, 3:7], rtol=0, atol=1e-9)
    np.testing.assert_allclose(s[:, 10:13], ref[:, 10:13], rtol=0, atol=1e-9)
    np.testing.assert_allclose(s[:, :3], ref[:, :3], rtol=0, atol=1e-12)
    # Its angular momentum in the inertial frame is constant to the integrator's accuracy.
    _, l_t, _ = target_momentum(s, 2.0, I_T)
    l_spin = l_t - np.cross(s[:, :3], 2.0 * s[:, 7:10])
    assert np.abs(l_spin - l_spin[0]).max() < 1e-10 * np.linalg.norm(l_spin[0])


def test_bad_input_is_refused():
    robot, target = ball_robot(), ball_target()
    s0 = state([3.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    contact = ContactModel(stiffness=1e4)
    with pytest.raises(ArgumentError, match="give contact"):
        spacearm.simulate(robot, 0.1, target=target, target_state=s0)
    with pytest.raises(ArgumentError, match="go together"):
        spacearm.simulate(robot, 0.1, contact=contact, target=target)
    with pytest.raises(ShapeError, match="target_state"):
        spacearm.simulate(robot, 0.1, contact=contact, target=target, target_state=s0[:12])
    with pytest.raises(ArgumentError, match="no body or collision geometry named 'hull'.*'target'"):
        spacearm.simulate(robot, 0.1, contact=ContactModel(stiffness=1e4, pairs=[Pair("l1", "hull")]), target=target, target_state=s0)
    b = spacearm.RobotBuilder("bare", 1.0, np.eye(3) * 0.01)
    with pytest.raises(ArgumentError, match="no collision geometry"):
        spacearm.simulate(robot, 0.1, contact=contact, target=b.build(), target_state=s0)
    # The pair by the target's geometry name works, and a pair within the target is refused.
    traj = spacearm.simulate(robot, 0.01, contact=ContactModel(stiffness=1e4, pairs=[Pair("l1", "shell")]), target=target, target_state=s0)
    assert traj["target"].shape == (traj.t.size, 13)
    with pytest.raises(ArgumentError, match="one body"):
        spacearm.simulate(robot, 0.1, contact=ContactModel(stiffness=1e4, pairs=[Pair("target", "shell")]), target=target, target_state=s0)
