"""The ETS-VII preset: the transcribed parameters (typed here from the published tables, not
from spacearm), the kinematics against a chain of URDF transforms composed here with scipy, the
documented correction of the links whose moments break the triangle inequality, and the
``allow_nonphysical_inertia`` option on every loading door (preset, builder, TOML, URDF, CLI)."""

from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import spacearm
from spacearm.errors import ModelError, ModelFileError, NonPhysicalInertiaWarning
from spacearm.io.model_file import dumps_toml, loads_toml
from spacearm.io.urdf import loads_urdf
from spacearm.io.urdf_export import to_urdf

# The table of ets7.md (Vyas 2020 transcription of Yoshida 2003 / Yoshida & Abiko 2002):
# joint origin xyz, rpy (3.1416 and 1.5708 read as pi, pi/2), mass, (Ixx, Iyy, Izz).
PI = np.pi
LINKS = [
    ((-0.79, -0.29, 1.0), (0, 0, PI), 35.0, (0.25, 0.25, 1.69)),
    ((0, -0.275, 0.35), (-PI / 2, 0, 0), 22.5, (0.1, 1.31, 3.75)),
    ((0, -0.87, 0), (0, 0, 0), 21.9, (0.1, 0.71, 2.53)),
    ((-0.63, 0, 0), (0, 0, 0), 16.5, (0.15, 0.15, 0.073)),
    ((0, 0, 0.26), (PI / 2, 0, 0), 26.0, (0.15, 0.15, 0.13)),
    ((0, 0, 0.28), (0, -PI / 2, 0), 18.5, (0.97, 0.97, 0.26)),
]
BASE_MASS = 2550.0
BASE_INERTIA = np.array([[6200, 48.2, 78.5], [48.2, 3540, -29.2], [78.5, -29.2, 7090]])
TIP = np.array([0, 0, 0.53])
BROKEN = {0, 1, 2}  # links whose (Ixx, Iyy, Izz) break Ixx + Iyy >= Izz


def published() -> spacearm.Robot:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NonPhysicalInertiaWarning)
        return spacearm.presets.ets7(allow_nonphysical_inertia=True)


def urdf_chain(q):
    """End-effector position and link-6 rotation in the base frame (base at the origin,
    aligned): URDF joint transforms composed with scipy, each joint about its frame's z."""
    rot, pos = np.eye(3), np.zeros(3)
    for (xyz, rpy, _, _), angle in zip(LINKS, q):
        pos = pos + rot @ np.array(xyz)
        rot = rot @ Rotation.from_euler("xyz", rpy).as_matrix() @ Rotation.from_rotvec([0, 0, angle]).as_matrix()
    return pos + rot @ TIP, rot


def test_the_table_values_are_in_the_published_model():
    d = published().description
    assert d.base.mass == BASE_MASS
    np.testing.assert_array_equal(d.base.inertia, BASE_INERTIA)
    assert len(d.links) == 6 and all(link.type == "revolute" for link in d.links)
    for link, (xyz, rpy, mass, moments) in zip(d.links, LINKS):
        np.testing.assert_array_equal(link.origin, xyz)
        np.testing.assert_array_equal(link.com, 0.0)  # the transcription's CM at the joint frame origin
        np.testing.assert_allclose(link.axis, [0, 0, 1])
        assert link.mass == mass
        np.testing.assert_array_equal(link.inertia, np.diag(moments))
        np.testing.assert_allclose(Rotation.from_quat(link.rotation).as_matrix(), Rotation.from_euler("xyz", rpy).as_matrix(), atol=1e-15)
    assert d.end_effector == "end_effector"
    np.testing.assert_array_equal(d.points[0].offset, TIP)
    assert published().total_mass == pytest.approx(BASE_MASS + sum(link[2] for link in LINKS), rel=1e-15)


@pytest.mark.parametrize("seed", range(4))
def test_kinematics_match_the_urdf_chain(seed):
    robot = spacearm.presets.ets7()
    q = np.zeros(6) if seed == 0 else np.random.default_rng(seed).uniform(-np.pi, np.pi, 6)
    x = robot.neutral_configuration(q=q)
    ee, rot6 = urdf_chain(q)
    np.testing.assert_allclose(robot.point_position(x), ee, atol=1e-12)
    np.testing.assert_allclose(robot.forward_kinematics(x).body_to_world[6], rot6, atol=1e-12)


def test_published_moments_give_one_warning_per_broken_link():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = spacearm.presets.ets7(allow_nonphysical_inertia=True)
    messages = [str(w.message) for w in caught if w.category is NonPhysicalInertiaWarning]
    assert len(messages) == len(BROKEN) == len(robot.inertia_warnings)
    for k, message in zip(sorted(BROKEN), messages):
        assert f"link 'link{k + 1}'" in message and "triangle inequality" in message
    assert robot.allows_nonphysical_inertia
    # The transcription's moments do break it (the reason for the option), and only these links'.
    assert {k for k, link in enumerate(LINKS) if link[3][0] + link[3][1] < link[3][2]} == BROKEN


