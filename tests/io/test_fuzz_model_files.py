"""Model files never crash the program: hypothesis feeds mutated TOML and URDF documents.

Every document either loads into a valid model or raises a :class:`spacearm.SpacearmError`
(for files, :class:`~spacearm.ModelFileError`) with a message; any other exception (a Rust
panic surfaces as ``PanicException``, a parser bug as ``IndexError``/``KeyError``...) fails.

Seeds: the example TOML files, TOML written from random trees, URDF written from random
URDF trees and from the presets. Mutations: delete, duplicate or swap spans, insert tokens that
parsers trip over (quotes, brackets, ``nan``, ``-1e309``, entity declarations, unsupported
joint types, ``<mimic>``...), and replace numbers. Counts of documents, loads and errors are
printed (``pytest -s``) and the total is asserted to reach ``FUZZ_EXAMPLES`` per format.

Budget: ``SPACEARM_FUZZ_EXAMPLES`` per format (default 5000, i.e. 10,000 documents in about
half a minute); derandomized so that CI runs the same documents every time.
"""

from __future__ import annotations

import collections
import glob
import os
import re

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import spacearm
from spacearm.io import model_file
from spacearm.io.urdf import loads_urdf
from spacearm.io.urdf_export import to_urdf
from random_models import SEEDS, random_model
from random_urdf import random_urdf

FUZZ_EXAMPLES = int(os.environ.get("SPACEARM_FUZZ_EXAMPLES", "5000"))
FUZZ = settings(max_examples=FUZZ_EXAMPLES, deadline=None, derandomize=True, database=None,
                suppress_health_check=list(HealthCheck))
COUNTS: collections.Counter = collections.Counter()

MODELS_DIR = os.path.dirname(spacearm.examples.path("spatial6"))  # the shipped model files
TOML_SEEDS = [open(p).read() for p in sorted(glob.glob(os.path.join(MODELS_DIR, "*.toml")))] + [
    model_file.dumps_toml(random_model(s).robot) for s in SEEDS[:6]
]
URDF_SEEDS = [random_urdf(s, n_links=5) for s in range(6)] + [to_urdf(spacearm.presets.get(n)) for n in ("planar4", "dual_arm")]

TOKENS = [
    "", " ", "\n", "\x00", "\ufeff", '"', "'", "=", "[", "]", "{", "}", "[[link]]", "[base]", ",", "#",
    "nan", "inf", "-inf", "-1e309", "1e308", "-0.0", "0", "-5", "1e-320", "9" * 40,
    "<", ">", "/>", "</link>", "</joint>", "<link name=\"x\"/>", "&amp;", "&x;", "<![CDATA[", "<!--",
    '<!DOCTYPE r [<!ENTITY x "xx">]>', '<!ENTITY x SYSTEM "file:///etc/passwd">', '<mimic joint="j1"/>',
    'type="floating"', 'type="planar"', 'type="fixed"', 'type="continuous"', '<axis xyz="0 0 0"/>',
    '<limit lower="2" upper="1"/>', '<parent link="root"/>', '<child link="root"/>', 'xyz="1 2"', 'rpy="nan 0 0"',
    "parent = \"base\"", "type = \"prismatic\"", "mass = -1", "inertia = [1, 1, 5]", "axis = [0, 0, 0]",
]
NUMBER = re.compile(r"-?\d+(\.\d+)?(e-?\d+)?")


@st.composite
def mutated(draw, seeds):
    text = draw(st.sampled_from(seeds))
    for _ in range(draw(st.integers(1, 4))):
        n = len(text)
        i = draw(st.integers(0, n))
        j = draw(st.integers(i, min(n, i + 40)))
        op = draw(st.sampled_from(["delete", "insert", "duplicate", "number", "swap"]))
        if op == "delete":
            text = text[:i] + text[j:]
        elif op == "insert":
            text = text[:i] + draw(st.sampled_from(TOKENS) | st.text(max_size=8)) + text[i:]
        elif op == "duplicate":
            text = text[:j] + text[i:j] + text[j:]
        elif op == "swap":
            k = draw(st.integers(0, n))
            text = text[:i] + text[k:k + 20] + text[j:]
        else:
            numbers = list(NUMBER.finditer(text))
            if numbers:
                m = numbers[draw(st.integers(0, len(numbers) - 1))]
                text = text[:m.start()] + draw(st.sampled_from(["0", "-1", "1e300", "nan", "-inf", "3.5", "1e-300"])) + text[m.end():]
    return text


def check(kind: str, load, text: str) -> None:
    COUNTS[kind, "documents"] += 1
    try:
        robot = load(text)
    except spacearm.SpacearmError as exc:
        assert str(exc), "a spacearm error must carry a message"
        COUNTS[kind, "errors"] += 1
        return
    assert isinstance(robot, spacearm.Robot)
    COUNTS[kind, "loaded"] += 1


@FUZZ
@given(mutated(TOML_SEEDS))
def test_mutated_toml_loads_or_raises_a_spacearm_error(text):
    check("toml", lambda t: spacearm.io.loads_toml(t, source="fuzz.toml"), text)


@FUZZ
@given(mutated(URDF_SEEDS))
def test_mutated_urdf_loads_or_raises_a_spacearm_error(text):
    check("urdf", lambda t: loads_urdf(t, source="fuzz.urdf"), text)


def test_fuzz_counts():
    """Runs after the two fuzz tests (file order): report and hold the counts."""
    for kind in ("toml", "urdf"):
        total, loaded, errors = (COUNTS[kind, k] for k in ("documents", "loaded", "errors"))
        print(f"\nfuzz {kind}: {total} documents, {loaded} loaded, {errors} spacearm errors")
        if total:  # zero when this test is run alone
            assert total >= FUZZ_EXAMPLES and loaded + errors == total
            assert loaded > 0 and errors > 0, "the mutations should produce both valid and invalid documents"
