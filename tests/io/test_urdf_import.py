"""URDF import: frames, merging, re-rooting, limits, and every refusal naming element and line.

The dynamics against Pinocchio are in test_urdf_pinocchio.py; here are the rules of the
conversion (docs/urdf.md) and the error messages.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import spacearm
from spacearm.io.urdf import load_urdf, loads_urdf
from random_urdf import random_urdf

INERTIAL = '<inertial><origin xyz="0.1 0 0"/><mass value="2"/><inertia ixx="0.01" iyy="0.02" izz="0.02"/></inertial>'


def two_link(joint_extra: str = "", joint_type: str = "revolute", limit: str = '<limit lower="-1" upper="2" effort="5" velocity="3"/>') -> str:
    return f"""<robot name="two">
  <link name="a">{INERTIAL}</link>
  <link name="b">{INERTIAL}</link>
  <joint name="j" type="{joint_type}">
    <parent link="a"/><child link="b"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 0 1"/>{limit}{joint_extra}
  </joint>
</robot>
"""


def error_of(text: str, **kwargs) -> str:
    with pytest.raises(spacearm.ModelFileError) as info:
        loads_urdf(text, source="t.urdf", **kwargs)
    return str(info.value)


# ---- frames and mass properties ----------------------------------------------------------------
def test_frames_are_cm_frames():
    r = loads_urdf(two_link())
    d = r.describe()
    link = d["links"][0]
    # base CM at 0.1 on x: the joint (0.3 from the base link origin) is 0.2 from the base CM
    assert np.allclose(link["origin"], [0.2, 0.0, 0.0])
    assert np.allclose(link["com"], [0.1, 0.0, 0.0])
    assert link["limits"] == [-1.0, 2.0, 3.0, 5.0]
    assert d["base"]["name"] == "a" and link["joint"] == "j"


def test_rotated_inertial_frame_is_rotated_into_link_axes():
    rotated = '<inertial><origin xyz="0 0 0" rpy="0 0 1.5707963267948966"/><mass value="2"/><inertia ixx="0.01" iyy="0.03" izz="0.035"/></inertial>'
    r = loads_urdf(f'<robot name="r"><link name="a">{rotated}</link></robot>')
    assert np.allclose(r.describe()["base"]["inertia"], np.diag([0.03, 0.01, 0.035]), atol=1e-15)


def test_fixed_joints_are_merged_with_parallel_axis_theorem_and_kept_as_points():
    text = """<robot name="m">
  <link name="a"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertial></link>
  <link name="tool"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertial></link>
  <joint name="weld" type="fixed"><parent link="a"/><child link="tool"/><origin xyz="0 0 1"/></joint>
