"""The native simulation core through its Python face: records against independent
computations (the generalized-Jacobian momentum map of eq. 109, forward dynamics through the
mass matrix, momentum and energy from H, forward kinematics), mode bookkeeping, options and bad
input. The integrators' orders, determinism, quaternion norm and the modes' wrench masks are
tested on the Rust side (crates/spacearm-core/tests/simulation.rs); the closed-form physical
validations are in tests/test_simulation_*.py."""

import numpy as np
import pytest

import spacearm
from spacearm import errors
from spacearm.control import Callback, JointPD, QuinticJoint, Thrusters


def tumbling(robot, seed=0):
    rng = np.random.default_rng(seed)
    x0 = robot.neutral_configuration(r0=(1.0, -2.0, 0.5), quat0=np.roll(np.r_[np.cos(0.3), np.sin(0.3) * np.array([0.6, 0.0, 0.8])], -1))
    u0 = np.r_[rng.uniform(-0.05, 0.05, 3), rng.uniform(-0.2, 0.2, 3), rng.uniform(-0.5, 0.5, robot.n_dof)]
    return x0, u0


@pytest.fixture(scope="module")
def floating_run():
    robot = spacearm.presets.spatial6()
    x0, u0 = tumbling(robot)
    traj = spacearm.simulate(robot, 1.0, x0=x0, u0=u0, dt=2e-3, record_every=10)
    return robot, x0, u0, {key: traj[key] for key in traj.keys}, traj.meta


def test_records_have_the_documented_keys_and_shapes(floating_run):
    robot, x0, u0, d, meta = floating_run
    k, n = 51, robot.n_dof
    shapes = {
        "t": (k,), "x": (k, 7 + n), "u": (k, 6 + n), "du": (k, 6 + n), "tau": (k, n), "tau_cmd": (k, n),
        "base_wrench": (k, 6), "P": (k, 3), "L_origin": (k, 3), "L_com": (k, 3), "energy": (k,), "com": (k, 3),
        "ee_position": (k, 3), "ee_quat": (k, 4), "saturation_t": (0,), "saturation_actuator": (0,), "saturation_kind": (0,),
    }
    assert {key: d[key].shape for key in shapes} == shapes
    assert "reference" not in d and "tracking_error" not in d and "wheel_speed" not in d
    np.testing.assert_allclose(d["t"], np.linspace(0, 1, k), atol=1e-15)
    np.testing.assert_array_equal(d["x"][0], x0)
    np.testing.assert_array_equal(d["u"][0], u0)
    assert meta["mode"] == "floating" and meta["integrator"] == "rk4" and meta["controller"] == "none"
    assert meta["conserved"] == ["P", "L_origin", "energy"]
    assert meta["n_steps"] == 500 and meta["n_rhs_evals"] == 4 * 500 + 1  # k1 reused when recording; one more for the end
    assert meta["actuator_names"] == [f"joint{i}" for i in range(1, 7)] + [
        "base_force_x", "base_force_y", "base_force_z", "base_torque_x", "base_torque_y", "base_torque_z"]
    assert meta["tracking_error_kind"] is None and meta["wheel_dofs"] == []
    for name, value in meta["drift"].items():
        assert value < 1e-11, (name, value)


def test_base_velocity_follows_the_momentum_map(floating_run):
    """Free-floating: the integrated base velocity equals H0^-1 (M0 - H0m qd) (eqs. 43, 109) with
    the initial momentum — the GJM relation, independent of the ABA that was integrated."""
    robot, x0, u0, d, _ = floating_run
    m = robot.momentum(x0, u0)
    assert np.linalg.norm(m.P) > 1.0 and np.linalg.norm(m.L_origin) > 1.0
    worst = 0.0
    for x, u in zip(d["x"][::5], d["u"][::5]):
        xd0 = robot.base_velocity_from_momentum(x, u[6:], P=m.P, L=m.L_origin)
        worst = max(worst, np.abs(xd0 - u[:6]).max())
    assert worst < 1e-9
    # The base really moved and turned.
    assert np.linalg.norm(d["x"][-1, :3] - x0[:3]) > 0.01 and abs(d["x"][-1, 6] - x0[6]) > 1e-3


