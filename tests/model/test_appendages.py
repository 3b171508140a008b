"""Hinged panels, rigid-finite-element beams and Spong's compliant joints (docs/flexibility.md;
the core's ``model/appendage.rs``) against independent sources:

- the panel's box inertia and hinge stiffness by hand, and its frequency on a free hub against the
  two-body closed form ``√(k / I_red)``, ``I_red = det M₂ / 1ᵀM₂1``;
- a clamped beam's first bending and torsion frequencies against Euler–Bernoulli
  ``(1.8751)² √(EI/(ρA L⁴))`` and ``(π/2) √(GJ/(ρJ L²))`` as N grows (the error falls like 1/N²);
- the Kane–Ryan–Banerjee spin-up beam (J. Guidance 10(2):139–151, 1987): spacearm's RFEM chain with
  the hub motion prescribed, against a reference written independently here (an assumed-modes
  Rayleigh–Ritz model with the geometric-stiffening matrix, integrated by scipy); the same
  assumed-modes model without the stiffening diverges;
- a rotor–spring–link on a clamped base: the free-motor frequency ``√(k (1/I + 1/B))`` and the
  held-motor frequency ``√(k/I)``; undamped runs keep momentum and energy (a sanity check only);
- builder and TOML give the same model.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import eigh

import spacearm
from spacearm import errors

BETA1 = 1.875104068711961


def clamped_builder(name="clamped"):
    """A base so heavy that it is a clamp to 1e-9 (its free-base correction of H*)."""
    return spacearm.Robot.builder(name, base_mass=1e12, base_inertia=[1e12, 1e12, 1e12])


# ---- panels ----------------------------------------------------------------------------------


def test_panel_geometry_inertia_and_frequency_stiffness():
    b = spacearm.Robot.builder("sat", base_mass=100.0, base_inertia=[8.0, 9.0, 10.0])
    b.add_panel("wing", hinge_position=(0.5, 0, 0), hinge_axis=(0, 0, 1), direction=(0, 1, 0),
                size=(2.0, 1.0, 0.02), mass=6.0, frequency=1.5, damping=0.1)
    robot = b.build()
    link = robot.description.links[0]
    m, (l, w, t) = 6.0, (2.0, 1.0, 0.02)
    assert link.joint == "wing_hinge" and not link.actuated
    assert np.allclose(link.com, [0, l / 2, 0], atol=1e-15)
    # length along y (direction), width along z (hinge), thickness along direction × hinge = x.
    want = np.diag([m / 12 * (l**2 + w**2), m / 12 * (w**2 + t**2), m / 12 * (l**2 + t**2)])
    assert np.allclose(link.inertia, want, rtol=1e-12, atol=1e-15)
    i_hinge = m / 12 * (l**2 + t**2) + m * (l / 2) ** 2
    assert link.stiffness == pytest.approx(i_hinge * 1.5**2, rel=1e-12)
    assert link.damping == 0.1
    (g,) = robot.description.geometries
    assert g.shape == "box" and np.allclose(g.size, [l, w, t])


def test_panel_on_a_free_hub_matches_the_two_body_closed_form():
    mh, ih, a = 50.0, 4.0, 0.6
    mp, l, w, t, k = 8.0, 1.8, 0.9, 0.03, 25.0
    b = spacearm.Robot.builder("hub", base_mass=mh, base_inertia=[3.0, 3.5, ih])
    b.add_panel("wing", hinge_position=(a, 0, 0), hinge_axis=(0, 0, 1), direction=(1, 0, 0), size=(l, w, t), mass=mp,
                stiffness=k)
    robot = b.build()
    mu = mh * mp / (mh + mp)
    i1 = mp / 12 * (l**2 + t**2)  # the plate's moment about its CM along the hinge (its width, z)
    d = l / 2
    m2 = np.array([[mu * a * a + ih, mu * a * d], [mu * a * d, mu * d * d + i1]])
    i_red = np.linalg.det(m2) / m2.sum()
    assert robot.natural_frequencies().frequencies[0] == pytest.approx(np.sqrt(k / i_red), rel=1e-10)


def test_panel_errors_name_the_panel():
    b = spacearm.Robot.builder("sat", base_mass=100.0, base_inertia=[8.0, 9.0, 10.0])
    with pytest.raises(errors.ModelError, match="panel 'p'.*perpendicular"):
        b.add_panel("p", hinge_position=(0, 0, 0), hinge_axis=(0, 0, 1), direction=(0, 1, 1), size=(1, 1, 0.1), mass=1.0,
                    stiffness=1.0)
    with pytest.raises(errors.SpacearmError, match="stiffness or frequency"):
        b.add_panel("p", hinge_position=(0, 0, 0), hinge_axis=(0, 0, 1), direction=(0, 1, 0), size=(1, 1, 0.1), mass=1.0)
    with pytest.raises(errors.SpacearmError, match="size"):
        b.add_panel("p", hinge_position=(0, 0, 0), hinge_axis=(0, 0, 1), direction=(0, 1, 0), mass=1.0, stiffness=1.0)


# ---- beams -----------------------------------------------------------------------------------

EI, RHO_A, L = 1.4e4, 1.2, 10.0


def cantilever(n, *, bending_axes=((0, 0, 1),), gj=None, rho_j=0.0, ei=EI):
    b = clamped_builder()
    b.add_beam("boom", root_position=(0.5, 0, 0), axis=(1, 0, 0), length=L, segments=n, EI=ei, rho_A=RHO_A,
               bending_axes=bending_axes, GJ=gj, rho_J=rho_j)
    return b.build()


def test_beam_mass_geometry_and_springs():
    robot = cantilever(4, bending_axes=None, gj=50.0, rho_j=0.01)
    links = robot.description.links
    assert sum(link.mass for link in links) == pytest.approx(RHO_A * L, rel=1e-14)
    x = robot.neutral_configuration()
    assert np.allclose(robot.point_position(x, "boom_tip"), [0.5 + L, 0, 0], atol=1e-12)
    moving = [link for link in links if link.type != "fixed"]
    assert len(moving) == 3 * 4 and not any(link.actuated for link in moving)
    l = L / 4
    assert sorted({link.stiffness for link in moving}) == pytest.approx(sorted({50.0 / l, EI / l}))
    # The joints of station i sit at (i - 1/2) l from the root; the elements' CMs midway.
    kin = robot.forward_kinematics(x)
    stations = [robot.body_index(f"boom_{i}") for i in range(1, 5)]
    assert np.allclose(kin.joint_position_in_world[stations, 0], [0.5 + (i - 0.5) * l for i in range(1, 5)], atol=1e-12)
    assert np.allclose(kin.com_in_world[stations, 0], [0.5 + i * l for i in range(1, 4)] + [0.5 + L - l / 4], atol=1e-12)


@pytest.mark.parametrize("n", [2, 4, 8, 16, 32])
def test_cantilever_first_bending_frequency_converges_to_euler_bernoulli(n):
    want = BETA1**2 * np.sqrt(EI / (RHO_A * L**4))
    got = cantilever(n).natural_frequencies().frequencies[0]
    err = abs(got - want) / want
    # RFEM with springs EI/l at the segment middles: the error falls like 1/N² (0.23/N² here).
    assert err < 1.0 / n**2, (n, got, want, err)
    if n >= 8:
        assert err > 0.1 / n**2  # a real discretization, not a formula copied into the model


def test_cantilever_error_falls_like_one_over_n_squared():
    want = BETA1**2 * np.sqrt(EI / (RHO_A * L**4))
    errs = [abs(cantilever(n).natural_frequencies().frequencies[0] - want) / want for n in (8, 16, 32)]
    assert errs[0] / errs[1] == pytest.approx(4.0, rel=0.1) and errs[1] / errs[2] == pytest.approx(4.0, rel=0.1)


def test_torsion_and_second_plane_frequencies():
    gj, rho_j = 80.0, 0.02
    robot = cantilever(24, bending_axes=[(0, 1, 0), (0, 0, 1)], ei=[EI, 4 * EI], gj=gj, rho_j=rho_j)
    w = np.sort(robot.natural_frequencies().frequencies)
    bend = BETA1**2 * np.sqrt(EI / (RHO_A * L**4))
    twist = np.pi / 2 * np.sqrt(gj / (rho_j * L**2))
    for want in (bend, 2 * bend, twist):
        assert np.min(np.abs(w - want)) / want < 2e-3, (want, w[:6])


def test_beam_errors():
    b = clamped_builder()
    with pytest.raises(errors.ModelError, match="rho_J"):
        b.add_beam("b", root_position=(0, 0, 0), axis=(1, 0, 0), length=1.0, segments=2, EI=1.0, rho_A=1.0, GJ=1.0)
    with pytest.raises(errors.ModelError, match="perpendicular"):
        b.add_beam("b", root_position=(0, 0, 0), axis=(1, 0, 0), length=1.0, segments=2, EI=1.0, rho_A=1.0,
                   bending_axes=[(1, 1, 0)])
    with pytest.raises(errors.ModelError, match="segments"):
        b.add_beam("b", root_position=(0, 0, 0), axis=(1, 0, 0), length=1.0, segments=0, EI=1.0, rho_A=1.0)


# ---- the Kane-Ryan-Banerjee spin-up beam -----------------------------------------------------

OMEGA_S, T_UP, T_END = 6.0, 15.0, 20.0


def hub_motion(t):
    """θ, Ω, Ω̇ of Kane, Ryan & Banerjee's spin-up: Ω = (Ω_s/T)(t − (T/2π) sin(2πt/T)) for t ≤ T."""
    if t <= T_UP:
        s = 2 * np.pi / T_UP
        theta = OMEGA_S / T_UP * (t**2 / 2 + (np.cos(s * t) - 1) / s**2)
        return theta, OMEGA_S / T_UP * (t - np.sin(s * t) / s), OMEGA_S / T_UP * (1 - np.cos(s * t))
    theta_T = OMEGA_S / T_UP * (T_UP**2 / 2)
    return theta_T + OMEGA_S * (t - T_UP), OMEGA_S, 0.0


