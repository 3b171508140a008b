"""Passive joints and joint spring–dampers through the Python doors (docs/flexibility.md).

Independent references: the passive force by hand, ``-k (q - rest) - c q̇``; the rigid model's
forward dynamics under ``f + Q``; the closed form of a spring–mass on a free base,
``μ q̈ + c q̇ + k q = 0`` with the reduced mass ``μ = M m / (M + m)``, solved by
``scipy.integrate.solve_ivp`` (the simulator's trajectory against it); the TOML and builder round
trips against the model they came from.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import spacearm
from spacearm import errors
from random_models import with_joint_springs

M_BASE, M_SLUG = 100.0, 5.0


def spring_mass(k=200.0, c=0.0, rest=0.0, actuated=False) -> spacearm.Robot:
    """A 100 kg base, a 5 kg slug on a prismatic joint along x through the base CM."""
    b = spacearm.Robot.builder("spring-mass", base_mass=M_BASE, base_inertia=[8.0, 9.0, 10.0])
    b.add_link("slug", joint="prismatic", axis=(1, 0, 0), origin=(0.5, 0, 0), mass=M_SLUG,
               inertia=[1e-3, 1e-3, 1e-3], actuated=actuated, stiffness=k, damping=c, rest=rest)
    return b.build()


def test_passive_forces_and_forward_dynamics_on_a_tree():
    rng = np.random.default_rng(24)
    rigid = spacearm.presets.get("spatial6")
    sprung, dyn = with_joint_springs(rigid, rng)
    n = rigid.n_dof
    x = rigid.neutral_configuration(q=rng.uniform(-1, 1, n))
    u = rng.normal(size=rigid.nu)
    f = rng.normal(size=rigid.nu)
    q_by_hand = np.zeros(rigid.nu)
    for j, d in enumerate(dyn):
        q_by_hand[6 + j] = -d["stiffness"] * (x[7 + j] - d["rest"]) - d["damping"] * u[6 + j]
    assert np.linalg.norm(q_by_hand) > 1.0
    np.testing.assert_allclose(sprung.passive_forces(x, u), q_by_hand, rtol=0, atol=1e-14)
    assert sprung.actuated_dofs.tolist() == [d["actuated"] for d in dyn]
    assert rigid.actuated_dofs.all() and not rigid.passive_forces(x, u).any()
    expected = rigid.forward_dynamics(x, u, f + q_by_hand)
    for method in ("aba", "mass_matrix", "reduced"):
        np.testing.assert_allclose(sprung.forward_dynamics(x, u, f, method=method), expected, rtol=1e-10, atol=1e-10)
    du = sprung.forward_dynamics(x, u, f)
    np.testing.assert_allclose(sprung.inverse_dynamics(x, u, du), f, rtol=1e-10, atol=1e-10)
    # A batch of states: one row each.
    xs, us = np.stack([x, x]), np.stack([u, -u])
    assert sprung.passive_forces(xs, us).shape == (2, rigid.nu)
    e = 0.5 * sum(d["stiffness"] * (x[7 + j] - d["rest"]) ** 2 for j, d in enumerate(dyn))
    assert sprung.spring_energy(x) == pytest.approx(e, rel=1e-14)


def test_description_builder_and_toml_carry_the_joint_dynamics():
    robot = spring_mass(k=200.0, c=1.5, rest=0.1)
    link = robot.description.link("slug")
    assert (link.actuated, link.stiffness, link.damping, link.rest) == (False, 200.0, 1.5, 0.1)
    assert robot.describe()["links"][0]["stiffness"] == 200.0
    again = spacearm.RobotBuilder.from_robot(robot).build()
    assert again.describe() == robot.describe()
    text = spacearm.io.dumps_toml(robot)
    assert "actuated = false" in text and "stiffness = 200.0" in text and "springref" not in text
    assert spacearm.io.loads_toml(text).describe() == robot.describe()


@pytest.mark.parametrize("kwargs, error, needle", [
    (dict(stiffness=-1.0), errors.ModelError, "stiffness must be finite and >= 0"),
    (dict(damping=float("nan")), errors.ModelError, "damping must be finite and >= 0"),
    (dict(rest=float("inf")), errors.ModelError, "rest must be finite"),
    (dict(actuated="no"), errors.SpacearmTypeError, "actuated must be True or False"),
    (dict(stiffness="stiff"), errors.ArgumentError, "stiffness must be a number"),
])
def test_bad_joint_dynamics_are_refused(kwargs, error, needle):
    b = spacearm.Robot.builder("m", base_mass=100.0, base_inertia=[10, 10, 10])
    with pytest.raises(error, match=needle):
        b.add_link("arm", joint="revolute", origin=(0.5, 0, 0), com=(0.5, 0, 0), mass=2.0, inertia=[0.01, 0.4, 0.4], **kwargs)


def test_a_fixed_joint_takes_no_spring():
    b = spacearm.Robot.builder("m", base_mass=100.0, base_inertia=[10, 10, 10])
    with pytest.raises(errors.ModelError, match="a fixed joint has no coordinate"):
        b.add_link("bolt", joint="fixed", origin=(0.5, 0, 0), mass=2.0, inertia=[0.01, 0.4, 0.4], stiffness=3.0)


def test_simulated_spring_mass_follows_the_reduced_mass_ode():
    k, c, amp = 200.0, 3.0, 0.02
    robot = spring_mass(k=k, c=c)
    mu = M_BASE * M_SLUG / (M_BASE + M_SLUG)
    x0 = robot.neutral_configuration(q=[amp])
    traj = spacearm.simulate(robot, 1.5, x0=x0, dt=1e-3)
    ref = solve_ivp(lambda t, y: [y[1], -(k * y[0] + c * y[1]) / mu], (0.0, 1.5), [amp, 0.0],
                    t_eval=traj.t, rtol=1e-12, atol=1e-15, method="DOP853")
    q = traj.x[:, 7]
    assert np.ptp(q) > amp  # it moves
    np.testing.assert_allclose(q, ref.y[0], rtol=0, atol=1e-9 * amp)
    # A passive joint takes no torque, whatever is commanded.
    with pytest.warns(RuntimeWarning, match=r"commanded torque on the passive joints \['slug_joint'\]"):
        pushed = spacearm.simulate(robot, 0.2, x0=x0, dt=1e-3,
                                   controller=spacearm.control.Callback(lambda t, x, u: 100.0 * (0.5 - x[7:]) - u[6:]))
    assert not pushed.tau.any() and pushed.tau_cmd.any()
    assert pushed.meta["passive_joints_commanded"] == ["slug_joint"] and traj.meta["passive_joints_commanded"] == []


def test_undamped_energy_record_includes_the_spring():
    k, amp = 200.0, 0.02
    robot = spring_mass(k=k)
    traj = spacearm.simulate(robot, 0.5, x0=robot.neutral_configuration(q=[amp]), dt=1e-3)
    energy = np.asarray(traj.energy).ravel()
    assert energy[0] == pytest.approx(0.5 * k * amp**2, rel=1e-12)
    kinetic = np.array([robot.kinetic_energy(x, u) for x, u in zip(traj.x, traj.u)])
    springs = np.array([robot.spring_energy(x) for x in traj.x])
    np.testing.assert_allclose(energy, kinetic + springs, rtol=1e-12)
    assert kinetic.max() > 0.4 * energy[0]  # the energy changes form
    assert "energy" in traj.meta["conserved"]
    assert traj.meta["drift"]["energy"] < 1e-9


URDF = """<?xml version="1.0"?>
<robot name="panel">
  <link name="bus"><inertial><mass value="100"/><inertia ixx="8" iyy="9" izz="10" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="panel"><inertial><origin xyz="0.5 0 0"/><mass value="10"/>
    <inertia ixx="0.1" iyy="0.75" izz="0.8" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="hinge" type="continuous">
    <parent link="bus"/><child link="panel"/><origin xyz="1 0 0"/><axis xyz="0 0 1"/>
    <dynamics damping="0.5" friction="0.1"/>
    <spacearm stiffness="30" rest="0.25" actuated="false"/>
  </joint>
