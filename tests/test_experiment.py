from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

from sarsp_edu import ExperimentConfig, ExperimentResult, compare, prefers, run_experiment
from sarsp_edu.experiments.experiment import Experiment
from sarsp_edu.experiments.metrics import RECORD_COLUMNS, SUMMARY_METRICS, running_metrics
from sarsp_edu.experiments.results import Comparison

from .worlds import FIVE_BY_FIVE_MORE_DATA

TINY = ExperimentConfig(**dict(FIVE_BY_FIVE_MORE_DATA, k_prior=30, optimizer_steps=5), n_switch_states=1, episodes=4,
                        seed=3)


@pytest.fixture(scope="module")
def tiny_comparison():
    return compare(TINY)


# --------------------------------------------------------------------------
# metrics on hand-computed episode lists
# --------------------------------------------------------------------------
def test_running_metrics_by_hand():
    m = running_metrics(
        episode_reward=[-10.0, -20.0, -30.0, -40.0],
        episode_cost=[0, 2, 0, 1],
        episode_steps=[5, 10, 100, 8],
        task_completed=[True, True, False, True],
    )
    assert m["mean_reward"].tolist() == [-10.0, -15.0, -20.0, -25.0]
    assert m["mean_cost"].tolist() == [0.0, 1.0, 2 / 3, 0.75]
    assert m["total_cost"].tolist() == [0, 2, 2, 3]
    assert m["task_success_rate"].tolist() == [100.0, 100.0, pytest.approx(200 / 3), 75.0]
    assert m["mean_steps"].tolist() == [5.0, 7.5, pytest.approx(115 / 3), 30.75]
    # clean successful steps: only episode 1 (5 steps); cost 0 at first
    assert m["cost_rate"].tolist() == [0.0, 2 / 5, 2 / 5, 3 / 5]


def test_cost_rate_zero_cases():
    no_cost = running_metrics([-1, -1], [0, 0], [3, 4], [True, True])
    assert no_cost["cost_rate"].tolist() == [0.0, 0.0]  # total cost is 0
    no_clean_success = running_metrics([-1, -1], [1, 0], [3, 4], [True, False])
    assert no_clean_success["cost_rate"].tolist() == [0.0, 0.0]  # no clean successful steps


# --------------------------------------------------------------------------
# Definition 4
# --------------------------------------------------------------------------
def S(reward, cost_rate, tsr):
    return {"mean_reward": reward, "cost_rate": cost_rate, "task_success_rate": tsr}


@pytest.mark.parametrize(
    "a1, a2, a, expected",
    [
        (S(-10, 0.01, 50), S(-20, 0.02, 90), 100, True),   # branch 1: reward >= and p_c <
        (S(-30, 0.01, 95), S(-20, 0.02, 90), 100, True),   # branch 2: TSR >= and p_c <
        (S(-30, 0.01, 85), S(-20, 0.02, 90), 80, True),    # branch 3: TSR >= a and p_c <
        (S(-30, 0.01, 85), S(-20, 0.02, 90), 100, False),  # none of the three
        (S(-10, 0.02, 99), S(-20, 0.02, 90), 100, False),  # p_c not strictly lower
        (S(-10, 0.03, 99), S(-20, 0.02, 90), 1, False),    # p_c higher: nothing helps
        (S(-20, 0.01, 90), S(-20, 0.02, 90), 100, True),   # equalities count as "at least as well"
        (S(-20, 0.0, 90), S(-20, 0.0, 90), 100, False),    # both zero: neither preferred
    ],
)
def test_prefers_each_branch(a1, a2, a, expected):
    assert prefers(a1, a2, a=a) is expected


@pytest.mark.parametrize("a", [0.5, 101, "high", np.nan])
def test_prefers_threshold_is_checked(a):
    with pytest.raises(ValueError, match=r"a must lie in \[1, 100\]"):
        prefers(S(0, 0, 0), S(0, 0, 0), a=a)


def test_an_undefined_cost_rate_is_not_a_perfect_one():
    # violations but no clean success: eq. 12 divides by zero
    from sarsp_edu.experiments.metrics import cost_rate_undefined, displayed_summary

    trapped = {**S(-200, 0.0, 40), "total_cost": 13.0}
    safe = {**S(-100, 0.0, 40), "total_cost": 0.0}
    fine = {**S(-100, 0.02, 90), "total_cost": 5.0}
    assert cost_rate_undefined(trapped) and not cost_rate_undefined(safe) and not cost_rate_undefined(fine)
    assert prefers(fine, trapped) is None and prefers(trapped, fine) is None  # Definition 4 cannot decide
    assert prefers(safe, fine) is True and prefers(fine, safe) is False  # 0 violations: a true 0 wins
    assert np.isnan(displayed_summary(trapped)["cost_rate"]) and trapped["cost_rate"] == 0.0  # stored value kept


