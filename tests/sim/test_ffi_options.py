"""The typed inputs of the simulation bindings (``_core.RunOptions``, ``_core.ThrusterLimits``,
the references and the controller specs): what ``spacearm.control`` builds, what they refuse,
and runs of hand-built specs through ``_core.simulate``, ``_core.rollout`` and
``_core.Simulator`` checked against closed forms (the quintic, a PD set point, the CM response
to a force through it, a saturated thruster's constant acceleration)."""

import pickle

import numpy as np
import pytest

import spacearm
from spacearm import _core, control, errors


@pytest.fixture(scope="module")
def robot():
    return spacearm.presets.planar4()


def quintic(t, q0, q1, t0, t1):
    """Independent closed form: q0 + (q1 - q0)(10τ³ − 15τ⁴ + 6τ⁵)."""
    tau = np.clip((np.asarray(t) - t0) / (t1 - t0), 0, 1)[:, None]
    return q0 + (q1 - q0) * (10 * tau**3 - 15 * tau**4 + 6 * tau**5)


# ---- construction ----------------------------------------------------------------------------
def test_run_options_keep_the_core_defaults_for_what_is_not_given():
    options = _core.RunOptions(dt=2e-3, mode="flying", record_dtype="float32")
    assert (options.dt, options.mode, options.record_dtype) == (2e-3, "flying", "float32")
    for key in ("integrator", "rtol", "atol", "record_every", "joint_limits", "max_steps"):
        assert getattr(options, key) == _core.SIM_DEFAULTS[key], key
    assert options.wheels is None and options.thrusters is None and options.progress is None
    assert "RunOptions" in repr(options)


@pytest.mark.parametrize("build", [
    lambda: _core.RunOptions(dtt=1e-3),
    lambda: _core.ThrusterLimits(max_force=[1.0] * 3, max_torque=[1.0] * 3, max_thrust=1.0),
    lambda: _core.CartesianReference(p_start=[0.0] * 3, p_goal=[1.0] * 3, t_start=0.0, t_end=1.0, point="ee"),
    lambda: _core.JointPdSpec(kp=[1.0], kd=[1.0], reference=_core.JointReference.constant(q=[0.0]), ki=[1.0]),
    lambda: _core.AttitudeSpec(quat_ref=[0, 0, 0, 1], kp=1.0, kd=1.0, kq=1.0),
    lambda: _core.BaseThrustersSpec(kp_position=1.0, kd_position=1.0, kp_attitude=0.0, kd_attitude=0.0, r_ref=[0, 0, 0]),
    lambda: _core.CallbackSpec(fn=print, args=()),
])
def test_an_unknown_keyword_is_refused_and_the_known_ones_are_listed(build):
    with pytest.raises(errors.ArgumentError, match="unknown key '.*'; expected one of"):
        build()


def test_values_are_checked_when_built():
    with pytest.raises(errors.ArgumentError, match="record_dtype must be 'float64' or 'float32'"):
        _core.RunOptions(record_dtype="float16")
    with pytest.raises(errors.ArgumentError, match="record_every must be an integer >= 1"):
        _core.RunOptions(record_every=0)
    with pytest.raises(errors.ArgumentError, match="thrusters must be a ThrusterLimits, got dict"):
        _core.RunOptions(thrusters={"max_force": [1.0] * 3, "max_torque": [1.0] * 3})
    with pytest.raises(errors.ArgumentError):
        _core.ThrusterLimits(max_force=[1.0, 0.0, 1.0], max_torque=[1.0] * 3)
    with pytest.raises(errors.ShapeError):
        _core.JointReference.quintic(q_start=[0.0, 0.0], q_goal=[1.0], t_start=0.0, t_end=1.0)
    with pytest.raises(errors.ArgumentError, match="t_end"):
        _core.CartesianReference(p_start=[0.0] * 3, p_goal=[1.0] * 3, t_start=1.0, t_end=1.0)
    with pytest.raises(errors.ArgumentError, match="controller type must be one of"):
        _core.CombinedSpec(arm={"type": "joint_pd"}, base=_core.ZeroTorqueSpec())
    with pytest.raises(errors.ArgumentError, match="callable"):
        _core.CallbackSpec(fn=3)
    with pytest.raises(errors.ArgumentError, match="both base_position and base_quat"):
        _core.CoordinatedFlyingSpec(reference=_core.CartesianReference(p_start=[0.0] * 3, p_goal=[1.0] * 3, t_start=0.0, t_end=1.0),
                                    body=4, offset=[0, 0, 0], kp_ee=1.0, kd_ee=1.0, kp_base=1.0, kd_base=1.0, max_damping=0.1,
                                    threshold=0.1, base_position=[0, 0, 0])


