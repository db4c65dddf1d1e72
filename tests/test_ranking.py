"""Runs with mixed models, and the reward model's ranking along a run (sarsp_edu.experiments.ranking)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from sarsp_edu import ExperimentConfig, GaussianProcess, StudentTLikelihoodGP, StudentTProcess, run_experiment
from sarsp_edu.experiments.ranking import (
    mixed_experiment,
    paired_episodes,
    ranking_study,
    ranking_summary,
    reward_ranking,
)
from sarsp_edu.world.preparation import prepare

from .worlds import SIX_BY_SIX

SMALL = ExperimentConfig(**SIX_BY_SIX, episodes=3, n_switch_states=1, max_steps=30)


def test_with_both_models_of_the_configs_kind_the_run_is_the_configs_own_step_for_step():
    experiment = mixed_experiment(SMALL.replace(model="gp"), "gp", "gp")
    steps = reward_ranking(experiment)
    own = run_experiment(SMALL.replace(model="gp")).records
    pd.testing.assert_frame_equal(experiment.records(), own)
    assert len(steps) == own["episode_steps"].sum()
    assert list(steps.groupby("episode")["completed"].first()) == list(own["task_completed"])


def test_each_model_is_of_the_kind_asked_and_fitted_on_the_configs_rows():
    experiment = mixed_experiment(SMALL, cost="t-likelihood", reward="gp")
    assert isinstance(experiment.agent.cost_model, StudentTLikelihoodGP)
    assert isinstance(experiment.agent.reward_model, GaussianProcess)
    assert experiment.config.model == "t-likelihood"
    default = mixed_experiment(SMALL)  # the config's model for both
    assert isinstance(default.agent.cost_model, StudentTProcess)
    assert isinstance(default.agent.reward_model, StudentTProcess)
    # the reward model is the one a run of its own kind fits: the same rows, the same hyperparameters
    gp_run = mixed_experiment(SMALL, "gp", "gp")
    assert experiment.agent.reward_model.kernel_.get_params() == gp_run.agent.reward_model.kernel_.get_params()


@pytest.mark.parametrize("name, value", [("cost", "student-t"), ("reward", "GP")])
def test_an_unknown_kind_is_refused_by_name(name, value):
    with pytest.raises(ValueError, match=rf"{name}.*{value}"):
        mixed_experiment(SMALL, **{name: value})


# a threshold so wide that the safe set often chooses, and lets a violating move in and a safe best move out
WIDE = SMALL.replace(variance_threshold=500)


@pytest.mark.parametrize("config", [SMALL, WIDE], ids=["backup-mostly", "safe-set-mostly"])
def test_each_step_holds_the_predicted_rewards_against_the_worlds(config):
    experiment = mixed_experiment(config, "tp", "tp")
    env, seen = experiment.env, []
    original = experiment.step

    def step():  # what the step saw, to recompute the ranking independently
        record = original()
        seen.append((record, np.array(experiment.env.unsafe_states)))
        return record

    experiment.step = step
    steps = reward_ranking(experiment)
    assert len(steps) == len(seen)
    moves = {0: (1, 0), 1: (0, 1), 2: (-1, 0), 3: (0, -1)}  # RIGHT, DOWN, LEFT, UP
    assert all(np.array_equal(unsafe, seen[0][1]) for _, unsafe in seen)  # the shifted world stays as it is
    for (record, unsafe), row, named in zip(seen, steps.itertuples(index=False), steps.to_dict("records")):
        goal = experiment.episodes[record.episode - 1]["goal"]  # the episode's own, as its record keeps it
        x, y = record.position
        cells = [(min(max(x + dx, 0), env.size - 1), min(max(y + dy, 0), env.size - 1)) for dx, dy in moves.values()]
        true = [-np.hypot(cx - goal[0], cy - goal[1]) for cx, cy in cells]
        violates = np.array([np.min(np.hypot(*(unsafe - cell).T)) < env.d for cell in cells])
        predicted = record.decision.mu_reward
        best = np.isclose(true, max(true))
        allowed = ~record.decision.known_unsafe if record.decision.backup else record.decision.safe
        assert (row[1], row[2], row[3]) == (x, y, record.action)
        assert row[5] == bool(np.any(best & allowed))
        assert row[6] == (true[int(np.argmax(predicted))] == pytest.approx(max(true)))  # predicted best is best
        assert row[7] == (true[record.action] == pytest.approx(max(true)))  # chosen is best
        assert row[8] == (true[record.action] > -np.hypot(x - goal[0], y - goal[1]))  # closer
        assert row[9] == pytest.approx(np.ptp(predicted)) and row[10] == pytest.approx(np.ptp(true))
        assert row[11] == pytest.approx(np.corrcoef(predicted, true)[0, 1])
        assert named["moves allowed"] == allowed.sum()
        assert named["safe moves excluded"] == np.sum(~violates & ~allowed)
        assert named["unsafe moves allowed"] == np.sum(violates & allowed)
        assert named["safe best excluded"] == (any(best & ~violates) and not any(best & allowed))
        assert (named["goal x"], named["goal y"]) == tuple(goal)
    own = steps[~steps["backup"]]
    if config is WIDE:  # each count is seen to be other than 0 off the backup
        assert own["unsafe moves allowed"].any() and own["safe best excluded"].any()
        assert own["safe moves excluded"].any() and not own["moves allowed"].eq(4).all()


def test_the_summary_counts_episodes_once_and_steps_by_their_share():
    steps = pd.DataFrame({"episode": [1, 1, 1, 2], "x": [0, 1, 0, 1], "y": [0, 0, 0, 0], "action": [0, 2, 0, 2],
                          "backup": [True, False, False, False],
                          "best move allowed": [True, True, True, False],
                          "predicted best is best": [True, True, False, False], "chosen is best": [False] * 4,
                          "closer": [True, False, False, False],
                          "predicted spread": [1.0, 2.0, 3.0, 4.0], "true spread": [2.0] * 4,
                          "correlation": [0.5, np.nan, 0.5, 0.2], "moves allowed": [4, 2, 3, 1],
                          "safe moves excluded": [0, 1, 1, 2], "unsafe moves allowed": [1, 0, 0, 0],
                          "safe best excluded": [True, False, False, True],
                          "goal x": [3] * 4, "goal y": [3] * 4, "completed": [True, True, True, False]})
    summary = ranking_summary(steps)
    assert summary["TSR %"] == 50 and summary["steps"] == 2 and summary["backup %"] == 25
    assert summary["best move allowed %"] == 75 and summary["closer %"] == 25
    assert summary["predicted best is best %"] == 50 and summary["predicted spread"] == 2.5
    assert summary["correlation"] == pytest.approx(0.4)  # NaN (all predictions equal) left out
    # the safe set's columns over the three steps off the backup only
    assert summary["safe set: moves"] == 2 and summary["safe set: safe moves excluded"] == pytest.approx(4 / 3)
    assert summary["safe set: unsafe moves allowed"] == 0
    assert summary["safe set: safe best excluded %"] == pytest.approx(100 / 3)
    assert summary["same move on a return %"] == 100  # episode 1 returns to (0, 0) once and moves right again;
    # episode 2's (1, 0) is its first visit
    steps.loc[2, "action"] = 1
    assert ranking_summary(steps)["same move on a return %"] == 0


def test_the_study_runs_every_pair_on_one_world():
    study = ranking_study(SMALL.replace(episodes=2), pairs=[("tp", "tp"), ("gp", "tp")])
    assert list(study.index) == [("tp", "tp"), ("gp", "tp")] and study.index.names == ["cost", "reward"]
    alone = ranking_summary(reward_ranking(mixed_experiment(SMALL.replace(episodes=2), "gp", "tp",
                                                            prepared=prepare(SMALL.replace(episodes=2)))))
    pd.testing.assert_series_equal(study.loc[("gp", "tp")], alone, check_names=False)


def _episodes(completed, starts=None, goals=None):
    """A ranking frame of two steps per episode (the second from another cell), with the episodes' outcomes."""
    n = len(completed)
    starts = [(0, 0)] * n if starts is None else starts
    goals = [(4, 5)] * n if goals is None else goals
    return pd.DataFrame({"episode": np.repeat(np.arange(1, n + 1), 2),
                         "x": [v for x, _ in starts for v in (x, x + 1)], "y": [v for _, y in starts for v in (y, 2)],
                         "goal x": np.repeat([x for x, _ in goals], 2), "goal y": np.repeat([y for _, y in goals], 2),
                         "completed": np.repeat(completed, 2)})


