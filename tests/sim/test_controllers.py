"""Controllers running natively in the simulation loop, each against an independent reference:
the closed-form quintic (computed torque with the exact model tracks it to integration
accuracy), forward kinematics of the final state (resolved-motion-rate control reaches the
target point), a second implementation in Python (joint PD through a callback), the base
attitude and the angular momentum split between arm and wheels (attitude control)."""

import numpy as np
import pytest

import spacearm
from spacearm import analysis, errors
from spacearm.control import (
    AttitudeControl,
    BaseThrusterControl,
    Callback,
    CartesianLine,
    Combined,
    ComputedTorque,
    CoordinatedFlying,
    JointPD,
    QuinticJoint,
    ResolvedMotionRate,
    perturbed_model,
)


def quintic(t, q0, q1, t0, t1):
    """Independent closed form: q0 + (q1 - q0)(10τ³ − 15τ⁴ + 6τ⁵)."""
    tau = np.clip((np.asarray(t) - t0) / (t1 - t0), 0, 1)[:, None]
    return q0 + (q1 - q0) * (10 * tau**3 - 15 * tau**4 + 6 * tau**5)


def with_wheels(robot, rotor=0.5, max_torque=np.inf, max_speed=np.inf):
    """``robot`` plus three orthogonal reaction wheels (RobotBuilder.add_reaction_wheel)."""
    d = robot.describe()
    b = spacearm.RobotBuilder(d["name"] + "_wheels", d["base"]["mass"], d["base"]["inertia"], base_name=d["base"]["name"])
    for link in d["links"]:
        b.add_link(link["name"], parent=link["parent"], joint=link["type"], axis=link["axis"], origin=link["origin"],
                   rotation=link["rotation"], com=link["com"], mass=link["mass"], inertia=link["inertia"], joint_name=link["joint"])
    for name, body, offset in d["points"]:
        b.add_point(name, body=body, offset=offset)
    b.set_end_effector(d["end_effector"])
    for k, pos in zip(np.eye(3), [(-0.3, 0, 0), (0, -0.3, 0), (0, 0, -0.3)]):
        b.add_reaction_wheel(k, rotor, position=pos, max_torque=max_torque, max_speed=max_speed, mass=2.0)
    b.set_initial_q(list(d["initial_q"]) + [0.0, 0.0, 0.0])
    return b.build()


# ---- computed torque -------------------------------------------------------------------------
@pytest.mark.parametrize("preset", ["planar4", "spatial6"])
@pytest.mark.parametrize("integrator", ["rk4", "dopri5"])
def test_computed_torque_with_the_exact_model_follows_the_quintic(preset, integrator):
    robot = getattr(spacearm.presets, preset)()
    q0 = robot.initial_q
    q1 = q0 + np.linspace(0.4, -0.3, robot.n_dof)
    ref = QuinticJoint(q0, q1, 0.2, 1.7)
    traj = spacearm.simulate(robot, 2.0, controller=ComputedTorque(kp=25.0, kd=10.0, reference=ref), integrator=integrator,
                             dt=2e-3 if integrator == "rk4" else 0.02, rtol=1e-10, atol=1e-12)
    q = traj["x"][:, 7:]
    q_ref = quintic(traj["t"], q0, q1, 0.2, 1.7)
    err = np.abs(q - q_ref).max()
    assert err < 1e-8, err
    np.testing.assert_allclose(traj["reference"], q_ref, atol=1e-14)
    np.testing.assert_allclose(traj["tracking_error"], np.linalg.norm(q_ref - q, axis=1), atol=1e-14)
    assert traj.meta["tracking_error_kind"] == "joint" and traj.meta["controller"] == "computed_torque"
    # Not trivial: the arm moved by the reference and the free base turned in reaction.
    assert np.abs(q[-1] - q0).max() > 0.3
    assert abs(traj["x"][-1, 6] - traj["x"][0, 6]) > 1e-4
    assert max(traj.meta["drift"].values()) < 1e-9


