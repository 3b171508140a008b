"""spacearm.Trajectory on synthetic runs built to the simulation contract: accessors against
independent formulas, drift against deviations planted by hand, exact save/load and CSV round
trips, atomic writes, clear errors."""

import json
import os

import numpy as np
import pytest

import spacearm
from spacearm.errors import NotFoundError, ShapeError, SpacearmError
from spacearm.rotations import quat_from_rpy, quat_to_matrix
from spacearm.sim.trajectory import Trajectory, euler_from_matrices

from sim_samples import synthetic


def test_accessors_are_the_contract_slices():
    robot, data, meta = synthetic()
    tr = Trajectory(robot=robot, data=data, meta=meta)
    assert len(tr) == tr.n_samples == 41 and tr.n_dof == 6
    np.testing.assert_array_equal(tr.q, data["x"][:, 7:])
    np.testing.assert_array_equal(tr.qd, data["u"][:, 6:])
    np.testing.assert_array_equal(tr.base_position, data["x"][:, :3])
    np.testing.assert_array_equal(tr.base_quat, data["x"][:, 3:7])
    np.testing.assert_array_equal(tr.base_velocity, data["u"][:, :3])
    np.testing.assert_array_equal(tr.base_angular_velocity, data["u"][:, 3:6])
    assert tr.duration == pytest.approx(2.0)
    x, u = tr.state(-1)
    np.testing.assert_array_equal(x, data["x"][-1])
    with pytest.raises(ValueError):
        tr.q[0, 0] = 1.0  # read-only
    assert tr.mode == "floating" and tr.conserved == ["P", "L_origin"]


def test_base_rotation_and_euler_against_single_sample_formulas():
    rng = np.random.default_rng(3)
    rpy = np.column_stack([rng.uniform(-3, 3, 30), rng.uniform(-1.5, 1.5, 30), rng.uniform(-3, 3, 30)])
    quats = np.array([quat_from_rpy(*a) for a in rpy])
    mats = quat_to_matrix(quats)  # the batch form
    for q, m in zip(quats, mats):
        np.testing.assert_allclose(m, quat_to_matrix(q), atol=1e-15)
    # Independent samples: no unwrapping relation, so compare one at a time.
    back = np.array([euler_from_matrices(m[None])[0] for m in mats])
    np.testing.assert_allclose(back, rpy, atol=1e-12)
    # A steady yaw rotation through ±π unwraps to a straight line.
    yaw = np.linspace(0, 4 * np.pi, 50)
    e = euler_from_matrices(quat_to_matrix(np.array([quat_from_rpy(0, 0, a) for a in yaw])))
    np.testing.assert_allclose(e[:, 2], yaw, atol=1e-12)


def test_rotation_angle_and_body_rates():
    robot, data, meta = synthetic()
    tr = Trajectory(robot=robot, data=data, meta=meta)
    # The base turns at 0.3 rad/s about a fixed axis.
    np.testing.assert_allclose(tr.base_rotation_angle, 0.3 * tr.t, atol=1e-12)
    assert tr.base_rotation_angle[-1] > 0.5
    # Spinning about a fixed axis: the body-frame rate is R0^T w0, computed here per sample.
    for k in (0, 20, 40):
        np.testing.assert_allclose(tr.base_angular_velocity_in_base[k], quat_to_matrix(tr.base_quat[k]).T @ tr.base_angular_velocity[k], atol=1e-15)


