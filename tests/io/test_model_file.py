"""TOML model files (spacearm.io.model_file, docs/model-format.md): the example files equal the
presets, round trips are exact, every bad input raises a spacearm error that says where and
what, and no mutated document makes anything else come out."""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import spacearm
from spacearm import presets
from spacearm.io import model_file
from spacearm.io.model_file import dumps_toml, load_toml, loads_toml, save_toml
from spacearm.rotations import quat_from_axis_angle

ROOT = Path(__file__).resolve().parents[2]
MODELS = Path(spacearm.examples.path("spatial6")).parent  # the shipped model files

DEMO = """\
[model]
name = "demo"
end_effector = "tip"
initial_q = [0.3, 0.1]

[base]
mass = 100
inertia = { ixx = 10, iyy = 12, izz = 14, ixy = 0.5 }

[[link]]
name = "arm"
parent = "base"
com = [0.5, 0.0, 0.0]
mass = 5.0
inertia = [0.01, 0.4, 0.4]
joint = { type = "revolute", origin = [0.5, 0.0, 0.0], axis = [0.0, 0.0, 1.0], limits = { lower = -1.0, upper = 1.0 } }

[[link]]
name = "slider"
parent = "arm"
com = [0.1, 0.0, 0.0]
mass = 1.0
inertia = [[0.01, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.02]]
[link.joint]
type = "prismatic"
name = "slide"
origin = [0.5, 0.0, 0.0]
rotation = [0.0, 0.0, 0.7071067811865476, 0.7071067811865476]
axis = [1.0, 0.0, 0.0]

[[point]]
name = "tip"
body = "slider"
offset = [0.2, 0.0, 0.0]
"""


def line_of(text: str, needle: str) -> int:
    """1-based line of the first occurrence of needle."""
    return text[: text.index(needle)].count("\n") + 1


def random_configuration(robot, rng):
    quat = rng.normal(size=4)
    return robot.neutral_configuration(q=rng.uniform(-math.pi, math.pi, robot.n_dof), r0=rng.normal(size=3),
                                       quat0=quat / np.linalg.norm(quat))


# ---- the example model files -------------------------------------------------------------------------


@pytest.mark.parametrize("name", presets.NAMES)
def test_example_files_are_the_presets(name):
    robot = spacearm.io.load_toml(MODELS / f"{name}.toml")
    preset = presets.get(name)
    assert robot.name == name and robot.end_effector == preset.end_effector
    np.testing.assert_array_equal(robot.initial_q, preset.initial_q)
    rng = np.random.default_rng(11)
    for _ in range(25):
        x = random_configuration(preset, rng)
        np.testing.assert_allclose(robot.mass_matrix(x), preset.mass_matrix(x), rtol=0, atol=1e-12)
        np.testing.assert_allclose(robot.point_position(x), preset.point_position(x), rtol=0, atol=1e-12)


def test_reading_a_valid_document():
    robot = loads_toml(DEMO, "demo.toml")
    d = robot.describe()
    assert robot.n_dof == 2 and robot.end_effector == "tip"
    assert d["base"]["inertia"][0][1] == 0.5 and d["base"]["inertia"][1][0] == 0.5
    arm, slider = d["links"]
    assert arm["joint"] == "arm_joint" and arm["limits"] == [-1.0, 1.0, math.inf, math.inf]
    assert slider["type"] == "prismatic" and slider["joint"] == "slide"
    np.testing.assert_allclose(slider["rotation"], quat_from_axis_angle([0, 0, 1], math.pi / 2), atol=1e-15)
    np.testing.assert_array_equal(robot.initial_q, [0.3, 0.1])


def test_rpy_and_quaternion_give_the_same_model():
    a = loads_toml(DEMO)
    b = loads_toml(DEMO.replace("rotation = [0.0, 0.0, 0.7071067811865476, 0.7071067811865476]",
                                "rpy = [0.0, 0.0, 1.5707963267948966]"))
    x = random_configuration(a, np.random.default_rng(0))
    np.testing.assert_allclose(a.mass_matrix(x), b.mass_matrix(x), rtol=0, atol=1e-13)


