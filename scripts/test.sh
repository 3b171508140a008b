#!/usr/bin/env bash
# Install the package with its test extras, then run every test: the Rust core's (cargo) and
# the Python suite (pytest). This is the README's test command and what CI runs.
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m pip install -e ".[test]"
cargo test -p spacearm-core
python3 -m pytest tests -q
