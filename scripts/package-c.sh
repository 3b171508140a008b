#!/usr/bin/env bash
# The C library's release artifact (docs/c-api.md, "Getting the library"):
#
#   bash scripts/package-c.sh [OUT_DIR]     # default dist/
#
# builds crates/spacearm-c in release (reusing target/) and writes
# OUT_DIR/spacearm-c-<version>-<os>-<arch>.tar.gz holding include/spacearm.h,
# lib/libspacearm_c.{so,a} (.dylib on macOS), lib/pkgconfig/spacearm.pc,
# lib/cmake/spacearm/spacearm-config.cmake (target spacearm::spacearm) and the licences. Unpack it
# anywhere: the pkg-config and CMake files locate the rest relative to themselves (the layout is
# scripts/stage-c-prefix.sh's, which also fills the wheel's spacearm/c/).
# Also run by scripts/c-tests.sh, which builds the C example against the unpacked artifact
# through pkg-config and through CMake (when they are installed).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-dist}
cargo build --release -p spacearm-c
version=$(sed -n 's/^version = "\(.*\)"$/\1/p' Cargo.toml | head -1)
os=$(uname -s | tr '[:upper:]' '[:lower:]')
arch=$(uname -m)
name=spacearm-c-$version-$os-$arch
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
root=$stage/$name
# The layout (header, libraries, pkg-config and CMake files) is scripts/stage-c-prefix.sh's.
bash scripts/stage-c-prefix.sh "$root" target/release --static
cp LICENSE-MIT LICENSE-APACHE "$root/"
mkdir -p "$out"
tar -C "$stage" -czf "$out/$name.tar.gz" "$name"
echo "package-c: wrote $out/$name.tar.gz"