def test_top_level_end_effector_and_initial_q_are_accepted():
    text = DEMO.replace('end_effector = "tip"\ninitial_q = [0.3, 0.1]\n', "")
    robot = loads_toml('end_effector = "tip"\ninitial_q = [0.3, 0.1]\n' + text)
    assert robot.end_effector == "tip"
    np.testing.assert_array_equal(robot.initial_q, [0.3, 0.1])


def test_dh_section():
    rows = "".join(
        "[[dh.link]]\nd = 0.0\ntheta = 0.0\na = 1.0\nalpha = 0.0\ncom = [-0.5, 0.0, 0.0]\nmass = 10.0\n"
        "inertia = [0.004166666666666667, 0.8354166666666666, 0.8354166666666666]\n\n" for _ in range(4))
    text = (
        '[model]\nname = "planar4"\ninitial_q = [0.7853981633974483, -0.7853981633974483, -0.7853981633974483, '
        "0.7853981633974483]\n\n[base]\nmass = 100.0\ninertia = [4.1667, 4.1667, 4.1667]\n\n"
        '[dh]\nconvention = "classic"\njoint1_origin = [0.25, 0.0, 0.0]\n\n' + rows
        + '[[point]]\nname = "elbow"\nbody = "link2"\noffset = [0.5, 0.0, 0.0]\n'
    )
    robot = loads_toml(text, "dh.toml")
    preset = presets.planar4()
    assert robot.end_effector == "end_effector" and "elbow" in robot.point_names
    rng = np.random.default_rng(3)
    for _ in range(10):
        x = random_configuration(preset, rng)
        np.testing.assert_allclose(robot.mass_matrix(x), preset.mass_matrix(x), rtol=0, atol=1e-12)
    paper = text.replace('"classic"', '"paper"').replace("d = 0.0\n", "").replace("a = 1.0\n", "").replace(
        "com = [-0.5, 0.0, 0.0]", "joint_to_com = [0.5, 0.0, 0.0]\ncom_to_next = [0.5, 0.0, 0.0]")
    robot = loads_toml(paper, "paper.toml")
    x = random_configuration(preset, rng)
    np.testing.assert_allclose(robot.mass_matrix(x), preset.mass_matrix(x), rtol=0, atol=1e-12)
    with pytest.raises(spacearm.ModelFileError, match=r"dh\.toml:\d+:\d+: DH link 1: `joint_to_com` does not belong"):
        loads_toml(text.replace("a = 1.0\n", "a = 1.0\njoint_to_com = [0.5, 0.0, 0.0]\n", 1), "dh.toml")
    with pytest.raises(spacearm.ModelFileError, match="unknown variant `craig`"):
        loads_toml(text.replace('"classic"', '"craig"'), "dh.toml")


# ---- round trips ---------------------------------------------------------------------------------------


def random_robot(rng, n_links):
    b = spacearm.Robot.builder(f"random-{n_links}", base_mass=rng.uniform(50, 500), base_inertia=[8.0, 9.0, 10.0])
    names = ["base"]
    kinds = []
    for k in range(n_links):
        kind = rng.choice(["revolute", "revolute", "prismatic", "fixed"]) if k else "revolute"
        principal = rng.uniform(0.1, 1.0, 3)
        inertia = np.diag([principal[1] + principal[2], principal[0] + principal[2], principal[0] + principal[1]])
        axis = rng.normal(size=3)
        quat = rng.normal(size=4)
        limits = {"lower": -rng.uniform(0, 3), "upper": rng.uniform(0, 3)} if rng.random() < 0.5 else None
        b.add_link(f"l{k}", parent=names[rng.integers(len(names))], joint=str(kind), axis=axis,
                   origin=rng.normal(size=3), rotation=quat / np.linalg.norm(quat), com=rng.normal(size=3),
                   mass=rng.uniform(0.1, 20), inertia=inertia, limits=limits)
        names.append(f"l{k}")
        kinds.append(kind)
    b.add_point("tip", body=names[-1], offset=rng.normal(size=3))
    b.set_end_effector("tip")
    b.set_initial_q(rng.normal(size=sum(k != "fixed" for k in kinds)))
    return b.build()