def test_computed_torque_with_a_mismatched_model_tracks_worse_but_converges():
    robot = spacearm.presets.spatial6()
    q0 = robot.initial_q
    q1 = q0 + 0.5
    ref = QuinticJoint(q0, q1, 0.0, 1.5)
    errs = {}
    for name, model in [
        ("exact", None),
        ("mass", perturbed_model(robot, base_mass_scale=0.8, link_mass_scale=1.3)),
        ("slosh", perturbed_model(robot, slosh_fraction=0.2, slosh_offset=(0.4, -0.3, 0.2))),
        ("removed", perturbed_model(robot, slosh_fraction=0.3, slosh_removed=True)),
    ]:
        traj = spacearm.simulate(robot, 4.0, dt=2e-3, record_every=5, controller=ComputedTorque(16.0, 8.0, ref, model=model))
        e = np.linalg.norm(traj["x"][:, 7:] - quintic(traj["t"], q0, q1, 0.0, 1.5), axis=1)
        errs[name] = (e.max(), e[-1])
    exact_max = errs["exact"][0]
    assert exact_max < 1e-9
    for name in ("mass", "slosh", "removed"):
        worst, final = errs[name]
        assert worst > 1e-4 and worst > 1e4 * exact_max, (name, worst)
        assert final < 0.05 * worst, (name, final, worst)  # the PD terms pull it back at rest


def test_perturbed_model_properties():
    robot = spacearm.presets.planar4()
    m = perturbed_model(robot, base_mass_scale=1.1, link_mass_scale=0.9, slosh_fraction=0.1, slosh_offset=(0.2, 0, 0))
    d0, d1 = robot.describe(), m.describe()
    assert d1["base"]["mass"] == pytest.approx(1.1 * d0["base"]["mass"])
    assert d1["links"][0]["mass"] == pytest.approx(0.9 * d0["links"][0]["mass"])
    # The base CM moved by f d = 0.02 m along x: the first joint's origin, measured from it, by -0.02.
    assert d1["links"][0]["origin"][0] == pytest.approx(d0["links"][0]["origin"][0] - 0.02)
    for bad in (dict(base_mass_scale=0.0), dict(slosh_fraction=1.0), dict(link_mass_scale=np.nan)):
        with pytest.raises(errors.ArgumentError):
            perturbed_model(robot, **bad)
    with pytest.raises(errors.ArgumentError, match="same|dofs"):
        spacearm.simulate(robot, 0.01, controller=ComputedTorque(1.0, 1.0, robot.initial_q[:4], model=spacearm.presets.spatial6()))


# ---- joint PD --------------------------------------------------------------------------------
def pd_gains(robot, omega=6.0):
    """Per-joint gains from the diagonal of H* (critically damped at ``omega``)."""
    h = np.diag(robot.generalized_inertia(robot.neutral_configuration()))
    return omega**2 * h, 2 * omega * h


@pytest.mark.parametrize("preset", ["planar4", "spatial6"])
def test_joint_pd_converges_to_the_set_point(preset):
    robot = getattr(spacearm.presets, preset)()
    kp, kd = pd_gains(robot)
    q0 = robot.initial_q
    q1 = q0 + np.resize([0.3, -0.2, 0.25, -0.3], robot.n_dof)
    traj = spacearm.simulate(robot, 5.0, dt=2e-3, record_every=10, controller=JointPD(kp, kd, QuinticJoint(q0, q1, 0.0, 1.5)))
    e = traj["tracking_error"]
    assert e.max() > 1e-3  # PD lags the moving reference
    assert e[-1] < 1e-4, e[-1]
    np.testing.assert_allclose(traj["x"][-1, 7:], q1, atol=1e-4)


