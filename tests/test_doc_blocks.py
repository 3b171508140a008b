"""Every code block of README.md and docs/**/*.md runs as written.

The contract (also stated in docs/contributing.md):

- ```` ```python ```` blocks of one page run in order in ONE namespace: they are written, with
  every other line of the page blanked, to a script that ``python`` runs, so a traceback's line
  numbers are the page's line numbers. The script runs as ``__main__`` (a page may use an
  ``if __name__ == "__main__":`` guard, as code that starts worker processes must).
- ```` ```bash ```` / ```` ```sh ```` / ```` ```shell ```` blocks run with ``bash -e`` after the
  page's Python, in the same directory.
- Both run in a fresh, empty temporary directory outside the repository, as a reader's would
  (no path of the source tree resolves there: the example models ship in the package,
  ``spacearm.examples``), with matplotlib's Agg back end; files a page writes land there.
- A block whose info string has the word ``skip`` (```` ```python skip ````) is deliberately
  partial and is not run; the line right above its fence must be an HTML comment
  ``<!-- skip: the reason -->``. Other languages (``text``, ``toml``, ``console``, none) are
  never run.

Extra words in the info string (markdown-exec's ``exec="on" session=...``) are allowed.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import List

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs").rglob("*.md"))
PYTHON_LANGS = {"python", "py", "python3"}
SHELL_LANGS = {"bash", "sh", "shell"}
#: Seconds one page may take (its Python script, then each shell block).
PAGE_TIMEOUT = 170

_FENCE = re.compile(r"^(?P<indent>[ \t]*)(?P<fence>`{3,}|~{3,})(?P<info>.*)$")
#: Commands a shell block must never run in a test (they install or run the whole suite): such
#: blocks must be marked ``skip``; the test fails instead of running them.
_FORBIDDEN = re.compile(r"\b(pip3?\s+install|maturin|scripts/test\.sh|cargo\s+(build|test|install))\b")
_SKIP_REASON = re.compile(r"^\s*<!--\s*skip:\s*\S.*-->\s*$")


@dataclass
class Block:
    lang: str  # first word of the info string, lower case ("" when there is none)
    words: List[str]  # the other words of the info string
    first_line: int  # 1-based line number of the first code line
    code: List[str]  # code lines, fence indentation removed
    line_above: str  # the page line right above the opening fence

    @property
    def skipped(self) -> bool:
        return "skip" in self.words


def parse_blocks(text: str) -> List[Block]:
    """The fenced code blocks of a Markdown text (CommonMark fences, indented ones included)."""
    lines = text.splitlines()
    blocks: List[Block] = []
    i = 0
    while i < len(lines):
        m = _FENCE.match(lines[i])
        if not m or (m.group("fence")[0] == "`" and "`" in m.group("info")):
            i += 1
            continue
        indent, fence = len(m.group("indent")), m.group("fence")
        info = m.group("info").strip().split()
        lang = info[0].lower().lstrip("{.").rstrip("}") if info else ""
        start = i + 1
        j = start
        close = re.compile(r"^[ \t]*" + re.escape(fence[0]) + "{" + str(len(fence)) + r",}\s*$")
        while j < len(lines) and not close.match(lines[j]):
            j += 1
        code = [ln[indent:] if ln[:indent].strip() == "" else ln.lstrip() for ln in lines[start:j]]
        blocks.append(Block(lang, info[1:], start + 1, code, lines[i - 1] if i > 0 else ""))
        i = j + 1
    return blocks


def _page_id(page: Path) -> str:
    return str(page.relative_to(ROOT))


def _runnable(page: Path) -> List[Block]:
    return [b for b in parse_blocks(page.read_text(encoding="utf-8"))
            if not b.skipped and (b.lang in PYTHON_LANGS or b.lang in SHELL_LANGS)]


def _workdir(tmp_path: Path) -> Path:
    """An empty directory outside the repository (pytest's tmp_path), as a reader's would be."""
    assert ROOT not in tmp_path.resolve().parents, f"{tmp_path} is inside the repository"
    assert not any(tmp_path.iterdir()), f"{tmp_path} is not empty"
    return tmp_path


def _run(cmd, cwd: Path, what: str) -> None:
    env = dict(os.environ, MPLBACKEND="Agg")
    # A session of its own, so that a timeout ends every process the block started.
    proc = subprocess.Popen(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=PAGE_TIMEOUT)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        pytest.fail(f"{what} ran past {PAGE_TIMEOUT} s")
    if proc.returncode != 0:
        pytest.fail(f"{what} failed (exit {proc.returncode}):\n--- stdout ---\n{out[-4000:]}"
                    f"\n--- stderr ---\n{err[-6000:]}")


RUNNABLE_PAGES = [p for p in PAGES if _runnable(p)]


@pytest.mark.parametrize("page", RUNNABLE_PAGES, ids=_page_id)
def test_page_blocks_run(page: Path, tmp_path: Path) -> None:
    blocks = _runnable(page)
    for b in blocks:
        forbidden = _FORBIDDEN.search("\n".join(b.code)) if b.lang in SHELL_LANGS else None
        assert not forbidden, (f"{_page_id(page)}:{b.first_line}: a doc block must not run "
                               f"`{forbidden.group(0)}`; mark it `skip` with a reason")
    cwd = _workdir(tmp_path)
    n_lines = len(page.read_text(encoding="utf-8").splitlines())
    python = [b for b in blocks if b.lang in PYTHON_LANGS]
    if python:
        # One script, line for line with the page, so tracebacks cite the page's line numbers.
        script = [""] * n_lines
        for b in python:
            for k, line in enumerate(b.code):
                script[b.first_line - 1 + k] = line
        path = cwd / (page.name + ".py")
        path.write_text("\n".join(script) + "\n", encoding="utf-8")
        _run([sys.executable, path.name], cwd, f"{_page_id(page)}: the Python blocks")
    for b in blocks:
        if b.lang in SHELL_LANGS:
            _run(["bash", "-e", "-c", "\n".join(b.code)], cwd, f"{_page_id(page)}:{b.first_line}: the {b.lang} block")


@pytest.mark.parametrize("page", PAGES, ids=_page_id)
def test_skipped_blocks_give_a_reason(page: Path) -> None:
    missing = [b.first_line for b in parse_blocks(page.read_text(encoding="utf-8"))
               if b.skipped and not _SKIP_REASON.match(b.line_above)]
    assert not missing, (f"{_page_id(page)}: the skipped blocks starting at lines {missing} need an "
                         "HTML comment `<!-- skip: reason -->` right above their fence")


def test_parser_reads_fences() -> None:
    text = "\n".join([
        "intro", "```python", "a = 1", "```", "", "<!-- skip: partial -->", "```python skip", "b = (",
        "```", "- item", "", "    ```bash", "    echo hi", "    ```", "~~~toml", "x = 1", "~~~",
        '```python exec="on" session="s"', "print(a)", "```", "```", "plain", "```",
    ])
    blocks = parse_blocks(text)
    assert [(b.lang, b.skipped, b.first_line, b.code) for b in blocks] == [
        ("python", False, 3, ["a = 1"]),
        ("python", True, 8, ["b = ("]),
        ("bash", False, 13, ["echo hi"]),
        ("toml", False, 16, ["x = 1"]),
        ("python", False, 19, ["print(a)"]),
        ("", False, 22, ["plain"]),
    ]
    assert _SKIP_REASON.match(blocks[1].line_above)


def test_the_pages_have_blocks_to_run() -> None:
    # Guards the parser against silently finding nothing: the README's quick start is Python.
    assert any(b.lang == "python" for b in _runnable(ROOT / "README.md"))
    assert len(RUNNABLE_PAGES) >= 10


def test_site_hook_hides_the_skip_word() -> None:
    # The site (scripts/mkdocs_hooks.py) renders ```python skip as ```python; other fences unchanged.
    import importlib.util

    spec = importlib.util.spec_from_file_location("mkdocs_hooks", ROOT / "scripts" / "mkdocs_hooks.py")
    hooks = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hooks)
    text = '```python skip\na\n```\n  ```bash skip\n```python exec="on" session="s"\n~~~sh skip\n```\n'
    assert hooks.on_page_markdown(text) == '```python\na\n```\n  ```bash\n```python exec="on" session="s"\n~~~sh\n```\n'
