"""Stored results that disagree with themselves are refused, no work is lost, extreme values are
refused before any work, and every message gives the true reason."""

from __future__ import annotations

import json
import math
import re
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import sarsp_edu
from sarsp_edu import ExperimentConfig, run_experiment, run_sweep
from sarsp_edu.cli import main
from sarsp_edu.experiments.provenance import _source_files, code_provenance
from sarsp_edu.experiments.results import Comparison, ExperimentResult, StoredResultError
from sarsp_edu.experiments.sweep import LOCK_NAME, StoredResultWarning, SweepResults
from sarsp_edu.experiments.tables import summary_tables

from .test_cli import _usage_error as usage_error  # a usage error's last line, with no traceback
from .worlds import FIVE_BY_FIVE

TINY = ExperimentConfig(**FIVE_BY_FIVE, episodes=3)
GRID = dict(magnitudes=(40,), proportions=(0.2,), n_switch_states=(1, 2))
SETTINGS = ["--grid-size", "5", "--n-unsafe", "3", "--episodes", "3", "--offline-episodes", "5",
            "--cost-fit-points", "50", "--reward-fit-points", "50", "--k-prior", "20", "--optimizer-steps", "3",
            "--quiet"]
FLAGS = [*SETTINGS, "--m", "40", "--p", "0.2", "--nss", "1", "2"]  # the sweep GRID
CELL = "m40_p0.2_nss1_seed0"


@pytest.fixture(scope="module")
def stored(tmp_path_factory):
    folder = tmp_path_factory.mktemp("stored") / "sweep"
    run_sweep(TINY, **GRID, results_dir=folder)
    return folder


@pytest.fixture
def sweep(stored, tmp_path):
    """A fresh copy of the stored sweep, to damage."""
    folder = tmp_path / "sweep"
    shutil.copytree(stored, folder)
    return folder


def edit_json(path, change):
    payload = json.loads(path.read_text())
    change(payload)
    path.write_text(json.dumps(payload))


# -- 2. a stored result that disagrees with its sweep is refused, not used ---------------------------
def test_a_cell_run_with_other_settings_is_named_by_tables_and_recomputed_by_a_resume(sweep, capsys):
    result_json = sweep / "cells" / CELL / "tp" / "result.json"
    edit_json(result_json, lambda p: p["config"].update(nu=5.0))
    with pytest.raises(StoredResultError, match=rf"{CELL}/tp/result.json is not this sweep's cell m=40 p=0.2 nss=1 "
                                                r"seed=0: it ran nu=5.0 where the sweep gives 3.0"):
        SweepResults.load(sweep)
    assert "it ran nu=5.0 where the sweep gives 3.0" in usage_error(["tables", str(sweep)], capsys)
    with pytest.warns(StoredResultWarning, match="it ran nu=5.0 where the sweep gives 3.0; computing the cell again"):
        resumed = run_sweep(TINY, **GRID, results_dir=sweep)
    assert json.loads(result_json.read_text())["config"]["nu"] == 3.0
    fresh = run_sweep(TINY, **GRID)
    assert resumed.frame().equals(fresh.frame())


def test_a_sweep_json_that_no_cell_ran_is_refused_with_the_true_reason(sweep, capsys):
    edit_json(sweep / "sweep.json", lambda p: p["base_config"].update(episodes=20))
    reason = "sweep.json does not describe the 2 cells stored beside it (episodes=20 where they ran episodes=3)"
    with pytest.raises(StoredResultError, match=re.escape(reason)):
        SweepResults.load(sweep)
    assert usage_error(["tables", str(sweep)], capsys).endswith(reason + ": it was edited or belongs to another "
                                                               "sweep; restore it, or move the cells to their "
                                                               "own folder")
    assert reason in usage_error(["sweep", "--out", str(sweep)], capsys)
    assert reason in usage_error(["sweep", *FLAGS, "--episodes", "20", "--out", str(sweep)], capsys)


