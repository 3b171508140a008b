"""The inputs of the simulation bindings (``_core.RunOptions``, ``_core.ThrusterLimits``, and
``_core.ControllerSpec``, the core's data of a run's controller, control/spec.rs): what
``spacearm.control`` makes of its classes, what the core refuses, and runs of hand-written specs through ``_core.simulate``, ``_core.rollout`` and
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


@pytest.mark.parametrize("build, match", [
    (lambda: _core.RunOptions(dtt=1e-3), "unknown key 'dtt'; expected one of"),
    (lambda: _core.ThrusterLimits.from_spec({"max_force": 1.0, "max_thrust": 1.0}), "unknown field `max_thrust`, expected"),
    (lambda: _core.ControllerSpec({"kind": "joint_pd", "kp": 1.0, "kd": 1.0, "reference": [0.0], "ki": 1.0}), "unknown field `ki`, expected"),
    (lambda: _core.ControllerSpec({"kind": "attitude", "quat_ref": [0, 0, 0, 1], "kp": 1.0, "kd": 1.0, "kq": 1.0}), "unknown field `kq`"),
    (lambda: _core.ControllerSpec({"kind": "base_thrusters", "r_ref": [0, 0, 0]}), "unknown field `r_ref`"),
    (lambda: _core.ControllerSpec({"kind": "resolved_motion_rate", "gain": 1.0,
                                   "reference": {"kind": "line", "p_start": [0.0] * 3, "p_goal": [1.0] * 3, "t_start": 0, "t_end": 1,
                                                 "pointt": "ee"}}), "unknown field `pointt`"),
])
def test_an_unknown_field_is_refused_and_the_known_ones_are_listed(build, match):
    with pytest.raises(errors.ArgumentError, match=match):
        build()


def test_values_are_checked_when_built():
    with pytest.raises(errors.ArgumentError, match="record_dtype must be 'float64' or 'float32'"):
        _core.RunOptions(record_dtype="float16")
    with pytest.raises(errors.ArgumentError, match="record_every must be an integer >= 1"):
        _core.RunOptions(record_every=0)
    with pytest.raises(errors.ArgumentError, match="thrusters must be a ThrusterLimits, got dict"):
        _core.RunOptions(thrusters={"max_force": [1.0] * 3, "max_torque": [1.0] * 3})
    with pytest.raises(errors.ArgumentError):
        _core.ThrusterLimits.from_spec({"max_force": [1.0, 0.0, 1.0]})
    with pytest.raises(errors.ShapeError):
        _core.JointReference.from_spec({"kind": "quintic", "q_start": [0.0, 0.0], "q_goal": [1.0], "t_start": 0.0, "t_end": 1.0})
    with pytest.raises(errors.ArgumentError, match="t_end"):
        _core.check_spec("point_reference", {"kind": "line", "p_start": [0.0] * 3, "p_goal": [1.0] * 3, "t_start": 1.0, "t_end": 1.0})
    with pytest.raises(errors.ArgumentError, match="unknown variant `lqr`"):
        _core.ControllerSpec({"kind": "combined", "arm": {"kind": "lqr"}, "base": {"kind": "none"}})
    with pytest.raises(errors.ArgumentError, match="callable"):
        _core.ControllerSpec({"kind": "external", "index": 0}, [3])
    with pytest.raises(errors.ArgumentError, match="1 callables given"):
        _core.ControllerSpec({"kind": "external", "index": 1}, [print])
    with pytest.raises(errors.ArgumentError, match="unknown spec family"):
        _core.check_spec("lqr", {})


def test_the_control_classes_become_the_core_data_of_what_the_user_gave(robot):
    """One reader (spacearm._util.spec) turns every control class into the core's data; the
    core's serde types name the fields (control/spec.rs) and its build resolves points and tasks
    on the plant."""
    from spacearm._util.spec import controller_spec

    q0 = robot.initial_q
    ref = control.QuinticJoint(q0, q0 + 0.3, 0.5, 2.0)
    data = controller_spec(control.ComputedTorque(kp=[1.0, 2.0, 3.0, 4.0], kd=5.0, reference=ref, model=robot)).to_data()
    assert data["kind"] == "computed_torque" and data["passive"] == "drift"
    assert list(data["kp"]) == [1.0, 2.0, 3.0, 4.0] and list(data["kd"]) == [5.0]
    assert data["reference"]["kind"] == "quintic" and (data["reference"]["t_start"], data["reference"]["t_end"]) == (0.5, 2.0)
    np.testing.assert_array_equal(data["reference"]["q_goal"], q0 + 0.3)
    # The controller's own model travels as its model file text, bit-exact.
    again = spacearm.Robot(_core.model_from_toml(data["model"], "a controller's model", False))
    x = robot.neutral_configuration()
    np.testing.assert_array_equal(again.generalized_inertia(x), robot.generalized_inertia(x))

    set_point = controller_spec(control.JointPD(kp=1.0, kd=1.0, reference=q0)).to_data()["reference"]
    assert set_point["kind"] == "constant"
    np.testing.assert_array_equal(set_point["q"], q0)

    line = control.CartesianLine([1.0, 0.5, 0.0], [1.2, 0.4, 0.0], 0.0, 1.0)
    rmrc = controller_spec(control.ResolvedMotionRate(line, gain=3.0)).to_data()
    assert rmrc["kind"] == "resolved_motion_rate" and rmrc["gain"] == 3.0
    assert rmrc["max_damping"] == _core.DLS_DEFAULTS["max_damping"] and rmrc["threshold"] == _core.DLS_DEFAULTS["threshold"]
    assert (rmrc["task"], rmrc["strategy"]) == ("position", "naive") and rmrc.get("point") is None
    np.testing.assert_array_equal(rmrc["reference"]["p_goal"], [1.2, 0.4, 0.0])
    spec = controller_spec(control.ResolvedMotionRate(line, gain=3.0, task="planar", strategy="reactionless")).to_data()
    assert (spec["task"], spec["strategy"]) == ("planar", "reactionless")
    assert list(controller_spec(control.ResolvedMotionRate(line, gain=3.0, task=[0, 1, 5])).to_data()["task"]) == [0, 1, 5]
    with pytest.raises(errors.ArgumentError, match="strategy"):
        control.ResolvedMotionRate(line, gain=3.0, strategy="minimal")
    with pytest.raises(errors.ArgumentError, match="strategy"):
        control.ResolvedMotionRate(line, gain=3.0, strategy=1)
    with pytest.raises(errors.ShapeError):
        control.ResolvedMotionRate(line, gain=3.0, task=[0, 0])
    # A task name is resolved on the plant, when the run starts.
    with pytest.raises(errors.ArgumentError, match="unknown task 'sideways'"):
        spacearm.simulate(robot, 0.01, controller=control.ResolvedMotionRate(line, gain=3.0, task="sideways"))
    # ... and so is the point: a name the plant does not have is refused there.
    with pytest.raises(errors.NotFoundError, match="no body named 'nowhere'"):
        spacearm.simulate(robot, 0.01, controller=control.ResolvedMotionRate(line, gain=3.0, point="nowhere"))

    base = control.BaseThrusterControl(com_ref=[1.0, 2.0, 3.0], kp_position=4.0)
    combined = controller_spec(control.Combined(arm=control.JointPD(1.0, 1.0, q0), base=base)).to_data()
    assert combined["arm"]["kind"] == "joint_pd" and combined["base"]["kind"] == "base_thrusters"
    np.testing.assert_array_equal(combined["base"]["com_ref"], [1.0, 2.0, 3.0])
    assert combined["base"].get("quat_ref") is None and combined["base"]["kp_position"] == 4.0

    limits = _core.ThrusterLimits.from_spec({"max_force": 2.0, "max_torque": [1.0, np.inf, 3.0]})
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
    reference = {"kind": "quintic", "q_start": q0.tolist(), "q_goal": q1.tolist(), "t_start": 0.2, "t_end": 1.2}
    spec = _core.ControllerSpec({"kind": "computed_torque", "kp": 25.0, "kd": 10.0, "reference": reference})
    data = _core.simulate(robot.core_model, robot.neutral_configuration(), robot.zero_velocity(), 1.5, _core.RunOptions(dt=2e-3), spec).records.to_dict()
    err = np.abs(data["x"][:, 7:] - quintic(data["t"], q0, q1, 0.2, 1.2)).max()
    assert err < 1e-8, err
    assert np.abs(data["x"][-1, 7:] - q0).max() > 0.3  # the arm did move


def test_joint_pd_spec_settles_at_its_set_point(robot):
    """At rest the PD torque kp (q_ref - q) is zero only at q_ref: the steady state is the set point."""
    q_ref = robot.initial_q + np.array([0.3, -0.2, 0.1, 0.25])
    spec = _core.ControllerSpec({"kind": "joint_pd", "kp": 200.0, "kd": 100.0, "reference": q_ref.tolist()})
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
    spec = _core.ControllerSpec({"kind": "base_thrusters", "com_ref": target.tolist(), "kp_position": 4.0, "kd_position": 4.0})
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
    spec = _core.ControllerSpec({"kind": "base_thrusters", "com_ref": (rg0 + [1000.0, 0.0, 0.0]).tolist(), "kp_position": 100.0,
                                 "kd_position": 1.0})
    limits = _core.ThrusterLimits.from_spec({"max_force": max_force})
    data = _core.simulate(robot.core_model, x0, robot.zero_velocity(), 1.0,
                          _core.RunOptions(mode="translation-flying", dt=1e-3, record_every=10, thrusters=limits), spec).records.to_dict()
    t = data["t"]
    expected = rg0 + np.outer(max_force * t**2 / (2 * robot.total_mass), [1.0, 0.0, 0.0])
    np.testing.assert_allclose(data["com"], expected, atol=1e-10)
    assert np.abs(data["com"][-1, 0] - rg0[0]) > 1e-3


def test_rollout_takes_one_spec_per_rollout_and_the_none_spec(robot):
    q_refs = robot.initial_q + np.array([[0.2], [-0.1]])
    specs = [_core.ControllerSpec({"kind": "joint_pd", "kp": 200.0, "kd": 100.0, "reference": q.tolist()}) for q in q_refs]
    x0 = np.tile(robot.neutral_configuration(), (2, 1))
    u0 = np.tile(robot.zero_velocity(), (2, 1))
    options = _core.RunOptions(dt=5e-3, record_every=200)
    data = _core.rollout([robot.core_model], x0, u0, 15.0, options, specs).records.to_dict()
    np.testing.assert_allclose(data["x"][:, -1, 7:], q_refs, atol=1e-5)
    # No control: a joint speed given keeps the arm moving (no torque stops it); at rest it stays.
    u0[1, 7] = 0.1
    free = _core.rollout([robot.core_model], x0, u0, 1.0, options, [_core.ControllerSpec({"kind": "none"})] * 2).records.to_dict()
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

    sim = _core.Simulator(robot.core_model, _core.RunOptions(dt=1e-4), _core.ControllerSpec({"kind": "external", "index": 0}, [fn]))
    x0, u0 = robot.neutral_configuration(), robot.zero_velocity()
    sim.reset(x0, u0)
    sim.step()
    tau = np.zeros(robot.n_dof)
    tau[0] = c
    accel = robot.forward_dynamics(x0, u0, tau=tau)
    np.testing.assert_allclose(sim.state[robot.nx:] / 1e-4, accel, rtol=1e-3, atol=1e-9)
    assert len(seen) == 4  # RK4: four stages
