"""``Robot.joint_names`` and ``Robot.dof_types``: one entry per degree of freedom, in ``q`` order,
checked against sources that do not go through spacearm: the URDF's joint list (xml.etree),
Pinocchio's model of the same URDF, the TOML file's ``[[link]]`` tables (tomllib), and which
bodies move when one coordinate of ``q`` changes (forward kinematics)."""

from __future__ import annotations

import glob
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import spacearm
from spacearm import presets
from spacearm.io.urdf import load_urdf

from robot_data import robots_dir

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = pytest.importorskip("tomli")

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
# URDF joint type -> spacearm dof type (a continuous joint is a revolute joint without limits).
URDF_DOF_TYPES = {"revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic"}


URDFS = {
    "ur5": ("ur_description/urdf/ur5_robot.urdf", {}),
    "panda": ("panda_description/urdf/panda.urdf", {"mimic": "independent"}),
}


def urdf_dofs(path: str) -> list:
    """``(name, dof type)`` of the URDF's moving joints, in document order (a chain: q order)."""
    return [(j.get("name"), URDF_DOF_TYPES[j.get("type")]) for j in ET.parse(path).getroot().findall("joint")
            if j.get("type") != "fixed"]


def moved_bodies(robot, k: int) -> set:
    """Indices of the bodies whose pose changes when ``q[k]`` alone changes."""
    q = np.array(robot.initial_q, dtype=float)
    before = robot.forward_kinematics(robot.neutral_configuration(q))
    q[k] += 0.3
    after = robot.forward_kinematics(robot.neutral_configuration(q))
    moved = np.any(np.abs(after.body_to_world - before.body_to_world) > 1e-12, axis=(1, 2)) | np.any(
        np.abs(after.com_in_world - before.com_in_world) > 1e-12, axis=1)
    return set(np.flatnonzero(moved))


# (The UR5 cannot keep its fixed links: its root link 'world' is massless.)
@pytest.mark.parametrize("name, fixed", [("ur5", "merge"), ("panda", "merge"), ("panda", "keep")])
def test_urdf_arm_matches_the_urdf_joint_list_and_pinocchio(name, fixed):
    rel, opts = URDFS[name]
    path = os.path.join(robots_dir(), rel)
    robot = load_urdf(path, fixed=fixed, **opts)
    expected = urdf_dofs(path)
    assert robot.joint_names == [n for n, _ in expected]
    assert robot.dof_types == [t for _, t in expected]
    assert len(robot.joint_names) == robot.n_dof
    pin = pytest.importorskip("pinocchio")
    model = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
    assert list(model.names)[:2] == ["universe", "root_joint"]
    assert robot.joint_names == list(model.names)[2:]
    # Pinocchio's velocity index of each joint: q order is the same as Pinocchio's v order.
    assert [model.joints[model.getJointId(n)].idx_v - 6 for n in robot.joint_names] == list(range(robot.n_dof))


def test_joint_types_is_per_link_and_dof_types_per_dof():
    # The Panda with its fixed links kept as bodies: joint_types counts them, dof_types does not.
    rel, opts = URDFS["panda"]
    robot = load_urdf(os.path.join(robots_dir(), rel), fixed="keep", **opts)
    assert len(robot.joint_types) == robot.n_bodies - 1
    assert "fixed" in robot.joint_types
    assert robot.dof_types == [t for t in robot.joint_types if t != "fixed"]


