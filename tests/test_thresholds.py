"""The threshold study: the ablation's runs at each sigma*^2 and the third model's on the same folders."""

from __future__ import annotations

import json
import math

import matplotlib
import pytest

from sarsp_edu.experiments.ablation import AblationResults, run_ablation, setting_folder
from sarsp_edu.experiments.sweep.models import run_model_sweep
from sarsp_edu.experiments.thresholds import DEFAULT_SETTING, ThresholdStudy, threshold_settings

from .worlds import FIVE_BY_FIVE_MORE_DATA

matplotlib.use("Agg")

TINY = dict(FIVE_BY_FIVE_MORE_DATA)
HIGH = "default, variance threshold 10"
SETTINGS = {DEFAULT_SETTING: dict(TINY), HIGH: dict(TINY, variance_threshold=10.0)}


@pytest.fixture(scope="module")
def study_folders(tmp_path_factory):
    root = tmp_path_factory.mktemp("thresholds")
    run_ablation(SETTINGS, cells=[(40, 0.2, 1)], seeds=(0, 1), episodes=2, results_dir=root / "ablation")
    for name in SETTINGS:
        run_model_sweep(root / "ablation" / setting_folder(name), root / "third" / setting_folder(name), n_jobs=1)
    return root


def test_the_study_reads_the_ablation_and_the_third_model_on_the_same_runs(study_folders):
    study = ThresholdStudy.load(study_folders / "ablation", study_folders / "third")
    assert study.thresholds == [0.8, 10.0] and study.models == ["TP", "GP", "t-likelihood GP"]
    table = study.table()
    assert list(table.index) == [(t, m) for t in (0.8, 10.0) for m in ("TP", "GP", "t-likelihood GP")]
    assert (table["runs"] == 2).all()
    for measure in ("backup_share", "total_cost", "task_success_rate"):
        assert ((table[f"{measure} low"] <= table[measure] + 1e-12)
                & (table[measure] <= table[f"{measure} high"] + 1e-12)).all()
    # the TP and GP rows are the ablation's own runs, their thresholds the settings' configs'
    ablation = AblationResults.load(study_folders / "ablation").runs()
    for name, threshold in ((DEFAULT_SETTING, 0.8), (HIGH, 10.0)):
        mine = study.runs[(study.runs["threshold"] == threshold) & study.runs["model"].isin(["TP", "GP"])]
        theirs = ablation[ablation["setting"] == name]
        assert sorted(mine["total_cost"]) == sorted(theirs["total_cost"])
        assert sorted(mine["backup_share"]) == sorted(theirs["backup_share"])
    pairs = study.pairs()
    assert list(pairs.index.get_level_values("pair").unique()) == [
        "TP vs GP", "TP vs t-likelihood GP", "GP vs t-likelihood GP"]
    assert (pairs["runs"] == 2).all()


def test_without_the_third_model_the_study_holds_tp_and_gp(study_folders):
    study = ThresholdStudy.load(study_folders / "ablation")
    assert study.models == ["TP", "GP"] and len(study.runs) == 8
    left = study.lowest_threshold_off_backup(share=101.0)  # every share is below 101%: the smallest threshold
    assert left == {"TP": 0.8, "GP": 0.8}
    assert math.isnan(study.lowest_threshold_off_backup(share=0.0)["TP"])  # no share is below 0%


def test_a_third_model_run_on_another_setting_is_refused(study_folders, tmp_path):
    import shutil

    third = tmp_path / "third"
    shutil.copytree(study_folders / "third", third)
    meta = third / setting_folder(HIGH) / "model_sweep.json"
    payload = json.loads(meta.read_text())
    payload["paired"] = payload["paired"].replace(setting_folder(HIGH), setting_folder(DEFAULT_SETTING))
    meta.write_text(json.dumps(payload))
    with pytest.raises(ValueError, match="not on the ablation's setting"):
        ThresholdStudy.load(study_folders / "ablation", third)


def test_the_study_names_every_threshold_setting_of_the_ablation():
    from sarsp_edu.experiments.ablation import ABLATION_SETTINGS, VARIANCE_THRESHOLDS

    names = threshold_settings()
    assert names[0] == DEFAULT_SETTING and len(names) == len(VARIANCE_THRESHOLDS) + 1
    assert all(name in ABLATION_SETTINGS for name in names)


