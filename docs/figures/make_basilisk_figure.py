"""Draw docs/figures/basilisk_mission.png and basilisk_compensator.png: run the Python blocks of docs/basilisk.md in order (as
tests/test_doc_blocks.py does) in a temporary directory and keep the figure they write.

    PYTHONPATH=python python3 docs/figures/make_basilisk_figure.py
"""

from __future__ import annotations

import os
import re
import runpy
import shutil
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
PAGE = HERE.parent / "basilisk.md"
FIGURES = ("basilisk_mission.png", "basilisk_compensator.png")


def page_code() -> str:
    code, inside = [], False
    for line in PAGE.read_text().splitlines():
        fence = re.match(r"^```(\w*)", line)
        if fence and not inside:
            inside, keep = True, fence.group(1) == "python"
            continue
        if fence and inside:
            inside = False
            continue
        code.append(line if inside and keep else "")
    return "\n".join(code)


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "basilisk_page.py"
        script.write_text(page_code())
        cwd = os.getcwd()
        os.chdir(tmp)
        try:
            runpy.run_path(str(script), run_name="__main__")
        finally:
            os.chdir(cwd)
        for name in FIGURES:
            shutil.copy(Path(tmp) / name, HERE / name)
    for name in FIGURES:
        print("wrote", HERE / name)


if __name__ == "__main__":
    main()
