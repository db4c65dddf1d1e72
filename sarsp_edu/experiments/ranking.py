"""Which of an agent's two models costs it the goal: runs with the cost and the reward model of different kinds, and
how the reward model ranks the four moves along the run's own steps.

An agent reaches its goal by following its reward model among the moves its
cost model lets it take.  :func:`mixed_experiment` builds a run whose cost
model is one kind (``"tp"``, ``"gp"``, ``"t-likelihood"``) and whose reward
model is another, on the same world, data, episodes and random stream as the
config's own run: with both kinds the config's model it *is* that run, step
for step.  :func:`reward_ranking` runs it and records, at every step, the four
predicted rewards against the true ones (minus the distance from each move's
cell to the goal): whether the move predicted best is truly a best move, the
spread of the predictions against the truth's, and their correlation; and
the moves the rule chose from against the world's own rule, which off the
backup are the cost model's safe set.  :func:`ranking_study` sets several
pairs of kinds side by side on one world, and :func:`paired_episodes` two
runs' episodes, each started at the same cell with the same goal.

Unlike :func:`~sarsp_edu.experiments.audit.safe_set_audit`, which predicts from
every cell of the world once, these are the cells the agent visits, as often
as it visits them: a model wrong where the agent circles weighs as much as the
agent's circling does.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .._internal.threads import one_blas_thread
from .._internal.validation import check_choice
from ..config import MODELS, ExperimentConfig, config_or_default
from ..world.gridworld.layout import goal_reward, moved, nearest
from ..world.preparation import prepare
from .experiment import Experiment
from .tables import sign_test

__all__ = ["RANKING_PAIRS", "mixed_experiment", "paired_episodes", "ranking_study", "ranking_summary",
           "reward_ranking"]

#: (cost model, reward model): each model alone, and the third model's two models each beside the TP's
RANKING_PAIRS = (("tp", "tp"), ("t-likelihood", "t-likelihood"), ("t-likelihood", "tp"), ("tp", "t-likelihood"))


def mixed_experiment(config: ExperimentConfig | None = None, cost: str | None = None, reward: str | None = None, *,
                     prepared=None) -> Experiment:
    """A run of ``config`` whose cost model is of kind ``cost`` and reward model of kind ``reward``.

    Parameters
    ----------
    config : ExperimentConfig, optional
        Everything else: the world, the data, the episodes, the settings.
    cost, reward : {"tp", "gp", "t-likelihood"}, optional
        Each model's kind (default the config's ``model`` and ``reward_model``), with the config's settings of
        that kind (``nu``, ``likelihood_nu``).
    prepared : Prepared, optional
        ``prepare(config)``, to share one world among several runs.

    Returns
    -------
    Experiment
        Fitted, not yet run.  The agent's random stream is the config's run's: with ``cost == reward ==
        config.model`` its steps are :func:`~sarsp_edu.experiments.experiment.run_experiment`'s.
    """
    config = config_or_default(config)
    cost = config.model if cost is None else cost
    reward = config.model_kinds[-1] if reward is None else reward
    check_choice("cost", cost, MODELS)
    check_choice("reward", reward, MODELS)

    return Experiment(config.replace(model=cost, reward_model=None if reward == cost else reward), prepared=prepared)


def reward_ranking(experiment: Experiment) -> pd.DataFrame:
    """Run ``experiment`` to its end; at each step, how its reward model ranked the four moves.

    Returns
    -------
    pandas.DataFrame
        One row per step: ``episode``, the cell ``x, y`` and the ``action`` taken, ``backup`` (no action was
        safe), ``best move allowed`` (a move of the highest true reward is among those the rule chooses from:
        the safe set, or on a backup every move not known to be unsafe), ``predicted best is best`` (the move of
        the highest predicted reward is a move of the highest true reward), ``chosen is best`` (the move taken
        is), ``closer`` (the move taken ends nearer the goal than it began), ``predicted spread`` and ``true
        spread`` (the largest minus the smallest of the four), their ``correlation`` (NaN where the
        predictions are all equal); the moves the rule chose from, against the world's own rule (a move
        violates when it ends closer than ``d`` to an unsafe state): ``moves allowed`` (how many),
        ``safe moves excluded`` and ``unsafe moves allowed`` (how many), ``safe best excluded`` (a best move is
        truly safe, yet no best move is allowed), which on a step off the backup are the cost model's safe
        set's; the ``goal x, goal y`` of the step's episode, and the episode's ``completed``.
    """
    rows = []
    with one_blas_thread():
        while not experiment.finished:
            rows.append(_ranked_step(experiment))
    steps = pd.DataFrame(rows)
    completed = {i + 1: bool(episode["task_completed"]) for i, episode in enumerate(experiment.episodes)}
    return steps.assign(completed=steps["episode"].map(completed))


def _ranked_step(experiment: Experiment) -> dict:
    """One step of ``experiment``, and its reward model's ranking of the four moves (:func:`reward_ranking`)."""
    record = experiment.step()
    env = experiment.env  # its goal is the step's: an episode's end leaves it, the next step's reset draws anew
    after = [moved(record.position, action, env.size) for action in range(4)]
    true = np.array([goal_reward(cell, env.goal) for cell in after])
    safe = np.array([nearest(cell, env.unsafe_states)[1] >= env.d for cell in after])  # the world's cost rule
    predicted = np.asarray(record.decision.mu_reward, dtype=float)
    best = np.isclose(true, true.max())
    here = goal_reward(record.position, env.goal)
    decision = record.decision
    allowed = ~np.asarray(decision.known_unsafe) if decision.backup else np.asarray(decision.safe)
    return {"episode": record.episode, "x": int(record.position[0]), "y": int(record.position[1]),
            "action": int(record.action), "backup": bool(decision.backup),
            "best move allowed": bool(np.any(best & allowed)),
            "predicted best is best": bool(best[np.argmax(predicted)]), "chosen is best": bool(best[record.action]),
            "closer": bool(true[record.action] > here),
            "predicted spread": float(np.ptp(predicted)), "true spread": float(np.ptp(true)),
            "correlation": float(np.corrcoef(predicted, true)[0, 1]) if np.ptp(predicted) > 0 else np.nan,
            "moves allowed": int(allowed.sum()), "safe moves excluded": int(np.sum(safe & ~allowed)),
            "unsafe moves allowed": int(np.sum(~safe & allowed)),
            "safe best excluded": bool(np.any(best & safe) and not np.any(best & allowed)),
            "goal x": int(env.goal[0]), "goal y": int(env.goal[1])}


