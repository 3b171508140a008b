"""Engine-independent checks of :mod:`spacearm.interop` and of the random-model generator that
``test_pinocchio.py`` and ``test_mujoco.py`` rely on."""

from __future__ import annotations

import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import spacearm
from spacearm import interop
from spacearm.rotations import quat_to_matrix
from random_models import SEEDS, random_model, tree_features


# ---- the generator produces what the cross-engine tests claim to cover ------------------------
def test_random_models_cover_trees_and_joint_types():
    feats = [random_model(s).features for s in SEEDS]
    count = {k: sum(f[k] for f in feats) for k in feats[0]}
    assert count["mid_chain_branch"] >= 5, count
    assert count["base_branch"] >= 5, count
    assert count["fixed"] >= 5 and count["fixed_with_children"] >= 2, count
    assert count["prismatic"] >= 5 and count["revolute"] >= 30, count
    dofs = [random_model(s).robot.n_dof for s in SEEDS]
    assert min(dofs) == 1 and max(dofs) >= 10, dofs
    # and the permutation to depth-first order is exercised (not the identity everywhere)
    assert sum(np.any(interop.engine_dof_order(random_model(s).robot) != np.arange(random_model(s).robot.n_dof)) for s in SEEDS) >= 3


def test_tree_features():
    assert tree_features([0, 1, 1], ["revolute"] * 3)["mid_chain_branch"]
    assert not tree_features([0, 1, 2], ["revolute"] * 3)["mid_chain_branch"]
    assert tree_features([0, 0, 1], ["revolute"] * 3)["base_branch"]
    assert tree_features([0, 1], ["fixed", "revolute"])["fixed_with_children"]


def test_random_models_are_deterministic_and_physical():
    a, b = random_model(4), random_model(4)
    x = a.robot.neutral_configuration()
    np.testing.assert_array_equal(a.robot.mass_matrix(x), b.robot.mass_matrix(x))
    for s in SEEDS:
        for spec in random_model(s).specs:
            assert 0.5 <= spec["mass"] <= 20.0
            moments = np.linalg.eigvalsh(spec["inertia"])
            assert moments.min() > 0 and moments[0] + moments[1] >= moments[2]


@pytest.mark.parametrize("seed", SEEDS[:12])
def test_describe_echoes_the_builder_inputs(seed):
    """The exporters read ``Robot.describe()``: it must be the model the user built (else the
    engines and spacearm could agree on a model nobody asked for)."""
    rm = random_model(seed)
    links = rm.robot.describe()["links"]
    assert len(links) == len(rm.specs)
    for link, spec in zip(links, rm.specs):
        assert link["parent"] == spec["parent"] and link["type"] == spec["joint"]
        np.testing.assert_allclose(link["origin"], spec["origin"], rtol=0, atol=1e-15)
        np.testing.assert_allclose(link["com"], spec["com"], rtol=0, atol=1e-15)
        np.testing.assert_allclose(quat_to_matrix(link["rotation"]), quat_to_matrix(spec["rotation"]), rtol=0, atol=1e-15)
        if spec["joint"] != "fixed":
            np.testing.assert_allclose(link["axis"], spec["axis"] / np.linalg.norm(spec["axis"]), rtol=0, atol=1e-15)
        assert link["mass"] == spec["mass"]
        np.testing.assert_allclose(link["inertia"], spec["inertia"], rtol=0, atol=1e-15)


# ---- depth-first joint order ---------------------------------------------------------------
def test_engine_dof_order_is_depth_first():
    b = spacearm.Robot.builder("t", 100.0, [10, 10, 10])
    inertia = [0.1, 0.1, 0.1]
    b.add_link("a", parent="base", mass=1, inertia=inertia)  # dof 0
    b.add_link("b", parent="base", mass=1, inertia=inertia)  # dof 1
    b.add_link("f", parent="a", joint="fixed", mass=1, inertia=inertia)
    b.add_link("c", parent="f", mass=1, inertia=inertia)  # dof 2, under a through a fixed link
    b.add_link("d", parent="b", joint="prismatic", mass=1, inertia=inertia)  # dof 3
    b.add_link("e", parent="a", mass=1, inertia=inertia)  # dof 4
    r = b.build()
    # depth-first: base, a, f, c, e, b, d
    np.testing.assert_array_equal(interop.engine_dof_order(r), [0, 2, 4, 1, 3])
    np.testing.assert_array_equal(interop.engine_dof_order(spacearm.presets.spatial6()), np.arange(6))


# ---- MJCF text ---------------------------------------------------------------------------------
def test_mjcf_text():
    r = spacearm.presets.planar4()
    root = ET.fromstring(interop.to_mjcf(r))
    assert root.find("option").get("gravity") == "0 0 0"
    assert root.find("option/flag").get("contact") == "disable"
    assert root.find("worldbody/body/freejoint") is not None
    # The preset's shapes, massless and without contacts: a box per body.
    geoms = list(root.iter("geom"))
    assert [g.get("type") for g in geoms] == ["box"] * 5
    assert all(g.get("mass") == "0" and g.get("contype") == "0" and g.get("conaffinity") == "0" for g in geoms)
    assert [a.get("joint") for a in root.iter("motor")] == [f"joint{k}" for k in range(1, 5)]
    assert interop.to_mjcf(r, geometry=(), actuators=False).count("<geom") == 0
    assert [j.get("type") for j in root.iter("joint")] == ["hinge"] * 4
    assert all(i.get("fullinertia") for i in root.iter("inertial"))
    assert [s.get("name") for s in root.iter("site")] == ["end_effector"]


# ---- optional dependencies -------------------------------------------------------------------
@pytest.mark.parametrize("module, func, package", [("pinocchio", "to_pinocchio", "pin"), ("mujoco", "to_mujoco", "mujoco")])
def test_missing_engine_names_the_pip_package(monkeypatch, module, func, package):
    monkeypatch.setitem(sys.modules, module, None)  # makes `import module` raise ImportError
    with pytest.raises(ImportError, match=f"pip install {package}"):
        getattr(interop, func)(spacearm.presets.planar4())


def test_converters_work_without_the_engines(monkeypatch):
    monkeypatch.setitem(sys.modules, "pinocchio", None)
    monkeypatch.setitem(sys.modules, "mujoco", None)
    r = spacearm.presets.planar4()
    x, u = r.neutral_configuration(), np.arange(r.nu, dtype=float)
    q, v = interop.to_pinocchio_state(r, x, u)
    qpos, qvel = interop.to_mujoco_state(r, x, u)
    np.testing.assert_array_equal(q, x)
    np.testing.assert_array_equal(qpos[3:7], [1, 0, 0, 0])
    assert isinstance(interop.to_mjcf(r), str)
