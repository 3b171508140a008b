"""The cylinder's slosh parameters (``spacearm.slosh_parameters``, core
``model/slosh_tank.rs::cylinder_slosh``) against the exact linear potential-flow mode, integrated
here by Gauss–Legendre quadrature (docs/flexibility.md, "From a tank to the slosh parameters").

Independent of the formulas under test: only scipy's Bessel functions and zeros of J₁′ and
numpy's Gauss–Legendre nodes. Mode n of an upright flat-bottomed cylinder (radius R, fill h, z
from the bottom, k = ξₙ/R), tank at rest, liquid density ρ, axial acceleration a:

    φ = Φ(r, θ, z) sin ωt,   Φ = cos θ J₁(k r) cosh(k z) / cosh(k h)

(harmonic; ∂Φ/∂r = 0 on the wall since J₁′(ξₙ) = 0; ∂Φ/∂z = 0 on the bottom). With the velocity
u = ∇Φ sin ωt integrated over the liquid:

- momentum amplitude P = ρ ∫ u_x dV;
- kinetic energy max T = ½ρ ∫ |∇Φ|² dV; the surface elevation from linear Bernoulli
  (φ_t + a η = 0) has amplitude η = ω Φ(h)/a, the potential energy max V = ½ρ a ∫ η² dA; T = V
  gives ω² (a Rayleigh quotient: a volume integral over a surface integral), and the kinematic
  condition ∂Φ/∂z = (ω²/a) Φ at z = h is then checked pointwise as a residual;
- angular momentum about the y axis through the liquid's CM (0, 0, h/2):
  H_y = ρ ∫ ((z − h/2) u_x − x w) dV.

The equivalent model, one mass m at height ℓ above the liquid's CM moving as ẋ = ω X cos ωt,
has momentum m ω X, kinetic energy ½ m ω² X² and angular momentum m ℓ ẋ, hence m = P²/(2T) and
ℓ = H_y/P: the same mass and place give the same coupling to the tank's translation and rotation
(the Lagrangian's cross terms), so the same force and moment on it, bottom pressure included.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import jnp_zeros, jv, jvp

import spacearm

R, A, RHO = 0.4, 0.7, 850.0
H_OVER_R = (0.2, 0.5, 1.0, 2.0, 4.0)
MODES = 3
N_R, N_THETA, N_Z = 48, 32, 72
CENTER = np.array([0.15, -0.2, 0.35])  # the liquid's CM in the base frame, for the built models


def _gauss(n, lo, hi):
    x, w = np.polynomial.legendre.leggauss(n)
    return lo + (hi - lo) * (x + 1.0) / 2.0, w * (hi - lo) / 2.0


def potential_flow_mode(radius, h, n, a, rho):
    """m, ℓ, ω², the energies and the residuals of mode n, by quadrature (module docs)."""
    xi = float(jnp_zeros(1, n)[-1])
    k = xi / radius
    r, wr = _gauss(N_R, 0.0, radius)
    th, wth = _gauss(N_THETA, 0.0, 2.0 * np.pi)
    z, wz = _gauss(N_Z, 0.0, h)
    rr, tt, zz = np.meshgrid(r, th, z, indexing="ij")
    dv = np.einsum("i,j,k->ijk", wr, wth, wz) * rr  # r dr dθ dz
    ch = np.cosh(k * zz) / np.cosh(k * h)
    sh = np.sinh(k * zz) / np.cosh(k * h)
    j1 = jv(1, k * r)[:, None, None]  # on the radial nodes, broadcast over θ and z
    dj1 = jvp(1, k * r)[:, None, None]
    u_r = np.cos(tt) * k * dj1 * ch
    u_t = -np.sin(tt) * j1 / rr * ch
    w = np.cos(tt) * j1 * k * sh
    u_x = u_r * np.cos(tt) - u_t * np.sin(tt)
    x = rr * np.cos(tt)
    p = rho * np.sum(dv * u_x)
    t = 0.5 * rho * np.sum(dv * (u_r**2 + u_t**2 + w**2))
    hy = rho * np.sum(dv * ((zz - h / 2.0) * u_x - x * w))
    # The free surface z = h: Φ and ∂Φ/∂z on the (r, θ) grid.
    rs, ts = np.meshgrid(r, th, indexing="ij")
    da = np.einsum("i,j->ij", wr, wth) * rs
    phi_h = np.cos(ts) * jv(1, k * rs)
    dphi_h = np.cos(ts) * jv(1, k * rs) * k * np.tanh(k * h)
    surface = np.sum(da * phi_h**2)
    # The kinematic (η_t = ∂φ/∂z) and dynamic (φ_t + a η = 0) conditions at z = h together:
    # ∂Φ/∂z = (ω²/a) Φ; ω² from them in the surface's least-squares sense ...
    w2_surface = a * np.sum(da * dphi_h * phi_h) / surface
    residual = np.max(np.abs(dphi_h - w2_surface / a * phi_h)) / np.max(np.abs(dphi_h))
    # ... and from the energies (T = V, V = ½ρ a ∫ (ω Φ/a)² dA: a volume over a surface integral).
    w2 = 2.0 * a * t / (rho * surface)
    eta = math.sqrt(w2_surface) * phi_h / a
    v = 0.5 * rho * a * np.sum(da * eta**2)  # with the surface's ω: T = V is then Green's identity
    # The pressure on the tank (at rest, in the acceleration a): p = −ρ φ_t − ρ a (z − h), the
    # hydrostatic part symmetric (no moment); its moment about the liquid's CM, y component, from
    # the wall (outward normal r̂) and the bottom (−ẑ): amplitude −ρ ω (∫_wall (z − h/2) Φ cos θ R dθ dz
    # + ∫_bottom x Φ dA) cos ωt, against the mass's displacement X = −P/(m ω) cos ωt.
    tw, zw = np.meshgrid(th, z, indexing="ij")
    wall = np.sum(np.einsum("j,k->jk", wth, wz) * radius * np.cos(tw) ** 2 * jv(1, xi) * np.cosh(k * zw) / np.cosh(k * h)
                  * (zw - h / 2.0))
    bottom = np.sum(da * np.cos(ts) ** 2 * jv(1, k * rs) / np.cosh(k * h) * rs)
    return {"xi": xi, "mass": p**2 / (2.0 * t), "height": hy / p, "w2": w2, "w2_surface": w2_surface, "T": t, "V": v,
            "surface_residual": residual, "wall_residual": abs(jvp(1, xi)),
            # the moment per unit displacement of the equivalent mass, N·m/m: m ω² ρ (wall + bottom)/P
            "pressure_moment": (p**2 / (2.0 * t)) * w2 * rho * (wall + bottom) / p,
            "wall_moment": (p**2 / (2.0 * t)) * w2 * rho * wall / p}


@pytest.fixture(scope="module")
def flows():
    return {(hr, n): potential_flow_mode(R, hr * R, n, A, RHO) for hr in H_OVER_R for n in range(1, MODES + 1)}


def _tank(hr):
    h = hr * R
    return spacearm.slosh_parameters("cylinder", radius=R, fill_height=h, density=RHO, axial_acceleration=A, modes=MODES)


@pytest.mark.parametrize("hr", H_OVER_R)
def test_modes_equal_the_potential_flow_by_quadrature(flows, hr):
    h = hr * R
    params = _tank(hr)
    m_liquid = RHO * math.pi * R * R * h
    assert params.liquid_mass == pytest.approx(m_liquid, rel=1e-14)
    for n, mode in enumerate(params.modes, start=1):
        f = flows[(hr, n)]
        assert f["wall_residual"] < 1e-14  # ∂Φ/∂r = 0 on the wall
        assert f["surface_residual"] < 1e-11  # the kinematic and dynamic surface conditions agree
        assert f["V"] == pytest.approx(f["T"], rel=1e-12)
        assert mode.frequency**2 == pytest.approx(f["w2"], rel=1e-11)
        assert mode.frequency**2 == pytest.approx(f["w2_surface"], rel=1e-11)
        assert mode.mass == pytest.approx(f["mass"], rel=1e-11)
        assert mode.height == pytest.approx(f["height"], abs=1e-11 * R)
        assert mode.stiffness == pytest.approx(f["mass"] * f["w2"], rel=1e-11)
        assert mode.length == pytest.approx(A / f["w2"], rel=1e-11)
    # The fixed part: the masses add up to the liquid's and the model's CM is the liquid's, with
    # the sloshing masses and heights of the quadrature.
    sloshing = [flows[(hr, n)] for n in range(1, MODES + 1)]
    assert params.fixed_mass + sum(f["mass"] for f in sloshing) == pytest.approx(m_liquid, rel=1e-11)
    moment = params.fixed_mass * params.fixed_height + sum(f["mass"] * f["height"] for f in sloshing)
    assert abs(moment) < 1e-10 * m_liquid * R


def test_the_moment_location_includes_the_bottom_pressure(flows):
    # The wall pressure alone puts the mass at h/2 − (R/ξ) tanh(ξh/2R) (the height quoted without
    # the bottom's pressure); the quadrature's H_y/P is lower by as much again. The hinge height
    # ℓ + a/ω² from the bottom is the convective height "including base pressure" of the seismic
    # tank literature, h [1 − (cosh λ − 2)/(λ sinh λ)], λ = ξh/R (Housner 1963; Malhotra, Wenk &
    # Wieland 2000).
    for (hr, n), f in flows.items():
        h, xi = hr * R, f["xi"]
        wall_only = h / 2 - R / xi * math.tanh(xi * h / (2 * R))
        assert f["height"] < wall_only
        assert (h / 2 - f["height"]) == pytest.approx(2 * (h / 2 - wall_only), rel=1e-11)
        lam = xi * h / R
        hinge_from_bottom = h / 2 + f["height"] + A / f["w2"]
        assert hinge_from_bottom == pytest.approx(h * (1 - (math.cosh(lam) - 2) / (lam * math.sinh(lam))), rel=1e-11)


def _build(params, model, base_mass=1e9):
    b = spacearm.Robot.builder("tank-sat", base_mass=base_mass, base_inertia=[base_mass] * 3)
    params.add_to(b, "prop", center=CENTER, axis=(0, 0, 1), lateral=(1, 0, 0), model=model)
    return b.build()


@pytest.mark.parametrize("hr", [0.5, 2.0])
@pytest.mark.parametrize("model", ["spring-mass", "pendulum"])
def test_built_models_put_the_masses_where_the_flow_does(flows, hr, model):
    params = _tank(hr)
    robot = _build(params, model)
    x = robot.neutral_configuration()
    _, com, joint_pos, _ = robot.forward_kinematics(x)
    names = list(robot.body_names)
    hm = robot.mass_matrix(x)[6:, 6:]  # the joints' block
    m_liquid = params.liquid_mass
    assert robot.total_mass - 1e9 == pytest.approx(m_liquid, rel=1e-6)
    # The whole model's CM is the liquid's (the base's CM is the origin).
    np.testing.assert_allclose(robot.center_of_mass(x) * robot.total_mass / m_liquid, CENTER, atol=1e-9)
    for n in range(1, MODES + 1):
        f, body = flows[(hr, n)], names.index(f"prop_{n}")
        dof = n - 1
        # the mass (or bob) at q = 0 sits at ℓ above the liquid's CM, on the tank axis
        np.testing.assert_allclose(com[body], CENTER + np.array([0.0, 0.0, f["height"]]), atol=1e-10)
        q = x.copy()
        q[7 + dof] = 1e-3  # x = [base position (3), quaternion (4), q]
        stiffness = -robot.passive_forces(q, robot.zero_velocity())[6 + dof] / 1e-3
        if model == "spring-mass":
            assert hm[dof, dof] == pytest.approx(f["mass"], rel=1e-11)
            assert stiffness == pytest.approx(f["mass"] * f["w2"], rel=1e-11)
        else:
            # the hinge a/ω² above the bob: the rod force m a θ = k x then acts there
            rod = joint_pos[body] - com[body]
            np.testing.assert_allclose(rod, [0.0, 0.0, A / f["w2"]], atol=1e-10)
            length = float(rod[2])
            assert hm[dof, dof] == pytest.approx(f["mass"] * length**2, rel=1e-11)
            # a spring-restored joint standing for the acceleration field: k = m a L = m ω² L²
            assert stiffness == pytest.approx(f["mass"] * A * length, rel=1e-11)
    # On a very heavy base the modes run at the flow's frequencies.
    w = np.sort(robot.natural_frequencies(x).frequencies)
    expected = np.sort([math.sqrt(flows[(hr, n)]["w2"]) for n in range(1, MODES + 1)])
    np.testing.assert_allclose(w, expected, rtol=1e-6)


def test_the_pressure_moment_on_the_tank_acts_at_the_hinge(flows):
    # The wall and bottom pressures of the mode (the displaced liquid's weight included: the
    # hydrostatic pressure under the raised surface) put on the tank the moment k X (ℓ + L) about
    # the liquid's CM: the spring force at ℓ plus the displaced weight m a X, or the pendulum's
    # rod force at its hinge (docs/flexibility.md, "Slosh under thrust"). Against the quadrature's
    # own m, ω² and ℓ = H_y/P: ℓ + a/ω², not ℓ (the arm of the free-space stand-in's springs).
    for (hr, n), f in flows.items():
        k = f["mass"] * f["w2"]
        assert f["pressure_moment"] == pytest.approx(k * (f["height"] + A / f["w2"]), rel=1e-11)
        # the displaced weight is part of it: without it the arm would be ℓ
        assert abs(f["pressure_moment"] - k * f["height"]) == pytest.approx(f["mass"] * A, rel=1e-11)


def _moment_on_tank(robot, params, n, model, thrust):
    """The moment (y, about the liquid's CM at the base CM) that mode n's sloshing mass, moved by a
    small X, puts on a tank translating with the acceleration ``A`` along z (``thrust``) or at
    rest, per unit X: by inverse dynamics, the base held from turning and the slosh joint free."""
    names = list(robot.body_names)
    dof, body = n - 1, names.index(f"prop_{n}")
    x0 = robot.neutral_configuration()
    u = robot.zero_velocity()
    out = []
    for dq in (0.0, 1e-6):
        x = x0.copy()
        x[7 + dof] = dq
        du = np.zeros(robot.nu)
        du[2] = A if thrust else 0.0
        tau0 = robot.inverse_dynamics(x, u, du)[6 + dof]
        du[6 + dof] = -tau0 / robot.mass_matrix(x)[6 + dof, 6 + dof]  # the joint free: τ = 0
        f = robot.inverse_dynamics(x, u, du)
        assert abs(f[6 + dof]) < 1e-12 * (1.0 + abs(tau0))
        # the base does not turn: the applied N0 balances the liquid's moment
        out.append((-f[4], robot.forward_kinematics(x)[1][body][0]))
    (m0, x0_), (m1, x1_) = out
    return (m1 - m0) / (x1_ - x0_)


@pytest.mark.parametrize("hr", [0.5, 2.0])
@pytest.mark.parametrize("model", ["spring-mass", "pendulum"])
def test_in_field_models_put_the_pressure_moment_on_the_tank(flows, hr, model):
    # SloshParameters.add_to(thrust=True), the tank accelerated by the thrust: the core's moment
    # on the tank equals the potential flow's wall + bottom pressure moment (both models); the
    # default stand-in (joint springs, no thrust) gives k X ℓ, without the displaced weight.
    params = _tank(hr)
    for thrust in (True, False):
        b = spacearm.Robot.builder("tank-sat", base_mass=500.0, base_inertia=[50.0] * 3)
        params.add_to(b, "prop", center=(0, 0, 0), axis=(0, 0, 1), lateral=(1, 0, 0), model=model, thrust=thrust)
        robot = b.build()
        for n in range(1, MODES + 1):
            f = flows[(hr, n)]
            got = _moment_on_tank(robot, params, n, model, thrust)
            want = f["pressure_moment"] if thrust else f["mass"] * f["w2"] * f["height"]
            assert got == pytest.approx(want, rel=1e-9)


def lid_inertia_ritz(radius, h, order=12, nq=60):
    """The pitching inertia per unit density about the CM of liquid filling a closed cylinder
    (radius, height h), by the Ritz method, independent of the core's series: the lid flow's
    potential Ψ (∇²Ψ = 0, ∂Ψ/∂n = (ŷ × r)·n on the wall, the bottom and the lid) maximizes
    2∮ψ g dA − ∫|∇ψ|² dV, whose maximum is J/ρ = ∫|∇Ψ|² dV (Kelvin): a lower bound that rises
    to J as the trial space grows. Trial functions ψ = cos θ · r Z(z) S(r²/R²) (odd Legendre
    polynomials Z in z/c, Legendre S in 2r²/R² − 1; c = h/2, z from the CM), the θ integrals
    done by hand (∫cos² = ∫sin² = π), r and z by Gauss–Legendre (exact for these polynomials)."""
    from numpy.polynomial import legendre as leg

    c = h / 2.0
    r, wr = _gauss(nq, 0.0, radius)
    z, wz = _gauss(nq, -c, c)
    s = (r / radius) ** 2
    zs = [np.eye(a + 1)[a] for a in range(1, 2 * order, 2)]
    ss = [np.eye(b + 1)[b] for b in range(order)]
    f, fr, fo, fz, g = [], [], [], [], []
    for cz in zs:
        zv, dz = leg.legval(z / c, cz), leg.legval(z / c, leg.legder(cz)) / c
        for cs in ss:
            sv, ds = leg.legval(2 * s - 1, cs), 2.0 * leg.legval(2 * s - 1, leg.legder(cs))
            fo.append(np.outer(sv, zv))  # f / r
            fr.append(np.outer(sv + 2 * s * ds, zv))  # ∂f/∂r
            fz.append(np.outer(r * sv, dz))  # ∂f/∂z
            # g: the wall (z cos θ, f at r = R) and the lid and bottom (∓ r cos θ, f odd in z)
            wall = np.pi * radius * np.sum(wz * radius * leg.legval(1.0, cs) * zv * z)
            lids = -2.0 * np.pi * np.sum(wr * r * sv * leg.legval(1.0, cz) * r * r)
            g.append(wall + lids)
    w = np.outer(wr * r, wz)
    k = np.pi * sum(np.einsum("irz,jrz,rz->ij", d, d, w) for d in (np.array(fr), np.array(fo), np.array(fz)))
    g = np.array(g)
    return float(g @ np.linalg.solve(k, g))


@pytest.mark.parametrize("hr", H_OVER_R)
def test_fixed_inertia_is_the_lid_inertia_less_the_masses(flows, hr):
    # I0 = J − m0 l0² − Σ mn ln², with J by the Ritz method and mn, ln (and so m0, l0) from the
    # potential-flow quadrature: the model's kinetic energy in any motion of the tank is the
    # liquid's (docs/flexibility.md, "The fixed liquid's moment of inertia").
    h = hr * R
    params = _tank(hr)
    m_liquid = RHO * math.pi * R * R * h
    j = RHO * lid_inertia_ritz(R, h)
    sloshing = [flows[(hr, n)] for n in range(1, MODES + 1)]
    m0 = m_liquid - sum(f["mass"] for f in sloshing)
    l0 = -sum(f["mass"] * f["height"] for f in sloshing) / m0
    i0 = j - m0 * l0**2 - sum(f["mass"] * f["height"] ** 2 for f in sloshing)
    rigid = m_liquid * (R * R / 4 + h * h / 12)
    assert params.fixed_inertia == pytest.approx(i0, abs=1e-8 * rigid)
    # The Ritz value is a lower bound: the core's J is not below it.
    j_core = params.fixed_inertia + params.fixed_mass * params.fixed_height**2 + sum(m.mass * m.height**2 for m in params.modes)
    assert j_core >= j - 1e-12 * rigid
    assert 0.0 < params.fixed_inertia < j_core < rigid  # the lid flow lags the rigid body


@pytest.mark.parametrize("model", ["spring-mass", "pendulum"])
def test_built_tank_pitches_with_the_lid_inertia(model):
    # With the sloshing masses held at rest, the built model (masses at ln, fixed mass with I0)
    # has the liquid's rigid-lid pitching inertia J about the liquid's CM, and none about the
    # tank axis (an ideal liquid does not turn with an axisymmetric tank).
    h = 1.0 * R
    params = _tank(1.0)
    b = spacearm.Robot.builder("tank-sat", base_mass=500.0, base_inertia=[50.0, 60.0, 70.0])
    params.add_to(b, "prop", center=(0, 0, 0), axis=(0, 0, 1), lateral=(1, 0, 0), model=model)
    robot = b.build()
    h0 = robot.mass_matrix(robot.neutral_configuration())[3:6, 3:6]
    j = RHO * lid_inertia_ritz(R, h)
    np.testing.assert_allclose(np.diag(h0) - [50.0, 60.0, 70.0], [j, j, 0.0], atol=1e-8 * params.liquid_mass * R * R)