@pytest.mark.parametrize("seed", range(8))
def test_round_trip_is_exact(seed):
    rng = np.random.default_rng(seed)
    robot = random_robot(rng, 1 + seed)
    text = dumps_toml(robot)
    back = loads_toml(text, "round.toml")
    assert back.describe() == robot.describe()
    assert dumps_toml(back) == text
    x = random_configuration(robot, rng)
    np.testing.assert_array_equal(back.mass_matrix(x), robot.mass_matrix(x))


@pytest.mark.parametrize("name", presets.NAMES)
def test_presets_round_trip(name):
    robot = presets.get(name)
    assert loads_toml(dumps_toml(robot)).describe() == robot.describe()


def test_save_and_load(tmp_path):
    robot = loads_toml(DEMO)
    path = save_toml(robot, tmp_path / "demo.toml")
    assert path == tmp_path / "demo.toml"
    assert path.read_text(encoding="utf-8") == dumps_toml(robot)
    assert load_toml(path).describe() == robot.describe()
    assert load_toml(str(path)).describe() == robot.describe()
    # Replacing an existing file keeps its permission bits and leaves no temporary file.
    os.chmod(path, 0o640)
    save_toml(presets.planar4(), path)
    assert (os.stat(path).st_mode & 0o777) == 0o640
    assert load_toml(path).name == "planar4"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demo.toml"]


def test_save_is_atomic(tmp_path, monkeypatch):
    path = tmp_path / "model.toml"
    save_toml(presets.planar4(), path)
    before = path.read_bytes()

    def failing_replace(src, dst):
        raise OSError("disk full (simulated)")

    monkeypatch.setattr(model_file.os, "replace", failing_replace)
    with pytest.raises(OSError, match="simulated"):
        save_toml(presets.spatial6(), path)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["model.toml"]


