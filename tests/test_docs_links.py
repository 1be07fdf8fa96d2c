"""The Markdown documentation holds together: every relative link of README.md, docs/ and
bench/README.md names a file or folder that exists and, with a ``#anchor``, a heading of the
Markdown file it names; README.md stays a front page; docs/README.md lists every page of docs/.

Anchors are GitHub's: the heading's text, lower case, without anything but letters, digits,
spaces, hyphens and underscores, spaces made hyphens; a repeated heading gets ``-1``, ``-2`` ….
Links and headings inside fenced code blocks, and links inside code spans, are not links.
"""

from __future__ import annotations

import re
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote

import pytest

ROOT = Path(__file__).resolve().parents[1]
FRONT_PAGE_LINES = 200

FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})")
HEADING = re.compile(r"^ {0,3}#{1,6}[ \t]+(.*?)(?:[ \t]+#+)?[ \t]*$")
HTML_ANCHOR = re.compile(r"""<a\s+(?:id|name)\s*=\s*["']([^"']+)["']""")
# a code span: a run of backticks, text not crossing a blank line, the same run again
CODE_SPAN = re.compile(r"(?<!`)(`+)(?!`)((?:(?!\n[ \t]*\n).)+?)(?<!`)\1(?!`)", re.DOTALL)
INLINE_LINK = re.compile(r"!?\[(?P<text>[^\]\n]*(?:\n[^\]\n]*)?)\]\(\s*<?(?P<target>[^)\s>]*)>?(?:\s+\"[^\"]*\")?\s*\)")
LINK_DEFINITION = re.compile(r"^ {0,3}\[(?P<text>[^\]]+)\]:[ \t]*<?(?P<target>[^\s>]+)>?", re.MULTILINE)
MARKDOWN_LINK_IN_HEADING = re.compile(r"!?\[([^\]]*)\]\([^)]*\)")
NOT_IN_SLUG = re.compile(r"[^\w\- ]")
EXTERNAL = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")  # http:, https:, mailto:, any other scheme


@dataclass(frozen=True)
class Link:
    source: Path
    line: int
    text: str
    target: str


def documents() -> list[Path]:
    """The Markdown files whose links are checked."""
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md")), ROOT / "bench" / "README.md"]


def github_slug(heading: str) -> str:
    """The anchor GitHub gives a heading (before the suffix of a repeated one)."""
    text = MARKDOWN_LINK_IN_HEADING.sub(r"\1", heading).strip().lower()
    return NOT_IN_SLUG.sub("", text).replace(" ", "-")


def closes(fence: str, line: str) -> bool:
    """Whether ``line`` ends the code block that ``fence`` opened: the same character, at least
    as many, and nothing after them."""
    closing = FENCE.match(line)
    if closing is None:
        return False
    run = closing.group(1)
    return run[0] == fence[0] and len(run) >= len(fence) and not line[closing.end():].strip()


def without_fenced_code(text: str) -> list[str]:
    """The lines of ``text``, those of fenced code blocks (fences included) left empty."""
    lines = []
    fence = ""
    for line in text.splitlines():
        if fence:
            fence = "" if closes(fence, line) else fence
            lines.append("")
        elif opening := FENCE.match(line):
            fence = opening.group(1)
            lines.append("")
        else:
            lines.append(line)
    return lines


def blank_code_spans(text: str) -> str:
    """``text`` with every code span replaced by spaces, line breaks kept, so offsets stay."""
    return CODE_SPAN.sub(lambda span: re.sub(r"[^\n]", " ", span.group()), text)


def anchors(path: Path) -> set[str]:
    """The anchors of a Markdown file: its headings' slugs and its HTML ``<a id>`` anchors."""
    seen: Counter[str] = Counter()
    found = set()
    for line in without_fenced_code(path.read_text(encoding="utf-8")):
        heading = HEADING.match(line)
        if heading:
            slug = github_slug(heading.group(1))
            found.add(f"{slug}-{seen[slug]}" if seen[slug] else slug)
            seen[slug] += 1
        found.update(HTML_ANCHOR.findall(blank_code_spans(line)))
    return found