def test_recorded_quantities_match_the_robot_methods(floating_run):
    robot, _, _, d, _ = floating_run
    for i in (0, 17, 50):
        x, u = d["x"][i], d["u"][i]
        f = np.r_[d["base_wrench"][i], d["tau"][i]]
        np.testing.assert_allclose(d["du"][i], robot.forward_dynamics(x, u, f, method="mass_matrix"), rtol=1e-9, atol=1e-10)
        H = robot.mass_matrix(x)
        np.testing.assert_allclose(d["energy"][i], 0.5 * u @ H @ u, rtol=1e-12)
        np.testing.assert_allclose(np.r_[d["P"][i], d["L_origin"][i]], np.r_[robot.momentum(x, u).P, robot.momentum(x, u).L_origin], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(d["L_com"][i], robot.momentum(x, u).L_com, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(d["com"][i], robot.center_of_mass(x), atol=1e-12)
        np.testing.assert_allclose(d["ee_position"][i], robot.point_position(x), atol=1e-12)
        body, _ = robot._point(None)
        R = robot.forward_kinematics(x).body_to_world[body]
        qx, qy, qz, qw = d["ee_quat"][i]
        R_q = np.array([
            [1 - 2 * (qy**2 + qz**2), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
            [2 * (qx * qy + qz * qw), 1 - 2 * (qx**2 + qz**2), 2 * (qy * qz - qx * qw)],
            [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx**2 + qy**2)],
        ])
        np.testing.assert_allclose(R_q, R, atol=1e-12)
    # Quaternion sign kept continuous along the run.
    assert np.all(np.sum(d["ee_quat"][1:] * d["ee_quat"][:-1], axis=1) > 0)


def test_simulate_returns_a_trajectory_and_dopri5_agrees_with_rk4():
    robot = spacearm.presets.planar4()
    x0, u0 = tumbling(robot, 3)
    a = spacearm.simulate(robot, 1.0, x0=x0, u0=u0, dt=1e-3, record_every=100)
    b = spacearm.simulate(robot, 1.0, x0=x0, u0=u0, integrator="dopri5", dt=0.1, rtol=1e-10, atol=1e-12)
    assert isinstance(a, spacearm.sim.trajectory.Trajectory) and len(a) == len(b) == 11
    np.testing.assert_allclose(b["x"], a["x"], atol=1e-8)
    assert b.meta["integrator"] == "dopri5" and b.meta["n_steps"] < 200 and b.meta["n_rejected"] >= 0


@pytest.mark.parametrize(
    "mode, conserved",
    [("floating", ["P", "L_origin"]), ("rotation-floating", ["P", "L_origin"]), ("rotation-flying", ["P"]),
     ("translation-flying", ["L_com"]), ("flying", [])],
)
def test_modes_report_what_they_conserve_and_drop_what_they_forbid(mode, conserved):
    robot = spacearm.presets.planar4()
    wrench = np.array([2.0, -1.0, 0.5, 0.3, -0.2, 0.4])
    ctrl = Callback(lambda t, x, u: (np.full(4, 0.1), wrench))
    if mode == "flying":
        traj = spacearm.simulate(robot, 0.2, mode=mode, dt=2e-3, controller=ctrl)
    else:
        with pytest.warns(RuntimeWarning, match="dropped"):
            traj = spacearm.simulate(robot, 0.2, mode=mode, dt=2e-3, controller=ctrl)
    meta = traj.meta
    assert meta["conserved"] == conserved and sorted(meta["drift"]) == sorted(conserved)
    for v in meta["drift"].values():
        assert v < 1e-10
    allowed = {"floating": [], "rotation-floating": [], "rotation-flying": [3, 4, 5], "translation-flying": [0, 1, 2], "flying": list(range(6))}[mode]
    bw = traj["base_wrench"]
    np.testing.assert_array_equal(bw[:, allowed[:3] if mode == "translation-flying" else allowed], np.broadcast_to(wrench[allowed], (len(traj), len(allowed))))
    forbidden = sorted(set(range(6)) - set(allowed))
    if mode != "translation-flying":
        assert np.all(bw[:, forbidden] == 0)
    dropped = np.linalg.norm(wrench[forbidden])
    assert meta["dropped_base_wrench"]["max_norm"] == pytest.approx(dropped, rel=1e-12)


def test_non_zero_initial_momentum_and_energy_conservation_with_zero_torque():
    robot = spacearm.presets.spatial6()
    x0, u0 = tumbling(robot, 7)
    traj = spacearm.simulate(robot, 0.5, x0=x0, u0=u0, integrator="dopri5", dt=0.05, rtol=1e-11, atol=1e-13)
    assert np.linalg.norm(traj["P"][0]) > 1.0
    drift = traj.meta["drift"]
    assert set(drift) == {"P", "L_origin", "energy"} and max(drift.values()) < 1e-9
    # Reference non-trivial: the energy is not near zero.
    assert traj["energy"][0] > 0.1


def test_callback_errors_and_progress():
    robot = spacearm.presets.planar4()
    seen = []
    spacearm.simulate(robot, 0.05, dt=1e-3, progress=seen.append)
    assert seen[-1] == 1.0 and all(0 < f <= 1 for f in seen) and seen == sorted(seen)

    def bad_shape(t, x, u):
        return np.zeros(3)

    with pytest.raises(errors.ShapeError, match="tau"):
        spacearm.simulate(robot, 0.01, controller=Callback(bad_shape))

    def stop(fraction):
        if fraction > 0.5:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        spacearm.simulate(robot, 0.1, progress=stop)
    with pytest.raises(errors.SimulationError, match="non-finite"):
        spacearm.simulate(robot, 0.01, controller=Callback(lambda t, x, u: np.full(4, np.nan)))


def test_diverging_motion_is_a_simulation_error():
    robot = spacearm.presets.spatial6()
    q0 = robot.initial_q
    # gains far beyond dt = 1 ms: refused before the first step (sim/step_limit.rs)
    with pytest.raises(errors.SimulationError, match="fastest mode of the motion"):
        spacearm.simulate(robot, 1.0, controller=JointPD(1e5, 1e4, q0 + 0.1))


def test_tqdm_progress_bar_runs(capsys):
    spacearm.simulate(spacearm.presets.planar4(), 0.02, progress=True)


# ---- bad input -------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def robot():
    return spacearm.presets.planar4()


@pytest.mark.parametrize(
    "kwargs, exc, match",
    [
        (dict(mode="hovering"), errors.ArgumentError, "mode must be one of"),
        (dict(integrator="euler"), errors.ArgumentError, "integrator must be one of"),
        (dict(dt=0.0), errors.ArgumentError, "dt must be finite and > 0"),
        (dict(dt=-1e-3), errors.ArgumentError, "dt must be finite and > 0"),
        (dict(dt=np.nan), errors.ArgumentError, "dt must be finite"),
        (dict(rtol=0.0, integrator="dopri5"), errors.ArgumentError, "rtol"),
        (dict(atol=-1.0, integrator="dopri5"), errors.ArgumentError, "atol"),
        (dict(record_every=0), errors.ArgumentError, "record_every"),
        (dict(x0=np.r_[0, 0, 0, 0, 0, 0, 1, 0, 0, 0, np.nan]), errors.NonFiniteError, "x0"),
        (dict(x0=np.zeros(11)), errors.QuaternionError, "quaternion"),
        (dict(x0=np.r_[0, 0, 0, 0, 0, 0, 1, 0, 0]), errors.ShapeError, "x0 must have length 7\\+N = 11"),
        (dict(u0=np.zeros(9)), errors.ShapeError, "6\\+N = 10"),
        (dict(u0=np.r_[np.zeros(9), np.inf]), errors.NonFiniteError, "u0"),
        (dict(wheels=["no_such_joint"]), errors.NotFoundError, "no_such_joint"),
        (dict(wheels=[9]), errors.NotFoundError, "wheel dof 9"),
        (dict(controller="pd"), errors.ArgumentError, "controller must be None or"),
        (dict(controller=JointPD(1.0, 1.0, np.zeros(3))), errors.ShapeError, "number of arm joints 4"),
        (dict(controller=JointPD([1.0, 2.0], 1.0, np.zeros(4))), errors.ShapeError, "kp"),
    ],
)
def test_bad_input_raises_a_clear_error(robot, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        spacearm.simulate(robot, 0.01, **kwargs)


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: Thrusters(max_force=0.0), "max_force must be > 0"),
        (lambda: Thrusters(max_torque=[1.0, -1.0, 1.0]), "max_torque must be > 0"),
        (lambda: Thrusters(max_torque=[1.0, 1.0]), "one number or three"),
        (lambda: JointPD(-1.0, 1.0, np.zeros(4)), "kp' must be finite and >= 0"),
        (lambda: JointPD("a", 1.0, np.zeros(4)), "expected a number or a list of numbers"),
    ],
)
def test_bad_values_are_refused_where_they_are_made(make, match):
    """The core checks a description when it is made (control/spec.rs), not first at the run."""
    with pytest.raises(errors.ArgumentError, match=match):
        make()


