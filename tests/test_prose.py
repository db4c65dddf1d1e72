"""The tutorials' prose states only numbers the reader can see computed, and predictions come before answers."""

from __future__ import annotations

import re
from pathlib import Path

import nbformat
import pytest

from sarsp_edu.teaching.course import clear_reveals, sources, student_path
from sarsp_edu.teaching.exercises.short_answers import LOOKUPS
from sarsp_edu.teaching.prose import REVEAL_TAG, declared_numbers, output_numbers, prose_numbers, traces, untraced

ROOT = Path(__file__).resolve().parents[1]
SOURCES = sources(ROOT / "tutorials")


def _texts(markdown: str) -> list[str]:
    return [number.text for number in prose_numbers(markdown)]


@pytest.mark.parametrize("markdown, stated", [
    ("rmse 0.41, then 0.66", ["0.41", "0.66"]),
    ("a mean of 134 to 1,854 for the TP", ["134", "1,854"]),
    ("it waits 10-23 s; 45 configurations; 3 seeds", ["10", "23"]),
    ("TSR 92% and 88.5 %", ["92%", "88.5%"]),
    ("p = 8.3e-07 and $5^{-4} = 0.0016$", ["8.3e-07", "0.0016"]),
    ("$40^2 = 1{,}600$ residuals", ["1,600"]),
    ("move nu from 3 to 30", []),
])
def test_the_numbers_a_sentence_states(markdown, stated):
    assert _texts(markdown) == stated


@pytest.mark.parametrize("markdown", [
    "eq. 6, eqs. 8-9 and equation 12", "sections 2.1, 3.1-3.2 and 5.2", "Table 2 and tables 1 and 3",
    "Figure 4; figures 2-7", "exercise 2.5 and exercises 5.1-5.3", "Tutorial 4, chapter 2, appendix 3.1",
    "Shah et al. (2014, eq. 7)", "[the paper](https://example.org/1234.5678)", "doi:10.1016/j.x.2020.123",
])
def test_references_years_and_links_state_no_number(markdown):
    assert _texts(markdown) == []


def test_a_number_is_traced_by_the_same_digits_or_more_that_round_to_it():
    stated = prose_numbers("0.41 and 43% and 1,854")
    assert traces(stated[0], output_numbers("0.41")) and traces(stated[0], output_numbers("0.4051"))
    assert not traces(stated[0], output_numbers("0.4")), "fewer digits than the prose states trace nothing"
    assert not traces(stated[0], output_numbers("0.4151"))
    assert traces(stated[1], output_numbers("share 0.432")) and traces(stated[1], output_numbers("43.2%"))
    assert traces(stated[2], output_numbers("1854 episodes")) and not traces(stated[2], output_numbers("1855"))


def _notebook(*cells):
    notebook = nbformat.v4.new_notebook()
    for kind, text, *printed in cells:
        if kind == "code":
            cell = nbformat.v4.new_code_cell(text, execution_count=1)
            cell.outputs = [nbformat.v4.new_output("stream", name="stdout", text=printed[0])] if printed else []
        else:
            cell = nbformat.v4.new_markdown_cell(text)
        notebook.cells.append(cell)
    return notebook


def test_a_number_printed_only_below_its_sentence_or_not_at_all_is_named():
    notebook = _notebook(("markdown", "The rmse is 0.41."), ("code", "print(rmse)", "rmse 0.41"),
                         ("markdown", "Again 0.41, and 2.5 from nowhere."))
    assert untraced(notebook) == ["cell 0: '0.41' in \"The rmse is 0.41.\"",
                                  "cell 2: '2.5' in \"Again 0.41, and 2.5 from nowhere.\""]


def test_an_outside_number_is_declared_with_its_source():
    notebook = _notebook(("markdown", "The paper's lead is 5.6 points."),
                         ("markdown", "### Numbers from elsewhere\n\n| number | source |\n|---|---|\n"
                                      "| 5.6 | the paper's Table 2 |\n| 7.5 | |"))
    assert untraced(notebook) == ["cell 1: '7.5' is declared without a source"]
    assert [n.text for n in declared_numbers(notebook)[0]] == ["5.6", "7.5"]


def _source_outputs(source):
    """A student notebook's outputs, with its source's for the reveals (a student sees those on running them)."""
    def outputs_of(index, cell):
        from sarsp_edu.teaching.prose import _output_text

        if REVEAL_TAG in cell.metadata.get("tags", []):
            return _output_text(source.cells[index])
        return _output_text(cell)
    return outputs_of


NOTEBOOKS = SOURCES + [student_path(p) for p in SOURCES]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_every_number_in_the_prose_is_printed_above_it_or_declared(path):
    notebook = nbformat.read(path, as_version=4)
    outputs_of = None
    if path.parent.name != "source":
        outputs_of = _source_outputs(nbformat.read(path.parent / "source" / path.name, as_version=4))
    problems = untraced(notebook, outputs_of)
    assert not problems, (f"{path.name}: numbers the prose states that no output above prints and the 'Numbers "
                          "from elsewhere' cell does not declare (print them, declare them with their source, or "
                          "cut them):\n" + "\n".join(problems))


