"""Collision detection on a model's collision shapes (spacearm.contact, core collision/):
closed forms for balls and a box, and MuJoCo's own signed distance (``mj_geomDistance``) between
the same geoms of the exported MJCF, at random configurations, for every pair of shape kinds."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm.contact import Contact, contacts
from spacearm.errors import ArgumentError, NotFoundError, SpacearmTypeError

mujoco = pytest.importorskip("mujoco")


def shapes_robot() -> spacearm.Robot:
    """A base and a three-link arm, each body with one collision shape of another kind."""
    b = spacearm.RobotBuilder("shapes", 200.0, np.diag([20.0, 25.0, 30.0]))
    b.add_link("l1", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.6, 0, 0), com=(0.3, 0, 0), mass=5.0,
               inertia=np.diag([0.1, 0.2, 0.2]))
    b.add_link("l2", parent="l1", joint="revolute", axis=(0, 1, 0), origin=(0.6, 0, 0), com=(0.3, 0, 0), mass=4.0,
               inertia=np.diag([0.1, 0.2, 0.2]))
    b.add_link("l3", parent="l2", joint="revolute", axis=(1, 0, 0), origin=(0.6, 0, 0), com=(0.2, 0, 0), mass=2.0,
               inertia=np.diag([0.05, 0.1, 0.1]))
    b.add_geometry("base", "box", role="collision", size=(0.8, 0.7, 0.6), origin=(0.0, 0.0, 0.0))
    b.add_geometry("l1", "capsule", role="collision", radius=0.08, length=0.4, origin=(0.0, 0.0, 0.0), rpy=(0.0, np.pi / 2, 0.0))
    b.add_geometry("l2", "cylinder", role="collision", radius=0.07, length=0.45, origin=(0.0, 0.0, 0.0), rpy=(0.3, 1.2, 0.0))
    b.add_geometry("l3", "sphere", role="collision", radius=0.12, origin=(0.1, 0.0, 0.0))
    return b.build()


def test_two_balls_touch_at_the_closed_form_depth_and_points():
    b = spacearm.RobotBuilder("balls", 100.0, np.eye(3) * 10.0)
    b.add_link("slider", parent="base", joint="prismatic", axis=(1, 0, 0), com=(0, 0, 0), mass=1.0, inertia=np.eye(3) * 0.1)
    b.add_geometry("base", "sphere", role="collision", radius=0.3)
    b.add_geometry("slider", "sphere", role="collision", radius=0.2, origin=(0.0, 0.1, 0.0))
    robot = b.build()
    x = robot.neutral_configuration()
    x[7] = 0.35  # centres (0, 0, 0) and (0.35, 0.1, 0): distance 0.364005..., depth 0.5 − that
    found = contacts(robot, x, pairs=[("base", "slider")])
    assert len(found) == 1 and isinstance(found[0], Contact)
    c = found[0]
    d = np.hypot(0.35, 0.1)
    n = np.array([0.35, 0.1, 0.0]) / d
    assert c.distance == pytest.approx(d - 0.5, abs=1e-14)
    np.testing.assert_allclose(c.normal, n, atol=1e-14)
    np.testing.assert_allclose(c.point_a, 0.3 * n, atol=1e-14)
    np.testing.assert_allclose(c.point_b, [0.35, 0.1, 0.0] - 0.2 * n, atol=1e-14)
    assert c.bodies == ("base", "slider") and "distance" in repr(c)
    # Parent and child are left out by default; far apart, nothing is reported.
    assert contacts(robot, x) == []
    x[7] = 2.0
    assert contacts(robot, x, pairs=[("slider", "base")]) == []
    assert len(contacts(robot, x, pairs=[("slider", "base")], margin=2.0)) == 1


def test_signed_distances_equal_mujocos_for_every_pair_of_shape_kinds():
    robot = shapes_robot()
    model = spacearm.interop.to_mujoco(robot, geometry=("collision",))
    data = mujoco.MjData(model)
    rng = np.random.default_rng(7)
    names = [g.name for g in robot.description.geometries]  # base box, l1 capsule, l2 cylinder, l3 ball
    pairs = [(a, b) for a in ("base", "l1", "l2", "l3") for b in ("base", "l1", "l2", "l3") if a < b]
    compared = 0
    for _ in range(12):
        x = robot.neutral_configuration()
        x[7:] = rng.uniform(-2.5, 2.5, 3)
        found = {c.geometries: c for c in contacts(robot, x, pairs=pairs, margin=10.0)}
        qpos, _ = spacearm.interop.to_mujoco_state(robot, x, robot.zero_velocity())
        data.qpos[:] = qpos
        mujoco.mj_forward(model, data)
        for key, c in found.items():
            g1, g2 = (mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, n) for n in key)
            fromto = np.zeros(6)
            want = mujoco.mj_geomDistance(model, data, g1, g2, 10.0, fromto)
            # MuJoCo's convex–convex distance is its GJK/EPA's (tolerance 1e-6 by default); a
            # ball against a ball or a capsule is closed-form in both.
            tol = 1e-12 if {key[0], key[1]} <= {names[1], names[3]} else 1e-5
            if want < 0.0:
                # Interpenetrating (here a link and the base it is hinged to): the depth is the
                # contact generator's, which for MuJoCo's box–capsule and box–cylinder is not the
                # minimum translation of parry's EPA; both must see the overlap.
                assert c.distance < 0.0, (key, c.distance, want)
                continue
            assert c.distance == pytest.approx(want, abs=tol), (key, c.distance, want)
            # The closest points are MuJoCo's too (a flat face's closest point is unique here).
            np.testing.assert_allclose(np.r_[c.point_a, c.point_b], fromto, atol=1e-4)
            compared += 1
    assert compared >= 12 * 3


def test_bad_input_is_refused_with_the_reason():
    robot = shapes_robot()
    x = robot.neutral_configuration()
    with pytest.raises(ArgumentError, match="margin must be finite and >= 0"):
        contacts(robot, x, margin=-1.0)
    with pytest.raises(NotFoundError, match="no body named 'ghost'"):
        contacts(robot, x, pairs=[("base", "ghost")])
    with pytest.raises(SpacearmTypeError, match="spacearm.Robot"):
        contacts("shapes", x)
    with pytest.raises(spacearm.errors.ShapeError):
        contacts(robot, x[:5])
    meshy = robot.to_builder()
    meshy.add_geometry("l3", "mesh", role="collision", file="hull.stl", name="hull")
    with pytest.raises(ArgumentError, match="'hull' is a mesh"):
        contacts(meshy.build(), x)
