"""spacearm.rollout against one spacearm.simulate call per rollout: bit-identical records with
per-rollout plants (perturbed models), initial states and controllers, whatever the thread
count; failed rollouts reported with their reason while the others run on; bad input named by
its rollout."""

import numpy as np
import pytest

import spacearm
from spacearm import errors
from spacearm.control import Callback, JointPD, QuinticJoint, perturbed_model


def batch(robot, b, seed=0):
    rng = np.random.default_rng(seed)
    x0 = np.tile(robot.neutral_configuration(), (b, 1))
    x0[:, 7:] += rng.uniform(-0.3, 0.3, (b, robot.n_dof))
    u0 = np.c_[rng.uniform(-0.05, 0.05, (b, 3)), rng.uniform(-0.1, 0.1, (b, 3)), rng.uniform(-0.3, 0.3, (b, robot.n_dof))]
    return x0, u0


def controllers(robot, x0):
    return [JointPD(20.0, 8.0, QuinticJoint(x[7:], x[7:] + 0.1 * (k + 1), 0.0, 0.2)) for k, x in enumerate(x0)]


@pytest.fixture(scope="module")
def study():
    robot = spacearm.presets.spatial6()
    b = 5
    x0, u0 = batch(robot, b)
    plants = [perturbed_model(robot, base_mass_scale=1 + 0.05 * k, link_mass_scale=1 - 0.03 * k) for k in range(b)]
    ctrl = controllers(robot, x0)
    opts = dict(dt=1e-3, record_every=20)
    expected = [spacearm.simulate(plants[k], 0.3, x0=x0[k], u0=u0[k], controller=ctrl[k], **opts) for k in range(b)]
    return robot, x0, u0, plants, ctrl, opts, expected


@pytest.mark.parametrize("threads", [1, 2, 3, None])
def test_each_rollout_is_bit_identical_to_simulate(study, threads):
    robot, x0, u0, plants, ctrl, opts, expected = study
    runs = spacearm.rollout(robot, 0.3, x0, u0, controller=ctrl, plants=plants, threads=threads, **opts)
    assert runs.ok.all() and runs.reason == [None] * len(x0)
    # The rollouts differ from one another: the equality below is per rollout.
    assert not np.array_equal(runs["x"][0], runs["x"][1])
    for k, traj in enumerate(expected):
        for key in traj.keys:
            if key.startswith("saturation"):
                continue
            np.testing.assert_array_equal(runs[key][k], traj[key], err_msg=f"rollout {k}, {key}")
        assert runs.meta[k]["drift"] == traj.meta["drift"]
        assert runs.meta[k]["n_rhs_evals"] == traj.meta["n_rhs_evals"]
        one = runs.trajectory(k)
        np.testing.assert_array_equal(one["tracking_error"], traj["tracking_error"])
        assert one.robot is plants[k]


def test_a_shared_controller_and_one_initial_row_broadcast(study):
    robot, x0, u0, plants, ctrl, opts, expected = study
    # One controller for every rollout (each runs its own instance), one x0 row for all.
    c = ctrl[0]
    runs = spacearm.rollout(robot, 0.3, x0[0], u0, controller=c, **opts)
    for k in (0, 3):
        traj = spacearm.simulate(robot, 0.3, x0=x0[0], u0=u0[k], controller=c, **opts)
        np.testing.assert_array_equal(runs.x[k], traj.x)
        np.testing.assert_array_equal(runs.tau[k], traj.tau)
    final = runs.final_state()
    assert final.shape == (len(u0), robot.nx + robot.nu)
    np.testing.assert_array_equal(final[2], np.r_[runs.x[2, -1], runs.u[2, -1]])


def test_failed_rollouts_are_reported_and_the_others_run_on(study):
    robot, x0, u0, plants, ctrl, opts, expected = study

    def raises(t, x, u):
        if t > 0.05:
            raise RuntimeError("controller broke")
        return np.zeros(robot.n_dof)

    mixed = list(ctrl)
    mixed[1] = Callback(raises)
    # Gains far beyond what dt = 1 ms can integrate: the motion diverges.
    mixed[3] = JointPD(1e9, 1e7, QuinticJoint(x0[3, 7:], x0[3, 7:] + 0.5, 0.0, 0.2))
    runs = spacearm.rollout(robot, 0.3, x0, u0, controller=mixed, plants=plants, threads=2, **opts)
    assert runs.ok.tolist() == [True, False, True, False, True]
    assert "controller broke" in runs.reason[1] and "t = 0.05" in runs.reason[1]
    assert "fastest mode" in runs.reason[3]  # refused before its first step (sim/step_limit.rs)
    assert runs.error_class[3] == "SimulationError"
    assert np.isnan(runs.x[1]).all() and np.isnan(runs.x[3]).all()
    for k in (0, 2, 4):
        np.testing.assert_array_equal(runs.x[k], expected[k].x)
    with pytest.raises(errors.SimulationError, match="rollout 3 failed"):
        runs.trajectory(3)
    with pytest.raises(errors.SimulationError, match="2 of 5 rollouts failed"):
        runs.raise_failures()


def test_bad_input_names_the_rollout(study):
    robot, x0, u0, plants, ctrl, opts, expected = study
    bad = x0.copy()
    bad[2, 3:7] = [0.0, 0.0, 0.5, 0.5]
    with pytest.raises(errors.QuaternionError, match="rollout 2"):
        spacearm.rollout(robot, 0.3, bad, u0)
    bad = u0.copy()
    bad[4, 7] = np.nan
    with pytest.raises(errors.NonFiniteError, match="rollout 4"):
        spacearm.rollout(robot, 0.3, x0, bad)
    with pytest.raises(errors.ShapeError, match="batch sizes disagree"):
        spacearm.rollout(robot, 0.3, x0, u0[:3])
    with pytest.raises(errors.ShapeError, match=r"\(B, 13\)"):
        spacearm.rollout(robot, 0.3, x0[:, :10], u0)
    with pytest.raises(errors.ShapeError, match="needs a batch"):
        spacearm.rollout(robot, 0.3)
    with pytest.raises(errors.ArgumentError, match="threads"):
        spacearm.rollout(robot, 0.3, x0, u0, threads=0)
    with pytest.raises(errors.ShapeError, match="plants\\[0\\] has N = 4"):
        spacearm.rollout(robot, 0.3, x0, u0, plants=[spacearm.presets.planar4()] * len(x0))
    with pytest.raises(errors.ArgumentError, match="record_dtype"):
        spacearm.rollout(robot, 0.3, x0, u0, record_dtype="float16")


def test_float32_records_are_the_float64_ones_rounded(study):
    robot, x0, u0, plants, ctrl, opts, expected = study
    runs = spacearm.rollout(robot, 0.3, x0, u0, controller=ctrl, plants=plants, record_dtype="float32", **opts)
    assert runs.x.dtype == np.float32 and runs.t.dtype == np.float64
    np.testing.assert_array_equal(runs.x[2], expected[2].x.astype(np.float32))
    np.testing.assert_array_equal(runs.t[2], expected[2].t)
