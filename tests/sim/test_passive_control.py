"""Control with passive joints, input shaping and the tank-to-slosh parameters
(docs/flexibility.md).

Independent references: the plant's own forward dynamics (the actuated joints' accelerations
under the computed torque equal the command); the closed form of a prismatic cart carrying a
spring–mass on a free base (``μ q̈_p + k q_p = −m_s (M_b/M) q̈_a``, ``μ = m_s (M − m_s)/M``) for the
shaper's design frequency; the ZV/ZVD impulses of Singer & Seering (1990) written out here; the
cylinder's equivalent mechanical model (Abramson 1966, Table 6.1; Dodge 2000, §3.2) coded here
from the formulas, with its deep and shallow limits.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import spacearm
from spacearm import errors
from spacearm.control import ComputedTorque, QuinticJoint, input_shaper

M_BASE, M_CART, M_SLUG, K_SLUG = 100.0, 10.0, 2.0, 50.0


def cart_with_slug() -> spacearm.Robot:
    """An actuated prismatic cart along x through the base CM carrying a passive 2 kg slug on a
    spring along x: every force on one line through the CMs, so the motion is linear."""
    b = spacearm.Robot.builder("cart", base_mass=M_BASE, base_inertia=[8.0, 9.0, 10.0])
    b.add_link("cart", joint="prismatic", axis=(1, 0, 0), origin=(0.5, 0, 0), mass=M_CART, inertia=[0.1, 0.1, 0.1])
    b.add_slosh("slug", parent="cart", model="spring-mass", mass=M_SLUG, position=(0.2, 0, 0), axis=(1, 0, 0), stiffness=K_SLUG)
    return b.build()


def arm_with_fuel() -> spacearm.Robot:
    b = spacearm.Robot.builder("arm-fuel", base_mass=150.0, base_inertia=[12.0, 14.0, 16.0])
    b.add_link("l1", joint="revolute", axis=(0, 0, 1), origin=(0.6, 0, 0.1), com=(0.5, 0, 0), mass=6.0, inertia=[0.02, 0.5, 0.5])
    b.add_slosh("fuel", model="pendulum", mass=25.0, position=(0.0, 0.1, 0.2), axis=(0, 0, -1), hinge=(1, 0, 0),
                length=0.3, frequency=1.2, damping=0.2)
    b.add_link("l2", joint="revolute", axis=(0, 1, 0), parent="l1", origin=(1.0, 0, 0), com=(0.4, 0, 0), mass=4.0, inertia=[0.02, 0.3, 0.3])
    return b.build()


def slug_frequency() -> float:
    m = M_BASE + M_CART + M_SLUG
    return math.sqrt(K_SLUG / (M_SLUG * (m - M_SLUG) / m))


def test_computed_torque_commands_only_the_actuated_joints_and_they_track_exactly():
    robot = arm_with_fuel()
    assert list(robot.actuated_dofs) == [True, False, True]
    q0 = np.array([0.3, 0.0, -0.2])
    ref = QuinticJoint(q0[[0, 2]], q0[[0, 2]] + [0.5, -0.4], t_start=0.0, t_end=2.0)
    x0 = robot.neutral_configuration(q=q0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no "commanded torque on the passive joints" warning
        traj = spacearm.simulate(robot, 2.5, x0=x0, controller=ComputedTorque(kp=0.0, kd=0.0, reference=ref), rtol=1e-11, atol=1e-12)
    assert traj.meta["passive_joints_commanded"] == []
    assert not np.any(traj.tau_cmd[:, 1])
    # No feedback at all (kp = kd = 0): the actuated joints follow the reference only because
    # the computed torque realizes its acceleration exactly through the moving fuel.
    q_ref, _, _ = ref.evaluate(traj.t)
    assert np.max(np.abs(traj.x[:, [7, 9]] - q_ref)) < 1e-7
    assert np.ptp(traj.x[:, 8]) > 1e-3  # the fuel swings
    # The plant's forward dynamics under the recorded torques gives the commanded accelerations.
    _, _, qdd_ref = ref.evaluate(traj.t)
    for i in range(0, len(traj.t), 50):
        ud = robot.forward_dynamics(traj.x[i], traj.u[i], tau=traj.tau[i])
        np.testing.assert_allclose(ud[[6, 8]], qdd_ref[i], rtol=0, atol=1e-9)
    # Frozen (designed on the rigid model): the fuel's motion is a model error it does not see.
    frozen = spacearm.simulate(robot, 2.5, x0=x0, controller=ComputedTorque(kp=0.0, kd=0.0, reference=ref, passive="frozen"),
                               rtol=1e-11, atol=1e-12)
    assert np.max(np.abs(frozen.x[:, [7, 9]] - q_ref)) > 1e-4
    with pytest.raises(errors.ShapeError, match="actuated arm joints 2"):
        spacearm.simulate(robot, 0.1, controller=ComputedTorque(kp=1.0, kd=1.0, reference=q0))
    with pytest.raises(errors.ArgumentError, match="passive"):
        spacearm.simulate(robot, 0.1, controller=ComputedTorque(kp=1.0, kd=1.0, reference=q0[[0, 2]], passive="held"))


def test_resolved_motion_rate_leaves_the_passive_joints_alone():
    robot = arm_with_fuel()
    x0 = robot.neutral_configuration(q=[0.3, 0.0, -0.2])
    p = robot.point_position(x0, "l2")
    line = spacearm.control.CartesianLine(p, p + [0.0, 0.05, 0.0], t_start=0.0, t_end=1.0, point="l2")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        traj = spacearm.simulate(robot, 1.2, x0=x0, controller=spacearm.control.ResolvedMotionRate(line, gain=5.0))
    assert traj.meta["passive_joints_commanded"] == []
    assert not np.any(traj.tau_cmd[:, 1])


def test_shaper_impulses_are_singer_seerings():
    w, z = 3.0, 0.04
    k = math.exp(-z * math.pi / math.sqrt(1 - z * z))
    td = 2 * math.pi / (w * math.sqrt(1 - z * z))
    zv = input_shaper("zv", frequency=w, damping=z)
    np.testing.assert_allclose(zv.amplitudes, [1 / (1 + k), k / (1 + k)], rtol=1e-14)
    np.testing.assert_allclose(zv.times, [0.0, td / 2], rtol=1e-14)
    zvd = input_shaper("zvd", frequency=w, damping=z)
    np.testing.assert_allclose(zvd.amplitudes, np.array([1, 2 * k, k * k]) / (1 + k) ** 2, rtol=1e-14)
    np.testing.assert_allclose(zvd.times, [0.0, td / 2, td], rtol=1e-14)
    for s in (zv, zvd):
        assert s.residual_vibration(w, z) < 1e-12
        assert s.residual_vibration(1.25 * w, z) > 1e-2
    with pytest.raises(errors.ArgumentError):
        input_shaper("zvdd", frequency=1.0)
    with pytest.raises(errors.ArgumentError):
        input_shaper("zv", frequency=-1.0)


def residual_amplitude(traj, t_after: float, w: float) -> float:
    keep = traj.t >= t_after
    q, qd = traj.x[keep, 8], traj.u[keep, 7]
    return float(np.max(np.sqrt(q**2 + (qd / w) ** 2)))


def test_a_shaped_move_leaves_no_residual_vibration():
    robot = cart_with_slug()
    w = slug_frequency()
    modes = robot.natural_frequencies(robot.neutral_configuration(q=[0.0, 0.0]))
    assert modes.frequencies[0] == pytest.approx(w, rel=1e-10)  # the closed form is the model's mode
    move = QuinticJoint([0.0], [0.4], t_start=0.0, t_end=1.0)
    x0 = robot.neutral_configuration(q=[0.0, 0.0])
    results = {}
    for name, ref in [("plain", move), ("zv", input_shaper("zv", frequency=w).shape(move)),
                      ("zvd", input_shaper("zvd", frequency=w).shape(move))]:
        traj = spacearm.simulate(robot, 4.0, x0=x0, controller=ComputedTorque(kp=0.0, kd=0.0, reference=ref), rtol=1e-11, atol=1e-13)
        assert traj.x[-1, 7] == pytest.approx(0.4, abs=1e-6)  # open loop: integration error only
        results[name] = residual_amplitude(traj, 1.0 + (ref.shaper.times[-1] if name != "plain" else 0.0), w)
    assert results["plain"] > 1e-3
    assert results["zv"] < 1e-4 * results["plain"]
    assert results["zvd"] < 1e-4 * results["plain"]



def cylinder_closed_form(r, h, m, a):
    xi = 1.8411837813406593
    t = math.tanh(xi * h / r)
    m1 = m * 2 * r * t / (xi * (xi**2 - 1) * h)
    w1 = math.sqrt(a / r * xi * t)
    l1 = h / 2 - 2 * r / xi * math.tanh(xi * h / (2 * r))  # wall + bottom pressure (tests/model/test_slosh_potential_flow.py)
    return m1, w1, l1


@pytest.mark.parametrize("h", [0.05, 0.4, 1.0, 3.0])
def test_cylinder_slosh_parameters_against_the_closed_form(h):
    r, m, a = 0.5, 120.0, 0.3
    p = spacearm.slosh_parameters("cylinder", radius=r, fill_height=h, propellant_mass=m, axial_acceleration=a)
    m1, w1, l1 = cylinder_closed_form(r, h, m, a)
    mode = p.modes[0]
    assert mode.mass == pytest.approx(m1, rel=1e-13)
    assert mode.frequency == pytest.approx(w1, rel=1e-13)
    assert mode.height == pytest.approx(l1, rel=1e-12, abs=1e-15)
    assert mode.stiffness == pytest.approx(m1 * w1**2, rel=1e-13)
    assert mode.length == pytest.approx(a / w1**2, rel=1e-13)
    assert p.fixed_mass + mode.mass == pytest.approx(m, rel=1e-14)  # mass conserved
    assert p.fixed_mass * p.fixed_height + mode.mass * mode.height == pytest.approx(0.0, abs=1e-12)  # CM preserved
    # sqrt(a) scaling of the frequency, nothing else changes
    q = spacearm.slosh_parameters(radius=r, fill_height=h, propellant_mass=m, axial_acceleration=4 * a)
    assert q.modes[0].frequency == pytest.approx(2 * w1, rel=1e-13) and q.modes[0].mass == mode.mass


def test_cylinder_slosh_limits_and_fill_options():
    r, a = 0.5, 0.3
    xi = 1.8411837813406593
    deep = spacearm.slosh_parameters(radius=r, fill_height=50.0, propellant_mass=10.0, axial_acceleration=a)
    assert deep.modes[0].frequency ** 2 == pytest.approx(a * xi / r, rel=1e-12)  # tanh -> 1
    assert deep.modes[0].height == pytest.approx(25.0 - 2 * r / xi, rel=1e-12)  # 2R/xi below the surface
    shallow = spacearm.slosh_parameters(radius=r, fill_height=1e-4, propellant_mass=10.0, axial_acceleration=a)
    assert shallow.modes[0].mass / 10.0 == pytest.approx(2 / (xi**2 - 1), rel=1e-6)
    three = spacearm.slosh_parameters(radius=r, fill_height=1e-4, propellant_mass=10.0, axial_acceleration=a, modes=3)
    assert sum(m.mass for m in three.modes) + three.fixed_mass == pytest.approx(10.0, rel=1e-13)
    by_fraction = spacearm.slosh_parameters(radius=r, fill_fraction=0.25, tank_height=2.0, density=800.0, axial_acceleration=a)
    assert by_fraction.fill_height == pytest.approx(0.5) and by_fraction.liquid_mass == pytest.approx(800.0 * math.pi * r * r * 0.5)
    with pytest.raises(errors.ArgumentError, match="surface tension"):
        spacearm.slosh_parameters(radius=r, fill_height=0.5, propellant_mass=10.0, axial_acceleration=0.0)
    with pytest.raises(errors.ArgumentError, match="must be one of"):
        spacearm.slosh_parameters("cone", radius=r, fill_height=0.5, propellant_mass=10.0, axial_acceleration=a)
    with pytest.raises(errors.ArgumentError, match="one of them"):
        spacearm.slosh_parameters(radius=r, fill_height=0.5, fill_fraction=0.5, tank_height=1.0, propellant_mass=1.0, axial_acceleration=a)


@pytest.mark.parametrize("model", ["spring-mass", "pendulum"])
def test_tank_model_on_a_builder(model):
    r, h, m, a = 0.4, 0.5, 60.0, 0.5
    p = spacearm.slosh_parameters(radius=r, fill_height=h, propellant_mass=m, axial_acceleration=a)
    b = spacearm.Robot.builder("tank-sat", base_mass=5000.0, base_inertia=[900.0, 900.0, 900.0])
    center = np.array([0.2, -0.1, 0.3])
    p.add_to(b, "prop", center=center, axis=(0, 0, 1), lateral=(1, 0, 0), model=model)
    robot = b.build()
    assert robot.total_mass == pytest.approx(5000.0 + m)
    x = robot.neutral_configuration()
    cm = (robot.center_of_mass(x) * robot.total_mass - 0.0) / m  # the base CM is at the origin
    np.testing.assert_allclose(cm, center, atol=1e-12)  # the model's CM is the liquid's
    # On a heavy base the mode runs at the tank's frequency (reduced mass within 1.2 %).
    w = robot.natural_frequencies(x).frequencies[0]
    assert w == pytest.approx(p.modes[0].frequency, rel=2e-2)


# ---- joint PD and coordinated flying on the actuated joints only (issue 24, item 5) ----------
def test_joint_pd_takes_a_reference_for_the_actuated_joints_only():
    robot = arm_with_fuel()
    assert robot.actuated_arm_dofs == [0, 2]
    q0 = np.array([0.3, 0.2, -0.2])
    x0 = robot.neutral_configuration(q=q0)
    with pytest.raises(errors.SpacearmError, match=r"actuated arm joints 2 .*1 passive joints"):
        spacearm.simulate(robot, 0.01, x0=x0, controller=spacearm.control.JointPD(kp=10.0, kd=1.0, reference=[0.0, 0.0, 0.0]))
    kp, kd, goal = np.array([40.0, 25.0]), np.array([12.0, 6.0]), np.array([0.6, -0.5])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no "commanded torque on the passive joints" warning
        traj = spacearm.simulate(robot, 1.0, x0=x0, dt=1e-3, record_every=10,
                                 controller=spacearm.control.JointPD(kp=kp, kd=kd, reference=goal))
    assert traj.meta["passive_joints_commanded"] == [] and not np.any(traj.tau_cmd[:, 1])
    assert np.ptp(traj.q[:, 1]) > 1e-3  # the fuel sloshes, uncommanded
    # The PD law by hand over the actuated joints, and the tracking error over them alone.
    np.testing.assert_allclose(traj.tau_cmd[:, [0, 2]], kp * (goal - traj.q[:, [0, 2]]) - kd * traj["u"][:, [6, 8]],
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(traj["tracking_error"], np.linalg.norm(goal - traj.q[:, [0, 2]], axis=1), rtol=0, atol=1e-14)


def spatial6_with_fuel_and_panel() -> spacearm.Robot:
    b = spacearm.RobotBuilder.from_robot(spacearm.presets.spatial6(), "spatial6-flex")
    b.add_slosh("fuel", model="pendulum", mass=40.0, position=(0.0, 0.2, 0.3), axis=(0, 0, -1), hinge=(1, 0, 0),
                length=0.4, frequency=1.5, damping=0.3)
    b.add_panel("wing", hinge_position=(0.0, -0.8, 0.0), hinge_axis=(1, 0, 0), direction=(0, -1, 0), size=(1.0, 0.6, 0.02),
                mass=5.0, frequency=2.0)
    return b.build()


def test_coordinated_flying_with_passive_joints_follows_the_closed_form_error_dynamics():
    """Partial feedback linearization (docs/flexibility.md): with the exact model the end-effector
    and base-position errors obey e'' + kd e' + kp e = 0 from rest, critically damped:
    e(t) = e0 (1 + w t) exp(-w t) with w = 10 (kp = 100, kd = 20) and w = 5 (kp = 25, kd = 10),
    while the fuel and the panel swing with zero commanded torque."""
    robot = spatial6_with_fuel_and_panel()
    passive = ~robot.actuated_dofs
    assert passive.sum() == 2
    q0 = np.array(robot.initial_q, dtype=float)
    q0[passive] = [0.25, -0.15]
    x0 = robot.neutral_configuration(q=q0)
    p0 = robot.point_position(x0)
    target = p0 + np.array([0.03, -0.02, 0.04])
    r_ref = x0[:3] + np.array([0.05, -0.03, 0.02])
    ctrl = spacearm.control.CoordinatedFlying(spacearm.control.CartesianLine(target, target, 0.0, 1.0),
                                             base_pose_ref=(r_ref, x0[3:7]), kp_ee=100.0, kd_ee=20.0, kp_base=25.0, kd_base=10.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        traj = spacearm.simulate(robot, 1.5, x0=x0, mode="flying", dt=1e-3, record_every=10, controller=ctrl)
    assert traj.meta["passive_joints_commanded"] == [] and not np.any(traj.tau_cmd[:, passive])
    assert np.ptp(traj.q[:, passive], axis=0).min() > 1e-3  # they move
    t = traj.t[:, None]
    p = np.array([robot.point_position(x) for x in traj.x])
    np.testing.assert_allclose(p, target - (target - p0) * (1 + 10 * t) * np.exp(-10 * t), rtol=0, atol=1e-9)
    np.testing.assert_allclose(traj.x[:, :3], r_ref + (x0[:3] - r_ref) * (1 + 5 * t) * np.exp(-5 * t), rtol=0, atol=1e-9)
    np.testing.assert_allclose(traj.x[:, 3:7], np.broadcast_to(x0[3:7], traj.x[:, 3:7].shape), rtol=0, atol=1e-9)
