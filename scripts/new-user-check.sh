#!/usr/bin/env bash
# What a new user sees, checked before the test suite (CI's first stage; runnable by anyone).
#
# 1. Build the wheel and install it into a fresh venv with NO extras; the CLI must start:
#    `spacearm --version`, `python -m spacearm --version`, and `--help` of every subcommand.
#    A command that needs a missing extra must answer one line naming the extra, exit 2, and
#    print no traceback.
# 2. In another fresh venv, run the README's main-job command exactly as the README writes it
#    (scripts/readme_command.py reads it from the block marked `<!-- ci: main-job -->`).
#
# Usage: bash scripts/new-user-check.sh [WHEEL]   (default: build one with maturin into dist/)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

say() { printf '\n== new user: %s\n' "$*"; }

wheel=${1:-}
if [ -z "$wheel" ]; then
    say "building the wheel"
    python3 -m pip install --quiet "maturin>=1.9.4,<2"
    rm -rf dist/new-user && python3 -m maturin build --release --quiet -o dist/new-user
    wheel=$(ls dist/new-user/spacearm-*.whl)
fi

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
cd "$root"

say "the README's main job, exactly as written, in a fresh venv"
main_job=$(python3 scripts/readme_command.py main-job)
echo "\$ $main_job"
python3 -m venv "$work/readme"
"$work/readme/bin/pip" install --quiet --upgrade pip
start=$(date +%s)
# The README's command runs with the venv first on PATH, as after `source venv/bin/activate`.
( export VIRTUAL_ENV="$work/readme" PATH="$work/readme/bin:$PATH"; bash -euo pipefail -c "$main_job" )
echo "README main job took $(( $(date +%s) - start )) s (including the build)"
for f in spatial6_computed_torque.png spatial6_torque_free.png spatial6_computed_torque.gif spatial6_computed_torque.npz; do
    test -s "spacearm-demo/$f" || { echo "the main job did not write spacearm-demo/$f" >&2; exit 1; }
done
say "passed"