TOML_WITH_FIXED_JOINTS = """
[model]
name = "mixed"
format_version = 1

[base]
name = "bus"
mass = 500.0
inertia = [80.0, 90.0, 100.0]

[[link]]
name = "boom"
parent = "bus"
com = [0.0, 0.0, 0.2]
mass = 3.0
inertia = [0.05, 0.05, 0.01]
joint = { name = "boom_mount", type = "fixed", origin = [0.5, 0.0, 0.5] }

[[link]]
name = "upper"
parent = "boom"
com = [0.3, 0.0, 0.0]
mass = 5.0
inertia = [0.01, 0.2, 0.2]
joint = { name = "shoulder", type = "revolute", origin = [0.0, 0.0, 0.4], axis = [0.0, 0.0, 1.0] }

[[link]]
name = "camera"
parent = "upper"
com = [0.0, 0.0, 0.0]
mass = 0.5
inertia = [0.001, 0.001, 0.001]
joint = { name = "camera_mount", type = "fixed", origin = [0.2, 0.0, 0.1] }

[[link]]
name = "slider"
parent = "upper"
com = [0.2, 0.0, 0.0]
mass = 2.0
inertia = [0.005, 0.05, 0.05]
joint = { name = "extend", type = "prismatic", origin = [0.6, 0.0, 0.0], axis = [1.0, 0.0, 0.0] }

[[link]]
name = "wrist"
parent = "slider"
com = [0.1, 0.0, 0.0]
mass = 1.0
inertia = [0.002, 0.004, 0.004]
joint = { type = "revolute", origin = [0.4, 0.0, 0.0], axis = [0.0, 1.0, 0.0] }

[[link]]
name = "side"
parent = "bus"
com = [0.2, 0.0, 0.0]
mass = 2.0
inertia = [0.005, 0.03, 0.03]
joint = { name = "side_hinge", type = "revolute", origin = [0.0, 0.6, 0.0], axis = [1.0, 0.0, 0.0] }
"""


def toml_dofs(doc: dict) -> list:
    """``(joint name, type, link name)`` of the moving joints in file order; a joint's name
    defaults to ``<link>_joint`` (docs/model-format.md)."""
    out = []
    for link in doc.get("link", []):
        joint = link["joint"]
        if joint["type"] != "fixed":
            out.append((joint.get("name", f"{link['name']}_joint"), joint["type"], link["name"]))
    # A [[gripper]] adds its fingers after the links, on the joints docs/contact.md names
    # (<name>_finger<i>_joint: prismatic for two fingers, revolute for three).
    for g in doc.get("gripper", []):
        n = g.get("fingers", 2)
        out += [(f"{g['name']}_finger{i}_joint", "prismatic" if n == 2 else "revolute", f"{g['name']}_finger{i}") for i in range(n)]
    return out


def test_toml_model_with_fixed_joints():
    robot = spacearm.io.loads_toml(TOML_WITH_FIXED_JOINTS)
    expected = toml_dofs(tomllib.loads(TOML_WITH_FIXED_JOINTS))
    assert robot.joint_names == ["shoulder", "extend", "wrist_joint", "side_hinge"] == [n for n, _, _ in expected]
    assert robot.dof_types == ["revolute", "prismatic", "revolute", "revolute"]
    assert robot.joint_types == ["fixed", "revolute", "fixed", "prismatic", "revolute", "revolute"]
    # q[k] belongs to joint_names[k]: moving q[k] alone moves that joint's link first (and its
    # subtree), not the links of the other joints.
    bodies = robot.body_names
    for k, (_, _, link) in enumerate(expected):
        moved = moved_bodies(robot, k)
        assert min(moved) == bodies.index(link), (k, [bodies[b] for b in sorted(moved)])
        for j, (_, _, other) in enumerate(expected):
            if j != k and bodies.index(other) < bodies.index(link):
                assert bodies.index(other) not in moved


@pytest.mark.parametrize("path", sorted(glob.glob(os.path.join(os.path.dirname(spacearm.examples.path("spatial6")), "*.toml"))),
                         ids=os.path.basename)
def test_example_model_files(path):
    robot = spacearm.io.load_toml(path)
    with open(path, "rb") as fh:
        expected = toml_dofs(tomllib.load(fh))
    assert robot.joint_names == [n for n, _, _ in expected]
    assert robot.dof_types == [t for _, t, _ in expected]


@pytest.mark.parametrize("name", presets.NAMES)
def test_presets_have_one_name_per_dof(name):
    robot = presets.get(name)
    assert len(robot.joint_names) == len(robot.dof_types) == robot.n_dof
    assert len(set(robot.joint_names)) == robot.n_dof