</robot>
"""


def test_urdf_reads_damping_and_the_spacearm_extension_element():
    robot = spacearm.io.loads_urdf(URDF)
    link = robot.description.link("panel")
    assert (link.actuated, link.stiffness, link.damping, link.rest) == (False, 30.0, 0.5, 0.25)
    text = spacearm.io.to_urdf(robot)
    assert '<dynamics damping="0.5"' in text and "<spacearm " in text
    assert spacearm.io.loads_urdf(text).description.link("panel").stiffness == 30.0
    again = spacearm.io.loads_urdf(text)
    x = robot.neutral_configuration(q=[0.4])
    u = np.r_[np.zeros(6), 0.3]
    np.testing.assert_array_equal(again.passive_forces(x, u), robot.passive_forces(x, u))
    with pytest.raises(errors.ModelFileError, match="<spacearm> takes stiffness, rest and actuated"):
        spacearm.io.loads_urdf(URDF.replace('rest="0.25"', 'springref="0.25"'))
    with pytest.raises(errors.ModelFileError, match="must be 'true' or 'false'"):
        spacearm.io.loads_urdf(URDF.replace('actuated="false"', 'actuated="no"'))
    with pytest.raises(errors.ModelFileError, match="stiffness must be finite and >= 0"):
        spacearm.io.loads_urdf(URDF.replace('stiffness="30"', 'stiffness="-30"'))


def test_casadi_equations_of_motion_carry_the_springs():
    pytest.importorskip("casadi")
    from spacearm import casadi as sc

    rng = np.random.default_rng(5)
    robot, _ = with_joint_springs(spacearm.presets.get("planar4"), rng)
    x = robot.neutral_configuration(q=rng.uniform(-1, 1, robot.n_dof))
    u, tau = rng.normal(size=robot.nu), rng.normal(size=robot.n_dof)
    fd = sc.forward_dynamics(robot)
    got = np.asarray(fd(x, u, tau, np.zeros(6))).ravel()
    np.testing.assert_allclose(got, robot.forward_dynamics(x, u, tau=tau), rtol=1e-12, atol=1e-12)
    du = rng.normal(size=robot.nu)
    f = np.asarray(sc.inverse_dynamics(robot)(x, u, du)).ravel()
    np.testing.assert_allclose(f, robot.inverse_dynamics(x, u, du), rtol=1e-12, atol=1e-12)


def test_trajectory_drift_recomputed_from_the_records_equals_the_simulators():
    robot = spring_mass(k=200.0)
    traj = spacearm.simulate(robot, 0.3, x0=robot.neutral_configuration(q=[0.02]), dt=1e-3)
    # The energy scale is the mechanical energy (the kinetic energy starts at zero here).
    assert traj.drift_scale("energy") == pytest.approx(traj.meta["drift_scales"]["energy"], rel=1e-12)
    assert traj.drift(["energy"], scale={"energy": traj.drift_scale("energy")})["energy"] == pytest.approx(
        traj.meta["drift"]["energy"], rel=1e-6, abs=1e-15)


def hinged_panel(k=30.0, c=0.0, base_mass=100.0, base_izz=10.0) -> spacearm.Robot:
    """A panel (10 kg, I_zz 0.8 kg m², CM 0.5 m out) hinged about z at 1 m from the hub's CM."""
    b = spacearm.Robot.builder("hinged", base_mass=base_mass, base_inertia=[0.8 * base_izz, 0.9 * base_izz, base_izz])
    b.add_link("panel", joint="revolute", axis=(0, 0, 1), origin=(1.0, 0, 0), com=(0.5, 0, 0), mass=10.0,
               inertia=[0.1, 0.75, 0.8], actuated=False, stiffness=k, damping=c)
    return b.build()


