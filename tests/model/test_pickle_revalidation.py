"""Unpickling a data object re-validates its values as its constructor does (issue 38): a
tampered pickle of a PayloadEstimate, a CampaignResult or a campaign/control data class is
refused with a spacearm error, never loaded with values its constructor would refuse."""

from __future__ import annotations

import copy
import pickle

import numpy as np
import pytest

import spacearm
from spacearm import errors
from spacearm.campaign import Fixed, Flexibility, Panel, Perturbations, Tank, Uniform
from spacearm.campaign.results import FAILED, CampaignResult
from spacearm.control import CartesianLine, QuinticJoint
from spacearm.identify import identify_payload


def _tampered(obj, **values):
    """A pickle of ``obj`` with ``values`` put in place (past any check), read back."""
    bad = copy.copy(obj)
    for key, value in values.items():
        object.__setattr__(bad, key, value)
    return pickle.loads(pickle.dumps(bad))


@pytest.fixture(scope="module")
def estimate():
    robot = spacearm.presets.spatial6()
    combined = spacearm.RobotBuilder.from_robot(robot).attach_payload("p", body="link6", mass=40.0, inertia=[2.0, 3.0, 4.5],
                                                                       origin=(0.4, 0.05, -0.02)).build()
    u0 = combined.zero_velocity()
    u0[:6] = [0.01, 0.02, -0.01, 0.02, -0.01, 0.03]
    u0[6:] = [0.3, -0.25, 0.35, 0.4, -0.3, 0.5]
    traj = spacearm.simulate(combined, 2.0, x0=combined.neutral_configuration(), u0=u0, integrator="dopri5", rtol=1e-12,
                             atol=1e-12, dt=0.05)
    return identify_payload(robot, traj, body="link6")


def test_a_payload_estimate_round_trips(estimate):
    back = pickle.loads(pickle.dumps(estimate))
    assert back.mass == estimate.mass and np.array_equal(back.covariance, estimate.covariance)


@pytest.mark.parametrize("values, error", [
    (dict(parameters=np.full(10, np.nan)), errors.NonFiniteError),
    (dict(covariance=np.ones((9, 9))), errors.ShapeError),
    (dict(rank=11), errors.ArgumentError),
    (dict(rank="10"), errors.SpacearmTypeError),
    (dict(singular_values=-np.arange(10.0)), errors.ArgumentError),
    (dict(condition_number=-1.0), errors.ArgumentError),
    (dict(noise_std=np.array([-1.0, 0.1])), errors.ArgumentError),
    (dict(body=3), errors.SpacearmTypeError),
    (dict(n_samples=0), errors.ArgumentError),
])
def test_a_tampered_payload_estimate_is_refused(estimate, values, error):
    # Before: loaded as is (NaN masses, a rank of 11, negative noise).
    with pytest.raises(error):
        _tampered(estimate, **values)


@pytest.fixture
def result():
    r = CampaignResult('{"samples": 3}', ["a", "b"], ["m"], 3)
    r.record(0, {"a": 1.0, "b": 2.0}, {"m": 0.5}, seconds=0.1)
    r.record(1, {"a": 1.5, "b": 2.5}, None, error="SimulationError: diverged", seconds=0.2)
    return r


def test_a_campaign_result_round_trips(result):
    back = pickle.loads(pickle.dumps(result))
    assert back.n_ok == 1 and back.n_failed == 1 and back.n_pending == 1
    assert np.array_equal(back.params, result.params, equal_nan=True) and back.failures() == result.failures()


@pytest.mark.parametrize("tamper", [
    lambda r: r.status.__setitem__(2, 7),
    lambda r: setattr(r, "params", r.params[:2]),
    lambda r: setattr(r, "metrics", r.metrics.astype(np.float32)),
    lambda r: r.error.__setitem__(1, ""),
    lambda r: r.seconds.__setitem__(0, -5.0),
    lambda r: setattr(r, "spec_json", "{not json"),
    lambda r: setattr(r, "param_names", ("a", "a")),
    lambda r: setattr(r, "run", ["not", "a", "dict"]),
])
def test_a_tampered_campaign_result_is_refused(result, tamper):
    tamper(result)
    with pytest.raises(errors.ArgumentError, match="not a valid CampaignResult"):
        pickle.loads(pickle.dumps(result))


