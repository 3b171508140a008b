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
    pushed = spacearm.simulate(robot, 0.2, x0=x0, dt=1e-3,
                               controller=spacearm.control.JointPD(kp=100.0, kd=1.0, reference=[0.5]))
    assert not pushed.tau.any() and pushed.tau_cmd.any()


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