def test_load_errors_name_the_file(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text(DEMO.replace("mass = 5.0", "mass = -5.0"), encoding="utf-8")
    with pytest.raises(spacearm.ModelFileError) as info:
        load_toml(path)
    assert str(info.value).startswith(f"{path}:{line_of(DEMO, 'mass = 5.0')}:8: ")
    with pytest.raises(FileNotFoundError):
        load_toml(tmp_path / "missing.toml")
    path.write_bytes(b'[model]\nname = "\xff"\n')
    with pytest.raises(spacearm.ModelFileError, match="not valid UTF-8"):
        load_toml(path)


def test_dumps_rejects_non_robots():
    with pytest.raises(TypeError):
        dumps_toml("planar4")


# ---- every bad input -----------------------------------------------------------------------------------

BAD = [
    # (what, edit of DEMO, line of the error, pattern)
    ("unknown key", ("mass = 5.0", "mas = 5.0"), "mas = 5.0",
     r"unknown field `mas`, expected one of `name`, `parent`, `joint`, `com`, `mass`, `inertia`"),
    ("unknown table", ("[[point]]", "[[points]]"), "[[points]]", r"unknown field `points`"),
    ("unknown joint key", ('type = "prismatic"', 'type = "prismatic"\nspeed = 1'), "speed = 1", r"unknown field `speed`"),
    ("wrong type", ("mass = 5.0", 'mass = "five"'), 'mass = "five"', r"invalid type: string \"five\", expected f64"),
    ("wrong vector length", ("offset = [0.2, 0.0, 0.0]", "offset = [0.2, 0.0]"), "offset = [0.2, 0.0]",
     r"invalid length 2, expected an array of length 3"),
    ("missing field", ("com = [0.5, 0.0, 0.0]\n", ""), None, r"missing field `com`"),
    ("bad joint type", ('type = "prismatic"', 'type = "hinge"'), 'type = "hinge"', r"unknown variant `hinge`"),
    ("bad parent", ('parent = "arm"', 'parent = "elbow"'), 'parent = "elbow"',
     r"link 'slider': parent 'elbow' is not a body of the model; bodies defined so far: \[\"base\", \"arm\"\]"),
    ("cycle", ('parent = "base"', 'parent = "slider"'), 'parent = "slider"',
     r"link 'arm': the parents form a cycle 'arm' -> 'slider' -> 'arm'"),
    ("own parent", ('parent = "base"', 'parent = "arm"'), 'parent = "arm"', r"link 'arm' cannot be its own parent"),
    ("negative mass", ("mass = 5.0", "mass = -5.0"), "mass = -5.0", r"link 'arm': mass must be >= 0 kg, got -5"),
    ("zero base mass", ("mass = 100", "mass = 0"), "mass = 0", r"base 'base': mass must be > 0 kg"),
    ("triangle inequality", ("inertia = [0.01, 0.4, 0.4]", "inertia = [0.01, 0.4, 1.4]"), "inertia = [0.01, 0.4, 1.4]",
     r"link 'arm': principal moments .* violate the triangle inequality"),
    ("negative inertia", ("inertia = [0.01, 0.4, 0.4]", "inertia = [-0.01, 0.4, 0.4]"), "inertia = [-0.01",
     r"link 'arm': inertia tensor must be positive semi-definite"),
    ("asymmetric inertia", ("[0.0, 0.02, 0.0], [0.0, 0.0, 0.02]]", "[0.005, 0.02, 0.0], [0.0, 0.0, 0.02]]"),
     "inertia = [[0.01", r"link 'slider': inertia tensor must be symmetric"),
    ("inertia shape", ("inertia = [0.01, 0.4, 0.4]", "inertia = [0.01, 0.4]"), "inertia = [0.01, 0.4]",
     r"link 'arm': inertia must be \[ixx, iyy, izz\], a 3x3 array"),
    ("inertia table key", ("ixy = 0.5", "ixy = 0.5, jxx = 1"), "inertia = {", r"unknown inertia key `jxx`"),
    ("zero axis", ("axis = [0.0, 0.0, 1.0]", "axis = [0.0, 0.0, 0.0]"), "axis = [0.0, 0.0, 0.0]",
     r"link 'arm': joint axis must be a non-zero vector"),
    ("non-unit quaternion", ("rotation = [0.0, 0.0, 0.7071067811865476, 0.7071067811865476]", "rotation = [0.0, 0.0, 0.0, 2.0]"),
     "rotation = [0.0, 0.0, 0.0, 2.0]", r"link 'slider': joint rotation must be a unit quaternion .* got norm 2"),
    ("rotation and rpy", ("axis = [1.0, 0.0, 0.0]", "axis = [1.0, 0.0, 0.0]\nrpy = [0.0, 0.0, 0.0]"),
     "rotation = [0.0, 0.0, 0.7", r"link 'slider': give `rotation` or `rpy`, not both"),
    ("missing axis", (", axis = [0.0, 0.0, 1.0]", ""), "joint = {", r"link 'arm': a revolute joint needs an `axis`"),
    ("duplicate link", ('name = "slider"', 'name = "arm"'), 'name = "arm"\nparent = "arm"', r"body name 'arm' is used twice"),
    ("duplicate joint", ('name = "slide"', 'name = "arm_joint"'), 'name = "arm_joint"',
     r"joint name 'arm_joint' is used twice \(first on line 16\)"),
    ("bad limits", ("lower = -1.0, upper = 1.0", "lower = 1.0, upper = -1.0"), "joint = {",
     r"joint 'arm_joint' of link 'arm': position limits must satisfy lower <= upper"),
    ("initial_q length", ("initial_q = [0.3, 0.1]", "initial_q = [0.3]"), "initial_q",
     r"initial_q must have N = 2 entries \(one per moving joint\), got 1"),
    ("unknown end effector", ('end_effector = "tip"', 'end_effector = "hand"'), "end_effector",
     r"end effector 'hand' is not a defined point; points: \[\"tip\"\]"),
    ("point on unknown body", ('body = "slider"', 'body = "hand"'), 'body = "hand"',
     r"point 'tip': body 'hand' is not a body of the model"),
    ("point name clash", ('name = "tip"', 'name = "arm"'), 'name = "arm"\nbody', r"point name 'arm' is already used"),
    ("syntax error", ("mass = 5.0", "mass = = 5.0"), "mass = = 5.0", r"string values must be quoted|invalid|expected"),
    ("unclosed table header", ("[base]", "[base"), "[base", r"."),
    ("non-finite", ("com = [0.5, 0.0, 0.0]", "com = [nan, 0.0, 0.0]"), "com = [nan", r"link 'arm': com must be finite"),
    ("format version", ('name = "demo"', 'name = "demo"\nformat_version = 2'), "format_version = 2",
     r"format_version 2 is not supported"),
]


@pytest.mark.parametrize("what, edit, at, pattern", BAD, ids=[b[0] for b in BAD])
def test_bad_input_raises_model_file_error(what, edit, at, pattern):
    old, new = edit
    assert old in DEMO
    text = DEMO.replace(old, new, 1)
    with pytest.raises(spacearm.ModelFileError) as info:
        loads_toml(text, "model.toml")
    message = str(info.value)
    assert isinstance(info.value, spacearm.ModelError) and isinstance(info.value, ValueError)
    # Always: source:line:column:, then the message, then the line with a caret.
    location = re.match(r"model\.toml:(\d+):(\d+): ", message)
    assert location, message
    if at is not None:
        assert int(location.group(1)) == line_of(text, at), message
    assert re.search(pattern, message), message
    assert "^" in message.splitlines()[-1], message


def test_error_message_example():
    """The example in docs/model-format.md."""
    text = DEMO.replace("mass = 5.0", "mass = -5.0")
    with pytest.raises(spacearm.ModelFileError) as info:
        loads_toml(text, "arm.toml")
    assert str(info.value) == (
        "arm.toml:14:8: invalid model: link 'arm': mass must be >= 0 kg, got -5\n"
        " 14 | mass = -5.0\n"
        "    |        ^"
    )


def test_forward_reference_is_explained():
    text = DEMO.replace('parent = "base"', 'parent = "slider"').replace('parent = "arm"', 'parent = "base"')
    with pytest.raises(spacearm.ModelFileError, match=r"link 'arm': parent 'slider' is defined later in the file \(line 18\); "
                                                      r"list every link after its parent"):
        loads_toml(text, "order.toml")


def test_loads_rejects_non_text():
    with pytest.raises(TypeError):
        loads_toml(12)


# ---- fuzzing: only spacearm errors (or a model) come out -----------------------------------------------

TOKENS = ["", "0", "-1", "1e400", "-1e308", "nan", "inf", "1e100", "\"", "'", "[", "]", "{", "}", "=", ",", "\n",
          "[[link]]", "[link.joint]", "[[point]]", "[dh]", "[[dh.link]]", "#", "é", "\x00", "true", "1979-05-27",
          'type = "fixed"', 'type = "prismatic"', 'parent = "base"', "axis = [0, 0, 0]", "mass = -1",
          "inertia = [1, 1, 3]", 'convention = "paper"']
BASE_TEXTS = [DEMO, dumps_toml(presets.spatial6()), (MODELS / "planar4.toml").read_text(encoding="utf-8")]


def check_only_spacearm_errors(text):
    try:
        robot = loads_toml(text, "fuzz.toml")
    except spacearm.SpacearmError as exc:
        assert str(exc).startswith("fuzz.toml"), str(exc)
    else:
        # Whatever loads is a valid model that survives a round trip.
        assert loads_toml(dumps_toml(robot)).describe() == robot.describe()


@st.composite
def mutated_documents(draw):
    chars = list(draw(st.sampled_from(BASE_TEXTS)))
    for _ in range(draw(st.integers(1, 4))):
        pos = draw(st.integers(0, len(chars)))
        op = draw(st.integers(0, 3))
        if op == 0:
            del chars[pos:pos + draw(st.integers(1, 60))]
        elif op == 1:
            chars[pos:pos] = list(draw(st.sampled_from(TOKENS)))
        elif op == 2:
            chars[pos:pos] = list(draw(st.text(max_size=8)))
        else:
            chars[pos:pos] = list(repr(draw(st.floats(allow_nan=True, allow_infinity=True))))
    return "".join(chars)


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_documents())
def test_mutated_documents_raise_only_spacearm_errors(text):
    check_only_spacearm_errors(text)


