from __future__ import annotations

import json

import pytest

from sarsp_edu.experiments.ablation import ABLATION_SETTINGS, AblationResults, run_ablation, setting_config

from .worlds import FIVE_BY_FIVE_MORE_DATA

TINY = dict(FIVE_BY_FIVE_MORE_DATA)
SETTINGS = {"per action": dict(TINY), "per step": dict(TINY, prior_draw="per_step")}


def test_ablation_runs_each_setting_and_resumes(tmp_path):
    results = run_ablation(SETTINGS, cells=[(40, 0.2, 1)], seeds=(0, 1), episodes=2, results_dir=tmp_path,
                           command="sarsp-edu ablation ...")
    table = results.table()
    assert list(table.index) == [("per action", "TP"), ("per action", "GP"), ("per step", "TP"), ("per step", "GP")]
    assert (table["runs"] == 2).all()
    for column in ("task_success_rate", "mean_steps", "total_cost", "cost_rate", "backup_share"):
        assert column in table and f"{column} 95% CI" in table
    runs = results.runs()
    assert (runs["trapped_failures"] <= runs["failures"]).all()
    payload = json.loads((tmp_path / "ablation.json").read_text())
    assert payload["commands"] == ["sarsp-edu ablation ..."] and payload["seeds"] == [0, 1]
    loaded = AblationResults.load(tmp_path)
    assert loaded.table().equals(table)
    again = run_ablation(SETTINGS, cells=[(40, 0.2, 1)], seeds=(0, 1), episodes=2, results_dir=tmp_path)
    assert again.runs().equals(runs)  # everything was stored: nothing ran again, the same numbers


def test_settings_are_valid_configs():
    for name, setting in ABLATION_SETTINGS.items():
        config = setting_config(setting, episodes=3)
        assert config.episodes == 3, name
    assert setting_config(ABLATION_SETTINGS["reference preset"]).preset == "reference"
    fewer = setting_config(ABLATION_SETTINGS["reference preset, reward fit on 1,000 rows"])
    reference = setting_config(ABLATION_SETTINGS["reference preset"])
    assert fewer.reward_fit_points == 1000 and fewer.replace(reward_fit_points=None) == reference
    assert setting_config(
        ABLATION_SETTINGS["default (per action, k=100, whole cost fit, 1,000-row reward fit)"]).preset == "default"


def test_bad_settings_are_named():
    with pytest.raises(ValueError, match="names preset='fast'"):
        run_ablation({"x": dict(preset="fast")})
    with pytest.raises(ValueError, match="k_prior"):
        run_ablation({"x": dict(k_prior=0)})
    with pytest.raises(ValueError, match="at least one setting"):
        run_ablation({})


def test_two_settings_whose_names_give_one_folder_are_refused(tmp_path):
    with pytest.raises(ValueError, match="settings 'per step' and 'Per-step' would share the folder 'per-step'"):
        run_ablation({"per step": SETTINGS["per step"], "Per-step": SETTINGS["per action"]}, results_dir=tmp_path)
    assert not (tmp_path / "ablation.json").exists()  # refused before anything was written
    run_ablation({"per step": SETTINGS["per step"]}, cells=[(40, 0.2, 1)], seeds=(0,), episodes=1,
                 results_dir=tmp_path)
    with pytest.raises(ValueError, match="settings 'per step' and 'PER STEP' would share the folder"):  # a later call
        run_ablation({"PER STEP": SETTINGS["per action"]}, cells=[(40, 0.2, 1)], seeds=(0,), episodes=1,
                     results_dir=tmp_path)


def test_a_later_call_adds_settings_and_refuses_another_design(tmp_path):
    first = {"per action": SETTINGS["per action"]}
    run_ablation(first, cells=[(40, 0.2, 1)], seeds=(0,), episodes=1, results_dir=tmp_path, command="one")
    second = {"per step": SETTINGS["per step"]}
    run_ablation(second, cells=[(40, 0.2, 1)], seeds=(0,), episodes=1, results_dir=tmp_path, command="two")
    payload = json.loads((tmp_path / "ablation.json").read_text())
    assert sorted(payload["settings"]) == ["per action", "per step"] and payload["commands"] == ["one", "two"]
    assert sorted(AblationResults.load(tmp_path).sweeps) == ["per action", "per step"]
    with pytest.raises(ValueError, match="other episodes"):
        run_ablation(second, cells=[(40, 0.2, 1)], seeds=(0,), episodes=2, results_dir=tmp_path)
    with pytest.raises(ValueError, match="other changes"):
        run_ablation({"per step": dict(TINY, k_prior=5)}, cells=[(40, 0.2, 1)], seeds=(0,), episodes=1,
                     results_dir=tmp_path)


def test_500_random_rows_flatten_the_cost_model_because_of_the_outliers():
    """REPRODUCTION.md's 'Why 500-row fits flatten the cost model', recomputed: long with outliers seen once, short
    otherwise."""
    import pytest

    from sarsp_edu.experiments.ablation import cost_fit_length_scales

    table = cost_fit_length_scales()
    scale = table["length scale"]
    assert list(table.index) == ["500 random rows", "500 random rows, no outlier", "one row per distinct input",
                                 "all 4709 rows"]
    assert table.loc["500 random rows, no outlier", "outlier rows"] == 0
    assert table.loc["one row per distinct input", "rows"] == table.loc["all 4709 rows", "distinct inputs"]
    assert scale["500 random rows"] > 10 and scale["one row per distinct input"] > 10  # nearly constant
    assert scale["500 random rows, no outlier"] < 2 and scale["all 4709 rows"] < 2  # a grid step or less
    assert table.loc["500 random rows", "correlation, 1 step"] > 0.99
    with pytest.raises(ValueError, match="rows must be a whole number in \\[1, 3767\\].*got rows=0"):
        cost_fit_length_scales(rows=0)


def test_a_cell_that_raises_is_named_with_its_setting_and_the_other_settings_still_run(tmp_path, monkeypatch, capsys):
    from sarsp_edu.cli import main
    from sarsp_edu.experiments.sweep import run as sweep_module  # where the cells are run
    from sarsp_edu.experiments.sweep.failures import CellsFailed

    original = sweep_module.compare

    def failing(config, *args, **kwargs):  # the per-action setting's cell raises
        if config.prior_draw == "per_action":
            raise RuntimeError("the posterior mode was not found")
        return original(config, *args, **kwargs)

    monkeypatch.setattr(sweep_module, "compare", failing)
    named = r"1 cell raised \(per-action/m40_p0.2_nss1_seed0: RuntimeError: the posterior mode was not found\)"
    with pytest.raises(CellsFailed, match=named + "; the other cells ran and are stored") as caught:
        run_ablation(SETTINGS, cells=[(40, 0.2, 1)], seeds=(0,), episodes=1, results_dir=tmp_path)
    assert list(caught.value.failures) == [("per-action", 40.0, 0.2, 1, 0)]
    assert len(caught.value.results.sweeps["per action"]) == 0 and len(caught.value.results.sweeps["per step"]) == 1
    assert (tmp_path / "per-step" / "cells" / "m40_p0.2_nss1_seed0" / "cell.json").exists()  # the later setting ran
    # the command prints each traceback, named with its setting, and fails
    import sarsp_edu.experiments.ablation as ablation_module

    def raising(*args, **kwargs):
        raise caught.value

    monkeypatch.setattr(ablation_module, "run_ablation", raising)
    assert main(["ablation", "--out", str(tmp_path / "another"), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert "per-action/m40_p0.2_nss1_seed0:\nTraceback" in err and "in failing" in err and "error: 1 cell raised" in err
