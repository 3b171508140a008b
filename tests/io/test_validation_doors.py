"""The same bad model gets the same verdict from every door that makes a model.

A model can come from a TOML file, from ``RobotBuilder``, from a URDF string or from a DH
table; all of them feed the core's one builder, whose rules are defined once
(``crates/spacearm-core/src/model/validate.rs``). Each case here writes the same physical model
through every door that can express it and checks that each door refuses it with a
``ModelError`` carrying the builder's own message (a file door adds only its location).
"""

from __future__ import annotations

import re

import pytest

import spacearm
from spacearm.io.dh import robot_from_dh
from spacearm.io.model_file import dumps_toml, loads_toml
from spacearm.io.urdf import loads_urdf

BASE_INERTIA = [10.0, 10.0, 10.0]
GOOD_INERTIA = [0.01, 0.4, 0.4]
# Principal moments 0.01 + 0.4 < 1.4: no physical body has them.
NON_PHYSICAL_INERTIA = [0.01, 0.4, 1.4]
# Every component below the 1e-9 floor of a joint axis, although the norm (1.4e-9) is above it.
TINY_AXIS = [8e-10, 8e-10, 8e-10]


def through_builder(axis=(0.0, 0.0, 1.0), mass=5.0, inertia=GOOD_INERTIA) -> spacearm.ModelError:
    b = spacearm.Robot.builder("doors", base_mass=100.0, base_inertia=BASE_INERTIA)
    with pytest.raises(spacearm.ModelError) as info:
        b.add_link("arm", parent="base", joint="revolute", axis=axis, origin=(0.5, 0.0, 0.0),
                   com=(0.5, 0.0, 0.0), mass=mass, inertia=inertia)
        b.build()
    return info.value


def through_toml(axis=(0.0, 0.0, 1.0), mass=5.0, inertia=GOOD_INERTIA) -> spacearm.ModelError:
    text = f"""
[model]
name = "doors"

[base]
mass = 100.0
inertia = {BASE_INERTIA!r}

[[link]]
name = "arm"
parent = "base"
com = [0.5, 0.0, 0.0]
mass = {mass!r}
inertia = {list(inertia)!r}
joint = {{ type = "revolute", origin = [0.5, 0.0, 0.0], axis = {list(axis)!r} }}
"""
    with pytest.raises(spacearm.ModelFileError) as info:
        loads_toml(text, "doors.toml")
    return info.value


def through_urdf(axis=(0.0, 0.0, 1.0), mass=5.0, inertia=GOOD_INERTIA) -> spacearm.ModelError:
    ixx, iyy, izz = inertia
    text = f"""<robot name="doors">
  <link name="base"><inertial><mass value="100"/><inertia ixx="10" iyy="10" izz="10"/></inertial></link>
  <link name="arm"><inertial><origin xyz="0.5 0 0"/><mass value="{mass!r}"/><inertia ixx="{ixx!r}" iyy="{iyy!r}" izz="{izz!r}"/></inertial></link>
  <joint name="arm_joint" type="continuous">
    <parent link="base"/><child link="arm"/><origin xyz="0.5 0 0"/><axis xyz="{' '.join(repr(a) for a in axis)}"/>
  </joint>
</robot>
"""
    with pytest.raises(spacearm.ModelFileError) as info:
        loads_urdf(text, source="doors.urdf")
    return info.value


def through_dh(mass=5.0, inertia=GOOD_INERTIA) -> spacearm.ModelError:
    # A classic DH row whose link matches the others: joint on the base at (0.5, 0, 0), axis z,
    # CM 0.5 m along x from the joint (a = 1, com = -0.5 from the DH origin at the far end).
    row = dict(name="arm", joint_name="arm_joint", d=0.0, theta=0.0, a=1.0, alpha=0.0, com=(-0.5, 0.0, 0.0),
               mass=mass, inertia=inertia)
    with pytest.raises(spacearm.ModelError) as info:
        robot_from_dh("doors", base_mass=100.0, base_inertia=BASE_INERTIA, joint1_origin=(0.5, 0.0, 0.0), links=[row])
    return info.value


def builder_message(error: spacearm.ModelError) -> str:
    """The rule's own message, as the builder states it (after the kind prefix)."""
    text = str(error)
    assert text.startswith("invalid model: "), text
    return text[len("invalid model: "):]


