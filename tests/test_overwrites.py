"""Nothing a user wrote is overwritten: output files, a student's notebooks; a failing cell said in one line."""

from __future__ import annotations

from pathlib import Path

import nbformat
import pytest

from sarsp_edu.cli.main import main
from sarsp_edu.teaching.course import SCHEMA_VERSION, typed_answers, write_student_notebooks

from .test_cli import _usage_error as usage_error

ROOT = Path(__file__).resolve().parents[1]
SWEEP = ROOT / "results" / "sweep-reduced"


def nbgrader(grade_id, **flags):
    return {"nbgrader": {"grade": False, "grade_id": grade_id, "locked": False, "schema_version": SCHEMA_VERSION,
                         "solution": False, "task": False, **flags}}


def tiny_course(tmp_path, failing=False) -> Path:
    """A tutorials folder with one source: an answer cell, and (``failing``) a cell that raises."""
    tutorials = tmp_path / "tutorials"
    (tutorials / "source").mkdir(parents=True)
    cells = [nbformat.v4.new_markdown_cell("# A unit"),
             nbformat.v4.new_code_cell("def my_answer():\n    ### BEGIN SOLUTION\n    return 42\n    ### END SOLUTION",
                                       metadata=nbgrader("answer", solution=True))]
    if failing:
        cells.append(nbformat.v4.new_code_cell("x = 1\nraise ValueError('the world has no goal')"))
    nbformat.write(nbformat.v4.new_notebook(cells=cells), tutorials / "source" / "01_unit.ipynb")
    return tutorials


@pytest.mark.parametrize("argv", [
    ["tables", str(SWEEP), "--markdown", "{file}"],
    ["tables", str(ROOT / "results" / "sweep-reduced-t-likelihood"), "--figure", "{file}"],
    ["threshold-study", "--ablation", str(ROOT / "results" / "ablation"), "--markdown", "{file}"],
    ["threshold-study", "--ablation", str(ROOT / "results" / "ablation"), "--figure", "{file}"],
])
def test_an_existing_output_file_is_refused_without_overwrite(tmp_path, capsys, argv):
    mine = tmp_path / ("notes.md" if "--markdown" in argv else "figure.png")
    mine.write_text("my own notes")
    argv = [part.replace("{file}", str(mine)) for part in argv]
    assert usage_error(argv, capsys).endswith(f"{mine} exists; add --overwrite to replace it, or give a new name")
    assert mine.read_text() == "my own notes"


def test_overwrite_replaces_an_output_file(tmp_path, capsys):
    mine = tmp_path / "notes.md"
    mine.write_text("my own notes")
    assert main(["tables", str(SWEEP), "--markdown", str(mine), "--overwrite"]) == 0
    assert "Table 2" in mine.read_text()


def test_the_threshold_study_refuses_a_missing_or_single_models_folder_and_says_what_it_holds(tmp_path, capsys):
    ablation = str(ROOT / "results" / "ablation")
    assert usage_error(["threshold-study", "--ablation", ablation, "--models", str(tmp_path / "none")],
                       capsys).endswith("is not a folder; give the folder that holds the third model's sweeps, one "
                                        "per setting (results/ablation-t-likelihood)")
    single = ROOT / "results" / "ablation-t-likelihood" / "default-variance-threshold-0-1"
    assert "is one model sweep; give the folder that holds one per setting" in usage_error(
        ["threshold-study", "--ablation", ablation, "--models", str(single)], capsys)
    assert main(["threshold-study", "--ablation", ablation, "--models", str(tmp_path)]) == 0
    assert "holds no run of the third model on the study's settings" in capsys.readouterr().out


def test_handout_takes_out_or_zip_not_both(tmp_path, capsys):
    assert usage_error(["course", "handout", "--out", str(tmp_path / "a"), "--zip", str(tmp_path / "b.zip")],
                       capsys).endswith("handout takes --out DIR or --zip FILE, not both")


