"""The browser check of the built site (``scripts/check_site_browser.py``, run by
``scripts/docs.sh``): on small pages in a real headless Chromium, so that it can fail — a page whose
maths KaTeX typesets passes; one without the renderer, and one with LaTeX KaTeX cannot parse, fail."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

import browser

ROOT = Path(__file__).resolve().parents[1]
KATEX = Path("/usr/share/javascript/katex")


def _checker():
    spec = importlib.util.spec_from_file_location("check_site_browser", ROOT / "scripts" / "check_site_browser.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


check = _checker()


def _page(tmp_path: Path, name: str, formula: str, *, renderer: bool) -> Path:
    scripts = ""
    if renderer:
        scripts = (
            f'<link rel="stylesheet" href="{(KATEX / "katex.min.css").as_uri()}">'
            f'<script src="{(KATEX / "katex.min.js").as_uri()}"></script>'
            f'<script src="{(KATEX / "contrib" / "auto-render.js").as_uri()}"></script>'
            "<script>document.addEventListener('DOMContentLoaded', () => {"
            " for (const e of document.querySelectorAll('.arithmatex')) renderMathInElement(e,"
            " {delimiters: [{left: '\\\\(', right: '\\\\)', display: false}], throwOnError: false}); });</script>"
        )
    body = "".join(f"<p>line {i}</p>" for i in range(12))
    path = tmp_path / name
    path.write_text(f'<!DOCTYPE html><html><head><meta charset="utf-8">{scripts}</head><body>{body}<p><span class="arithmatex">\\({formula}\\)</span></p></body></html>')
    return path


def test_the_audit_counts_typeset_and_raw_maths():
    dom = ('<div><span class="arithmatex"><span class="katex">x</span></span>'
           '<span class="arithmatex">\\(y\\)</span><br><span class="katex-error">z</span></div>')
    result = check.audit(dom)
    assert (result.maths, result.rendered, result.errors) == (2, 1, 1)


@pytest.mark.skipif(not KATEX.is_dir(), reason="Debian's libjs-katex is not installed")
def test_typeset_maths_passes_and_raw_or_broken_maths_fails(tmp_path):
    good = _page(tmp_path, "good.html", "H^* = H_m - H_{0m}^T H_0^{-1} H_{0m}", renderer=True)
    raw = _page(tmp_path, "raw.html", "H^*", renderer=False)
    broken = _page(tmp_path, "broken.html", "\\frac{1}{", renderer=True)
    assert check.problems_of_page("good", browser.dump_dom(good)) == []
    assert "1 of 1 maths elements were not typeset" in " ".join(check.problems_of_page("raw", browser.dump_dom(raw)))
    # auto-render keeps LaTeX it cannot parse as raw text (KaTeX itself would write a katex-error)
    assert check.problems_of_page("broken", browser.dump_dom(broken)) == ["broken: 1 of 1 maths elements were not typeset by KaTeX"]
