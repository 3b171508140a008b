#!/usr/bin/env bash
# Build the documentation site into site/ (strict: any warning — a broken link, a docstring
# mkdocstrings cannot parse — fails the build). The tutorials are executed during the build
# (markdown-exec), so spacearm itself must be importable, with the packages of the `test`
# extra (example-robot-data, SymPy, matplotlib). Installs the documentation tools it needs.
set -euo pipefail
cd "$(dirname "$0")/.."

python -m pip install --quiet \
    "mkdocs>=1.6,<2" "mkdocs-material>=9.5" "mkdocstrings[python]>=0.26" "markdown-exec>=1.9"

python -c "import spacearm" 2>/dev/null || {
    echo "scripts/docs.sh: spacearm is not importable: install it first (pip install \".[test]\")" >&2
    exit 2
}

export MPLBACKEND=Agg NO_MKDOCS_2_WARNING=1
python -m mkdocs build --strict --site-dir site "$@"
echo "site built: $(pwd)/site/index.html"