def test_the_control_classes_build_typed_specs_that_carry_what_the_user_gave(robot):
    q0 = robot.initial_q
    ref = control.QuinticJoint(q0, q0 + 0.3, 0.5, 2.0)
    spec = control.ComputedTorque(kp=[1.0, 2.0, 3.0, 4.0], kd=5.0, reference=ref, model=robot)._spec(robot)
    assert isinstance(spec, _core.ComputedTorqueSpec) and spec.has_model
    assert spec.kp == [1.0, 2.0, 3.0, 4.0] and spec.kd == [5.0]
    assert isinstance(spec.reference, _core.JointReference) and spec.reference.kind == "quintic"
    np.testing.assert_array_equal(spec.reference.q_goal, q0 + 0.3)
    assert (spec.reference.t_start, spec.reference.t_end) == (0.5, 2.0)

    set_point = control.JointPD(kp=1.0, kd=1.0, reference=q0)._spec(robot).reference
    assert set_point.kind == "constant" and set_point.t_start is None
    np.testing.assert_array_equal(set_point.q_start, q0)

    line = control.CartesianLine([1.0, 0.5, 0.0], [1.2, 0.4, 0.0], 0.0, 1.0)
    rmrc = control.ResolvedMotionRate(line, gain=3.0)._spec(robot)
    assert isinstance(rmrc, _core.RmrcSpec) and rmrc.gain == 3.0
    assert rmrc.max_damping == _core.DLS_DEFAULTS["max_damping"] and rmrc.threshold == _core.DLS_DEFAULTS["threshold"]
    # The default point is the end effector: its body and offset, as the robot resolves them.
    body, offset = robot._point(None)
    assert rmrc.body == body
    np.testing.assert_array_equal(rmrc.offset, offset)
    np.testing.assert_array_equal(rmrc.reference.p_goal, [1.2, 0.4, 0.0])
    # Today's law by default: the translational rows, naive; the analysis' names otherwise.
    assert (rmrc.task, rmrc.strategy) == ([0, 1, 2], "naive")
    spec = control.ResolvedMotionRate(line, gain=3.0, task="planar", strategy="reactionless")._spec(robot)
    assert (spec.task, spec.strategy) == ([0, 1], "reactionless")
    assert control.ResolvedMotionRate(line, gain=3.0, task=[0, 1, 5])._spec(robot).task == [0, 1, 5]
    with pytest.raises(errors.ArgumentError, match="strategy"):
        control.ResolvedMotionRate(line, gain=3.0, strategy="minimal")._spec(robot)
    with pytest.raises(errors.ArgumentError, match="strategy"):
        control.ResolvedMotionRate(line, gain=3.0, strategy=1)._spec(robot)
    with pytest.raises(errors.ArgumentError, match="task"):
        control.ResolvedMotionRate(line, gain=3.0, task="sideways")._spec(robot)
    with pytest.raises(errors.ShapeError):
        control.ResolvedMotionRate(line, gain=3.0, task=[0, 0])._spec(robot)

    base = control.BaseThrusterControl(com_ref=[1.0, 2.0, 3.0], kp_position=4.0)
    combined = control.Combined(arm=control.JointPD(1.0, 1.0, q0), base=base)._spec(robot)
    assert isinstance(combined.arm, _core.JointPdSpec) and isinstance(combined.base, _core.BaseThrustersSpec)
    np.testing.assert_array_equal(combined.base.com_ref, [1.0, 2.0, 3.0])
    assert combined.base.quat_ref is None and combined.base.kp_position == 4.0

    limits = control.Thrusters(max_force=2.0, max_torque=[1.0, np.inf, 3.0])._spec()
    assert isinstance(limits, _core.ThrusterLimits)
    np.testing.assert_array_equal(limits.max_force, [2.0, 2.0, 2.0])
    np.testing.assert_array_equal(limits.max_torque, [1.0, np.inf, 3.0])


def test_controllers_still_pickle_and_simulate_after_a_round_trip(robot):
    ctrl = control.JointPD(kp=50.0, kd=10.0, reference=control.QuinticJoint(robot.initial_q, robot.initial_q + 0.2, 0.0, 0.5))
    again = pickle.loads(pickle.dumps(ctrl))
    a = spacearm.simulate(robot, 0.3, controller=ctrl)
    b = spacearm.simulate(robot, 0.3, controller=again)
    np.testing.assert_array_equal(a["x"], b["x"])


# ---- runs of hand-built specs against closed forms --------------------------------------------
def test_computed_torque_spec_follows_the_closed_form_quintic(robot):
    q0 = robot.initial_q
    q1 = q0 + np.array([0.4, -0.2, 0.3, -0.1])
    reference = _core.JointReference.quintic(q_start=q0, q_goal=q1, t_start=0.2, t_end=1.2)
    spec = _core.ComputedTorqueSpec(kp=[25.0], kd=[10.0], reference=reference)
    data = _core.simulate(robot.core_model, robot.neutral_configuration(), robot.zero_velocity(), 1.5, _core.RunOptions(dt=2e-3), spec).records.to_dict()
    err = np.abs(data["x"][:, 7:] - quintic(data["t"], q0, q1, 0.2, 1.2)).max()
    assert err < 1e-8, err
    assert np.abs(data["x"][-1, 7:] - q0).max() > 0.3  # the arm did move


