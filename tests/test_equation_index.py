"""docs/equations.md stays true: every ``file::name`` it cites exists where it says, every
``Robot.method`` is a Robot attribute, and every test it names is defined in its file."""

import re
from pathlib import Path

import pytest

import spacearm

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "equations.md"
CORE = ROOT / "crates" / "spacearm-core" / "src"
PACKAGE = ROOT / "python" / "spacearm"

SPANS = re.findall(r"`([^`]+)`", PAGE.read_text(encoding="utf-8"))


def _refs(pattern):
    return sorted({s for s in SPANS if re.fullmatch(pattern, s)})


CORE_REFS = _refs(r"[a-z_/]+\.rs::\w+")
PYTHON_REFS = _refs(r"(?!tests/)[a-z_/]+\.py::\w+")
TEST_REFS = _refs(r"tests/[a-z_/]+\.py::\w+")
ROBOT_REFS = _refs(r"Robot\.\w+")
FILES = _refs(r"[a-z_/]+\.(rs|py)")


def test_the_page_cites_enough_to_be_an_index():
    # Guards the regular expressions above: a page they no longer parse would pass vacuously.
    assert len(CORE_REFS) >= 20 and len(TEST_REFS) >= 15 and len(ROBOT_REFS) >= 12 and len(PYTHON_REFS) >= 8


@pytest.mark.parametrize("ref", CORE_REFS)
def test_core_reference_exists(ref):
    path, name = ref.split("::")
    text = (CORE / path).read_text(encoding="utf-8")
    assert re.search(rf"\b(fn|struct|enum|trait)\s+{name}\b", text), f"{name} is not defined in {path}"


@pytest.mark.parametrize("ref", PYTHON_REFS)
def test_python_reference_exists(ref):
    path, name = ref.split("::")
    text = (PACKAGE / path).read_text(encoding="utf-8")
    assert re.search(rf"^\s*(def|class)\s+{name}\b", text, re.M), f"{name} is not defined in {path}"


@pytest.mark.parametrize("ref", TEST_REFS)
def test_test_reference_exists(ref):
    path, name = ref.split("::")
    text = (ROOT / path).read_text(encoding="utf-8")
    assert re.search(rf"^(def|async def)\s+{name}\(", text, re.M), f"{name} is not a test in {path}"


@pytest.mark.parametrize("ref", ROBOT_REFS)
def test_robot_method_exists(ref):
    assert hasattr(spacearm.Robot, ref.split(".", 1)[1]), ref


@pytest.mark.parametrize("ref", FILES)
def test_cited_files_exist(ref):
    assert (CORE / ref).exists() or (PACKAGE / ref).exists() or (ROOT / ref).exists(), ref
