"""MkDocs hooks of the documentation site (mkdocs.yml).

- The doc-test marker ``skip`` leaves fence info strings before rendering: ```` ```python skip ````
  tells ``tests/test_doc_blocks.py`` not to run a block (docs/contributing.md); Markdown renderers
  do not know the word (PyMdown's superfences would not recognize the fence at all), so the site
  sees ```` ```python ````.
- The maths renderer is bundled into the site: KaTeX's script, style sheet, auto-render extension
  and fonts are copied into ``site/javascripts/katex/`` from ``$KATEX_DIR`` or Debian's
  ``libjs-katex`` (``/usr/share/javascript/katex``; ``scripts/docs.sh`` installs it), so the
  pages typeset their maths offline. A missing KaTeX stops the build with that advice.
"""

import os
import re
import shutil
from pathlib import Path

#: Where KaTeX's distribution files are looked for, in order.
KATEX_DIRS = [os.environ.get("KATEX_DIR", ""), "/usr/share/javascript/katex"]
#: The files of the distribution the site uses (with its fonts/ folder).
KATEX_FILES = ("katex.min.js", "katex.min.css", "contrib/auto-render.js")

_SKIP_WORD = re.compile(r"^(?P<fence>[ \t]*(?:`{3,}|~{3,})[^\s`]+)(?P<before>[^\n`]*?)[ \t]+skip(?=[ \t]|$)", re.MULTILINE)


def on_page_markdown(markdown: str, **kwargs) -> str:
    return _SKIP_WORD.sub(lambda m: m.group("fence") + m.group("before"), markdown)


def katex_dir() -> Path:
    for candidate in KATEX_DIRS:
        if candidate and all((Path(candidate) / f).is_file() for f in KATEX_FILES) and (Path(candidate) / "fonts").is_dir():
            return Path(candidate)
    raise SystemExit("mkdocs_hooks: KaTeX not found (the site bundles its maths renderer): install Debian's "
                     "libjs-katex (apt-get install libjs-katex; scripts/docs.sh does) or set KATEX_DIR to a KaTeX "
                     "distribution folder (katex.min.js, katex.min.css, contrib/auto-render.js, fonts/)")


def on_config(config, **kwargs):
    katex_dir()  # fail before building, not after
    # The header and every page title name the version documented (the installed package's,
    # the one the API pages are read from): "spacearm 0.1.0".
    from importlib.metadata import version

    config["site_name"] = f"spacearm {version('spacearm')}"
    return config


def on_post_build(config, **kwargs) -> None:
    source, target = katex_dir(), Path(config["site_dir"]) / "javascripts" / "katex"
    for name in KATEX_FILES:
        (target / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source / name, target / name)
    shutil.copytree(source / "fonts", target / "fonts", dirs_exist_ok=True)
