"""The core's model edits from Python (model/edit.rs, issue 32): Robot.attach_body, Robot.attach,
Robot.remove_subtree. Each is checked against the same model made a second way — through the
RobotBuilder link by link, and by the parallel-axis theorem computed here in numpy — and the
untouched part of the model against the original, bit for bit."""

import warnings

import numpy as np
import pytest

import spacearm
from spacearm.errors import ArgumentError, ModelError, NonPhysicalInertiaWarning, SpacearmTypeError
from spacearm.rotations import quat_to_matrix

from random_models import random_state


def _assert_same_dynamics(a, b, seed=0):
    assert (a.n_dof, a.n_bodies, a.total_mass) == (b.n_dof, b.n_bodies, b.total_mass)
    np.testing.assert_array_equal(a.initial_q, b.initial_q)
    rng = np.random.default_rng(seed)
    for _ in range(3):
        x, u = random_state(a, rng)
        np.testing.assert_array_equal(a.mass_matrix(x), b.mass_matrix(x))
        np.testing.assert_array_equal(a.bias_forces(x, u), b.bias_forces(x, u))


@pytest.mark.parametrize("name", spacearm.presets.NAMES)
def test_attach_body_equals_the_builders_payload(name):
    robot = spacearm.presets.get(name)
    body = robot.body_names[-1]
    quat = np.array([0.1, -0.2, 0.3, 0.9]) / np.linalg.norm([0.1, -0.2, 0.3, 0.9])
    kw = dict(body=body, mass=7.5, inertia=[0.4, 0.7, 0.9], origin=(0.3, -0.1, 0.05), rotation=quat)
    attached = robot.attach_body("payload", **kw)
    replayed = robot.to_builder().attach_payload("payload", **kw).build()
    _assert_same_dynamics(attached, replayed)
    assert attached.describe() == replayed.describe()
    # The untouched part, bit for bit; the original unchanged.
    d, a = robot.describe(), attached.describe()
    assert a["links"][:-1] == d["links"] and a["points"] == d["points"] and a["base"] == d["base"]
    assert attached.total_mass == robot.total_mass + 7.5 and robot.n_bodies == attached.n_bodies - 1


def test_a_payload_on_the_base_has_the_parallel_axis_inertia():
    m0, i0 = 300.0, np.array([[40.0, 1.0, -2.0], [1.0, 55.0, 0.5], [-2.0, 0.5, 61.0]])
    bus = spacearm.Robot.builder("sat", m0, i0, base_name="bus").build()
    m, p, rpy, ip = 25.0, np.array([0.8, -0.3, 1.2]), (-0.4, 0.9, 0.25), np.diag([2.0, 3.0, 4.0])
    sat = bus.attach_body("tank", body="bus", mass=m, inertia=ip, origin=p, rpy=rpy)
    r = quat_to_matrix(spacearm.rotations.quat_from_rpy(*rpy))
    # The base block of H at the identity pose: the Hessian of the kinetic energy of the base
    # and of the tank moving at v0 + w x p.
    h = sat.mass_matrix(sat.neutral_configuration())
    px = np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])
    i_total = i0 + r @ ip @ r.T + m * (p @ p * np.eye(3) - np.outer(p, p))
    np.testing.assert_allclose(h[:3, :3], (m0 + m) * np.eye(3), rtol=1e-14)
    np.testing.assert_allclose(h[:3, 3:], -m * px, rtol=0, atol=1e-13 * m)
    np.testing.assert_allclose(h[3:, 3:], i_total, rtol=0, atol=1e-13 * np.abs(i_total).max())
    np.testing.assert_allclose(sat.center_of_mass(sat.neutral_configuration()), m * p / (m0 + m), rtol=1e-14)


