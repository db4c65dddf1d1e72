"""Units that fit their time: each tutorial states its minutes, its prose keeps to 40 words a minute of them (1,800
for a 45-minute unit, exercises' prompts counted), and the lecturer's guide states their sum."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

TUTORIALS = Path(__file__).resolve().parents[1] / "tutorials"
STUDENT = sorted(TUTORIALS.glob("0*.ipynb"))
#: words of markdown a minute of a unit may hold (1,800 for 45 minutes)
WORDS_PER_MINUTE = 40


def words(notebook: dict) -> int:
    """The words of a notebook's markdown cells (a word: a run of letters or digits, with ' . - inside)."""
    return sum(len(re.findall(r"[A-Za-z0-9][\w'.-]*", "".join(cell["source"])))
               for cell in notebook["cells"] if cell["cell_type"] == "markdown")


def minutes(notebook: dict) -> int:
    """The minutes the unit states in its first cell: '**Time.** About N minutes'."""
    found = re.search(r"\*\*Time\.\*\* About (\d+) minutes", "".join(notebook["cells"][0]["source"]))
    assert found, "the first cell states no '**Time.** About N minutes'"
    return int(found.group(1))


@pytest.mark.parametrize("path", STUDENT, ids=[p.stem for p in STUDENT])
def test_a_units_prose_fits_its_minutes(path):
    notebook = json.loads(path.read_text(encoding="utf-8"))
    budget = WORDS_PER_MINUTE * minutes(notebook)
    assert words(notebook) <= budget, f"{path.name}: {words(notebook)} words of prose for {budget}"


def test_the_guide_states_the_sum_of_the_units_minutes():
    stated = [minutes(json.loads(path.read_text(encoding="utf-8"))) for path in STUDENT]
    guide = (TUTORIALS / "LECTURER.md").read_text(encoding="utf-8")
    assert f"{' + '.join(map(str, stated))} = {sum(stated)}" in guide


def test_the_guides_table_gives_each_units_own_minutes():
    guide = (TUTORIALS / "LECTURER.md").read_text(encoding="utf-8")
    for path in STUDENT:
        row = re.search(rf"^\| {path.name[:2]} [^|]*\|[^|]*\| (\d+) min \|$", guide, flags=re.M)
        assert row, f"LECTURER.md's table has no row for {path.name}"
        assert int(row.group(1)) == minutes(json.loads(path.read_text(encoding="utf-8"))), path.name


def test_the_word_count_counts_what_a_reader_reads():
    cell = {"cell_type": "markdown", "source": ["The TP's factor, (nu + beta - 2) / (nu + n - 2), is 1.08."]}
    assert words({"cells": [cell, {"cell_type": "code", "source": ["x = 1 + 2"]}]}) == 11


def test_the_documents_give_the_courses_counts_as_the_notebooks_have_them():
    """The counts a reader checks first, computed from the notebooks and the exercises: tutorials, functions to
    write (per tutorial and in all) and predictions, as README.md, tutorials/README.md, HANDOUT.md and
    LECTURER.md state them."""
    from sarsp_edu.teaching.exercises import CODING, EXERCISES

    root = TUTORIALS.parent
    per_tutorial = [sum(name.startswith(f"{n}.") for name in CODING) for n in range(1, 7)]
    predictions = len([name for name in EXERCISES if name not in CODING and not name.startswith("7.")])
    spelt = {3: "three", 4: "four", 5: "five", 6: "Six", 7: "Seven"}
    readme = (root / "README.md").read_text(encoding="utf-8")
    guide = (TUTORIALS / "README.md").read_text(encoding="utf-8")
    lecturer = (TUTORIALS / "LECTURER.md").read_text(encoding="utf-8")
    handout = (TUTORIALS / "HANDOUT.md").read_text(encoding="utf-8")
    span = f"{spelt[min(per_tutorial)]} to {spelt[max(per_tutorial)]}"
    assert f"({len(CODING)} functions in all, beside {spelt[predictions].lower()} predictions" in readme
    assert f"({len(CODING)} in all, {span} in" in guide
    assert f"({span} per tutorial)" in lecturer and f"students write {span} functions" in lecturer
    assert f"{spelt[len(STUDENT)]} Jupyter notebooks" in handout
    assert all(f"]({path.name})" in handout for path in STUDENT)
    sessions = lecturer.count("**Session ")
    assert sessions == 3 and "## Three 90-minute sessions" in lecturer
    assert "2 x 90" not in readme + guide and "three 90-minute sessions" in readme + guide


def test_each_session_plan_adds_up_and_its_homework_is_what_its_units_leave():
    """A session's items' minutes sum to its stated total (90); with its homework they make its units' minutes (its
    10 minutes on REPRODUCTION.md aside), and the guide's count of the homework is the sum of the sessions'."""
    guide = (TUTORIALS / "LECTURER.md").read_text(encoding="utf-8")
    plans = re.findall(r"\*\*Session \d: [^*]+\((Tutorials? [^)]*)\)\.\*\* ([\d + ]+) = (\d+) minutes(.*?)"
                       r"(?=\*\*Session|\n## )", guide, flags=re.S)
    assert len(plans) == 3
    stated = {int(path.name[:2]): minutes(json.loads(path.read_text(encoding="utf-8"))) for path in STUDENT}
    homework = []
    for units, terms, total, body in plans:
        items = [int(m) for m in re.findall(r"^\d+\. \((\d+) min\)", body, flags=re.M)]
        assert [int(t) for t in terms.split(" + ")] == items and sum(items) == int(total) == 90, units
        taught = sum(stated[int(n)] for n in re.findall(r"\d+", units))
        home = re.search(r"Homework, (\d+) minutes", body)
        aside = 10 if "REPRODUCTION.md" in body.split("Homework")[0] else 0
        homework.append(int(home.group(1)))
        assert int(total) - aside + homework[-1] == taught, units
    said = re.search(r"the other (\d+) are homework: (\d+) after session 1, (\d+) after session 2, (\d+)\s+after "
                     r"session 3, and Tutorial 7's (\d+)", guide)
    assert said and [int(g) for g in said.groups()[1:4]] == homework and int(said.group(5)) == stated[7]
    in_class = re.search(r"hold (\d+) of them in class", guide)
    assert in_class and int(in_class.group(1)) == sum(int(total) for _, _, total, _ in plans) - 10
    assert int(said.group(1)) == sum(homework) + stated[7] == sum(stated.values()) - int(in_class.group(1))
