"""Each URDF ``<inertial>`` meets the core's rule for one body's mass properties before fixed
links are merged (``_core.body_mass_properties_error``, the rule of ``model/body.rs`` that the
builder applies): the verdict is checked against numpy's eigenvalues and ``MODEL_BOUNDS``, the
message against the builder's own refusal of the same link, and the location against the line of
the ``<mass>`` or ``<inertia>`` element."""

from __future__ import annotations

import numpy as np
import pytest

import spacearm
from spacearm import _core
from spacearm.errors import NonPhysicalInertiaWarning
from spacearm.io.urdf import loads_urdf
from spacearm.rotations import quat_to_matrix

from random_models import random_quaternion

GOOD_INERTIA = np.diag([0.01, 0.2, 0.2])
BOUNDS = _core.MODEL_BOUNDS


def builder_refusal(name: str, mass: float, inertia) -> str:
    """The builder's message for a link ``name`` with these mass properties (another door)."""
    b = spacearm.Robot.builder("rule", base_mass=100.0, base_inertia=[10.0, 12.0, 14.0])
    with pytest.raises(spacearm.ModelError) as info:
        b.add_link(name, parent="base", joint="revolute", axis=(0, 0, 1), origin=(0.5, 0, 0), com=(0.2, 0, 0),
                   mass=mass, inertia=np.asarray(inertia, dtype=float))
        b.build()
    return str(info.value)


def verdict(mass, inertia, triangle_inequality=True):
    return _core.body_mass_properties_error("link 'x'", mass, np.asarray(inertia, dtype=float).tolist(),
                                            triangle_inequality=triangle_inequality)


def test_random_inertias_against_numpy_eigenvalues():
    rng = np.random.default_rng(20240601)
    seen = set()
    for _ in range(300):
        moments = rng.uniform(-0.5, 2.0, size=3) * 10.0 ** rng.uniform(-4, 4)
        if np.min(np.abs(moments)) < 1e-6 * np.max(np.abs(moments)):
            continue  # too close to the tolerance of the rule to be a clear case
        r = quat_to_matrix(random_quaternion(rng))
        inertia = r @ np.diag(moments) @ r.T
        inertia = 0.5 * (inertia + inertia.T)
        a, b, c = np.sort(np.linalg.eigvalsh(inertia))
        indefinite = a < 0
        triangle_broken = a + b < c - 1e-6 * abs(c)
        if not indefinite and abs(a + b - c) < 1e-6 * abs(c):
            continue  # at the triangle inequality's boundary
        for enforce in (True, False):
            got = verdict(1.0, inertia, triangle_inequality=enforce)
            refused = indefinite or (enforce and triangle_broken)
            assert (got is not None) == refused, (moments, enforce, got)
            if refused:
                field, message = got
                assert field == "inertia"
                assert ("semi-definite" if indefinite else "triangle inequality") in message, message
                seen.add("semi-definite" if indefinite else "triangle")
    assert seen == {"semi-definite", "triangle"}  # both rules were exercised


@pytest.mark.parametrize("mass, refused", [
    (0.0, False), (BOUNDS["min_mass"], False), (1.0, False), (BOUNDS["max_mass"], False),
    (-1.0, True), (0.1 * BOUNDS["min_mass"], True), (10.0 * BOUNDS["max_mass"], True), (float("inf"), True),
])
def test_mass_against_the_model_bounds(mass, refused):
    got = verdict(mass, GOOD_INERTIA)
    assert (got is not None) == refused, got
    if refused:
        assert got[0] == "mass"


def test_inertia_entry_bound():
    limit = BOUNDS["max_inertia_entry"]
    assert verdict(1.0, np.eye(3) * limit) is None
    field, message = verdict(1.0, np.eye(3) * 1.1 * limit)
    assert field == "inertia" and "exceeds" in message


