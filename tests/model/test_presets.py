"""The presets carry exactly their defining parameters (presets.py says where each set comes
from), checked against values computed here from those numbers (not from spacearm)."""

import numpy as np
import pytest

import spacearm


def rot(axis, angle):
    """Rotation matrix about a unit axis (Rodrigues), written out independently of spacearm."""
    k = np.asarray(axis, float)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def serial_chain_points(first_joint, axes, lengths, q):
    """Joint positions and link CMs of a serial arm whose link frames align with the base at
    q = 0 and extend along x, with the base at the origin aligned with 𝒥."""
    r = np.eye(3)
    p = np.asarray(first_joint, float)
    coms, tips = [], []
    for axis, length, angle in zip(axes, lengths, q):
        r = r @ rot(axis, angle)
        coms.append(p + r @ [length / 2, 0, 0])
        p = p + r @ [length, 0, 0]
        tips.append(p)
    return np.array(coms), np.array(tips)


PLANAR4 = dict(
    base_mass=100.0,
    base_inertia=np.diag([4.1667] * 3),
    first_joint=(0.25, 0, 0),
    axes=[(0, 0, 1)] * 4,
    lengths=[1.0] * 4,
    masses=[10.0] * 4,
    width=0.05,
    q0=[np.pi / 4, -np.pi / 4, -np.pi / 4, np.pi / 4],
)
SPATIAL6 = dict(
    base_mass=500.0,
    base_inertia=np.diag([68.33, 86.67, 101.67]),
    first_joint=(0.6, 0, 0),
    axes=[(1, 0, 0), (0, 1, 0), (0, 1, 0), (1, 0, 0), (0, 1, 0), (1, 0, 0)],
    lengths=[0.2, 1.0, 1.0, 0.15, 0.15, 0.2],
    masses=[8, 15, 12, 4, 3, 3],
    width=0.1,
    q0=[0, np.pi / 4, -np.pi / 2, 0, np.pi / 4, 0],
)


@pytest.mark.parametrize("name, spec", [("planar4", PLANAR4), ("spatial6", SPATIAL6)])
def test_preset_parameters(name, spec):
    robot = spacearm.presets.get(name)
    d = robot.describe()
    assert d["base"]["mass"] == spec["base_mass"]
    assert np.allclose(d["base"]["inertia"], spec["base_inertia"], rtol=0, atol=1e-12)
    assert robot.n_dof == len(spec["axes"])
    assert robot.total_mass == pytest.approx(spec["base_mass"] + sum(spec["masses"]), rel=1e-15)
    assert np.allclose(robot.initial_q, spec["q0"], rtol=0, atol=1e-15)
    w = spec["width"]
    for link, m, length in zip(d["links"], spec["masses"], spec["lengths"]):
        assert link["type"] == "revolute"
        assert link["mass"] == m
        expected = np.diag([m * w**2 / 6, m * (length**2 + w**2) / 12, m * (length**2 + w**2) / 12])
        assert np.allclose(link["inertia"], expected, rtol=1e-14, atol=0)


@pytest.mark.parametrize("name, spec", [("planar4", PLANAR4), ("spatial6", SPATIAL6)])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_preset_geometry_matches_hand_kinematics(name, spec, seed):
    robot = spacearm.presets.get(name)
    q = spec["q0"] if seed == 0 else np.random.default_rng(seed).uniform(-2, 2, robot.n_dof)
    coms, tips = serial_chain_points(spec["first_joint"], spec["axes"], spec["lengths"], q)
    x = robot.neutral_configuration(q)
    kin = robot.forward_kinematics(x)
    assert np.allclose(kin.com_in_world[1:], coms, rtol=0, atol=1e-13)
    ee = robot.point_position(x)
    assert np.linalg.norm(tips[-1]) > 1.0
    assert np.allclose(ee, tips[-1], rtol=0, atol=1e-13)
    # The system CM from the same hand computation.
    masses = np.array(spec["masses"], float)
    rg = (masses[:, None] * coms).sum(0) / (spec["base_mass"] + masses.sum())
    assert np.allclose(robot.center_of_mass(x), rg, rtol=0, atol=1e-13)


def test_planar4_initial_end_effector_position():
    # Joint 1 at 0.25 m; absolute link angles 45°, 0°, -45°, 0°: x = 0.25 + 2 + sqrt(2), y = 0.
    robot = spacearm.presets.planar4()
    ee = robot.point_position(robot.neutral_configuration())
    assert np.allclose(ee, [0.25 + 2 + np.sqrt(2), 0, 0], rtol=0, atol=1e-13)


def test_planar4_stays_planar():
    # All axes +z: J* has zero rows for vz, wx, wy, and H* couples only in-plane motion.
    robot = spacearm.presets.planar4()
    js = robot.generalized_jacobian(robot.neutral_configuration())
    assert np.abs(js[[2, 3, 4]]).max() < 1e-14
    assert np.abs(js[[0, 1, 5]]).max() > 0.1
