"""``python -m spacearm.c``: where the spacearm C library of this installation is, for a C or C++
build (docs/c-api.md, "Getting the library"):

    cc app.c $(python -m spacearm.c --cflags --libs) -o app
    PKG_CONFIG_PATH=$(python -m spacearm.c --pkg-config-path) pkg-config --cflags --libs spacearm
    cmake -S . -B build -Dspacearm_DIR=$(python -m spacearm.c --cmake-dir)

``--cflags`` and ``--libs`` print their flags on one line (as pkg-config does); each folder or file
option prints one line, in the order of the options below. A missing part is one line on stderr
and exit 2.
"""

from __future__ import annotations

import argparse
import sys
from typing import List, Optional

from ..errors import MissingDependencyError
from . import cflags, cmake_dir, include_dir, lib_dir, libs, library_path, pkg_config_path

#: The path options: (flag, help, function), printed one a line in this order.
PATHS = [
    ("--include-dir", "the folder of spacearm.h", include_dir),
    ("--lib-dir", "the folder of the shared library", lib_dir),
    ("--library", "the shared library itself (for ctypes, MATLAB's loadlibrary, an FMU)", library_path),
    ("--pkg-config-path", "the folder of spacearm.pc (for PKG_CONFIG_PATH)", pkg_config_path),
    ("--cmake-dir", "the folder of spacearm-config.cmake (for -Dspacearm_DIR=)", cmake_dir),
]


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m spacearm.c", description=(
        "Where the spacearm C library of this installation is, for a C or C++ build "
        "(docs/c-api.md). Example: cc app.c $(python -m spacearm.c --cflags --libs) -o app"))
    p.add_argument("--cflags", action="store_true", help="the compiler flags (-I...)")
    p.add_argument("--libs", action="store_true", help="the linker flags (-L... -Wl,-rpath,... -lspacearm_c)")
    for flag, text, _ in PATHS:
        p.add_argument(flag, action="store_true", help=text)
    return p


def main(argv: Optional[List[str]] = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    asked = [(flag, fn) for flag, _, fn in PATHS if getattr(args, flag[2:].replace("-", "_"))]
    if not (args.cflags or args.libs or asked):
        parser.print_usage(sys.stderr)
        print("python -m spacearm.c: error: give at least one option (--cflags, --libs, --include-dir, --lib-dir, "
              "--library, --pkg-config-path, --cmake-dir)", file=sys.stderr)
        return 2
    try:
        lines = []
        flags = (cflags() if args.cflags else []) + (libs() if args.libs else [])
        if flags:
            lines.append(" ".join(flags))
        lines += [str(fn()) for _, fn in asked]
    except MissingDependencyError as e:
        print(f"python -m spacearm.c: error: {e}", file=sys.stderr)
        return 2
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
