"""The typed results of the simulation bindings: ``_core.simulate`` and ``Simulator.result``
return a ``RunResult`` (``RunRecords``, ``RunEvents``, ``RunMeta`` with ``ConservedDrift``),
``_core.rollout`` a ``RolloutBatch``. Their values are checked against independent sources: the
momenta and energy from the CRBA mass matrix ``H u``, the drift recomputed in numpy from the
records, the saturation and dropped-wrench counters from what the controller commanded, a
rollout's rows against a single run."""

import numpy as np
import pytest

import spacearm
from spacearm._util.spec import controller_spec
from spacearm import _core, control, errors
from spacearm.sim.simulation import DEFAULTS, _options

# Every record docs/simulation.md lists, with its attribute on RunRecords.
ALWAYS = ("t", "x", "u", "du", "tau", "tau_cmd", "base_wrench", "P", "L_origin", "L_com", "energy", "com")
OPTIONAL = ("ee_position", "ee_quat", "reference", "tracking_error", "link_tracking_error", "attitude_error", "wheel_speed", "cmg_measure", "cmg_envelope_fraction")


def core_options(robot, **given):
    """The core's options for ``robot``: the defaults of ``spacearm.simulate`` with ``given``."""
    kw = {name: DEFAULTS[name] for name in ("mode", "integrator", "dt", "rtol", "atol", "record_every", "joint_limits", "max_steps")}
    kw.update(wheels=None, thrusters=None, record_dtype="float64")
    kw.update(given)
    return _options(robot, **kw)


@pytest.fixture(scope="module")
def robot():
    return spacearm.presets.spatial6()


@pytest.fixture(scope="module")
def torque_free(robot):
    """A torque-free spatial6 run with base and joint velocities (non-zero momentum)."""
    u0 = robot.zero_velocity()
    u0[:6] = [0.05, -0.02, 0.03, 0.1, -0.05, 0.08]
    u0[6:] = np.linspace(0.2, 0.7, robot.n_dof)
    return u0, _core.simulate(robot.core_model, robot.neutral_configuration(), u0, 0.5, core_options(robot, record_every=10))


def test_simulate_returns_the_typed_classes(robot, torque_free):
    _, res = torque_free
    assert isinstance(res, _core.RunResult)
    assert isinstance(res.records, _core.RunRecords)
    assert isinstance(res.events, _core.RunEvents)
    assert isinstance(res.meta, _core.RunMeta)
    assert all(isinstance(d, _core.ConservedDrift) for d in res.meta.drift)
    assert "RunRecords(" in repr(res.records) and "x: (51, 13)" in repr(res.records)


def test_fields_name_exactly_the_records_that_are_not_none(robot, torque_free):
    _, res = torque_free
    rec = res.records
    # 0.5 s at 1 ms, every 10th step: 51 samples; spatial6 has an end effector, no controller.
    assert rec.fields == ALWAYS + ("ee_position", "ee_quat")
    k = 51
    widths = {"t": None, "x": 13, "u": 12, "du": 12, "tau": 6, "tau_cmd": 6, "base_wrench": 6, "P": 3, "L_origin": 3,
              "L_com": 3, "energy": None, "com": 3, "ee_position": 3, "ee_quat": 4}
    for name, width in widths.items():
        a = getattr(rec, name)
        assert isinstance(a, np.ndarray) and a.dtype == np.float64
        assert a.shape == ((k,) if width is None else (k, width)), name
    for name in set(OPTIONAL) - set(rec.fields):
        assert getattr(rec, name) is None, name
    # One object per record (the arrays are held, not rebuilt on each access).
    assert rec.x is rec.x


def test_records_agree_with_the_mass_matrix(robot, torque_free):
    """P, L_origin, L_com and the energy recorded by the loop against H(x) u from CRBA:
    H u = [P; L about the base CM; ...] (eq. 42), moved to the origin and the system CM."""
    _, res = torque_free
    rec = res.records
    for i in (0, 25, 50):
        x, u = rec.x[i], rec.u[i]
        h_u = robot.mass_matrix(x) @ u
        p, l_base = h_u[:3], h_u[3:6]
        r0, rg = x[:3], robot.center_of_mass(x)
        np.testing.assert_allclose(rec.P[i], p, rtol=0, atol=1e-12 * max(1.0, np.abs(p).max()))
        np.testing.assert_allclose(rec.L_origin[i], l_base + np.cross(r0, p), atol=1e-11)
        np.testing.assert_allclose(rec.L_com[i], l_base + np.cross(r0 - rg, p), atol=1e-11)
        assert rec.energy[i] == pytest.approx(0.5 * u @ h_u, rel=1e-12)
    assert np.abs(rec.P[0]).max() > 1e-3  # a run that could not pass on zero momentum


