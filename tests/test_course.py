"""One source per tutorial, in nbgrader's format; the student notebooks are what the command makes of it."""

from __future__ import annotations

import ast
import json
import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import nbformat
import pytest

from sarsp_edu.teaching.course import (
    CODE_STUB,
    TEXT_STUB,
    check_source,
    clear_solutions,
    relinked,
    sources,
    student_notebook,
    student_path,
    write_handout,
)
from sarsp_edu.teaching.exercises import EXERCISES

ROOT = Path(__file__).resolve().parents[1]
SOURCES = sources(ROOT / "tutorials")


def comparable(notebook) -> list:
    """What a student notebook holds apart from its outputs: each cell's type, text and nbgrader metadata."""
    return [(cell.cell_type, cell.source, cell.metadata.get("nbgrader")) for cell in notebook.cells]


@pytest.mark.parametrize("source", SOURCES, ids=lambda p: p.name)
def test_each_student_notebook_is_what_the_command_makes_of_its_source(source):
    made = student_notebook(nbformat.read(source, as_version=4))
    stored = nbformat.read(student_path(source), as_version=4)
    assert comparable(stored) == comparable(made), (
        f"{student_path(source).name} differs from its source: edit tutorials/source/{source.name}, then run "
        "'sarsp-edu course student'")


@pytest.mark.parametrize("source", SOURCES, ids=lambda p: p.name)
def test_sources_are_in_nbgraders_format_and_hold_no_answer_in_the_student_copy(source):
    notebook = nbformat.read(source, as_version=4)
    assert check_source(notebook) == []
    student = nbformat.read(student_path(source), as_version=4)
    text = "\n".join(cell.source for cell in student.cells)
    assert "BEGIN SOLUTION" not in text and "HIDDEN TESTS" not in text
    graded = [cell for cell in notebook.cells if cell.metadata.get("nbgrader", {}).get("grade")]
    assert graded, "a source without a graded cell"


def test_the_sources_ask_every_exercise_once_and_only_those():
    asked = []
    for source in SOURCES:
        for cell in nbformat.read(source, as_version=4).cells:
            meta = cell.metadata.get("nbgrader", {})
            if meta.get("grade") and not meta.get("solution"):
                asked.append(cell.source.split('"')[1])  # check("2.1", ...)
    assert sorted(asked, key=lambda n: tuple(map(int, n.split(".")))) == list(EXERCISES)


@pytest.mark.parametrize("source", SOURCES, ids=lambda p: p.name)
def test_no_notebook_defines_a_function_or_class_outside_its_exercises(source):
    for index, cell in enumerate(nbformat.read(source, as_version=4).cells):
        if cell.cell_type != "code" or cell.metadata.get("nbgrader", {}).get("solution"):
            continue
        defined = [node.name for node in ast.walk(ast.parse(cell.source))
                   if isinstance(node, (ast.FunctionDef, ast.ClassDef, ast.AsyncFunctionDef))]
        assert not defined, f"{source.name} cell {index} defines {defined}: algorithms live in the package"


def test_nbgrader_itself_makes_the_same_student_notebooks(tmp_path):
    pytest.importorskip("nbgrader")
    course = tmp_path / "course"
    (course / "source" / "tutorials").mkdir(parents=True)
    for source in SOURCES:
        shutil.copy(source, course / "source" / "tutorials" / source.name)
    (course / "nbgrader_config.py").write_text('c = get_config()\nc.CourseDirectory.course_id = "sarsp_edu"\n')
    result = subprocess.run([sys.executable, "-m", "nbgrader", "generate_assignment", "tutorials", "--force"],
                            cwd=course, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr[-3000:]
    for source in SOURCES:
        theirs = nbformat.read(course / "release" / "tutorials" / source.name, as_version=4)
        ours = student_notebook(nbformat.read(source, as_version=4))
        # nbgrader keeps the source's links; ours are pointed from tutorials/, where the student copy lies
        theirs = [(c.cell_type, relinked(c.source) if c.cell_type == "markdown" else c.source) for c in theirs.cells]
        assert theirs == [(c.cell_type, c.source) for c in ours.cells]


def test_regions_become_nbgraders_stubs_indented_as_their_markers():
    code = "import numpy as np\n\ndef f(x):\n    ### BEGIN SOLUTION\n    return 2 * x\n    ### END SOLUTION"
    assert clear_solutions(code) == "import numpy as np\n\ndef f(x):\n" + "\n".join(
        "    " + line for line in CODE_STUB.split("\n"))
    notebook = nbformat.v4.new_notebook(cells=[
        nbformat.v4.new_code_cell("f(1)\n### BEGIN HIDDEN TESTS\nassert f(1) == 2\n### END HIDDEN TESTS"),
        nbformat.v4.new_markdown_cell("Because 2.", metadata={"nbgrader": {"solution": True}}),
    ])
    student = student_notebook(notebook)
    assert [c.source for c in student.cells] == ["f(1)", TEXT_STUB]
    assert notebook.cells[0].source.endswith("### END HIDDEN TESTS")  # the source is left as it was


@pytest.mark.parametrize("text, problem", [
    ("### BEGIN SOLUTION\nx = 1", "has no '### END SOLUTION'"),
    ("x = 1\n### END SOLUTION", "without a '### BEGIN SOLUTION'"),
])
def test_an_unpaired_marker_is_named(text, problem):
    notebook = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(text)])
    assert any(problem in p for p in check_source(notebook))


