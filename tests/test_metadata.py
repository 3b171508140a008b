"""Legal and citation metadata, and the wheel verification scripts (fast: nothing is built).

That the licence files really land in the wheel and the sdist is checked by listing the archives
that scripts/build-wheels.sh makes (too slow for the test suite); here: the files exist and are
the licences they claim to be, pyproject names them, the licence is declared the same way
everywhere, CITATION.cff is valid CFF 1.2.0 naming the two papers, and the GLIBC checker and the
fingerprint comparison give the right verdicts.
"""

from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
LICENSE_FILES = ("LICENSE-MIT", "LICENSE-APACHE")
SPDX_EXPRESSION = "MIT OR Apache-2.0"

try:  # Python 3.11+
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.9/3.10
    tomllib = pytest.importorskip("tomli")


def _toml(name: str) -> dict:
    with open(ROOT / name, "rb") as f:
        return tomllib.load(f)


# --------------------------------------------------------------------------------------------
# licences
# --------------------------------------------------------------------------------------------
def test_licence_texts_are_the_two_licences():
    mit = (ROOT / "LICENSE-MIT").read_text(encoding="utf-8")
    assert "Permission is hereby granted, free of charge" in mit
    assert 'THE SOFTWARE IS PROVIDED "AS IS"' in mit
    apache = (ROOT / "LICENSE-APACHE").read_text(encoding="utf-8")
    assert "Apache License" in apache and "Version 2.0, January 2004" in apache
    # The full text, not a pointer to it: all nine sections of the terms.
    for section in range(1, 10):
        assert re.search(rf"^\s*{section}\. [A-Z]", apache, re.MULTILINE), f"section {section} missing"
    assert "END OF TERMS AND CONDITIONS" in apache
    for text in (mit, apache):
        assert "Copyright (c) the spacearm developers" in text


def test_pyproject_declares_the_licence_by_pep_639_and_names_the_files():
    project = _toml("pyproject.toml")["project"]
    assert project["license"] == SPDX_EXPRESSION
    assert sorted(project["license-files"]) == sorted(LICENSE_FILES)
    for pattern in project["license-files"]:
        assert list(ROOT.glob(pattern)), f"license-files entry {pattern!r} matches no file"
    # PEP 639: with a licence expression, "License ::" classifiers must not be given (PyPI
    # refuses the upload).
    assert not [c for c in project["classifiers"] if c.startswith("License ::")]
    # maturin before 1.9.4 drops the licence files from the sdist.
    requires = " ".join(_toml("pyproject.toml")["build-system"]["requires"])
    match = re.search(r"maturin>=(\d+)\.(\d+)\.?(\d*)", requires)
    assert match, requires
    assert tuple(int(g or 0) for g in match.groups()) >= (1, 9, 4)


def test_cargo_declares_the_same_licence_and_a_real_repository():
    workspace = _toml("Cargo.toml")["workspace"]["package"]
    assert workspace["license"] == SPDX_EXPRESSION
    assert workspace["repository"].startswith("https://") and "invalid" not in workspace["repository"]
    assert workspace["authors"]
    for crate in ("spacearm-core", "spacearm-py"):
        package = _toml(f"crates/{crate}/Cargo.toml")["package"]
        for key in ("license", "repository", "authors"):
            assert package[key] == {"workspace": True}, f"{crate}: {key} not inherited from the workspace"


def test_project_urls_and_classifiers():
    project = _toml("pyproject.toml")["project"]
    urls = project["urls"]
    for key in ("Homepage", "Repository", "Documentation", "Changelog", "Issues"):
        assert urls[key].startswith("https://"), key
    assert urls["Repository"] == _toml("Cargo.toml")["workspace"]["package"]["repository"]
    classifiers = set(project["classifiers"])
    # One classifier per supported Python minor version, from requires-python's lower bound.
    lowest = int(re.fullmatch(r">=3\.(\d+)", project["requires-python"]).group(1))
    for minor in range(lowest, 14):
        assert f"Programming Language :: Python :: 3.{minor}" in classifiers
    for os_classifier in ("POSIX :: Linux", "MacOS", "Microsoft :: Windows"):
        assert f"Operating System :: {os_classifier}" in classifiers


# --------------------------------------------------------------------------------------------
# citation
# --------------------------------------------------------------------------------------------
def _citation_text() -> str:
    return (ROOT / "CITATION.cff").read_text(encoding="utf-8")


def test_citation_cff_is_valid():
    text = _citation_text()
    # Without any YAML reader, at least the keys CFF 1.2.0 requires are present.
    for required in ("cff-version: 1.2.0", "message:", "title: spacearm", "authors:"):
        assert re.search(rf"^{re.escape(required)}", text, re.MULTILINE), required
    try:
        from cffconvert.cli.create_citation import create_citation
    except ImportError:
        pass
    else:  # the schema check proper
        create_citation(str(ROOT / "CITATION.cff"), None).validate()
    yaml = pytest.importorskip("yaml")  # PyYAML comes with dask (the campaign extra)
    cff = yaml.safe_load(text)
    assert cff["cff-version"] == "1.2.0"
    assert cff["title"] == "spacearm" and cff["type"] == "software" and cff["message"]
    assert cff["authors"]
    assert cff["version"] == _toml("Cargo.toml")["workspace"]["package"]["version"]
    # A list of licences is a disjunction in CFF: the same as the SPDX expression.
    assert " OR ".join(cff["license"]) == SPDX_EXPRESSION