@pytest.mark.parametrize("duration", [0.0, -1.0, np.nan, np.inf, "long"])
def test_bad_duration(robot, duration):
    with pytest.raises(errors.ArgumentError, match="duration"):
        spacearm.simulate(robot, duration)


def test_bad_references_options_and_specs(robot):
    with pytest.raises(errors.ArgumentError, match="t_end > t_start"):
        QuinticJoint(np.zeros(4), np.ones(4), 1.0, 0.5)
    with pytest.raises(errors.ShapeError):
        QuinticJoint(np.zeros(4), np.ones(3), 0.0, 1.0)
    x0, u0 = robot.neutral_configuration(), robot.zero_velocity()
    with pytest.raises(errors.ArgumentError, match="unknown key 'dtt'"):
        spacearm._core.RunOptions(dtt=1e-3)
    with pytest.raises(errors.ArgumentError, match="a controller must be a spacearm.control controller"):
        spacearm._core.simulate(robot.core_model, x0, u0, 1.0, spacearm._core.RunOptions(), {"type": "lqr"})
    with pytest.raises(errors.ArgumentError, match="unknown variant `lqr`"):
        spacearm._core.ControllerSpec({"kind": "lqr"})
    with pytest.raises(errors.ArgumentError, match="unknown field `ki`"):
        spacearm._core.ControllerSpec({"kind": "joint_pd", "kp": 1.0, "kd": 1.0, "ki": 1.0, "reference": [0.0] * 4})
    with pytest.raises(errors.ArgumentError, match="missing field `kd`"):
        spacearm._core.ControllerSpec({"kind": "joint_pd", "kp": 1.0, "reference": [0.0] * 4})
    # A missing keyword of a spacearm.control class is Python's own TypeError, naming it.
    with pytest.raises(TypeError, match="'kd'"):
        JointPD(kp=1.0, reference=np.zeros(4))


