#!/usr/bin/env bash
# Build the documentation site into site/ (strict: any warning — a broken link, a docstring
# mkdocstrings cannot parse, a cross-reference that resolves nowhere — fails the build), then
# check it (scripts/check_site.py: no raw Sphinx role, every public name has an API entry,
# nothing loaded from the network; scripts/check_site_browser.py: the maths typeset in
# Chromium). Works on a fresh clone by itself: it installs what it needs.
#
# - the documentation tools (the `docs` extra's packages);
# - spacearm itself with the `test` extra, when it is not importable: the tutorials are executed
#   during the build (markdown-exec) and need example-robot-data, SymPy, matplotlib;
# - the maths renderer bundled into the site: KaTeX, from Debian's libjs-katex (apt-get, when
#   it is missing and this runs as root), or from $KATEX_DIR (a KaTeX distribution folder).
set -euo pipefail
cd "$(dirname "$0")/.."

python3 -m pip install --quiet \
    "mkdocs>=1.6,<2" "mkdocs-material>=9.5" "mkdocstrings[python]>=0.26" "markdown-exec>=1.9"

if ! python3 -c "import spacearm" 2>/dev/null; then
    echo "scripts/docs.sh: spacearm is not importable: installing it (pip install -e \".[test]\")"
    python3 -m pip install --quiet -e ".[test]"
fi

if [ -z "${KATEX_DIR:-}" ] && [ ! -f /usr/share/javascript/katex/katex.min.js ]; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "scripts/docs.sh: installing the maths renderer (Debian's libjs-katex)"
        apt-get install -y -qq libjs-katex >/dev/null || { apt-get update -qq && apt-get install -y -qq libjs-katex >/dev/null; }
    else
        echo "scripts/docs.sh: KaTeX is missing: install Debian's libjs-katex, or set KATEX_DIR to a KaTeX" \
             "distribution folder (katex.min.js, katex.min.css, contrib/auto-render.js, fonts/)" >&2
        exit 2
    fi
fi

export MPLBACKEND=Agg NO_MKDOCS_2_WARNING=1
python3 -m mkdocs build --strict --site-dir site "$@"
python3 scripts/check_site.py site
# The pages as a reader sees them: every page with maths loaded in headless Chromium, its maths
# typeset by the bundled KaTeX (skipped without Chromium, unless SPACEARM_REQUIRE_BROWSER=1 as in CI).
python3 scripts/check_site_browser.py site --screenshots "${TMPDIR:-/tmp}/spacearm-site-screenshots"
echo "site built: $(pwd)/site/index.html"