PREDICTIONS = sorted(LOOKUPS)


def _cells_by_grade_id(notebook):
    return {cell.metadata.get("nbgrader", {}).get("grade_id"): index for index, cell in enumerate(notebook.cells)}


@pytest.mark.parametrize("exercise", PREDICTIONS)
def test_each_prediction_is_checked_before_a_reveal_that_students_run_themselves(exercise):
    tutorial = int(exercise.split(".")[0])
    source_path = sources(ROOT / "tutorials", [tutorial])[0]
    source = nbformat.read(source_path, as_version=4)
    student = nbformat.read(student_path(source_path), as_version=4)
    check = _cells_by_grade_id(source)[f"ex-{exercise.replace('.', '-')}-check"]
    later = [index for index in range(check + 1, len(source.cells)) if source.cells[index].cell_type == "code"]
    assert later and REVEAL_TAG in source.cells[later[0]].metadata.get("tags", []), (
        f"exercise {exercise}: the first code cell after its check must be tagged '{REVEAL_TAG}'")
    for index, cell in enumerate(student.cells):
        if REVEAL_TAG in cell.metadata.get("tags", []):
            assert not cell.get("outputs"), f"{student_path(source_path).name} cell {index}: a reveal keeps its output"


def test_the_student_command_clears_every_reveal():
    notebook = _notebook(("code", "print(1)", "1"), ("code", "print(2)", "2"))
    notebook.cells[1].metadata["tags"] = [REVEAL_TAG]
    clear_reveals(notebook)
    assert notebook.cells[0].outputs and not notebook.cells[1].outputs
    assert notebook.cells[1].execution_count is None


#: the classroom units: at most this much prose, and this many numbers in it, in the student notebook
#: the evidence tutorials, whose numbers a class must read: 1,500 words and 80 numbers for 40 minutes, scaled to the
#: minutes each states (Tutorial 6 states 60)
CLASS_SIZE = {"05": 40, "06": 60}


def prose_size(notebook) -> tuple[int, int]:
    """Words, and numerals of any kind (section numbers included), in a notebook's Markdown."""
    import re

    markdown = "\n".join(cell.source for cell in notebook.cells if cell.cell_type == "markdown")
    return len(markdown.split()), len(re.findall(r"\d+(?:[.,]\d+)*", markdown))


@pytest.mark.parametrize("tutorial", sorted(CLASS_SIZE))
def test_the_evidence_tutorials_hold_no_more_prose_than_a_class_reads(tutorial):
    source = sources(ROOT / "tutorials", [int(tutorial)])[0]
    words, numbers = prose_size(nbformat.read(student_path(source), as_version=4))
    minutes = CLASS_SIZE[tutorial]
    stated = re.search(r"\*\*Time\.\*\* About (\d+) minutes", nbformat.read(source, as_version=4).cells[0].source)
    assert stated and int(stated.group(1)) == minutes, f"{source.name} states another time than {minutes} minutes"
    most_words, most_numbers = 1500 * minutes // 40, 80 * minutes // 40
    assert words <= most_words and numbers <= most_numbers, (
        f"{source.name}: {words} words and {numbers} numbers of prose; a {minutes}-minute unit holds at most "
        f"{most_words} and {most_numbers} (move details to REPRODUCTION.md)")


def test_the_lecturers_guide_quotes_only_numbers_a_notebook_prints():
    """LECTURER.md's numbers (decimals, percentages, integers of four or more digits): each printed by a
    notebook's stored output or declared in its "Numbers from elsewhere" cell. Minutes and counts of a plan
    (integers below 1,000), commands (in backticks) and screen sizes (1280x720) are the guide's own."""
    import re

    from sarsp_edu.teaching.prose import _output_text

    printed, declared = [], []
    for path in SOURCES:
        notebook = nbformat.read(path, as_version=4)
        printed += [n for cell in notebook.cells if cell.cell_type == "code"
                    for n in output_numbers(_output_text(cell))]
        declared += declared_numbers(notebook)[0]
    text = (ROOT / "tutorials" / "LECTURER.md").read_text(encoding="utf-8")
    missing = []
    for line in text.splitlines():
        for number in prose_numbers(re.sub(r"`[^`]*`|\b\d+x\d+\b", " ", line)):
            whole = number.resolution >= 1 and not number.percent
            if whole and number.value < 1000:
                continue
            if not traces(number, printed) and not traces(number, declared):
                missing.append(f"{number.text!r} in: {line.strip()[:120]}")
    assert not missing, "LECTURER.md states numbers no notebook prints:\n" + "\n".join(missing)