def ranking_summary(steps: pd.DataFrame) -> pd.Series:
    """One run's :func:`reward_ranking` in a few numbers.

    Returns
    -------
    pandas.Series
        ``TSR %`` and ``steps`` per episode; over steps, ``backup %``, ``best move allowed %``,
        ``predicted best is best %``, ``chosen is best %``, ``closer %``, ``same move on a return %`` (of the
        steps from a cell the episode has left before, those that take the move taken there last: an agent
        circling repeats itself), the mean ``predicted spread`` and ``true spread``, the mean
        ``correlation``; over the steps off the backup alone, where the moves allowed are the cost model's safe
        set (on a backup they are every move not known unsafe, and no truly safe move is known unsafe): the
        mean ``safe set: moves``, ``safe set: safe moves excluded`` and ``safe set: unsafe moves allowed``, and
        ``safe set: safe best excluded %`` (NaN where every step took the backup).
    """
    episodes = steps.groupby("episode")
    own = steps[~steps["backup"]]  # the cost model's safe set chose
    return pd.Series({"TSR %": 100 * episodes["completed"].first().mean(), "steps": episodes.size().mean(),
                      "backup %": 100 * steps["backup"].mean(),
                      "best move allowed %": 100 * steps["best move allowed"].mean(),
                      "predicted best is best %": 100 * steps["predicted best is best"].mean(),
                      "chosen is best %": 100 * steps["chosen is best"].mean(),
                      "closer %": 100 * steps["closer"].mean(),
                      "same move on a return %": 100 * _same_move_on_return(steps),
                      "predicted spread": steps["predicted spread"].mean(),
                      "true spread": steps["true spread"].mean(), "correlation": steps["correlation"].mean(),
                      "safe set: moves": own["moves allowed"].mean(),
                      "safe set: safe moves excluded": own["safe moves excluded"].mean(),
                      "safe set: unsafe moves allowed": own["unsafe moves allowed"].mean(),
                      "safe set: safe best excluded %": 100 * own["safe best excluded"].astype(float).mean()})


