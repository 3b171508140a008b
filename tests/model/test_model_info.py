"""The typed description at the extension boundary (``_core.Model.describe()`` → ``ModelDescription``)
and the plain ``Robot.describe()`` dict built from it, against sources that do not go through
it: the keyword arguments given to ``RobotBuilder`` for the random trees, and the model file the
core writes (``_core.model_to_toml``, read back with ``tomllib``) for every preset."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import spacearm
from spacearm import _core, presets
from spacearm.errors import NonPhysicalInertiaWarning
from spacearm.rotations import quat_to_matrix

from random_models import random_model

tomllib = pytest.importorskip("tomllib")  # in the standard library from Python 3.11

SEEDS = [0, 3, 7, 11, 19, 23, 31]
PRESETS = list(presets.NAMES)
LIMIT_NAMES = ("lower", "upper", "velocity", "effort")


def _robot(name: str) -> spacearm.Robot:
    if name != "ets7":
        return presets.get(name)
    with warnings.catch_warnings():  # ets7's published inertias break the triangle inequality
        warnings.simplefilter("ignore", NonPhysicalInertiaWarning)
        return presets.get(name, allow_nonphysical_inertia=True)


def test_describe_returns_the_typed_classes():
    info = presets.dual_arm().core_model.describe()
    assert isinstance(info, _core.ModelDescription)
    assert isinstance(info.base, _core.BaseDescription)
    assert isinstance(info.links, tuple) and all(isinstance(link, _core.LinkDescription) for link in info.links)
    assert isinstance(info.points, tuple) and all(isinstance(p, _core.PointDescription) for p in info.points)
    assert all(isinstance(link.limits, _core.JointLimits) for link in info.links)
    link, point = info.links[0], info.points[0]
    for array, shape in ((info.base.inertia, (3, 3)), (link.inertia, (3, 3)), (link.origin, (3,)), (link.rotation, (4,)),
                         (link.axis, (3,)), (link.com, (3,)), (point.offset, (3,)), (info.initial_q, (12,))):
        assert isinstance(array, np.ndarray) and array.dtype == np.float64 and array.shape == shape
    # Frozen: no attribute can be set, and the arrays handed out are read-only.
    for obj, attr in ((info, "name"), (info.base, "mass"), (link, "mass"), (link.limits, "upper"), (point, "body")):
        with pytest.raises(AttributeError):
            setattr(obj, attr, getattr(obj, attr))
    with pytest.raises(ValueError):
        link.origin[:] = 1e3
    assert not np.any(info.links[0].origin == 1e3)
    assert "LinkDescription 'left_link1'" in repr(link) and "inertia (3, 3)" in repr(link)


@pytest.mark.parametrize("seed", SEEDS)
def test_typed_fields_equal_the_builder_arguments(seed):
    rm = random_model(seed)
    info = rm.robot.core_model.describe()
    assert info.name == f"random{seed}"
    assert [link.name for link in info.links] == [f"link{k + 1}" for k in range(len(rm.specs))]
    body_names = ["base"] + [f"link{k + 1}" for k in range(len(rm.specs))]
    n_moving = 0
    for link, spec, parent, kind in zip(info.links, rm.specs, rm.parents, rm.kinds):
        assert (link.parent_index, link.parent, link.type) == (parent, body_names[parent], kind)
        assert link.joint == f"{link.name}_joint"
        assert link.mass == spec["mass"]
        np.testing.assert_array_equal(link.origin, spec["origin"])
        np.testing.assert_array_equal(link.com, spec["com"])
        np.testing.assert_allclose(link.inertia, spec["inertia"], rtol=0, atol=1e-15 * np.abs(spec["inertia"]).max())
        np.testing.assert_allclose(link.axis, spec["axis"], rtol=0, atol=1e-15)
        np.testing.assert_allclose(quat_to_matrix(link.rotation), quat_to_matrix(spec["rotation"]), rtol=0, atol=1e-14)
        assert [getattr(link.limits, k) for k in LIMIT_NAMES] == [-math.inf, math.inf, math.inf, math.inf]
        assert link.dof == (None if kind == "fixed" else n_moving)
        n_moving += kind != "fixed"
    assert n_moving == rm.robot.n_dof
    # Points: the body each is fixed to, by the model's own lookup (Model.point), by index and name.
    assert [p.name for p in info.points] == ["tip", "probe"] and info.end_effector == "tip"
    for p in info.points:
        body, offset = rm.robot.core_model.point(p.name)
        assert (p.body_index, p.body) == (body, body_names[body])
        np.testing.assert_array_equal(p.offset, offset)
    np.testing.assert_array_equal(info.initial_q, np.zeros(rm.robot.n_dof))
    # The base: its mass and inertia are the only parameters in neither the specs nor the file
    # below; the total mass is the model's own sum.
    assert info.base.mass + sum(spec["mass"] for spec in rm.specs) == pytest.approx(rm.robot.total_mass, rel=1e-14)
    assert np.all(np.linalg.eigvalsh(info.base.inertia) > 0)


def _matrix(value) -> list:
    """A model file's inertia (``[ixx, iyy, izz]`` or a 3×3 matrix) as a 3×3 list of floats."""
    a = np.asarray(value, dtype=float)
    return (np.diag(a) if a.shape == (3,) else a).tolist()