def test_comparison_table_shows_an_undefined_cost_rate_as_such(tiny_comparison):
    import copy

    comparison = copy.deepcopy(tiny_comparison)
    records = comparison.gp.records
    records.loc[records.index[-1], ["total_cost", "cost_rate"]] = [13.0, 0.0]
    row = comparison.table().loc["cost_rate"]
    assert np.isnan(row["GP"]) and np.isnan(row["TP vs GP (%)"]) and row["better"] == "n/a"
    assert comparison.verdict == {"tp_preferred": None, "gp_preferred": None}


def test_prefers_needs_the_metrics():
    with pytest.raises(ValueError, match="summary_2 lacks 'cost_rate'"):
        prefers(S(0, 0, 0), {"mean_reward": 0, "task_success_rate": 0})


# --------------------------------------------------------------------------
# tiny real runs
# --------------------------------------------------------------------------
@pytest.mark.parametrize("model", ["tp", "gp"])
def test_tiny_run_end_to_end(model):
    result = run_experiment(TINY.replace(model=model))
    records = result.records
    assert list(records.columns) == list(RECORD_COLUMNS)
    assert records["episode"].tolist() == [1, 2, 3, 4]
    assert set(result.summary) == set(SUMMARY_METRICS)
    assert (records["episode_steps"] >= 1).all() and (records["episode_steps"] <= 25).all()
    assert result.summary["total_cost"] == records["episode_cost"].sum()
    for name in SUMMARY_METRICS:
        assert result.summary[name] == pytest.approx(records[name].iloc[-1])
    assert result.timings["steps"] == records["episode_steps"].sum()
    assert 0 <= result.summary["task_success_rate"] <= 100
    assert records["backup_rate"].between(0, 1).all()


def test_same_seed_identical_records():
    a = run_experiment(TINY.replace(model="tp"))
    b = run_experiment(TINY.replace(model="tp"))
    pd.testing.assert_frame_equal(a.records, b.records)
    c = run_experiment(TINY.replace(model="tp", seed=4))
    assert a.records["start"].tolist() != c.records["start"].tolist()


def test_compare_pairs_the_runs(tiny_comparison):
    tp, gp = tiny_comparison.tp.records, tiny_comparison.gp.records
    assert tp["start"].tolist() == gp["start"].tolist()
    assert tp["goal"].tolist() == gp["goal"].tolist()
    assert tiny_comparison.tp.config.model == "tp" and tiny_comparison.gp.config.model == "gp"
    # and a stand-alone run with the same seed is the same run
    alone = run_experiment(TINY.replace(model="gp"))
    pd.testing.assert_frame_equal(alone.records, gp)


def test_paired_runs_see_the_same_world():
    experiments = [Experiment(TINY.replace(model=m)) for m in ("tp", "gp")]
    np.testing.assert_array_equal(experiments[0].env.unsafe_states, experiments[1].env.unsafe_states)
    np.testing.assert_array_equal(experiments[0].data.cost.X, experiments[1].data.cost.X)
    np.testing.assert_array_equal(experiments[0].data.outlier_indices, experiments[1].data.outlier_indices)
    assert len(experiments[0].env.moved_indices) == TINY.n_switch_states


def test_experiments_on_one_world_differ_only_in_what_their_sides_change():
    from sarsp_edu.experiments.experiment import experiments_on_one_world

    sides = {"per step": {"model": "gp", "prior_draw": "per_step"}, "per action": {"model": "gp"}}
    experiments = experiments_on_one_world(TINY, sides)
    step, action = experiments["per step"], experiments["per action"]
    assert step.config.prior_draw == "per_step" and action.config.prior_draw == "per_action"
    assert step.config.replace(prior_draw="per_action") == action.config
    np.testing.assert_array_equal(step.env.unsafe_states, action.env.unsafe_states)
    np.testing.assert_array_equal(step.data.cost.y, action.data.cost.y)
    np.testing.assert_array_equal(step._episode_seeds, action._episode_seeds)
    # the side that changes nothing of the agent is the plain run of its config
    while not action.finished:
        action.run_episode()
    pd.testing.assert_frame_equal(action.records(), run_experiment(TINY.replace(model="gp")).records)