def _same_move_on_return(steps: pd.DataFrame) -> float:
    """The share of returns to a cell (within an episode) that repeat the move taken there last (NaN: none)."""
    repeats = []
    for _, episode in steps.groupby("episode", sort=False):
        last = {}
        for x, y, action in zip(episode["x"], episode["y"], episode["action"]):
            if (x, y) in last:
                repeats.append(last[(x, y)] == action)
            last[(x, y)] = action
    return float(np.mean(repeats)) if repeats else float("nan")


def ranking_study(config: ExperimentConfig | None = None, pairs=RANKING_PAIRS) -> pd.DataFrame:
    """:func:`ranking_summary` of a run per (cost model, reward model) pair, all on ``config``'s one world.

    Parameters
    ----------
    config : ExperimentConfig, optional
        Its ``episodes`` are each run's.
    pairs : sequence of (str, str), default RANKING_PAIRS

    Returns
    -------
    pandas.DataFrame
        One row per pair, indexed by ``cost`` and ``reward``.
    """
    config = config_or_default(config)
    prepared = prepare(config)
    rows = {tuple(pair): ranking_summary(reward_ranking(mixed_experiment(config, *pair, prepared=prepared)))
            for pair in pairs}
    return pd.DataFrame(rows).T.rename_axis(["cost", "reward"])


def paired_episodes(first: pd.DataFrame, second: pd.DataFrame) -> pd.Series:
    """How two runs' paired episodes ended: counts of which reached the goal, and a sign test.

    Runs of one config (:func:`mixed_experiment` with different kinds) start each episode at the same cell
    with the same goal; their episodes pair one to one.  The sign test treats the episodes that only one run
    completed as independent coin flips; within a run they are not quite (the agent carries what it learnt,
    and its random stream, from one episode to the next).

    Parameters
    ----------
    first, second : pandas.DataFrame
        Two :func:`reward_ranking` frames.

    Returns
    -------
    pandas.Series
        The counts of episodes that ``both``, ``first only``, ``second only`` and ``neither`` completed, and
        ``sign test p``: :func:`~sarsp_edu.experiments.tables.sign_test` of the episodes' outcomes (1.0 when
        no episode ends differently).

    Raises
    ------
    ValueError
        If the runs' episodes do not start at the same cells with the same goals.
    """
    ends = [steps.groupby("episode")[["x", "y", "goal x", "goal y", "completed"]].first() for steps in (first, second)]
    places = ["x", "y", "goal x", "goal y"]
    if not ends[0].index.equals(ends[1].index) or not ends[0][places].equals(ends[1][places]):
        raise ValueError("first and second must be runs of the same episodes: the same starts and goals, episode "
                         "by episode (two runs of one config)")
    a, b = (end["completed"].to_numpy(dtype=bool) for end in ends)
    return pd.Series({"both": int(np.sum(a & b)), "first only": int(np.sum(a & ~b)),
                      "second only": int(np.sum(~a & b)), "neither": int(np.sum(~a & ~b)),
                      "sign test p": sign_test(a.astype(float), b.astype(float))})