def test_a_tampered_campaign_file_is_refused(result, tmp_path):
    result.status[2] = 9
    path = tmp_path / "r.npz"
    np.savez(path, index=result.index, status=result.status, params=result.params, param_names=np.array(result.param_names),
             metrics=result.metrics, metric_names=np.array(result.metric_names), error=np.array(result.error, dtype=str),
             seconds=result.seconds, spec_json=np.array(result.spec_json), run_json=np.array("{}"))
    with pytest.raises(errors.ArgumentError, match="status"):
        CampaignResult.load(path)


TANK = Tank(radius=0.5, height=2.0, density=1000.0, axial_acceleration=0.1)


@pytest.mark.parametrize("obj, values, error", [
    (Fixed(1.0), dict(value=float("nan")), errors.ArgumentError),
    (Uniform(0.2, 0.4), dict(low=0.9), errors.ArgumentError),
    (TANK, dict(radius=-1.0), errors.ArgumentError),
    (Panel((0, 0, 0), (0, 0, 1), (1, 0, 0), 5.0, (1.0, 0.5, 0.01)), dict(mass=float("inf")), errors.ArgumentError),
    (Flexibility(tank=TANK), dict(fill_fraction=Fixed(1.0)), errors.ArgumentError),
    (Perturbations(), dict(base_mass_sigma=-1.0), errors.ArgumentError),
    (QuinticJoint([0.0], [1.0], 0.0, 1.0), dict(t_end=-1.0), errors.ArgumentError),
    (CartesianLine([0, 0, 0], [1, 0, 0], 0.0, 1.0), dict(p_goal=np.array([np.nan, 0, 0])), errors.NonFiniteError),
])
def test_tampered_data_classes_are_refused(obj, values, error):
    back = pickle.loads(pickle.dumps(obj))
    assert type(back) is type(obj) and repr(back) == repr(obj)
    with pytest.raises(error):
        _tampered(obj, **values)


def test_a_pickle_cannot_rebuild_other_classes_through_the_helper():
    from spacearm._util.pickling import rebuild

    with pytest.raises(errors.SpacearmTypeError):
        rebuild(dict, {})


def test_a_tampered_trajectory_is_refused():
    robot = spacearm.presets.planar4()
    traj = spacearm.simulate(robot, 0.02, dt=0.01)
    back = pickle.loads(pickle.dumps(traj))
    assert np.array_equal(back.x, traj.x) and back.meta == traj.meta
    bad = copy.copy(traj)
    bad._data = dict(traj._data, u=traj.u[:, :3])
    # Before: loaded with a u of the wrong width.
    with pytest.raises(errors.ShapeError, match="'u' must have shape"):
        pickle.loads(pickle.dumps(bad))


def test_tampered_rollouts_are_refused():
    robot = spacearm.presets.planar4()
    x0 = np.tile(robot.neutral_configuration(), (2, 1))
    runs = spacearm.rollout(robot, 0.02, x0, np.zeros((2, robot.nu)))
    back = pickle.loads(pickle.dumps(runs))
    assert np.array_equal(back.x, runs.x) and back.reason == runs.reason and not back.x.flags.writeable
    for key, value in (("_ok", np.ones(3, dtype=bool)), ("_reason", [None]), ("_data", dict(runs._data, u=runs.u[:, :, :2]))):
        state = dict(runs.__dict__)
        state[key] = value
        bad = object.__new__(type(runs))
        bad.__dict__.update(state)
        # Before: loaded with 3 flags for 2 rollouts, one reason, a u of the wrong width.
        with pytest.raises(errors.ArgumentError, match="not a valid Rollouts"):
            pickle.loads(pickle.dumps(bad))