def krb_spacearm(n, times):
    """The RFEM beam on a hub joint, the hub's motion prescribed: the base and the hub joint
    follow the given motion (u̇ = Ω̇ on the hub row), the beam joints obey their rows of
    ``H u̇ + c = Q``: ``H_bb q̈_b = -(inverse dynamics at q̈_b = 0)_b``."""
    b = clamped_builder("krb")
    b.add_link("hub", joint="revolute", axis=(0, 0, 1), mass=1.0, inertia=[1.0, 1.0, 1.0])
    b.add_beam("beam", parent="hub", root_position=(0, 0, 0), axis=(1, 0, 0), length=L, segments=n, EI=EI,
               rho_A=RHO_A, bending_axes=[(0, 0, 1)])
    robot = b.build()
    hub = 6  # u index of the hub joint; the beam joints follow
    x0 = robot.neutral_configuration()

    def state(t, y):
        theta, omega, alpha = hub_motion(t)
        x = x0.copy()
        x[7], x[8:] = theta, y[:n]
        u = np.zeros(robot.nu)
        u[hub], u[hub + 1:] = omega, y[n:]
        return x, u, alpha

    def rhs(t, y):
        x, u, alpha = state(t, y)
        du = np.zeros(robot.nu)
        du[hub] = alpha
        f0 = robot.inverse_dynamics(x, u, du)[hub + 1:]
        h = robot.mass_matrix(x)[hub + 1:, hub + 1:]
        return np.concatenate([y[n:], -np.linalg.solve(h, f0)])

    sol = solve_ivp(rhs, (0, T_END), np.zeros(2 * n), method="DOP853", t_eval=times, rtol=1e-9, atol=1e-11)
    tip = []
    for t, y in zip(sol.t, sol.y.T):
        x, _, _ = state(t, y)
        p = robot.point_position(x, "beam_tip")
        c, s = np.cos(x[7]), np.sin(x[7])
        tip.append(-s * p[0] + c * p[1])  # the deflection along the hub's y axis
    return np.array(tip)


