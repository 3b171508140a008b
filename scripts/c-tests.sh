#!/usr/bin/env bash
# The C ABI (crates/spacearm-c, docs/c-api.md): build the library (release, reusing target/),
# check the committed header against cbindgen's (crates/spacearm-c-header), then compile the C
# test and the C example with the system compiler and run them: the test against the shared
# library, again under AddressSanitizer and UBSan, and the example linked statically, through the
# release artifact's pkg-config file and through its CMake package. Called by
# scripts/test.sh (so the FMU tests of the Python suite find target/release/libspacearm_c.so).
set -euo pipefail
cd "$(dirname "$0")/.."
cc=${CC:-cc}
# One release build of the core serves the extension (pip install -e, before this script) and
# the C library: their features are unified (crates/workspace-hack), so these compile only
# spacearm-c. The header check is its own crate (cbindgen would change this crate's features).
cargo build --release -p spacearm-c
cargo test --release -p spacearm-c
cargo test -p spacearm-c-header
lib=$PWD/target/release
inc=crates/spacearm-c/include
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
flags=(-std=c11 -Wall -Wextra -Werror -I "$inc")
# The C tests (the controllers' test reads python/spacearm/examples/spatial6_wheels.toml from
# the repository root, where this script runs).
tests=(test_c_api test_c_controllers test_c_target)
for t in "${tests[@]}"; do
    "$cc" "${flags[@]}" "crates/spacearm-c/tests/c/$t.c" -L "$lib" -lspacearm_c -lm -Wl,-rpath,"$lib" -o "$out/$t"
    "$out/$t"
done
if echo 'int main(void){return 0;}' | "$cc" -fsanitize=address,undefined -x c - -o "$out/probe" 2>/dev/null; then
    for t in "${tests[@]}"; do
        "$cc" "${flags[@]}" -g -fsanitize=address,undefined -fno-omit-frame-pointer "crates/spacearm-c/tests/c/$t.c" \
            -L "$lib" -lspacearm_c -lm -Wl,-rpath,"$lib" -o "$out/${t}_san"
        UBSAN_OPTIONS=halt_on_error=1 "$out/${t}_san"
    done
else
    echo "c-tests: $cc has no AddressSanitizer/UBSan runtime here; the sanitized run is skipped" >&2
fi
"$cc" "${flags[@]}" crates/spacearm-c/examples/example.c "$lib/libspacearm_c.a" -lpthread -ldl -lm -o "$out/example"
"$out/example"
# The release artifact (scripts/package-c.sh), unpacked: the example through its pkg-config file
# and its CMake package.
bash scripts/package-c.sh "$out/dist" >/dev/null
tar -C "$out" -xzf "$out"/dist/spacearm-c-*.tar.gz
prefix=$(echo "$out"/spacearm-c-*/)
if command -v pkg-config >/dev/null; then
    # shellcheck disable=SC2046
    "$cc" -std=c11 crates/spacearm-c/examples/example.c $(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs spacearm) \
        -o "$out/example_pc"
    "$out/example_pc" >/dev/null
fi
if command -v cmake >/dev/null; then
    mkdir -p "$out/cm"
    cat > "$out/cm/CMakeLists.txt" <<CMAKE
cmake_minimum_required(VERSION 3.16)
project(spacearm_example C)
find_package(spacearm REQUIRED)
add_executable(example "$PWD/crates/spacearm-c/examples/example.c")
target_link_libraries(example PRIVATE spacearm::spacearm m)
CMAKE
    cmake -S "$out/cm" -B "$out/cm/build" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
    cmake --build "$out/cm/build" >/dev/null
    "$out/cm/build/example" >/dev/null
fi
echo "c-tests: passed"