def hinge_frequency_closed_form(k, base_mass, base_izz, m=10.0, i1=0.8, a=1.0, b=0.5) -> float:
    """``√(k / I_red)``, ``I_red = det M₂ / (1ᵀ M₂ 1)`` (docs/flexibility.md, the hinged panel)."""
    mu = base_mass * m / (base_mass + m)
    m11, m12, m22 = mu * a * a + base_izz, mu * a * b, mu * b * b + i1
    return float(np.sqrt(k * (m11 + 2 * m12 + m22) / (m11 * m22 - m12 * m12)))


@pytest.mark.parametrize("base_mass, base_izz", [(20.0, 2.0), (100.0, 10.0), (1e7, 1e6)])
def test_hinged_panel_frequency_shift_on_a_free_hub(base_mass, base_izz):
    k = 30.0
    robot = hinged_panel(k, base_mass=base_mass, base_izz=base_izz)
    modes = robot.natural_frequencies()
    expected = hinge_frequency_closed_form(k, base_mass, base_izz)
    assert modes.frequencies[0] == pytest.approx(expected, rel=1e-12)
    fixed_hub = np.sqrt(k / (0.8 + 10.0 * 0.5**2))  # a clamped panel: the inertia about the hinge
    assert modes.frequencies[0] > fixed_hub  # a free hub always raises it
    if base_mass > 1e6:
        assert modes.frequencies[0] == pytest.approx(fixed_hub, rel=1e-3)  # and a heavy one tends to the clamped value
    # The linearization's eigenvalues say the same (zero damping, at rest).
    x, u = robot.neutral_configuration(), np.zeros(robot.nu)
    lin = robot.linearize(x, u, np.zeros(robot.nu))
    assert np.max(np.linalg.eigvals(lin.A).imag) == pytest.approx(expected, rel=1e-9)