@pytest.mark.parametrize("mass, inertia", [
    (-2.0, GOOD_INERTIA),
    (1e13, GOOD_INERTIA),
    (1e-12, GOOD_INERTIA),
    (1.0, np.diag([-0.01, 0.2, 0.2])),
    (1.0, np.diag([1e90, 1e90, 1e90])),
    (1.0, np.diag([0.01, 0.2, 0.6])),  # the triangle inequality: enforced by the verdict's default
])
def test_the_message_is_the_builders(mass, inertia):
    field, message = verdict(mass, inertia)
    assert message == builder_refusal("x", mass, inertia)


def _urdf(tool_mass: str, tool_inertia: str) -> str:
    """An arm with a tool on a fixed joint, each element on its own line."""
    return f"""<robot name="u">
  <link name="bus"><inertial><mass value="100"/><inertia ixx="10" iyy="12" izz="14"/></inertial></link>
  <link name="arm">
    <inertial>
      <origin xyz="0.2 0 0"/>
      <mass value="3"/>
      <inertia ixx="1" iyy="1" izz="1"/>
    </inertial>
  </link>
  <link name="tool">
    <inertial>
      <mass value="{tool_mass}"/>
      <inertia {tool_inertia}/>
    </inertial>
  </link>
  <joint name="shoulder" type="continuous"><parent link="bus"/><child link="arm"/><origin xyz="0.5 0 0"/><axis xyz="0 0 1"/></joint>
  <joint name="flange" type="fixed"><parent link="arm"/><child link="tool"/><origin xyz="0.4 0 0"/></joint>
</robot>"""


def _line_of(text: str, needle: str) -> int:
    (line,) = [i + 1 for i, row in enumerate(text.splitlines()) if needle in row]
    return line


@pytest.mark.parametrize("mass, ixx, element", [
    ("-2", "0.01", "mass"),  # the parent's mass would hide it in the merged body
    ("1e13", "0.01", "mass"),
    ("0.5", "-0.05", "inertia"),  # a negative moment inside a good merged total
    ("0.5", "1e90", "inertia"),
])
def test_a_merged_link_is_refused_at_its_element_with_the_builders_message(mass, ixx, element):
    text = _urdf(mass, f'ixx="{ixx}" iyy="0.2" izz="0.2"')
    with pytest.raises(spacearm.ModelFileError) as info:
        loads_urdf(text, source="t.urdf")
    needle = f'<mass value="{mass}"/>' if element == "mass" else f'<inertia ixx="{ixx}"'
    expected = f"t.urdf:{_line_of(text, needle)}: " + builder_refusal("tool", float(mass), np.diag([float(ixx), 0.2, 0.2]))
    assert str(info.value) == expected


def test_the_triangle_inequality_is_left_to_the_merged_body():
    # A massless sensor frame with a rod-like inertia that no physical body has (0.1 + 0.1 < 1):
    # merged into the arm it is harmless, so the URDF loads without the option...
    rod = 'ixx="1e-4" iyy="1e-4" izz="1e-3"'
    merged = loads_urdf(_urdf("0", rod), source="t.urdf")
    assert [link.name for link in merged.description.links] == ["arm"]
    # (a massless part adds its inertia alone, in the same axes)
    np.testing.assert_allclose(merged.description.links[0].inertia, np.diag([1.0001, 1.0001, 1.001]), rtol=0, atol=1e-12)
    # ...while kept as a body of its own, the builder applies the whole rule, and the option
    # loads it with a warning, as for every door.
    text = _urdf("0", rod)
    with pytest.raises(spacearm.ModelFileError, match="violate the triangle inequality"):
        loads_urdf(text, source="t.urdf", fixed="keep")
    with pytest.warns(NonPhysicalInertiaWarning, match="link 'tool'"):
        kept = loads_urdf(text, source="t.urdf", fixed="keep", allow_nonphysical_inertia=True)
    assert [link.name for link in kept.description.links] == ["arm", "tool"]
