"""URDF export: TOML → URDF → spacearm gives the same equations of motion (H to 1e-12)."""

from __future__ import annotations

import glob
import os

import numpy as np
import pytest

import spacearm
from spacearm.io.urdf import load_urdf, loads_urdf
from spacearm.io.urdf_export import save_urdf, to_urdf
from random_models import SEEDS, random_model

MODELS_DIR = os.path.dirname(spacearm.examples.path("spatial6"))  # the shipped model files
CASES = sorted(glob.glob(os.path.join(MODELS_DIR, "*.toml"))) + ["dual_arm"] + [f"seed{s}" for s in SEEDS[:8]]


def original(name: str) -> spacearm.Robot:
    if name.endswith(".toml"):
        return spacearm.io.load_toml(name)
    if name.startswith("seed"):
        return random_model(int(name[4:])).robot
    return spacearm.presets.get(name)


@pytest.mark.parametrize("name", CASES, ids=os.path.basename)
def test_round_trip_gives_the_same_mass_matrix(name):
    r1 = original(name)
    r2 = loads_urdf(to_urdf(r1), fixed="keep")  # fixed bodies stay bodies: the base CM stays put
    assert r2.n_dof == r1.n_dof and r2.total_mass == pytest.approx(r1.total_mass, rel=1e-14)
    dofs1 = [link["joint"] for link in r1.describe()["links"] if link["type"] != "fixed"]
    dofs2 = [link["joint"] for link in r2.describe()["links"] if link["type"] != "fixed"]
    perm = [dofs1.index(j) for j in dofs2]  # the importer numbers depth-first
    ix = np.concatenate([np.arange(6), 6 + np.array(perm, dtype=int)])
    rng = np.random.default_rng(5)
    for _ in range(3):
        x = r1.neutral_configuration(rng.uniform(-2, 2, r1.n_dof), r0=rng.normal(size=3),
                                     quat0=(lambda q: q / np.linalg.norm(q))(rng.normal(size=4)))
        x2 = np.concatenate([x[:7], x[7:][perm]])
        h1, h2 = r1.mass_matrix(x)[np.ix_(ix, ix)], r2.mass_matrix(x2)
        assert np.linalg.norm(h2 - h1) / np.linalg.norm(h1) <= 1e-12
        for point in r1.point_names:
            assert np.allclose(r2.point_position(x2, point), r1.point_position(x, point), rtol=0, atol=1e-12)


def test_limits_and_file(tmp_path):
    b = spacearm.RobotBuilder("lim", 10.0, [1, 1, 1])
    b.add_link("a", joint="revolute", mass=1.0, inertia=[0.1, 0.1, 0.1], com=(0.1, 0, 0), limits={"lower": -1, "upper": 1, "effort": 3})
    b.add_link("b", parent="a", joint="prismatic", axis=(1, 0, 0), mass=1.0, inertia=[0.1, 0.1, 0.1], limits={"velocity": 2})
    b.add_reaction_wheel([0, 0, 1], 0.05, (0.2, 0, 0), max_torque=0.1, max_speed=300.0, mass=1.0)
    r = b.build()
    path = tmp_path / "lim.urdf"
    save_urdf(r, path)
    back = load_urdf(path)
    assert [link["limits"] for link in back.describe()["links"]] == [link["limits"] for link in r.describe()["links"]]
    assert [t for t in back.joint_types] == ["revolute", "prismatic", "revolute"]
    assert not list(tmp_path.glob("*.tmp"))