def krb_assumed_modes(times, stiffening=True, n_terms=6, n_modes=3):
    """Independent reference: v(x, t) = Σ ψ_k(x) η_k(t), Rayleigh–Ritz with the mass M, bending
    stiffness K, the geometric stiffening G = ∫ ρA (L² − x²)/2 φ'ᵢ φ'ⱼ dx of the centrifugal
    tension, the centrifugal softening −Ω² M and the Euler load −Ω̇ ∫ ρA x φ dx (Kane, Ryan &
    Banerjee 1987, a hub of zero radius): M q̈ + (K + Ω² (G − M)) q = −Ω̇ b. The trial functions
    are φ_i = (x/L)^(i+1), i = 1..6; the motion is kept in the span of the first three
    non-rotating modes ψ_k of (K, M) (their higher ones only make the integration stiff)."""
    xg, wg = np.polynomial.legendre.leggauss(40)
    x = (xg + 1) * L / 2
    wq = wg * L / 2
    p = np.arange(2, n_terms + 2)
    phi = (x[:, None] / L) ** p
    dphi = p * x[:, None] ** (p - 1) / L**p
    ddphi = p * (p - 1) * x[:, None] ** (p - 2) / L**p
    mm = RHO_A * (phi * wq[:, None]).T @ phi
    kk = EI * (ddphi * wq[:, None]).T @ ddphi
    gg = RHO_A * (dphi * (wq * (L**2 - x**2) / 2)[:, None]).T @ dphi
    bb = RHO_A * (phi * (wq * x)[:, None]).sum(axis=0)
    _, vecs = eigh(kk, mm)
    psi = vecs[:, :n_modes]  # mass-normalized: ψᵀ M ψ = E
    k_m, g_m, b_m = psi.T @ kk @ psi, psi.T @ gg @ psi, psi.T @ bb
    g_m = g_m if stiffening else 0.0 * g_m

    def rhs(t, y):
        _, omega, alpha = hub_motion(t)
        return np.concatenate([y[n_modes:], -(k_m + omega**2 * (g_m - np.eye(n_modes))) @ y[:n_modes] - alpha * b_m])

    sol = solve_ivp(rhs, (0, T_END), np.zeros(2 * n_modes), method="DOP853", t_eval=times, rtol=1e-10, atol=1e-12)
    return (psi.sum(axis=0) @ sol.y[:n_modes])  # φ_i(L) = 1


