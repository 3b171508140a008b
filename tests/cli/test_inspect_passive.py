"""``spacearm inspect`` lists the passive joints and springs and their natural frequencies."""

import io

import numpy as np

import spacearm
from spacearm.cli.inspect import inspect

TOML = """
[model]
name = "sprung"

[base]
mass = 100.0
inertia = [8.0, 9.0, 10.0]

[[link]]
name = "arm"
parent = "base"
com = [0.4, 0.0, 0.0]
mass = 5.0
inertia = [0.01, 0.3, 0.3]
joint = { type = "revolute", origin = [0.5, 0.0, 0.0], axis = [0.0, 0.0, 1.0], damping = 0.2 }

[[link]]
name = "panel"
parent = "base"
com = [0.5, 0.0, 0.0]
mass = 10.0
inertia = [0.1, 0.75, 0.8]
joint = { type = "revolute", origin = [-1.0, 0.0, 0.0], rotation = [0.0, 0.0, 1.0, 0.0], axis = [0.0, 0.0, 1.0], actuated = false, stiffness = 30.0, damping = 0.5 }
"""


def test_inspect_lists_passive_joints_and_frequencies():
    robot = spacearm.io.loads_toml(TOML)
    out = io.StringIO()
    inspect(robot, out=out)
    text = out.getvalue()
    assert "arm_joint: actuated, stiffness 0, damping 0.2, rest 0" in text
    assert "panel_joint: passive, stiffness 30, damping 0.5, rest 0" in text
    omega = robot.natural_frequencies(actuated="held").frequencies[0]
    assert f"mode 1: {omega:.6g} rad/s = {omega / (2 * np.pi):.6g} Hz" in text and "mostly panel_joint" in text
    # A rigid model prints no such section.
    out = io.StringIO()
    inspect(spacearm.presets.planar4(), out=out)
    assert "passive joints" not in out.getvalue()
