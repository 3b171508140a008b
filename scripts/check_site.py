"""Check a built documentation site (``bash scripts/docs.sh`` runs this on ``site/``).

Fails (exit 1, one line per problem) when the site

- shows a raw Sphinx role (``:class:`Robot```, ``:func:``...): the docstrings are Markdown, with
  cross-references written ``[`Robot`][spacearm.Robot]`` (docs/contributing.md);
- lacks a public name: every name in the ``__all__`` of each public module (PUBLIC_MODULES) must
  have an entry in the site's inventory (``objects.inv``, written by mkdocstrings), under that
  module's path;
- loads anything from the network: a ``<script src>`` or a stylesheet ``<link href>`` that is not
  a file of the site (the maths renderer and the fonts are bundled: the site reads offline);
- has a page with maths but no bundled maths renderer.

Usage: ``python scripts/check_site.py SITE_DIR``.
"""

from __future__ import annotations

import importlib
import re
import sys
import zlib
from pathlib import Path
from typing import Iterable, List, Set

#: The modules whose ``__all__`` the API pages document (docs/api/).
PUBLIC_MODULES = (
    "spacearm", "spacearm.presets", "spacearm.examples", "spacearm.control", "spacearm.rotations",
    "spacearm.analysis", "spacearm.identify", "spacearm.campaign", "spacearm.capture", "spacearm.interop",
    "spacearm.io", "spacearm.errors", "spacearm.symbolic", "spacearm.casadi", "spacearm.plan", "spacearm.orbit",
    "spacearm.fmi", "spacearm.c", "spacearm.viz.viewer", "spacearm.gym", "spacearm.basilisk", "spacearm.contact",
    "spacearm.mpc",
)

#: A Sphinx role as it shows in HTML: ``:class:`` followed by a backtick or a code element.
RAW_ROLE = re.compile(r":(?:py:)?(?:class|meth|func|mod|attr|data|exc|obj|const|ref|doc|term|math):(?:`|<code)")
_SCRIPT_SRC = re.compile(r"<script\b[^>]*\bsrc=\"([^\"]+)\"", re.IGNORECASE)
_LINK = re.compile(r"<link\b[^>]*>", re.IGNORECASE)
_HREF = re.compile(r"\bhref=\"([^\"]+)\"", re.IGNORECASE)
_REMOTE = re.compile(r"^(?:[a-z]+:)?//", re.IGNORECASE)
#: The maths renderer bundled into the site by scripts/docs.sh (docs/contributing.md).
MATH_RENDERER = "javascripts/katex/katex.min.js"
_MATH = re.compile(r"class=\"arithmatex\"")


def inventory(site: Path) -> Set[str]:
    """The identifiers of the site's ``objects.inv`` (Sphinx inventory version 2)."""
    data = (site / "objects.inv").read_bytes()
    header_end = 0
    for _ in range(4):
        header_end = data.index(b"\n", header_end) + 1
    body = zlib.decompress(data[header_end:]).decode("utf-8")
    return {line.split(" ", 1)[0] for line in body.splitlines() if line.strip()}


def raw_roles(html: str) -> List[str]:
    return [html[max(0, m.start() - 40): m.end() + 40].replace("\n", " ") for m in RAW_ROLE.finditer(html)]


def remote_assets(html: str) -> List[str]:
    found = [src for src in _SCRIPT_SRC.findall(html) if _REMOTE.match(src)]
    for tag in _LINK.findall(html):
        if re.search(r"\brel=\"(?:stylesheet|preload|preconnect|modulepreload)\"", tag, re.IGNORECASE):
            found += [href for href in _HREF.findall(tag) if _REMOTE.match(href)]
    return found


def missing_public_names(names: Set[str], modules: Iterable[str] = PUBLIC_MODULES) -> List[str]:
    missing = []
    for module_name in modules:
        module = importlib.import_module(module_name)
        for name in getattr(module, "__all__", ()):
            if name.startswith("__"):
                continue
            if f"{module_name}.{name}" not in names:
                missing.append(f"{module_name}.{name}")
    return missing


def check(site: Path) -> List[str]:
    problems = []
    pages = sorted(site.rglob("*.html"))
    if not pages:
        return [f"{site}: no HTML pages (build the site first: bash scripts/docs.sh)"]
    renderer = (site / MATH_RENDERER).is_file()
    from importlib.metadata import version

    versioned = f"spacearm {version('spacearm')}"
    for page in pages:
        html = page.read_text(encoding="utf-8")
        rel = page.relative_to(site)
        title = re.search(r"<title>(.*?)</title>", html, re.S)
        # The site's own pages (MkDocs writes its generator tag), not the viewer scenes it ships.
        own = 'name="generator" content="mkdocs' in html
        if own and rel.name != "404.html" and (title is None or versioned not in title.group(1)):
            problems.append(f"{rel}: its title does not name the version ({versioned!r})")
        for snippet in raw_roles(html):
            problems.append(f"{rel}: a raw Sphinx role: ...{snippet}...")
        for url in remote_assets(html):
            problems.append(f"{rel}: loads {url} from the network (bundle it into the site)")
        if _MATH.search(html) and not renderer:
            problems.append(f"{rel}: has maths, but the site has no {MATH_RENDERER}")
    problems += [f"no API entry for the public name {name}" for name in missing_public_names(inventory(site))]
    return problems


def main(argv: List[str]) -> int:
    if len(argv) != 1:
        print("usage: python scripts/check_site.py SITE_DIR", file=sys.stderr)
        return 2
    problems = check(Path(argv[0]))
    for line in problems:
        print(f"check_site: {line}", file=sys.stderr)
    if problems:
        print(f"check_site: {len(problems)} problems", file=sys.stderr)
        return 1
    print(f"check_site: {argv[0]}: no raw roles, every public name has an entry, nothing loaded from the network")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
