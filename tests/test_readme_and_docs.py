"""The README and the pages beside it stay true to the repository.

Every relative link in README.md, CHANGELOG.md and docs/*.md names a file that exists (and,
where it names a heading of a Markdown page, a heading that exists); the README is a front
page (at most 150 lines) that opens with the two set-up commands and links every page of
docs/; every runtime dependency in pyproject.toml is named, with its reason, in the table
of docs/libraries.md.

Run as a script, it prints the broken links: python tests/test_readme_and_docs.py
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PAGES = sorted([ROOT / "README.md", ROOT / "CHANGELOG.md", *(ROOT / "docs").glob("*.md")])
SETUP_COMMANDS = [
    "python3 -m pip install -e . && python3 -m scenerender render scenes/showcase.yaml -o out/",
    "make test",
]

_FENCE = re.compile(r"^```.*?^```", re.M | re.S)
_CODE_SPAN = re.compile(r"`[^`\n]*`")
_LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def _prose(text: str) -> str:
    """The text without code blocks and code spans, where brackets are not links."""
    return _CODE_SPAN.sub("", _FENCE.sub("", text))


def _anchors(page: Path) -> set[str]:
    """The anchors GitHub gives a page's headings: lower case, punctuation dropped, spaces to
    hyphens, a repeated heading numbered."""
    anchors: set[str] = set()
    seen: dict[str, int] = {}
    for heading in re.findall(r"^#{1,6} +(.+?) *#*$", _FENCE.sub("", page.read_text(encoding="utf-8")), re.M):
        slug = re.sub(r"[^\w\- ]", "", heading.replace("`", "").lower()).replace(" ", "-")
        anchors.add(f"{slug}-{seen[slug]}" if slug in seen else slug)
        seen[slug] = seen.get(slug, 0) + 1
    return anchors


def broken_links(page: Path) -> list[str]:
    problems = []
    for target in _LINK.findall(_prose(page.read_text(encoding="utf-8"))):
        if re.match(r"[a-z][a-z0-9+.-]*:", target, re.I):  # https:, mailto:
            continue
        path_part, _, anchor = target.partition("#")
        dest = (page.parent / path_part).resolve() if path_part else page
        if not dest.exists():
            problems.append(f"{target}: no such file")
        elif anchor and dest.suffix == ".md" and anchor not in _anchors(dest):
            problems.append(f"{target}: no heading with that anchor in {dest.name}")
    return problems


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_readme_and_docs_relative_links_resolve(page):
    assert broken_links(page) == []


def test_readme_opens_with_the_setup_commands():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    first_block = re.search(r"^```sh\n(.*?)^```", text, re.M | re.S)
    assert first_block and text.index(first_block.group(0)) < text.index("\n## ")
    assert first_block.group(1).splitlines() == SETUP_COMMANDS


def test_the_link_check_catches_a_missing_file_and_a_missing_heading(tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "usage.md").write_text("# Using it\n\n## The commands\n\ntext\n", encoding="utf-8")
    page = tmp_path / "README.md"
    page.write_text("[ok](docs/usage.md) [ok too](docs/usage.md#the-commands) [self](#a-front-page)\n"
                    "# A front page\n[gone](docs/usage.md#the-comands) [missing](docs/ci.md)\n"
                    "`[not a link](docs/none.md)`\n", encoding="utf-8")
    assert broken_links(page) == ["docs/usage.md#the-comands: no heading with that anchor in usage.md",
                                  "docs/ci.md: no such file"]


def test_readme_is_a_front_page_linking_every_doc():
    """A newcomer reads it in two minutes; the manual lives in docs/, every page one link away."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(readme.splitlines()) <= 150
    linked = {target.partition("#")[0] for target in _LINK.findall(_prose(readme))}
    assert sorted(page.name for page in (ROOT / "docs").glob("*.md") if f"docs/{page.name}" not in linked) == []


def test_docs_name_every_dependency_with_its_reason():
    pyproject = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    block = re.search(r"^dependencies = \[(.*?)^\]", pyproject, re.M | re.S).group(1)
    names = re.findall(r"^\s*\"([A-Za-z0-9_.-]+)", block, re.M)
    assert len(names) > 5
    rows = {}
    for line in (ROOT / "docs" / "libraries.md").read_text(encoding="utf-8").splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if line.startswith("|") and len(cells) >= 2:
            rows[cells[0].split(" (")[0].lower()] = cells[1]
    missing = [name for name in names if not rows.get(name.lower())]
    assert missing == [], f"pyproject.toml dependencies without a row and a reason in docs/libraries.md: {missing}"


if __name__ == "__main__":
    found = [(page, problem) for page in PAGES for problem in broken_links(page)]
    for page, problem in found:
        print(f"{page.relative_to(ROOT)}: {problem}")
    print(f"{len(found)} broken link(s) in {len(PAGES)} page(s)")
    sys.exit(1 if found else 0)
