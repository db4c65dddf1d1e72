"""Each model's safe set held to the world: which actions it calls safe, and which of those truly violate.

After the offline fit and the shift, every model of a paired comparison
predicts the cost signal (the distance to the nearest unsafe state after the
move) of every action from every free cell, each prediction from a fresh
strategic prior as a decision draws it.  :func:`safe_set_audit` records the
predicted distance, its variance, how often the action falls in Algorithm 1's
safe set (variance at most sigma*^2, distance at least d; ``S_u`` empty, as at
the first online step), and whether it truly violates (the distance after the
move is below d); beside them, the predicted reward of every action against the
true one (minus the distance from the new cell to the world's goal of the
moment).  :func:`audit_summary` counts, per model: the truly unsafe actions its
safe set holds, the safe actions it leaves out, the cells with no safe action
(where the backup decides), where the models disagree, and the cells where the
reward model's best action is truly a best move (the backup's choice, and the
safe set's when it holds every action).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .._internal.rng import as_generator
from ..agent.decision import safe_actions
from ..config import MODELS, ExperimentConfig, config_or_default
from ..world.gridworld.layout import goal_reward, moved, nearest
from .experiment import experiments_on_one_world

__all__ = ["audit_summary", "disagreements", "fitted_hyperparameters", "safe_set_audit"]


def safe_set_audit(config: ExperimentConfig | None = None, models=MODELS, draws: int = 3, rng=0) -> pd.DataFrame:
    """Every model's cost predictions and safe set, for every action from every free cell of the shifted world.

    Parameters
    ----------
    config : ExperimentConfig, optional
        The world, data and settings (its ``model`` is ignored); the models are fitted on its one world.
    models : sequence of str, default every model of ``MODELS``
    draws : int, default 3
        Fresh strategic priors per cell and model.
    rng : None, int or numpy.random.Generator
        Draws the priors (the agents' own streams are left as they are).

    Returns
    -------
    pandas.DataFrame
        One row per model, cell and action: ``model, x, y, action``, the mean over draws of the predicted
        distance ``mu_cost`` and its variance ``var_cost``, ``safe_share`` (the share of draws in which the action
        is in the safe set), the true distance after the move and ``violates`` (below d), the mean predicted
        reward ``mu_reward`` and the true ``reward`` of the move.
    """
    config = config_or_default(config)
    experiments = experiments_on_one_world(config, {model: {"model": model} for model in models})
    env = next(iter(experiments.values())).env
    unsafe = {tuple(int(v) for v in cell) for cell in env.unsafe_states}
    goal = tuple(int(v) for v in env.observation_at((0, 0))[2:4])
    cells = [(x, y) for x in range(env.size) for y in range(env.size) if (x, y) not in unsafe and (x, y) != goal]
    seeds = as_generator(rng).integers(2**63, size=len(cells) * draws)
    rows = []
    for model, experiment in experiments.items():
        agent, saved = experiment.agent, experiment.agent.rng
        for c, cell in enumerate(cells):
            observation = env.observation_at(cell)
            mus, variances, safe, rewards = [], [], [], []
            for draw in range(draws):
                agent.rng = np.random.default_rng(seeds[c * draws + draw])  # the same draws for every model
                mu, var, mu_reward = agent.predict(observation)[:3]
                mus.append(mu)
                rewards.append(mu_reward)
                variances.append(var)
                safe.append(safe_actions(mu, var, np.zeros(len(mu), dtype=bool), config.d, config.variance_threshold))
            for action in range(len(mus[0])):
                after = moved(cell, action, env.size)
                distance = nearest(after, env.unsafe_states)[1]
                rows.append({"model": model, "x": cell[0], "y": cell[1], "action": action,
                             "mu_cost": float(np.mean([m[action] for m in mus])),
                             "var_cost": float(np.mean([v[action] for v in variances])),
                             "safe_share": float(np.mean([s[action] for s in safe])),
                             "distance": float(distance), "violates": bool(distance < config.d),
                             "mu_reward": float(np.mean([r[action] for r in rewards])),
                             "reward": goal_reward(after, goal)})
        agent.rng = saved
    return pd.DataFrame(rows)


def _best_move_share(part: pd.DataFrame) -> float:
    """The share of cells where an action of the highest mean predicted reward truly rewards most."""
    hits = []
    for _, cell in part.groupby(["x", "y"]):
        reward = cell["reward"].to_numpy()
        hits.append(bool(np.isclose(reward[np.argmax(cell["mu_reward"].to_numpy())], reward.max())))
    return float(np.mean(hits))


def audit_summary(audit: pd.DataFrame) -> pd.DataFrame:
    """Per model: how its safe set meets the truth, from :func:`safe_set_audit`'s rows.

    Parameters
    ----------
    audit : pandas.DataFrame
        :func:`safe_set_audit`'s rows.

    Returns
    -------
    pandas.DataFrame
        Per model: ``unsafe actions called safe`` (the share of truly violating actions in the safe set, over
        draws), ``safe actions called safe``, ``cells left to the backup`` (the share of cells and draws whose
        safe set is empty, estimated as the cells where no action is ever safe), the median predicted variance,
        ``disagreements``: the (cell, action) pairs whose safe-set verdict (in the set in most draws) differs
        from another model's, and ``best move by reward``: the share of cells whose highest mean predicted reward
        is a move of the highest true reward.
    """
    verdict = audit.assign(safe=audit["safe_share"] > 0.5).pivot_table(
        index=["x", "y", "action"], columns="model", values="safe", aggfunc="first")
    rows = {}
    for model, part in audit.groupby("model", sort=False):
        violating, fine = part[part["violates"]], part[~part["violates"]]
        by_cell = part.groupby(["x", "y"])["safe_share"].max()
        others = [other for other in verdict.columns if other != model]
        rows[model] = {"unsafe actions called safe": violating["safe_share"].mean(),
                       "safe actions called safe": fine["safe_share"].mean(),
                       "cells left to the backup": float((by_cell == 0).mean()),
                       "median variance": part["var_cost"].median(),
                       "disagreements": int((verdict[others].ne(verdict[model], axis=0)).any(axis=1).sum()),
                       "best move by reward": _best_move_share(part)}
    return pd.DataFrame(rows)


def disagreements(audit: pd.DataFrame) -> pd.DataFrame:
    """Where the models' safe sets part: each model's predictions at the (cell, action) pairs it judges otherwise.

    Parameters
    ----------
    audit : pandas.DataFrame
        :func:`safe_set_audit`'s rows.

    Returns
    -------
    pandas.DataFrame
        One row per pair of models: the (cell, action) pairs whose verdicts (in the safe set in most draws)
        differ, how many of them truly violate, and for each of the two models the pairs it calls safe and its
        median predicted distance and variance there.
    """
    verdict = audit.assign(safe=audit["safe_share"] > 0.5).set_index(["model", "x", "y", "action"])
    models = list(dict.fromkeys(audit["model"]))
    rows = []
    for i, first in enumerate(models):
        for second in models[i + 1:]:
            one, two = verdict.loc[first], verdict.loc[second]
            differ = one.index[one["safe"].to_numpy() != two["safe"].reindex(one.index).to_numpy()]
            row = {"pair": f"{first} vs {second}", "pairs that differ": len(differ),
                   "truly violate": int(one.loc[differ, "violates"].sum())}
            for model, part in ((first, one.loc[differ]), (second, two.loc[differ])):
                row[f"{model}: called safe"] = int(part["safe"].sum())
                row[f"{model}: median distance"] = float(part["mu_cost"].median()) if len(part) else float("nan")
                row[f"{model}: median variance"] = float(part["var_cost"].median()) if len(part) else float("nan")
            rows.append(row)
    return pd.DataFrame(rows).set_index("pair")


def fitted_hyperparameters(config: ExperimentConfig | None = None, models=MODELS) -> pd.DataFrame:
    """Each model's offline fit on one world: the cost and the reward model's amplitude, length scale and noise.

    Parameters
    ----------
    config : ExperimentConfig, optional
        The world, data and settings (its ``model`` is ignored); every model is fitted on its one world.
    models : sequence of str, default every model of ``MODELS``

    Returns
    -------
    pandas.DataFrame
        One row per model and target (``"cost"``, ``"reward"``): ``amplitude``, ``length_scale`` and
        ``noise_variance``, the variance of a new observation's noise (for the GP with Student-t noise
        ``s^2 nu / (nu - 2)``, its ``scale`` s beside it).
    """
    from ..models.processes.laplace import noise_variance

    config = config_or_default(config)
    experiments = experiments_on_one_world(config, {model: {"model": model} for model in models})
    rows = []
    for model, experiment in experiments.items():
        for target in ("cost", "reward"):
            fitted = getattr(experiment.agent, f"{target}_model")
            row = {"model": model, "target": target, "amplitude": float(fitted.kernel_.amplitude),
                   "length_scale": float(fitted.kernel_.length_scale)}
            if hasattr(fitted, "scale_"):
                row.update(noise_variance=noise_variance(fitted.nu, fitted.scale_), scale=fitted.scale_)
            else:
                row.update(noise_variance=float(fitted.noise_variance_), scale=np.nan)
            rows.append(row)
    return pd.DataFrame(rows).set_index(["model", "target"])