def test_a_students_answers_are_refused_then_kept_beside_the_new_notebook(tmp_path, capsys):
    tutorials = tiny_course(tmp_path)
    (student,) = write_student_notebooks(tutorials, run=False)
    notebook = nbformat.read(student, as_version=4)
    assert typed_answers(student, notebook) == []
    notebook.cells[1].source = "def my_answer():\n    return 41  # my answer"
    nbformat.write(notebook, student)
    typed = student.read_bytes()
    with pytest.raises(ValueError, match=r"a student typed answers in .*01_unit.ipynb \(1 answer cell: answer\); "
                                         r"add --overwrite"):
        write_student_notebooks(tutorials, run=False)
    assert student.read_bytes() == typed
    argv = ["course", "student", "--tutorials", str(tutorials), "--no-execute"]
    assert "a student typed answers in" in usage_error(argv, capsys)
    assert main([*argv, "--overwrite"]) == 0
    assert f"kept the student's answers of {student} in {student}.bak" in capsys.readouterr().out
    assert Path(f"{student}.bak").read_bytes() == typed
    assert "my answer" not in student.read_text()
    notebook.cells[1].source = "def my_answer():\n    return 40  # typed again"
    nbformat.write(notebook, student)
    assert main([*argv, "--overwrite"]) == 0  # a second backup keeps the first
    assert Path(f"{student}.bak").read_bytes() == typed and "typed again" in Path(f"{student}.bak2").read_text()


@pytest.mark.slow  # starts a kernel
def test_a_cell_that_raises_is_said_in_one_line_and_nothing_is_written(tmp_path, capsys):
    tutorials = tiny_course(tmp_path, failing=True)
    source = tutorials / "source" / "01_unit.ipynb"
    before = source.read_bytes()
    for action in ("sources", "student"):
        assert main(["course", action, "--tutorials", str(tutorials)]) == 1
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "Traceback" not in err[0], err
        assert err[0] == (f"error: {source}: cell 3 ('x = 1') raised ValueError: the world has no goal; no file was "
                          "written for it")
    assert source.read_bytes() == before and not (tutorials / "01_unit.ipynb").exists()


def test_a_hostile_pass_s_losses_and_tracebacks_are_refusals_now(tmp_path, capsys):
    ablation, models = str(ROOT / "results" / "ablation"), str(ROOT / "results" / "ablation-t-likelihood")
    inside = str(ROOT / "results" / "ablation" / "ablation.json")
    assert usage_error(["threshold-study", "--ablation", ablation, "--models", models, "--markdown", inside,
                        "--overwrite"], capsys).endswith("whose files it could replace; write it outside")
    assert usage_error(["course", "handout", "--root", str(ROOT), "--zip", str(tmp_path / "notes.md")],
                       capsys).endswith("name a .zip file")
    assert usage_error(["course", "handout", "--root", str(tmp_path), "--zip", str(tmp_path / "in.zip")],
                       capsys).endswith("whose files it could replace; write it outside")
    assert usage_error(["tables", str(SWEEP), "--markdown", ""], capsys).endswith(
        "--markdown was given an empty file name; give a file to write")
    assert "--out was given an empty folder name" in usage_error(["run", "--out", "", "--episodes", "1"], capsys)
    same = str(tmp_path / "both.pdf")
    assert usage_error(["threshold-study", "--ablation", ablation, "--markdown", same, "--figure", same],
                       capsys).endswith(f"--markdown and --figure name the same file {same}; give each its own")
    assert main(["rule-study", "--out", str(tmp_path / "s"), "--ablation", ablation, "--models", models,
                 "--questions", "fit"]) == 0
    assert "no run stored yet" in capsys.readouterr().out
    assert usage_error(["rule-study", "--out", str(tmp_path / "s"), "--ablation", str(tmp_path)], capsys).endswith(
        "is not an ablation results folder (no ablation.json); the study reads the stored TP and GP runs and the "
        "third model's from there")


def test_two_commands_writing_one_new_markdown_file_do_not_replace_each_other_silently(tmp_path):
    from sarsp_edu._internal.io import atomic_write_text

    target = tmp_path / "tables.md"
    atomic_write_text(target, "first\n", replace=False)
    with pytest.raises(FileExistsError):  # the second writer finds it made meanwhile
        atomic_write_text(target, "second\n", replace=False)
    assert target.read_text() == "first\n" and sorted(p.name for p in tmp_path.iterdir()) == ["tables.md"]
    atomic_write_text(target, "second\n")  # --overwrite: replaced
    assert target.read_text() == "second\n"
