"""Predict, run, reveal: no page a student reads before a question states its answer.

Each prediction and discussion question declares, in its cell's metadata, the few phrases that state its answer:
``"sarsp_edu": {"answer_phrases": [...]}``. None of them may stand in a markdown cell above the question in its
tutorial (the question cell's own text before the question included), in an earlier tutorial, in the glossary, in
the READMEs' tables of contents, in any tutorial's learning goals or in any section title of the course; and a
reveal must follow the question. The check reads the notebooks' JSON only, for the student notebooks and their
sources alike.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

TUTORIALS = Path(__file__).resolve().parents[1] / "tutorials"
SOURCES = sorted((TUTORIALS / "source").glob("[0-9][0-9]_*.ipynb"))
STUDENTS = [TUTORIALS / path.name for path in SOURCES]
NOTEBOOKS = SOURCES + STUDENTS
GLOSSARY = TUTORIALS / "GLOSSARY.md"
READMES = [TUTORIALS.parent / "README.md", TUTORIALS / "README.md"]
REVEAL_TAG = "reveal"  # sarsp_edu.teaching.prose.REVEAL_TAG, kept here so that the test reads JSON only
NAMESPACE, KEY = "sarsp_edu", "answer_phrases"

#: a question's lead: a bold run at the start of a line that names a prediction or a question
#: ("**Predict first (exercise 1.4).**", "**Exercise 3.4 (predict).**", "**Questions (no code).**",
#: "**Discussion question.**", "**Read the table with one question:**")
LEAD = re.compile(r"^\*\*[^*\n]*\b(?:predict|question)[^*\n]*\*\*", re.IGNORECASE | re.MULTILINE)
HEADING = re.compile(r"^ {0,3}#{1,6}\s.*$", re.MULTILINE)


def _read(path: Path) -> dict:
    return json.loads(path.read_text(encoding="utf-8"))


def _text(cell: dict) -> str:
    source = cell["source"]
    return source if isinstance(source, str) else "".join(source)


def normalised(text: str) -> str:
    """Lower case, Markdown's emphasis, code and maths marks dropped, every run of white space one space."""
    return re.sub(r"\s+", " ", re.sub(r"[*`$]", "", text)).strip().lower()


def contains(text: str, phrase: str) -> bool:
    """Whether ``phrase`` stands in ``text``, both normalised, not inside a longer word."""
    return re.search(rf"(?<!\w){re.escape(normalised(phrase))}(?!\w)", normalised(text)) is not None


def phrases(cell: dict) -> list[str]:
    return cell.get("metadata", {}).get(NAMESPACE, {}).get(KEY, [])


def _grading(cell: dict) -> dict:
    return cell.get("metadata", {}).get("nbgrader", {})


def _written_answer(cell: dict) -> bool:
    """A Markdown cell the student writes an answer in (nbgrader's solution cell)."""
    return cell["cell_type"] == "markdown" and bool(_grading(cell).get("solution"))


def _prediction_answer(cell: dict) -> bool:
    """The code cell in which a student returns a prediction (``my_prediction``)."""
    return (cell["cell_type"] == "code" and bool(_grading(cell).get("solution"))
            and "def my_prediction" in _text(cell))


#: the cell a student writes a prediction or an answer in, where no check grades it (a slider's prediction)
YOURS = re.compile(r"^\*Your (?:prediction|answer):\*\s*$")


def _yours(cell: dict) -> bool:
    """A Markdown cell that holds only '*Your prediction:*' or '*Your answer:*', for the student to write in."""
    return cell["cell_type"] == "markdown" and bool(YOURS.match(_text(cell)))


def _is_reveal(cell: dict) -> bool:
    return cell["cell_type"] == "code" and REVEAL_TAG in cell.get("metadata", {}).get("tags", [])


def question_start(text: str) -> int | None:
    """Where a Markdown cell's question starts (None: the cell asks none by its lead)."""
    lead = LEAD.search(text)
    return lead.start() if lead else None


