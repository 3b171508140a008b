"""One release build of the core serves the extension and the C library.

cargo compiles a crate once per resolved feature set and per LTO mode. CI builds the extension
(`pip install -e`, crates/spacearm-py) and then the C library (`cargo build/test --release -p
spacearm-c`, scripts/c-tests.sh) in one target directory; when the two graphs resolve a crate that
spacearm-core depends on with different features, the core and everything above it compile again
(three release builds of the core, about four minutes of CI on two cores). crates/workspace-hack
asks the C library's graph for the extension's extra features; these tests fail, naming the crate
and the features, when the graphs drift apart (a new dependency, a new version).
"""

from __future__ import annotations

import shutil
import subprocess
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(shutil.which("cargo") is None, reason="cargo is not installed")


def resolved(*args: str) -> dict[str, str]:
    """Each package of `cargo tree` (normal, build and dev edges as asked) and its features."""
    out = subprocess.run(
        ["cargo", "tree", "--locked", "--prefix", "none", "-f", "{p}|{f}", *args],
        cwd=ROOT, check=True, capture_output=True, text=True,
    ).stdout
    packages: dict[str, str] = {}
    for line in out.splitlines():
        line = line.replace(" (*)", "").replace(" (proc-macro)", "").strip()
        if "|" not in line:
            continue
        package, features = line.split("|", 1)
        packages.setdefault(package, features)
    return packages


def core_closure() -> set[str]:
    return set(resolved("-p", "spacearm-core", "-e", "normal,build"))


def test_the_core_and_its_dependencies_resolve_alike_for_the_extension_and_the_c_library():
    closure = core_closure()
    assert any(p.startswith("spacearm-core ") for p in closure)
    assert len(closure) > 20, closure  # nalgebra, parry, serde, ...: the check sees the graph
    extension = resolved("-p", "spacearm-py", "--features", "pyo3/extension-module", "-e", "normal,build")
    # The C library as `cargo build` sees it, and as `cargo test` does (dev-dependencies too).
    for edges in ("normal,build", "normal,build,dev"):
        library = resolved("-p", "spacearm-c", "-e", edges)
        differ = {
            p: (extension.get(p), library.get(p))
            for p in closure
            if extension.get(p) != library.get(p)
        }
        assert not differ, (
            f"crates the core depends on resolve with other features for spacearm-c ({edges}) than for "
            f"the extension (package: (extension's, C library's)): {differ}; add the missing features to "
            "crates/workspace-hack/Cargo.toml, or CI compiles the core in release twice more"
        )


def test_the_c_library_has_no_rlib_target():
    # An rlib among the crate types makes cargo compile every dependency with object code beside
    # the LTO bitcode: another build of the core than the extension's (a cdylib).
    manifest = tomllib.loads((ROOT / "crates/spacearm-c/Cargo.toml").read_text())
    crate_types = manifest["lib"]["crate-type"]
    assert "cdylib" in crate_types and "staticlib" in crate_types
    assert "rlib" not in crate_types
    extension = tomllib.loads((ROOT / "crates/spacearm-py/Cargo.toml").read_text())
    assert extension["lib"]["crate-type"] == ["cdylib"]