def test_a_gutted_sweep_json_is_refused_not_filled_with_defaults(sweep, capsys):
    edit_json(sweep / "sweep.json", lambda p: p.update(base_config={"nu": 3.0}))
    err = usage_error(["tables", str(sweep)], capsys)
    assert "sweep.json holds an invalid base_config: the config lacks the fields [" in err
    assert "folder 250" not in err


def test_a_records_row_that_disagrees_with_its_summary_is_refused(sweep):
    records = sweep / "cells" / CELL / "gp" / "records.csv"
    table = pd.read_csv(records)
    table.loc[table.index[-1], "total_cost"] += 7
    table.to_csv(records, index=False)
    with pytest.raises(StoredResultError, match=r"gp/result.json gives total_cost=\S+ where the last row of "
                                                r"records.csv beside it gives \S+: one of the two was edited"):
        SweepResults.load(sweep)


def test_a_cell_under_another_cells_name_belongs_to_another_cell(sweep):
    edit_json(sweep / "cells" / CELL / "cell.json", lambda p: p.update(key=[40.0, 0.2, 2, 0]))
    with pytest.raises(StoredResultError, match=f"{CELL} belongs to another cell: its cell.json says m=40 p=0.2 "
                                                "nss=2 seed=0, its place m=40 p=0.2 nss=1 seed=0"):
        SweepResults.load(sweep)
    with pytest.warns(StoredResultWarning, match="belongs to another cell"):
        run_sweep(TINY, **GRID, results_dir=sweep)


def test_a_second_sweep_in_the_same_folder_is_told_another_sweep_holds_it(sweep, capsys):
    import fcntl

    with open(sweep / LOCK_NAME, "w") as held:
        fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
        held.write("4242\n")
        held.flush()
        with pytest.raises(ValueError, match=f"another sweep is running in {sweep} \\(process 4242\\); wait"):
            run_sweep(TINY, **GRID, results_dir=sweep)
        assert "another sweep is running in" in usage_error(["sweep", "--out", str(sweep)], capsys)
    run_sweep(TINY, **GRID, results_dir=sweep)  # released: resumes


def test_tables_of_an_absent_seed_names_the_seeds_present(sweep, capsys):
    assert usage_error(["tables", str(sweep), "--seeds", "5"], capsys).endswith(
        "holds no cell of seed 5; its seeds are 0")


def test_every_result_records_its_code_and_tables_say_when_cells_differ(sweep, capsys):
    code = json.loads((sweep / "cells" / CELL / "tp" / "result.json").read_text())["code"]
    assert code == code_provenance()
    assert len(code["source_sha256"]) == 64 and code["numpy"] == np.__version__
    assert main(["tables", str(sweep)]) == 0
    assert "versions of the code" not in capsys.readouterr().out
    edit_json(sweep / "cells" / CELL / "gp" / "result.json", lambda p: p["code"].update(source_sha256="0" * 64))
    assert main(["tables", str(sweep)]) == 0
    assert "note: the runs were computed by 2 versions of the code" in capsys.readouterr().out


# -- 3. no work lost, nothing overwritten without asking ----------------------------------------------
def refuse_work(monkeypatch):
    """Any computing now fails the test: a refusal must come before the work."""
    import sarsp_edu.experiments.experiment

    def no_work(*args, **kwargs):
        raise AssertionError("the work started before the refusal")

    for name in ("run_experiment", "compare"):
        monkeypatch.setattr(sarsp_edu.experiments.experiment, name, no_work)


def test_the_source_hash_covers_every_python_file_of_the_package():
    """The hash a result records is of the whole package, not of the folder the provenance module lives in
    (from the move to layer folders until this test, it hashed sarsp_edu/experiments alone, so a change to
    the models or the agent left a run's recorded source the same)."""
    package = Path(sarsp_edu.__file__).resolve().parent
    hashed = {path.relative_to(package).as_posix() for path in _source_files()}
    assert hashed == {path.relative_to(package).as_posix() for path in package.rglob("*.py")}
    assert {"models/processes/laplace.py", "agent/sarsp.py", "world/preparation.py", "__init__.py"} <= hashed