def test_drift_is_the_largest_relative_deviation_of_the_records(robot, torque_free):
    _, res = torque_free
    rec, drift = res.records, {d.quantity: d for d in res.meta.drift}
    # Floating, torque-free: P, L_origin and the energy are conserved.
    assert [d.quantity for d in res.meta.drift] == ["P", "L_origin", "energy"]
    for name in ("P", "L_origin"):
        values = getattr(rec, name)
        d = drift[name]
        # The scale is a sum of magnitudes of the bodies' contributions: never below |total|.
        assert d.scale >= np.linalg.norm(values[0]) * (1 - 1e-12)
        expected = np.linalg.norm(values - values[0], axis=1).max() / max(np.linalg.norm(values[0]), d.scale)
        assert d.drift == pytest.approx(expected, rel=1e-9, abs=1e-300)
        assert d.drift < 1e-9
    e = drift["energy"]
    expected = np.abs(rec.energy - rec.energy[0]).max() / max(abs(rec.energy[0]), e.scale)
    assert e.drift == pytest.approx(expected, rel=1e-9, abs=1e-300)


def test_meta_describes_the_run(robot, torque_free):
    _, res = torque_free
    m = res.meta
    assert (m.mode, m.integrator, m.dt, m.record_every, m.record_dtype) == ("floating", "rk4", 1e-3, 10, "float64")
    assert m.controller == "none" and m.tracking_error_kind is None
    # Four evaluations per RK4 step, and one for the accelerations of the first sample.
    assert m.n_steps == 500 and m.n_rhs_evals == 4 * 500 + 1 and m.n_rejected == 0
    assert m.actuator_names[: robot.n_dof] == robot.joint_names and len(m.actuator_names) == robot.n_dof + 6
    assert (m.dropped_base_wrench_count, m.dropped_base_wrench_max_norm) == (0, 0.0)


def test_events_and_dropped_counters_follow_the_command(robot):
    """rotation-flying allows a base torque only: a commanded force of norm 1 is dropped at every
    evaluation, and a commanded torque of 2 N·m about z against a 0.5 N·m thruster limit
    saturates the thruster channel base_torque_z (index N + 5) once, from the first step."""
    command = control.Callback(lambda t, x, u: (np.zeros(6), np.array([0.6, 0.0, 0.8, 0.0, 0.0, 2.0])))
    options = core_options(robot, mode="rotation-flying", thrusters=control.Thrusters(max_force=1.0, max_torque=0.5))
    res = _core.simulate(robot.core_model, robot.neutral_configuration(), robot.zero_velocity(), 0.01, options, controller_spec(command))
    ev, m = res.events, res.meta
    assert ev.saturation_t.dtype == np.float64 and ev.saturation_actuator.dtype == np.int64
    np.testing.assert_array_equal(ev.saturation_t, [0.0])
    np.testing.assert_array_equal(ev.saturation_actuator, [robot.n_dof + 5])
    np.testing.assert_array_equal(ev.saturation_kind, [2])
    assert m.actuator_names[robot.n_dof + 5] == "base_torque_z"
    assert m.dropped_base_wrench_count == m.n_rhs_evals == 4 * 10 + 1
    assert m.dropped_base_wrench_max_norm == pytest.approx(1.0, rel=1e-15)
    # The applied wrench: no force, the torque clamped at the limit.
    np.testing.assert_allclose(res.records.base_wrench[1:], np.tile([0, 0, 0, 0, 0, 0.5], (10, 1)), atol=1e-15)
    assert [d.quantity for d in m.drift] == ["P"]


def test_float32_records(robot):
    res = _core.simulate(robot.core_model, robot.neutral_configuration(), robot.zero_velocity(), 0.01, core_options(robot, record_dtype="float32"))
    assert res.records.t.dtype == np.float64
    assert {getattr(res.records, f).dtype for f in res.records.fields if f != "t"} == {np.dtype(np.float32)}
    assert res.meta.record_dtype == "float32"


def test_the_classes_are_frozen(torque_free):
    _, res = torque_free
    for obj, name in ((res, "records"), (res.records, "x"), (res.meta, "dt"), (res.meta.drift[0], "drift"), (res.events, "saturation_t")):
        with pytest.raises(AttributeError):
            setattr(obj, name, None)


def test_rollout_batch_rows_are_the_single_runs(robot):
    """Row i of each stacked record is the run simulate makes of rollout i's inputs; a diverging
    rollout is reported with its error class and NaN rows."""
    b = 3
    x0 = np.tile(robot.neutral_configuration(), (b, 1))
    u0 = np.zeros((b, robot.nu))
    u0[:, 6:] = np.array([[0.1], [0.3], [1e8]])
    q0 = x0[0, 7:]
    pd = control.JointPD(20.0, 8.0, control.QuinticJoint(q0, q0 + 0.3, 0.0, 0.2))
    options = core_options(robot, record_every=20)
    batch = _core.rollout([robot.core_model], x0, u0, 0.2, options, controller_spec(pd), 2)
    assert isinstance(batch, _core.RolloutBatch) and isinstance(batch.records, _core.RunRecords)
    np.testing.assert_array_equal(batch.ok, [True, True, False])
    assert batch.reason[:2] == [None, None] and "fastest mode" in batch.reason[2]  # 1e8 rad/s: refused before its first step
    assert batch.error_class == [None, None, "SimulationError"]
    assert issubclass(getattr(errors, batch.error_class[2]), errors.SpacearmError)
    assert batch.meta[2] is None and batch.events[2] is None
    assert isinstance(batch.meta[0], _core.RunMeta) and isinstance(batch.events[0], _core.RunEvents)
    assert "tracking_error" in batch.records.fields and batch.records.wheel_speed is None
    for i in range(2):
        single = _core.simulate(robot.core_model, x0[i], u0[i], 0.2, options, controller_spec(pd))
        for name in single.records.fields:
            np.testing.assert_array_equal(getattr(batch.records, name)[i], getattr(single.records, name), err_msg=name)
        assert [(d.quantity, d.drift) for d in batch.meta[i].drift] == [(d.quantity, d.drift) for d in single.meta.drift]
    assert batch.records.x.shape == (b, 11, robot.nx)
    assert np.isnan(batch.records.x[2]).all()