@settings(max_examples=200, deadline=None)
@given(st.text(max_size=200))
def test_random_text_raises_only_spacearm_errors(text):
    check_only_spacearm_errors(text)


NUMBER_SITES = ["mass = 5.0", "com = [0.5, 0.0, 0.0]", "inertia = [0.01, 0.4, 0.4]", "axis = [0.0, 0.0, 1.0]",
                "lower = -1.0", "ixx = 10", "mass = 100", "offset = [0.2, 0.0, 0.0]", "0.7071067811865476"]


@settings(max_examples=200, deadline=None)
@given(st.floats(allow_nan=True, allow_infinity=True), st.sampled_from(NUMBER_SITES))
def test_any_number_anywhere_raises_only_spacearm_errors(value, site):
    literal = re.search(r"-?\d+(\.\d+)?", site).group(0)
    text = DEMO.replace(site, site.replace(literal, repr(value), 1), 1)
    check_only_spacearm_errors(text)


# ---- the documentation's examples -------------------------------------------------------------------------


def doc_blocks(name, lang):
    """The fenced code blocks of a doc whose info string is ``lang``."""
    blocks, current, info = [], None, None
    for line in (ROOT / "docs" / name).read_text(encoding="utf-8").splitlines(keepends=True):
        if line.startswith("```"):
            if current is None:
                current, info = [], line[3:].strip()
            else:
                if info == lang:
                    blocks.append("".join(current))
                current = None
        elif current is not None:
            current.append(line)
    return blocks