</robot>"""
    r = loads_urdf(text)
    d = r.describe()
    assert r.n_bodies == 1 and d["base"]["mass"] == 2.0
    # two unit masses 1 m apart about their midpoint: + 2 * 0.5² about x and y
    assert np.allclose(d["base"]["inertia"], np.diag([0.7, 0.7, 0.2]))
    assert d["points"] == [("tool", "a", [0.0, 0.0, 0.5])] or list(d["points"][0]) == ["tool", "a", [0.0, 0.0, 0.5]]
    assert r.end_effector == "tool"


def test_continuous_joint_has_no_position_limits():
    r = loads_urdf(two_link(joint_type="continuous"))
    assert r.describe()["links"][0]["limits"] == [-np.inf, np.inf, 3.0, 5.0]


def test_prismatic_joint():
    r = loads_urdf(two_link(joint_type="prismatic"))
    assert r.joint_types == ["prismatic"]


@pytest.mark.parametrize("seed", range(4))
def test_base_link_choice_leaves_the_reduced_inertia_unchanged(seed):
    """H* q̇ q̇ / 2 is the kinetic energy at zero momentum: a property of the system and of q
    alone, whichever body is called the base (joints on the re-rooted path keep their q)."""
    text = random_urdf(seed)
    r1 = loads_urdf(text)
    links = [n for n in r1.body_names[1:]]
    r2 = loads_urdf(text, base_link=links[-1])
    assert r2.body_names[0] == links[-1] and r2.n_dof == r1.n_dof
    q = np.random.default_rng(seed).uniform(-1, 1, r1.n_dof)
    names1 = [link["joint"] for link in r1.describe()["links"] if link["type"] != "fixed"]
    names2 = [link["joint"] for link in r2.describe()["links"] if link["type"] != "fixed"]
    perm = [names1.index(n) for n in names2]
    h1 = r1.generalized_inertia(r1.neutral_configuration(q))
    h2 = r2.generalized_inertia(r2.neutral_configuration(q[perm]))
    assert np.allclose(h2, h1[np.ix_(perm, perm)], rtol=1e-11, atol=1e-13 * np.abs(h1).max())


def test_mount_on_a_spacecraft_and_prefix():
    bus = spacearm.RobotBuilder("bus", 500.0, [50, 60, 70], base_name="a").build()
    with pytest.raises(spacearm.ModelFileError, match="prefix"):
        loads_urdf(two_link(), mount_on=bus)
    r = loads_urdf(two_link(), mount_on=bus, at=(1, 0, 0, 0, 0, 0), prefix="arm_")
    assert r.body_names == ["a", "arm_a", "arm_b"] and r.joint_types == ["fixed", "revolute"]
    assert r.total_mass == pytest.approx(504.0)


def test_mount_on_takes_a_model_file_or_a_shipped_name(tmp_path):
    """mount_on as the CLI's --mount-on takes it: a TOML path or a shipped model's name gives the
    same model as the Robot loaded by hand; anything else is a SpacearmTypeError (not a raw
    AttributeError, issue 26)."""
    path = spacearm.examples.path("spacecraft_bus")
    bus = spacearm.io.load_toml(path)
    at = (0.6, 0, 0, 0, 0, 0)
    ref = loads_urdf(two_link(), mount_on=bus, at=at, prefix="arm_")
    x = ref.neutral_configuration(np.array([0.4]))
    for spec in (path, str(path), "spacecraft_bus", "spacecraft_bus.toml"):
        r = loads_urdf(two_link(), mount_on=spec, at=at, prefix="arm_")
        assert r.body_names == ref.body_names
        np.testing.assert_array_equal(r.mass_matrix(x), ref.mass_matrix(x))
    with pytest.raises(spacearm.errors.SpacearmTypeError, match="mount_on must be a spacearm Robot"):
        loads_urdf(two_link(), mount_on=3, at=at)
    with pytest.raises(OSError):
        loads_urdf(two_link(), mount_on=str(tmp_path / "missing.toml"), at=at)


# ---- refusals: element and line ----------------------------------------------------------------
@pytest.mark.parametrize(
    "text,expected",
    [
        (two_link('\n<mimic joint="x"/>'), r"t\.urdf:7: joint 'j': <mimic> joints are not supported"),
        (two_link(joint_type="floating"), r"t\.urdf:4: joint 'j': type 'floating' is not supported"),
        (two_link(joint_type="planar"), r"t\.urdf:4: joint 'j': type 'planar'"),
        (two_link(joint_type="screw"), r"t\.urdf:4: joint 'j': unknown joint type 'screw'"),
        (two_link().replace('<child link="b"/>', '<child link="c"/>'), r"t\.urdf:4: joint 'j': child link 'c' is not defined"),
        (two_link().replace('<axis xyz="0 0 1"/>', '<axis xyz="0 0 0"/>'), r"t\.urdf:4: invalid model: link 'b': joint axis must be a non-zero vector"),
        (two_link().replace('<origin xyz="0.3 0 0"/>', '<origin xyz="0.3 0"/>'), r"t\.urdf:6: joint 'j': <origin xyz=\"0.3 0\"> must be 3 numbers"),
        (two_link().replace('<origin xyz="0.3 0 0"/>', '<origin xyz="0.3 nan 0"/>'), r"must be finite"),
        (two_link(limit='<limit lower="2" upper="1"/>'), r"t\.urdf:4: invalid model: joint 'j' of link 'b': position limits must satisfy lower <= upper, got \[2, 1\]"),
        (two_link().replace("</robot>", '<link name="c"/></robot>'), r"t\.urdf:8: the links do not form one tree"),
        (two_link().replace("</robot>", '<link name="a"/></robot>'), r"t\.urdf:8: link name 'a' is used twice \(first on line 2\)"),
        (two_link().replace('<inertia ixx="0.01"', '<inertia ixx="x"', 1), r"t\.urdf:2: link 'a': <inertia ixx=\"x\"> must be a number"),
        (two_link().replace('<mass value="2"/>', '<mass value="-2"/>', 2), r"t\.urdf:2: invalid model: link 'a': mass must be >= 0 kg, got -2"),
        ("<robot name='x'><link name='a'/>", r"t\.urdf:1:\d+: not well-formed XML"),
        ("<model/>", r"t\.urdf:1: the root element must be <robot>"),
        ("<robot name='x'/>", r"t\.urdf:1: the URDF has no <link>"),
    ],
)
def test_refusals_name_element_and_line(text, expected):
    assert error_of(text) == error_of(text)  # deterministic
    import re

    assert re.search(expected, error_of(text)), error_of(text)


def test_closed_loop_is_refused():
    text = f"""<robot name="loop">
  <link name="a">{INERTIAL}</link>
  <link name="b">{INERTIAL}</link>
  <link name="c">{INERTIAL}</link>
  <joint name="ab" type="revolute"><parent link="a"/><child link="b"/></joint>
  <joint name="bc" type="revolute"><parent link="b"/><child link="c"/></joint>
  <joint name="ac" type="revolute"><parent link="a"/><child link="c"/></joint>