def test_a_compare_of_other_settings_is_not_overwritten(tmp_path, capsys):
    out = tmp_path / "c"
    assert main(["compare", *SETTINGS, "--out", str(out)]) == 0
    err = usage_error(["compare", *SETTINGS, "--nu", "4", "--out", str(out)], capsys)
    assert "holds a compare of other settings (nu: stored 3.0, now 4.0); to keep both, give another folder; " \
           "to replace it, add --overwrite" in err
    assert main(["compare", *SETTINGS, "--nu", "4", "--out", str(out), "--overwrite"]) == 0
    assert json.loads((out / "gp" / "result.json").read_text())["config"]["nu"] == 4.0


@pytest.mark.parametrize("out, reason", [("/proc/sarsp-edu-x", "cannot be written"),
                                         ("FILE/inside", "cannot be made: FILE is a file")])
def test_a_bad_out_is_found_before_any_work_and_nothing_is_left(tmp_path, capsys, monkeypatch, out, reason):
    (tmp_path / "FILE").write_text("x")
    monkeypatch.chdir(tmp_path)
    refuse_work(monkeypatch)
    for command in ("run", "compare"):
        assert reason in usage_error([command, "--out", out], capsys)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["FILE"]


def test_a_writable_out_is_probed_without_leaving_anything(tmp_path, capsys, monkeypatch):
    refuse_work(monkeypatch)
    with pytest.raises(AssertionError, match="the work started"):
        main(["run", "--out", str(tmp_path / "new" / "deep"), "--quiet"])
    assert not (tmp_path / "new").exists()


def test_a_config_of_numpy_numbers_runs_and_saves(tmp_path):
    config = TINY.replace(episodes=np.int64(2), nu=np.float64(3.5), outlier_magnitude=np.int32(60),
                          cost_outliers=np.bool_(True))
    assert type(config.episodes) is int and type(config.outlier_magnitude) is int
    result = run_experiment(config)
    result.save(tmp_path / "r")
    assert ExperimentResult.load(tmp_path / "r").config == config


