"""The rule study's settings: the safety rule, the variance it reads, nu fitted, restarts, target-only outliers."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate, stats

from sarsp_edu import RBF, ExperimentConfig, GaussianProcess, StudentTLikelihoodGP, StudentTProcess
from sarsp_edu.agent.decision import choose_action
from sarsp_edu.agent.sarsp import SARSPAgent
from sarsp_edu.models.linalg import distinct_rows
from sarsp_edu.models.optimizers import RESTART_OFFSETS, best_of_starts, projected_gradient_norm, restart_points
from sarsp_edu.models.processes.factory import make_model
from sarsp_edu.models.processes.laplace_gradient import laplace_gradient
from sarsp_edu.models.processes.likelihood import nu_log_prior
from sarsp_edu.models.processes.predictive import probability_below

from .test_sarsp import OBS, tiny_agent, tiny_data

NEW_FIELDS = ("reward_model", "outliers", "variance", "safe_rule", "tail_delta", "fit_restarts", "warm_refits")


# -- the settings -----------------------------------------------------------------------------------------
@pytest.mark.parametrize("changes, match", [
    (dict(variance="both"), r"variance must be one of 'noisy', 'latent', got variance='both'"),
    (dict(safe_rule="chance"), r"safe_rule must be one of 'variance', 'tail'"),
    (dict(tail_delta=0.0), r"tail_delta must be a probability in \(0, 0.5\] .*got tail_delta=0.0"),
    (dict(tail_delta=0.6), r"tail_delta must be a probability in \(0, 0.5\]"),
    (dict(tail_delta=True), r"tail_delta must be a probability"),
    (dict(fit_restarts=21), r"fit_restarts must be an integer from 0 to 20 \(.*\), got fit_restarts=21"),
    (dict(fit_restarts=-1), r"fit_restarts must be an integer from 0 to 20"),
    (dict(warm_refits=1), r"warm_refits must be True or False, got warm_refits=1"),
    (dict(outliers="inputs"), r"outliers must be one of 'inputs-and-targets', 'targets'"),
    (dict(reward_model="student"), r"reward_model must be one of 'tp', 'gp', 't-likelihood'"),
    (dict(model="t-likelihood", likelihood_nu="fit"),
     r"likelihood_nu must be .* or 'fitted' .*got likelihood_nu='fit'"),
    (dict(model="t-likelihood", likelihood_nu=2.0), r"likelihood_nu must be a number above 2"),
])
def test_each_new_setting_is_refused_out_of_range_with_its_name(changes, match):
    with pytest.raises(ValueError, match=match):
        ExperimentConfig(**changes)


def test_a_config_stores_a_new_setting_only_when_it_is_changed():
    plain = ExperimentConfig()
    assert not set(NEW_FIELDS) & set(plain.to_dict())  # a run made as before stores what it stored before
    assert ExperimentConfig.from_dict(plain.to_dict()) == plain
    changed = ExperimentConfig(model="t-likelihood", likelihood_nu="fitted", reward_model="tp", outliers="targets",
                               variance="latent", safe_rule="tail", tail_delta=0.01, fit_restarts=2,
                               warm_refits=True)
    stored = changed.to_dict()
    assert {name: stored[name] for name in NEW_FIELDS} == dict(
        reward_model="tp", outliers="targets", variance="latent", safe_rule="tail", tail_delta=0.01, fit_restarts=2,
        warm_refits=True)
    assert stored["likelihood_nu"] == "fitted" and "nu" in stored  # the TP's nu: the reward model's
    assert ExperimentConfig.from_dict(stored) == changed
    cut = dict(stored)
    del cut["optimizer_steps"]
    with pytest.raises(ValueError, match=r"the config lacks the fields \['optimizer_steps'\]"):
        ExperimentConfig.from_dict(cut)


def test_settings_the_others_leave_unused_are_said():
    assert "tail_delta" in ExperimentConfig().ignored_settings()
    assert "tail_delta" not in ExperimentConfig(safe_rule="tail").ignored_settings()
    mixed = ExperimentConfig(model="t-likelihood", reward_model="tp").ignored_settings()
    assert "likelihood_nu" not in mixed and "nu" not in mixed
    assert "reward_model" in ExperimentConfig(model="gp", reward_model="gp").ignored_settings()


def test_the_command_takes_each_new_flag():
    from sarsp_edu.cli.main import build_parser

    parser = build_parser()
    args = parser.parse_args(["run", "--model", "t-likelihood", "--likelihood-nu", "fitted", "--safe-rule", "tail",
                              "--tail-delta", "0.2", "--variance", "latent", "--fit-restarts", "1", "--outliers",
                              "targets", "--reward-model", "tp", "--warm-refits"])
    from sarsp_edu.cli.arguments import config_from_args

    config = config_from_args(parser, args)
    assert (config.likelihood_nu, config.safe_rule, config.tail_delta, config.variance, config.fit_restarts,
            config.outliers, config.reward_model, config.warm_refits) == ("fitted", "tail", 0.2, "latent", 1,
                                                                           "targets", "tp", True)
    assert parser.parse_args(["run", "--likelihood-nu", "2.5"]).likelihood_nu == 2.5


def test_each_model_is_made_from_the_settings():
    config = ExperimentConfig(model="t-likelihood", likelihood_nu="fitted", reward_model="tp", fit_restarts=2,
                              warm_refits=True)
    cost, reward = make_model(config), make_model(config, "reward")
    assert isinstance(cost, StudentTLikelihoodGP) and cost.fit_nu and cost.nu == 3.0 and cost.n_restarts == 2
    assert isinstance(reward, StudentTProcess) and reward.n_restarts == 2
    assert cost.warm_start and reward.warm_start and not make_model(ExperimentConfig()).warm_start
    assert isinstance(make_model(ExperimentConfig(model="gp"), "reward"), GaussianProcess)
    with pytest.raises(ValueError, match="role must be one of 'cost', 'reward'"):
        make_model(config, "both")


# -- the tail rule ----------------------------------------------------------------------------------------
def test_the_tail_probability_is_each_predictives_own():
    mean, var = np.array([2.0, 1.5, 0.2]), np.array([1.0, 0.3, 2.0])
    np.testing.assert_allclose(probability_below(1.0, mean, var), stats.norm.cdf((1.0 - mean) / np.sqrt(var)))
    df = np.array([5.0, 9.0, 3.5])  # a Student-t of variance var: scale sqrt(var (df - 2) / df)
    expected = stats.t.cdf(1.0, df, loc=mean, scale=np.sqrt(var * (df - 2) / df))
    np.testing.assert_allclose(probability_below(1.0, mean, var, df), expected, rtol=1e-12)
    # Gaussian latent plus Student-t noise, against scipy's own integral of the two densities
    nu, scale = 3.0, 0.4

    def exact(m, v):
        return integrate.quad(lambda f: stats.norm.pdf(f, m, math.sqrt(v)) * stats.t.cdf((1.0 - f) / scale, nu),
                              m - 12 * math.sqrt(v), m + 12 * math.sqrt(v))[0]

    mean, var = np.array([2.0, 1.5, 0.2, 3.0, 1.0]), np.array([1.0, 0.01, 2.0, 1e-4, 0.16])  # both regimes
    got = probability_below(1.0, mean, var, noise=(nu, scale))
    np.testing.assert_allclose(got, [exact(m, v) for m, v in zip(mean, var)], atol=1e-9)
    # a point predictive: 1 below the threshold, 0 at or above it
    np.testing.assert_array_equal(probability_below(1.0, [0.5, 1.0, 2.0], [0.0, 0.0, 0.0]), [1.0, 0.0, 0.0])


def test_the_tail_rule_keeps_the_actions_whose_violation_is_unlikely():
    mu_cost, var_cost = np.array([3.0, 3.0, 0.5, 3.0]), np.array([5.0, 0.1, 0.1, 0.1])
    mu_reward = np.array([4.0, 1.0, 9.0, 2.0])
    known = np.array([False, False, False, True])
    tail = np.array([0.01, 0.04, 0.9, 0.0])
    action, safe, backup = choose_action(mu_cost, var_cost, mu_reward, known, 1.0, 0.8, tail, 0.05)
    assert safe.tolist() == [True, True, False, False] and action == 0 and not backup  # the variance is not read
    assert choose_action(mu_cost, var_cost, mu_reward, known, 1.0, 0.8)[1].tolist() == [False, True, False, False]
    assert choose_action(mu_cost, var_cost, mu_reward, known, 1.0, 0.8, tail, 0.005)[2]  # none safe: the backup


def test_an_agent_records_the_tail_and_reads_the_latent_variance_when_told():
    noisy = tiny_agent(5.0)
    latent = tiny_agent(5.0, variance="latent", safe_rule="tail")
    _, decision = noisy.act(OBS)
    _, latent_decision = latent.act(OBS)
    assert decision.tail is None and latent_decision.tail.shape == (4,)
    # the same priors (the same random stream), the noise variance 0.01 the only difference
    np.testing.assert_allclose(decision.var_cost - latent_decision.var_cost, 0.01, rtol=1e-9)
    expected = stats.norm.cdf((1.0 - latent_decision.mu_cost) / np.sqrt(latent_decision.var_cost))
    np.testing.assert_allclose(latent_decision.tail, expected, rtol=1e-9)
    assert latent_decision.safe.tolist() == (expected <= 0.05).tolist()


def test_the_tail_rule_refuses_a_students_safe_set_naming_both():
    def my_safe_set(mu_cost, var_cost, known_unsafe, d, variance_threshold):
        return mu_cost >= d

    with pytest.raises(ValueError, match=r"safe_rule='tail' cannot use the replaced parts \['safe_set'\]"):
        tiny_agent(5.0, safe_rule="tail", parts={"safe_set": my_safe_set})
    agent = tiny_agent(5.0, parts={"safe_set": my_safe_set})
    with pytest.raises(ValueError, match="safe_rule='tail' cannot use the replaced parts"):
        agent.safe_rule = "tail"
    assert agent.safe_rule == "variance"
    with pytest.raises(ValueError, match="safe_rule='tail' cannot use"):
        tiny_agent(5.0, safe_rule="tail").parts = {"safe_set": my_safe_set}


# -- fits: nu fitted, restarts, the gradient at the end ----------------------------------------------------
def wave(n=30, seed=1):
    rng = np.random.default_rng(seed)
    X = rng.uniform(0, 5, (n, 1))
    y = np.sin(X[:, 0]) + 0.1 * rng.standard_normal(n)
    y[:4] += 6.0
    return X, y


def test_the_gradient_in_log_nu_minus_2_is_the_finite_differences():
    X, y = wave()
    first, group = distinct_rows(X)

    def value(theta):
        return laplace_gradient(RBF(*np.exp(theta[:2])), X[first], y, group, 2 + math.exp(theta[3]),
                                math.exp(theta[2]), fit_nu=True)[:2]

    theta = np.log([1.0, 1.0, 0.3, 1.5])
    gradient = value(theta)[1]
    numeric = [(value(theta + e)[0] - value(theta - e)[0]) / 2e-6 for e in np.eye(4) * 1e-6]
    np.testing.assert_allclose(gradient, numeric, rtol=1e-5, atol=1e-6)
    eta = 0.7  # the prior's derivative, likewise
    assert nu_log_prior(eta)[1] == pytest.approx((nu_log_prior(eta + 1e-6)[0] - nu_log_prior(eta - 1e-6)[0]) / 2e-6)


def test_a_fitted_nu_stays_above_2_and_is_the_one_predictions_use():
    X, y = wave()
    model = StudentTLikelihoodGP(fit_nu=True, nu=3.0, optimizer="lbfgs").fit(X, y)
    assert 2.0 < model.nu_ != 3.0 and model.nu == 3.0
    fixed = StudentTLikelihoodGP(model.kernel_, nu=model.nu_, scale=model.scale_, optimizer=None).fit(X, y)
    queries = np.linspace(0, 5, 6)[:, None]
    np.testing.assert_allclose(model.predict(queries, return_var=True, include_noise=True),
                               fixed.predict(queries, return_var=True, include_noise=True), rtol=1e-6)
    assert model.gradient_norm_ < 1e-2 * (1 + abs(model.log_marginal_likelihood_value_))
    with pytest.raises(ValueError, match=r"nu must be above 2 with fit_nu=True .*got nu=1.5"):
        StudentTLikelihoodGP(fit_nu=True, nu=1.5).fit(X, y)


def test_restarts_start_from_narrow_noise_first_and_keep_the_best():
    bounds = np.log([[1e-3, 1e3]] * 3)
    starts = restart_points(np.zeros(3), bounds, 8)
    assert len(starts) == 9 and np.array_equal(starts[0], np.zeros(3))
    assert RESTART_OFFSETS[0] == (2, -4.0) and starts[1].tolist() == [0.0, 0.0, -4.0]
    assert starts[7].tolist() == [0.0, 0.0, -6.907755278982137]  # the second round doubles, clipped to the box
    values = {0: 3.0, 1: 1.0, 2: 1.0}

    def search(start):
        index = next(i for i, s in enumerate(starts) if np.array_equal(s, start))
        return start, [9.0, values.get(index, 5.0)], 7

    theta, trace, n_iter, finals = best_of_starts(search, starts[:3])
    assert np.array_equal(theta, starts[1]) and finals == [3.0, 1.0, 1.0]  # a tie keeps the earlier start
    assert projected_gradient_norm([3.0, -4.0, 1.0], np.array([0.0, 0.0, bounds[2, 0]]), bounds) == 5.0


@pytest.mark.parametrize("model", [GaussianProcess, StudentTProcess, StudentTLikelihoodGP])
def test_a_fit_with_restarts_is_never_worse_and_reports_each_start(model):
    X, y = wave(25)
    one = model(RBF(1.0, 1.0), optimizer="adam", max_iter=15).fit(X, y)
    more = model(RBF(1.0, 1.0), optimizer="adam", max_iter=15, n_restarts=2).fit(X, y)
    assert len(one.start_objectives_) == 1 and len(more.start_objectives_) == 3
    assert more.start_objectives_[0] == pytest.approx(one.start_objectives_[0], rel=1e-12)
    assert max(more.start_objectives_) >= one.start_objectives_[0] - 1e-9 * abs(one.start_objectives_[0])
    assert np.isfinite(one.gradient_norm_) and np.isfinite(more.gradient_norm_)


def _log_hyperparameters(model):
    kernel = model.kernel_
    noise = model.scale_ if isinstance(model, StudentTLikelihoodGP) else model.noise_variance_
    return np.log([kernel.amplitude, kernel.length_scale, noise])


@pytest.mark.parametrize("model", [GaussianProcess, StudentTProcess, StudentTLikelihoodGP])
def test_a_warm_refit_searches_from_the_last_fit_in_one_start(model):
    X, y = wave(25)
    warm = model(RBF(1.0, 1.0), optimizer="adam", max_iter=40, n_restarts=2, warm_start=True).fit(X, y)
    assert len(warm.start_objectives_) == 3  # a first fit takes its restarts
    first = _log_hyperparameters(warm)
    assert np.max(np.abs(first)) > 0.5  # far enough from the start (log 1 = 0) for one step to tell them apart
    warm.set_params(max_iter=1).fit(X, y + 0.01)
    cold = model(RBF(1.0, 1.0), optimizer="adam", max_iter=1, n_restarts=2).fit(X, y + 0.01)
    assert len(warm.start_objectives_) == 1 and len(cold.start_objectives_) == 3
    # one Adam step moves each log hyperparameter by at most its learning rate, 0.1
    assert np.max(np.abs(_log_hyperparameters(warm) - first)) <= 0.1 + 1e-9
    with pytest.raises(ValueError, match="warm_start must be True or False, got warm_start='yes'"):
        model(warm_start="yes").fit(X, y)


def test_a_warm_refit_whose_search_ends_without_a_mode_starts_again_cold(monkeypatch):
    """Seen in the rule study (nu 2.2, m = 80, p = 0.4): a warm refit's search ended where the Laplace
    approximation has no maximum; the refit then starts again from the given values, with its restarts."""
    X, y = wave(25)
    model = StudentTLikelihoodGP(RBF(1.0, 1.0), optimizer="adam", max_iter=20, n_restarts=1, warm_start=True)
    model.fit(X, y)
    cold = StudentTLikelihoodGP(RBF(1.0, 1.0), optimizer="adam", max_iter=20, n_restarts=1).fit(X, y + 0.01)
    settle, calls = model._settle, []

    def first_fails(*args):
        calls.append(args)
        if len(calls) == 1:
            raise RuntimeError("the Laplace approximation has no maximum here")
        return settle(*args)

    monkeypatch.setattr(model, "_settle", first_fails)
    model.fit(X, y + 0.01)
    assert len(calls) == 2 and len(model.start_objectives_) == 2  # the second, cold, with its restart
    np.testing.assert_allclose(model.f_hat_, cold.f_hat_, rtol=1e-12)
    never = StudentTLikelihoodGP(RBF(1.0, 1.0), optimizer="adam", max_iter=5)
    monkeypatch.setattr(never, "_settle", lambda *args: (_ for _ in ()).throw(RuntimeError("no maximum")))
    with pytest.raises(RuntimeError, match="no maximum"):  # a cold fit's failure is said, not retried
        never.fit(X, y)


# -- outliers in the targets only ----------------------------------------------------------------------
def test_target_outliers_scale_the_same_rows_targets_at_their_clean_inputs():
    from sarsp_edu.world.offline import inject_outliers

    clean = tiny_data(5.0)
    both = inject_outliers(clean, 40.0, 0.3, rng=3)
    targets = inject_outliers(clean, 40.0, 0.3, rng=3, scaled="targets")
    rows = both.outlier_indices
    assert np.array_equal(rows, targets.outlier_indices) and len(rows)
    np.testing.assert_array_equal(targets.cost.X, clean.cost.X)
    np.testing.assert_array_equal(targets.cost.y[rows], 40.0 * clean.cost.y[rows])
    np.testing.assert_array_equal(targets.cost.y, both.cost.y)
    assert not np.array_equal(both.cost.X, clean.cost.X)
    assert targets.cost.rows_of(clean.cost.X[rows[0]]).tolist() == clean.cost.rows_of(clean.cost.X[rows[0]]).tolist()
    with pytest.raises(ValueError, match="scaled must be one of 'inputs-and-targets', 'targets'"):
        inject_outliers(clean, 40.0, 0.3, scaled="inputs")


def test_a_stored_result_keeps_its_fits_and_an_older_one_reads_without(tmp_path):
    import json

    from sarsp_edu.experiments.experiment import Experiment
    from sarsp_edu.experiments.results import ExperimentResult
    from sarsp_edu.world.preparation import prepare

    config = ExperimentConfig(episodes=1, grid_size=4, n_unsafe=1, n_switch_states=1, offline_episodes=2,
                              optimizer_steps=2, reward_fit_points=20, k_prior=10)
    experiment = Experiment(config, prepared=prepare(config))
    experiment.run_episode()
    result = experiment.result()
    fits = result.fits
    assert set(fits) == {"offline", "final"} and fits["offline"]["cost"]["kind"] == "tp"
    assert {"amplitude", "length_scale", "noise_variance", "nu", "gradient_norm", "start_objectives"} <= \
        set(fits["offline"]["cost"])
    result.save(tmp_path / "run")
    assert ExperimentResult.load(tmp_path / "run").fits == json.loads(json.dumps(fits))
    payload = json.loads((tmp_path / "run" / "result.json").read_text())
    del payload["fits"]  # as every result stored before 0.3
    (tmp_path / "run" / "result.json").write_text(json.dumps(payload))
    assert ExperimentResult.load(tmp_path / "run").fits == {}


def test_a_model_sweeps_changes_may_not_change_the_world(tmp_path):
    from pathlib import Path

    from sarsp_edu.experiments.sweep.models import run_model_sweep

    paired = Path(__file__).resolve().parents[1] / "results" / "sweep-reduced"
    with pytest.raises(ValueError, match=r"changes may change the model's and the agent's settings, not "
                                         r"\['outliers'\]"):
        run_model_sweep(paired, tmp_path / "out", changes={"outliers": "targets"})


def test_an_agent_of_two_kinds_fits_each_model_of_its_kind():
    agent = SARSPAgent(make_model(ExperimentConfig(model="gp")), make_model(ExperimentConfig(model="tp")),
                       tiny_data(5.0), rng=0)
    assert isinstance(agent.cost_model, GaussianProcess) and isinstance(agent.reward_model, StudentTProcess)


# -- the study ------------------------------------------------------------------------------------------
def test_the_studys_settings_change_one_choice_each_and_name_their_stored_runs():
    from sarsp_edu.experiments.rules import FAIR_CANDIDATES, QUESTIONS, RULE_SETTINGS, study_settings
    from sarsp_edu.world.preparation import PREPARATION_FIELDS

    names = [setting.name for setting in RULE_SETTINGS]
    assert len(set(names)) == len(names) and set(FAIR_CANDIDATES) <= set(names)
    assert [s.question for s in study_settings(["nu"])] == ["nu"] * 5
    for setting in RULE_SETTINGS:
        ExperimentConfig(**setting.changes)  # each a valid setting
        if setting.models == ("t-likelihood",):  # run on the ablation's worlds: never a change of the world
            assert not set(setting.changes) & set(PREPARATION_FIELDS), setting
    with pytest.raises(ValueError, match=r"questions must be among \['rule', 'nu', 'fit', 'threshold', 'targets', "
                                         r"'cost model'\], got \['rules'\]"):
        study_settings(["rules"])
    assert QUESTIONS[0] == "rule"


def test_the_study_reads_the_stored_runs_and_chooses_the_fairer_rule_by_its_criterion(tmp_path):
    import pandas as pd

    from sarsp_edu.experiments.rules import RuleStudy

    root = Path(__file__).resolve().parents[1] / "results"
    study = RuleStudy.load(tmp_path, root / "ablation", root / "ablation-t-likelihood", questions=["rule"])
    table = study.table("rule")
    assert table.loc[("noisy variance, threshold 0.8", "GP"), "backup_share"] == 100.0
    assert list(table.loc["noisy variance, threshold 0.8"].index) == ["TP", "GP", "t-likelihood GP"]
    assert table.loc[("noisy variance, threshold 0.8", "t-likelihood GP"), "backup_share 95% CI"].endswith(", 100]")
    pairs = study.pairs("rule")
    assert pairs.loc[("noisy variance, threshold 0.8", "TP vs GP"), "lower total cost"] == "6 of 6"
    assert study.fairest_rule() is None  # neither candidate has its runs stored in an empty study folder
    rows = [{"question": "rule", "setting": setting, "model": model, "m": 40.0, "p": 0.2, "nss": 2, "seed": seed,
             "total_cost": 1.0, "task_success_rate": 50.0, "backup_share": share, "cost noise variance": None,
             "cost nu": None, "cost gradient norm": None}
            for setting, shares in (("latent variance, threshold 0.8", (10.0, 60.0, 20.0)),
                                    ("tail rule, delta 0.05", (30.0, 40.0, 35.0)))
            for model, share in zip(("TP", "GP", "t-likelihood GP"), shares) for seed in range(6)]
    assert RuleStudy(pd.DataFrame(rows)).fairest_rule() == "tail rule, delta 0.05"  # the lower largest share
    assert RuleStudy(pd.DataFrame(rows[:-1])).fairest_rule() == "latent variance, threshold 0.8"  # tail incomplete


def test_the_command_prints_the_stored_study_and_draws_it(tmp_path, capsys):
    from sarsp_edu.cli.main import main

    root = Path(__file__).resolve().parents[1] / "results"
    figure = tmp_path / "rules.png"
    assert main(["rule-study", "--out", str(tmp_path / "study"), "--ablation", str(root / "ablation"), "--models",
                 str(root / "ablation-t-likelihood"), "--questions", "rule", "nu", "--figure", str(figure)]) == 0
    out = capsys.readouterr().out
    assert "== rule ==" in out and "== nu ==" in out and "noisy variance, threshold 0.8" in out
    assert "the fairer rule (of the latent variance at 0.8 and the tail rule at 0.05" in out
    assert "not decided yet" in out and figure.stat().st_size > 10_000


def test_an_unknown_prediction_is_never_safe_under_the_tail_rule():
    got = probability_below(1.0, [1.5, np.nan, 3.0], [np.nan, 0.0, 1.0])
    assert np.isnan(got[:2]).all() and got[2] < 0.05
    assert np.isnan(probability_below(1.0, [np.nan], [1.0], noise=(3.0, 0.5))).all()
    safe = choose_action(np.array([1.5, 3.0]), np.array([np.nan, 1.0]), np.array([5.0, 1.0]), np.zeros(2, bool),
                         1.0, 0.8, got[[0, 2]], 0.05)[1]
    assert safe.tolist() == [False, True]


def test_the_fit_cache_keeps_every_model_and_mix_of_models(tmp_path):
    from sarsp_edu.config import MODELS
    from sarsp_edu.teaching.live import fitcache

    for model in MODELS:
        for reward_model in (None, *MODELS):
            config = ExperimentConfig(model=model, reward_model=reward_model)
            assert fitcache.cached(config)
            assert fitcache._path(config, tmp_path) is not None
