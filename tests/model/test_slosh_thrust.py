"""Slosh under thrust: the pitching stability of a pendulum on a thrusting base, derived here by
hand and compared with the core's linearization (docs/flexibility.md, "Slosh under thrust:
which model holds which moment"; issue 38, item 4).

The closed form (independent of spacearm). A rigid body of mass M and pitch inertia I about its
CM carries a pendulum: a point mass m on a massless rod of length L, hinged on the body's axis
at the distance d from its CM (d > 0 toward the thrust). A thrust F = (M + m) a acts on the body
along its axis (fixed in the body; its line is the axis, so its moment about the body's CM is
zero at every attitude). Planar motion in the inertial frame, ψ the body's pitch, θ the rod's
angle to the body's axis, ê = (−sin ψ, cos ψ) the thrust direction; linearized about the steady
acceleration a (rod tension m a):

- body, moment about its CM: the rod pulls the hinge with m a along the rod,
  I ψ̈ = d ê × (m a u), u = (sin(ψ+θ), −cos(ψ+θ)), so I ψ̈ = −m a d θ;
- body, lateral force: M Ẍ = −F ψ + m a (ψ + θ), so Ẍ = −a ψ + (m/M) a θ;
- bob, lateral: m ẍ = −m a (ψ + θ) with x = X − d ψ + L (ψ + θ), so
  L θ̈ + (L − d) ψ̈ = −a (1 + m/M) θ.

Eliminating ψ̈: θ̈ = −(a/L) S θ with the static stiffness

    S = 1 + m/M − m d (L − d) / I,

and ψ follows θ (two zero eigenvalues: the free pitch). S < 0, the pendulum hinged ahead of the
CM with its bob behind it and m d (L − d) > I (1 + m/M), is the statically unstable pitch of the
textbook (the bob's displaced weight, acting at the hinge, pushes the body further).

A joint spring k_θ = m a L on a base with no thrust (the free-space stand-in) leaves only
internal forces: linearized, the bob acts as a lateral spring m a/L at its own height d − L, so
the bob's equation is the same but the body's moment loses the displaced weight m a L θ:

    I ψ̈ = m a (L − d) θ,   L θ̈ + (L − d) ψ̈ = −a (1 + m/M) θ,
    ω² = (a/L) (1 + m/M + m (L − d)² / I) > 0,

always stable: the moment arm of the bob's height instead of the hinge's.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import spacearm


def _skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _eigenvalues_with_thrust(robot, thrust):
    """The eigenvalues of the core's linearization at rest under a thrust ``thrust`` (N, base
    frame = 𝒥 at rest) along the base axis through the base CM, the thrust turning with the base:
    ``A + B ∂f/∂x`` with ``∂F0/∂δθ = −[F0]×`` (``R0 = exp([δθ]×) R0_ref``, Robot.linearize)."""
    x, n = robot.neutral_configuration(), robot.nu
    f = np.zeros(n)
    f[0:3] = thrust
    lin = robot.linearize(x, np.zeros(n), f, inputs="all")
    dfdz = np.zeros((n, 2 * n))
    dfdz[0:3, 3:6] = -_skew(np.asarray(thrust, dtype=float))
    return np.linalg.eigvals(lin.A + lin.B @ dfdz)


def _nonzero_square(eigs):
    """λ² of the one non-zero pair (checked to be one pair, ±λ)."""
    big = eigs[np.abs(eigs) > 1e-4 * np.max(np.abs(eigs))]
    assert len(big) == 2, eigs
    assert big[0] ** 2 == pytest.approx(big[1] ** 2, rel=1e-9, abs=1e-12)
    lam2 = complex(big[0] ** 2)
    assert abs(lam2.imag) < 1e-9 * abs(lam2.real)
    return lam2.real


def _in_field(m, big_m, inertia, d, length):
    return 1.0 + m / big_m - m * d * (length - d) / inertia


# (base mass M, pitch inertia I, bob mass m, rod L, hinge d from the base CM, acceleration a):
# the first two statically unstable (S < 0), the last two stable.
CASES = [
    (50.0, 0.5, 10.0, 0.6, 0.3, 2.0),
    (200.0, 1.0, 40.0, 0.5, 0.2, 0.7),
    (50.0, 4.0, 10.0, 0.6, 0.5, 2.0),
    (80.0, 6.0, 10.0, 0.4, -0.3, 1.5),
]


@pytest.mark.parametrize("big_m, inertia, m, length, d, a", CASES)
def test_pendulum_on_a_thrusting_base_against_the_closed_form(big_m, inertia, m, length, d, a):
    b = spacearm.Robot.builder("pitch", base_mass=big_m, base_inertia=[inertia] * 3)
    b.add_slosh("bob", model="pendulum", mass=m, position=(0, 0, d), axis=(0, 0, -1), length=length, hinge=(0, 1, 0),
                stiffness=0.0)
    robot = b.build()
    lam2 = _nonzero_square(_eigenvalues_with_thrust(robot, [0.0, 0.0, (big_m + m) * a]))
    s = _in_field(m, big_m, inertia, d, length)
    assert lam2 == pytest.approx(-(a / length) * s, rel=1e-9)
    # The sign of the static stiffness: the first two cases diverge (a real positive root).
    assert (lam2 > 0) == (s < 0)


@pytest.mark.parametrize("big_m, inertia, m, length, d, a", CASES)
def test_the_free_space_stand_in_has_the_bobs_moment_arm(big_m, inertia, m, length, d, a):
    # The joint spring m a L with no thrust (the default of SloshParameters.add_to): always
    # stable, the closed form of the module docs (the moment arm of the bob, not of the hinge).
    b = spacearm.Robot.builder("pitch", base_mass=big_m, base_inertia=[inertia] * 3)
    b.add_slosh("bob", model="pendulum", mass=m, position=(0, 0, d), axis=(0, 0, -1), length=length, hinge=(0, 1, 0),
                stiffness=m * a * length)
    robot = b.build()
    lam2 = _nonzero_square(_eigenvalues_with_thrust(robot, [0.0, 0.0, 0.0]))
    w2 = (a / length) * (1.0 + m / big_m + m * (length - d) ** 2 / inertia)
    assert lam2 == pytest.approx(-w2, rel=1e-9)
    w = robot.natural_frequencies(robot.neutral_configuration()).frequencies
    assert w[0] ** 2 == pytest.approx(w2, rel=1e-9)


# A shallow fill (h/R = 0.2: most of the liquid sloshes, m1 = 0.80 m_L) on the axis of a light base.
R, H, RHO, A = 0.4, 0.08, 850.0, 0.7


def _tank_robot(model, thrust, base_inertia, center_z):
    p = spacearm.slosh_parameters("cylinder", radius=R, fill_height=H, density=RHO, axial_acceleration=A, modes=1)
    b = spacearm.Robot.builder("tank", base_mass=60.0, base_inertia=[base_inertia] * 3)
    p.add_to(b, "prop", center=(0.0, 0.0, center_z), axis=(0, 0, 1), lateral=(1, 0, 0), model=model, thrust=thrust)
    return p, b.build()


@pytest.mark.parametrize("base_inertia", [0.2, 5.0])
@pytest.mark.parametrize("model", ["pendulum", "spring-mass"])
def test_tank_models_under_thrust_have_the_in_field_pitch(model, base_inertia):
    # SloshParameters.add_to(thrust=True) with the thrust M a applied: the closed form with the
    # rigid part (base + fixed liquid m0 at l0, with its own I0) as the body, its CM and inertia by
    # hand, and the hinge at l + L above the liquid's CM; the spring-mass and the pendulum agree
    # (linearly).
    p = spacearm.slosh_parameters("cylinder", radius=R, fill_height=H, density=RHO, axial_acceleration=A, modes=1)
    mode = p.modes[0]
    # The liquid's CM placed so that the rigid part's CM falls midway between the bob and the hinge.
    center_z = (p.fixed_mass * p.fixed_height - (60.0 + p.fixed_mass) * (mode.height + 0.5 * mode.length)) / 60.0
    p, robot = _tank_robot(model, True, base_inertia, center_z)
    m0, z0 = p.fixed_mass, center_z + p.fixed_height
    big_m = 60.0 + m0
    z_rigid = m0 * z0 / big_m
    inertia = base_inertia + 60.0 * z_rigid**2 + m0 * (z0 - z_rigid) ** 2 + p.fixed_inertia
    d = center_z + mode.height + mode.length - z_rigid
    total = big_m + mode.mass
    assert robot.total_mass == pytest.approx(total, rel=1e-14)
    lam2 = _nonzero_square(_eigenvalues_with_thrust(robot, [0.0, 0.0, total * A]))
    s = _in_field(mode.mass, big_m, inertia, d, mode.length)
    assert lam2 == pytest.approx(-(A / mode.length) * s, rel=1e-9)
    assert (lam2 > 0) == (base_inertia < 1.0)  # the light base pitches away, the heavy one holds


def test_thrust_option_is_checked():
    p = spacearm.slosh_parameters("cylinder", radius=R, fill_height=H, density=RHO, axial_acceleration=A)
    b = spacearm.Robot.builder("tank", base_mass=60.0, base_inertia=[5.0] * 3)
    with pytest.raises(spacearm.errors.ArgumentError, match="thrust must be True or False"):
        p.add_to(b, "prop", model="pendulum", thrust="yes")


def test_in_field_pendulum_has_no_spring_and_the_stand_in_has_one():
    # Without the thrust the in-field pendulum has nothing to restore it (frequency 0 in
    # natural_frequencies); the stand-in's spring is m a L. The spring-mass keeps k = m ω² in both.
    for model, stiffness in (("pendulum", 0.0), ("spring-mass", None)):
        p, robot = _tank_robot(model, True, 5.0, 0.0)
        _, robot_free = _tank_robot(model, False, 5.0, 0.0)
        mode = p.modes[0]
        x = robot.neutral_configuration()
        q = x.copy()
        q[7] = 1e-3
        k_field = -robot.passive_forces(q, robot.zero_velocity())[6] / 1e-3
        k_free = -robot_free.passive_forces(q, robot_free.zero_velocity())[6] / 1e-3
        if stiffness is None:
            assert k_field == pytest.approx(mode.stiffness, rel=1e-12)
            assert k_free == pytest.approx(mode.stiffness, rel=1e-12)
        else:
            assert k_field == 0.0
            assert k_free == pytest.approx(mode.mass * A * mode.length, rel=1e-12)
    assert math.isfinite(mode.length)
