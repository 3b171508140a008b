#!/usr/bin/env bash
# What a new user sees, checked before the test suite (CI's first stage; runnable by anyone).
#
# 1. Build the wheel and install it into a fresh venv with NO extras; the CLI must start:
#    `spacearm --version`, `python -m spacearm --version`, and `--help` of every subcommand.
#    A command that needs a missing extra must answer one line naming the extra, exit 2, and
#    print no traceback.
# 2. The C library ships in that wheel (docs/c-api.md, "Getting the library"): the wheel's file
#    list has the header, the shared library, the pkg-config and CMake files; the C example
#    builds and runs with `python -m spacearm.c --cflags --libs`, and through pkg-config and
#    CMake where they are installed; and the plain install exports FMUs (`spacearm fmu spatial6
#    --out s6.fmu`, and spacearm.fmi.export) that FMPy, installed alone in a third venv as a
#    Simulink user's importer would be, validates and runs, its states equal to those of
#    spacearm.simulate of the plain install.
# 3. In another fresh venv, run the README's main-job command exactly as the README writes it
#    (scripts/readme_command.py reads it from the block marked `<!-- ci: main-job -->`).
#
# Usage: bash scripts/new-user-check.sh [--no-main-job] [WHEEL]   (default: build the portable wheel
# of this machine with scripts/build-wheels.sh into dist/: a plain `maturin build` has no C
# library). Step 3 is scripts/readme-main-job.sh; --no-main-job leaves it out (.ci/run runs it
# while the wheel builds).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

say() { printf '\n== new user: %s\n' "$*"; }

main_job=1
if [ "${1:-}" = --no-main-job ]; then
    main_job=0
    shift
fi
wheel=${1:-}
if [ -z "$wheel" ]; then
    say "building the wheel"
    if [ "$(uname -m)" = x86_64 ]; then bash scripts/build-wheels.sh --x86_64-only; else bash scripts/build-wheels.sh; fi
    wheel=$(ls dist/spacearm-*manylinux*_"$(uname -m)".whl)
fi
wheel=$(realpath "$wheel")

say "plain install of $(basename "$wheel") into a fresh venv (no extras)"
python3 -m venv "$work/plain"
"$work/plain/bin/pip" install --quiet --upgrade pip
"$work/plain/bin/pip" install --quiet "$wheel"
for pkg in matplotlib sympy distributed imageio_ffmpeg; do
    if "$work/plain/bin/python" -c "import $pkg" 2>/dev/null; then
        echo "new-user check is void: '$pkg' is installed in the plain venv" >&2; exit 1
    fi
done

cd "$work"   # away from the source tree, so the installed package is the one imported
"$work/plain/bin/python" - "$work/plain/bin/spacearm" <<'PY'
import subprocess, sys, time
t = time.perf_counter()
out = subprocess.run([sys.argv[1], "--version"], check=True, stdout=subprocess.PIPE, text=True).stdout.strip()
print(f"{out}: 'spacearm --version' took {time.perf_counter() - t:.2f} s")
PY
"$work/plain/bin/python" -m spacearm --version
"$work/plain/bin/spacearm" --help >/dev/null
subcommands=$("$work/plain/bin/spacearm" --help | grep -o '{[a-z,_-]*}' | head -n 1 | tr -d '{}' | tr "," " ")
echo "subcommands: $subcommands"
for cmd in $subcommands; do
    "$work/plain/bin/spacearm" "$cmd" --help >/dev/null
done
"$work/plain/bin/spacearm" inspect spatial6 >/dev/null
# The example model files ship in the wheel (spacearm.examples): found by name from any directory.
"$work/plain/bin/spacearm" inspect spatial6_wheels >/dev/null
"$work/plain/bin/python" -c "import spacearm; assert spacearm.examples.path('spacecraft_bus').is_file()"

