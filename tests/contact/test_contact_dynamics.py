"""Compliant contact in the core's loop (spacearm.contact.ContactModel, core collision/compliant.rs
and sim/contact.rs): the linear spring–dashpot impact of two bodies of a floating system against
its closed form (restitution and contact time with the reduced mass), the contact force against
the law and against the dynamics, momentum kept through an oblique frictional contact with the
energy ledger closed, the regularized friction's closed-form velocity change, and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import spacearm
from spacearm.contact import ContactModel, Pair
from spacearm.errors import ArgumentError


def balls(M: float = 100.0, m: float = 1.0) -> spacearm.Robot:
    """A floating base with a ball (radius 0.3) at its CM and a slider along x carrying a ball
    (0.2) at its CM: the two meet when q = 0.5, along the line through both CMs."""
    b = spacearm.RobotBuilder("balls", M, np.eye(3) * 10.0)
    b.add_link("slider", parent="base", joint="prismatic", axis=(1, 0, 0), mass=m, inertia=np.eye(3) * 0.1)
    b.add_geometry("base", "sphere", role="collision", radius=0.3)
    b.add_geometry("slider", "sphere", role="collision", radius=0.2)
    return b.build()


def linear_impact_closed_form(k: float, d: float, m_r: float, v0: float):
    """The linear spring–dashpot with no pull, δ(0) = 0, δ̇(0) = v0 (Schwager & Pöschel,
    Granular Matter 9, 2007): the force vanishes (and the contact force ends) when δ̈ = 0, at
    t_c = (π − 2 asin ζ)/ω_d, with the relative velocity reversed to e·v0,
    e = exp(−ζ (π − 2 asin ζ)/√(1 − ζ²)). Without the clamp at zero it would be the textbook
    π/ω_d and exp(−ζπ/√(1 − ζ²))."""
    w = math.sqrt(k / m_r)
    zeta = d / (2.0 * math.sqrt(k * m_r))
    wd = w * math.sqrt(1.0 - zeta * zeta)
    t_c = (math.pi - 2.0 * math.asin(zeta)) / wd
    return t_c, math.exp(-zeta * w * t_c), zeta


@pytest.mark.parametrize("integrator", ["rk4", "dopri5"])
def test_a_linear_spring_dashpot_impact_has_the_closed_form_restitution_and_contact_time(integrator):
    M, m, k, v0, t0, dt = 100.0, 1.0, 1e4, 0.5, 0.0100137, 2e-5
    m_r = M * m / (M + m)
    d = 2.0 * 0.2 * math.sqrt(k * m_r)  # ζ = 0.2
    robot = balls(M, m)
    x0 = robot.neutral_configuration()
    x0[7] = 0.5 + v0 * t0  # the balls touch at t0, within a step: the core locates the onset
    u0 = robot.zero_velocity()
    u0[6] = -v0
    contact = ContactModel(stiffness=k, damping=d, pairs=[Pair("base", "slider")])
    traj = spacearm.simulate(robot, 0.06, x0=x0, u0=u0, dt=dt, integrator=integrator, rtol=1e-11, atol=1e-13, contact=contact)
    t_c, e, zeta = linear_impact_closed_form(k, d, m_r, v0)
    assert 0.02 < t_c < 0.04 and zeta == pytest.approx(0.2)
    q, qd = traj.x[:, 7], traj.u[:, 6]
    # Restitution: the relative velocity after the contact force ends (the balls fly apart freely).
    # (RK4: the kink where the clamped force reaches zero falls inside a step, a local error
    # of second order there.)
    tol = 2e-7 if integrator == "rk4" else 1e-9
    assert qd[-1] / v0 == pytest.approx(e, rel=tol)
    # Contact time: from onset (t0) to the zero of the law's unclamped force k δ + d δ̇, located
    # between the samples on the recorded states (linear interpolation, second order in dt).
    raw = k * (0.5 - q) + d * (-qd)
    i = int(np.flatnonzero((traj.t > t0 + 0.5 * t_c) & (raw <= 0.0))[0])
    t_end = traj.t[i - 1] + (traj.t[i] - traj.t[i - 1]) * raw[i - 1] / (raw[i - 1] - raw[i])
    assert t_end - t0 == pytest.approx(t_c, rel=1e-6)
    # The recorded force is the law on the recorded state, and it is what moved the bodies:
    # the relative acceleration times the reduced mass.
    f = traj.contact_normal_force
    on = f > 0.0
    assert on.sum() > 500 and np.all(traj.contact_count[on] == 1)
    np.testing.assert_allclose(f[on], raw[on], rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(f[on], m_r * traj.du[on, 6], rtol=1e-9, atol=1e-9)
    assert np.all(f[~on] == 0.0)
    # Internal forces: the system's momentum is kept; the energy ledger closes (energy minus the
    # contact forces' work), and the work is the dissipated energy ½ m_r v0² (1 − e²).
    assert traj.meta["drift"]["P"] < 1e-12 and traj.meta["drift"]["L_origin"] < 1e-12
    assert traj.contact_work[-1] == pytest.approx(-0.5 * m_r * v0 ** 2 * (1.0 - e ** 2), rel=1e-6)
    ledger = traj.energy - traj.contact_work
    assert np.ptp(ledger) < 1e-9 * traj.energy[0]
    assert traj.meta["drift"]["energy"] < 1e-9
    assert traj.meta["contact"]["stiffness"] == k and traj.meta["contact"]["law"] == "kelvin_voigt"


def test_the_hunt_crossley_force_is_its_law_and_has_no_jump_at_onset():
    k, c, p, v0, t0 = 2e6, 0.8, 1.5, 0.5, 0.01
    robot = balls()
    x0 = robot.neutral_configuration()
    x0[7] = 0.5 + v0 * t0
    u0 = robot.zero_velocity()
    u0[6] = -v0
    contact = ContactModel(stiffness=k, damping=c, exponent=p, law="hunt_crossley", pairs=[("base", "slider")])
    traj = spacearm.simulate(robot, 0.04, x0=x0, u0=u0, dt=2e-5, contact=contact)
    delta, rate = 0.5 - traj.x[:, 7], -traj.u[:, 6]
    on = delta > 0.0
    np.testing.assert_allclose(traj.contact_normal_force[on], np.maximum(k * delta[on] ** p * (1.0 + c * rate[on]), 0.0), rtol=1e-12)
    # Zero force at first touch (a spring–dashpot would start at d v0), and a rebound slower
    # than the approach but not stopped.
    first = int(np.flatnonzero(on)[0])
    assert traj.contact_normal_force[first] < 1e-3 * traj.contact_normal_force.max()
    assert 0.3 * v0 < traj.u[-1, 6] < v0
    assert traj.meta["drift"]["energy"] < 1e-6


def arm_and_box() -> spacearm.Robot:
    """A floating base with an off-centre box and a two-link arm whose tip ball sweeps into it."""
    b = spacearm.RobotBuilder("arm_box", 50.0, np.diag([5.0, 6.0, 7.0]))
    b.add_link("l1", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.7, 0, 0), com=(0.3, 0, 0), mass=3.0,
               inertia=np.diag([0.02, 0.1, 0.1]))
    b.add_link("l2", parent="l1", joint="revolute", axis=(0, 1, 0), origin=(0.6, 0, 0), com=(0.15, 0, 0), mass=2.0,
               inertia=np.diag([0.01, 0.05, 0.05]))
    b.add_geometry("base", "box", role="collision", size=(1.0, 2.0, 1.0), origin=(0.0, 0.1, 0.05))
    b.add_geometry("l2", "sphere", role="collision", radius=0.1, origin=(0.15, 0.0, 0.0))
    return b.build()


def test_momentum_is_kept_through_an_oblique_frictional_contact_and_the_energy_ledger_closes():
    robot = arm_and_box()
    x0 = robot.neutral_configuration()
    x0[7:] = [0.3, 0.2]
    u0 = robot.zero_velocity()
    u0[6:] = [4.0, 1.0]
    free = spacearm.simulate(robot, 1.0, x0=x0, u0=u0, dt=1e-4)
    contact = ContactModel(stiffness=2e4, damping=30.0, friction=0.5, slip_velocity=0.01, pairs=[("base", "l2")])
    traj = spacearm.simulate(robot, 1.0, x0=x0, u0=u0, dt=1e-4, contact=contact)
    # The contact happened, slid (friction did work) and changed the motion a great deal.
    assert traj.contact_count.max() >= 1 and traj.contact_normal_force.max() > 10.0
    assert np.linalg.norm(traj.x[-1, 7:] - free.x[-1, 7:]) > 0.1
    assert np.linalg.norm(traj.u[-1, 3:6] - free.u[-1, 3:6]) > 0.01
    # Equal and opposite forces at one point: P and L of the floating system are kept, sample
    # by sample, to round-off over the 10⁴ steps (the base's attitude and the arm's motion
    # changed at contact); a force on one body only, or a couple, would change them by O(1).
    assert set(traj.meta["conserved"]) >= {"P", "L_origin", "energy"}
    for name in ("P", "L_origin"):
        assert traj.meta["drift"][name] < 1e-10, (name, traj.meta["drift"][name])
    L = traj.L_origin
    assert np.abs(L - L[0]).max() < 1e-10 * np.abs(L).max()
    # Energy: what the kinetic energy lost is the (negative) work of the contact forces.
    assert traj.contact_work[-1] < -0.05 * traj.energy[0]
    assert traj.meta["drift"]["energy"] < 1e-8
    assert free.meta["drift"]["energy"] < 1e-9


def friction_rig() -> spacearm.Robot:
    """A base too heavy to move (1e9 kg) with a box face at x = 0.5; a ball carried by two
    sliders (x, then y) touches it when x = 0.6 and slides along y on the face."""
    b = spacearm.RobotBuilder("rig", 1e9, np.eye(3) * 1e9)
    b.add_link("sx", parent="base", joint="prismatic", axis=(1, 0, 0), mass=1.0, inertia=np.eye(3) * 0.01)
    b.add_link("sy", parent="sx", joint="prismatic", axis=(0, 1, 0), mass=2.0, inertia=np.eye(3) * 0.01)
    b.add_geometry("base", "box", role="collision", size=(1.0, 4.0, 1.0))
    b.add_geometry("sy", "sphere", role="collision", radius=0.1)
    return b.build()


def test_regularized_friction_changes_the_sliding_velocity_by_its_closed_form():
    # m_y dv/dt = −μ f_n v / √(v² + ε²) with v > 0 throughout integrates to
    # G(v1) = G(v0) − μ J_n / m_y, G(v) = √(v² + ε²) − ε asinh(ε/v), J_n the normal impulse
    # (read from the x-momentum change, the face's normal being x).
    mu, eps, v0, vy0, t0 = 0.4, 0.2, 0.5, 1.0, 0.01
    robot = friction_rig()
    x0 = robot.neutral_configuration()
    x0[7] = 0.6 + v0 * t0
    u0 = robot.zero_velocity()
    u0[6:] = [-v0, vy0]
    contact = ContactModel(stiffness=1e4, damping=40.0, friction=mu, slip_velocity=eps, pairs=[("base", "sy")])
    traj = spacearm.simulate(robot, 0.08, x0=x0, u0=u0, dt=2e-5, contact=contact)
    m_x, m_y = 3.0, 2.0
    j_n = m_x * (traj.u[-1, 6] + v0)
    assert traj.u[-1, 6] > 0.0 and traj.contact_normal_force[-1] == 0.0  # bounced off, apart
    G = lambda v: math.sqrt(v * v + eps * eps) - eps * math.asinh(eps / v)  # noqa: E731
    target = G(vy0) - mu * j_n / m_y
    vy1 = brentq(lambda v: G(v) - target, 1e-6, vy0, xtol=1e-15)
    assert traj.u[-1, 7] == pytest.approx(vy1, rel=1e-8)
    # Unregularized Coulomb would give vy0 − μ J_n / m_y: a different number, which the run is not.
    assert abs(traj.u[-1, 7] - (vy0 - mu * j_n / m_y)) > 1e-3
    # The friction opposed the slip: y-momentum fell while sliding in +y, never rose.
    assert np.all(np.diff(traj.u[:, 7]) <= 1e-15)


def test_bad_contact_input_is_refused_with_the_name():
    robot = balls()
    with pytest.raises(ArgumentError, match="'hand'"):
        spacearm.simulate(robot, 0.01, contact=ContactModel(stiffness=1e4, pairs=[("base", "hand")]))
    with pytest.raises(ArgumentError, match="contact stiffness must be finite and > 0"):
        spacearm.simulate(robot, 0.01, contact=ContactModel(stiffness=-1.0))
    with pytest.raises(ArgumentError, match="contact friction"):
        spacearm.simulate(robot, 0.01, contact=ContactModel(stiffness=1.0, friction=-0.2))
    with pytest.raises(ArgumentError, match="law"):
        spacearm.simulate(robot, 0.01, contact=ContactModel(stiffness=1.0, law="rigid"))
    with pytest.raises(ArgumentError, match="ContactModel"):
        spacearm.simulate(robot, 0.01, contact={"stiffness": 1.0})
    b = spacearm.RobotBuilder("bare", 10.0, np.eye(3))
    b.add_link("l1", mass=1.0, inertia=np.eye(3) * 0.1, origin=(0.5, 0, 0))
    with pytest.raises(ArgumentError, match="collision shapes on at least two bodies"):
        spacearm.simulate(b.build(), 0.01, contact=ContactModel(stiffness=1e4))
    with pytest.raises(ArgumentError, match="a body does not touch itself"):
        spacearm.simulate(robot, 0.01, contact=ContactModel(stiffness=1e4, pairs=[("slider", "slider")]))