def test_a_solution_without_nbgrader_metadata_or_with_a_reused_id_is_refused():
    meta = {"grade": True, "grade_id": "a", "locked": True, "schema_version": 3, "solution": False, "task": False,
            "points": 1}
    notebook = nbformat.v4.new_notebook(cells=[
        nbformat.v4.new_code_cell("### BEGIN SOLUTION\nx = 1\n### END SOLUTION"),
        nbformat.v4.new_code_cell("x", metadata={"nbgrader": meta}),
        nbformat.v4.new_code_cell("x", metadata={"nbgrader": {**meta, "points": None, "locked": False}}),
    ])
    problems = check_source(notebook)
    assert any("no nbgrader metadata with solution: true" in p for p in problems)
    assert any("grade_id 'a' is used twice" in p for p in problems)
    assert any("needs points" in p for p in problems) and any("must be locked" in p for p in problems)


def test_the_handout_holds_the_student_course_and_no_answer(tmp_path):
    for made in (write_handout(ROOT, out=tmp_path / "course"), write_handout(ROOT, zip_path=tmp_path / "c.zip")):
        if made.suffix == ".zip":
            with zipfile.ZipFile(made) as archive:
                names = archive.namelist()
                notebooks = {n: archive.read(n).decode() for n in names if n.endswith(".ipynb")}
        else:
            names = [str(p.relative_to(made)) for p in made.rglob("*") if p.is_file()]
            notebooks = {n: (made / n).read_text() for n in names if n.endswith(".ipynb")}
        prefix = "sarsp-edu-course/" if made.suffix == ".zip" else ""
        assert sorted(n for n in notebooks) == sorted(f"{prefix}tutorials/{p.name}" for p in SOURCES)
        assert f"{prefix}tutorials/GLOSSARY.md" in names
        assert (f"{prefix}results/sweep-default/sweep.json" in names
                and f"{prefix}results/ablation/ablation.json" in names)
        assert not any("source" in Path(n).parts for n in names)
        assert not any("BEGIN SOLUTION" in text or "HIDDEN TESTS" in text for text in notebooks.values())
    with pytest.raises(ValueError, match="out must be a new or empty folder"):
        write_handout(ROOT, out=tmp_path / "course")


def test_the_handout_holds_every_results_folder_and_file_a_student_notebook_names():
    """What a notebook reads ('sweep-latent' in a loop of names, as Tutorial 6 has it) and links to
    ('../REPRODUCTION.md') travels with the hand-out: a missing one raised FileNotFoundError in the hand-out only."""
    from sarsp_edu.teaching.course import HANDOUT_FILES, HANDOUT_RESULTS

    folders = {path.name for path in (ROOT / "results").iterdir() if path.is_dir()}
    shipped = {Path(inside).as_posix() for _, inside in HANDOUT_FILES} | set(HANDOUT_RESULTS)
    for path in sorted((ROOT / "tutorials").glob("0*.ipynb")):
        notebook = nbformat.read(path, as_version=4)
        code = "\n".join(cell.source for cell in notebook.cells if cell.cell_type == "code")
        text = "\n".join(cell.source for cell in notebook.cells if cell.cell_type == "markdown")
        named = {folder for folder in folders if f'"{folder}"' in code or f"'{folder}'" in code}
        assert {f"results/{folder}" for folder in named} <= set(HANDOUT_RESULTS), path.name
        linked = {link.split("#")[0] for link in re.findall(r"\]\(\.\./([^)\s]+)\)", text)}
        assert linked <= shipped, (path.name, linked - shipped)


