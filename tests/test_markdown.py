"""Every Markdown file of the repository renders as written: no code fence left open or closed with text after
it (which turns the rest of a guide into one code block), no relative link to a missing file or heading.

Parsed with markdown-it-py, a CommonMark parser (GitHub and JupyterLab render CommonMark)."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

markdown_it = pytest.importorskip("markdown_it")

ROOT = Path(__file__).resolve().parents[1]
PARSER = markdown_it.MarkdownIt("commonmark").enable("table")


def _slug(heading: str) -> str:
    """A heading's anchor as GitHub writes it: lower case, punctuation dropped, spaces as hyphens."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def _headings(text: str) -> set:
    tokens = PARSER.parse(text)
    return {_slug(tokens[i + 1].content) for i, token in enumerate(tokens) if token.type == "heading_open"}


def problems(text: str, path: Path) -> list:
    """What does not render as written in the Markdown ``text`` of the file ``path``, in words."""
    found, lines = [], text.splitlines()
    tokens = PARSER.parse(text)
    for token in tokens:
        if token.type != "fence":
            continue
        start, end = token.map
        if any(line.lstrip().startswith(("```", "~~~")) for line in token.content.splitlines()):
            found.append(f"line {start + 1}: a code block holds a fence line (a closing fence with text after it)")
        last = lines[end - 1].strip() if end - 1 < len(lines) else ""
        if end - 1 == start or not last.startswith(("```", "~~~")):
            found.append(f"line {start + 1}: a code block is never closed")
    for token in tokens:
        for child in token.children or []:
            href = child.attrs.get("href", "") if child.type == "link_open" else ""
            if not href or re.match(r"^[a-z][a-z0-9+.-]*:", href):
                continue
            target, _, anchor = href.partition("#")
            destination = path.parent / target if target else path
            if target and not destination.exists():
                found.append(f"a link to {href}, which does not exist")
            elif anchor and destination.suffix == ".md" and anchor not in _headings(
                    destination.read_text(encoding="utf-8")):
                found.append(f"a link to {href}, a heading that does not exist")
    return found


def _markdown_files() -> list:
    listed = subprocess.run(["git", "ls-files", "*.md"], cwd=ROOT, capture_output=True, text=True, check=False)
    files = listed.stdout.split() if listed.returncode == 0 else [
        str(p.relative_to(ROOT)) for p in ROOT.rglob("*.md") if ".git" not in p.parts]
    return sorted(files)


@pytest.mark.parametrize("name", _markdown_files())
def test_every_markdown_file_renders_as_written(name):
    path = ROOT / name
    assert problems(path.read_text(encoding="utf-8"), path) == []


def test_the_check_finds_a_closing_fence_with_text_an_open_fence_and_a_broken_link(tmp_path):
    path = tmp_path / "guide.md"
    (tmp_path / "there.md").write_text("# A heading\n")
    text = ("# Guide\n\n```bash\nsarsp-edu prefit\n``` From the static pages alone\n\n"
            "## Three sessions\n\n[ok](there.md#a-heading) [gone](missing.md) [no heading](there.md#nowhere)\n")
    found = problems(text, path)
    assert any("closing fence with text" in p for p in found)
    assert any("never closed" in p for p in found)
    assert problems("[ok](there.md#a-heading)\n", path) == []
    assert problems("[gone](missing.md) [no](there.md#nowhere)\n", path) == [
        "a link to missing.md, which does not exist", "a link to there.md#nowhere, a heading that does not exist"]


def _notebooks() -> list:
    return sorted(str(p.relative_to(ROOT)) for p in (ROOT / "tutorials").rglob("*.ipynb")
                  if ".ipynb_checkpoints" not in p.parts)


@pytest.mark.parametrize("name", _notebooks())
def test_every_markdown_cell_of_every_notebook_links_to_what_is_there(name):
    """The answer copies in tutorials/source/ too: a lecturer opens them where they lie."""
    import nbformat

    path = ROOT / name
    cells = nbformat.read(path, as_version=4).cells
    found = [f"cell {i}: {problem}" for i, cell in enumerate(cells) if cell.cell_type == "markdown"
             for problem in problems(cell.source, path)]
    assert found == []