def _describe_from_model_file(robot: spacearm.Robot) -> dict:
    """The dict :meth:`Robot.describe` has always returned, rebuilt from the model file the core
    writes for ``robot`` (docs/model-format.md: defaults for what the file leaves out)."""
    doc = tomllib.loads(_core.model_to_toml(robot.core_model))
    links = doc.get("link", [])
    body_names = [doc["base"]["name"]] + [link["name"] for link in links]
    out_links, n_moving = [], 0
    for link in links:
        joint, limits = link["joint"], link["joint"].get("limits", {})
        moving = joint["type"] != "fixed"
        out_links.append({
            "name": link["name"],
            "parent": link["parent"],
            "parent_index": body_names.index(link["parent"]),
            "joint": joint.get("name", f"{link['name']}_joint"),
            "type": joint["type"],
            "origin": [float(v) for v in joint.get("origin", [0.0, 0.0, 0.0])],
            "rotation": [float(v) for v in joint.get("rotation", [0.0, 0.0, 0.0, 1.0])],
            "axis": [float(v) for v in joint.get("axis", [0.0, 0.0, 1.0])],
            "com": [float(v) for v in link.get("com", [0.0, 0.0, 0.0])],
            "mass": float(link["mass"]),
            "inertia": _matrix(link["inertia"]),
            "limits": [float(limits.get("lower", -math.inf)), float(limits.get("upper", math.inf)),
                       float(limits.get("velocity", math.inf)), float(limits.get("effort", math.inf))],
            "dof": n_moving if moving else None,
            # the joint's dynamics (docs/model-format.md: actuated, a spring-damper; defaults)
            "actuated": bool(joint.get("actuated", True)),
            "stiffness": float(joint.get("stiffness", 0.0)),
            "damping": float(joint.get("damping", 0.0)),
            "rest": float(joint.get("rest", 0.0)),
        })
        n_moving += moving
    return {
        "name": doc["model"]["name"],
        "base": {"name": doc["base"]["name"], "mass": float(doc["base"]["mass"]), "inertia": _matrix(doc["base"]["inertia"])},
        "links": out_links,
        "points": [(p["name"], p["body"], [float(v) for v in p["offset"]]) for p in doc.get("point", [])],
        "end_effector": doc["model"].get("end_effector"),
        "initial_q": [float(v) for v in doc["model"].get("initial_q", [0.0] * n_moving)],
    }


def _assert_same_plain_data(got, want, where="describe()"):
    """Equal values of the same Python types, all the way down (a tuple is not a list, an int is
    not a float)."""
    assert type(got) is type(want), f"{where}: {type(got).__name__} != {type(want).__name__}"
    if isinstance(want, dict):
        assert list(got) == list(want), f"{where}: keys {list(got)} != {list(want)}"
        for k in want:
            _assert_same_plain_data(got[k], want[k], f"{where}[{k!r}]")
    elif isinstance(want, (list, tuple)):
        assert len(got) == len(want), f"{where}: length {len(got)} != {len(want)}"
        for i, (g, w) in enumerate(zip(got, want)):
            _assert_same_plain_data(g, w, f"{where}[{i}]")
    else:
        assert got == want, f"{where}: {got!r} != {want!r}"


@pytest.mark.parametrize("name", PRESETS)
def test_describe_is_the_model_file_for_the_presets(name):
    robot = _robot(name)
    _assert_same_plain_data(robot.describe(), _describe_from_model_file(robot))


@pytest.mark.parametrize("seed", SEEDS)
def test_describe_is_the_model_file_for_random_trees(seed):
    robot = random_model(seed).robot
    _assert_same_plain_data(robot.describe(), _describe_from_model_file(robot))


def test_describe_of_a_urdf_with_limits_and_fixed_links():
    """Finite limits, named joints, a merged fixed link and a kept one, through the URDF door."""
    text = """<robot name="u">
  <link name="bus"><inertial><mass value="100"/><inertia ixx="10" iyy="12" izz="14"/></inertial></link>
  <link name="arm"><inertial><origin xyz="0.2 0 0"/><mass value="3"/><inertia ixx="0.01" iyy="0.2" izz="0.2"/></inertial></link>
  <link name="tool"><inertial><mass value="0.5"/><inertia ixx="0.001" iyy="0.001" izz="0.001"/></inertial></link>
  <joint name="shoulder" type="revolute"><parent link="bus"/><child link="arm"/><origin xyz="0.5 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-1.5" upper="2" velocity="0.7" effort="40"/></joint>
  <joint name="flange" type="fixed"><parent link="arm"/><child link="tool"/><origin xyz="0.4 0 0"/></joint>
</robot>"""
    for fixed in ("merge", "keep"):
        robot = spacearm.io.urdf.loads_urdf(text, fixed=fixed)
        _assert_same_plain_data(robot.describe(), _describe_from_model_file(robot))
        shoulder = robot.core_model.describe().links[0]
        assert (shoulder.joint, shoulder.limits.lower, shoulder.limits.upper, shoulder.limits.velocity,
                shoulder.limits.effort) == ("shoulder", -1.5, 2.0, 0.7, 40.0)
    assert [link.type for link in robot.core_model.describe().links] == ["revolute", "fixed"]


def test_describe_stays_a_fresh_dict_of_plain_data():
    robot = presets.spatial6()
    d = robot.describe()
    d["links"][0]["mass"] = -1.0
    d["base"]["inertia"][0][0] = -1.0
    assert robot.describe()["links"][0]["mass"] > 0 and robot.describe()["base"]["inertia"][0][0] > 0
    assert robot.description.links[0].mass > 0
