"""The spacearm C library (``libspacearm_c``, crates/spacearm-c; docs/c-api.md) in this
installation: where its header, shared library, pkg-config file and CMake package are, for a C or
C++ build, for ``ctypes`` and for the FMUs (``spacearm.fmi``, whose binary is this library).

From a shell, ``python -m spacearm.c --cflags --libs`` prints the compiler and linker flags:

    cc app.c $(python -m spacearm.c --cflags --libs) -o app

A wheel ships the library in this folder, laid out as an installation prefix (by
scripts/stage-c-prefix.sh when scripts/build-wheels.sh builds the wheel): ``include/spacearm.h``,
``lib/libspacearm_c.so``, ``lib/pkgconfig/spacearm.pc`` and ``lib/cmake/spacearm/`` (target
``spacearm::spacearm``). The library is looked for, in order:

1. the path in the environment variable ``SPACEARM_C_LIBRARY``;
2. in a source checkout (the editable install of ``scripts/test.sh``), ``target/release/`` of the
   repository, built by ``cargo build --release -p spacearm-c``, so that a fresh build is never
   hidden by an older copy in this folder;
3. ``lib/`` of this folder (a wheel).

A build without it (an install from the sdist, or a checkout before ``cargo build``) raises a
[`MissingDependencyError`][spacearm.errors.MissingDependencyError] that says how to get it.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import List

from ..errors import MissingDependencyError

__all__ = ["LIBRARY_NAME", "PREFIX", "library_path", "include_dir", "lib_dir", "pkg_config_path", "cmake_dir",
           "cflags", "libs"]

#: The library's file name on this platform.
LIBRARY_NAME = {"darwin": "libspacearm_c.dylib", "win32": "spacearm_c.dll"}.get(sys.platform, "libspacearm_c.so")

#: This folder: the installation prefix of the library a wheel ships (include/, lib/).
PREFIX = Path(__file__).resolve().parent

_CHECKOUT = PREFIX.parents[2]
_CHECKOUT_HEADER = _CHECKOUT / "crates" / "spacearm-c" / "include" / "spacearm.h"
_CHECKOUT_LIBRARY = _CHECKOUT / "target" / "release" / LIBRARY_NAME


def _in_checkout() -> bool:
    return _CHECKOUT_HEADER.is_file()


def _not_here(what: str) -> MissingDependencyError:
    if _in_checkout():
        how = "run `cargo build --release -p spacearm-c` in the repository"
    else:
        how = ("install a spacearm wheel (it ships the library), or build it from the source repository with "
               "`cargo build --release -p spacearm-c`")
    return MissingDependencyError(
        f"the spacearm C library ({what}) is not in this installation; {how} and set SPACEARM_C_LIBRARY to the "
        "library it writes (docs/c-api.md, 'Getting the library')")


def library_path() -> Path:
    """The shared library's path (see the module docs for where it is looked for)."""
    env = os.environ.get("SPACEARM_C_LIBRARY")
    if env:
        p = Path(env)
        if not p.is_file():
            raise MissingDependencyError(f"SPACEARM_C_LIBRARY is '{env}', which is not a file; point it at {LIBRARY_NAME}")
        return p
    candidates = ([_CHECKOUT_LIBRARY] if _in_checkout() else []) + [PREFIX / "lib" / LIBRARY_NAME]
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    raise _not_here(LIBRARY_NAME)


def lib_dir() -> Path:
    """The folder of the shared library (``library_path().parent``)."""
    return library_path().parent


def include_dir() -> Path:
    """The folder of ``spacearm.h``: ``include/`` of this folder (a wheel), or the crate's in a
    source checkout."""
    for header in (PREFIX / "include" / "spacearm.h", _CHECKOUT_HEADER):
        if header.is_file():
            return header.parent
    raise _not_here("its header spacearm.h")


def _prefix_file(relative: str, what: str) -> Path:
    p = PREFIX / relative
    if p.exists():
        return p
    if _in_checkout():
        raise MissingDependencyError(
            f"{what} ships with the wheel and the release tarball, not with a source checkout: use "
            "`python -m spacearm.c --cflags --libs`, or `bash scripts/package-c.sh` and its unpacked tarball "
            "(docs/c-api.md, 'Getting the library')")
    raise _not_here(what)


def pkg_config_path() -> Path:
    """The folder of ``spacearm.pc``, for ``PKG_CONFIG_PATH`` (a wheel's installation)."""
    return _prefix_file("lib/pkgconfig", "the pkg-config file spacearm.pc")


def cmake_dir() -> Path:
    """The folder of ``spacearm-config.cmake``, for ``-Dspacearm_DIR=`` or ``CMAKE_PREFIX_PATH``'s
    search (a wheel's installation)."""
    return _prefix_file("lib/cmake/spacearm", "the CMake package spacearm-config.cmake")


def cflags() -> List[str]:
    """The compiler flags: the header's folder."""
    return [f"-I{include_dir()}"]


def libs() -> List[str]:
    """The linker flags: the library's folder, searched at link time and recorded as the run-time
    path, and the library."""
    lib = library_path()
    folder = lib.parent.resolve()
    name = ["-lspacearm_c"] if lib.name == LIBRARY_NAME else [str(lib.resolve())]
    return [f"-L{folder}", f"-Wl,-rpath,{folder}"] + name
