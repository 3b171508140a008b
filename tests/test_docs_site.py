"""The documentation site's rules that can be checked without building it, and the checker that
``scripts/docs.sh`` runs on the built site (``scripts/check_site.py``: no raw Sphinx role, every
public name has an API entry, nothing loaded from the network), tested on small HTML pages here
so that it can fail."""

from __future__ import annotations

import ast
import importlib.util
import os
import re
import subprocess
import sys
import zlib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "python" / "spacearm"


def _checker():
    spec = importlib.util.spec_from_file_location("check_site", ROOT / "scripts" / "check_site.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


check_site = _checker()


def _docstrings(path: Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            doc = ast.get_docstring(node, clean=False)
            if doc:
                yield node, doc


_SOURCE_ROLE = re.compile(r":(?:py:)?(?:class|meth|func|mod|attr|data|exc|obj|const):`")


def test_no_docstring_uses_a_sphinx_role():
    """Docstrings are Markdown (mkdocstrings renders them): a cross-reference is
    ``[`Robot`][spacearm.Robot]`` (docs/contributing.md), a Sphinx role would show raw."""
    found = []
    for path in sorted(PACKAGE.rglob("*.py")) + [PACKAGE / "_core.pyi"]:
        for node, doc in _docstrings(path):
            for m in _SOURCE_ROLE.finditer(doc):
                found.append(f"{path.relative_to(ROOT)}:{getattr(node, 'lineno', 1)}: {doc[m.start():m.start() + 40]!r}")
    assert not found, "Sphinx roles in docstrings (write [`Name`][spacearm.path]):\n" + "\n".join(found)


def test_the_source_check_sees_a_role():
    assert _SOURCE_ROLE.search("See :class:`~spacearm.Robot`.") and not _SOURCE_ROLE.search("[`Robot`][spacearm.Robot]")


def test_raw_roles_are_found_in_html():
    html = '<p>Build one with :meth:<code>Robot.builder</code> or :class:`Robot`.</p><p><a href="#x">Robot</a></p>'
    assert len(check_site.raw_roles(html)) == 2
    assert check_site.raw_roles('<p>ratio 1:2, a <code>dict</code>: see <a href="../api/">x</a></p>') == []


def test_remote_assets_are_found():
    html = ('<script src="https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex-mml-chtml.js"></script>'
            '<script src="../javascripts/katex/katex.min.js"></script>'
            '<link rel="stylesheet" href="//fonts.googleapis.com/css?family=Roboto">'
            '<link rel="stylesheet" href="../assets/main.css">'
            '<a href="https://doi.org/10.3389/frobt.2018.00041">the paper</a>')
    assert check_site.remote_assets(html) == ["https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex-mml-chtml.js",
                                              "//fonts.googleapis.com/css?family=Roboto"]


def _write_site(tmp_path: Path, names, html="<p>ok</p>"):
    body = "".join(f"{n} py:class 1 api/#$ -\n" for n in names).encode()
    header = b"# Sphinx inventory version 2\n# Project: x\n# Version: 0\n# The remainder of this file is compressed using zlib.\n"
    (tmp_path / "objects.inv").write_bytes(header + zlib.compress(body))
    (tmp_path / "index.html").write_text(html, encoding="utf-8")
    return tmp_path


def test_missing_public_names_are_found(tmp_path):
    import spacearm.examples

    names = {f"spacearm.examples.{n}" for n in spacearm.examples.__all__}
    assert check_site.missing_public_names(names, modules=["spacearm.examples"]) == []
    assert check_site.missing_public_names(names - {"spacearm.examples.path"}, modules=["spacearm.examples"]) == [
        "spacearm.examples.path"]
    site = _write_site(tmp_path, names)
    problems = check_site.check(site)
    assert "no API entry for the public name spacearm.Robot" in problems  # an inventory without the rest


def test_a_page_with_maths_needs_the_bundled_renderer(tmp_path):
    site = _write_site(tmp_path, [], html='<span class="arithmatex">\\(x\\)</span>')
    assert any("has maths, but the site has no" in p for p in check_site.check(site))
    (site / "javascripts" / "katex").mkdir(parents=True)
    (site / check_site.MATH_RENDERER).write_text("", encoding="utf-8")
    assert not any("has maths" in p for p in check_site.check(site))


def test_the_site_config_loads_nothing_from_the_network():
    text = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    section = text.split("extra_javascript:", 1)[1].split("\n\n", 1)[0]
    assert "http" not in section and "katex" in section
    assert re.search(r"^\s+font: false", text, re.MULTILINE)  # no Google Fonts


def test_the_subpackages_are_attributes_imported_on_first_use():
    code = (
        "import sys, spacearm\n"
        "lazy = spacearm._LAZY_SUBPACKAGES\n"
        "assert set(lazy) >= {'plan', 'identify', 'analysis', 'casadi', 'symbolic', 'campaign', 'interop', 'examples'}\n"
        "loaded = [n for n in lazy if f'spacearm.{n}' in sys.modules]\n"
        "assert not loaded, loaded\n"
        "heavy = [m for m in ('casadi', 'sympy', 'dask', 'scipy', 'matplotlib', 'gymnasium') if m in sys.modules]\n"
        "assert not heavy, heavy\n"
        "assert set(lazy) <= set(dir(spacearm))\n"
        "for n in lazy:\n"
        "    m = getattr(spacearm, n)\n"
        "    assert m is sys.modules[f'spacearm.{n}'], n\n"
        "try:\n"
        "    spacearm.no_such_thing\n"
        "except AttributeError as e:\n"
        "    assert 'no_such_thing' in str(e)\n"
        "else:\n"
        "    raise SystemExit('no AttributeError')\n"
    )
    env = dict(os.environ, PYTHONPATH=str(PACKAGE.parent))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr


# A LaTeX command written inside a non-raw Python string ("\tanh", "\frac", "\nabla", "\rho") turns
# into a control character or a line break plus the command's tail ("anh", "rac", "abla", "ho"):
# KaTeX then refuses the formula on the built site. The browser check in scripts/docs.sh finds it
# on the site; this finds it in the sources, in the test run.
_CONTROL = re.compile(r"[\x00-\x09\x0b-\x1f\x7f]")
_BROKEN_COMMAND_TAIL = re.compile(r"^(?:abla|rac\{|ho\^|ho_|artheta|arphi|ightarrow|ext\{|ig/)")


def _text_sources():
    """(where, text): the Markdown pages as written, and every docstring as Python reads it."""
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        yield str(path.relative_to(ROOT)), path.read_text(encoding="utf-8")
    for path in sorted(PACKAGE.rglob("*.py")):
        for node, doc in _docstrings(path):
            yield f"{path.relative_to(ROOT)} ({getattr(node, 'name', 'module')})", doc


def _broken_latex(text: str):
    found = []
    for number, line in enumerate(text.split("\n"), 1):
        if _CONTROL.search(line):
            found.append((number, "control character"))
        elif _BROKEN_COMMAND_TAIL.match(line):
            found.append((number, "a LaTeX command cut by an escape"))
    return found


def test_no_source_has_a_latex_command_turned_into_an_escape():
    bad = []
    for where, text in _text_sources():
        for number, why in _broken_latex(text):
            bad.append(f"{where}: line {number}: {why}")
    assert not bad, "\n".join(bad)


def test_the_escape_check_sees_each_kind():
    assert _broken_latex("a $\x0crac{1}{2}$ b")  # "\frac" in a plain string
    assert _broken_latex("x = \tanh")
    assert _broken_latex("$|\nabla\\phi|$")  # "\nabla": a line break, then "abla"
    assert _broken_latex("$\\phi = \nho^l$")  # "\rho" after line endings were normalized
    assert not _broken_latex("$\\nabla\\phi = \\rho\\,\\frac{1}{2}$\nhow it works")


def test_every_page_title_names_the_version(tmp_path):
    # Issue 37 item 7: the docs header had no version. The hook names it in site_name, so every
    # page title carries it; the checker refuses a page without it.
    from importlib.metadata import version

    generator = '<meta name="generator" content="mkdocs-1.6.1">'
    site = _write_site(tmp_path, [], html=generator + "<title>Home - spacearm</title>")
    assert any("does not name the version" in p for p in check_site.check(site))
    (tmp_path / "b").mkdir()
    site = _write_site(tmp_path / "b", [], html=generator + f"<title>Home - spacearm {version('spacearm')}</title>")
    assert not any("does not name the version" in p for p in check_site.check(site))
