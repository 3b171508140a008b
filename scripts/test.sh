#!/usr/bin/env bash
# Install the package with its test extras, then run every test: the Rust core's (cargo) and
# the Python suite (pytest). This is the README's test command and what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m pip install -e ".[test]"
# Basilisk for tests/basilisk, without its pins (bsk 2.12.1 pins matplotlib <= 3.10.9, pillow <= 12.2.0,
# tqdm == 4.67.3, which the other extras' tests must not be held to; pyproject.toml's `basilisk` extra).
python3 -m pip install --no-deps "bsk>=2.12"
cargo test -p spacearm-core
# The C ABI: header check, C test (also sanitized) and C example; builds the library the FMU tests use.
bash scripts/c-tests.sh
# The suite runs on every core (pytest-xdist); tests are independent (each writes under tmp_path).
python3 -m pytest tests -q -n auto
