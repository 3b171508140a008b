"""The README shows what spacearm does (issue 37 item 6): its documentation list links every
page of docs/, its extras paragraph and the getting-started table name every extra of
pyproject.toml, and what they say `all` holds is what pyproject.toml's `all` holds."""

import re
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
GETTING_STARTED = (ROOT / "docs" / "getting-started.md").read_text(encoding="utf-8")
EXTRAS = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["optional-dependencies"]
# Extras for the project's own work, not features of the library.
DEVELOPMENT = {"test", "bench", "docs", "all"}
# User extras that `all` leaves out, with the reason in pyproject.toml: bsk pins matplotlib, pillow
# and tqdm below what the other extras run on.
OUTSIDE_ALL = {"basilisk"}


def _user_extras():
    return sorted(set(EXTRAS) - DEVELOPMENT)


def test_the_readme_links_every_docs_page():
    pages = sorted(p.name for p in (ROOT / "docs").glob("*.md") if p.name != "index.md")
    missing = [p for p in pages if f"(docs/{p})" not in README]
    assert not missing, f"README.md's documentation list lacks {missing}"


def test_all_holds_every_user_extra():
    (spec,) = EXTRAS["all"]
    inside = set(re.search(r"\[(.*)\]", spec).group(1).split(","))
    assert inside == set(_user_extras()) - OUTSIDE_ALL


def test_the_readme_and_getting_started_name_every_extra():
    paragraph = README[README.index("The plain install (`pip install .`)"):]
    paragraph = paragraph[: paragraph.index("\n\n")]
    for extra in _user_extras() + ["all"]:
        assert f"`{extra}`" in paragraph, f"README's extras paragraph lacks `{extra}`"
        assert f"| `{extra}` |" in GETTING_STARTED, f"getting-started's extras table lacks `{extra}`"
    n = len(set(_user_extras()) - OUTSIDE_ALL)
    words = {8: "eight", 9: "nine", 10: "ten", 7: "seven"}
    assert f"every one of these {words[n]}" in paragraph
    assert f"| `all` | the {words[n]} above |" in GETTING_STARTED


def test_no_page_lists_as_missing_what_it_documents():
    # Issue 37 item 6: flexibility.md's "Not yet" listed spherical tanks, documented on the
    # same page ("Spherical tanks").
    page = (ROOT / "docs" / "flexibility.md").read_text(encoding="utf-8")
    not_yet = page[page.index("## Not yet"):]
    assert "## Spherical tanks" in page or "Spherical tanks" in page
    assert "route for a **spherical** tank" not in not_yet