def test_attach_a_whole_model_equals_building_it_in_by_hand():
    host, arm = spacearm.presets.spatial6(), spacearm.presets.planar4()
    quat = np.array([0.0, 0.0, np.sin(0.3), np.cos(0.3)])
    both = host.attach(arm, body="base", origin=(1.5, 0.2, -0.4), rotation=quat, prefix="a_", name="arm_mount")
    assert both.n_dof == host.n_dof + arm.n_dof
    np.testing.assert_array_equal(both.initial_q, np.concatenate([host.initial_q, arm.initial_q]))
    assert both.end_effector == host.end_effector
    # By hand through the RobotBuilder: the arm's base a payload, its links and points prefixed.
    d = arm.describe()
    b = host.to_builder().attach_payload("arm_mount", body="base", mass=d["base"]["mass"], inertia=d["base"]["inertia"],
                                         origin=(1.5, 0.2, -0.4), rotation=quat)
    renamed = lambda n: "arm_mount" if n == d["base"]["name"] else f"a_{n}"  # noqa: E731
    for link in d["links"]:
        b.add_link(renamed(link["name"]), parent=renamed(link["parent"]), joint=link["type"], axis=link["axis"],
                   origin=link["origin"], rotation=link["rotation"], com=link["com"], mass=link["mass"],
                   inertia=link["inertia"], joint_name=f"a_{link['joint']}")
    for point, body, offset in d["points"]:
        b.add_point(f"a_{point}", body=renamed(body), offset=offset)
    b.set_initial_q(np.concatenate([host.initial_q, arm.initial_q]))
    _assert_same_dynamics(both, b.build())
    assert "a_" + arm.end_effector in both.point_names
    # Removing the attached subtree gives the host back, bit for bit.
    back = both.remove_subtree("arm_mount")
    assert back.describe() == host.describe()
    _assert_same_dynamics(back, host)


@pytest.mark.parametrize("name", ["planar4", "dual_arm"])
def test_remove_subtree_equals_the_builders_remove_body(name):
    robot = spacearm.presets.get(name)
    gone = robot.body_names[2]
    removed = robot.remove_subtree(gone)
    replayed = robot.to_builder().remove_body(gone).build()
    _assert_same_dynamics(removed, replayed)
    assert removed.describe() == replayed.describe()
    assert gone not in removed.body_names and removed.n_dof < robot.n_dof


def test_the_grasp_carries_the_targets_points_and_leaves_the_robot_bit_for_bit():
    from spacearm.capture.captured import combined_model

    robot = spacearm.presets.spatial6()
    target = spacearm.Target(50.0, [4.0, 5.0, 6.0], grasp_points={"handle": (-0.5, 0.0, 0.0)})
    combined = combined_model(robot, target, "link6", [0.1, 0.2, 0.3], [0.0, 0.0, 0.0, 1.0], payload="caught")
    d, c = robot.describe(), combined.describe()
    assert c["links"][:-1] == d["links"] and c["links"][-1]["name"] == "caught" and c["links"][-1]["type"] == "fixed"
    assert combined.name == "spatial6+caught" and "caught_handle" in combined.point_names
    assert combined.total_mass == robot.total_mass + 50.0


def test_edits_refuse_bad_input_clearly():
    robot = spacearm.presets.spatial6()
    with pytest.raises(ModelError, match="'base' is the base"):
        robot.remove_subtree("base")
    with pytest.raises(ModelError, match="'ghost' is not a link.*link1"):
        robot.remove_subtree("ghost")
    with pytest.raises(ModelError, match="used twice"):
        robot.attach(robot, body="base", prefix="", name="other")
    with pytest.raises(ModelError, match="'nope' is not defined"):
        robot.attach_body("p", body="nope", mass=1.0)
    with pytest.raises(ModelError, match="mass must be >= 0"):
        robot.attach_body("p", body="base", mass=-1.0)
    with pytest.raises(SpacearmTypeError, match="spacearm.Robot"):
        robot.attach("planar4", body="base")
    with pytest.raises(ArgumentError, match="rotation or rpy"):
        robot.attach_body("p", body="base", mass=1.0, rotation=[0, 0, 0, 1], rpy=[0, 0, 0])
    with pytest.raises(ModelError, match="allow_nonphysical_inertia"):
        robot.attach_body("p", body="base", mass=1.0, inertia=[1.0, 1.0, 3.0])


def test_a_nonphysical_payload_warns_once_on_a_model_that_allows_it():
    b = spacearm.Robot.builder("odd", 10.0, [1.0, 1.0, 1.0], allow_nonphysical_inertia=True)
    host = b.build()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        edited = host.attach_body("p", body="base", mass=1.0, inertia=[1.0, 1.0, 3.0])
        edited.attach_body("q", body="base", mass=1.0)  # no new warning for the old body
    assert [str(w.message).startswith("link 'p'") for w in caught if w.category is NonPhysicalInertiaWarning] == [True]