def test_modal_damping_ratio_of_a_damped_panel():
    k, c = 30.0, 0.5
    robot = hinged_panel(k, c)
    modes = robot.natural_frequencies()
    omega = hinge_frequency_closed_form(k, 100.0, 10.0)
    i_red = k / omega**2
    assert modes.damping_ratios[0] == pytest.approx(c / (2 * np.sqrt(k * i_red)), rel=1e-12)
    # The linearization's eigenvalues are −ζω ± iω√(1−ζ²).
    lin = robot.linearize(robot.neutral_configuration(), np.zeros(robot.nu), np.zeros(robot.nu))
    lam = np.linalg.eigvals(lin.A)
    top = lam[np.argmax(lam.imag)]
    zeta = modes.damping_ratios[0]
    assert top.real == pytest.approx(-zeta * omega, rel=1e-9)
    assert top.imag == pytest.approx(omega * np.sqrt(1 - zeta**2), rel=1e-9)
    with pytest.raises(errors.ArgumentError, match="actuated must be 'held' or 'free'"):
        robot.natural_frequencies(actuated="locked")


SLOSH_TOML = """
[model]
name = "tanker"

[base]
mass = 1.0e9
inertia = [1.0e9, 1.0e9, 1.0e9]

[[link]]
name = "boom"
parent = "base"
com = [0.5, 0.0, 0.0]
mass = 5.0
inertia = [0.01, 0.4, 0.4]
joint = { type = "revolute", origin = [1.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0] }

[[slosh]]
name = "fuel"
model = "spherical-pendulum"
mass = 20.0
position = [0.0, 0.0, -0.2]
axis = [0.0, 0.0, -1.0]
length = 0.3
frequency = 2.0
damping = 0.1

[[slosh]]
name = "oxidizer"
parent = "boom"
model = "spring-mass"
mass = 3.0
position = [0.2, 0.0, 0.0]
axis = [0.0, 1.0, 0.0]
stiffness = 48.0
"""


def test_slosh_from_the_builder_and_toml():
    robot = spacearm.io.loads_toml(SLOSH_TOML)
    b = spacearm.Robot.builder("tanker", base_mass=1e9, base_inertia=[1e9, 1e9, 1e9])
    b.add_link("boom", joint="revolute", axis=(0, 0, 1), origin=(1, 0, 0), com=(0.5, 0, 0), mass=5.0, inertia=[0.01, 0.4, 0.4])
    b.add_slosh("fuel", model="spherical-pendulum", mass=20.0, position=(0, 0, -0.2), axis=(0, 0, -1), length=0.3,
                frequency=2.0, damping=0.1)
    b.add_slosh("oxidizer", parent="boom", model="spring-mass", mass=3.0, position=(0.2, 0, 0), axis=(0, 1, 0), stiffness=48.0)
    built = b.build()
    assert built.describe() == robot.describe()
    assert robot.body_names == ["base", "boom", "fuel_gimbal", "fuel", "oxidizer"]
    assert robot.actuated_dofs.tolist() == [True, False, False, False]
    # The bob hangs at position + length·axis at q = 0; the gimbal is massless.
    kin = robot.forward_kinematics(robot.neutral_configuration())
    np.testing.assert_allclose(kin.com_in_world[3], [0.0, 0.0, -0.5], atol=1e-15)
    assert robot.description.link("fuel_gimbal").mass == 0.0
    # On this (nearly clamped) base the pendulum modes are the given frequency, the spring-mass √(k/m).
    w = robot.natural_frequencies().frequencies
    np.testing.assert_allclose(w, [2.0, 2.0, 4.0], rtol=1e-6)
    assert robot.describe() == spacearm.RobotBuilder.from_robot(robot).build().describe()
    assert spacearm.io.loads_toml(spacearm.io.dumps_toml(robot)).describe() == robot.describe()
    # Removing the gimbal removes the bob below it.
    assert "fuel" not in spacearm.RobotBuilder.from_robot(robot).remove_body("fuel_gimbal").build().body_names


@pytest.mark.parametrize("kwargs, needle", [
    (dict(model="slushy", length=0.3, frequency=1.0), "model must be one of"),
    (dict(model="pendulum", frequency=1.0), "a pendulum needs a length"),
    (dict(model="pendulum", length=0.3), "give stiffness or frequency"),
    (dict(model="pendulum", length=0.3, stiffness=1.0, frequency=1.0), "give stiffness or frequency"),
    (dict(model="pendulum", length=0.3, frequency=1.0, hinge=(0, 0, 1)), "must be perpendicular"),
])
def test_bad_slosh_is_refused(kwargs, needle):
    b = spacearm.Robot.builder("m", base_mass=100.0, base_inertia=[10, 10, 10])
    with pytest.raises(errors.ModelError, match=needle):
        b.add_slosh("fuel", mass=5.0, position=(0, 0, 0), axis=(0, 0, 1), **kwargs)


def test_slosh_toml_errors_point_at_the_table():
    text = SLOSH_TOML.replace('model = "spherical-pendulum"', 'model = "slushy"')
    with pytest.raises(errors.ModelFileError, match=r"<string>:19:9: slosh .fuel.: model must be one of"):
        spacearm.io.loads_toml(text)
