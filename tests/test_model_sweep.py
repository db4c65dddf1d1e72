"""A third model on the cells of a stored paired sweep, and the cells that raise in any sweep: named, the others
run on (``sweep.failures``)."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from sarsp_edu import run_sweep
from sarsp_edu.experiments.sweep import cell_config

from .test_sweep import TINY


def test_a_third_model_runs_on_the_very_worlds_of_a_stored_sweep_resumes_and_reads_back_paired(tmp_path):
    from sarsp_edu.experiments.experiment import run_experiment
    from sarsp_edu.experiments.sweep.models import load_model_sweep, run_model_sweep

    run_sweep(TINY, magnitudes=(40,), proportions=(0.2,), n_switch_states=(1, 2), seeds=(0,),
              results_dir=tmp_path / "paired")
    with pytest.raises(ValueError, match="model must be one of"):
        run_model_sweep(tmp_path / "paired", tmp_path / "tl", model="gp")
    with pytest.raises(ValueError, match="not cells of the paired sweep"):
        run_model_sweep(tmp_path / "paired", tmp_path / "tl", cells=[(60.0, 0.2, 1, 0)])
    with pytest.raises(ValueError, match="holds a paired sweep"):  # never into the paired sweep's own folder
        run_model_sweep(tmp_path / "paired", tmp_path / "paired")
    for n_jobs in (0, -2, 1.5, True, "2"):
        with pytest.raises(ValueError, match=rf"positive integer or -1 \(one per core\), got n_jobs={n_jobs!r}"):
            run_model_sweep(tmp_path / "paired", tmp_path / "tl", n_jobs=n_jobs)
    assert not (tmp_path / "tl").exists()  # refused before anything is written
    said = []
    with pytest.warns(UserWarning, match=r"n_jobs=3: running 1 worker process, for 1 cell to run on"):
        first = run_model_sweep(tmp_path / "paired", tmp_path / "tl", cells=[(40.0, 0.2, 1, 0)], n_jobs=3,
                                report=said.append)
    assert first == {(40.0, 0.2, 1, 0)} and said == [
        "t-likelihood: running 1 of 1 cells (0 stored) in 1 worker process: each fits its models, then runs its 3 "
        "episodes; a line as each is stored", "t-likelihood: m40_p0.2_nss1_seed0 stored (1 of 1)"]
    interrupted = tmp_path / "tl" / "cells" / "m40_p0.2_nss2_seed0" / ".t-likelihood.x1"
    interrupted.mkdir(parents=True)  # a run whose storing was cut short: cleared, and the run made again
    stored = (tmp_path / "tl" / "cells" / "m40_p0.2_nss1_seed0" / "t-likelihood" / "records.csv").read_bytes()
    assert run_model_sweep(tmp_path / "paired", tmp_path / "tl", n_jobs=1) == {(40.0, 0.2, 1, 0), (40.0, 0.2, 2, 0)}
    assert not interrupted.exists()
    assert (tmp_path / "tl" / "cells" / "m40_p0.2_nss1_seed0" / "t-likelihood" / "records.csv").read_bytes() == stored
    paired, runs = load_model_sweep(tmp_path / "tl")
    assert set(runs) == set(paired.comparisons)
    run_sweep(TINY, magnitudes=(40,), proportions=(0.2,), n_switch_states=(1,), seeds=(0,),
              results_dir=tmp_path / "another")
    with pytest.raises(ValueError, match="holds runs of 't-likelihood' on the paired sweep"):
        run_model_sweep(tmp_path / "another", tmp_path / "tl")  # the folder's runs belong to another sweep
    key = (40.0, 0.2, 2, 0)
    again = run_experiment(cell_config(TINY, *key).replace(model="t-likelihood"))  # the stored run, recomputed
    pd.testing.assert_frame_equal(again.records, runs[key].records)
    assert runs[key].records["start"].tolist() == paired.comparisons[key].gp.records["start"].tolist()


def test_a_cell_that_raises_is_named_and_the_other_cells_still_run(tmp_path, monkeypatch, capsys):
    import pickle

    import sarsp_edu.experiments.experiment as experiment
    from sarsp_edu.cli import main
    from sarsp_edu.experiments.sweep.models import CellsFailed, run_model_sweep

    run_sweep(TINY, magnitudes=(40,), proportions=(0.2,), n_switch_states=(1, 2, 3), seeds=(0,),
              results_dir=tmp_path / "paired")
    original = experiment.run_experiment

    def failing(config, *args, **kwargs):  # the middle cell raises, as a saddle once stopped the sweep
        if config.n_switch_states == 2:
            raise RuntimeError("the Laplace approximation has no maximum here")
        return original(config, *args, **kwargs)

    monkeypatch.setattr(experiment, "run_experiment", failing)
    said = []
    with pytest.raises(CellsFailed, match=r"1 cell raised \(m40_p0.2_nss2_seed0: RuntimeError: the Laplace") as caught:
        run_model_sweep(tmp_path / "paired", tmp_path / "tl", n_jobs=1, report=said.append)
    assert list(caught.value.failures) == [(40.0, 0.2, 2, 0)]
    line, text = caught.value.failures[(40.0, 0.2, 2, 0)]
    assert line == "RuntimeError: the Laplace approximation has no maximum here" and "in failing" in text  # all kept
    assert pickle.loads(pickle.dumps(caught.value)).failures == caught.value.failures  # as from a worker
    assert said == ["t-likelihood: running 3 of 3 cells (0 stored) in 1 worker process: each fits its models, then "
                    "runs its 3 episodes; a line as each is stored",
                    "t-likelihood: m40_p0.2_nss1_seed0 stored (1 of 3)",
                    "t-likelihood: m40_p0.2_nss2_seed0 raised RuntimeError: the Laplace approximation has no maximum "
                    "here (1 of 3 stored)",
                    "t-likelihood: m40_p0.2_nss3_seed0 stored (2 of 3)"]
    cells = tmp_path / "tl" / "cells"
    assert sorted(p.name for p in cells.iterdir()) == ["m40_p0.2_nss1_seed0", "m40_p0.2_nss3_seed0"]  # nothing half
    # the command says so and fails; the rerun, once the cause is gone, runs the missing cell alone
    command = ["model-sweep", "--paired", str(tmp_path / "paired"), "--out", str(tmp_path / "tl"), "--jobs", "1"]
    assert main(command) == 1
    err = capsys.readouterr().err
    assert "m40_p0.2_nss2_seed0:\nTraceback" in err and "error: 1 cell raised" in err
    monkeypatch.setattr(experiment, "run_experiment", original)
    said.clear()
    assert len(run_model_sweep(tmp_path / "paired", tmp_path / "tl", n_jobs=1, report=said.append)) == 3
    assert said[1:] == ["t-likelihood: m40_p0.2_nss2_seed0 stored (3 of 3)"]
    assert said[0].startswith("t-likelihood: running 1 of 3 cells (2 stored) in 1 worker process")


def test_a_paired_cell_that_raises_is_named_and_the_other_cells_still_run(tmp_path, monkeypatch, capsys):
    from sarsp_edu.cli import main
    from sarsp_edu.experiments.sweep import run as sweep_module  # where the cells are run
    from sarsp_edu.experiments.sweep.failures import CellsFailed

    original = sweep_module.compare

    def failing(config, *args, **kwargs):  # the middle cell raises; Ctrl-C at m = 50
        if config.outlier_magnitude == 50:
            raise KeyboardInterrupt
        if config.n_switch_states == 2:
            raise np.linalg.LinAlgError("Matrix is not positive definite")
        return original(config, *args, **kwargs)

    monkeypatch.setattr(sweep_module, "compare", failing)
    grid = dict(magnitudes=(40,), proportions=(0.2,), n_switch_states=(1, 2, 3))
    error = "LinAlgError: Matrix is not positive definite"
    named = rf"2 cells raised \(m40_p0.2_nss2_seed0: {error}; m40_p0.2_nss2_seed1: {error}\); the other cells ran"
    with pytest.raises(CellsFailed, match=named + " and are stored in .*a rerun runs only the cells missing") as caught:
        run_sweep(TINY, **grid, seeds=(0, 1), results_dir=tmp_path / "s", progress=True)
    assert f"m40_p0.2_nss2_seed1 raised {error}" in capsys.readouterr().err  # as it happened
    assert list(caught.value.failures) == [(40.0, 0.2, 2, 0), (40.0, 0.2, 2, 1)]
    assert "in failing" in caught.value.failures[(40.0, 0.2, 2, 0)][1]  # the whole traceback
    assert len(caught.value.results) == 4  # the cells that ran, returned
    assert sorted(p.name for p in (tmp_path / "s" / "cells").iterdir()) == [
        f"m40_p0.2_nss{nss}_seed{seed}" for nss in (1, 3) for seed in (0, 1)]
    with pytest.raises(CellsFailed, match=r"1 cell raised \(m40_p0.2_nss2_seed2: .*\); the other cells ran$"):
        run_sweep(TINY, **grid, seeds=(2,))  # storing nothing
    # Ctrl-C in a cell is no cell's error: it stops the sweep, and says which cells had raised before
    with pytest.raises(KeyboardInterrupt):
        run_sweep(TINY, magnitudes=(40, 50), proportions=(0.2,), n_switch_states=(2,), seeds=(3,))
    assert f"before the sweep stopped, 1 cell had raised: m40_p0.2_nss2_seed3: {error}" in capsys.readouterr().err
    # the command, resuming the stored sweep seed by seed: each seed runs, the traceback is printed once for
    # the cells that share it, and it fails; once the cause is gone the rerun runs the missing cells alone
    assert main(["sweep", "--out", str(tmp_path / "s"), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert "m40_p0.2_nss2_seed0, m40_p0.2_nss2_seed1:\nTraceback" in err and err.count("Traceback") == 1
    assert "error: 2 cells raised" in err
    monkeypatch.setattr(sweep_module, "compare", original)
    assert main(["sweep", "--out", str(tmp_path / "s"), "--quiet"]) == 0
    assert "6 cells, each a paired TP-vs-GP run" in capsys.readouterr().out


def test_a_sweep_where_every_cell_raises_names_a_few_and_counts_the_rest():
    from sarsp_edu.experiments.sweep.failures import CellsFailed, tracebacks

    failures = {(40.0, 0.2, nss, seed): ("MemoryError: no", "Traceback: the same") for nss in (2, 4, 6, 8, 10)
                for seed in (0, 1)}
    message = str(CellsFailed(failures, "out"))
    assert message.startswith("10 cells raised (m40_p0.2_nss2_seed0: MemoryError: no; m40_p0.2_nss2_seed1: ")
    assert message.count("MemoryError") == 5 and "; and 5 more); the other cells ran and are stored in out" in message
    assert "m40_p0.2_nss4_seed0; " not in message  # named in the order of the cells: nss 2 before nss 10
    assert tracebacks(failures).count("Traceback: the same") == 1
    ablation = {("default", 40.0, 0.2, 2, 0): ("E", "t")}
    assert str(CellsFailed(ablation)) == "1 cell raised (default/m40_p0.2_nss2_seed0: E); the other cells ran"


def test_the_three_model_tables_average_seeds_then_configurations_and_test_the_third_model(tmp_path, capsys):
    from sarsp_edu.cli import main
    from sarsp_edu.experiments.metrics import prefers
    from sarsp_edu.experiments.sweep.model_tables import model_sweep_tables
    from sarsp_edu.experiments.sweep.models import load_model_sweep, run_model_sweep

    run_sweep(TINY, magnitudes=(40,), proportions=(0.2,), n_switch_states=(1, 2), seeds=(0, 1),
              results_dir=tmp_path / "paired")
    run_model_sweep(tmp_path / "paired", tmp_path / "tl", n_jobs=1,
                    cells=[(40.0, 0.2, 1, 0), (40.0, 0.2, 1, 1), (40.0, 0.2, 2, 0)])
    paired, runs = load_model_sweep(tmp_path / "tl")
    tables = model_sweep_tables(paired, runs)
    config_1 = np.mean([runs[(40.0, 0.2, 1, seed)].summary["total_cost"] for seed in (0, 1)])
    config_2 = runs[(40.0, 0.2, 2, 0)].summary["total_cost"]  # the seeds the third model has run, only
    assert tables["mean"].loc["total_cost", "t-likelihood GP"] == pytest.approx((config_1 + config_2) / 2)
    tp_1 = np.mean([paired.comparisons[(40.0, 0.2, 1, seed)].tp.summary["total_cost"] for seed in (0, 1)])
    tp_2 = paired.comparisons[(40.0, 0.2, 2, 0)].tp.summary["total_cost"]
    assert tables["mean"].loc["total_cost", "TP"] == pytest.approx((tp_1 + tp_2) / 2)
    assert tables["mean"]["configurations"].iloc[0] == 2
    configurations = tables["configurations"]  # each configuration over the seeds the third model has run
    assert configurations["seeds"].tolist() == ["0, 1", "0"]
    assert configurations.loc[(40.0, 0.2, 1), "total_cost: t-likelihood GP"] == pytest.approx(config_1)
    assert configurations.loc[(40.0, 0.2, 2), "total_cost: TP"] == pytest.approx(tp_2)
    assert tables["definition4"].sum(axis=1).tolist() == [2, 2, 2]
    one = runs[(40.0, 0.2, 2, 0)].summary
    two = paired.comparisons[(40.0, 0.2, 2, 0)].gp.summary
    expected = "first preferred" if prefers(one, two) else "second preferred" if prefers(two, one) else "neither"
    assert tables["definition4"].loc["t-likelihood GP vs GP", expected] >= 1
    assert main(["tables", str(tmp_path / "tl")]) == 0
    out = capsys.readouterr().out
    assert "partial: 3 of the paired sweep's 4 cells" in out and "Table 2 with a third model" in out
    with pytest.raises(SystemExit):
        main(["tables", str(tmp_path / "tl"), "--all"])
    assert "--all: not for a model sweep's folder" in capsys.readouterr().err
    figure, markdown = tmp_path / "curves.png", tmp_path / "three.md"
    assert main(["tables", str(tmp_path / "tl"), "--figure", str(figure), "--markdown", str(markdown)]) == 0
    assert figure.read_bytes()[:4] == b"\x89PNG" and "| t-likelihood GP vs TP |" in markdown.read_text()
    assert "\n| 40 | 0.2 | 1 | 0, 1 | " in markdown.read_text()  # each configuration, m and p as written
    with pytest.raises(SystemExit):  # a paired sweep has no third model to draw
        main(["tables", str(tmp_path / "paired"), "--figure", str(figure)])
    assert "is neither" in capsys.readouterr().err
    stored = tmp_path / "tl" / "cells" / "m40_p0.2_nss2_seed0" / "t-likelihood" / "result.json"
    payload = json.loads(stored.read_text())
    payload["code"] = {**payload["code"], "source_sha256": "another version of the package"}
    stored.write_text(json.dumps(payload))
    assert main(["tables", str(tmp_path / "tl")]) == 0
    assert "computed by 2 versions of the code" in capsys.readouterr().out


def test_an_error_of_the_machine_stops_a_model_sweep_at_once(tmp_path, monkeypatch):
    import sarsp_edu.experiments.experiment as experiment
    from sarsp_edu.experiments.sweep.models import run_model_sweep

    run_sweep(TINY, magnitudes=(40,), proportions=(0.2,), n_switch_states=(1, 2), seeds=(0,),
              results_dir=tmp_path / "paired")
    runs = []

    def full_disk(config, *args, **kwargs):
        runs.append(config)
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(experiment, "run_experiment", full_disk)
    with pytest.raises(OSError, match="No space left"):
        run_model_sweep(tmp_path / "paired", tmp_path / "tl", n_jobs=1)
    assert len(runs) == 1  # the second cell was never started
