"""CMGs in URDF (docs/urdf.md, "Control-moment gyros"): the ``<spacearm><cmg>`` extension element
read, the exporter's gimbal and rotor links read back as the same CMGs, and bad elements refused
with the file, the line, the element and the attribute."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from cmg_models import J_S, pyramid_axes, pyramid_sat
from spacearm.errors import ModelFileError
from spacearm.io.urdf import loads_urdf
from spacearm.io.urdf_export import to_urdf


def _vec(v) -> str:
    return " ".join(repr(float(x)) for x in v)


def _cmg_elements(variable_speed: bool) -> str:
    """The pyramid of ``pyramid_sat`` as ``<spacearm><cmg>`` elements on the root link."""
    out = []
    for i, (g, s) in enumerate(zip(*pyramid_axes())):
        speed = ' variable_speed="true"' if variable_speed else ""
        out.append(f'<cmg name="cmg{i + 1}" parent="base" position="{_vec(0.3 * np.cross(g, s))}" gimbal_axis="{_vec(g)}" '
                   f'spin_axis="{_vec(s)}" rotor_inertia="{J_S!r}" gimbal_inertia="0.02 0.015 0.018" rotor_mass="3" '
                   f'gimbal_mass="1.5" max_wheel_speed="800"{speed}/>')
    return "<spacearm>\n    " + "\n    ".join(out) + "\n  </spacearm>"


def _hand_written(variable_speed: bool) -> str:
    """``pyramid_sat`` written by hand: the bus, the CMGs as extension elements, then the arm
    (in the builder's link order, which is depth-first: the importer numbers depth-first)."""
    return f'''<robot name="cmg-sat">
  <link name="base"><inertial><mass value="200"/><inertia ixx="30" iyy="34" izz="38"/></inertial></link>
  {_cmg_elements(variable_speed)}
  <link name="upper"><inertial><origin xyz="0.5 0 0"/><mass value="6"/><inertia ixx="0.02" iyy="0.5" izz="0.5"/></inertial></link>
  <joint name="upper_joint" type="continuous"><parent link="base"/><child link="upper"/><origin xyz="0.8 0 0.2"/><axis xyz="0 1 0"/></joint>
  <link name="fore"><inertial><origin xyz="0.4 0 0"/><mass value="4"/><inertia ixx="0.01" iyy="0.2" izz="0.2"/></inertial></link>
  <joint name="fore_joint" type="continuous"><parent link="upper"/><child link="fore"/><origin xyz="1.5 0 0"/><axis xyz="0 0 1"/></joint>
</robot>'''


def _states(robot, n=3):
    rng = np.random.default_rng(34)
    for _ in range(n):
        quat = rng.normal(size=4)
        yield robot.neutral_configuration(rng.uniform(-2, 2, robot.n_dof), r0=rng.normal(size=3), quat0=quat / np.linalg.norm(quat))


def _same_cmg_dofs(a: dict, b: dict) -> None:
    assert list(a) == list(b)
    for name in a:
        for key, value in a[name].items():
            np.testing.assert_array_equal(np.asarray(b[name][key]), np.asarray(value), err_msg=f"{name}.{key}")


def _same_dynamics(r1, r2) -> None:
    """H, H* and J* (of the forearm's CM) at random states, to 1e-14 relative."""
    assert r2.n_dof == r1.n_dof and r2.joint_names == r1.joint_names
    checked = 0
    for x in _states(r1):
        for f in (r1.mass_matrix, r1.generalized_inertia, lambda x: r1.generalized_jacobian(x, "fore")):
            a = f(x)
            b = {r1.mass_matrix: r2.mass_matrix, r1.generalized_inertia: r2.generalized_inertia}.get(f, lambda x: r2.generalized_jacobian(x, "fore"))(x)
            assert np.linalg.norm(a) > 1.0  # not an empty model
            assert np.linalg.norm(b - a) <= 1e-14 * np.linalg.norm(a)
            checked += 1
    assert checked == 9


@pytest.mark.parametrize("variable_speed", [False, True], ids=["sgcmg", "vscmg"])
def test_builder_urdf_robot_keeps_the_cmgs(variable_speed):
    r1 = pyramid_sat(variable_speed=variable_speed)
    text = to_urdf(r1)
    # The exporter writes each CMG as its gimbal and rotor links (readable by every URDF tool);
    # a single-gimbal CMG's free rotor is the passive spin joint of the <spacearm> joint element.
    assert text.count('<spacearm actuated="false" />') == (0 if variable_speed else 4)
    r2 = loads_urdf(text)
    assert len(r2.cmg_dofs) == 4 and [c["variable_speed"] for c in r2.cmg_dofs.values()] == [variable_speed] * 4
    _same_cmg_dofs(r1.cmg_dofs, r2.cmg_dofs)
    _same_dynamics(r1, r2)
    assert r2.arm_dofs == r1.arm_dofs == [8, 9]


@pytest.mark.parametrize("variable_speed", [False, True], ids=["sgcmg", "vscmg"])
def test_extension_element_gives_the_builders_cmgs(variable_speed):
    r1 = pyramid_sat(variable_speed=variable_speed)
    r2 = loads_urdf(_hand_written(variable_speed))
    _same_cmg_dofs(r1.cmg_dofs, r2.cmg_dofs)
    _same_dynamics(r1, r2)
    # The closed form of the pyramid: the gimbal axes of Wie's cluster, J_s, the rotors' dofs.
    g, s = pyramid_axes()
    for i, c in enumerate(r2.cmg_dofs.values()):
        assert np.allclose(c["gimbal_axis"], g[i], atol=1e-15) and np.allclose(c["spin_axis"], s[i], atol=1e-15)
        assert c["rotor_inertia"] == J_S and (c["gimbal"], c["rotor"]) == (2 * i, 2 * i + 1)
    # ... and a run from it spins the rotors (u0 from cmg_velocity, the wheel speed as state).
    u0 = r2.cmg_velocity(300.0)
    assert u0[6 + np.array([c["rotor"] for c in r2.cmg_dofs.values()])].tolist() == [300.0] * 4


def test_element_on_an_arm_link_with_a_rotated_frame():
    """A CMG whose parent link frame is turned: position and axes are in that URDF frame."""
    text = '''<robot name="r">
  <link name="bus"><inertial><mass value="50"/><inertia ixx="5" iyy="6" izz="7"/></inertial></link>
  <link name="arm"><inertial><origin xyz="0.2 0 0"/><mass value="3"/><inertia ixx="0.1" iyy="0.2" izz="0.2"/></inertial></link>
  <joint name="arm_joint" type="continuous"><parent link="bus"/><child link="arm"/><origin xyz="0.5 0 0" rpy="0 0 1.5707963267948966"/><axis xyz="0 0 1"/></joint>
  <spacearm><cmg name="c" parent="arm" position="0.4 0 0" gimbal_axis="0 0 1" spin_axis="1 0 0" rotor_inertia="0.02"/></spacearm>
</robot>'''
    r = loads_urdf(text)
    c = r.cmg_dofs["c"]
    assert (c["gimbal"], c["rotor"]) == (1, 2) and not c["variable_speed"]
    assert np.array_equal(c["gimbal_axis"], [0.0, 0.0, 1.0]) and np.array_equal(c["spin_axis"], [1.0, 0.0, 0.0])
    # The gimbal joint (the CMG's CM) sits 0.4 m along the arm frame's x, which the joint's yaw
    # of 90 degrees turns onto the bus's y: at (0.5, 0.4, 0) from the bus CM at q = 0, and the
    # rotor's momentum along the bus's y.
    x = r.neutral_configuration(np.zeros(3))
    assert np.allclose(r.point_position(x, "c"), [0.5, 0.4, 0.0], rtol=0, atol=1e-15)
    u = r.cmg_velocity(100.0)
    assert np.allclose(r.momentum(x, u).L_com, [0.0, 0.02 * 100.0, 0.0], rtol=0, atol=1e-13)


BAD = [
    ('spin_axis="0 1 0"', 'spin_axis="0 1 1"', ["<spacearm><cmg name=\"cmg1\">", "perpendicular"]),
    ('rotor_inertia="0.05"', 'rotor_inertia="-1"', ["cmg1", "rotor_inertia", "> 0"]),
    ('rotor_inertia="0.05"', 'rotor_inertia="fast"', ["<cmg rotor_inertia=\"fast\"> must be a number"]),
    ('rotor_mass="3"', 'rotor_mass="-3"', ["rotor_mass", ">= 0"]),
    ('gimbal_inertia="0.02 0.015 0.018"', 'gimbal_inertia="0.02 0.015"', ["gimbal_inertia", "must be 3 numbers"]),
    ('max_wheel_speed="800"', 'max_wheel_speed="800" max_wheel_torque="1"', ["max_wheel_torque needs variable_speed"]),
    ('max_wheel_speed="800"', 'max_wheel_speed="800" variable_speed="yes"', ["variable_speed must be 'true' or 'false'"]),
    ('max_wheel_speed="800"', 'max_wheel_speed="800" wheel_speed="300"', ["'wheel_speed' is not a model parameter", "cmg_velocity"]),
    ('max_wheel_speed="800"', 'max_wheel_speed="800" spin="300"', ["unknown attribute(s) ['spin']", "rotor_inertia"]),
    (' parent="base"', "", ["needs a non-empty 'parent' attribute"]),
    (' spin_axis="0.0 1.0 0.0"', "", ["needs a 'spin_axis' attribute"]),
    ('parent="base"', 'parent="bus"', ["joint 'cmg1_gimbal'", "parent link 'bus' is not defined"]),
    ('name="cmg2"', 'name="cmg1"', ["link name 'cmg1' is used twice"]),
]


@pytest.mark.parametrize("old, new, words", BAD, ids=[b[1] or b[0] for b in BAD])
def test_bad_elements_name_the_line_element_and_attribute(old, new, words):
    text = _hand_written(False).replace('spin_axis="0.0 1.0 0.0"', 'spin_axis="0 1 0"', 1)
    old = old.replace('spin_axis="0.0 1.0 0.0"', 'spin_axis="0 1 0"')
    assert old in text
    with pytest.raises(ModelFileError) as info:
        loads_urdf(text.replace(old, new, 1), source="sat.urdf")
    message = str(info.value)
    line = 4 if new != 'name="cmg1"' else 5  # the <cmg> elements are lines 4 to 7
    assert message.startswith(f"sat.urdf:{line}:"), message
    for w in words:
        assert w in message, message


def test_unknown_robot_level_spacearm_child_is_refused():
    text = _hand_written(False).replace("<spacearm>", '<spacearm>\n    <wheel name="w"/>')
    with pytest.raises(ModelFileError, match=r":4: <spacearm> at the robot level takes <cmg> elements, got <wheel>"):
        loads_urdf(text, source="sat.urdf")


@pytest.mark.parametrize("variable_speed", [False, True], ids=["sgcmg", "vscmg"])
def test_the_exporter_writes_the_extension_element_on_request(variable_speed):
    r1 = pyramid_sat(variable_speed=variable_speed)
    text = to_urdf(r1, cmgs="element")
    assert text.count("<cmg ") == 4 and "cmg1_rotor" not in text and "cmg1_spin" not in text
    r2 = loads_urdf(text)
    _same_cmg_dofs(r1.cmg_dofs, r2.cmg_dofs)
    _same_dynamics(r1, r2)
    # ... and the element read back is written again as the element (its moments to rounding:
    # they are read off the inertia tensors the core recomposed from them).
    again = to_urdf(r2, cmgs="element")
    assert again.count("<cmg ") == 4
    _same_dynamics(r2, loads_urdf(again))


def test_a_cmg_the_element_cannot_describe_is_written_as_links():
    """A unit turned about its gimbal joint (control.perturbed_cmgs: its gimbal frame is rotated)
    is not what <cmg> describes: its links are written, and it is still a CMG when read back."""
    r1 = spacearm.control.perturbed_cmgs(pyramid_sat(), 1.0, [[0.0, 0.0, 0.01]] + [[0.0, 0.0, 0.0]] * 3)
    text = to_urdf(r1, cmgs="element")
    assert text.count("<cmg ") == 3 and '<link name="cmg1_rotor">' in text
    r2 = loads_urdf(text)
    assert list(r2.cmg_dofs) == list(r1.cmg_dofs)
    np.testing.assert_allclose(r2.cmg_dofs["cmg1"]["gimbal_axis"], r1.cmg_dofs["cmg1"]["gimbal_axis"], rtol=0, atol=1e-15)
    _same_dynamics(r1, r2)
    with pytest.raises(spacearm.errors.ArgumentError, match="cmgs must be one of"):
        to_urdf(r1, cmgs="elements")