def test_krb_spin_up_matches_the_stiffened_assumed_modes_and_the_linear_one_diverges():
    times = np.linspace(0, T_END, 201)
    ref = krb_assumed_modes(times)
    peak = np.max(np.abs(ref))
    assert 0.2 < peak < 1.0 and ref[np.argmax(np.abs(ref))] < 0  # the beam lags the spin-up
    # The RFEM chain converges on the reference: 7 % of the peak at N = 4, 2 % at N = 8 (0.9 %
    # at N = 12, docs/flexibility.md).
    runs = {n: krb_spacearm(n, times) for n in (4, 8)}
    dev = {n: np.max(np.abs(tip - ref)) / peak for n, tip in runs.items()}
    assert dev[8] < 0.03 and dev[4] > 2 * dev[8], dev
    tip = runs[8]
    assert np.max(np.abs(tip[times > T_UP])) < 0.5 * peak  # bounded once the spin-up ends
    linear = krb_assumed_modes(times, stiffening=False)
    assert np.max(np.abs(linear)) > 20 * peak  # Ω_s = 6 rad/s > ω₁ ≈ 3.8 rad/s: K − Ω²M is indefinite


# ---- Spong's compliant joint -----------------------------------------------------------------


def rotor_spring_link(k=40.0, rotor=0.05, damping=0.0, gear_ratio=1.0):
    b = clamped_builder("spong")
    b.add_link("arm", joint="revolute", axis=(0, 0, 1), origin=(0.2, 0, 0), com=(0.5, 0, 0), mass=2.0,
               inertia=[0.01, 0.2, 0.2], compliant={"stiffness": k, "rotor_inertia": rotor, "damping": damping,
                                                     "gear_ratio": gear_ratio})
    return b.build()


def test_compliant_joint_expands_into_motor_and_deflection():
    robot = rotor_spring_link(gear_ratio=3.0)
    d = robot.description
    assert [link.name for link in d.links] == ["arm_rotor", "arm"]
    assert robot.joint_names == ["arm_joint", "arm_joint_deflection"]
    assert robot.actuated_dofs.tolist() == [True, False]
    assert d.links[0].inertia[2, 2] == pytest.approx(9 * 0.05) and d.links[1].stiffness == 40.0


