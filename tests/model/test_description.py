"""The typed model description (spacearm.ModelDescription, the extension's own class: Robot.description)
against sources that do not go through it: the TOML files read with ``tomllib``, a URDF read with
``xml.etree``, the core's total mass, and the plain ``describe()`` dict."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import spacearm
from spacearm import _core, presets
from spacearm.model.description import JointLimits, LinkDescription, ModelDescription, PointDescription

tomllib = pytest.importorskip("tomllib")  # in the standard library from Python 3.11
from spacearm.io.model_file import load_toml
from spacearm.rotations import quat_to_matrix
from spacearm.io.urdf import loads_urdf

from random_models import random_model

MODELS = Path(spacearm.examples.path("spatial6")).parent  # the shipped model files
TOML_FILES = sorted(MODELS.glob("*.toml"))
PRESETS = ["planar4", "spatial6", "dual_arm", "spatial7"]


def _inertia_matrix(value) -> np.ndarray:
    """A TOML inertia (docs/model-format.md): ``[ixx, iyy, izz]``, a 3×3 matrix, or a table of
    ``ixx … iyz`` whose products default to 0."""
    if isinstance(value, dict):
        g = lambda k: float(value.get(k, 0.0))  # noqa: E731
        return np.array([[g("ixx"), g("ixy"), g("ixz")], [g("ixy"), g("iyy"), g("iyz")], [g("ixz"), g("iyz"), g("izz")]])
    a = np.asarray(value, dtype=float)
    return np.diag(a) if a.shape == (3,) else a


@pytest.mark.parametrize("path", TOML_FILES, ids=lambda p: p.stem)
def test_fields_equal_the_toml_file(path):
    doc = tomllib.loads(path.read_text(encoding="utf-8"))
    desc = load_toml(path).description

    assert desc.name == doc["model"]["name"]
    assert desc.base.name == doc["base"]["name"]
    assert desc.base.mass == doc["base"]["mass"]
    np.testing.assert_array_equal(desc.base.inertia, _inertia_matrix(doc["base"]["inertia"]))

    # A [[gripper]] adds, after the links, its palm and fingers with the names and points
    # docs/contact.md gives (their fields: tests/contact/test_gripper.py, against closed forms).
    grippers = [(g["name"], g.get("fingers", 2)) for g in doc.get("gripper", [])]
    made = [[name] + [f"{name}_finger{i}" for i in range(n)] for name, n in grippers]
    assert [link.name for link in desc.links] == [link["name"] for link in doc.get("link", [])] + sum(made, [])
    body_names = [doc["base"]["name"]] + [link["name"] for link in doc.get("link", [])]
    n_moving = 0
    for got, want in zip(desc.links, doc.get("link", [])):
        joint = want["joint"]
        assert got.parent == want["parent"]
        assert got.parent_index == body_names.index(want["parent"])
        assert got.joint == joint["name"]
        assert got.type == joint["type"]
        np.testing.assert_array_equal(got.origin, joint.get("origin", [0.0, 0.0, 0.0]))
        np.testing.assert_array_equal(got.com, want.get("com", [0.0, 0.0, 0.0]))
        assert got.mass == want["mass"]
        np.testing.assert_array_equal(got.inertia, _inertia_matrix(want["inertia"]))
        np.testing.assert_array_equal(got.rotation, joint.get("rotation", [0.0, 0.0, 0.0, 1.0]))
        if joint["type"] == "fixed":
            assert got.dof is None
        else:
            axis = np.asarray(joint["axis"], dtype=float)
            np.testing.assert_allclose(got.axis, axis / np.linalg.norm(axis), rtol=0, atol=1e-15)
            assert got.dof == n_moving
            n_moving += 1
            limits = joint.get("limits", {})
            assert got.limits.lower == limits.get("lower", -math.inf)
            assert got.limits.upper == limits.get("upper", math.inf)
            assert got.limits.velocity == limits.get("velocity", math.inf)
            assert got.limits.effort == limits.get("effort", math.inf)

    points = doc.get("point", [])
    made = sum([[(f"{name}_center", name)] + [(f"{name}_tip{i}", f"{name}_finger{i}") for i in range(n)] for name, n in grippers], [])
    assert [(p.name, p.body) for p in desc.points] == [(p["name"], p["body"]) for p in points] + made
    for got, want in zip(desc.points, points):
        np.testing.assert_array_equal(got.offset, want["offset"])
    assert desc.end_effector == doc["model"].get("end_effector")
    n_moving += sum(n for _, n in grippers)  # the fingers' joints (open at 0)
    np.testing.assert_array_equal(desc.initial_q, doc["model"].get("initial_q", [0.0] * n_moving))


# A two-link arm whose URDF frames sit at the joints (spacearm's sit at the CMs), with a tilted,
# non-unit axis and a joint rpy, so origin, com, axis and rotation all differ from the raw XML.
URDF = """<?xml version="1.0"?>
<robot name="two_link">
  <link name="bus">
    <inertial><origin xyz="0.1 -0.05 0.02" rpy="0 0 0"/><mass value="120"/>
      <inertia ixx="20" ixy="0" ixz="0" iyy="25" iyz="0" izz="30"/></inertial>
  </link>
  <link name="upper">
    <inertial><origin xyz="0.3 0 0" rpy="0 0 0"/><mass value="6"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.2"/></inertial>
  </link>
  <link name="fore">
    <inertial><origin xyz="0.25 0.01 0" rpy="0 0 0"/><mass value="4"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="bus"/><child link="upper"/>
    <origin xyz="0.8 0.2 0.1" rpy="0 0 0.5"/><axis xyz="0 0 2"/>
    <limit lower="-2" upper="2.5" velocity="1.5" effort="80"/>
  </joint>
  <joint name="elbow" type="prismatic">
    <parent link="upper"/><child link="fore"/>
    <origin xyz="0.6 0 0" rpy="0.2 -0.3 0.1"/><axis xyz="1 1 0"/>
    <limit lower="0" upper="0.4" velocity="0.2" effort="300"/>
  </joint>
