"""Check a built documentation site in a real headless browser (Chromium): the maths is typeset.

``scripts/check_site.py`` reads the HTML files as written; this reads the pages as a reader sees
them, after their scripts ran in Chromium from ``file://`` with no network. A page fails when

- one of its ``arithmatex`` elements (the maths that pymdownx.arithmatex leaves for the
  renderer) holds no KaTeX output (the bundled KaTeX did not load or did not run), or
- KaTeX reports an error on it (``katex-error``: LaTeX the renderer could not parse), or
- the page's scripts left no DOM at all.

Every page of the site that has maths is checked (about a second each). With ``--screenshots DIR``
a PNG of each page named in SCREENSHOT_PAGES is written there, to be looked at.

Usage: ``python scripts/check_site_browser.py SITE_DIR [--screenshots DIR]``. Exit 0 when every
page passes, 1 with one line per problem, 2 when no Chromium is found and
``SPACEARM_REQUIRE_BROWSER=1`` (CI) requires one; without that variable a missing browser is
reported and the check is skipped (exit 0).
"""

from __future__ import annotations

import argparse
import os
import sys
from html.parser import HTMLParser
from pathlib import Path
from typing import List, Tuple

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import browser  # noqa: E402  (tests/browser.py: the one Chromium runner)

#: Pages worth a screenshot: two equation-heavy guides and an API page.
SCREENSHOT_PAGES = ("physics/index.html", "orbit/index.html", "api/robot/index.html")


class _MathAudit(HTMLParser):
    """Counts the arithmatex elements, those with KaTeX output inside, and KaTeX errors."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: List[Tuple[str, bool]] = []  # (tag, is_arithmatex) of the open elements
        self.open_math: List[List[bool]] = []  # one [has_katex] per open arithmatex element
        self.maths = 0
        self.rendered = 0
        self.errors = 0
        self.elements = 0

    _VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source", "track", "wbr"}

    def handle_starttag(self, tag, attrs):
        self.elements += 1
        classes = (dict(attrs).get("class") or "").split()
        if "katex-error" in classes:
            self.errors += 1
        if self.open_math and ("katex" in classes or "katex-display" in classes):
            for flag in self.open_math:
                flag[0] = True
        if tag in self._VOID:
            return
        is_math = "arithmatex" in classes
        if is_math:
            self.maths += 1
            self.open_math.append([False])
        self.stack.append((tag, is_math))

    def handle_endtag(self, tag):
        while self.stack:
            open_tag, is_math = self.stack.pop()
            if is_math:
                if self.open_math.pop()[0]:
                    self.rendered += 1
            if open_tag == tag:
                break


def audit(dom: str) -> _MathAudit:
    parser = _MathAudit()
    parser.feed(dom)
    parser.close()
    return parser


def problems_of_page(rel: str, dom: str) -> List[str]:
    result = audit(dom)
    found = []
    if result.elements < 10:
        found.append(f"{rel}: the page's DOM after its scripts ran has {result.elements} elements")
    if result.rendered < result.maths:
        found.append(f"{rel}: {result.maths - result.rendered} of {result.maths} maths elements were not typeset by KaTeX")
    if result.errors:
        found.append(f"{rel}: KaTeX could not parse {result.errors} formula(s) (katex-error)")
    return found


def pages_with_maths(site: Path) -> List[Path]:
    return sorted(p for p in site.rglob("*.html") if 'class="arithmatex"' in p.read_text(encoding="utf-8", errors="replace"))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("site", type=Path)
    parser.add_argument("--screenshots", type=Path, default=None)
    args = parser.parse_args(argv)
    if browser.find_chromium() is None:
        message = "check_site_browser: no Chromium (Debian: apt-get install chromium)"
        if os.environ.get("SPACEARM_REQUIRE_BROWSER") == "1":
            print(message + ", and SPACEARM_REQUIRE_BROWSER=1 requires it", file=sys.stderr)
            return 2
        print(message + ": the browser check is skipped")
        return 0
    pages = pages_with_maths(args.site)
    if not pages:
        print(f"check_site_browser: no page of {args.site} has maths", file=sys.stderr)
        return 1
    problems: List[str] = []
    formulas = 0
    for page in pages:
        rel = page.relative_to(args.site).as_posix()
        dom = browser.dump_dom(page, budget_ms=4000)
        problems += problems_of_page(rel, dom)
        formulas += audit(dom).rendered
    if args.screenshots is not None:
        args.screenshots.mkdir(parents=True, exist_ok=True)
        for rel in SCREENSHOT_PAGES:
            page = args.site / rel
            if page.is_file():
                browser.screenshot(page, args.screenshots / (rel.split("/")[0] + ".png"), width=1280, height=900)
    for line in problems:
        print(line)
    if not problems:
        print(f"check_site_browser: {len(pages)} pages, {formulas} formulas typeset by the bundled KaTeX in Chromium")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
