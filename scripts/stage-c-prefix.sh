#!/usr/bin/env bash
# The installed layout of the C library (docs/c-api.md, "Getting the library"), written under a
# prefix from a built library:
#
#   bash scripts/stage-c-prefix.sh PREFIX LIB_DIR [--static]     # relative paths: from the repository root
#
# PREFIX/include/spacearm.h, PREFIX/lib/libspacearm_c.so (.dylib on macOS) copied from LIB_DIR
# (and libspacearm_c.a with --static), PREFIX/lib/pkgconfig/spacearm.pc and
# PREFIX/lib/cmake/spacearm/spacearm-config{,-version}.cmake (target spacearm::spacearm). The
# pkg-config and CMake files locate the rest relative to themselves, so the prefix can move.
# The one home of this layout, used by scripts/package-c.sh (the release tarball) and by
# scripts/build-wheels.sh (the wheel's spacearm/c/, which `python -m spacearm.c` reads).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 2 ] || [ $# -gt 3 ] || { [ $# -eq 3 ] && [ "$3" != --static ]; }; then
    echo "stage-c-prefix: error: expected PREFIX LIB_DIR [--static], got: $*" >&2
    exit 2
fi
root=$1
lib_dir=$2
static=${3:-}
shared=libspacearm_c.so
[ "$(uname -s)" = Darwin ] && shared=libspacearm_c.dylib
if [ ! -f "$lib_dir/$shared" ]; then
    echo "stage-c-prefix: error: '$lib_dir/$shared' is not a file (build it first: cargo build --release -p spacearm-c)" >&2
    exit 2
fi
version=$(sed -n 's/^version = "\(.*\)"$/\1/p' Cargo.toml | head -1)
mkdir -p "$root/include" "$root/lib/pkgconfig" "$root/lib/cmake/spacearm"
cp crates/spacearm-c/include/spacearm.h "$root/include/"
cp "$lib_dir/$shared" "$root/lib/"
if [ -n "$static" ]; then
    cp "$lib_dir/libspacearm_c.a" "$root/lib/"
fi
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