def test_rollout_batch_where_every_rollout_fails(robot):
    u0 = np.full((1, robot.nu), 1e8)
    batch = _core.rollout([robot.core_model], robot.neutral_configuration()[None], u0, 0.1, core_options(robot), None, 1)
    assert batch.records.fields == ("t", "x", "u")
    assert batch.records.du is None and batch.records.P is None
    assert batch.error_class == ["SimulationError"] and batch.meta == [None] and batch.events == [None]


def test_simulator_result_is_a_run_result(robot):
    sim = _core.Simulator(robot.core_model, core_options(robot), None, 4)
    u0 = robot.zero_velocity()
    u0[6:] = 0.2
    sim.reset(robot.neutral_configuration(), u0)
    sim.step(None, 10, None)
    res = sim.result()
    assert isinstance(res, _core.RunResult)
    # Samples at steps 0, 4, 8 and the current state (step 10).
    np.testing.assert_allclose(res.records.t, [0.0, 0.004, 0.008, 0.010], rtol=1e-12)
    np.testing.assert_array_equal(res.records.x[-1], sim.state[: robot.nx])
    np.testing.assert_array_equal(res.records.u[-1], sim.state[robot.nx:])
    assert res.meta.n_steps == 10 and res.meta.record_every == 4


def test_the_public_results_hold_no_extension_object_and_pickle(robot):
    """Trajectory and Rollouts keep plain dicts of the typed results, so they cross processes."""
    import pickle

    x0 = np.tile(robot.neutral_configuration(), (2, 1))
    u0 = np.zeros((2, robot.nu))
    u0[:, 6:] = [[0.1], [0.2]]
    runs = spacearm.rollout(robot, 0.05, x0, u0, record_every=10)
    again = pickle.loads(pickle.dumps(runs))
    assert again.keys == runs.keys and again.meta == runs.meta
    np.testing.assert_array_equal(again.x, runs.x)
    np.testing.assert_array_equal(again.saturation_count, runs.saturation_count)
    traj = runs.trajectory(1)
    assert isinstance(traj.meta["drift"], dict) and traj.meta["conserved"] == list(traj.meta["drift"])
    np.testing.assert_array_equal(pickle.loads(pickle.dumps(traj)).x, traj.x)


def test_to_dict_is_the_public_plain_form(robot, torque_free):
    """Each type once: the plain forms Trajectory and Rollouts hold come from the typed results'
    own ``to_dict`` (no Python list of their fields), every field accounted for."""
    _, res = torque_free
    records = res.records.to_dict()
    assert tuple(records) == res.records.fields
    assert all(records[name] is getattr(res.records, name) for name in res.records.fields)  # the arrays, no copy
    events = res.events.to_dict()
    assert set(events) == {"saturation_t", "saturation_actuator", "saturation_kind"}
    assert all(events[k] is getattr(res.events, k) for k in events)
    meta, m = res.meta.to_dict(), res.meta
    public = {a for a in dir(m) if not a.startswith("_") and a != "to_dict"}
    renamed = {"drift", "balance", "dropped_base_wrench_max_norm", "dropped_base_wrench_count",
               "goal_distance", "goal_sigma_min", "goal_unreachable"}  # meta["goal"], an RMRC run's
    assert public - renamed <= set(meta)
    assert "goal" not in meta and m.goal_distance is None  # a torque-free run has no goal
    for name in public - renamed:
        assert meta[name] == getattr(m, name), name
    assert meta["conserved"] == [d.quantity for d in m.drift] == list(meta["drift"]) == list(meta["drift_scales"])
    assert m.balance is False and meta["balanced"] == []
    assert meta["drift"] == {d.quantity: d.drift for d in m.drift} and meta["drift_scales"] == {d.quantity: d.scale for d in m.drift}
    assert meta["dropped_base_wrench"] == {"max_norm": m.dropped_base_wrench_max_norm, "count": m.dropped_base_wrench_count}
    traj = spacearm.simulate(robot, 0.05, dt=0.01)
    assert set(traj.meta) == set(meta) | {"duration", "robot", "passive_joints_commanded"}  # the last: spacearm.simulate's check
