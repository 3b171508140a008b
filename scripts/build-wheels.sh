#!/usr/bin/env bash
# Build the portable Linux wheels and the sdist into dist/:
#
#   bash scripts/build-wheels.sh                 # manylinux2014 x86_64 + aarch64 wheels, sdist
#   bash scripts/build-wheels.sh --x86_64-only   # manylinux2014 x86_64 wheel, sdist (CI)
#
# (SPACEARM_WHEELS_X86_64_ONLY=1 is the same as --x86_64-only.)
#
# The wheels link against glibc 2.17 (manylinux2014: RHEL/CentOS 7 and every newer Linux),
# whatever glibc this machine has: maturin links through zig (`--zig`, zig from the `ziglang`
# PyPI package), which targets an old glibc's symbol versions instead of the host's. Each wheel
# is then checked by scripts/check-wheel-glibc.sh. The extension is abi3 (CPython 3.9+), so one
# wheel per architecture serves every Python version.
#
# Each wheel also ships the C library (crates/spacearm-c, docs/c-api.md), the binary of the FMUs
# that `spacearm fmu` writes: before maturin packs a wheel, the library is built for the same
# target and glibc, linked by the same zig (`maturin zig cc` as cargo's linker), and staged under
# python/spacearm/c/ (include/, lib/ with the pkg-config and CMake files: scripts/stage-c-prefix.sh),
# which pyproject's [tool.maturin] include puts in the wheel. The staged files are removed after
# the last wheel (they are build products, ignored by git), so the sdist and an editable install
# have none: there the library comes from target/release/ (spacearm.c, `python -m spacearm.c`).
# This is one more release build of the core per target (in target/wheel-c/: cargo fingerprints
# the linker, so maturin's build, with its own zig wrapper, cannot reuse these crates). Measured
# on the shared 2-core development machine, x86_64, from cold: 105 s (load ~3) to 249 s (load ~8).
#
# What it installs itself, when missing: maturin and ziglang (pip, into the running Python's
# environment) and the Rust standard library of each target (rustup). A target whose standard
# library cannot be had is reported in one line and skipped; the rest is still built.
# macOS and Windows wheels are built by .github/workflows/release.yml on their own runners.
set -euo pipefail
cd "$(dirname "$0")/.."

PYTHON=${PYTHON:-python3}
OUT_DIR=dist

x86_64_only=${SPACEARM_WHEELS_X86_64_ONLY:-0}
for arg in "$@"; do
    case "$arg" in
        --x86_64-only) x86_64_only=1 ;;
        -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        *) echo "build-wheels: error: unknown argument '$arg' (expected --x86_64-only or --help)" >&2; exit 2 ;;
    esac
done

targets=(x86_64-unknown-linux-gnu)
if [ "$x86_64_only" != 1 ]; then
    targets+=(aarch64-unknown-linux-gnu)
fi

# --- tools -------------------------------------------------------------------------------------
# maturin as pyproject's build-system requires it (1.9.4+: the PEP 639 licence files in both the
# wheel and the sdist); pip leaves a satisfying installed version alone, without the network.
maturin_requirement=$(sed -n 's/^requires = \["\(maturin[^"]*\)"\]$/\1/p' pyproject.toml)
if [ -z "$maturin_requirement" ]; then
    echo "build-wheels: error: no maturin requirement found in pyproject.toml's [build-system]" >&2
    exit 2
fi
"$PYTHON" -m pip install --quiet "$maturin_requirement" ziglang
# maturin finds zig through `python -m ziglang` of the Python it runs under.
MATURIN=("$PYTHON" -m maturin)
echo "build-wheels: $("${MATURIN[@]}" --version), zig $("$PYTHON" -m ziglang version), $(rustc --version)"

have_target() {
    # The standard library of a target is installed when rustc's sysroot has its directory.
    [ -d "$(rustc --print sysroot)/lib/rustlib/$1/lib" ]
}

# The C library's files staged for a wheel (the layout of scripts/stage-c-prefix.sh); the .py
# files of python/spacearm/c/ are the sources and stay.
c_prefix=python/spacearm/c
unstage_c() { rm -rf "$c_prefix/include" "$c_prefix/lib"; }
c_target_dir=target/wheel-c
trap unstage_c EXIT

build_c_library() {
    # The C library for $1 (a Rust target triple), linked through zig against glibc 2.17 like
    # maturin's --zig --compatibility manylinux2014 extension: `maturin zig cc` is the linker.
    # Its own target directory, target/wheel-c/, and a linker wrapper at a fixed path there:
    # cargo's fingerprints include the linker but its file names do not, so in maturin's
    # directory the two builds would overwrite each other's crates and rebuild them all on
    # every run; apart, each is incremental.
    local target=$1 linker=$PWD/$c_target_dir/zigcc-$1.sh
    mkdir -p "$(dirname "$linker")"
    printf '#!/bin/sh\nexec %q -m maturin zig cc -- -target %s "$@"\n' "$PYTHON" "${target%%-*}-linux-gnu.2.17" >"$linker.new"
    chmod +x "$linker.new"
    mv "$linker.new" "$linker"
    local var
    var=CARGO_TARGET_$(tr '[:lower:]-' '[:upper:]_' <<<"$target")_LINKER
    # Only the shared library (the crate's staticlib and rlib are not shipped in the wheel).
    env "$var=$linker" cargo rustc --release -p spacearm-c --target "$target" --target-dir "$c_target_dir" --crate-type cdylib
}

mkdir -p "$OUT_DIR"
# Old artifacts of this project would be checked and shipped with the new ones.
rm -f "$OUT_DIR"/spacearm-*.whl "$OUT_DIR"/spacearm-*.tar.gz

built=()
skipped=()
for target in "${targets[@]}"; do
    if ! have_target "$target"; then
        rustup target add "$target" >/dev/null 2>&1 || true
    fi
    if ! have_target "$target"; then
        echo "build-wheels: SKIPPED $target: its Rust standard library is not installed and 'rustup target add $target' failed (offline?); the other wheels are still built" >&2
        skipped+=("$target")
        continue
    fi
    echo "build-wheels: building the C library for $target"
    c_start=$(date +%s)
    build_c_library "$target"
    unstage_c
    bash scripts/stage-c-prefix.sh "$c_prefix" "$c_target_dir/$target/release"
    echo "build-wheels: the C library for $target took $(( $(date +%s) - c_start )) s"
    echo "build-wheels: building the manylinux2014 wheel for $target"
    "${MATURIN[@]}" build --release --zig --compatibility manylinux2014 \
        --target "$target" --out "$OUT_DIR"
    unstage_c
    built+=("$target")
done

echo "build-wheels: building the sdist"
"${MATURIN[@]}" sdist --out "$OUT_DIR"

# --- checks ------------------------------------------------------------------------------------
for wheel in "$OUT_DIR"/spacearm-*manylinux*.whl; do
    bash scripts/check-wheel-glibc.sh "$wheel"
done

echo "build-wheels: done: ${built[*]} wheel(s) and the sdist in $OUT_DIR/:"
ls -l "$OUT_DIR"/spacearm-*
if [ ${#skipped[@]} -gt 0 ]; then
    echo "build-wheels: NOT built: ${skipped[*]} (see the SKIPPED line above)" >&2
fi