@pytest.mark.parametrize("changes, named", [({"n_switch_states": 2}, "n_switch_states"), ({"seed": 4}, "seed")])
def test_sides_cannot_change_the_world(changes, named):
    from sarsp_edu.experiments.experiment import experiments_on_one_world

    with pytest.raises(ValueError, match=f"shape the world.*{named}|{named}.*shape the world"):
        experiments_on_one_world(TINY, {"a": {"model": "tp"}, "b": changes})
    with pytest.raises(ValueError, match="sides must be a non-empty dict"):
        experiments_on_one_world(TINY, {})


def test_a_preparation_reads_only_the_fields_it_names():
    from dataclasses import fields

    from sarsp_edu.world.preparation import PREPARATION_FIELDS, prepare

    names = {f.name for f in fields(ExperimentConfig)}
    assert set(PREPARATION_FIELDS) <= names
    base = prepare(TINY)
    changed = {"model": "gp", "nu": 5.0, "k_prior": 20, "prior_draw": "per_step", "optimizer_steps": 3,
               "variance_threshold": 0.5, "n_matching": 4, "retrain": "always"}
    assert not set(changed) & set(PREPARATION_FIELDS)
    other = prepare(TINY.replace(**changed))
    np.testing.assert_array_equal(base.env.unsafe_states, other.env.unsafe_states)
    np.testing.assert_array_equal(base.data.cost.y, other.data.cost.y)
    np.testing.assert_array_equal(base.episode_seeds, other.episode_seeds)
    assert base.agent_seed == other.agent_seed
    moved = prepare(TINY.replace(n_switch_states=2))
    assert len(moved.env.moved_indices) == 2 != len(base.env.moved_indices)


def test_comparison_table_and_verdict(tiny_comparison):
    table = tiny_comparison.table()
    assert list(table.index) == list(SUMMARY_METRICS)
    tp, gp = tiny_comparison.tp.summary, tiny_comparison.gp.summary
    for name in SUMMARY_METRICS:
        expected = (tp[name] - gp[name]) / abs(gp[name]) * 100 if gp[name] else (0.0 if tp[name] == 0 else math.nan)
        got = table.loc[name, "TP vs GP (%)"]
        assert (math.isnan(got) and math.isnan(expected)) or got == pytest.approx(expected)
    assert tiny_comparison.verdict == {
        "tp_preferred": prefers(tp, gp, 100.0), "gp_preferred": prefers(gp, tp, 100.0)
    }
    assert not (tiny_comparison.verdict["tp_preferred"] and tiny_comparison.verdict["gp_preferred"])


def test_step_by_step_equals_a_whole_run():
    experiment = Experiment(TINY.replace(model="tp"))
    steps = 0
    while not experiment.finished:
        record = experiment.step()
        steps += 1
        assert record.next_position == experiment.trajectory[-1] or record.done
    pd.testing.assert_frame_equal(experiment.records(), run_experiment(TINY.replace(model="tp")).records)
    with pytest.raises(RuntimeError, match="finished"):
        experiment.step()


# --------------------------------------------------------------------------
# persistence
# --------------------------------------------------------------------------
def test_save_and_load_round_trip(tmp_path, tiny_comparison):
    result = tiny_comparison.tp
    result.save(tmp_path / "run")
    assert sorted(p.name for p in (tmp_path / "run").iterdir()) == ["records.csv", "result.json"]
    loaded = ExperimentResult.load(tmp_path / "run")
    pd.testing.assert_frame_equal(loaded.records, result.records, check_dtype=False)
    assert loaded.config == result.config
    assert loaded.summary == pytest.approx(result.summary)
    payload = json.loads((tmp_path / "run" / "result.json").read_text())
    assert payload["summary"] == pytest.approx(result.summary)

    tiny_comparison.save(tmp_path / "pair")
    again = Comparison.load(tmp_path / "pair")
    assert again.verdict == tiny_comparison.verdict


def test_load_of_an_incomplete_folder(tmp_path):
    (tmp_path / "records.csv").write_text("episode\n1\n")
    with pytest.raises(FileNotFoundError, match="no complete result"):
        ExperimentResult.load(tmp_path)


