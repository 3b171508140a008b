"""MkDocs hook: remove the doc-test marker ``skip`` from fence info strings before rendering.

```` ```python skip ```` tells ``tests/test_doc_blocks.py`` not to run a block
(docs/contributing.md); Markdown renderers do not know the word (PyMdown's superfences would
not recognize the fence at all), so the site sees ```` ```python ````.
"""

import re

_SKIP_WORD = re.compile(r"^(?P<fence>[ \t]*(?:`{3,}|~{3,})[^\s`]+)(?P<before>[^\n`]*?)[ \t]+skip(?=[ \t]|$)", re.MULTILINE)


def on_page_markdown(markdown: str, **kwargs) -> str:
    return _SKIP_WORD.sub(lambda m: m.group("fence") + m.group("before"), markdown)