def test_the_doors_accept_the_good_model():
    """The bad cases below differ from a model that every door accepts in one value only."""
    b = spacearm.Robot.builder("doors", base_mass=100.0, base_inertia=BASE_INERTIA)
    b.add_link("arm", parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.5, 0, 0),
               mass=5.0, inertia=GOOD_INERTIA)
    built = b.build()
    for door in (lambda: loads_toml(dumps_toml(built), "good.toml"),
                 lambda: robot_from_dh("doors", base_mass=100.0, base_inertia=BASE_INERTIA, joint1_origin=(0.5, 0, 0),
                                       links=[dict(name="arm", joint_name="arm_joint", d=0, theta=0, a=1.0, alpha=0,
                                                   com=(-0.5, 0, 0), mass=5.0, inertia=GOOD_INERTIA)])):
        robot = door()
        assert robot.n_dof == 1
        assert robot.total_mass == pytest.approx(105.0)


def test_tiny_axis_is_refused_by_every_door():
    builder = through_builder(axis=TINY_AXIS)
    message = builder_message(builder)
    assert message.startswith("link 'arm': joint axis must be a non-zero vector"), message
    toml = through_toml(axis=TINY_AXIS)
    assert isinstance(toml, spacearm.ModelError)
    assert str(toml).startswith("doors.toml:")
    assert str(toml).splitlines()[0].endswith("invalid model: " + message), str(toml)
    urdf = through_urdf(axis=TINY_AXIS)
    assert isinstance(urdf, spacearm.ModelError)
    assert str(urdf).splitlines()[0].endswith("invalid model: " + message), str(urdf)


@pytest.mark.parametrize("what, bad, rule", [
    ("triangle inequality", dict(inertia=NON_PHYSICAL_INERTIA), "violate the triangle inequality"),
    ("negative mass", dict(mass=-1.0), "mass must be >= 0 kg"),
])
def test_bad_mass_properties_get_the_builders_message_from_every_door(what, bad, rule):
    message = builder_message(through_builder(**bad))
    assert message.startswith("link 'arm': ") and rule in message, message
    # The URDF reader applies the core's rule to each <inertial> before merging fixed links
    # (the triangle inequality excepted, left to the merged body): the same message either way.
    doors = {"toml": through_toml(**bad), "dh": through_dh(**bad), "urdf": through_urdf(**bad)}
    for door, error in doors.items():
        assert isinstance(error, spacearm.ModelError), (door, error)
        assert message in str(error), (door, str(error))


# ---- names: short printable labels (issue 26: NUL characters loaded, a 100 kB name was echoed) --
NAMED_TOML = """
[model]
name = "doors"

[base]
name = "base"
mass = 100.0
inertia = [10.0, 10.0, 10.0]

[[link]]
name = "{name}"
parent = "base"
mass = 5.0
inertia = [0.01, 0.4, 0.4]
com = [0.5, 0.0, 0.0]
[link.joint]
type = "revolute"
origin = [0.5, 0.0, 0.0]
axis = [0.0, 0.0, 1.0]
"""


@pytest.mark.parametrize("name, expected", [
    ("arm\\u0000x", "link name must not contain control characters, got U+0000"),
    ("arm\\nx", "link name must not contain control characters, got U+000A"),
    ("x" * 100_000, "link name must be at most 256 characters, got 100000"),
])
def test_names_are_short_printable_labels_at_every_door(name, expected):
    with pytest.raises(spacearm.ModelFileError, match=re.escape(expected)) as info:
        loads_toml(NAMED_TOML.format(name=name), source="named.toml")
    assert "named.toml:" in str(info.value) and len(str(info.value)) < 1000
    real = name.encode().decode("unicode_escape")
    b = spacearm.Robot.builder("doors", base_mass=100.0, base_inertia=BASE_INERTIA)
    with pytest.raises(spacearm.ModelError, match=re.escape(expected)) as info:
        b.add_link(real, parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0),
                   com=(0.5, 0, 0), mass=5.0, inertia=GOOD_INERTIA)
    assert len(str(info.value)) < 1000
    # the model's own name too
    with pytest.raises(spacearm.ModelError, match="model name must not contain control characters"):
        spacearm.Robot.builder("doors\x00", base_mass=100.0, base_inertia=BASE_INERTIA)