def test_the_course_command(tmp_path, capsys):
    from sarsp_edu.cli import main

    assert main(["course", "handout", "--root", str(ROOT), "--zip", str(tmp_path / "c.zip")]) == 0
    assert "no sources, no solutions" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["course", "handout", "--root", str(ROOT)])
    assert "handout needs --out DIR or --zip FILE" in capsys.readouterr().err
    tutorials = tmp_path / "tutorials"
    shutil.copytree(ROOT / "tutorials" / "source", tutorials / "source")
    assert main(["course", "student", "--tutorials", str(tutorials), "--no-execute"]) == 0
    written = sorted(p.name for p in tutorials.glob("*.ipynb"))
    assert written == [p.name for p in SOURCES]
    assert json.loads((tutorials / SOURCES[0].name).read_text())["cells"][0]["cell_type"] == "markdown"


def _table_width(html: str) -> int:
    """Columns of a pandas HTML table, its index included: the widest header row's cells."""
    import re

    head = html[html.find("<thead"):html.find("</thead>")]
    return max(len(re.findall(r"<th[ >]", row)) for row in head.split("</tr>"))


@pytest.mark.parametrize("source", SOURCES, ids=lambda p: p.name)
def test_every_figure_is_followed_by_what_to_see_and_no_table_is_wider_than_seven_columns(source):
    cells = nbformat.read(source, as_version=4).cells
    for index, cell in enumerate(cells):
        outputs = cell.get("outputs", []) if cell.cell_type == "code" else []
        if any("image/png" in output.get("data", {}) for output in outputs):
            after = cells[index + 1] if index + 1 < len(cells) else None
            assert after is not None and after.cell_type == "markdown" and not after.source.lstrip().startswith("#"), (
                f"{source.name} cell {index}: a figure must be followed by a sentence saying what to see in it")
        for output in outputs:
            html = output.get("data", {}).get("text/html", "")
            if "<table" in html:
                assert _table_width(html) <= 7, f"{source.name} cell {index}: a table {_table_width(html)} columns wide"


def test_a_tutorial_copied_without_its_results_says_what_is_missing_and_how_to_get_it(tmp_path, monkeypatch):
    from sarsp_edu import stored_results

    monkeypatch.delenv("SARSP_EDU_RESULTS", raising=False)
    (tmp_path / "tutorials").mkdir()
    monkeypatch.chdir(tmp_path / "tutorials")  # the tutorials folder copied alone
    with pytest.raises(FileNotFoundError, match=r"the stored results 'sweep-default' were not found .*open the "
                                                r"notebook inside a clone of it or a course hand-out "
                                                r".*SARSP_EDU_RESULTS"):
        stored_results("sweep-default")
    monkeypatch.setenv("SARSP_EDU_RESULTS", str(ROOT / "results"))
    assert stored_results("sweep-default") == ROOT / "results" / "sweep-default"
    monkeypatch.delenv("SARSP_EDU_RESULTS")
    monkeypatch.chdir(ROOT / "tutorials" / "source")  # a source notebook finds them two folders up
    assert stored_results("ablation").resolve() == (ROOT / "results" / "ablation").resolve()


@pytest.mark.parametrize("path", SOURCES + [student_path(p) for p in SOURCES],
                         ids=lambda p: f"{p.parent.name}/{p.name}")
def test_every_stored_dashboard_picture_is_projector_wide(path):
    """A dashboard's output carries its picture for readers without a kernel: at least 1,600 px wide."""
    import base64
    import struct

    from sarsp_edu.teaching.dashboards.framework import SNAPSHOT_WIDTH_PX

    for index, cell in enumerate(nbformat.read(path, as_version=4).cells):
        for output in cell.get("outputs", []):
            data = output.get("data", {})
            if "application/vnd.jupyter.widget-view+json" in data and "image/png" in data:
                width = struct.unpack(">I", base64.b64decode(data["image/png"])[16:20])[0]
                assert width >= SNAPSHOT_WIDTH_PX, f"{path.name} cell {index}: a dashboard picture {width} px wide"