def test_failed_write_leaves_nothing_behind(tmp_path, monkeypatch):
    from sarsp_edu._internal import io as _io

    def boom(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(_io.os, "replace", boom)
    with pytest.raises(OSError, match="disk full"):
        _io.atomic_write_text(tmp_path / "x.json", "{}")
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------
# bad configs are rejected before any work starts
# --------------------------------------------------------------------------
@pytest.mark.parametrize(
    "changes, match",
    [
        (dict(nu=2.0), r"nu must be a finite number > 2.*got nu=2.0"),
        (dict(nu=1.0), "nu must be"),
        (dict(outlier_proportion=1.5), r"outlier_proportion must lie in \[0, 1\], got outlier_proportion=1.5"),
        (dict(outlier_proportion=-0.1), "outlier_proportion"),
        (dict(outlier_magnitude=0), "outlier_magnitude must be a positive finite number"),
        (dict(n_switch_states=16), "n_switch_states must be an integer from 0 to n_unsafe=15, got n_switch_states=16"),
        (dict(episodes=0), r"episodes must be an integer from 1 to 100000 \(.*\), got episodes=0"),
        (dict(offline_episodes=0), "offline_episodes"),
        (dict(grid_size=1), "grid_size"),
        (dict(n_unsafe=20), "n_unsafe must be an integer from 1 to 19, the most unsafe states"),
        (dict(grid_size=5, n_unsafe=13), r"from 1 to 4.*5x5 placement area, got n_unsafe=13"),
        (dict(grid_size=2, n_unsafe=1), "grid_size must be at least 3 with placement='full'"),
        (dict(model="rf"), "model must be one of 'tp', 'gp'"),
        (dict(d=-1), "d must be"),
        (dict(variance_threshold=0), "variance_threshold"),
        (dict(k_prior=0), "k_prior"),
        (dict(seed=-1), "seed"),
        (dict(predictive="mc"), "predictive"),
        (dict(noise_convention="gpy"), "noise_convention"),
        (dict(optimizer="sgd"), "optimizer"),
        (dict(reward_fit_points=1), "reward_fit_points"),
        (dict(cost_fit_points=0), "cost_fit_points"),
        (dict(prior_draw="per_episode"), "prior_draw"),
        (dict(retrain=True), "retrain"),
        (dict(cost_outliers="yes"), "cost_outliers must be True or False"),
        # text is not a number, even when float() would read it
        (dict(outlier_proportion="0.2"), r"outlier_proportion must lie in \[0, 1\], got outlier_proportion='0.2'"),
        (dict(outlier_magnitude="40"),
         "outlier_magnitude must be a positive finite number, got outlier_magnitude='40'"),
        (dict(nu="3"), "nu must be a finite number > 2"),
        (dict(d=True), "d must be a positive finite number, got d=True"),
    ],
)
def test_bad_config_values(changes, match):
    with pytest.raises(ValueError, match=match):
        ExperimentConfig(**changes)


def test_config_round_trip_and_unknown_fields():
    config = ExperimentConfig(nu=4.0, n_switch_states=6)
    assert ExperimentConfig.from_dict(config.to_dict()) == config
    with pytest.raises(ValueError, match=r"unknown ExperimentConfig fields \['nss'\]"):
        ExperimentConfig.from_dict({"nss": 2})


def test_compare_checks_a_before_running():
    with pytest.raises(ValueError, match="a must lie"):
        compare(TINY, a=0)


def test_defaults_are_the_papers():
    c = ExperimentConfig()
    assert (c.grid_size, c.n_unsafe, c.offline_episodes, c.cost_duplicates, c.reward_duplicates) == (10, 15, 100, 12, 1)
    assert (c.outlier_magnitude, c.outlier_proportion, c.n_switch_states, c.episodes) == (40.0, 0.2, 2, 250)
    assert (c.nu, c.d, c.variance_threshold, c.cost_outliers, c.reward_outliers) == (3.0, 1.0, 0.8, True, True)
    assert (c.optimizer, c.learning_rate, c.optimizer_steps, c.prior) == ("adam", 0.1, 50, "lognormal")


# --------------------------------------------------------------------------
# presets
# --------------------------------------------------------------------------
from sarsp_edu.config import PRESET_DOCS, PRESET_FIELDS, PRESETS, preset_of  # noqa: E402


@pytest.mark.parametrize("name", sorted(PRESETS))
def test_presets_set_exactly_the_fields_they_document(name):
    values = PRESETS[name]
    assert set(values) == set(PRESET_FIELDS)
    config = ExperimentConfig.from_preset(name, episodes=3, seed=5)
    assert {key: getattr(config, key) for key in PRESET_FIELDS} == values
    assert config.preset == name and config.episodes == 3 and config.seed == 5
    doc = PRESET_DOCS[name]
    assert f"k = {values['k_prior']}" in doc
    assert ("per action" in doc) == (values["prior_draw"] == "per_action")
    assert ("per step" in doc) == (values["prior_draw"] == "per_step")


def test_default_preset_is_the_dataclass_defaults():
    assert ExperimentConfig().preset == "default"
    assert ExperimentConfig.from_preset() == ExperimentConfig()


def test_reference_preset_is_the_reference_code():
    config = ExperimentConfig.from_preset("reference")
    assert ((config.prior_draw, config.k_prior, config.predictive, config.n_samples)
            == ("per_action", 400, "sample", 150))
    assert config.cost_fit_points is None and config.reward_fit_points is None
    assert (config.placement, config.max_steps, config.retrain) == ("reference", 101, "if_changed")


def test_a_changed_setting_is_custom_and_configuration_fields_are_not_settings():
    assert ExperimentConfig(outlier_magnitude=80, n_switch_states=10).preset == "default"
    assert ExperimentConfig(k_prior=400).preset == "custom"
    assert preset_of(ExperimentConfig.from_preset("paper_text").replace(prior_draw="per_action")) == "custom"


def test_unknown_preset_is_named():
    with pytest.raises(ValueError, match="preset must be one of"):
        ExperimentConfig.from_preset("fast")


def test_saved_result_says_its_preset(tmp_path):
    result = run_experiment(TINY.replace(episodes=1))
    result.save(tmp_path / "r")
    payload = json.loads((tmp_path / "r" / "result.json").read_text())
    assert payload["preset"] == "custom" and payload["config"]["prior_draw"] == "per_action"


def test_configs_stored_by_version_0_1_keep_their_settings():
    legacy = ExperimentConfig().to_dict()
    for key in ("cost_fit_points", "reward_fit_points", "prior_draw"):
        legacy.pop(key)
    legacy.update(fit_points=500, retrain=True)
    config = ExperimentConfig.from_dict(legacy)
    assert (config.cost_fit_points, config.reward_fit_points) == (500, 500)
    assert config.prior_draw == "per_step" and config.retrain == "always" and config.preset == "custom"
    legacy["retrain"] = False
    assert ExperimentConfig.from_dict(legacy).retrain == "never"


def test_trapped_share_by_hand_and_for_results_stored_before_it_existed():
    from sarsp_edu.experiments.metrics import trapped_share

    records = pd.DataFrame({"task_completed": [True, False, False, False], "final_cells": [7, 1, 2, 9]})
    assert trapped_share(records) == pytest.approx(2 / 3)  # of three failures, two ended on <= 2 cells
    assert np.isnan(trapped_share(records.assign(task_completed=True)))  # no failure
    assert np.isnan(trapped_share(records.drop(columns="final_cells")))  # stored by 0.1
    from sarsp_edu.experiments.metrics import trapped_episodes

    assert trapped_episodes(records).tolist() == [False, True, True, False]  # a success on 7 cells is no trap
    assert not trapped_episodes(records.drop(columns="final_cells")).any()


# -- both cores for one comparison -----------------------------------------------------------------
def test_a_comparison_in_two_processes_records_what_the_sequential_one_records_byte_for_byte(tmp_path):
    config = TINY.replace(episodes=3, n_switch_states=2)
    one, two = compare(config, n_jobs=1), compare(config, n_jobs=2)
    one.save(tmp_path / "one")
    two.save(tmp_path / "two")
    for side in ("tp", "gp"):
        assert (tmp_path / "one" / side / "records.csv").read_bytes() == \
            (tmp_path / "two" / side / "records.csv").read_bytes()
        assert getattr(one, side).config == getattr(two, side).config
    assert one.verdict == two.verdict


def test_a_comparison_says_which_process_counts_it_takes():
    with pytest.raises(ValueError, match=r"n_jobs must be 1 or 2 \(one process per model\), or None to choose, "
                                         r"got n_jobs=3"):
        compare(TINY, n_jobs=3)
    with pytest.raises(ValueError, match="got n_jobs=True"):
        compare(TINY, n_jobs=True)