def test_sweep_out_alone_resumes_the_stored_sweep_with_its_settings(sweep, capsys):
    shutil.rmtree(sweep / "cells" / CELL)
    assert main(["sweep", "--out", str(sweep), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert f"resuming the sweep in {sweep}: 2 cells, preset custom (its stored settings)" in captured.err
    assert "2 cells, each a paired TP-vs-GP run of 3 episodes" in captured.out
    assert (sweep / "cells" / CELL / "cell.json").exists()


def test_the_tables_hint_quotes_a_path_with_spaces(tmp_path, capsys):
    out = tmp_path / "my sweep"
    assert main(["sweep", *FLAGS, "--nss", "1", "--out", str(out)]) == 0
    assert f"print every table with: sarsp-edu tables '{out}'" in capsys.readouterr().out


# -- 4. extreme values: a clear error before the work -------------------------------------------------
@pytest.mark.parametrize("flag, value, message", [
    ("--episodes", "99999999999999999999", "episodes must be an integer from 1 to 100000"),
    ("--episodes", "1000000000", "episodes must be an integer from 1 to 100000"),
    ("--m", "1e200", "outlier_magnitude must be a positive number of at most 10000"),
    ("--n-samples", "100000000000000000000", "n_samples must be an integer from 2 to 10000"),
    ("--nu", "1e308", "nu must be a number above 2 and at most 1e+06 (beyond it the TP's variance factor"),
    ("--optimizer-steps", "100000000000000000000", "optimizer_steps must be an integer from 1 to 10000"),
    ("--grid-size", "1000", "grid_size must be an integer from 2 to 50"),
    ("--k-prior", "1000000", "k_prior must be an integer from 1 to 5000"),
])
def test_extreme_values_are_refused_before_any_work(flag, value, message, capsys, monkeypatch):
    refuse_work(monkeypatch)
    for command in ("run", "compare"):
        assert message in usage_error([command, flag, value], capsys)


def test_a_scheduler_without_dask_is_one_line_naming_the_extra(tmp_path, capsys, monkeypatch):
    import importlib.util
    import sys

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name.startswith("dask") else real(name, *a))
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    refuse_work(monkeypatch)
    assert usage_error(["sweep", "--scheduler", "tcp://127.0.0.1:1", "--out", str(tmp_path / "s")], capsys) == (
        "sarsp-edu sweep: error: --scheduler needs Dask, which is not installed: pip install 'sarsp_edu[dask]'")
    with pytest.raises(ImportError, match=r"pip install 'sarsp_edu\[dask\]'"):
        run_sweep(TINY, **GRID, scheduler="tcp://127.0.0.1:1")


def test_a_setting_the_other_settings_ignore_is_reported(tmp_path, capsys):
    assert main(["run", *SETTINGS, "--n-samples", "50", "--model", "gp", "--nu", "5", "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "warning: --n-samples is ignored: predictions are exact (predictive='closed_form')" in err
    assert "warning: --nu is ignored: it is the TP's degrees of freedom, and model='gp'" in err


# -- 5. small truths -----------------------------------------------------------------------------------
def test_undefined_cost_rates_are_left_out_of_the_levels_and_the_wilcoxon_test(stored):
    results = SweepResults.load(stored)
    first, second = results.comparisons.values()
    for run, (total_cost, cost_rate) in zip((first.tp, first.gp, second.tp, second.gp),
                                            [(2.0, 0.1), (4.0, 0.0), (1.0, 0.2), (3.0, 0.3)]):
        run.records.loc[run.records.index[-1], ["total_cost", "cost_rate"]] = [total_cost, cost_rate]
    # the first configuration's GP cost rate is undefined: violations, no clean success
    tables = summary_tables(results)
    levels, wilcoxon = tables["levels"], tables["wilcoxon"]
    assert levels.loc["cost_rate", "GP n"] == 1 and levels.loc["cost_rate", "TP n"] == 2
    assert levels.loc["mean_cost", "GP n"] == 2
    assert wilcoxon.loc["cost_rate", "n"] == 1 and wilcoxon.loc["cost_rate", "left out (p_c undefined)"] == 1
    assert levels.loc["cost_rate", "GP"] == 0.3 and levels.loc["cost_rate", "TP"] == pytest.approx(0.15)
    assert math.isnan(levels.loc["cost_rate", "GP 95% CI low"])  # one value: no interval



# -- the stored results are what the code computes -----------------------------------------------
#: per-episode diagnostics of the models' predictions: sums of predicted values whose last digits depend on
#: the BLAS kernels of the processor (OpenBLAS runs its SkylakeX kernels on some machines of this kind, its
#: Haswell ones on others). They are compared relative to each diagnostic's largest value over the run: the
#: third model's cell below, computed on a SkylakeX machine, has an episode whose cost prediction error is
#: 2.9e-6, and the Haswell kernels move it by 1.7e-10, the size of every other episode's difference (a relative
#: 5.8e-5 of that episode's value, 2e-10 of the run's scale). Every other column, the agents' steps and
#: everything counted from them, is the same to the last digit.
def test_a_stored_cell_of_the_reduced_sweep_is_what_the_code_computes():
    """Recomputed on this machine: every column equal, the prediction diagnostics to 1e-7 of their scale."""
    from pathlib import Path

    from sarsp_edu.experiments.sweep import check_cell

    report = check_cell(Path(__file__).resolve().parents[1] / "results" / "sweep-reduced", "m40_p0.2_nss2_seed0")
    assert report.identical, str(report)
    assert report.tp.episodes == report.gp.episodes == 10
    assert set(report.tp.diagnostics) == {"reward_mse", "cost_prediction_error", "safe_action_variance"}


def test_a_stored_run_of_the_third_model_on_the_reduced_sweep_is_what_the_code_computes():
    """The GP with Student-t noise on a cell of the reduced sweep, recomputed: every column equal, the prediction
    diagnostics to 1e-7 of their scale."""
    from pathlib import Path

    from sarsp_edu.experiments.sweep.models import check_model_cell

    folder = Path(__file__).resolve().parents[1] / "results" / "sweep-reduced-t-likelihood"
    report = check_model_cell(folder, "m40_p0.2_nss2_seed0")
    assert report.differing_columns == () and report.episodes == 10, report
    assert all(value <= 1e-7 for value in report.diagnostics.values()), report


def test_check_cell_names_the_first_episode_and_the_columns_that_differ(sweep, capsys):
    from sarsp_edu.experiments.sweep import check_cell

    same = check_cell(sweep, CELL, n_jobs=1)
    assert same.identical and same.same_trajectories and "identical" in str(same)
    tp, gp = (sweep / "cells" / CELL / side / "records.csv" for side in ("tp", "gp"))
    records = pd.read_csv(tp)
    records.loc[1, "backup_rate"] = (records.loc[1, "backup_rate"] + 0.25) % 1  # parted at the second episode
    records.to_csv(tp, index=False)
    records = pd.read_csv(gp)
    records.loc[0, "reward_mse"] *= 1 + 1e-4  # a diagnostic's last digits, beyond the tolerance
    records.to_csv(gp, index=False)
    report = check_cell(sweep, CELL, n_jobs=1)
    assert not report.identical and not report.same_trajectories
    assert report.tp.differing_columns == ("backup_rate",) and report.tp.first_differing_episode == 1
    assert report.gp.differing_columns == () and report.gp.diagnostics["reward_mse"] > 1e-5
    assert "TP: first at episode 2 of 3: backup_rate" in str(report)
    assert main(["check-cell", str(sweep), CELL, "--jobs", "1"]) == 1
    assert "NOT identical" in capsys.readouterr().out
    assert check_cell(sweep, CELL, n_jobs=1, rtol=1e-3).gp.diagnostics["reward_mse"] < 1e-3


def test_check_cell_names_a_bad_cell():
    from pathlib import Path

    from sarsp_edu.experiments.sweep import check_cell

    folder = Path(__file__).resolve().parents[1] / "results" / "sweep-reduced"
    with pytest.raises(ValueError, match=r"cell='m40_p0.2' is not a cell's name; expected one like"):
        check_cell(folder, "m40_p0.2")
    with pytest.raises(ValueError, match=r"cell='m40_p0.2_nss2_seed7': .* holds no such cell \(\d+ stored"):
        check_cell(folder, "m40_p0.2_nss2_seed7")


RESULTS = Path(__file__).resolve().parents[1] / "results"


def test_constraints_pin_the_versions_the_stored_results_record():
    """constraints.txt, which the test command, CI and Binder install with, names the numpy and scipy every stored
    result records (results stored before the provenance was recorded say nothing)."""
    lines = (RESULTS.parent / "constraints.txt").read_text().splitlines()
    pins = dict(line.split("==") for line in lines if line.strip() and not line.startswith("#"))
    recorded = {(code["numpy"], code["scipy"]) for code in (json.loads(path.read_text()).get("code")
                                                            for path in RESULTS.rglob("result.json")) if code}
    assert recorded == {(pins["numpy"], pins["scipy"])}, recorded


def _committed(folder: Path, into: Path) -> Path:
    """A copy of a model sweep's folder with only the files git tracks (a sweep running here adds cells that
    are not committed yet, nor in REPRODUCTION.md); the folder itself where git is not there to ask."""
    import subprocess

    try:
        listed = subprocess.run(["git", "ls-files", "-z", "--", "."], cwd=folder, capture_output=True, check=True)
    except (OSError, subprocess.CalledProcessError):  # not a git checkout: every file there is the package's
        return folder
    for name in filter(None, listed.stdout.decode().split("\0")):
        (into / folder.name / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(folder / name, into / folder.name / name)
    paired = json.loads((folder / "model_sweep.json").read_text())["paired"]  # a path relative to the folder
    (into / folder.name / paired).resolve().symlink_to((folder / paired).resolve(), target_is_directory=True)
    return into / folder.name


def test_reproduction_md_holds_the_three_model_tables_of_the_cells_stored(tmp_path, capsys):
    """REPRODUCTION.md's "Beyond the paper" tables are what ``sarsp-edu tables --markdown`` writes from the
    three-model sweep's committed cells, and every count of its cells is theirs: a cell committed without the
    section redone fails here."""
    folder, markdown = _committed(RESULTS / "sweep-default-t-likelihood", tmp_path), tmp_path / "three.md"
    assert main(["tables", str(folder), "--markdown", str(markdown)]) == 0
    text = (RESULTS.parent / "REPRODUCTION.md").read_text()
    tables = markdown.read_text().strip().split("\n\n")
    assert len(tables) == 4  # Table 2 with a third column, the tests, Definition 4, each configuration
    for table in tables:  # whole: followed by a blank line, not by more rows of an older table
        assert f"\n{table}\n\n" in text, f"REPRODUCTION.md lacks this table as the stored cells give it:\n{table}"
    cells = len(list((folder / "cells").glob("m*/t-likelihood/result.json")))
    configurations = len(tables[3].splitlines()) - 2
    words = " ".join(text.split())
    if cells == 135:  # complete: said so, with no count of a partial sweep left
        counts = ("its sweep holds all 135 cells", "All 135 cells are stored", "third column (the 45 configurations)")
        section = words.split("## Beyond the paper")[1].split("## Reproduce")[0]
        assert configurations == 45 and " of 135 cells" not in words and "so far" not in section
    else:
        counts = (f"its sweep holds {cells} of 135 cells", f"{cells} of the 135 cells are stored",
                  f"({configurations} of the 45 configurations")
    for said in (*counts, f"the mean over the {cells} cells"):
        assert said in words, said


@pytest.mark.parametrize("folder", sorted(p.name for p in RESULTS.iterdir() if p.is_dir()))
def test_every_shipped_results_folder_loads_with_tables(folder, capsys):
    """Every folder under results/ loads: a sweep's tables (older formats read in today's terms; a sweep still
    running across sessions, its stored cells), an ablation's table, a rule study's tables."""
    assert main(["tables", str(RESULTS / folder), "--allow-partial"]) == 0
    out = capsys.readouterr().out
    assert ("TP" in out and "GP" in out) and "error" not in out.lower()


def test_an_older_format_cell_is_compared_in_todays_terms():
    """paper-sweep's cells say retrain=True (sarsp_edu 0.1): that is today's retrain='always', as sweep.json says."""
    from sarsp_edu.experiments.sweep import stored_sweep

    cell = json.loads(next((RESULTS / "paper-sweep" / "cells").glob("*/tp/result.json")).read_text())
    assert cell["config"]["retrain"] is True
    base, _ = stored_sweep(RESULTS / "paper-sweep")
    assert base.retrain == "always"


def _edit_records(path, change, summary_too=False):
    """Edit a stored records.csv (and, to hide the edit, its result.json's summary)."""
    table = pd.read_csv(path)
    change(table)
    table.to_csv(path, index=False)
    if summary_too:
        last = table.iloc[-1]
        edit_json(path.parent / "result.json",
                  lambda p: p["summary"].update({k: float(last[k]) for k in p["summary"]}))


@pytest.mark.parametrize("change, summary_too, message", [
    (lambda t: t.__setitem__("task_success_rate", 150.0), True,
     r"has task_success_rate=150.0 in episode 1: it must be in \[0, 100\]"),
    (lambda t: t.loc.__setitem__((1, "episode_cost"), -1), False,
     r"has episode_cost=-1 in episode 2: it must be a whole"),
    (lambda t: t.__setitem__("episode_cost", t["episode_cost"].astype(float) + [0, 0.5, 0]), False,
     r"has episode_cost=0.5 in episode 2: it must be a whole"),
    (lambda t: t.loc.__setitem__((1, "mean_steps"), math.inf), False, r"has mean_steps=inf in episode 2"),
    (lambda t: t.loc.__setitem__((0, "safe_action_variance"), -0.3), False,
     r"has safe_action_variance=-0.3 in episode 1: it must be in \[0, inf\]"),
    (lambda t: t.loc.__setitem__((0, "start"), "7 2"), False, r"has start=\(7, 2\) in episode 1: off the 5 x 5 grid"),
    (lambda t: t.loc.__setitem__((0, "goal"), "-1 0"), False, r"has goal=\(-1, 0\) in episode 1: off the 5 x 5 grid"),
    (lambda t: t.loc.__setitem__((0, "episode_cost"), t.loc[0, "episode_cost"] + 2), False,
     r"has mean_cost=\S+ in episode 1, where the episodes' rewards, costs, steps and successes up to it give"),
])
def test_a_stored_value_out_of_its_range_is_refused_naming_file_row_and_column(sweep, capsys, change, summary_too,
                                                                                message):
    records = sweep / "cells" / CELL / "gp" / "records.csv"
    _edit_records(records, change, summary_too)
    with pytest.raises(StoredResultError, match=message):
        ExperimentResult.load(records.parent)
    assert re.search(message, usage_error(["tables", str(sweep)], capsys))


def test_swapped_rows_are_named_as_moved_not_as_a_short_run(sweep):
    records = sweep / "cells" / CELL / "gp" / "records.csv"
    _edit_records(records, lambda t: t.__setitem__("episode", t["episode"].to_numpy()[[1, 0, 2]]))
    with pytest.raises(StoredResultError, match=r"has episode 2 in row 1, where the episodes run 1 to 3 in order"):
        ExperimentResult.load(records.parent)


def test_a_comparison_of_two_runs_is_refused(sweep, tmp_path):
    other = tmp_path / "other"
    shutil.copytree(sweep / "cells" / CELL, other)
    shutil.rmtree(other / "gp")
    shutil.copytree(sweep / "cells" / "m40_p0.2_nss2_seed0" / "gp", other / "gp")
    with pytest.raises(StoredResultError, match=r"tp/ and gp/ are not one paired comparison \(n_switch_states 1 "
                                                r"against 2, seed \d+ against \d+\)"):
        Comparison.load(other)


def test_a_run_of_another_model_does_not_replace_a_stored_run(tmp_path, capsys):
    out = tmp_path / "r"
    assert main(["run", *SETTINGS, "--out", str(out)]) == 0
    err = usage_error(["run", *SETTINGS, "--model", "gp", "--out", str(out)], capsys)
    assert "holds a run of other settings (model: stored 'tp', now 'gp')" in err
    assert json.loads((out / "result.json").read_text())["config"]["model"] == "tp"
    assert main(["run", *SETTINGS, "--out", str(out)]) == 0  # the same settings again: replaced, as said


@pytest.mark.parametrize("command", ["run", "compare"])
def test_a_second_command_writing_the_same_out_is_refused_while_the_first_runs(tmp_path, capsys, command):
    from sarsp_edu._internal.io import lock_folder
    from sarsp_edu.experiments.sweep import LOCK_NAME

    out = tmp_path / "busy"
    out.mkdir()
    holder = lock_folder(out, LOCK_NAME, "sweep")  # another process's command, in the middle of its run
    try:
        err = usage_error([command, *SETTINGS, "--out", str(out)], capsys)
    finally:
        holder.close()
    assert f"another sarsp-edu command is running in {out} (process " in err
    assert not (out / "result.json").exists() and not (out / "tp").exists()
    assert main([command, *SETTINGS, "--out", str(out)]) == 0  # once it is done, the folder is free