def links(path: Path) -> list[Link]:
    """The inline links, images and link definitions of a Markdown file, outside code."""
    prose = blank_code_spans("\n".join(without_fenced_code(path.read_text(encoding="utf-8"))))
    found = []
    for pattern in (INLINE_LINK, LINK_DEFINITION):
        for match in pattern.finditer(prose):
            line = prose.count("\n", 0, match.start()) + 1
            found.append(Link(path, line, match.group("text"), match.group("target")))
    return sorted(found, key=lambda link: link.line)


def shown(path: Path) -> str:
    """``path`` from the repository root, or as it is when outside the repository."""
    return path.relative_to(ROOT).as_posix() if path.is_relative_to(ROOT) else str(path)


def problem(link: Link) -> str | None:
    """Why ``link`` does not resolve, or None when it does."""
    if EXTERNAL.match(link.target):
        return None
    address, _, anchor = link.target.partition("#")
    address, anchor = unquote(address), unquote(anchor)
    if not address:
        target = link.source
    elif address.startswith("/"):
        target = ROOT / address.lstrip("/")
    else:
        target = link.source.parent / address
    if not target.exists():
        return f"no such file or folder {address}"
    if not anchor:
        return None
    if target.is_dir():
        target = target / "README.md"
    if target.suffix != ".md" or not target.is_file():
        return None
    if anchor not in anchors(target):
        return f"no heading with the anchor #{anchor} in {shown(target)}"
    return None


def broken_links(paths: list[Path]) -> list[str]:
    """One line per link that does not resolve: file:line, the link and why."""
    broken = []
    for path in paths:
        for link in links(path):
            reason = problem(link)
            if reason:
                broken.append(f"{shown(path)}:{link.line}: [{link.text}]({link.target}): {reason}")
    return broken


def test_every_relative_link_of_the_documentation_resolves() -> None:
    broken = broken_links(documents())
    assert not broken, f"{len(broken)} broken link(s):\n" + "\n".join(broken)


def test_the_readme_is_a_front_page() -> None:
    lines = (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
    assert len(lines) < FRONT_PAGE_LINES, f"README.md has {len(lines)} lines; move detail into docs/"


def test_the_docs_index_lists_every_page() -> None:
    index = ROOT / "docs" / "README.md"
    listed = {(index.parent / unquote(link.target.partition("#")[0])).resolve() for link in links(index)}
    pages = {page.resolve() for page in (ROOT / "docs").rglob("*.md") if page != index}
    missing = sorted(page.relative_to(ROOT).as_posix() for page in pages - listed)
    assert not missing, f"docs/README.md does not list: {', '.join(missing)}"


SLUGS = {
    "`earl-m2t verify`: system-level model checking with SPIN": "earl-m2t-verify-system-level-model-checking-with-spin",
    "4. Conditions: the predicate language": "4-conditions-the-predicate-language",
    "The switch between processes: `switch_protocol.hpp`": "the-switch-between-processes-switch_protocolhpp",
    "The files a change touches: `--affected OUT_DIR --target T`":
        "the-files-a-change-touches---affected-out_dir---target-t",
    "A repository's own rules": "a-repositorys-own-rules",
    "See [the guide](docs/modelling-guide.md)": "see-the-guide",
}


@pytest.mark.parametrize(("heading", "slug"), SLUGS.items())
def test_a_heading_gets_githubs_anchor(heading: str, slug: str) -> None:
    assert github_slug(heading) == slug


def test_broken_links_are_all_reported_with_file_and_line(tmp_path: Path) -> None:
    (tmp_path / "other.md").write_text("# Other\n\n## Part\n\n## Part\n", encoding="utf-8")
    page = tmp_path / "page.md"
    page.write_text(
        "# Page\n\n"
        "[fine](other.md#part-1) and [fine](#page) and [web](https://example.org/missing)\n"
        "[gone](missing.md) and `[in a span](missing.md)`\n"
        "```\n[in a block](missing.md)\n# Heading in a block\n```\n"
        "[bad anchor](other.md#part-2) and [no such heading](#heading-in-a-block)\n"
        "[label]: also-missing.md\n",
        encoding="utf-8")
    assert broken_links([page]) == [
        f"{page}:4: [gone](missing.md): no such file or folder missing.md",
        f"{page}:9: [bad anchor](other.md#part-2): no heading with the anchor #part-2 in {tmp_path / 'other.md'}",
        f"{page}:9: [no such heading](#heading-in-a-block): no heading with the anchor #heading-in-a-block in "
        f"{page}",
        f"{page}:10: [label](also-missing.md): no such file or folder also-missing.md",
    ]