def _submission(release, source, wrong: str | None = None, answered: bool = True):
    """A student's submission: the released notebook with each solution cell answered as the source answers it
    (markers dropped), the exercise ``wrong`` answered wrongly, or nothing answered."""
    notebook = nbformat.read(release, as_version=4)
    answers = {cell.metadata["nbgrader"]["grade_id"]: cell for cell in nbformat.read(source, as_version=4).cells
               if cell.metadata.get("nbgrader", {}).get("solution")}
    for cell in notebook.cells:
        grade_id = cell.metadata.get("nbgrader", {}).get("grade_id")
        if not answered or grade_id not in answers or cell.cell_type != "code":
            continue
        cell.source = "\n".join(line for line in answers[grade_id].source.split("\n") if "### " not in line)
        if grade_id == wrong:  # the usual slip of exercise 1.1: the log of the normalising constant forgotten
            cell.source += "\n\n_right = student_t_logpdf\nstudent_t_logpdf = lambda x, nu: _right(x, nu) + 1.0"
    return notebook


def test_a_course_grades_submissions_with_nbgrader_end_to_end(tmp_path):
    """generate_assignment, three submissions (right, one slip, untouched), autograde, feedback: full, partial and
    zero automatic scores, and the package's diagnosis in the feedback a student reads."""
    pytest.importorskip("nbgrader")
    from nbgrader.api import Gradebook

    source = sources(ROOT / "tutorials", [1])[0]
    course = tmp_path / "course"
    (course / "source" / "tutorials").mkdir(parents=True)
    shutil.copy(source, course / "source" / "tutorials" / source.name)
    (course / "nbgrader_config.py").write_text(
        'c = get_config()\nc.CourseDirectory.course_id = "sarsp_edu"\nc.ExecutePreprocessor.timeout = 300\n')

    def nbgrader(*args):
        done = subprocess.run([sys.executable, "-m", "nbgrader", *args], cwd=course, capture_output=True, text=True,
                              timeout=600, env={**os.environ, "SARSP_EDU_AUTOPLAY": "0"})
        assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-3000:]

    nbgrader("generate_assignment", "tutorials", "--force")
    release = course / "release" / "tutorials" / source.name
    for student, kwargs in {"right": {}, "slip": {"wrong": "ex-1-1-answer"}, "blank": {"answered": False}}.items():
        folder = course / "submitted" / student / "tutorials"
        folder.mkdir(parents=True)
        nbformat.write(_submission(release, source, **kwargs), folder / source.name)
    nbgrader("autograde", "tutorials", "--create", "--force")
    nbgrader("generate_feedback", "tutorials", "--force")
    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as gradebook:
        automatic = {student: sum(grade.auto_score or 0 for grade in
                                  gradebook.find_submission("tutorials", student).notebooks[0].grades)
                     for student in ("right", "slip", "blank")}
        most = sum(cell.max_score for cell in gradebook.find_notebook(source.stem, "tutorials").grade_cells
                   if cell.cell_type == "code")
    assert automatic == {"right": most, "slip": most - 1, "blank": 0}, automatic
    feedback = (course / "feedback" / "slip" / "tutorials" / f"{source.stem}.html").read_text(encoding="utf-8")
    assert "Exercise 1.1: not yet. On x = [0], nu = 3, it gives other values than the package" in feedback
    assert "Exercise 1.2: right" in feedback


def test_the_course_command_names_the_extra_it_needs_on_a_plain_install(monkeypatch, capsys):
    import importlib.util

    from sarsp_edu.cli import main

    plain = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "nbclient" else plain(name, *a))
    with pytest.raises(SystemExit) as exit_:
        main(["course", "student", "--root", str(ROOT)])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert "needs nbclient" in err and "pip install 'sarsp_edu[course]'" in err


def test_a_handout_page_says_as_text_each_link_to_a_file_the_handout_lacks():
    from sarsp_edu.teaching.course import _unlinked

    page = "![curves](results/x/curves.png), [T4](tutorials/04.ipynb#s), [web](https://a.b), [top](#top)"
    assert _unlinked(page, Path("REPRODUCTION.md"), {"tutorials/04.ipynb"}) == (
        "curves (`results/x/curves.png` in the sarsp_edu repository), [T4](tutorials/04.ipynb#s), [web](https://a.b), "
        "[top](#top)")
    assert _unlinked("[R](../REPRODUCTION.md)", Path("tutorials/GLOSSARY.md"), {"REPRODUCTION.md"}) == (
        "[R](../REPRODUCTION.md)")
