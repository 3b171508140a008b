#!/usr/bin/env bash
# Check that a Linux wheel's compiled extensions run on glibc 2.17 (manylinux2014):
#
#   bash scripts/check-wheel-glibc.sh dist/spacearm-0.1.0-cp39-abi3-manylinux_2_17_x86_64.manylinux2014_x86_64.whl
#
# Lists the versioned GLIBC symbols each shared object of the wheel imports, prints the highest
# version and the symbols that need it, and exits 1 if that version is above 2.17 (a wheel that
# then fails to import on RHEL/CentOS 7 and 8, Ubuntu 20.04, Debian 11...), 2 on bad input.
# Needs objdump or readelf (Debian/Ubuntu: apt-get install binutils).
set -euo pipefail

MAX_ALLOWED=2.17

if [ $# -ne 1 ]; then
    echo "check-wheel-glibc: error: expected one argument, the path of a .whl file" >&2
    exit 2
fi
wheel=$1
if [ ! -f "$wheel" ] || [[ "$wheel" != *.whl ]]; then
    echo "check-wheel-glibc: error: '$wheel' is not a .whl file" >&2
    exit 2
fi
if command -v objdump >/dev/null; then
    # objdump -T: "... DF *UND*  ... (GLIBC_2.14) memcpy"
    list_glibc_symbols() { objdump -T "$1" | sed -n 's/.*(\(GLIBC_[0-9.]*\))[[:space:]]*\([^[:space:]]*\)$/\1 \2/p'; }
elif command -v readelf >/dev/null; then
    # readelf --dyn-syms -W: "... UND memcpy@GLIBC_2.14 (3)"
    list_glibc_symbols() { readelf --dyn-syms -W "$1" | sed -n 's/.* \([^[:space:]@]*\)@\{1,2\}\(GLIBC_[0-9.]*\).*/\2 \1/p'; }
else
    echo "check-wheel-glibc: error: neither objdump nor readelf is installed (apt-get install binutils)" >&2
    exit 2
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if ! "${PYTHON:-python3}" -c 'import sys, zipfile; zipfile.ZipFile(sys.argv[1]).extractall(sys.argv[2])' \
    "$wheel" "$work" 2>"$work/unzip.log"; then
    echo "check-wheel-glibc: error: cannot unpack '$wheel': $(tail -n 1 "$work/unzip.log")" >&2
    exit 2
fi

mapfile -t shared_objects < <(find "$work" -type f -name '*.so*' | sort)
if [ ${#shared_objects[@]} -eq 0 ]; then
    echo "check-wheel-glibc: error: '$wheel' holds no shared object (.so)" >&2
    exit 2
fi

status=0
for so in "${shared_objects[@]}"; do
    name=${so#"$work"/}
    symbols=$(list_glibc_symbols "$so" | sort -u)
    if [ -z "$symbols" ]; then
        echo "$name: no versioned GLIBC symbols"
        continue
    fi
    versions=$(cut -d' ' -f1 <<<"$symbols" | sed 's/^GLIBC_//' | sort -u -V)
    highest=$(tail -n 1 <<<"$versions")
    count=$(wc -l <<<"$symbols")
    echo "$name: $count versioned GLIBC symbols; versions: $(tr '\n' ' ' <<<"$versions")"
    needing=$(grep "^GLIBC_$highest " <<<"$symbols" | cut -d' ' -f2)
    n_needing=$(wc -l <<<"$needing")
    shown=$(head -n 8 <<<"$needing" | tr '\n' ' ')
    [ "$n_needing" -gt 8 ] && shown="$shown... ($n_needing symbols)"
    echo "$name: highest GLIBC_$highest, needed by: $shown"
    if [ "$(printf '%s\n%s\n' "$highest" "$MAX_ALLOWED" | sort -V | tail -n 1)" != "$MAX_ALLOWED" ]; then
        echo "check-wheel-glibc: FAIL: $name needs GLIBC_$highest, above the $MAX_ALLOWED of manylinux2014" >&2
        status=1
    fi
done
if [ $status -eq 0 ]; then
    echo "check-wheel-glibc: OK: $(basename "$wheel") needs at most GLIBC_$MAX_ALLOWED"
fi
exit $status