@pytest.mark.parametrize("gear_ratio", [1.0, 4.0])
def test_rotor_spring_link_frequencies_match_the_closed_form(gear_ratio):
    k, rotor = 40.0, 0.05
    robot = rotor_spring_link(k, rotor, gear_ratio=gear_ratio)
    i_link = 0.2 + 2.0 * 0.5**2  # about the joint axis
    j = gear_ratio**2 * rotor
    free = robot.natural_frequencies(actuated="free").frequencies
    assert free[0] == pytest.approx(0.0, abs=1e-6)
    assert free[1] == pytest.approx(np.sqrt(k * (1 / i_link + 1 / j)), rel=1e-8)
    held = robot.natural_frequencies().frequencies
    assert held[0] == pytest.approx(np.sqrt(k / i_link), rel=1e-8)


def test_undamped_compliant_arm_on_a_free_base_conserves_momentum_and_energy():
    b = spacearm.Robot.builder("free", base_mass=20.0, base_inertia=[2.0, 2.5, 3.0])
    b.add_link("a1", joint="revolute", axis=(0, 0, 1), origin=(0.3, 0, 0), com=(0.4, 0, 0), mass=3.0,
               inertia=[0.01, 0.2, 0.2], compliant={"stiffness": 30.0, "rotor_inertia": 0.02})
    b.add_link("a2", parent="a1", joint="revolute", axis=(0, 1, 0), origin=(0.4, 0, 0), com=(0.3, 0, 0), mass=1.5,
               inertia=[0.01, 0.1, 0.1], compliant={"stiffness": 20.0, "rotor_inertia": 0.01, "gear_ratio": 2.0})
    robot = b.build()
    x0 = robot.neutral_configuration(q=[0.2, 0.1, -0.3, 0.05])
    u0 = np.zeros(robot.nu)
    u0[6:] = [0.5, -0.2, 0.3, 0.1]
    traj = spacearm.simulate(robot, 1.0, x0=x0, u0=u0, dt=1e-3)
    e = np.asarray(traj.energy)
    assert np.ptp(e) < 1e-6 * np.max(np.abs(e))
    m0, m1 = robot.momentum(traj.x[0], traj.u[0]), robot.momentum(traj.x[-1], traj.u[-1])
    assert np.allclose(m0.P, m1.P, atol=1e-9) and np.allclose(m0.L_origin, m1.L_origin, atol=1e-9)


def test_compliant_errors():
    b = clamped_builder()
    with pytest.raises(errors.SpacearmError, match="revolute"):
        b.add_link("s", joint="prismatic", axis=(1, 0, 0), mass=1.0, inertia=[1, 1, 1],
                   compliant={"stiffness": 1.0, "rotor_inertia": 1.0})
    with pytest.raises(errors.ArgumentError, match="missing"):
        b.add_link("s", mass=1.0, inertia=[1, 1, 1], compliant={"stiffness": 1.0})
    with pytest.raises(errors.ArgumentError, match="no actuated"):
        b.add_link("s", mass=1.0, inertia=[1, 1, 1], stiffness=2.0, compliant={"stiffness": 1.0, "rotor_inertia": 1.0})


# ---- TOML ------------------------------------------------------------------------------------

TOML = """
[model]
name = "flex-sat"

[base]
mass = 100.0
inertia = [8.0, 9.0, 10.0]

[[link]]
name = "arm"
parent = "base"
joint = { type = "revolute", origin = [0.5, 0.0, 0.0], axis = [0.0, 0.0, 1.0], compliant = { stiffness = 40.0, rotor_inertia = 0.05, damping = 0.2, gear_ratio = 2.0 } }
com = [0.5, 0.0, 0.0]
mass = 2.0
inertia = [0.01, 0.2, 0.2]

[[panel]]
name = "wing"
hinge_position = [0.0, 0.6, 0.0]
hinge_axis = [1.0, 0.0, 0.0]
direction = [0.0, 1.0, 0.0]
size = [2.0, 1.0, 0.02]
mass = 6.0
frequency = 1.5
damping = 0.1

[[beam]]
name = "boom"
root_position = [0.0, 0.0, 0.5]
axis = [0.0, 0.0, 1.0]
length = 3.0
segments = 3
EI = [200.0, 300.0]
GJ = 50.0
rho_A = 0.5
rho_J = 0.001
damping_ratio = 0.01
"""