def questions(notebook: dict) -> dict[int, int]:
    """The question-shaped cells of a notebook: {cell index: where in its text the question starts}.

    A cell asks a question if it has a question's lead, if a written answer, a prediction's answer cell or a
    cell for the student's own answer ('*Your prediction:*') follows it, or if it asks something ('?') and a
    reveal comes next.
    """
    cells, found = notebook["cells"], {}
    for index, cell in enumerate(cells):
        if cell["cell_type"] != "markdown" or _written_answer(cell):
            continue
        text = _text(cell)
        start = question_start(text)
        later = cells[index + 1:]
        graded = bool(later) and (_written_answer(later[0]) or _prediction_answer(later[0]))
        answered = graded or (bool(later) and _yours(later[0]))
        revealed = "?" in text and bool(later) and _is_reveal(later[0])
        if start is None and (answered or revealed):
            mark = text.find("?")
            start = text.rfind("\n\n", 0, mark) + 2 if mark >= 0 and not graded else 0
        if start is not None:
            found[index] = start
    return found


def _where(path: Path, index: int, cell: dict) -> str:
    return f"{path.relative_to(TUTORIALS.parent)} cell {index} (id {cell.get('id')})"


def _kind(path: Path) -> list[Path]:
    return SOURCES if path.parent.name == "source" else STUDENTS


def earlier_texts(path: Path, index: int, start: int) -> list[tuple[str, str]]:
    """(where, text) of everything a student may read before the question of cell ``index`` at ``start``."""
    notebook, kind = _read(path), _kind(path)
    texts = [(_where(path, i, cell) + ", above the question", _text(cell))
             for i, cell in enumerate(notebook["cells"][:index]) if cell["cell_type"] == "markdown"]
    texts.append((_where(path, index, notebook["cells"][index]) + ", the question's own cell above its lead",
                  _text(notebook["cells"][index])[:start]))
    for other in kind:
        cells = _read(other)["cells"]
        for i, cell in enumerate(cells):
            if cell["cell_type"] != "markdown":
                continue
            text = _text(cell)
            if other.name < path.name:
                texts.append((_where(other, i, cell) + ", an earlier tutorial", text))
                continue
            if "**Learning goals.**" in text:
                texts.append((_where(other, i, cell) + ", a learning-goal cell", text))
            texts += [(_where(other, i, cell) + f", the section title {heading.strip()!r}", heading)
                      for heading in HEADING.findall(text)]
    texts.append((str(GLOSSARY.relative_to(TUTORIALS.parent)) + ", the glossary", GLOSSARY.read_text(encoding="utf-8")))
    for readme in READMES:  # the course's tables of contents, read before any tutorial
        texts.append((str(readme.relative_to(TUTORIALS.parent)) + ", a table of contents",
                      readme.read_text(encoding="utf-8")))
    return texts


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_every_question_declares_the_phrases_that_state_its_answer(path):
    notebook = _read(path)
    asked = questions(notebook)
    problems = [f"{_where(path, index, cell)}: a question without {NAMESPACE}.{KEY} in its metadata: "
                f"{_text(cell)[asked[index]:][:80]!r}"
                for index, cell in enumerate(notebook["cells"]) if index in asked and not phrases(cell)]
    problems += [f"{_where(path, index, cell)}: declares answer phrases but asks no question (no lead such as "
                 "'**Predict, then check.**' or '**Question.**')"
                 for index, cell in enumerate(notebook["cells"]) if phrases(cell) and index not in asked]
    problems += [f"{_where(path, index, cell)}: {KEY} must be a list of non-empty strings"
                 for index, cell in enumerate(notebook["cells"]) if phrases(cell)
                 and not all(isinstance(p, str) and p.strip() for p in phrases(cell))]
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("source", SOURCES, ids=lambda p: p.name)
def test_source_and_student_declare_the_same_phrases(source):
    student = TUTORIALS / source.name
    declared = {cell["id"]: phrases(cell) for cell in _read(source)["cells"] if phrases(cell)}
    copied = {cell["id"]: phrases(cell) for cell in _read(student)["cells"] if phrases(cell)}
    assert declared == copied, f"{student.name}: the question cells' answer phrases differ from its source's"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_a_reveal_follows_every_question(path):
    """A cell tagged 'reveal' comes after the question; a written question's reveal is its model answer (the
    source's nbgrader solution cell right after it, which the student's copy holds blank until feedback)."""
    notebook, source = _read(path), _read(TUTORIALS / "source" / path.name)
    model_answers = {cell["id"]: _text(cell) for cell in source["cells"] if _written_answer(cell)}
    problems = []
    for index, cell in enumerate(notebook["cells"]):
        if not phrases(cell):
            continue
        later = notebook["cells"][index + 1:]
        written = bool(later) and _written_answer(later[0]) and model_answers.get(later[0]["id"], "").strip()
        if not (written or any(_is_reveal(c) for c in later)):
            problems.append(f"{_where(path, index, cell)}: no reveal follows the question (tag a later code cell "
                            f"'{REVEAL_TAG}', or follow it with a written answer cell)")
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_every_question_is_followed_by_a_cell_for_the_students_answer(path):
    """Question, the student's answer, then the run: the cell right after a question is a written answer, a
    prediction's answer cell or a Markdown cell that holds only '*Your prediction:*' (or '*Your answer:*')."""
    cells, problems = _read(path)["cells"], []
    for index, cell in enumerate(cells):
        if not phrases(cell):
            continue
        after = cells[index + 1] if index + 1 < len(cells) else None
        if after is None or not (_written_answer(after) or _prediction_answer(after) or _yours(after)):
            problems.append(f"{_where(path, index, cell)}: no cell for the student's answer right after the question")
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_no_answer_stands_above_its_question(path):
    notebook, problems = _read(path), []
    asked = questions(notebook)
    for index, cell in enumerate(notebook["cells"]):
        if not phrases(cell):
            continue
        texts = earlier_texts(path, index, asked.get(index, 0))
        for phrase in phrases(cell):
            problems += [f"{_where(path, index, cell)}: answer phrase {phrase!r} leaks in {where}"
                         for where, text in texts if contains(text, phrase)]
    assert not problems, ("answers stated before their questions (reword the earlier text, or move it below the "
                          "reveal):\n" + "\n".join(problems))


