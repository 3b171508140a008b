#!/usr/bin/env bash
# The C ABI (crates/spacearm-c, docs/c-api.md): build the library (release, reusing target/),
# check the committed header against cbindgen's (a Rust test of the crate), then compile the C
# test and the C example with the system compiler and run them: the test against the shared
# library, again under AddressSanitizer and UBSan, and the example linked statically. Called by
# scripts/test.sh (so the FMU tests of the Python suite find target/release/libspacearm_c.so).
set -euo pipefail
cd "$(dirname "$0")/.."
cc=${CC:-cc}
cargo build --release -p spacearm-c
cargo test --release -p spacearm-c
lib=$PWD/target/release
inc=crates/spacearm-c/include
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
flags=(-std=c11 -Wall -Wextra -Werror -I "$inc")
"$cc" "${flags[@]}" crates/spacearm-c/tests/c/test_c_api.c -L "$lib" -lspacearm_c -lm -Wl,-rpath,"$lib" -o "$out/test_c_api"
"$out/test_c_api"
if echo 'int main(void){return 0;}' | "$cc" -fsanitize=address,undefined -x c - -o "$out/probe" 2>/dev/null; then
    "$cc" "${flags[@]}" -g -fsanitize=address,undefined -fno-omit-frame-pointer crates/spacearm-c/tests/c/test_c_api.c \
        -L "$lib" -lspacearm_c -lm -Wl,-rpath,"$lib" -o "$out/test_c_api_san"
    UBSAN_OPTIONS=halt_on_error=1 "$out/test_c_api_san"
else
    echo "c-tests: $cc has no AddressSanitizer/UBSan runtime here; the sanitized run is skipped" >&2
fi
"$cc" "${flags[@]}" crates/spacearm-c/examples/example.c "$lib/libspacearm_c.a" -lpthread -ldl -lm -o "$out/example"
"$out/example"
