"""Model editing through a builder: Robot.to_builder / RobotBuilder.from_robot hold a model
exactly, attach_payload merges a rigid payload, remove_body drops a subtree. Checked against
models built independently (by hand through the builder, the payload folded into the body's
mass properties with the parallel-axis theorem computed here in numpy)."""


import numpy as np
import pytest

import spacearm
from spacearm.campaign.scenario import with_payload
from spacearm.errors import ModelError
from spacearm.rotations import quat_to_matrix

from random_models import random_model, random_state
from robot_data import robot_urdf


def _same_model(a, b, seed=0, exact=True):
    """Same model: bit for bit, or to rounding where the description's unit axes and rotations
    are normalized again on the way back in (random trees)."""
    assert a.n_dof == b.n_dof and a.n_bodies == b.n_bodies
    assert a.total_mass == pytest.approx(b.total_mass, rel=0 if exact else 1e-15)
    assert a.end_effector == b.end_effector
    np.testing.assert_array_equal(a.initial_q, b.initial_q)
    rng = np.random.default_rng(seed)
    for _ in range(3):
        x, u = random_state(a, rng)
        for f, args in ((lambda r, *s: r.mass_matrix(*s), (x,)), (lambda r, *s: r.bias_forces(*s), (x, u))):
            if exact:
                np.testing.assert_array_equal(f(a, *args), f(b, *args))
            else:
                ref = f(a, *args)
                np.testing.assert_allclose(f(b, *args), ref, rtol=0, atol=1e-13 * np.max(np.abs(ref)))


@pytest.mark.parametrize("name", spacearm.presets.NAMES)
def test_to_builder_round_trip_of_presets_is_exact(name):
    robot = spacearm.presets.get(name)
    rebuilt = robot.to_builder().build()
    _same_model(robot, rebuilt)
    assert rebuilt.describe() == robot.describe()


@pytest.mark.parametrize("seed", range(6))
def test_to_builder_round_trip_of_random_trees_is_exact(seed):
    robot = random_model(seed).robot
    _same_model(robot, robot.to_builder().build(), seed, exact=False)


def test_round_trip_keeps_limits_of_a_urdf_arm():
    from spacearm.io.urdf import load_urdf

    robot = load_urdf(robot_urdf("ur_description/urdf/ur5_robot.urdf"))
    rebuilt = robot.to_builder(name="ur5_copy").build()
    assert rebuilt.name == "ur5_copy"
    assert [l["limits"] for l in rebuilt.describe()["links"]] == [l["limits"] for l in robot.describe()["links"]]
    _same_model(robot, rebuilt)


def _folded(mass_a, com_a, inertia_a, mass_p, com_p, rot_p, inertia_p):
    """Two rigid bodies as one, in body a's frame (origin at a's CM): mass, CM, inertia about the
    new CM — the parallel-axis theorem, computed independently of spacearm."""
    m = mass_a + mass_p
    c = (mass_a * com_a + mass_p * com_p) / m

    def shifted(inertia, mass, d):
        return inertia + mass * (d @ d * np.eye(3) - np.outer(d, d))

    i = shifted(inertia_a, mass_a, com_a - c) + shifted(rot_p @ inertia_p @ rot_p.T, mass_p, com_p - c)
    return m, c, i