</robot>"""
    assert "t.urdf:7: joint 'ac': link 'c' is already the child of joint 'bc' (line 6): closed kinematic loops" in error_of(text)
    cycle = text.replace('<joint name="ac" type="revolute"><parent link="a"/><child link="c"/></joint>',
                         '<joint name="ca" type="revolute"><parent link="c"/><child link="a"/></joint>')
    assert "closed loop" in error_of(cycle)


def test_massless_moving_subtree_is_refused():
    text = two_link().replace(f'<link name="b">{INERTIAL}</link>', '<link name="b"/>')
    assert "t.urdf:4: joint 'j' (revolute) moves link 'b', but neither it nor anything attached beyond it has an <inertial>" in error_of(text)


def test_massless_free_flying_base_is_refused_with_a_hint():
    text = two_link().replace(f'<link name="a">{INERTIAL}</link>', '<link name="a"/>')
    message = error_of(text)
    assert message.startswith("t.urdf:2: link 'a' is the free-flying base") and "mount_on" in message


def test_mimic_can_be_loaded_as_independent():
    r = loads_urdf(two_link('<mimic joint="x"/>'), mimic="independent")
    assert r.n_dof == 1


# ---- the parser does not expand entities ---------------------------------------------------------
@pytest.mark.parametrize(
    "doctype",
    [
        '<!DOCTYPE robot [<!ENTITY xxe SYSTEM "file:///etc/passwd">]>',
        '<!DOCTYPE robot [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">]>',
        '<!DOCTYPE robot SYSTEM "http://example.com/robot.dtd">',
    ],
)
def test_entities_and_external_references_are_refused(doctype):
    text = f'<?xml version="1.0"?>\n{doctype}\n<robot name="&xxe;"><link name="a">{INERTIAL}</link></robot>'
    message = error_of(text)
    assert "t.urdf:" in message and ("unsafe XML" in message or "not well-formed" in message)


# ---- files and the CLI ---------------------------------------------------------------------------
def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "spacearm", *args], capture_output=True, text=True)


def test_load_file_and_cli(tmp_path):
    path = tmp_path / "two.urdf"
    path.write_text(two_link())
    assert load_urdf(path).n_dof == 1
    out = run_cli("inspect", str(path))
    assert out.returncode == 0 and "model 'two'" in out.stdout, out.stderr
    out = run_cli("inspect", str(path), "--mount-on", "spatial6", "--prefix", "arm_", "--at", "0.6,0,0.4,0,0,0")
    assert out.returncode == 0 and "arm_b" in out.stdout, out.stderr
    assert run_cli("inspect", str(path), "--at", "1,2").returncode == 2
    assert run_cli("inspect", "spatial6", "--mount-on", "planar4").returncode == 2
    bad = tmp_path / "bad.urdf"
    bad.write_text(two_link(joint_type="floating"))
    out = run_cli("inspect", str(bad))
    assert out.returncode == 2 and "bad.urdf:4: joint 'j'" in out.stderr
