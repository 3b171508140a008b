"""Absurd but finite models are refused by the one validation, with the same message from every
door (``RobotBuilder``, TOML, URDF, DH) and the field at fault.

The bounds (docs/model-format.md, rule 10) are the core's: a non-zero mass in 1e-9 … 1e12 kg,
lengths (joint origin, CM, point offset, initial q) within 1e6 in magnitude, inertia entries
within 1e24 kg·m². The values below are the reproductions of the hardening report: a base mass
of 1e308, a joint origin at 1e150, a CM at 1e300, a URDF inertia of 1e90; each was accepted and
gave a non-finite or indefinite mass matrix without any error.
"""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm import _core
from spacearm.io.dh import robot_from_dh
from spacearm.io.model_file import loads_toml
from spacearm.io.urdf import loads_urdf

GOOD = dict(mass=5.0, origin=(0.5, 0.0, 0.0), com=(0.5, 0.0, 0.0), inertia=(0.01, 0.4, 0.4), base_mass=100.0)


def through_builder(**kw):
    p = {**GOOD, **kw}
    b = spacearm.Robot.builder("bounds", base_mass=p["base_mass"], base_inertia=[10.0, 10.0, 10.0])
    b.add_link("arm", parent="base", joint="revolute", axis=(0, 0, 1), origin=p["origin"], com=p["com"],
               mass=p["mass"], inertia=p["inertia"])
    return b.build()


def through_toml(**kw):
    p = {**GOOD, **kw}
    return loads_toml(f"""
[model]
name = "bounds"
[base]
mass = {p['base_mass']!r}
inertia = [10.0, 10.0, 10.0]
[[link]]
name = "arm"
parent = "base"
com = {list(p['com'])!r}
mass = {p['mass']!r}
inertia = {list(p['inertia'])!r}
joint = {{ type = "revolute", origin = {list(p['origin'])!r}, axis = [0.0, 0.0, 1.0] }}
""", "bounds.toml")


def through_urdf(**kw):
    p = {**GOOD, **kw}
    ixx, iyy, izz = p["inertia"]
    xyz = " ".join(repr(v) for v in p["origin"])
    com = " ".join(repr(v) for v in p["com"])
    return loads_urdf(f"""<robot name="bounds">
  <link name="base"><inertial><mass value="{p['base_mass']!r}"/><inertia ixx="10" iyy="10" izz="10"/></inertial></link>
  <link name="arm"><inertial><origin xyz="{com}"/><mass value="{p['mass']!r}"/><inertia ixx="{ixx!r}" iyy="{iyy!r}" izz="{izz!r}"/></inertial></link>
  <joint name="arm_joint" type="continuous"><parent link="base"/><child link="arm"/><origin xyz="{xyz}"/><axis xyz="0 0 1"/></joint>
</robot>""", source="bounds.urdf")


def through_dh(**kw):
    p = {**GOOD, **kw}
    # Classic DH: joint 1 at `origin` on the base; its link's CM `com` from the joint is
    # (com - (a, 0, 0)) from the DH frame at the far end, with a = 1.
    com = (p["com"][0] - 1.0, p["com"][1], p["com"][2])
    row = dict(name="arm", joint_name="arm_joint", d=0.0, theta=0.0, a=1.0, alpha=0.0, com=com, mass=p["mass"],
               inertia=p["inertia"])
    return robot_from_dh("bounds", base_mass=p["base_mass"], base_inertia=[10.0, 10.0, 10.0],
                         joint1_origin=p["origin"], links=[row])


DOORS = {"builder": through_builder, "toml": through_toml, "urdf": through_urdf, "dh": through_dh}

CASES = [
    ("base mass 1e308", dict(base_mass=1e308), "mass 1e308 kg is outside the physical range"),
    ("link mass 1e13", dict(mass=1e13), "mass 1e13 kg is outside the physical range"),
    ("link mass 1e-12", dict(mass=1e-12), "mass 1e-12 kg is outside the physical range"),
    ("joint origin 1e150", dict(origin=(1e150, 0.0, 0.0)), "joint origin component 1e150 m exceeds 1e6 m"),
    ("CM 1e300", dict(com=(0.0, 1e300, 0.0)), "com component 1e300 m exceeds 1e6 m"),
    ("inertia 1e90", dict(inertia=(1e90, 1e90, 1e90)), "exceeds 1e24 in magnitude"),
]


def test_the_good_model_passes_every_door():
    x_of = lambda r: r.neutral_configuration()  # noqa: E731
    matrices = [door().mass_matrix(x_of(door())) for door in DOORS.values()]
    for h in matrices[1:]:
        np.testing.assert_allclose(h, matrices[0], rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
@pytest.mark.parametrize("door", sorted(DOORS))
def test_absurd_values_are_refused_by_every_door(door, case):
    name, values, rule = case
    if door == "dh" and "com" in values:
        pytest.skip("a DH row's CM is measured from the DH frame; the same bound applies through the builder")
    with pytest.raises(spacearm.ModelError) as info:
        DOORS[door](**values)
    assert rule in str(info.value).replace("1e+", "1e"), str(info.value)
    if door in ("toml", "urdf"):
        assert str(info.value).startswith(f"bounds.{door}:"), str(info.value)


def test_the_bounds_are_the_cores_and_inclusive():
    bounds = _core.MODEL_BOUNDS
    assert bounds == {"min_mass": 1e-9, "max_mass": 1e12, "max_length": 1e6, "max_inertia_entry": 1e24}
    # At the bounds: accepted (a 1e12 kg base with a link 1e6 m away is extreme but physical).
    robot = through_builder(base_mass=1e12, mass=1e-9, origin=(1e6, 0.0, 0.0))
    h = robot.mass_matrix(robot.neutral_configuration())
    assert np.all(np.isfinite(h)) and np.linalg.eigvalsh(h).min() > 0


def test_initial_q_beyond_the_length_bound():
    text = """
[model]
name = "q"
initial_q = [2e6]
[base]
mass = 100.0
inertia = [10.0, 10.0, 10.0]
[[link]]
name = "slider"
parent = "base"
com = [0.0, 0.0, 0.0]
mass = 1.0
inertia = [0.01, 0.01, 0.01]
joint = { type = "prismatic", origin = [0.0, 0.0, 0.0], axis = [1.0, 0.0, 0.0] }
"""
    with pytest.raises(spacearm.ModelFileError, match=r"q.toml:4:\d+: .*initial_q entry 2e6 exceeds 1e6"):
        loads_toml(text, "q.toml")