</robot>
"""


def _rpy_matrix(rpy) -> np.ndarray:
    """URDF's fixed-axis roll-pitch-yaw: ``Rz(yaw) Ry(pitch) Rx(roll)``."""
    r, p, y = rpy
    cx, sx, cy, sy, cz, sz = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rz @ ry @ rx


def test_joints_equal_the_urdf():
    root = ET.fromstring(URDF)
    com_in_urdf_frame = {
        link.get("name"): np.array([float(v) for v in link.find("inertial/origin").get("xyz").split()])
        for link in root.findall("link")
    }
    desc = loads_urdf(URDF).description
    assert desc.base.name == "bus"
    assert [link.joint for link in desc.links] == [j.get("name") for j in root.findall("joint")]
    for joint in root.findall("joint"):
        link = next(link for link in desc.links if link.joint == joint.get("name"))
        parent, child = joint.find("parent").get("link"), joint.find("child").get("link")
        assert (link.parent, link.name, link.type) == (parent, child, joint.get("type"))
        xyz = np.array([float(v) for v in joint.find("origin").get("xyz").split()])
        rpy = [float(v) for v in joint.find("origin").get("rpy").split()]
        axis = np.array([float(v) for v in joint.find("axis").get("xyz").split()])
        # the joint from the parent's CM, in the parent's axes (no inertial rotation here)
        np.testing.assert_allclose(link.origin, xyz - com_in_urdf_frame[parent], rtol=0, atol=1e-14)
        np.testing.assert_allclose(quat_to_matrix(link.rotation), _rpy_matrix(rpy), rtol=0, atol=1e-14)
        np.testing.assert_allclose(link.axis, axis / np.linalg.norm(axis), rtol=0, atol=1e-15)
        np.testing.assert_allclose(link.com, com_in_urdf_frame[child], rtol=0, atol=1e-14)
        lim = joint.find("limit")
        assert (link.limits.lower, link.limits.upper, link.limits.velocity, link.limits.effort) == tuple(
            float(lim.get(k)) for k in ("lower", "upper", "velocity", "effort"))


@pytest.mark.parametrize("name", PRESETS)
def test_preset_masses_sum_to_the_total_mass(name):
    robot = presets.get(name)
    desc = robot.description
    assert desc.base.mass + sum(link.mass for link in desc.links) == pytest.approx(robot.total_mass, rel=1e-14)
    assert len(desc.links) == robot.n_bodies - 1
    assert sum(link.dof is not None for link in desc.links) == robot.n_dof > 0


@pytest.mark.parametrize("name", PRESETS)
def test_to_dict_is_describe_for_the_presets(name):
    robot = presets.get(name)
    assert robot.description.to_dict() == robot.describe()


@pytest.mark.parametrize("seed", [0, 7, 19, 31])
def test_to_dict_is_describe_for_random_models(seed):
    robot = random_model(seed).robot
    assert robot.description.to_dict() == robot.describe()


def test_description_is_built_once():
    robot = presets.spatial6()
    assert robot.description is robot.description
    desc = robot.description
    assert desc.links is desc.links and desc.links[0].origin is desc.links[0].origin and desc.base is desc.base
    assert robot.describe() is not robot.describe()  # the dict form stays a fresh copy


def test_classes_are_frozen_and_arrays_read_only():
    desc = presets.dual_arm().description
    link, point = desc.links[0], desc.points[0]
    for obj, field in ((desc, "name"), (desc.base, "mass"), (link, "mass"), (link.limits, "upper"), (point, "body")):
        with pytest.raises(AttributeError):
            setattr(obj, field, getattr(obj, field))
    for array in (desc.base.inertia, link.axis, link.origin, link.rotation, link.com, link.inertia, point.offset,
                  desc.initial_q):
        assert not array.flags.writeable
        with pytest.raises(ValueError):
            array[0] = 1.0
    assert isinstance(desc.links, tuple) and isinstance(desc.points, tuple)


def test_lookup_by_name():
    desc = presets.dual_arm().description
    assert isinstance(desc.link("left_link2"), LinkDescription)
    assert desc.link("left_link2").parent == "left_link1"
    assert isinstance(desc.point("right_tool"), PointDescription)
    assert desc.point("right_tool").body == "right_link6"
    with pytest.raises(spacearm.NotFoundError, match="no link named 'elbow'"):
        desc.link("elbow")
    with pytest.raises(spacearm.NotFoundError, match="no point named 'nose'"):
        desc.point("nose")


def test_exported_from_the_package():
    """Each type once: the public classes are the extension's, not copies of them."""
    for name in ("ModelDescription", "BaseDescription", "LinkDescription", "PointDescription", "JointLimits"):
        assert name in spacearm.__all__
        assert getattr(spacearm, name) is getattr(_core, name)
    assert spacearm.JointLimits is JointLimits
    desc = presets.planar4().description
    assert type(desc) is ModelDescription and type(desc.links[0].limits) is JointLimits
    assert desc.links[0].limits.to_list() == desc.to_dict()["links"][0]["limits"]
