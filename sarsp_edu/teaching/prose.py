"""Numbers in a tutorial's prose, traced to the outputs that print them.

A tutorial earns trust when every number its text states can be found where
the reader can see it computed: in the stored output of a code cell *above*
the sentence, printed at the same digits or at more digits that round to it.
A number that comes from outside the notebook (the paper's table, a
definition) is declared once, with its source, in the notebook's visible
"Numbers from elsewhere" cell: a Markdown table whose first column holds the
numbers and whose second says where each comes from.

What counts as a stated number: a decimal (``0.41``, ``1.02e-07``), a
percentage (``43%``), an integer of three or more digits (``226``,
``1,854``) and both ends of a range (``10-23``, ``134 to 1,854``).  What does
not: equation, section, table, figure, exercise, tutorial, chapter and
appendix numbers (``eq. 6``, ``sections 2.1, 3.1-3.2``), years, DOIs and
link targets, and small integers outside a range (counts such as "45
configurations" are read off a table or a setting the text names).

:func:`untraced` lists what a notebook states without a source;
``tests/test_prose.py`` runs it on every source and student notebook.

Examples
--------
>>> [n.text for n in prose_numbers("rmse 0.41, then 0.66; section 3.2; 226 of 226 episodes; 12%")]
['0.41', '0.66', '226', '226', '12%']
>>> traces(prose_numbers("0.41")[0], output_numbers("rmse = 0.4123"))
True
>>> traces(prose_numbers("0.41")[0], output_numbers("rmse = 0.4"))
False
"""

from __future__ import annotations

import re
from dataclasses import dataclass

__all__ = ["ELSEWHERE_HEADING", "REVEAL_TAG", "Number", "prose_numbers", "output_numbers", "traces",
           "declared_numbers", "untraced"]

#: the heading of the cell that declares a notebook's outside numbers
ELSEWHERE_HEADING = "Numbers from elsewhere"
#: the tag of a cell that reveals a prediction's answer (its outputs are not stored in student notebooks)
REVEAL_TAG = "reveal"

_NUMBER = r"\d{1,3}(?:,\d{3})+(?!\d)(?:\.\d+)?|\d+(?:\.\d+)?(?:[eE][-+−]?\d+)?|\.\d+"
_REFERENCE_WORDS = (r"eqs?\.|equations?|sections?|§+|tables?|figures?|figs?\.|exercises?|tutorials?|chapters?|"
                    r"appendix|appendices|algorithm|definitions?|theorem|lemma|pages?|pp?\.|lines?|"
                    r"part|parts|items?|issues?|session|python|version|v")
_LIST = rf"(?:{_NUMBER})[a-z]?(?:\s*(?:,|-|–|and|to|or|&)\s*(?:{_NUMBER})[a-z]?)*"
_REFERENCE = re.compile(rf"\b(?:{_REFERENCE_WORDS})\s*(?:{_LIST})", re.IGNORECASE)
_RANGE = re.compile(rf"(?<!from )(?<![\w.])({_NUMBER})\s*(?:-|–|to)\s*({_NUMBER})(?![\w.]*\d)")
_TOKEN = re.compile(rf"(?<![\w.])[-−]?({_NUMBER})(\s*%)?")


@dataclass(frozen=True)
class Number:
    """A number as written: its text, value, resolution (the unit of its last digit) and whether it is a percent."""

    text: str
    value: float
    resolution: float
    percent: bool = False


def _parse(text: str, percent: bool = False) -> Number:
    plain = text.replace(",", "").replace("−", "-")
    mantissa, _, exponent = plain.lower().partition("e")
    decimals = len(mantissa.partition(".")[2])
    resolution = 10.0 ** (-decimals + (int(exponent) if exponent else 0))
    return Number(text + ("%" if percent else ""), abs(float(plain)), resolution, percent)


def _strip(markdown: str) -> str:
    """The prose without what holds no stated number: link targets, URLs, DOIs, references, years, HTML tags."""
    text = re.sub(r"\]\([^)]*\)", "]", markdown)                       # [text](target) -> [text]
    text = re.sub(r"https?://\S+|doi:\S+|\b10\.\d{4,}/\S+", " ", text)
    text = re.sub(r"<[^>]+>", " ", text)
    text = _REFERENCE.sub(" ", text)
    text = re.sub(r"\b(?:19|20)\d\d[a-z]?\b(?!\s*(?:rows|episodes|steps|points|samples|draws|data|runs|cells))",
                  " ", text)                                            # years (1900-2099)
    text = re.sub(r"\\[a-zA-Z]+", " ", text.replace("{,}", ","))                            # LaTeX command names
    return text


