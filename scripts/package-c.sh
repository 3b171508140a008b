#!/usr/bin/env bash
# The C library's release artifact (docs/c-api.md, "Getting the library"):
#
#   bash scripts/package-c.sh [OUT_DIR]     # default dist/
#
# builds crates/spacearm-c in release (reusing target/) and writes
# OUT_DIR/spacearm-c-<version>-<os>-<arch>.tar.gz holding include/spacearm.h,
# lib/libspacearm_c.{so,a} (.dylib on macOS), lib/pkgconfig/spacearm.pc,
# lib/cmake/spacearm/spacearm-config.cmake (target spacearm::spacearm) and the licences. Unpack it
# anywhere: the pkg-config and CMake files locate the rest relative to themselves.
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
shared=libspacearm_c.so
[ "$os" = darwin ] && shared=libspacearm_c.dylib
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
root=$stage/$name
mkdir -p "$root/include" "$root/lib/pkgconfig" "$root/lib/cmake/spacearm"
cp crates/spacearm-c/include/spacearm.h "$root/include/"
cp "target/release/$shared" target/release/libspacearm_c.a "$root/lib/"
cp LICENSE-MIT LICENSE-APACHE "$root/"
cat > "$root/lib/pkgconfig/spacearm.pc" <<PC
prefix=\${pcfiledir}/../..
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: spacearm
Description: Equations of motion of spacecraft-manipulator systems (GJM formulation): the C ABI
Version: $version
Cflags: -I\${includedir}
Libs: -L\${libdir} -Wl,-rpath,\${libdir} -lspacearm_c
Libs.private: -lpthread -ldl -lm
PC
cat > "$root/lib/cmake/spacearm/spacearm-config.cmake" <<'CMAKE'
# spacearm's C ABI as the imported target spacearm::spacearm (the shared library).
get_filename_component(_spacearm_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET spacearm::spacearm)
  add_library(spacearm::spacearm SHARED IMPORTED)
  find_library(_spacearm_lib NAMES spacearm_c PATHS "${_spacearm_prefix}/lib" NO_DEFAULT_PATH REQUIRED)
  set_target_properties(spacearm::spacearm PROPERTIES
    IMPORTED_LOCATION "${_spacearm_lib}"
    INTERFACE_INCLUDE_DIRECTORIES "${_spacearm_prefix}/include")
endif()
CMAKE
echo "set(PACKAGE_VERSION \"$version\")" > "$root/lib/cmake/spacearm/spacearm-config-version.cmake"
mkdir -p "$out"
tar -C "$stage" -czf "$out/$name.tar.gz" "$name"
echo "package-c: wrote $out/$name.tar.gz"
