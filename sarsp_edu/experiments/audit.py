"""Each model's safe set held to the world: which actions it calls safe, and which of those truly violate.

After the offline fit and the shift, every model of a paired comparison
predicts the cost signal (the distance to the nearest unsafe state after the
move) of every action from every free cell, each prediction from a fresh
strategic prior as a decision draws it.  :func:`safe_set_audit` records the
predicted distance, its variance, how often the action falls in Algorithm 1's
safe set (variance at most sigma*^2, distance at least d; ``S_u`` empty, as at
the first online step), and whether it truly violates (the distance after the
move is below d).  :func:`audit_summary` counts, per model: the truly unsafe
actions its safe set holds, the safe actions it leaves out, the cells with no
safe action (where the backup decides), and where the models disagree.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .._internal.rng import as_generator
from ..agent.decision import safe_actions
from ..config import MODELS, ExperimentConfig, config_or_default
from ..world.gridworld.layout import moved, nearest
from .experiment import experiments_on_one_world

__all__ = ["audit_summary", "safe_set_audit"]


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
        is in the safe set), the true distance after the move and ``violates`` (below d).
    """
    config = config_or_default(config)
    experiments = experiments_on_one_world(config, {model: {"model": model} for model in models})
    env = next(iter(experiments.values())).env
    unsafe = {tuple(int(v) for v in cell) for cell in env.unsafe_states}
    cells = [(x, y) for x in range(env.size) for y in range(env.size) if (x, y) not in unsafe]
    seeds = as_generator(rng).integers(2**63, size=len(cells) * draws)
    rows = []
    for model, experiment in experiments.items():
        agent, saved = experiment.agent, experiment.agent.rng
        for c, cell in enumerate(cells):
            observation = env.observation_at(cell)
            mus, variances, safe = [], [], []
            for draw in range(draws):
                agent.rng = np.random.default_rng(seeds[c * draws + draw])  # the same draws for every model
                mu, var = agent.predict(observation)[:2]
                mus.append(mu)
                variances.append(var)
                safe.append(safe_actions(mu, var, np.zeros(len(mu), dtype=bool), config.d, config.variance_threshold))
            for action in range(len(mus[0])):
                distance = nearest(moved(cell, action, env.size), env.unsafe_states)[1]
                rows.append({"model": model, "x": cell[0], "y": cell[1], "action": action,
                             "mu_cost": float(np.mean([m[action] for m in mus])),
                             "var_cost": float(np.mean([v[action] for v in variances])),
                             "safe_share": float(np.mean([s[action] for s in safe])),
                             "distance": float(distance), "violates": bool(distance < config.d)})
        agent.rng = saved
    return pd.DataFrame(rows)


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
        and ``disagreements``: the (cell, action) pairs whose safe-set verdict (in the set in most draws) differs
        from another model's.
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
                       "disagreements": int((verdict[others].ne(verdict[model], axis=0)).any(axis=1).sum())}
    return pd.DataFrame(rows)
