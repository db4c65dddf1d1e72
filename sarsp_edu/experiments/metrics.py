"""The paper's metrics, their comparison and Definition 4.

Running metrics per episode (section 5.2, eq. 12), the percentage of TP
against GP that the paper's tables print, which of two values is better, the
preference criterion (Definition 4), and the diagnostics of a run's records
(backup share, trapped failures).
"""

from __future__ import annotations

import math
import numbers

import numpy as np
import pandas as pd

from .._internal.validation import check_range
from ..config import DEFINITION_4_A

__all__ = [
    "SUMMARY_METRICS",
    "RECORD_COLUMNS",
    "HIGHER_IS_BETTER",
    "running_metrics",
    "percent_difference",
    "symmetric_percent_difference",
    "better_of",
    "displayed_summary",
    "check_a",
    "backup_share",
    "trapped_share",
    "TRAPPED_CELLS",
    "trapped_episodes",
    "cost_rate_undefined",
    "prefers",
]


#: summary metrics, the paper's order (Tables 2-4)
SUMMARY_METRICS = ("mean_reward", "mean_cost", "total_cost", "task_success_rate", "mean_steps", "cost_rate")

#: every column of ``ExperimentResult.records`` and what it holds
RECORD_COLUMNS = {
    "episode": "episode number, from 1",
    "mean_reward": "running mean over episodes of the episode's summed reward (J_r)",
    "mean_cost": "running mean over episodes of the episode's violations",
    "total_cost": "running sum of violations",
    "task_success_rate": "running % of episodes that reached the goal (TSR)",
    "mean_steps": "running mean episode length",
    "cost_rate": ("running total cost / steps of the episodes that reached the goal with zero cost (p_c, eq. 12); "
                  "0 while either is 0"),
    "reward_mse": "this episode: mean squared error of the predicted reward of the taken action",
    "cost_prediction_error": "this episode: mean absolute error of the predicted cost signal of the taken action",
    "safe_action_variance": "this episode: mean predicted cost variance of the actions chosen as safe (NaN if none)",
    "backup_rate": "this episode: share of decisions where no action was safe and the backup chose",
    "corrective_updates": "running number of corrective updates of the cost model's data",
    "retrains": "running number of cost-model retrains",
    "final_cells": "this episode: distinct cells among the agent's last 10 positions (<= 2 on a failure: trapped)",
    "episode_reward": "this episode: summed reward",
    "episode_cost": "this episode: violations",
    "episode_steps": "this episode: steps",
    "task_completed": "this episode: whether the goal was reached",
    "start": "this episode: start cell (x, y)",
    "goal": "this episode: goal cell (x, y)",
}