def test_paired_episodes_counts_each_outcome_and_tests_the_discordant_ones():
    first = _episodes([True] * 9 + [False, True, False])
    second = _episodes([False] * 9 + [True, True, False])
    second.loc[second.index % 2 == 1, "x"] += 1  # later steps differ between the runs; the starts do not
    paired = paired_episodes(first, second)
    assert (paired["both"], paired["first only"], paired["second only"], paired["neither"]) == (1, 9, 1, 1)
    assert paired["sign test p"] == pytest.approx(2 * 11 / 2**10)  # P(9 or more of 10, or 1 or fewer), halves at 1/2
    assert paired_episodes(first, first)["sign test p"] == 1.0  # no discordant episode


@pytest.mark.parametrize("other", [dict(starts=[(1, 0)] * 12), dict(goals=[(5, 5)] * 12), dict(n=11)],
                         ids=["starts", "goals", "episodes"])
def test_paired_episodes_refuses_runs_of_other_episodes(other):
    first = _episodes([True] * 12)
    n = other.pop("n", 12)
    with pytest.raises(ValueError, match="same starts and goals"):
        paired_episodes(first, _episodes([True] * n, **other))


def test_runs_of_one_config_with_different_models_pair_episode_by_episode():
    config = WIDE.replace(episodes=3)
    prepared = prepare(config)
    experiments = {kind: mixed_experiment(config, kind, kind, prepared=prepared) for kind in ("tp", "gp")}
    runs = {kind: reward_ranking(experiment) for kind, experiment in experiments.items()}
    for kind, steps in runs.items():  # each episode's first row is its start, with its goal and its end
        first = steps.groupby("episode").first()
        for i, episode in enumerate(experiments[kind].episodes):
            assert tuple(first.loc[i + 1, ["x", "y"]]) == tuple(episode["start"])
            assert tuple(first.loc[i + 1, ["goal x", "goal y"]]) == tuple(episode["goal"])
            assert first.loc[i + 1, "completed"] == episode["task_completed"]
    paired = paired_episodes(runs["tp"], runs["gp"])
    completed = [experiments[kind].records()["task_completed"].to_numpy() for kind in ("tp", "gp")]
    assert paired["both"] == np.sum(completed[0] & completed[1])
    assert paired["first only"] == np.sum(completed[0] & ~completed[1])
    assert paired["second only"] == np.sum(~completed[0] & completed[1])