def test_the_command_prints_the_tables_and_draws_the_figure(study_folders, tmp_path, capsys):
    from sarsp_edu.cli import main

    figure, markdown = tmp_path / "study.png", tmp_path / "study.md"
    assert main(["threshold-study", "--ablation", str(study_folders / "ablation"), "--models",
                 str(study_folders / "third"), "--figure", str(figure), "--markdown", str(markdown)]) == 0
    out = capsys.readouterr().out
    assert "t-likelihood GP" in out and "TP vs GP" in out and "backup share falls below 50%" in out
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "| threshold |" in markdown.read_text()
    with pytest.raises(SystemExit):
        main(["threshold-study", "--ablation", str(study_folders / "ablation"), "--figure", str(tmp_path / "x.txt")])
    assert "--figure" in capsys.readouterr().err
    # 'tables' on the folder of the third model's sweeps finds their ablation and prints the same study
    assert main(["tables", str(study_folders / "third")]) == 0
    assert "the threshold study" in capsys.readouterr().out


def test_the_three_learning_curves_are_the_means_of_the_cells_run(study_folders):
    import matplotlib.pyplot as plt

    from sarsp_edu.experiments.sweep.model_tables import model_sweep_curves
    from sarsp_edu.experiments.sweep.models import load_model_sweep
    from sarsp_edu.teaching.plotting import plot_model_curves

    paired, runs = load_model_sweep(study_folders / "third" / setting_folder(DEFAULT_SETTING))
    curves = model_sweep_curves(paired, runs, "total_cost")
    assert list(curves.columns) == ["TP", "GP", "t-likelihood GP"] and list(curves.index) == [1, 2]
    third = sum(run.records["total_cost"].to_numpy() for run in runs.values()) / len(runs)
    assert curves["t-likelihood GP"].to_numpy() == pytest.approx(third)
    gp = sum(paired.comparisons[key].gp.records["total_cost"].to_numpy() for key in runs) / len(runs)
    assert curves["GP"].to_numpy() == pytest.approx(gp)
    with pytest.raises(ValueError, match="records column"):
        model_sweep_curves(paired, runs, "no such metric")
    with pytest.raises(ValueError, match="none of the paired sweep's cells"):
        model_sweep_curves(paired, {}, "total_cost")
    figure, ax = plt.subplots()
    plot_model_curves(ax, curves, metric="total_cost")
    assert [line.get_label() for line in ax.get_lines()] == ["TP", "GP", "t-likelihood GP"]
    plt.close(figure)


def test_the_complete_study_leaves_out_what_is_still_running(study_folders, tmp_path):
    import shutil

    shutil.copytree(study_folders, tmp_path / "copy")  # the third model's folders name the ablation's relatively
    third = tmp_path / "copy" / "third"
    run = next((third / setting_folder(HIGH) / "cells").glob("m*")) / "t-likelihood"
    shutil.rmtree(run)  # one run of the third model at sigma*^2 = 10 not stored yet
    study = ThresholdStudy.load(tmp_path / "copy" / "ablation", third)
    assert study.planned == 2
    assert study.missing[(10.0, "t-likelihood GP")] == 1 and study.missing[(0.1, "TP")] == 0
    assert (0.8, "TP") not in study.missing
    without = ThresholdStudy.load(tmp_path / "copy" / "ablation")  # no third model asked for: none missing
    assert all(model != "t-likelihood GP" for _, model in without.missing)
    complete = study.complete()
    assert set(zip(complete.runs["threshold"], complete.runs["model"])) == {
        (0.8, "TP"), (0.8, "GP"), (0.8, "t-likelihood GP"), (10.0, "TP"), (10.0, "GP")}
    assert (complete.table()["runs"] == 2).all()


def test_the_stored_study_holds_what_reproduction_md_reads_from_it():
    """REPRODUCTION.md, "The threshold the comparison hinges on", from the stored runs."""
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent / "results"
    study = ThresholdStudy.load(root / "ablation", root / "ablation-t-likelihood").complete()
    table, pairs = study.table(), study.pairs()
    assert set(study.thresholds) == {0.1, 0.3, 0.8, 2.0, 5.0, 10.0}
    tp = study.runs[study.runs["model"] == "TP"].sort_values(["threshold", "m", "p", "nss", "seed"])
    by_threshold = [part[["total_cost", "backup_share", "task_success_rate"]].to_numpy()
                    for _, part in tp.groupby("threshold")]
    assert all((runs == by_threshold[0]).all() for runs in by_threshold)  # the TP's runs: the same at every threshold
    gp = table.xs("GP", level="model")["backup_share"]
    assert (gp.loc[[0.1, 0.3, 0.8, 2.0]] == 100.0).all() and gp.loc[10.0] < 10.0
    tp_vs_gp = pairs.xs("TP vs GP", level="pair")["mean total cost difference"]
    assert (tp_vs_gp < 0).all() and tp_vs_gp.loc[10.0] > tp_vs_gp.loc[0.8]  # lower everywhere, by less at 10
