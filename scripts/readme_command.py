"""Print one of the README's set-up commands, exactly as the README writes it.

The README marks each set-up block with an HTML comment on the line before its fence:
``<!-- ci: main-job -->`` (install and run the main job) and ``<!-- ci: test-command -->``
(install the test needs and run every test). CI runs the printed command as written, so the
README cannot drift from what is checked. Usage: ``python3 scripts/readme_command.py main-job``.
"""

import pathlib
import re
import sys


def readme_command(name: str, readme: pathlib.Path) -> str:
    text = readme.read_text(encoding="utf-8")
    pattern = re.compile(r"<!-- ci: " + re.escape(name) + r" -->\s*\n```[a-z]*\n(.*?)\n```", re.S)
    found = pattern.findall(text)
    if len(found) != 1:
        raise SystemExit(f"readme_command: expected one block marked '<!-- ci: {name} -->' in {readme}, found {len(found)}")
    return found[0].strip()


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit("usage: readme_command.py main-job|test-command")
    root = pathlib.Path(__file__).resolve().parent.parent
    print(readme_command(sys.argv[1], root / "README.md"))