def test_drift_measures_planted_deviation():
    robot, data, meta = synthetic()
    p0 = np.array([3.0, -4.0, 0.0])  # |P0| = 5
    data["P"] = np.tile(p0, (len(data["t"]), 1))
    data["P"][17] += [0.0, 0.0, 2e-6]
    data["P"][30] += [1e-6, 0.0, 0.0]
    tr = Trajectory(robot=robot, data=data, meta=meta)
    d = tr.drift(["P"], scale={"P": 0.0})
    assert d["P"] == pytest.approx(2e-6 / 5.0, rel=1e-9)
    # Zero initial momentum: the deviation is measured against the core's drift scale, the
    # largest sum over the bodies of |p_i| (|r_i x p_i| + |I_i w_i| for L), computed here body by
    # body from the point Jacobians at each body's CM.
    data["P"] = np.zeros((len(data["t"]), 3))
    data["P"][5] = [0, 1e-9, 0]
    tr = Trajectory(robot=robot, data=data, meta=meta)
    d_ = robot.describe()
    masses = [d_["base"]["mass"]] + [l["mass"] for l in d_["links"]]
    inertias = [np.asarray(d_["base"]["inertia"])] + [np.asarray(l["inertia"]) for l in d_["links"]]
    sp, slo, slc = [], [], []
    for x, u in zip(data["x"], data["u"]):
        kin = robot.forward_kinematics(x)
        rg = robot.center_of_mass(x)
        tp = to = tc = 0.0
        for b, (m, i_body) in enumerate(zip(masses, inertias)):
            j0, jm = robot.point_jacobian(x, (b, np.zeros(3)))
            tw = j0 @ u[:6] + jm @ u[6:]
            p_b = m * tw[:3]
            r, c = kin.body_to_world[b], kin.com_in_world[b]
            spin = np.linalg.norm(r @ i_body @ r.T @ tw[3:])
            # P's terms: the velocity of the body's point at the base CM, and the lever term.
            lever = np.cross(tw[3:], c - x[0:3])
            tp += m * (np.linalg.norm(tw[:3] - lever) + np.linalg.norm(lever))
            to += np.linalg.norm(np.cross(c, p_b)) + spin
            tc += np.linalg.norm(np.cross(c - rg, p_b)) + spin
        sp.append(tp), slo.append(to), slc.append(tc)
    assert max(sp) > 1.0
    assert tr.drift_scale("P") == pytest.approx(max(sp), rel=1e-12)
    assert tr.drift_scale("L_origin") == pytest.approx(max(slo), rel=1e-12)
    assert tr.drift_scale("L_com") == pytest.approx(max(slc), rel=1e-12)
    assert tr.drift(["P"])["P"] == pytest.approx(1e-9 / max(sp), rel=1e-9)
    # The default names are the mode's conserved quantities.
    assert set(tr.drift()) == {"P", "L_origin"}


def test_saturation_events_and_summary():
    robot, data, meta = synthetic()
    meta["actuator_names"] = [f"joint{i + 1}" for i in range(6)] + ["thruster_force"]
    tr = Trajectory(robot=robot, data=data, meta=meta)
    ev = tr.saturation_events
    assert [e.actuator for e in ev] == ["joint2", "joint2", "thruster_force"]
    assert [e.kind for e in ev] == ["torque limit", "torque limit", "force limit"]
    assert tr.saturation_counts() == {"joint2 (torque limit)": 2, "thruster_force (force limit)": 1}
    s = tr.summary()
    for needle in ("spatial6", "mode floating", "JointPD", "conservation (max relative drift): P", "L_origin",
                   "tracking error (joint): final", "saturation: 3 events", "joint2 (torque limit) x2"):
        assert needle in s, needle


def test_missing_data_and_bad_shapes_raise_clear_errors():
    robot, data, meta = synthetic()
    tr = Trajectory(robot=robot, data={k: data[k] for k in ("t", "x", "u")}, meta={})
    with pytest.raises(NotFoundError, match="no end effector"):
        tr.ee_position
    with pytest.raises(NotFoundError, match="no reaction wheels"):
        tr.wheel_speed
    with pytest.raises(NotFoundError, match="no 'energy' data"):
        tr["energy"]
    assert tr.saturation_events == [] and not tr.has("P")
    with pytest.raises(ShapeError, match="lacks u"):
        Trajectory(data={"t": data["t"], "x": data["x"]})
    with pytest.raises(ShapeError, match=r"'u' must have shape \(K, 6\+N\)"):
        Trajectory(data={"t": data["t"], "x": data["x"], "u": data["u"][:, :-1]})
    with pytest.raises(ShapeError, match="one row per sample"):
        Trajectory(data={"t": data["t"], "x": data["x"], "u": data["u"], "energy": data["energy"][:-1]})
    with pytest.raises(ShapeError, match="robot 'planar4' has N = 4"):
        Trajectory(robot=spacearm.presets.planar4(), data={k: data[k] for k in ("t", "x", "u")})
    with pytest.raises(TypeError):
        Trajectory(robot)


def test_save_load_round_trip_is_exact(tmp_path):
    robot, data, meta = synthetic()
    tr = Trajectory(robot=robot, data=data, meta=meta)
    path = tmp_path / "run.npz"
    tr.save(path)
    back = Trajectory.load(path)
    assert back.keys == tr.keys
    for k in tr.keys:
        np.testing.assert_array_equal(back[k], tr[k])
        assert back[k].dtype == tr[k].dtype
    assert back.meta == json.loads(json.dumps(meta))
    # The model comes back from its embedded TOML: the same physics.
    assert back.robot is not None and back.robot.describe() == robot.describe()
    np.testing.assert_array_equal(back.robot.mass_matrix(data["x"][3]), robot.mass_matrix(data["x"][3]))
    assert [f for f in os.listdir(tmp_path)] == ["run.npz"]


def test_save_is_atomic(tmp_path, monkeypatch):
    robot, data, meta = synthetic()
    tr = Trajectory(robot=robot, data=data, meta=meta)
    path = tmp_path / "run.npz"
    tr.save(path)
    before = path.read_bytes()

    def boom(*a, **k):
        raise RuntimeError("disk full")

    monkeypatch.setattr(np, "savez_compressed", boom)
    with pytest.raises(RuntimeError):
        tr.save(path)
    assert path.read_bytes() == before
    assert os.listdir(tmp_path) == ["run.npz"]  # no temporary left behind


