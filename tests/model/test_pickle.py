"""pickle and copy.deepcopy round trips: Robot (through the core's TOML writer, floats in
shortest round-trip form), Trajectory, the controllers, references and limits of
spacearm.control, and campaign specs; results after the round trip equal bit for bit."""

import copy
import pickle

import numpy as np
import pytest

import spacearm
from spacearm import control, presets
from spacearm.campaign.perturbation import Perturbations
from spacearm.campaign.scenario import Scenario
from spacearm.campaign.spec import CampaignSpec

from random_models import random_model, random_state


def round_trips(obj):
    return [pickle.loads(pickle.dumps(obj)), pickle.loads(pickle.dumps(obj, protocol=0)), copy.deepcopy(obj), copy.copy(obj)]


@pytest.mark.parametrize("make", [presets.spatial6, presets.planar4, lambda: random_model(2).robot, lambda: random_model(9).robot])
def test_robot_round_trip_is_bit_exact(make):
    robot = make()
    rng = np.random.default_rng(0)
    x, u = random_state(robot, rng)
    f = rng.normal(size=robot.nu)
    for other in round_trips(robot):
        assert isinstance(other, spacearm.Robot) and other is not robot
        assert other.describe() == robot.describe()
        assert np.array_equal(other.mass_matrix(x), robot.mass_matrix(x))
        assert np.array_equal(other.forward_dynamics(x, u, f), robot.forward_dynamics(x, u, f))
        assert np.array_equal(other.generalized_jacobian(x), robot.generalized_jacobian(x))
        assert np.array_equal(other.linearize(x, u, f).A, robot.linearize(x, u, f).A)
        assert other.total_mass == robot.total_mass


def test_model_with_awkward_floats_round_trips_exactly():
    b = spacearm.Robot.builder('arm "A"', 1 / 3, [0.1 + 0.2, 1 / 3, 2 ** 0.5 / 3])
    b.add_link("l1", parent="base", joint="revolute", axis=[0, 0, 1], origin=[1e-7 / 3, 0.1, 2 / 3], com=[1 / 9, 0, 0],
               mass=np.pi, inertia=[1 / 11, 1 / 13, 1 / 17])
    robot = b.build()
    other = pickle.loads(pickle.dumps(robot))
    assert other.describe() == robot.describe()
    assert other.name == 'arm "A"'


def test_trajectory_round_trip():
    robot = presets.planar4()
    traj = spacearm.simulate(robot, 0.2, dt=0.01)
    for other in round_trips(traj):
        assert np.array_equal(other.x, traj.x) and np.array_equal(other.t, traj.t)
        assert other.robot.describe() == robot.describe()


def test_controllers_round_trip_and_simulate_identically():
    robot = presets.planar4()
    x0 = robot.neutral_configuration()
    goal = robot.initial_q + 0.3
    controllers = [
        control.JointPD(kp=50.0, kd=10.0, reference=control.QuinticJoint(robot.initial_q, goal, 0.0, 0.5)),
        control.ComputedTorque(kp=100.0, kd=20.0, reference=control.QuinticJoint(robot.initial_q, goal, 0.0, 0.5),
                               model=control.perturbed_model(robot, base_mass_scale=1.1)),
    ]
    for ctrl in controllers:
        reference = spacearm.simulate(robot, 0.3, x0=x0, controller=ctrl, dt=0.01)
        for other in round_trips(ctrl):
            assert type(other) is type(ctrl)
            again = spacearm.simulate(robot, 0.3, x0=x0, controller=other, dt=0.01)
            assert np.array_equal(again.x, reference.x)


def test_references_and_limits_round_trip():
    objects = [control.QuinticJoint([0.0, 1.0], [1.0, 2.0], 0.0, 1.0), control.Thrusters(max_force=[1, 2, 3], max_torque=[4, 5, 6])]
    for obj in objects:
        for other in round_trips(obj):
            assert repr(other) == repr(obj)


def test_campaign_spec_round_trip():
    spec = CampaignSpec(model_toml=spacearm.io.model_file.dumps_toml(presets.planar4()), samples=3, seed=5,
                        perturbations=Perturbations(), scenario=Scenario(duration=1.0))
    for other in round_trips(spec):
        assert other == spec
        assert other.to_json() == spec.to_json()


def test_a_model_that_allows_nonphysical_inertia_round_trips_with_its_choice():
    import warnings

    from spacearm.errors import NonPhysicalInertiaWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NonPhysicalInertiaWarning)
        robot = presets.ets7(allow_nonphysical_inertia=True)
        other = pickle.loads(pickle.dumps(robot))
    assert other.allows_nonphysical_inertia and other.describe() == robot.describe()
    x = robot.neutral_configuration()
    assert np.array_equal(other.mass_matrix(x), robot.mass_matrix(x))