def _notebook(*cells: dict) -> dict:
    return {"cells": list(cells)}


def _markdown(text: str, answer_phrases=None, **metadata) -> dict:
    if answer_phrases:
        metadata[NAMESPACE] = {KEY: answer_phrases}
    return {"cell_type": "markdown", "id": "x", "metadata": metadata, "source": text}


def _code(text: str = "print(1)", tags=(), **metadata) -> dict:
    return {"cell_type": "code", "id": "y", "metadata": {"tags": list(tags), **metadata}, "source": text}


def test_a_phrase_matches_whatever_its_case_emphasis_and_line_breaks_but_not_inside_a_word():
    assert contains("The band gets **Narrower**\nat $\\nu = 30$.", "narrower")
    assert contains("it does *not* discount outliers\n  one by one", "not discount outliers one by one")
    assert not contains("the narrowest band", "narrower") and not contains("150 draws", "15")


def test_the_questions_a_notebook_asks_are_found_by_their_lead_their_answer_cell_or_their_reveal():
    notebook = _notebook(
        _markdown("Text.\n\n**Predict, then check.** Wider or narrower?"),  # 0: a lead, after some text
        _code(tags=["reveal"]),
        _markdown("**Exercise 2.5 (predict, then compute).** Above or below?"),  # 2: a lead
        _code("def my_prediction():\n    return 1", nbgrader={"solution": True}),
        _markdown("Why would a package refuse it?"),  # 4: a written answer follows
        _markdown("Because.", nbgrader={"solution": True}),
        _markdown("## 6. Experiments\n\n**Experiment 1.** What happens to the cost?"),  # 6: a reveal follows
        _code(tags=["reveal"]),
        _markdown("**Which comparison is fair?** At fixed settings the TP wins."),  # rhetorical: no question
        _code(),
    )
    assert questions(notebook) == {0: 7, 2: 0, 4: 0, 6: 19}
