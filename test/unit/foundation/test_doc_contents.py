"""Every long page of the README and docs/ opens with a table of contents that is true: a list of links,
before the first section, that names every section (``##``) of the page and leads to a heading that exists.
Links into a page (``#anchor``, ``page.md#anchor``) anywhere in the docs must also lead to a heading.
Anchors follow GitHub's rule: the heading's text without markup, lower case, punctuation dropped,
each space a hyphen, and ``-1``, ``-2``, ... for repeated headings."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
LONG = 80  # lines: a page longer than this needs a table of contents

LINK = re.compile(r"\[([^\]]*)\]\(([^)\s]*)\)")


def _prose_lines(text: str) -> list[str]:
    """The page's lines outside fenced code blocks (a ``# comment`` in a bash block is no heading)."""
    lines, fenced = [], False
    for line in text.splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if not fenced:
            lines.append(line)
    return lines


def anchor_of(heading: str) -> str:
    """GitHub's anchor for a heading's text (before the repeat suffix)."""
    text = LINK.sub(r"\1", heading)          # a link shows its text
    text = re.sub(r"<[^>]+>", "", text)      # inline HTML
    text = text.replace("`", "").replace("*", "")
    text = re.sub(r"[^\w\- ]", "", text.strip().lower())
    return text.replace(" ", "-")


def headings(text: str) -> list[tuple[int, str]]:
    """(level, text) of every heading outside code blocks."""
    found = []
    for line in _prose_lines(text):
        match = re.match(r"(#{1,6})\s+(.*?)\s*#*\s*$", line)
        if match:
            found.append((len(match.group(1)), match.group(2)))
    return found


def anchors(text: str) -> set[str]:
    """Every anchor the page's headings make, repeats numbered as GitHub numbers them."""
    seen: dict[str, int] = {}
    result = set()
    for _, heading in headings(text):
        base = anchor_of(heading)
        count = seen.get(base, 0)
        seen[base] = count + 1
        result.add(base if count == 0 else f"{base}-{count}")
    return result


def table_of_contents(text: str) -> list[str]:
    """The anchors linked from the list items before the page's first ``##`` section."""
    targets = []
    for line in _prose_lines(text):
        if line.startswith("## "):
            break
        if re.match(r"\s*[-*] ", line):
            targets += [target[1:] for _, target in LINK.findall(line) if target.startswith("#")]
    return targets


def test_anchor_of_follows_githubs_rule():
    assert anchor_of("Using it from your own shell") == "using-it-from-your-own-shell"
    assert anchor_of("Rank 1: `spec`") == "rank-1-spec"
    assert anchor_of("Messages and actions") == "messages-and-actions"
    assert anchor_of("Recovery & characterization (§4.3)") == "recovery--characterization-43"
    assert anchor_of("[Links](x.md) are text") == "links-are-text"
    assert anchors("# A\n## B\n## B\n```\n## C\n```\n") == {"a", "b", "b-1"}


def test_the_checker_finds_a_broken_table_of_contents():
    page = "# T\n\n- [One](#one)\n- [Gone](#gone)\n\n## One\n\n## Two\n"
    contents = table_of_contents(page)
    assert contents == ["one", "gone"]
    assert set(contents) - anchors(page) == {"gone"}
    assert {anchor_of(h) for level, h in headings(page) if level == 2} - set(contents) == {"two"}


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_a_long_page_has_a_true_table_of_contents(page):
    text = page.read_text(encoding="utf-8")
    if len(text.splitlines()) <= LONG:
        return
    contents = table_of_contents(text)
    assert contents, f"{page.name} has {len(text.splitlines())} lines and no table of contents before its first section"
    missing = [target for target in contents if target not in anchors(text)]
    assert not missing, f"{page.name}: the table of contents links to headings that do not exist: {missing}"
    sections = [anchor_of(h) for level, h in headings(text) if level == 2]
    unlisted = [s for s in sections if s not in contents]
    assert not unlisted, f"{page.name}: sections missing from the table of contents: {unlisted}"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_links_to_a_heading_lead_to_one(page):
    text = page.read_text(encoding="utf-8")
    broken = []
    for _, target in LINK.findall("\n".join(_prose_lines(text))):
        if "#" not in target or target.startswith(("http://", "https://")):
            continue
        where, anchor = target.split("#", 1)
        linked = (page.parent / where) if where else page
        if linked.suffix == ".md" and linked.is_file() and anchor not in anchors(linked.read_text(encoding="utf-8")):
            broken.append(target)
    assert not broken, f"{page.name}: links to headings that do not exist: {broken}"
