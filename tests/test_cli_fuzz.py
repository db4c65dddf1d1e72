"""Every subcommand fed bad values and damaged folders: a clear one-line error, never a traceback."""

from __future__ import annotations

import json
import re

import pytest

from sarsp_edu.cli import main

TINY = ["--grid-size", "5", "--n-unsafe", "3", "--episodes", "2", "--offline-episodes", "5",
        "--cost-fit-points", "50", "--reward-fit-points", "50", "--k-prior", "20", "--optimizer-steps", "3",
        "--quiet"]
SWEEP_GRID = ["--m", "40", "--p", "0.2", "--nss", "1"]


@pytest.fixture(scope="module")
def stored(tmp_path_factory):
    """A finished one-cell sweep, copied and damaged by the cases below."""
    folder = tmp_path_factory.mktemp("stored") / "sweep"
    assert main(["sweep", *SWEEP_GRID, *TINY, "--out", str(folder)]) == 0
    return folder


def _damage(folder, how):
    import shutil

    cell = folder / "cells" / "m40_p0.2_nss1_seed0"
    if how == "sweep.json cut short":
        path = folder / "sweep.json"
    elif how == "records.csv cut short":
        path = cell / "gp" / "records.csv"
    elif how == "result.json cut short":
        path = cell / "tp" / "result.json"
    elif how == "cell.json cut short":
        path = cell / "cell.json"
    elif how == "records.csv header only":
        path = cell / "tp" / "records.csv"
        path.write_text(path.read_text().splitlines()[0] + "\n")
        return path
    else:
        shutil.rmtree(cell / "gp")
        return cell / "gp"
    text = path.read_text()
    path.write_text(text[: len(text) // 2])
    return path


BAD_VALUES = [
    (["run", "--nu", "2"], "nu"),
    (["run", "--p", "1.5"], "outlier_proportion"),
    (["run", "--p", "abc"], "--p"),
    (["run", "--episodes", "0"], "episodes"),
    (["run", "--grid-size", "2"], "grid_size"),
    (["run", "--n-unsafe", "50"], "n_unsafe"),
    (["run", "--grid-size", "5", "--n-unsafe", "13"], "n_unsafe"),
    (["run", "--k-prior", "-1"], "k_prior"),
    (["run", "--cost-fit-points", "1"], "cost_fit_points"),
    (["run", "--max-steps", "0"], "max_steps"),
    (["run", "--retrain", "sometimes"], "--retrain"),
    (["run", "--preset", "fast"], "--preset"),
    (["compare", "--a", "0"], "a must lie"),
    (["compare", "--nss", "20"], "n_switch_states"),
    (["sweep", "--m", "-1"], "magnitudes"),
    (["sweep", "--p", "2"], "proportions"),
    (["sweep", "--nss", "99"], "n_switch_states"),
    (["sweep", "--seeds", "-1"], "seeds"),
    (["sweep", "--jobs", "0"], "n_jobs"),
    (["tables", "/nonexistent/sweep"], "/nonexistent/sweep"),
    (["ablation", "--settings", "nope"], "nope"),
    (["ablation", "--cells", "40", "0.2"], "--cells"),
    (["ablation", "--episodes", "0"], "episodes"),
    (["ablation", "--seeds", "-1"], "seeds"),
]


def _one_error_line(argv, capsys, named):
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code in (1, 2)
    err = capsys.readouterr().err
    assert "Traceback" not in err
    errors = [line for line in err.splitlines() if re.match(r"(usage: )?sarsp-edu.*error: ", line)]
    assert len(errors) == 1, err
    assert named in errors[0], errors[0]


@pytest.mark.parametrize("argv, named", BAD_VALUES)
def test_bad_values(argv, named, capsys, tmp_path):
    _one_error_line(argv + ["--quiet"] if argv[0] not in ("tables",) else argv, capsys, named)
    assert not list(tmp_path.rglob("*"))  # nothing written


def test_model_sweep_jobs(capsys, tmp_path):
    """As the library's: a positive number or -1 (one per core); -1 passes on to the next check."""
    argv = ["model-sweep", "--paired", str(tmp_path / "paired"), "--out", str(tmp_path / "out"), "--jobs"]
    _one_error_line(argv + ["0"], capsys, "--jobs takes a whole number >= 1, or -1 (one per core), got 0")
    _one_error_line(argv + ["-1"], capsys, str(tmp_path / "paired"))
    assert not list(tmp_path.rglob("*"))

@pytest.mark.parametrize("command", ["run", "compare", "sweep", "ablation"])
def test_out_paths(command, capsys, tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("x")
    _one_error_line([command, "--out", str(afile), "--quiet"], capsys, str(afile))
    _one_error_line([command, "--out", str(afile / "sub"), "--quiet"], capsys, str(afile))
    assert afile.read_text() == "x"


@pytest.mark.parametrize("how", ["sweep.json cut short", "records.csv cut short", "result.json cut short",
                                 "cell.json cut short", "records.csv header only", "gp run missing"])
def test_damaged_folders(how, stored, capsys, tmp_path):
    import shutil

    folder = tmp_path / "sweep"
    shutil.copytree(stored, folder)
    path = _damage(folder, how)
    # tables names what is wrong and refuses
    named = "partial sweep" if how == "cell.json cut short" else str(path)
    if how == "cell.json cut short":
        named = str(path.parent)
    _one_error_line(["tables", str(folder)], capsys, named)
    # a sweep repairs what it can and refuses what it cannot
    if how == "sweep.json cut short":
        _one_error_line(["sweep", *SWEEP_GRID, *TINY, "--out", str(folder)], capsys, str(path))
    else:
        from sarsp_edu.experiments.sweep import StoredResultWarning

        with pytest.warns(StoredResultWarning, match="computing the cell again"):
            assert main(["sweep", *SWEEP_GRID, *TINY, "--out", str(folder)]) == 0
        assert "Traceback" not in capsys.readouterr().err
        assert main(["tables", str(folder)]) == 0
    assert not [p for p in folder.rglob("*") if p.name.endswith(".tmp") or p.name.startswith(".m")]


def test_a_sweep_folder_with_other_settings(stored, capsys, tmp_path):
    import shutil

    folder = tmp_path / "sweep"
    shutil.copytree(stored, folder)
    _one_error_line(["sweep", *SWEEP_GRID, *TINY, "--k-prior", "21", "--out", str(folder)], capsys,
                    "other settings (k_prior")
    assert json.loads((folder / "sweep.json").read_text())["base_config"]["k_prior"] == 20