def prose_numbers(markdown: str) -> list[Number]:
    """The numbers a Markdown text states (see the module docstring for which count)."""
    text = _strip(markdown)
    found, in_range = [], set()
    for match in _RANGE.finditer(text):
        for group in (1, 2):
            found.append((match.start(group), _parse(match.group(group))))
            in_range.add(match.start(group))
    for match in _TOKEN.finditer(text):
        start = match.start(1)
        if start in in_range:
            continue
        number = _parse(match.group(1), bool(match.group(2)))
        digits = match.group(1).replace(",", "")
        if number.percent or not digits.isdigit() or len(digits) >= 3:
            found.append((start, number))
    return [number for _, number in sorted(found, key=lambda pair: pair[0])]


def output_numbers(text: str) -> list[Number]:
    """Every number an output prints (as text), with the resolution it is printed at."""
    return [_parse(match.group(1)) for match in _TOKEN.finditer(text.replace("\u2212", "-"))]


def traces(stated: Number, printed) -> bool:
    """Whether a stated number is one of ``printed``, at the same digits or at more digits that round to it.

    A percentage is also traced by a printed fraction (43% by 0.432).

    Parameters
    ----------
    stated : Number
        A number of the prose (:func:`prose_numbers`).
    printed : iterable of Number
        The numbers printed (:func:`output_numbers`) or declared.
    """
    for number in printed:
        for scale in ((1.0, 100.0) if stated.percent else (1.0,)):
            value, resolution = number.value * scale, number.resolution * scale
            if resolution <= stated.resolution * (1 + 1e-9) and \
                    abs(value - stated.value) <= stated.resolution / 2 * (1 + 1e-9) + 1e-300:
                return True
    return False


def _output_text(cell) -> str:
    parts = []
    for output in cell.get("outputs", []):
        if output.get("output_type") == "stream":
            parts.append(output.get("text", ""))
        elif output.get("output_type") == "error":
            parts.append(" ".join(output.get("traceback", [])))
        else:
            data = output.get("data", {})
            parts += [data[kind] for kind in ("text/plain", "text/html", "text/markdown", "text/latex") if kind in data]
    return "\n".join(part if isinstance(part, str) else "".join(part) for part in parts)


def declared_numbers(notebook) -> tuple[list[Number], list[str]]:
    """The numbers the notebook's "Numbers from elsewhere" cell declares, and what is wrong with the cell.

    Each row of its table names numbers in its first column and their source
    in its second; a row without a source is a problem.
    """
    declared, problems = [], []
    for index, cell in enumerate(notebook.cells):
        if cell.cell_type != "markdown" or ELSEWHERE_HEADING.lower() not in cell.source.split("\n")[0].lower():
            continue
        for line in cell.source.split("\n"):
            columns = [column.strip() for column in line.strip().strip("|").split("|")]
            if not line.lstrip().startswith("|") or set("".join(columns)) <= set("-: "):
                continue
            numbers = prose_numbers(columns[0]) or output_numbers(columns[0])
            if numbers and (len(columns) < 2 or not columns[1]):
                problems.append(f"cell {index}: '{columns[0]}' is declared without a source")
            declared += numbers
    return declared, problems


def untraced(notebook, outputs_of=None) -> list[str]:
    """Each number the notebook's Markdown states with no output above it and no declaration, as a message.

    ``outputs_of(index, cell)`` gives the text of a code cell's outputs (by
    default its stored outputs): a student notebook passes the source's
    outputs for the cells whose outputs it does not store (the reveals).

    Parameters
    ----------
    notebook : nbformat.NotebookNode
    outputs_of : callable, optional
        ``outputs_of(index, cell) -> str``; default the cell's stored outputs.
    """
    outputs_of = outputs_of or (lambda index, cell: _output_text(cell))
    declared, problems = declared_numbers(notebook)
    printed: list[Number] = []
    for index, cell in enumerate(notebook.cells):
        if cell.cell_type == "code":
            printed += output_numbers(outputs_of(index, cell))
            continue
        if cell.cell_type != "markdown" or ELSEWHERE_HEADING.lower() in cell.source.split("\n")[0].lower():
            continue
        for number in prose_numbers(cell.source):
            if not traces(number, printed) and not traces(number, declared):
                problems.append(f"cell {index}: {number.text!r} in \"{_excerpt(cell.source, number.text)}\"")
    return problems


def _excerpt(source: str, text: str, width: int = 60) -> str:
    """The line of ``source`` that states ``text`` (1,600 also as LaTeX's 1{,}600), cut to ``width`` around it."""
    pattern = re.escape(text.rstrip("%")).replace(",", r"(?:,|\{,\})")
    line = next((line for line in source.split("\n") if re.search(pattern, line)), source.split("\n")[0])
    match = re.search(pattern, line)
    at, end = (match.start(), match.end()) if match else (0, 0)
    start = max(at - width, 0)
    return ("..." if start else "") + line[start:end + width].strip() + ("..." if end + width < len(line) else "")