def test_attached_payload_equals_the_body_with_folded_mass_properties():
    robot = spacearm.presets.planar4()
    d = robot.describe()
    last = d["links"][-1]
    origin = np.array([0.3, -0.1, 0.05])
    quat = np.array([0.1, -0.2, 0.3, 0.9]) / np.linalg.norm([0.1, -0.2, 0.3, 0.9])
    inertia_p = np.diag([0.4, 0.7, 0.9])
    edited = robot.to_builder()
    edited.attach_payload("target", body=last["name"], mass=7.5, inertia=inertia_p, origin=origin, rotation=quat)
    plant = edited.build()
    assert plant.n_dof == robot.n_dof and plant.total_mass == pytest.approx(robot.total_mass + 7.5, rel=1e-15)

    # The same plant by hand: the last link's mass properties replaced by the folded ones. Its
    # CM moves by c in its own frame, so its com (measured from the joint) moves by c and the
    # end-effector point (measured from the CM) by -c.
    m, c, i = _folded(last["mass"], np.zeros(3), np.asarray(last["inertia"]), 7.5, origin, quat_to_matrix(quat), inertia_p)
    b = spacearm.Robot.builder(d["name"], d["base"]["mass"], d["base"]["inertia"], base_name=d["base"]["name"])
    for link in d["links"]:
        folded = link is last
        b.add_link(link["name"], parent=link["parent"], joint=link["type"], axis=link["axis"], origin=link["origin"],
                   rotation=link["rotation"], com=np.asarray(link["com"]) + (c if folded else 0.0),
                   mass=m if folded else link["mass"], inertia=i if folded else link["inertia"], joint_name=link["joint"])
    for point, body, offset in d["points"]:
        b.add_point(point, body=body, offset=np.asarray(offset) - (c if body == last["name"] else 0.0))
    b.set_end_effector(d["end_effector"])
    b.set_initial_q(d["initial_q"])
    by_hand = b.build()
    rng = np.random.default_rng(7)
    for _ in range(4):
        x, u = random_state(robot, rng)
        # The hand-built base CM is the same; states line up one to one.
        np.testing.assert_allclose(plant.mass_matrix(x), by_hand.mass_matrix(x), rtol=1e-12, atol=1e-10)
        np.testing.assert_allclose(plant.bias_forces(x, u), by_hand.bias_forces(x, u), rtol=1e-11, atol=1e-9)
        np.testing.assert_allclose(plant.point_position(x), by_hand.point_position(x), atol=1e-12)
    # The original robot is untouched.
    assert robot.total_mass == pytest.approx(sum([d["base"]["mass"]] + [l["mass"] for l in d["links"]]), rel=1e-15)


def test_remove_body_drops_the_subtree_and_equals_the_smaller_model_built_directly():
    robot = spacearm.presets.planar4()
    d = robot.describe()
    edited = robot.to_builder()
    edited.remove_body(d["links"][2]["name"])  # links 3 and 4 go, with the end effector on 4
    smaller = edited.build()
    assert smaller.n_dof == 2 and smaller.end_effector is None
    np.testing.assert_array_equal(smaller.initial_q, robot.initial_q[:2])
    b = spacearm.Robot.builder(d["name"], d["base"]["mass"], d["base"]["inertia"], base_name=d["base"]["name"])
    for link in d["links"][:2]:
        b.add_link(link["name"], parent=link["parent"], joint=link["type"], axis=link["axis"], origin=link["origin"],
                   rotation=link["rotation"], com=link["com"], mass=link["mass"], inertia=link["inertia"],
                   joint_name=link["joint"])
    b.set_initial_q(robot.initial_q[:2])
    _same_model(smaller, b.build())
    # Adding a link afterwards: the kept joints keep their initial q, the new one starts at 0.
    edited.add_link("new", parent=d["links"][1]["name"], axis=(0, 0, 1), origin=(1.0, 0, 0), com=(0.5, 0, 0),
                    mass=2.0, inertia=[0.01, 0.2, 0.2])
    grown = edited.build()
    np.testing.assert_array_equal(grown.initial_q, list(robot.initial_q[:2]) + [0.0])


def test_remove_body_refuses_the_base_and_unknown_names():
    edited = spacearm.presets.planar4().to_builder()
    with pytest.raises(ModelError, match="base"):
        edited.remove_body(spacearm.presets.planar4().describe()["base"]["name"])
    with pytest.raises(ModelError, match="'nope' is not a link of the model; links: "):
        edited.remove_body("nope")


def test_payload_on_a_link_whose_name_needs_quoting():
    # A valid link name with quotes and a backslash broke the TOML-by-concatenation route.
    b = spacearm.Robot.builder("quoted", 100.0, [10, 10, 10])
    b.add_link('arm "A" \\ 1', parent="base", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.5, 0, 0), mass=5.0,
               inertia=[0.01, 0.4, 0.4])
    b.add_point("tip", body='arm "A" \\ 1', offset=(0.5, 0, 0))
    b.set_end_effector("tip")
    robot = b.build()
    plant = with_payload(robot, 2.0)
    assert plant.total_mass == pytest.approx(robot.total_mass + 2.0, rel=1e-15)
    # The payload sits at the tip: the system CM moves towards it by 2 kg's share.
    x = robot.neutral_configuration()
    expected = (robot.total_mass * robot.center_of_mass(x) + 2.0 * robot.point_position(x)) / plant.total_mass
    np.testing.assert_allclose(plant.center_of_mass(x), expected, atol=1e-13)