def test_load_rejects_other_files(tmp_path):
    p = tmp_path / "other.npz"
    np.savez(p, a=np.zeros(3))
    with pytest.raises(SpacearmError, match="not a spacearm trajectory"):
        Trajectory.load(p)
    q = tmp_path / "junk.npz"
    q.write_bytes(b"not a zip")
    with pytest.raises(SpacearmError, match="not a spacearm trajectory"):
        Trajectory.load(q)
    with pytest.raises(FileNotFoundError):
        Trajectory.load(tmp_path / "missing.npz")


def test_csv_has_units_and_round_trips(tmp_path):
    robot, data, meta = synthetic()
    meta["wheel_dofs"] = [4, 5]
    data["wheel_speed"] = np.column_stack([data["u"][:, 10], data["u"][:, 11]])
    tr = Trajectory(robot=robot, data=data, meta=meta)
    path = tmp_path / "run.csv"
    tr.to_csv(path)
    lines = path.read_text().splitlines()
    comments = [l for l in lines if l.startswith("#")]
    header = lines[len(comments)].split(",")
    assert any("mode floating" in c for c in comments)
    for col in ("t [s]", "r0_x [m]", "quat0_w [1]", "q_joint1 [rad]", "w0_z [rad/s]", "qd_joint6 [rad/s]",
                "qdd_joint2 [rad/s^2]", "tau_joint3 [N m]", "F0_x [N]", "N0_z [N m]", "P_y [N s]",
                "L_origin_x [N m s]", "energy [J]", "com_z [m]", "ee_x [m]", "q_ref_joint4 [rad]",
                "tracking_error [rad]", "wheel_speed_joint5 [rad/s]", "wheel_speed_joint6 [rad/s]"):
        assert col in header, col
    table = np.loadtxt(path, delimiter=",", comments="#", skiprows=len(comments) + 1)
    assert table.shape == (41, len(header))
    col = {h: table[:, i] for i, h in enumerate(header)}
    np.testing.assert_array_equal(col["t [s]"], data["t"])
    np.testing.assert_array_equal(col["q_joint5 [rad]"], data["x"][:, 11])
    np.testing.assert_array_equal(col["energy [J]"], data["energy"])
    np.testing.assert_array_equal(col["wheel_speed_joint6 [rad/s]"], data["u"][:, 11])


def test_csv_prismatic_units_without_and_with_robot(tmp_path):
    b = spacearm.Robot.builder("slider", base_mass=50.0, base_inertia=[5, 5, 5])
    b.add_link("s", joint="prismatic", axis=(1, 0, 0), origin=(0.3, 0, 0), mass=2.0, inertia=[0.01, 0.01, 0.01])
    robot = b.build()
    k = 5
    data = {"t": np.arange(k) * 0.1, "x": np.tile(robot.neutral_configuration(), (k, 1)), "u": np.zeros((k, 7)),
            "tau": np.zeros((k, 1))}
    header = open(Trajectory(robot=robot, data=data).to_csv(tmp_path / "a.csv")).read().splitlines()[-k - 1]
    for col in ("q_s_joint [m]", "qd_s_joint [m/s]", "tau_s_joint [N]"):
        assert col in header.split(","), col
    header = open(Trajectory(data=data).to_csv(tmp_path / "b.csv")).read().splitlines()[-k - 1]
    assert "q_q1 [rad]" in header.split(",")


def test_drift_of_a_simulated_run_is_the_simulators_number():
    # One run, one number: the recomputation from the records uses the simulator's scales and
    # agrees with meta["drift"] (the figures the summary prints), which the core computed on
    # its own records; a save/load round trip keeps both.
    robot = spacearm.presets.spatial6()
    u0 = robot.zero_velocity()
    u0[6:] = [0.3, -0.2, 0.4, 0.5, -0.3, 0.6]
    tr = spacearm.simulate(robot, 1.0, u0=u0, dt=2e-3)
    assert set(tr.meta["drift_scales"]) == set(tr.meta["drift"]) == {"P", "L_origin", "energy"}
    assert all(v > 0 for v in tr.meta["drift_scales"].values())
    recomputed = tr.drift()
    for name, value in tr.meta["drift"].items():
        assert value > 0
        assert recomputed[name] == pytest.approx(value, rel=1e-12, abs=0)
    # An explicit scale still overrides the simulator's.
    p = tr.P
    dev = np.max(np.linalg.norm(p - p[0], axis=1))
    assert np.linalg.norm(p[0]) < 1e6
    assert tr.drift(["P"], scale={"P": 1e6})["P"] == pytest.approx(dev / 1e6, rel=1e-12)