def test_default_preset_corrects_only_the_broken_links_by_the_documented_rule():
    with warnings.catch_warnings():
        warnings.simplefilter("error", NonPhysicalInertiaWarning)
        robot = spacearm.presets.ets7()
    assert robot.inertia_warnings == [] and not robot.allows_nonphysical_inertia
    d = robot.description
    np.testing.assert_array_equal(d.base.inertia, BASE_INERTIA)
    for k, (link, (_, _, mass, (a, b, c))) in enumerate(zip(d.links, LINKS)):
        x, y, z = np.diag(link.inertia)
        assert link.mass == mass and np.count_nonzero(link.inertia - np.diag(np.diag(link.inertia))) == 0
        if k not in BROKEN:
            assert (x, y, z) == (a, b, c)
            continue
        # Second moments S_xx = (Iyy + Izz - Ixx)/2, S_yy = (Ixx + Izz - Iyy)/2 kept, S_zz raised to 0.
        assert z == c
        assert (y + z - x) / 2 == pytest.approx((b + c - a) / 2, abs=1e-14)
        assert (x + z - y) / 2 == pytest.approx((a + c - b) / 2, abs=1e-14)
        assert (x + y - z) / 2 == pytest.approx(0.0, abs=1e-14)
    np.testing.assert_allclose(np.diag(d.links[0].inertia), [0.845, 0.845, 1.69], atol=1e-14)
    np.testing.assert_allclose(np.diag(d.links[1].inertia), [1.27, 2.48, 3.75], atol=1e-14)
    np.testing.assert_allclose(np.diag(d.links[2].inertia), [0.96, 1.57, 2.53], atol=1e-14)


def test_published_model_has_a_positive_definite_mass_matrix():
    # The option relaxes only the triangle inequality; the dynamics stay well posed.
    robot = published()
    for seed in range(3):
        q = np.random.default_rng(seed).uniform(-np.pi, np.pi, 6)
        assert np.linalg.eigvalsh(robot.mass_matrix(robot.neutral_configuration(q=q))).min() > 0


def test_builder_refuses_the_published_moments_and_names_the_option():
    with pytest.raises(ModelError, match="allow_nonphysical_inertia=True") as info:
        spacearm.RobotBuilder.from_robot(published(), allow_nonphysical_inertia=False)
    assert "link 'link1'" in str(info.value) and "triangle inequality" in str(info.value)
    # An edited copy keeps the published model's choice (and warns again).
    with pytest.warns(NonPhysicalInertiaWarning):
        copy = published().to_builder().attach_payload("target", body="link6", mass=10.0, inertia=[1, 1, 1]).build()
    assert copy.allows_nonphysical_inertia


def test_toml_door_refuses_by_default_and_loads_with_the_option():
    text = dumps_toml(published())
    with pytest.raises(ModelFileError, match="allow_nonphysical_inertia=True"):
        loads_toml(text, source="ets7.toml")
    with pytest.warns(NonPhysicalInertiaWarning, match="link 'link2'"):
        robot = loads_toml(text, source="ets7.toml", allow_nonphysical_inertia=True)
    x = robot.neutral_configuration(q=[0.3, -0.2, 0.5, 0.1, -0.4, 0.7])
    np.testing.assert_array_equal(robot.mass_matrix(x), published().mass_matrix(x))


def test_urdf_door_refuses_by_default_and_loads_with_the_option():
    text = to_urdf(published())
    with pytest.raises(ModelFileError, match="allow_nonphysical_inertia"):
        loads_urdf(text, source="ets7.urdf")
    with pytest.warns(NonPhysicalInertiaWarning):
        robot = loads_urdf(text, source="ets7.urdf", allow_nonphysical_inertia=True)
    x = robot.neutral_configuration(q=[0.3, -0.2, 0.5, 0.1, -0.4, 0.7])
    np.testing.assert_allclose(robot.mass_matrix(x), published().mass_matrix(x), rtol=1e-12, atol=1e-9)


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "spacearm", *args], capture_output=True, text=True, timeout=300)


def test_cli_loads_ets7_and_the_option_reaches_model_files(tmp_path):
    assert "ets7" in spacearm.presets.NAMES
    done = run_cli("inspect", "ets7")
    assert done.returncode == 0, done.stderr
    assert "warning" not in done.stderr
    path = tmp_path / "ets7_published.toml"
    path.write_text(dumps_toml(published()))
    refused = run_cli("inspect", str(path))
    assert refused.returncode == 2
    assert refused.stderr.startswith("spacearm: error:") and "--allow-nonphysical-inertia" in refused.stderr
    loaded = run_cli("inspect", str(path), "--allow-nonphysical-inertia")
    assert loaded.returncode == 0, loaded.stderr
    lines = loaded.stderr.splitlines()
    assert len(lines) == 3 and all(line.startswith("spacearm: warning: link 'link") for line in lines), loaded.stderr