@pytest.mark.parametrize("name", ["model-format.md", "dh.md"])
def test_documented_model_files_load(name):
    blocks = doc_blocks(name, "toml")
    assert blocks
    for block in blocks:
        robot = loads_toml(block, name)
        assert loads_toml(dumps_toml(robot)).describe() == robot.describe()


def test_documented_worked_example():
    (block,) = doc_blocks("model-format.md", "toml")
    robot = loads_toml(block)
    assert robot.n_dof == 3 and robot.body_names == ["bus", "upper_arm", "forearm", "tool", "mast"]
    assert robot.end_effector == "grasp" and robot.point_names == ["grasp", "camera"]
    assert robot.joint_types == ["revolute", "revolute", "prismatic", "fixed"]


def test_documented_error_messages():
    blocks = [b.rstrip("\n") for b in doc_blocks("model-format.md", "") if re.match(r"\w+\.toml:\d+:\d+: ", b)]
    produced = []
    for source, text in [("arm.toml", DEMO.replace("mass = 5.0", "mass = -5.0")),
                         ("arm.toml", DEMO.replace("mass = 5.0", "mas = 5.0")),
                         ("order.toml", DEMO.replace('parent = "base"', 'parent = "slider"').replace('parent = "arm"', 'parent = "base"'))]:
        with pytest.raises(spacearm.ModelFileError) as info:
            loads_toml(text, source)
        produced.append(str(info.value))
    assert blocks == produced