# A feature whose extra is missing: one line naming the extra, exit 2, no traceback.
expect_missing_extra() {
    local extra=$1; shift
    set +e
    "$@" >"$work/out.txt" 2>"$work/err.txt"
    local rc=$?
    set -e
    if [ "$rc" -ne 2 ] || grep -q Traceback "$work/err.txt" || ! grep -q "spacearm\[$extra\]" "$work/err.txt" \
        || [ "$(wc -l <"$work/err.txt")" -ne 1 ]; then
        echo "expected one line naming spacearm[$extra] and exit 2 from: $*" >&2
        echo "got exit $rc, stderr:" >&2; cat "$work/err.txt" >&2
        exit 1
    fi
    echo "  $* -> exit 2: $(cat "$work/err.txt")"
}
expect_missing_extra symbolic "$work/plain/bin/spacearm" derive planar4 --python d.py
expect_missing_extra plot "$work/plain/bin/spacearm" demo --no-animation
expect_missing_extra plot "$work/plain/bin/spacearm" simulate planar4 --duration 0.01 --plot run.png
expect_missing_extra video "$work/plain/bin/spacearm" simulate planar4 --duration 0.01 --video run.mp4
"$work/plain/bin/spacearm" demo --no-figures --out-dir "$work/demo" >/dev/null
test -s "$work/demo/spatial6_computed_torque.npz"

say "the C library in the wheel: its files, a C build through python -m spacearm.c, FMUs that FMPy runs"
"$work/plain/bin/python" - "$wheel" <<'PY'
import sys, zipfile
names = set(zipfile.ZipFile(sys.argv[1]).namelist())
need = ["spacearm/c/include/spacearm.h", "spacearm/c/lib/libspacearm_c.so", "spacearm/c/lib/pkgconfig/spacearm.pc",
        "spacearm/c/lib/cmake/spacearm/spacearm-config.cmake", "spacearm/c/lib/cmake/spacearm/spacearm-config-version.cmake"]
missing = [n for n in need if n not in names]
if missing:
    sys.exit(f"new user: the wheel has no C library: it lacks {missing} (scripts/build-wheels.sh stages them)")
print("  the wheel has " + ", ".join(need))
PY
library=$("$work/plain/bin/python" -m spacearm.c --library)
case "$library" in
    "$work/plain/"*) echo "  python -m spacearm.c --library: $library" ;;
    *) echo "new user: the C library found is '$library', not the wheel's (under $work/plain)" >&2; exit 1 ;;
esac
mkdir "$work/cbuild"
# shellcheck disable=SC2046
"${CC:-cc}" -std=c11 "$root/crates/spacearm-c/examples/example.c" $("$work/plain/bin/python" -m spacearm.c --cflags --libs) \
    -lm -o "$work/cbuild/example"
"$work/cbuild/example" | head -n 1
if command -v pkg-config >/dev/null; then
    # shellcheck disable=SC2046
    "${CC:-cc}" -std=c11 "$root/crates/spacearm-c/examples/example.c" \
        $(PKG_CONFIG_PATH=$("$work/plain/bin/python" -m spacearm.c --pkg-config-path) pkg-config --cflags --libs spacearm) \
        -lm -o "$work/cbuild/example_pc"
    "$work/cbuild/example_pc" >/dev/null
    echo "  the C example built and ran through pkg-config"
fi
if command -v cmake >/dev/null; then
    mkdir "$work/cbuild/cm"
    cat > "$work/cbuild/cm/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.16)
project(spacearm_example C)
find_package(spacearm REQUIRED)
add_executable(example "$root/crates/spacearm-c/examples/example.c")
target_link_libraries(example PRIVATE spacearm::spacearm m)
CMAKE
    cmake -S "$work/cbuild/cm" -B "$work/cbuild/cm/build" -Dspacearm_DIR="$("$work/plain/bin/python" -m spacearm.c --cmake-dir)" >/dev/null
    cmake --build "$work/cbuild/cm/build" >/dev/null
    "$work/cbuild/cm/build/example" >/dev/null
    echo "  the C example built and ran through CMake (find_package(spacearm), -Dspacearm_DIR from --cmake-dir)"