def test_rk4_equals_a_numpy_rk4_on_the_mass_matrix_dynamics():
    """A second implementation of the whole step in numpy: RK4 with stage renormalization of
    the quaternion, quat' = 1/2 [w0; 0] ⊗ quat (Hamilton, w0 in the inertial frame), and
    accelerations from H^-1 (f - c) (CRBA + RNEA, not the ABA the core integrates)."""
    robot = spacearm.presets.spatial6()
    x0, u0 = tumbling(robot, 11)
    u0[3:6] = [0.4, -0.3, 0.5]
    n = robot.n_dof
    tau = np.linspace(-0.5, 0.5, n)

    def qmul(a, b):  # Hamilton product, [x, y, z, w]
        av, aw, bv, bw = a[:3], a[3], b[:3], b[3]
        return np.r_[aw * bv + bw * av + np.cross(av, bv), aw * bw - av @ bv]

    def f(y):
        x, u = y[: 7 + n].copy(), y[7 + n:]
        x[3:7] /= np.linalg.norm(x[3:7])
        du = robot.forward_dynamics(x, u, tau=tau, method="mass_matrix")
        return np.r_[u[:3], 0.5 * qmul(np.r_[u[3:6], 0.0], x[3:7]), u[6:], du]

    h, steps = 5e-3, 40
    y = np.r_[x0, u0]
    for _ in range(steps):
        k1 = f(y)
        k2 = f(y + 0.5 * h * k1)
        k3 = f(y + 0.5 * h * k2)
        k4 = f(y + h * k3)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        y[3:7] /= np.linalg.norm(y[3:7])
    traj = spacearm.simulate(robot, h * steps, x0=x0, u0=u0, dt=h, controller=Callback(lambda t, x, u: tau))
    np.testing.assert_allclose(traj["x"][-1], y[: 7 + n], atol=1e-11)
    np.testing.assert_allclose(traj["u"][-1], y[7 + n:], atol=1e-10)
    assert abs(y[6] - x0[6]) > 0.01  # the base turned