def running_metrics(episode_reward, episode_cost, episode_steps, task_completed) -> pd.DataFrame:
    """The paper's running metrics after each episode (section 5.2, eq. 12).

    Parameters
    ----------
    episode_reward, episode_cost, episode_steps, task_completed : array-like of shape (E,)

    Returns
    -------
    DataFrame with the columns of ``SUMMARY_METRICS``, one row per episode.

    Examples
    --------
    >>> m = running_metrics([-10, -30], [0, 2], [5, 20], [True, False])
    >>> m["cost_rate"].tolist()  # 2 violations / 5 clean successful steps
    [0.0, 0.4]
    """
    reward = np.asarray(episode_reward, dtype=float)
    cost = np.asarray(episode_cost, dtype=float)
    steps = np.asarray(episode_steps, dtype=float)
    done = np.asarray(task_completed, dtype=bool)
    count = np.arange(1, len(reward) + 1)
    total_cost = np.cumsum(cost)
    clean_steps = np.cumsum(np.where(done & (cost == 0), steps, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        cost_rate = np.where((total_cost > 0) & (clean_steps > 0), total_cost / clean_steps, 0.0)
    return pd.DataFrame(
        {
            "mean_reward": np.cumsum(reward) / count,
            "mean_cost": total_cost / count,
            "total_cost": total_cost,
            "task_success_rate": 100.0 * np.cumsum(done) / count,
            "mean_steps": np.cumsum(steps) / count,
            "cost_rate": cost_rate,
        }
    )


def percent_difference(tp: float, gp: float) -> float:
    """``(tp - gp) / |gp| * 100``, the paper's "TP vs GP" percentage.

    0 when both are 0; NaN when only ``gp`` is 0, or when either is NaN.

    Parameters
    ----------
    tp, gp : float
        The same summary metric for the TP and for the GP (the reference).
    """
    if math.isnan(tp) or math.isnan(gp):
        return math.nan
    if gp == 0:
        return 0.0 if tp == 0 else math.nan
    return (tp - gp) / abs(gp) * 100.0


def symmetric_percent_difference(a: float, b: float) -> float:
    """``|a - b| / ((|a| + |b|) / 2) * 100``: the "% difference" the paper's Table 1 prints in total cost.

    Unlike :func:`percent_difference` it has no sign and no reference model.  For the non-negative totals of
    Table 1 the denominator is the mean; with the magnitudes' mean it stays defined (at most 200) where the
    values have opposite signs, as rewards can (exercise 5.1 asks for the same rule).

    Parameters
    ----------
    a, b : float
        The two values, in either order.

    >>> symmetric_percent_difference(28, 58), symmetric_percent_difference(-3, 5), symmetric_percent_difference(0, 0)
    (69.76744186046511, 200.0, 0.0)
    """
    return 0.0 if a == b else abs(a - b) / ((abs(a) + abs(b)) / 2) * 100


#: for each summary metric, whether a higher value is better
HIGHER_IS_BETTER = {
    "mean_reward": True,
    "mean_cost": False,
    "total_cost": False,
    "task_success_rate": True,
    "mean_steps": False,
    "cost_rate": False,
}


def better_of(metric: str, tp: float, gp: float) -> str:
    """``"TP"``, ``"GP"``, ``"tie"``, or ``"n/a"`` when either value is undefined (NaN).

    Parameters
    ----------
    metric : str
        A key of :data:`HIGHER_IS_BETTER`, which says which direction is better.
    tp, gp : float
        The metric's value for the TP and for the GP.
    """
    if math.isnan(tp) or math.isnan(gp):
        return "n/a"
    if tp == gp:
        return "tie"
    return "TP" if (tp > gp) == HIGHER_IS_BETTER[metric] else "GP"


def displayed_summary(summary: dict) -> dict:
    """A summary for display: an undefined cost rate becomes NaN (shown as n/a)."""
    if cost_rate_undefined(summary):
        return {**summary, "cost_rate": math.nan}
    return dict(summary)


def check_a(a) -> float:
    """Definition 4's TSR threshold ``a``: a number in [1, 100] (%)."""
    return check_range("a", a, 1.0, 100.0, "a task success rate in %")


def backup_share(records: pd.DataFrame) -> float:
    """Share of all decisions in ``records`` taken by the backup rule (no action was safe)."""
    steps = records["episode_steps"].sum()
    return float((records["backup_rate"] * records["episode_steps"]).sum() / steps) if steps else math.nan


#: a failed episode whose last positions lie on at most this many cells was trapped
TRAPPED_CELLS = 2


def trapped_episodes(records: pd.DataFrame) -> pd.Series:
    """Per episode: whether it failed (goal not reached) trapped on at most ``TRAPPED_CELLS`` cells.

    A greedy agent that pushes into a wall, or steps back and forth between
    two cells, until the step limit (see ``final_cells``).  All False for
    results stored before version 0.2.0, which did not record ``final_cells``.
    """
    failed = ~records["task_completed"].astype(bool)
    if "final_cells" not in records:
        return failed & False
    return failed & (records["final_cells"] <= TRAPPED_CELLS)


def trapped_share(records: pd.DataFrame) -> float:
    """Share of failed episodes (goal not reached) that ended trapped (:func:`trapped_episodes`).

    NaN when no episode failed, or for results stored before version 0.2.0,
    which did not record ``final_cells``.
    """
    failed = ~records["task_completed"].astype(bool)
    if not failed.any() or "final_cells" not in records:  # results stored before 0.2.0 lack the column
        return math.nan
    return float(trapped_episodes(records).sum() / failed.sum())


def cost_rate_undefined(summary) -> bool:
    """Whether eq. 12's cost rate is undefined: violations, but no episode succeeded without one.

    Its denominator (the steps of clean successful episodes) is then 0.
    Records and summaries keep the paper's value 0 there, so that averages
    over configurations are the paper's; tables show ``n/a`` and
    Definition 4 does not decide.  ``summary`` needs ``total_cost`` and
    ``cost_rate``.
    """
    return bool(summary["total_cost"] > 0 and summary["cost_rate"] == 0)


def prefers(summary_1: dict, summary_2: dict, a: float = DEFINITION_4_A) -> bool | None:
    """Paper Definition 4: is agent 1 preferred to agent 2?

    ``A1 > A2`` iff ``p_c(A1) < p_c(A2)`` and at least one of
    ``J_r(A1) >= J_r(A2)``, ``TSR(A1) >= TSR(A2)`` or ``TSR(A1) >= a``.

    Parameters
    ----------
    summary_1, summary_2 : dict
        With ``mean_reward`` (J_r), ``cost_rate`` (p_c) and
        ``task_success_rate`` (TSR, in %).
    a : float, default 100.0
        The task-specific TSR threshold in [1, 100] (%).  The default is the
        strictest: the third branch then needs a perfect success rate.

    Returns
    -------
    bool, or None when either cost rate is undefined (see
    :func:`cost_rate_undefined`; needs ``total_cost`` in the summaries to
    tell) or NaN: Definition 4 then cannot decide.

    Raises
    ------
    TypeError, ValueError
        A summary that is not a mapping, lacks a value, or holds one that is not a number in its range (a
        success rate in [0, 100] %, a cost rate at least 0), named.

    Notes
    -----
    The cost-rate test is strict, so two agents with equal cost rates (both
    0, say) are never preferred to one another.

    Examples
    --------
    >>> tp = {"mean_reward": -70.0, "cost_rate": 0.010, "task_success_rate": 92.0}
    >>> gp = {"mean_reward": -120.0, "cost_rate": 0.012, "task_success_rate": 86.0}
    >>> prefers(tp, gp), prefers(gp, tp)
    (True, False)
    """
    a_value = check_a(a)
    ranges = {"mean_reward": (-math.inf, math.inf), "cost_rate": (0.0, math.inf), "task_success_rate": (0.0, 100.0)}
    for label, summary in (("summary_1", summary_1), ("summary_2", summary_2)):
        if not hasattr(summary, "__getitem__") or isinstance(summary, (str, bytes)):  # a dict, a pandas row ...
            raise TypeError(f"{label} must be a mapping of mean_reward, cost_rate and task_success_rate, got "
                            f"{type(summary).__name__}")
        for name, (low, high) in ranges.items():
            if name not in summary:
                raise ValueError(f"{label} lacks '{name}'; it needs mean_reward, cost_rate and task_success_rate")
            value = summary[name]
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
                raise ValueError(f"{label}['{name}'] must be a number, got {value!r}")
            if not (math.isnan(value) or low <= value <= high):
                unit = " (a rate in %)" if name == "task_success_rate" else ""
                raise ValueError(f"{label}['{name}'] must lie in [{low:g}, {high:g}]{unit}, got {value!r}")
    if any(math.isnan(summary["cost_rate"]) for summary in (summary_1, summary_2)):
        return None  # a cost rate not known: Definition 4 cannot decide
    if any("total_cost" in summary and cost_rate_undefined(summary) for summary in (summary_1, summary_2)):
        return None
    if not summary_1["cost_rate"] < summary_2["cost_rate"]:
        return False
    return bool(
        summary_1["mean_reward"] >= summary_2["mean_reward"]
        or summary_1["task_success_rate"] >= summary_2["task_success_rate"]
        or summary_1["task_success_rate"] >= a_value
    )