def test_citation_references_the_two_papers():
    yaml = pytest.importorskip("yaml")
    references = {r["doi"]: r for r in yaml.safe_load(_citation_text())["references"]}
    wilde = references["10.3389/frobt.2018.00041"]
    assert wilde["year"] == 2018 and wilde["journal"] == "Frontiers in Robotics and AI"
    assert [a["family-names"] for a in wilde["authors"]] == ["Wilde", "Kwok Choon", "Grompone", "Romano"]
    umetani = references["10.1109/70.34766"]
    assert umetani["year"] == 1989 and (umetani["volume"], umetani["issue"]) == (5, 3)
    assert (umetani["start"], umetani["end"]) == (303, 314)
    assert [a["family-names"] for a in umetani["authors"]] == ["Umetani", "Yoshida"]


def test_changelog_has_unreleased_and_0_1_0():
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    headings = re.findall(r"^## \[([^\]]+)\]", text, re.MULTILINE)
    assert headings[:2] == ["Unreleased", "0.1.0"]


# --------------------------------------------------------------------------------------------
# scripts/check-wheel-glibc.sh
# --------------------------------------------------------------------------------------------
def _glibc_needed_by_readelf(so: Path) -> tuple:
    """Highest GLIBC version in the object's version-needs section (readelf -V): a second
    reading of the ELF, independent of the objdump -T symbol table the script reads."""
    out = subprocess.run(["readelf", "-V", "-W", str(so)], capture_output=True, text=True, check=True).stdout
    versions = {tuple(int(p) for p in v.split(".")) for v in re.findall(r"Name: GLIBC_([0-9.]+)", out)}
    return max(versions)


@pytest.mark.skipif(shutil.which("readelf") is None or shutil.which("objdump") is None,
                    reason="binutils (readelf, objdump) not installed")
def test_glibc_checker_reports_the_highest_version_of_the_installed_extension(tmp_path):
    import spacearm._core

    so = Path(spacearm._core.__file__)
    wheel = tmp_path / "spacearm-0.0.0-cp39-abi3-linux_x86_64.whl"
    with zipfile.ZipFile(wheel, "w") as z:
        z.write(so, f"spacearm/{so.name}")
    result = subprocess.run(["bash", str(ROOT / "scripts/check-wheel-glibc.sh"), str(wheel)],
                            capture_output=True, text=True, timeout=60)
    reported = re.search(r"highest GLIBC_([0-9.]+)", result.stdout)
    assert reported, result.stdout + result.stderr
    highest = tuple(int(p) for p in reported.group(1).split("."))
    assert highest == _glibc_needed_by_readelf(so)
    assert result.returncode == (1 if highest > (2, 17) else 0), result.stdout + result.stderr


def test_glibc_checker_refuses_what_is_not_a_wheel(tmp_path):
    not_a_wheel = tmp_path / "x.txt"
    not_a_wheel.write_text("x")
    empty_wheel = tmp_path / "empty-0.0.0-py3-none-any.whl"
    with zipfile.ZipFile(empty_wheel, "w") as z:
        z.writestr("empty/__init__.py", "")
    corrupt_wheel = tmp_path / "corrupt-0.0.0-py3-none-any.whl"
    corrupt_wheel.write_bytes(b"not a zip archive")
    cases = ((not_a_wheel, "is not a .whl file"), (empty_wheel, "holds no shared object"),
             (corrupt_wheel, "cannot unpack"))
    for path, message in cases:
        result = subprocess.run(["bash", str(ROOT / "scripts/check-wheel-glibc.sh"), str(path)],
                                capture_output=True, text=True, timeout=60)
        assert result.returncode == 2 and message in result.stderr, result.stderr


# --------------------------------------------------------------------------------------------
# scripts/wheel_fingerprint.py --compare
# --------------------------------------------------------------------------------------------
def _fingerprint_module():
    spec = importlib.util.spec_from_file_location("wheel_fingerprint", ROOT / "scripts/wheel_fingerprint.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_fingerprint_compare_requires_identical_bits(tmp_path, capsys):
    fp = _fingerprint_module()
    rng = np.random.default_rng(7)
    arrays = {"m/state0/input_x": rng.normal(size=7), "m/state0/mass_matrix": rng.normal(size=(6, 6)),
              "meta/version": np.array("0")}
    reference = tmp_path / "a.npz"
    np.savez(reference, **arrays)

    same = tmp_path / "same.npz"
    np.savez(same, **arrays)
    assert fp.compare(str(reference), str(same)) == 0

    one_ulp = dict(arrays, **{"m/state0/mass_matrix": arrays["m/state0/mass_matrix"].copy()})
    one_ulp["m/state0/mass_matrix"][2, 3] = np.nextafter(one_ulp["m/state0/mass_matrix"][2, 3], np.inf)
    np.savez(tmp_path / "ulp.npz", **one_ulp)
    capsys.readouterr()
    assert fp.compare(str(reference), str(tmp_path / "ulp.npz")) == 1
    assert "1 of 36 values differ" in capsys.readouterr().out

    with_nan = dict(arrays, **{"m/state0/mass_matrix": arrays["m/state0/mass_matrix"].copy()})
    with_nan["m/state0/mass_matrix"][0, 0] = np.nan
    np.savez(tmp_path / "nan.npz", **with_nan)
    assert fp.compare(str(reference), str(tmp_path / "nan.npz")) == 1
    assert "NaN pattern differs" in capsys.readouterr().out

    other_input = dict(arrays, **{"m/state0/input_x": arrays["m/state0/input_x"] + 1.0})
    np.savez(tmp_path / "input.npz", **other_input)
    assert fp.compare(str(reference), str(tmp_path / "input.npz")) == 1
    assert "DIFFERENT INPUTS" in capsys.readouterr().out
