"""One clear line, never a traceback or a silent wrong run: prefit's settings, the cache's folder, a model sweep's
folder, a student's parts that return what no decision can use."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from sarsp_edu import ExperimentConfig, StudentTLikelihoodGP
from sarsp_edu.agent.parts import gp_posterior, tp_factor
from sarsp_edu.agent.sarsp import SARSPAgent
from sarsp_edu.models.processes.factory import make_model

from .test_cli import _usage_error as usage_error
from .test_sarsp import OBS, tiny_agent, tiny_data

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("flags, message", [
    (["--nss", "99"], "n_switch_states must be an integer from 0 to n_unsafe=15, got n_switch_states=99"),
    (["--episodes", "0"], "episodes must be an integer from 1 to 100000"),
    (["--p", "2"], "outlier_proportion must lie in [0, 1], got outlier_proportion=2.0"),
    (["--nu", "1"], "nu must be a finite number > 2"),
    (["--nu", "nan"], "got nu=nan"),
    (["--seed", "-5"], "seed must be an integer >= 0, got seed=-5"),
    (["--models", "tp", "gpy"], "argument --models: invalid choice: 'gpy' (choose from 'tp', 'gp', 't-likelihood')"),
])
def test_prefit_checks_its_settings_as_run_does(capsys, flags, message):
    assert message in usage_error(["prefit", *flags], capsys)


def test_a_cache_folder_of_an_unknown_users_home_is_one_line(capsys, monkeypatch):
    monkeypatch.setenv("SARSP_EDU_CACHE", "~nouser-sarsp-edu/x")
    assert usage_error(["cache"], capsys).endswith(
        "SARSP_EDU_CACHE='~nouser-sarsp-edu/x' names the home folder of a user this machine does not know; give a "
        "folder path, or SARSP_EDU_CACHE=off to turn the cache off")


def test_a_model_sweep_into_a_paired_sweeps_folder_is_one_line(capsys, tmp_path):
    paired = str(ROOT / "results" / "sweep-reduced")
    assert usage_error(["model-sweep", "--paired", paired, "--out", paired], capsys).endswith(
        "holds a paired sweep; the model's runs go into a folder of their own")


def test_a_students_posterior_that_returns_nan_or_a_negative_variance_stops_the_run_naming_it():
    def nan_posterior(K, K_star, k_star_star, y, noise_variance):
        mean, var = gp_posterior(K, K_star, k_star_star, y, noise_variance)
        return mean, np.full_like(var, np.nan)

    def negative_posterior(K, K_star, k_star_star, y, noise_variance):
        mean, var = gp_posterior(K, K_star, k_star_star, y, noise_variance)
        return mean, var - 5.0

    with pytest.raises(ValueError, match=r"the posterior part returned a variance with entries that are not finite"):
        tiny_agent(5.0, parts={"posterior": nan_posterior}).act(OBS)
    with pytest.raises(ValueError, match=r"the posterior part returned a negative variance \(-"):
        tiny_agent(5.0, parts={"posterior": negative_posterior}).act(OBS)
    # a variance that rounds a little below 0 is what k** - k*^T K^-1 k* gives near the data: kept, as 0
    rounded = tiny_agent(5.0, parts={"posterior": lambda *a: (gp_posterior(*a)[0], gp_posterior(*a)[1] * 0 - 1e-12)})
    rounded.act(OBS)


def test_a_negative_tp_factor_stops_the_run_naming_it():
    from sarsp_edu import StudentTProcess

    with pytest.raises(ValueError, match=r"the tp_factor part returned -5; the TP's factor .* is positive"):
        tiny_agent(5.0, model_cls=StudentTProcess, parts={"tp_factor": lambda *args: -5.0}).act(OBS)
    tiny_agent(5.0, model_cls=StudentTProcess, parts={"tp_factor": tp_factor}).act(OBS)  # the package's own: fine


def test_the_t_likelihood_model_refuses_parts_it_cannot_use_naming_both():
    config = ExperimentConfig(model="t-likelihood")
    with pytest.raises(ValueError, match=r"the cost and the reward model are GP with Student-t noise "
                                         r"\(model='t-likelihood' and reward_model='t-likelihood'\), which cannot use "
                                         r"the replaced parts \['kernel'\]"):
        SARSPAgent(make_model(config), make_model(config, "reward"), tiny_data(5.0),
                   parts={"kernel": lambda X, Y, amplitude, length_scale: np.zeros((len(X), len(Y)))})
    mixed = ExperimentConfig(model="tp", reward_model="t-likelihood")
    with pytest.raises(ValueError, match=r"the reward model is a GP with Student-t noise "
                                         r"\(reward_model='t-likelihood'\), .*\['posterior'\]"):
        SARSPAgent(make_model(mixed), make_model(mixed, "reward"), tiny_data(5.0),
                   parts={"posterior": lambda *args: gp_posterior(*args)})
    agent = SARSPAgent(make_model(config), make_model(config, "reward"), tiny_data(5.0),
                       parts={"corrective": lambda *args: False})  # a decision part it can use
    assert isinstance(agent.cost_model, StudentTLikelihoodGP)


def test_compare_models_refuses_a_sweeps_folder(capsys):
    out = str(ROOT / "results" / "sweep-reduced")
    assert usage_error(["compare", "--models", "gp", "tp", "--out", out, "--episodes", "1"], capsys).endswith(
        f"--out {out} holds a sweep's results; 'compare' writes into a new folder, an empty one or one holding a "
        "comparison's results")


@pytest.mark.parametrize("argv", [["compare", "--mod", "tp", "gp"], ["compare", "--models", "tp", "gp", "--model",
                                                                      "t-likelihood"], ["run", "--episode", "3"]])
def test_no_flag_is_read_as_an_abbreviation(capsys, argv):
    assert "unrecognized arguments" in usage_error(argv, capsys)


def test_a_runs_header_names_its_models(capsys):
    from sarsp_edu.cli.main import main

    tiny = ["--episodes", "1", "--grid-size", "4", "--n-unsafe", "1", "--nss", "1", "--offline-episodes", "2",
            "--optimizer-steps", "2", "--reward-fit-points", "20", "--k-prior", "10", "--quiet"]
    assert main(["run", "--model", "t-likelihood", *tiny]) == 0
    assert capsys.readouterr().out.startswith("SARSP, cost and reward model: GP, Student-t noise, ")
    assert main(["run", "--model", "t-likelihood", "--reward-model", "tp", *tiny]) == 0
    assert capsys.readouterr().out.startswith("SARSP, cost model: GP, Student-t noise, reward model: Student-t "
                                              "process, ")


@pytest.mark.parametrize("command", ["threshold-study", "rule-study", "model-sweep"])
def test_help_has_no_doubled_percent(capsys, command):
    from sarsp_edu.cli.main import main

    with pytest.raises(SystemExit):
        main([command, "--help"])
    assert "%%" not in capsys.readouterr().out


def test_a_model_sweep_says_what_it_does_before_its_first_cell_ends(tmp_path, monkeypatch):
    import sarsp_edu.experiments.sweep.models as models

    lines = []
    monkeypatch.setattr(models, "in_workers", lambda function, arguments, workers: iter(()))  # no run at all
    models.run_model_sweep(ROOT / "results" / "sweep-reduced", tmp_path / "third", n_jobs=1, report=lines.append)
    assert lines and lines[0].startswith("t-likelihood: running ") and "each fits its models, then runs its" in lines[0]


def test_prefers_names_a_bad_summary_value_and_cannot_decide_on_nan():
    from sarsp_edu import prefers

    good = {"mean_reward": -90.0, "cost_rate": 0.02, "task_success_rate": 90.0}
    with pytest.raises(ValueError, match=r"summary_1\['cost_rate'\] must be a number, got '0.01'"):
        prefers({**good, "cost_rate": "0.01"}, good)
    with pytest.raises(ValueError, match=r"summary_2\['task_success_rate'\] must be a number, got None"):
        prefers(good, {**good, "task_success_rate": None})
    with pytest.raises(ValueError, match=r"summary_1\['task_success_rate'\] must lie in \[0, 100\] \(a rate in %\), "
                                         r"got 150"):
        prefers({**good, "task_success_rate": 150}, good)
    with pytest.raises(ValueError, match=r"summary_1\['cost_rate'\] must lie in \[0, inf\], got -0.1"):
        prefers({**good, "cost_rate": -0.1}, good)
    with pytest.raises(TypeError, match="summary_1 must be a mapping"):
        prefers(None, good)
    assert prefers({**good, "cost_rate": float("nan")}, good) is None


def test_a_distance_threshold_beyond_the_grid_is_warned_of(capsys):
    from sarsp_edu.cli import main

    assert main(["run", "--grid-size", "4", "--n-unsafe", "2", "--episodes", "1", "--offline-episodes", "4",
                 "--optimizer-steps", "2", "--d", "100", "--quiet"]) == 0
    assert ("warning: --d 100 is beyond every distance on a 4x4 grid (at most 6): no action is ever predicted safe, "
            "every decision is the backup") in capsys.readouterr().err


def test_a_sweep_with_fewer_unsafe_states_than_the_presets_nss_runs_its_own_nss(tmp_path, capsys):
    from sarsp_edu.cli import main

    out = tmp_path / "one"
    assert main(["sweep", "--grid-size", "4", "--n-unsafe", "1", "--nss", "1", "--m", "40", "--p", "0.2",
                 "--episodes", "1", "--offline-episodes", "2", "--optimizer-steps", "2", "--reward-fit-points", "20",
                 "--k-prior", "10", "--out", str(out), "--quiet"]) == 0
    assert [cell.name for cell in (out / "cells").iterdir()] == ["m40_p0.2_nss1_seed0"]


def test_check_cell_on_a_model_sweeps_folder_checks_its_model_run(monkeypatch, tmp_path, capsys):
    from sarsp_edu.cli import main
    from sarsp_edu.experiments.sweep import models
    from sarsp_edu.experiments.sweep.check import SideCheck

    (tmp_path / "model_sweep.json").write_text("{}")
    seen = []
    monkeypatch.setattr(models, "check_model_cell", lambda folder, cell: seen.append((folder, cell)) or SideCheck(
        80, diagnostics={"reward_mse": 0.0}))
    assert main(["check-cell", str(tmp_path), "m40_p0.2_nss2_seed0"]) == 0
    assert seen == [(str(tmp_path), "m40_p0.2_nss2_seed0")]
    assert "m40_p0.2_nss2_seed0: identical: all 80 episodes equal" in capsys.readouterr().out
    monkeypatch.setattr(models, "check_model_cell", lambda folder, cell: SideCheck(
        80, differing_columns=("episode_cost",), first_differing_episode=3, diagnostics={"reward_mse": 0.0}))
    assert main(["check-cell", str(tmp_path), "m40_p0.2_nss2_seed0"]) == 1
    assert "differs from episode 3 in ['episode_cost']" in capsys.readouterr().out