def test_toml_equals_the_builder(tmp_path):
    path = tmp_path / "flex.toml"
    path.write_text(TOML)
    from_file = spacearm.io.load_toml(path)
    b = spacearm.Robot.builder("flex-sat", base_mass=100.0, base_inertia=[8.0, 9.0, 10.0])
    b.add_link("arm", origin=(0.5, 0, 0), axis=(0, 0, 1), com=(0.5, 0, 0), mass=2.0, inertia=[0.01, 0.2, 0.2],
               compliant={"stiffness": 40.0, "rotor_inertia": 0.05, "damping": 0.2, "gear_ratio": 2.0})
    b.add_panel("wing", hinge_position=(0, 0.6, 0), hinge_axis=(1, 0, 0), direction=(0, 1, 0), size=(2.0, 1.0, 0.02),
                mass=6.0, frequency=1.5, damping=0.1)
    b.add_beam("boom", root_position=(0, 0, 0.5), axis=(0, 0, 1), length=3.0, segments=3, EI=[200.0, 300.0], GJ=50.0,
               rho_A=0.5, rho_J=0.001, damping_ratio=0.01)
    built = b.build()
    assert from_file.joint_names == built.joint_names
    assert from_file.actuated_dofs.tolist() == built.actuated_dofs.tolist()
    x = built.neutral_configuration(q=np.linspace(-0.3, 0.3, built.n_dof))
    assert np.array_equal(from_file.mass_matrix(x), built.mass_matrix(x))
    u = np.linspace(-1, 1, built.nu)
    assert np.array_equal(from_file.passive_forces(x, u), built.passive_forces(x, u))
    assert from_file.point_names == built.point_names
    # save_toml writes the links they made; reading it back gives the same model.
    again = spacearm.io.load_toml(spacearm.io.save_toml(from_file, tmp_path / "again.toml"))
    assert np.array_equal(again.mass_matrix(x), built.mass_matrix(x))
    assert np.array_equal(again.passive_forces(x, u), built.passive_forces(x, u))


def test_an_initial_q_of_the_listed_links_starts_the_appendages_at_rest(tmp_path):
    # Issue 37 item 5: appending a [[panel]] and a [[beam]] to a model with an initial_q was
    # refused until the user counted the generated passive coordinates. The listed links here:
    # the compliant arm (its motor and its link: two coordinates). The panel's hinge starts at
    # its spring's rest (0.2 rad, given), the beam's joints at 0.
    text = TOML.replace('name = "flex-sat"', 'name = "flex-sat"\ninitial_q = [0.3, 0.25]').replace(
        "damping = 0.1\n", "damping = 0.1\nrest = 0.2\n", 1)
    path = tmp_path / "flex.toml"
    path.write_text(text)
    robot = spacearm.io.load_toml(path)
    q0 = robot.initial_q
    names = robot.joint_names
    assert len(q0) == robot.n_dof > 2
    assert list(q0[:2]) == [0.3, 0.25]
    hinge = names.index("wing_hinge")
    assert q0[hinge] == 0.2
    assert all(q0[j] == 0.0 for j in range(2, robot.n_dof) if j != hinge)
    # An initial_q of every coordinate is taken as it is; any other length is refused.
    full = np.arange(robot.n_dof) * 0.01
    path.write_text(TOML.replace('name = "flex-sat"', f'name = "flex-sat"\ninitial_q = {[float(v) for v in full]}'))
    assert np.array_equal(spacearm.io.load_toml(path).initial_q, full)
    path.write_text(TOML.replace('name = "flex-sat"', 'name = "flex-sat"\ninitial_q = [0.3]'))
    with pytest.raises(errors.ModelError, match="initial_q"):
        spacearm.io.load_toml(path)