def test_joint_pd_spec_settles_at_its_set_point(robot):
    """At rest the PD torque kp (q_ref - q) is zero only at q_ref: the steady state is the set point."""
    q_ref = robot.initial_q + np.array([0.3, -0.2, 0.1, 0.25])
    spec = _core.JointPdSpec(kp=[200.0], kd=[100.0], reference=_core.JointReference.constant(q=q_ref))
    data = _core.simulate(robot.core_model, robot.neutral_configuration(), robot.zero_velocity(), 15.0,
                          _core.RunOptions(dt=5e-3, record_every=100), spec).records.to_dict()
    np.testing.assert_allclose(data["x"][-1, 7:], q_ref, atol=1e-5)
    np.testing.assert_allclose(data["u"][-1, 6:], 0.0, atol=1e-5)


def test_base_thrusters_spec_moves_the_cm_with_the_closed_form_response(robot):
    """F0 = M (kp e - kd r_g') through the CM: e'' + kd e' + kp e = 0; kp = kd²/4 = 4 is critically
    damped, e(t) = e0 (1 + 2 t) exp(-2 t)."""
    x0 = robot.neutral_configuration()
    rg0 = robot.center_of_mass(x0)
    target = rg0 + np.array([0.3, -0.2, 0.0])
    spec = _core.BaseThrustersSpec(com_ref=target, kp_position=4.0, kd_position=4.0, kp_attitude=0.0, kd_attitude=0.0)
    data = _core.simulate(robot.core_model, x0, robot.zero_velocity(), 2.0,
                          _core.RunOptions(mode="translation-flying", dt=1e-3, record_every=10), spec).records.to_dict()
    t = data["t"][:, None]
    np.testing.assert_allclose(data["com"], target + (rg0 - target) * (1 + 2 * t) * np.exp(-2 * t), atol=1e-10)


def test_thruster_limits_clamp_the_force_to_a_constant_acceleration(robot):
    """A command far beyond the limit along x only: F0_x = max_force throughout, so the CM moves
    by max_force t² / (2 M) along x and not at all along y and z."""
    x0 = robot.neutral_configuration()
    rg0 = robot.center_of_mass(x0)
    max_force = 2.0
    spec = _core.BaseThrustersSpec(com_ref=rg0 + [1000.0, 0.0, 0.0], kp_position=100.0, kd_position=1.0, kp_attitude=0.0,
                                   kd_attitude=0.0)
    limits = _core.ThrusterLimits(max_force=[max_force] * 3, max_torque=[np.inf] * 3)
    data = _core.simulate(robot.core_model, x0, robot.zero_velocity(), 1.0,
                          _core.RunOptions(mode="translation-flying", dt=1e-3, record_every=10, thrusters=limits), spec).records.to_dict()
    t = data["t"]
    expected = rg0 + np.outer(max_force * t**2 / (2 * robot.total_mass), [1.0, 0.0, 0.0])
    np.testing.assert_allclose(data["com"], expected, atol=1e-10)
    assert np.abs(data["com"][-1, 0] - rg0[0]) > 1e-3


def test_rollout_takes_one_spec_per_rollout_and_the_zero_torque_spec(robot):
    q_refs = robot.initial_q + np.array([[0.2], [-0.1]])
    specs = [_core.JointPdSpec(kp=[200.0], kd=[100.0], reference=_core.JointReference.constant(q=q)) for q in q_refs]
    x0 = np.tile(robot.neutral_configuration(), (2, 1))
    u0 = np.tile(robot.zero_velocity(), (2, 1))
    options = _core.RunOptions(dt=5e-3, record_every=200)
    data = _core.rollout([robot.core_model], x0, u0, 15.0, options, specs).records.to_dict()
    np.testing.assert_allclose(data["x"][:, -1, 7:], q_refs, atol=1e-5)
    # No control: a joint speed given keeps the arm moving (no torque stops it); at rest it stays.
    u0[1, 7] = 0.1
    free = _core.rollout([robot.core_model], x0, u0, 1.0, options, [_core.ZeroTorqueSpec(), _core.ZeroTorqueSpec()]).records.to_dict()
    assert np.abs(free["x"][1, -1, 7:] - free["x"][1, 0, 7:]).max() > 1e-3
    np.testing.assert_array_equal(free["x"][0, -1], x0[0])


def test_simulator_takes_the_options_and_a_callback_spec(robot):
    """A callback commanding tau_1 = c on a system at rest: the joint accelerates as the forward
    dynamics of the robot say (an independent call), for the first step to RK4 accuracy."""
    c = 0.5
    seen = []

    def fn(t, x, u):
        seen.append(t)
        tau = np.zeros(robot.n_dof)
        tau[0] = c
        return tau

    sim = _core.Simulator(robot.core_model, _core.RunOptions(dt=1e-4), _core.CallbackSpec(fn=fn))
    x0, u0 = robot.neutral_configuration(), robot.zero_velocity()
    sim.reset(x0, u0)
    sim.step()
    tau = np.zeros(robot.n_dof)
    tau[0] = c
    accel = robot.forward_dynamics(x0, u0, tau=tau)
    np.testing.assert_allclose(sim.state[robot.nx:] / 1e-4, accel, rtol=1e-3, atol=1e-9)
    assert len(seen) == 4  # RK4: four stages