fi
# The issue's command, exactly: before the wheel shipped the library it exited 2 here.
"$work/plain/bin/spacearm" fmu spatial6 --out "$work/s6.fmu"
# The FMUs and the reference run of the same model and torques, from the plain install.
"$work/plain/bin/python" - "$work" <<'PY'
import sys
from pathlib import Path

import numpy as np

import spacearm
import spacearm.fmi
from spacearm.control import Callback

work = Path(sys.argv[1])
robot = spacearm.presets.spatial6()
tau = np.array([2.0, -1.5, 1.0, 0.5, -0.3, 0.2])
for version in (3, 2):
    spacearm.fmi.export(robot, work / f"s6-fmi{version}.fmu", dt=2e-3, fmi_version=version)
traj = spacearm.simulate(robot, 0.2, dt=2e-3, controller=Callback(lambda t, x, u: tau))
np.savez(work / "reference.npz", t=traj.t[::5], q=traj.q[::5], qd=traj.qd[::5], tau=tau)
PY
python3 -m venv "$work/importer"
"$work/importer/bin/pip" install --quiet --upgrade pip
"$work/importer/bin/pip" install --quiet "fmpy>=0.3.20"
"$work/importer/bin/python" - "$work" <<'PY'
import sys
from pathlib import Path

import fmpy
import numpy as np
from fmpy.validation import validate_fmu

work = Path(sys.argv[1])
for name in ("s6.fmu", "s6-fmi3.fmu", "s6-fmi2.fmu"):
    problems = validate_fmu(str(work / name))
    if problems:
        sys.exit(f"new user: FMPy finds problems in {name}: {problems}")
# The CLI's FMU (its defaults: floating, no controller) runs, held still: every output finite.
free = fmpy.simulate_fmu(str(work / "s6.fmu"), stop_time=0.1, output_interval=0.01)
values = np.column_stack([free[n] for n in free.dtype.names])
if len(free) != 11 or not np.all(np.isfinite(values)):
    sys.exit(f"new user: s6.fmu ran {len(free)} points, finite: {np.all(np.isfinite(values))}")
ref = np.load(work / "reference.npz")
names = [f"tau[{k}]" for k in range(1, 7)]
signal = np.array([(0.0, *ref["tau"]), (0.2, *ref["tau"])], dtype=[("time", float)] + [(n, float) for n in names])
for version in (3, 2):
    result = fmpy.simulate_fmu(str(work / f"s6-fmi{version}.fmu"), stop_time=0.2, step_size=0.01, output_interval=0.01,
                               input=signal, fmi_type="CoSimulation")
    q = np.column_stack([result[f"q[{k}]"] for k in range(1, 7)])
    qd = np.column_stack([result[f"qd[{k}]"] for k in range(1, 7)])
    if result["time"].shape != ref["t"].shape or np.abs(result["time"] - ref["t"]).max() > 1e-12:
        sys.exit(f"new user: FMI {version}: communication points {result['time']} differ from {ref['t']}")
    err = max(np.abs(q - ref["q"]).max(), np.abs(qd - ref["qd"]).max())
    moved = np.abs(ref["qd"][-1] - ref["qd"][0]).max()
    if err > 1e-9 or moved < 1e-3:
        sys.exit(f"new user: FMI {version}: FMU against spacearm.simulate: max difference {err:.3g}, motion {moved:.3g}")
    print(f"  FMI {version}: FMPy validates the FMU; its q, qd equal spacearm.simulate's to {err:.1e} (motion {moved:.2f} rad/s)")
PY
cd "$root"

if [ "$main_job" = 1 ]; then
    bash scripts/readme-main-job.sh
fi
say "passed"
