"""Shared fixtures: the presets and a hand-built branched tree (two arms on the base, one of
them forking mid-chain, with prismatic and fixed joints), so invariants are exercised on a
tree, not only on serial chains."""

import os
import sys

# MuJoCo's renderer offscreen (EGL) in every test process, whichever test imports mujoco first
# (MuJoCo reads MUJOCO_GL when it is imported; tests/viz/test_video.py renders with it).
if sys.platform.startswith("linux"):  # MuJoCo accepts egl on Linux only
    os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np
import pytest

# Tests live in sub-folders that mirror the package; the shared helpers (random_models.py,
# robot_data.py, ...) stay here, so this folder goes on the path for every test.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import spacearm


def branched_tree() -> spacearm.Robot:
    b = spacearm.Robot.builder("branched", base_mass=300.0, base_inertia=[[40, 1, -2], [1, 55, 3], [-2, 3, 60]])
    bar = lambda m, length: [m * 0.01 / 6, m * (length**2 + 0.01) / 12, m * (length**2 + 0.01) / 12]  # noqa: E731
    b.add_link("a1", parent="base", axis=(0, 0, 1), origin=(0.8, 0.2, 0.1), com=(0.3, 0, 0), mass=6, inertia=bar(6, 0.6))
    b.add_link("a2", parent="a1", axis=(0, 1, 0), origin=(0.3, 0, 0), com=(0.4, 0, 0), mass=5, inertia=bar(5, 0.8), rpy=(0.3, 0, 0))
    # Mid-chain branch: two children of a2.
    b.add_link("a3", parent="a2", axis=(1, 0, 0), origin=(0.4, 0, 0), com=(0.2, 0.05, 0), mass=2, inertia=bar(2, 0.4))
    b.add_link("a3b", parent="a2", joint="prismatic", axis=(0, 0, 1), origin=(0.1, 0.1, 0), com=(0, 0, 0.1), mass=1.5, inertia=bar(1.5, 0.3))
    b.add_link("cam", parent="a3", joint="fixed", origin=(0.2, 0, 0), rpy=(0, 0.5, 0), com=(0.05, 0, 0), mass=0.7, inertia=[0.002, 0.003, 0.004])
    # Second arm on the base.
    b.add_link("b1", parent="base", axis=(0, 1, 1), origin=(-0.8, 0, 0.3), com=(-0.3, 0, 0), mass=4, inertia=bar(4, 0.6), rpy=(0, 0, np.pi))
    b.add_link("b2", parent="b1", joint="prismatic", axis=(1, 0, 0), origin=(-0.3, 0, 0), com=(-0.2, 0, 0), mass=3, inertia=bar(3, 0.4))
    b.add_point("tool", body="cam", offset=(0.1, 0.02, -0.03))
    b.add_point("grip_b", body="b2", offset=(-0.2, 0, 0))
    b.set_end_effector("tool")
    b.set_initial_q([0.3, -0.5, 0.7, 0.05, 0.4, 0.1])
    return b.build()


MODELS = {
    "planar4": spacearm.presets.planar4,
    "spatial6": spacearm.presets.spatial6,
    "branched": branched_tree,
}


@pytest.fixture(params=sorted(MODELS))
def any_robot(request):
    return MODELS[request.param]()


def random_state(robot, seed, far=True):
    """A random configuration (base possibly far from the origin) and velocity."""
    rng = np.random.default_rng(seed)
    quat = rng.normal(size=4)
    quat /= np.linalg.norm(quat)
    r0 = rng.uniform(-50, 50, 3) if far else rng.uniform(-1, 1, 3)
    x = np.concatenate([r0, quat, rng.uniform(-2, 2, robot.n_dof)])
    u = rng.uniform(-1, 1, robot.nu)
    return x, u