def test_native_pd_equals_the_same_law_written_in_python():
    robot = spacearm.presets.spatial6()
    kp, kd = pd_gains(robot, 4.0)
    q0 = robot.initial_q
    q1 = q0 + 0.2
    ref = QuinticJoint(q0, q1, 0.0, 1.0)

    def pd(t, x, u):
        q_ref, qd_ref, _ = ref.evaluate(t)
        return kp * (q_ref - x[7:]) + kd * (qd_ref - u[6:])

    native = spacearm.simulate(robot, 1.2, dt=2e-3, controller=JointPD(kp, kd, ref))
    python = spacearm.simulate(robot, 1.2, dt=2e-3, controller=Callback(pd))
    np.testing.assert_allclose(python["x"], native["x"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(python["tau"], native["tau"], rtol=1e-12, atol=1e-12)
    assert np.abs(native["tau"]).max() > 0.1


# ---- resolved motion rate -------------------------------------------------------------------
@pytest.mark.parametrize("preset, delta", [("planar4", (0.3, 0.2, 0.0)), ("spatial6", (0.1, 0.15, -0.1))])
def test_rmrc_reaches_the_target_point_by_forward_kinematics(preset, delta):
    robot = getattr(spacearm.presets, preset)()
    x0 = robot.neutral_configuration()
    p0 = robot.point_position(x0)
    line = CartesianLine(p0, p0 + np.array(delta), 0.0, 2.0)
    traj = spacearm.simulate(robot, 3.0, dt=1e-3, record_every=10, controller=ResolvedMotionRate(line, gain=5.0))
    p_final = robot.point_position(traj["x"][-1])  # independent: forward kinematics of the final state
    assert np.linalg.norm(p_final - line.p_goal) < 1e-4
    # It followed the line all along, not only at the end.
    p_ref = line.evaluate(traj["t"])[0]
    assert np.abs(traj["ee_position"] - p_ref).max() < 5e-3
    np.testing.assert_allclose(traj["reference"], p_ref, atol=1e-14)
    assert traj.meta["tracking_error_kind"] == "cartesian"


def test_rmrc_compensates_the_momentum_drift():
    """With a drifting, tumbling base (non-zero momentum) the point still reaches the target,
    which moves with nothing: the J_0X H0^-1 M0 term is what makes this work."""
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    u0 = robot.zero_velocity()
    u0[:6] = [0.02, -0.01, 0.0, 0.0, 0.0, 0.01]
    p0 = robot.point_position(x0)
    line = CartesianLine(p0, p0 + [0.05, 0.1, 0.0], 0.0, 2.0)
    traj = spacearm.simulate(robot, 3.0, x0=x0, u0=u0, dt=1e-3, record_every=10, controller=ResolvedMotionRate(line, gain=5.0))
    assert np.linalg.norm(traj["P"][0]) > 1.0
    assert np.linalg.norm(robot.point_position(traj["x"][-1]) - line.p_goal) < 1e-3
    # Without the arm moving the point would have drifted away by centimetres.
    free = spacearm.simulate(robot, 3.0, x0=x0, u0=u0, dt=1e-2)
    assert np.linalg.norm(free["ee_position"][-1] - p0) > 0.05


def test_rmrc_stays_bounded_through_an_unreachable_target():
    """A target beyond reach drives the arm to full stretch (a singularity): the damping keeps
    the joint rates bounded and the run finite."""
    robot = spacearm.presets.planar4()
    x0 = robot.neutral_configuration()
    p0 = robot.point_position(x0)
    line = CartesianLine(p0, p0 + [5.0, 0.0, 0.0], 0.0, 2.0)
    traj = spacearm.simulate(robot, 3.0, dt=1e-3, record_every=10, controller=ResolvedMotionRate(line, gain=2.0, max_damping=0.1, threshold=0.2))
    assert np.all(np.isfinite(traj["u"]))
    assert np.abs(traj["u"][:, 6:]).max() < 20.0
    assert traj["tracking_error"][-1] > 1.0  # it could not get there


@pytest.mark.parametrize("preset, delta, task", [("spatial7", (-0.2, 0.1, 0.15), "position"), ("planar4", (0.3, 0.2, 0.0), "planar")])
def test_reactionless_rmrc_leaves_the_base_attitude_alone(preset, delta, task):
    """The native controller with strategy "reactionless" moves the arm in the reaction null
    space: the base attitude of the simulated trajectory (independent of the controller: the
    integrated quaternion) barely moves, where the naive law turns the base by degrees. What is
    left comes from the velocity loop's lag (q̇ ≠ q̇_cmd), so it shrinks as 1/velocity_gain."""
    from scipy.spatial.transform import Rotation

    robot = getattr(spacearm.presets, preset)()
    x0 = robot.neutral_configuration()
    p0 = robot.point_position(x0)
    line = CartesianLine(p0, p0 + np.array(delta), 0.0, 2.0)
    turn = {}
    for strategy in ("naive", "reactionless"):
        rmrc = ResolvedMotionRate(line, gain=5.0, task=task, strategy=strategy, velocity_gain=500.0)
        traj = spacearm.simulate(robot, 3.0, dt=1e-3, record_every=10, controller=rmrc)
        assert np.linalg.norm(robot.point_position(traj["x"][-1]) - line.p_goal) < 2e-5
        turn[strategy] = (Rotation.from_quat(traj["x"][:, 3:7]) * Rotation.from_quat(x0[3:7]).inv()).magnitude().max()
        if strategy == "reactionless":
            assert np.abs(traj["u"][:, 3:6]).max() < 5e-5
    assert turn["naive"] > 1e-2
    assert turn["reactionless"] < 2e-5 and turn["reactionless"] < 1e-3 * turn["naive"]


@pytest.mark.parametrize("strategy", ["naive", "reactionless", "minimum_disturbance"])
def test_native_rmrc_command_is_the_analysis_rmrc_rates(strategy):
    """One solver: at rest (zero momentum, c* = 0) the native controller's torque is
    τ = H* K_v q̇_cmd, and q̇_cmd equals spacearm.analysis.rmrc_rates for the same state and
    desired twist K (p_ref − p)."""
    robot = spacearm.presets.spatial7()
    x0 = robot.neutral_configuration()
    p0 = robot.point_position(x0)
    offset, gain, kv = np.array([0.02, -0.015, 0.01]), 5.0, 50.0
    line = CartesianLine(p0 + offset, p0 + offset, 0.0, 1.0)
    rmrc = ResolvedMotionRate(line, gain=gain, strategy=strategy, velocity_gain=kv)
    traj = spacearm.simulate(robot, 0.002, dt=1e-3, joint_limits=False, controller=rmrc)
    assert traj["t"][0] == 0.0
    qd_cmd = np.linalg.solve(robot.generalized_inertia(x0), traj["tau"][0]) / kv
    rates = analysis.rmrc_rates(robot, x0, np.r_[gain * offset, 0.0, 0.0, 0.0], task="position", strategy=strategy)
    assert np.abs(rates.qd).max() > 0.1
    np.testing.assert_allclose(qd_cmd, rates.qd, rtol=0, atol=1e-12)


# ---- attitude control with reaction wheels --------------------------------------------------
def test_attitude_control_holds_the_base_while_the_arm_moves():
    robot = with_wheels(spacearm.presets.spatial6())
    assert spacearm._core.default_wheel_dofs(robot.core_model) == [6, 7, 8]
    q0 = robot.initial_q[:6]
    ref = QuinticJoint(q0, q0 + 0.5, 0.0, 3.0)
    arm = ComputedTorque(25.0, 10.0, ref)
    held = spacearm.simulate(robot, 4.0, mode="rotation-floating", dt=2e-3, record_every=5,
                             controller=Combined(arm=arm, base=AttitudeControl([0, 0, 0, 1], kp=2e4, kd=3e3)))
    free = spacearm.simulate(robot, 4.0, mode="rotation-floating", dt=2e-3, record_every=5, controller=arm)
    angle = lambda x: 2 * np.arccos(np.minimum(1.0, np.abs(x[:, 6])))  # noqa: E731
    assert angle(free["x"]).max() > 0.1  # without wheels the base turns
    assert angle(held["x"]).max() < 3e-3
    np.testing.assert_allclose(held["attitude_error"], angle(held["x"]), atol=1e-12)
    # The arm still tracks exactly: computed torque compensates the wheel torques.
    assert held["tracking_error"].max() < 1e-9
    assert held.meta["wheel_dofs"] == [6, 7, 8] and held["wheel_speed"].shape == (len(held), 3)
    # Momentum bookkeeping: L is linear in u, L = L(base) + L(arm) + L(wheels). Total L stays 0;
    # with the base held the wheels carry minus the arm's angular momentum.
    worst, scale = 0.0, 0.0
    for x, u in zip(held["x"][::20], held["u"][::20]):
        parts = []
        for dofs in (slice(0, 6), slice(6, 12), slice(12, 15)):
            uu = np.zeros_like(u)
            uu[dofs] = u[dofs]
            parts.append(robot.momentum(x, uu).L_origin)
        l_base, l_arm, l_wheels = parts
        worst = max(worst, np.linalg.norm(l_wheels + l_arm))
        scale = max(scale, np.linalg.norm(l_arm))
        np.testing.assert_allclose(l_base + l_arm + l_wheels, 0.0, atol=1e-9)
    assert scale > 1.0
    assert worst < 0.05 * scale, (worst, scale)
    assert max(held.meta["drift"].values()) < 1e-9


def test_arm_keeps_tracking_while_the_wheels_saturate():
    # Wheel torques limited to 1 N m: the attitude controller asks for more, the wheels saturate
    # and the base turns. The computed-torque arm controller inside Combined compensates the
    # torques the wheels actually apply, so the arm still follows its quintic (an independent
    # closed form) to integration accuracy; the saturation is recorded, not hidden.
    robot = with_wheels(spacearm.presets.spatial6(), max_torque=1.0)
    q0 = robot.initial_q[:6]
    ref = QuinticJoint(q0, q0 + 0.5, 0.0, 3.0)
    traj = spacearm.simulate(robot, 4.0, mode="rotation-floating", dt=2e-3, record_every=5,
                             controller=Combined(arm=ComputedTorque(25.0, 10.0, ref),
                                                 base=AttitudeControl([0, 0, 0, 1], kp=2e4, kd=3e3)))
    assert len(traj["saturation_t"]) > 0
    assert np.abs(traj["tau_cmd"][:, 6:]).max() > 2.0
    assert np.abs(traj["tau"][:, 6:]).max() == pytest.approx(1.0)
    assert traj["attitude_error"].max() > 5e-3  # saturated wheels cannot hold the base
    t = traj["t"]
    np.testing.assert_allclose(traj["x"][:, 7:13], quintic(t, q0, q0 + 0.5, 0.0, 3.0), atol=1e-7)


def test_attitude_control_turns_the_base_to_a_new_attitude_and_saturates_wheels():
    robot = with_wheels(spacearm.presets.planar4(), max_torque=2.0, max_speed=200.0)
    target = np.r_[np.sin(0.1) * np.array([0.0, 0.6, 0.8]), np.cos(0.1)]  # 0.2 rad about (0, .6, .8)
    traj = spacearm.simulate(robot, 20.0, mode="rotation-floating", dt=5e-3, record_every=10,
                             controller=AttitudeControl(target, kp=60.0, kd=150.0))
    assert traj["attitude_error"][0] == pytest.approx(0.2, rel=1e-9)
    assert traj["attitude_error"][-1] < 2e-3
    np.testing.assert_allclose(np.abs(traj["x"][-1, 3:7] @ target), 1.0, atol=1e-5)
    # The commanded torque exceeded the 2 N m limit at the start: clamped and recorded.
    names = traj.meta["actuator_names"]
    events = [(names[a], k) for a, k in zip(traj["saturation_actuator"], traj["saturation_kind"])]
    assert ("wheel2_joint", 0) in events or ("wheel3_joint", 0) in events
    assert np.abs(traj["tau"][:, 4:]).max() == pytest.approx(2.0)
    assert np.abs(traj["tau_cmd"][:, 4:]).max() > 2.0


def test_attitude_control_needs_wheels_and_the_rotation_floating_mode():
    plain = spacearm.presets.planar4()
    with pytest.raises(errors.ArgumentError, match="reaction wheels"):
        spacearm.simulate(plain, 0.01, mode="rotation-floating", controller=AttitudeControl([0, 0, 0, 1], 1.0, 1.0))
    wheeled = with_wheels(plain)
    with pytest.raises(errors.ArgumentError, match="rotation-floating"):
        spacearm.simulate(wheeled, 0.01, mode="floating", controller=AttitudeControl([0, 0, 0, 1], 1.0, 1.0))
    with pytest.raises(errors.QuaternionError):
        spacearm.simulate(wheeled, 0.01, mode="rotation-floating", controller=AttitudeControl([0, 0, 0, 2], 1.0, 1.0))
    with pytest.raises(errors.ArgumentError, match="kp"):
        spacearm.simulate(wheeled, 0.01, mode="rotation-floating", controller=AttitudeControl([0, 0, 0, 1], -1.0, 1.0))
    # Wheels named explicitly, by joint name.
    traj = spacearm.simulate(wheeled, 0.01, mode="rotation-floating", wheels=["wheel1_joint", "wheel2"],
                             controller=AttitudeControl([0, 0, 0, 1], 1.0, 1.0))
    assert traj.meta["wheel_dofs"] == [4, 5]


# ---- coordinated flying ---------------------------------------------------------------------
@pytest.mark.parametrize("preset", ["planar4", "spatial6"])
def test_coordinated_flying_tracks_the_line_and_holds_the_base(preset):
    robot = getattr(spacearm.presets, preset)()
    x0 = robot.neutral_configuration()
    p0 = robot.point_position(x0)
    line = CartesianLine(p0, p0 + [0.1, 0.15, 0.0], 0.0, 2.0)
    traj = spacearm.simulate(robot, 2.5, mode="flying", dt=1e-3, record_every=5, controller=CoordinatedFlying(line))
    assert traj["tracking_error"].max() < 1e-9
    assert np.linalg.norm(robot.point_position(traj["x"][-1]) - line.p_goal) < 1e-9
    assert np.abs(traj["x"][:, :7] - x0[:7]).max() < 1e-12  # the base does not move at all
    assert np.abs(traj["base_wrench"]).max() > 1.0  # ... because the thrusters work
    assert traj.meta["conserved"] == []


def test_coordinated_flying_forces_are_the_flying_regime_reduced_eom():
    """tau = H* qdd + c* + H0m^T H0^-1 F_b (numpy, from the robot's H*, c*, H0, H0m) and
    F_b = H0 xdd0 + H0m qdd + c0, at recorded samples (the applied accelerations are the
    commanded ones: exact model, no saturation)."""
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    p0 = robot.point_position(x0)
    line = CartesianLine(p0, p0 + [0.1, -0.1, 0.05], 0.0, 1.0)
    base_ref = (np.array([0.05, 0.0, -0.02]), np.r_[np.sin(0.05) * np.array([0.0, 0.0, 1.0]), np.cos(0.05)])
    traj = spacearm.simulate(robot, 1.0, mode="flying", dt=1e-3, record_every=50,
                             controller=CoordinatedFlying(line, base_pose_ref=base_ref))
    for i in (3, 10, 17):
        x, u, du = traj["x"][i], traj["u"][i], traj["du"][i]
        blocks = robot.inertia_blocks(x)
        c = robot.bias_forces(x, u)
        f_b = blocks.H0 @ du[:6] + blocks.H0m @ du[6:] + c[:6]
        np.testing.assert_allclose(traj["base_wrench"][i], f_b, rtol=1e-9, atol=1e-9)
        tau = robot.generalized_inertia(x) @ du[6:] + robot.generalized_bias(x, u) + blocks.H0m.T @ np.linalg.solve(blocks.H0, f_b)
        np.testing.assert_allclose(traj["tau"][i], tau, rtol=1e-9, atol=1e-9)
        assert np.abs(traj["tau"][i]).max() > 0.01


def test_coordinated_flying_moves_the_base_with_the_closed_form_response():
    """Base position error obeys e'' + kd e' + kp e = 0: critically damped for kp = 25,
    kd = 10, e(t) = e0 (1 + 5 t) exp(-5 t), while the end effector still tracks its line."""
    robot = spacearm.presets.spatial6()
    x0 = robot.neutral_configuration()
    p0 = robot.point_position(x0)
    r_ref = np.array([0.1, -0.05, 0.03])
    line = CartesianLine(p0, p0 + [0.0, 0.1, 0.0], 0.0, 2.0)
    traj = spacearm.simulate(robot, 2.0, mode="flying", dt=1e-3, record_every=20,
                             controller=CoordinatedFlying(line, base_pose_ref=(r_ref, [0, 0, 0, 1]), kp_base=25.0, kd_base=10.0))
    t = traj["t"][:, None]
    expect = r_ref + (x0[:3] - r_ref) * (1 + 5 * t) * np.exp(-5 * t)
    np.testing.assert_allclose(traj["x"][:, :3], expect, atol=1e-9)
    assert traj["tracking_error"].max() < 1e-8


def test_coordinated_flying_needs_the_flying_mode_and_no_wheels():
    robot = spacearm.presets.planar4()
    p0 = robot.point_position(robot.neutral_configuration())
    ctrl = CoordinatedFlying(CartesianLine(p0, p0, 0.0, 1.0))
    with pytest.raises(errors.ArgumentError, match="flying"):
        spacearm.simulate(robot, 0.01, mode="rotation-flying", controller=ctrl)
    with pytest.raises(errors.ArgumentError, match="wheels"):
        spacearm.simulate(with_wheels(robot), 0.01, mode="flying", controller=ctrl)
    traj = spacearm.simulate(with_wheels(robot), 0.05, mode="flying", wheels=[], controller=ctrl)
    assert traj["tracking_error"].max() < 1e-9


# ---- thruster regulation (rotation-flying, translation-flying) -----------------------------
def test_translation_flying_moves_the_system_cm_with_the_closed_form_response():
    """A force through the system CM: M r_g'' = F0, so with F0 = M (kp e - kd r_g') the CM error
    is e0 (1 + 2 t) exp(-2 t) for kp = kd = 4 (critically damped), while the arm tracks its
    quintic exactly (computed torque compensates the applied wrench) and L about the CM stays."""
    robot = spacearm.presets.spatial6()
    q0 = robot.initial_q
    ref = QuinticJoint(q0, q0 + 0.5, 0.0, 2.0)
    x0 = robot.neutral_configuration()
    rg0 = robot.center_of_mass(x0)
    target = rg0 + np.array([0.2, -0.1, 0.05])
    traj = spacearm.simulate(robot, 3.0, mode="translation-flying", dt=1e-3, record_every=10,
                             controller=Combined(arm=ComputedTorque(25.0, 10.0, ref),
                                                 base=BaseThrusterControl(com_ref=target, kp_position=4.0, kd_position=4.0)))
    t = traj["t"][:, None]
    np.testing.assert_allclose(traj["com"], target + (rg0 - target) * (1 + 2 * t) * np.exp(-2 * t), atol=1e-10)
    assert traj["tracking_error"].max() < 1e-9
    assert traj.meta["conserved"] == ["L_com"] and traj.meta["drift"]["L_com"] < 1e-10
    # The applied couple is the moment of the force about the base CM: none about the system CM.
    r0, com, w = traj["x"][:, :3], traj["com"], traj["base_wrench"]
    np.testing.assert_allclose(w[:, 3:], np.cross(com - r0, w[:, :3]), atol=1e-12)
    assert np.abs(w[:, :3]).max() > 1.0


def test_rotation_flying_holds_the_attitude_with_thruster_torques():
    robot = spacearm.presets.spatial6()
    q0 = robot.initial_q
    arm = ComputedTorque(25.0, 10.0, QuinticJoint(q0, q0 + 0.5, 0.0, 2.0))
    held = spacearm.simulate(robot, 3.0, mode="rotation-flying", dt=1e-3, record_every=10,
                             controller=Combined(arm=arm, base=BaseThrusterControl(kp_attitude=2e4, kd_attitude=3e3)))
    free = spacearm.simulate(robot, 3.0, mode="rotation-flying", dt=1e-3, record_every=10, controller=arm)
    angle = lambda x: 2 * np.arccos(np.minimum(1.0, np.abs(x[:, 6])))  # noqa: E731
    assert angle(free["x"]).max() > 0.1 and angle(held["x"]).max() < 1e-2
    assert np.all(held["base_wrench"][:, :3] == 0)  # torque only
    assert held.meta["drift"]["P"] < 1e-10 and held["tracking_error"].max() < 1e-9
    # Euler for the whole system: L about the origin changes by the integral of the torque.
    dl = held["L_origin"] - held["L_origin"][0]
    n = held["base_wrench"][:, 3:]
    integral = np.r_[np.zeros((1, 3)), np.cumsum(0.5 * (n[1:] + n[:-1]) * np.diff(held["t"])[:, None], axis=0)]
    assert np.abs(dl).max() > 1.0
    np.testing.assert_allclose(dl, integral, atol=1e-3 * np.abs(dl).max())


def test_thruster_control_needs_a_flying_mode():
    with pytest.raises(errors.ArgumentError, match="flying mode"):
        spacearm.simulate(spacearm.presets.planar4(), 0.01, mode="floating", controller=BaseThrusterControl())


def test_inertia_scaled_gains_follow_the_diagonal_of_the_schur_complement():
    # H* = Hm − H0mᵀ H0⁻¹ H0m from the CRBA mass matrix (numpy), not from the core's GJM.
    robot = spacearm.presets.spatial6()
    x = robot.neutral_configuration(q=[0.3, -0.4, 0.5, 0.2, -0.1, 0.7])
    h = robot.mass_matrix(x)
    h_star = h[6:, 6:] - h[:6, 6:].T @ np.linalg.solve(h[:6, :6], h[:6, 6:])
    joints = [0, 2, 5]
    kp, kd = spacearm.control.inertia_scaled_gains(robot, x, joints, natural_frequency=3.0, damping_ratio=0.7)
    np.testing.assert_allclose(kp, 9.0 * np.diag(h_star)[joints], rtol=1e-12)
    np.testing.assert_allclose(kd, 2 * 0.7 * 3.0 * np.diag(h_star)[joints], rtol=1e-12)
    with pytest.raises(spacearm.ArgumentError, match="natural_frequency"):
        spacearm.control.inertia_scaled_gains(robot, x, joints, natural_frequency=0.0)


def test_every_joint_reference_evaluates_a_scalar_time_to_one_row():
    from spacearm import control

    # One shape rule (issue 37 item 8): ShapedJoint.evaluate(0.5) gave (1, n) where
    # QuinticJoint.evaluate(0.5) gives (n,); an array of times gives (len(t), n) for all.
    q = control.QuinticJoint([0.0, 1.0], [1.0, 2.0], t_start=0.0, t_end=1.0)
    shaped = control.ShapedJoint(q, control.input_shaper("zv", frequency=3.0))
    t = np.linspace(0.0, 1.0, 5)
    qs, qds, qdds = q.evaluate(t)
    sampled = control.SampledJoint(t=t, q=qs, qd=qds, qdd=qdds)
    for ref in (q, shaped, sampled):
        one = ref.evaluate(0.5)
        many = ref.evaluate([0.25, 0.5])
        assert [np.shape(a) for a in one] == [(2,)] * 3, type(ref).__name__
        assert [np.shape(a) for a in many] == [(2, 2)] * 3, type(ref).__name__
        for a, b in zip(one, many):
            assert np.array_equal(a, b[1])


def test_residual_vibration_is_singer_seerings_v():
    # Independently of the core: superpose the damped impulse responses
    # h(t) = e^{-ζω t} sin(ω_d t) of the shaper's impulses and compare the residual amplitude
    # with one unit impulse at t_N (V's definition) and at 0 (the unshaped move); they agree
    # only for ζ = 0 (issue 37 item 8: the docstring said "relative to the unshaped one").
    from spacearm import control

    omega = 3.0
    shaper = control.input_shaper("zv", frequency=2.5, damping=0.05)  # off the design mode
    amps, times = np.asarray(shaper.amplitudes), np.asarray(shaper.times)
    t_n = times[-1]
    t = t_n + 1.7

    def amplitude(impulses, zeta):
        # y(t) = Σ a e^{-ζω(t-τ)} sin(ω_d (t-τ)) = e^{-ζωt} (A sin ω_d t - B cos ω_d t): amplitude e^{-ζωt} √(A²+B²)
        wd = omega * np.sqrt(1 - zeta**2)
        a = sum(c * np.exp(zeta * omega * tau) * np.cos(wd * tau) for c, tau in impulses)
        b = sum(c * np.exp(zeta * omega * tau) * np.sin(wd * tau) for c, tau in impulses)
        return np.exp(-zeta * omega * t) * np.hypot(a, b)

    shaped = list(zip(amps, times))
    for zeta in (0.15, 0.0):
        v = shaper.residual_vibration(omega, zeta)
        assert v == pytest.approx(amplitude(shaped, zeta) / amplitude([(1.0, t_n)], zeta), rel=1e-12)
        relative_to_unshaped = amplitude(shaped, zeta) / amplitude([(1.0, 0.0)], zeta)
        assert v * np.exp(zeta * omega * t_n) == pytest.approx(relative_to_unshaped, rel=1e-12)
        assert (v == pytest.approx(relative_to_unshaped, rel=1e-12)) == (zeta == 0.0)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"slosh_fraction": float("nan")}, r"slosh_fraction must be in \[0, 1\), got NaN"),
    ({"slosh_fraction": 1.5, "slosh_removed": True}, r"slosh_fraction must be in \[0, 1\), got 1.5"),
    ({"slosh_fraction": 0.2, "slosh_offset": (0.0, float("inf"), 0.0)}, r"slosh_offset must be finite, got \[0, inf, 0\]"),
])
def test_a_bad_slosh_perturbation_names_the_argument_and_its_value(kwargs, message):
    # The core judges the slosh perturbation (control/mismatch.rs); its message names the
    # argument and the value given, not the internal enum.
    with pytest.raises(errors.ArgumentError, match=message):
        perturbed_model(spacearm.presets.spatial6(), **kwargs)
