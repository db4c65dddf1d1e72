"""Each model's safe set held to the world (sarsp_edu.experiments.audit)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from sarsp_edu import ExperimentConfig
from sarsp_edu.experiments.audit import audit_summary, safe_set_audit
from sarsp_edu.world.preparation import prepare

from .worlds import SIX_BY_SIX

SMALL = ExperimentConfig(**SIX_BY_SIX, episodes=2, n_switch_states=1)


@pytest.fixture(scope="module")
def audit():
    return safe_set_audit(SMALL, draws=2)


def test_every_action_from_every_free_cell_of_the_shifted_world_with_the_truth(audit):
    env = prepare(SMALL).env  # the world after the shift, as every side's
    goal = tuple(int(v) for v in env.observation_at((0, 0))[2:4])
    free = env.size * env.size - len(env.unsafe_states) - 1  # the goal's cell is no start of a move
    assert len(audit) == 3 * free * 4 and set(audit["model"]) == {"tp", "gp", "t-likelihood"}
    distances = env.distance_map()  # indexed [y, x]
    moves = {0: (1, 0), 1: (0, 1), 2: (-1, 0), 3: (0, -1)}  # RIGHT, DOWN, LEFT, UP
    for row in audit.sample(40, random_state=0).itertuples():
        dx, dy = moves[row.action]
        x, y = min(max(row.x + dx, 0), env.size - 1), min(max(row.y + dy, 0), env.size - 1)
        assert row.distance == pytest.approx(distances[y, x]) and row.violates == (distances[y, x] < SMALL.d)
        assert row.reward == pytest.approx(-np.hypot(x - goal[0], y - goal[1]))
    assert audit["safe_share"].between(0, 1).all() and (audit["var_cost"] > 0).all()


def test_the_same_priors_are_drawn_for_every_model_and_the_audit_is_reproducible(audit):
    again = safe_set_audit(SMALL, models=("gp",), draws=2)
    pd.testing.assert_frame_equal(again.reset_index(drop=True),
                                  audit[audit["model"] == "gp"].reset_index(drop=True))


def test_the_summary_counts_what_each_safe_set_holds():
    rows = []
    for model, safe in (("a", [1.0, 1.0, 0.0, 0.0]), ("b", [0.0, 1.0, 0.0, 0.0])):
        for action, share in enumerate(safe):
            rows.append({"model": model, "x": 0, "y": 0, "action": action, "mu_cost": 1.0, "var_cost": 0.5,
                         "safe_share": share, "distance": 1.0, "violates": action == 0,
                         "mu_reward": [-1.0, -2.0, -3.0, -4.0][action], "reward": [-1.0, -1.0, -2.0, -2.0][action]})
        rows += [{"model": model, "x": 1, "y": 0, "action": a, "mu_cost": 0.0, "var_cost": 2.0, "safe_share": 0.0,
                  "distance": 0.0, "violates": True, "mu_reward": float(a == (3 if model == "a" else 2)),
                  "reward": float(a == 3)} for a in range(4)]
    summary = audit_summary(pd.DataFrame(rows))
    assert summary.loc["unsafe actions called safe", "a"] == pytest.approx(1 / 5)
    assert summary.loc["unsafe actions called safe", "b"] == 0.0
    assert summary.loc["safe actions called safe", "b"] == pytest.approx(1 / 3)
    assert summary.loc["cells left to the backup"].tolist() == [0.5, 0.5]
    assert summary.loc["disagreements"].tolist() == [1, 1]
    assert np.allclose(summary.loc["median variance"], [1.25, 1.25])
    # cell (0, 0): both pick action 0, a best move (tied with action 1); cell (1, 0): only "a" picks the best, 3
    assert summary.loc["best move by reward"].tolist() == [1.0, 0.5]


def test_where_two_models_part_each_ones_predictions_are_read_at_those_pairs():
    from sarsp_edu.experiments.audit import disagreements

    rows = []
    for model, safe, variance in (("a", [1.0, 1.0, 0.0, 0.0], 0.1), ("b", [0.0, 1.0, 1.0, 0.0], 3.0)):
        for action, share in enumerate(safe):
            rows.append({"model": model, "x": 0, "y": 0, "action": action, "mu_cost": float(action),
                         "var_cost": variance * (action + 1), "safe_share": share, "distance": 1.0,
                         "violates": action == 0, "mu_reward": 0.0, "reward": 0.0})
    table = disagreements(pd.DataFrame(rows))
    row = table.loc["a vs b"]
    assert row["pairs that differ"] == 2 and row["truly violate"] == 1  # actions 0 and 2; action 0 violates
    assert row["a: called safe"] == 1 and row["b: called safe"] == 1
    assert row["a: median distance"] == pytest.approx(1.0) and row["b: median variance"] == pytest.approx(6.0)


def test_the_fitted_hyperparameters_are_each_agents_own():
    from sarsp_edu.experiments.audit import fitted_hyperparameters
    from sarsp_edu.experiments.experiment import Experiment
    from sarsp_edu.models.processes.laplace import noise_variance

    table = fitted_hyperparameters(SMALL, models=("gp", "t-likelihood"))
    assert list(table.index) == [("gp", "cost"), ("gp", "reward"), ("t-likelihood", "cost"),
                                 ("t-likelihood", "reward")]
    robust = Experiment(SMALL.replace(model="t-likelihood")).agent.cost_model
    row = table.loc[("t-likelihood", "cost")]
    assert row["length_scale"] == robust.kernel_.length_scale and row["scale"] == robust.scale_
    assert row["noise_variance"] == pytest.approx(noise_variance(robust.nu, robust.scale_))
    assert np.isnan(table.loc[("gp", "cost"), "scale"]) and table.loc[("gp", "cost"), "noise_variance"] > 0
