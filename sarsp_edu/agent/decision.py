"""Algorithm 1's decision rule and the records of what the agent decided and learned.

:func:`choose_action` is the rule as a pure function of the per-action
predictions (the exercises grade against it); :func:`safe_actions`,
:func:`choose_with_backup` and :func:`corrects` are its parts as the
exercises ask for them, the defaults of :class:`~sarsp_edu.agent.parts.DecisionParts`;
:class:`Decision` and :class:`LearnOutcome` are what
:class:`~sarsp_edu.agent.sarsp.SARSPAgent`'s ``act`` and ``learn`` return.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..config import TAIL_DELTA

__all__ = ["Decision", "LearnOutcome", "choose_action", "choose_with_backup", "corrects", "override_known_unsafe",
           "pick", "safe_actions"]


@dataclass
class Decision:
    """Why ``act`` chose its action: the per-action predictions and the rule applied.

    Arrays have one entry per action (RIGHT, DOWN, LEFT, UP).

    Attributes
    ----------
    position : tuple of int
        The agent's cell ``(x, y)``.
    mu_cost, var_cost : ndarray of shape (4,)
        Predicted cost signal (distance to the nearest unsafe state) and its
        predictive variance, *before* the ``S_u`` override.
    mu_reward, var_reward : ndarray of shape (4,)
        Predicted reward and its variance.
    known_unsafe : ndarray of bool, shape (4,)
        Actions in ``S_u`` from this cell (overridden to cost -inf, variance
        +inf, reward -inf).
    safe : ndarray of bool, shape (4,)
        Actions that passed the safety test.
    action : int
    backup : bool
        True when no action was safe and the backup rule chose.
    prior_size : tuple of ndarray
        Rows in each action's cost and reward prior, two arrays of shape (4,)
        (with ``prior_draw="per_step"`` the four entries are those of the
        one shared prior).
    tail : ndarray of shape (4,) or None
        With ``safe_rule="tail"``: the cost model's predictive probability of a
        distance below ``d`` after each action (None under the variance rule).
    """

    position: tuple
    mu_cost: np.ndarray
    var_cost: np.ndarray
    mu_reward: np.ndarray
    var_reward: np.ndarray
    known_unsafe: np.ndarray
    safe: np.ndarray
    action: int
    backup: bool
    prior_size: tuple = (0, 0)
    tail: np.ndarray | None = None

    @property
    def scores(self) -> dict:
        """The values the decision rule saw, after the ``S_u`` override."""
        mu_cost, var_cost, mu_reward = override_known_unsafe(
            self.mu_cost, self.var_cost, self.mu_reward, self.known_unsafe)
        return {"mu_cost": mu_cost, "var_cost": var_cost, "mu_reward": mu_reward}


@dataclass
class LearnOutcome:
    """What ``learn`` did after one step."""

    violation: bool = False
    added_to_unsafe: bool = False
    corrected: bool = False
    buffer_update: str | None = None  # "overwritten", "added" or "unchanged"
    retrained: bool = False
    retrain_seconds: float = 0.0


def override_known_unsafe(mu_cost, var_cost, mu_reward, known_unsafe):
    """Algorithm 1's ``S_u`` override: known-unsafe actions get cost -inf, variance +inf, reward -inf.

    Parameters
    ----------
    mu_cost, var_cost, mu_reward : ndarray of shape (n_actions,)
        Predicted cost signal (distance to the nearest unsafe state), its variance, and predicted reward.
    known_unsafe : ndarray of bool, shape (n_actions,)
        Actions in ``S_u`` from this cell.

    Returns
    -------
    mu_cost, var_cost, mu_reward : ndarray of shape (n_actions,)
        New arrays, the known-unsafe entries replaced; the inputs are not modified.
    """
    return (np.where(known_unsafe, -np.inf, mu_cost), np.where(known_unsafe, np.inf, var_cost),
            np.where(known_unsafe, -np.inf, mu_reward))


def choose_action(mu_cost, var_cost, mu_reward, known_unsafe, d: float, variance_threshold: float, tail=None,
                  tail_delta: float = TAIL_DELTA):
    """The decision rule of Algorithm 1 on given predictions (a pure function).

    Parameters
    ----------
    mu_cost, var_cost, mu_reward : ndarray of shape (n_actions,)
    known_unsafe : ndarray of bool, shape (n_actions,)
        Pairs in ``S_u``: their cost becomes -inf, variance +inf, reward -inf.
    d, variance_threshold : float
    tail : ndarray of shape (n_actions,), optional
        The tail rule's input: each action's predictive probability of a
        distance below ``d``.  Given, an action is safe when it is not known
        unsafe and that probability is at most ``tail_delta`` (``var_cost``
        and ``variance_threshold`` are then not read); None: the paper's
        variance rule.
    tail_delta : float, default 0.05

    Returns
    -------
    action : int
    safe : ndarray of bool
    backup : bool

    Notes
    -----
    Ties go to the lowest action number: the paper's loop replaces its
    candidate only on a strictly higher reward.  If every action is known
    unsafe, every reward is -inf and the backup takes action 0.
    """
    mu_cost, var_cost, mu_reward = override_known_unsafe(mu_cost, var_cost, mu_reward, known_unsafe)
    if tail is None:
        safe = (var_cost <= variance_threshold) & (mu_cost >= d)
    else:
        safe = ~np.asarray(known_unsafe, dtype=bool) & (np.asarray(tail) <= tail_delta)
    action, backup = pick(safe, mu_reward)
    return action, safe, backup


def pick(safe, mu_reward) -> tuple[int, bool]:
    """``(action, backup)`` from a safe set: the safe action of highest predicted reward, else the backup (the
    highest predicted reward of all); ties to the lowest action number.

    Parameters
    ----------
    safe : ndarray of bool, shape (n_actions,)
    mu_reward : ndarray of shape (n_actions,)
        Predicted reward, -inf for the actions known unsafe (:func:`override_known_unsafe`).
    """
    if safe.any():
        return int(np.argmax(np.where(safe, mu_reward, -np.inf))), False
    return int(np.argmax(mu_reward)), True


def safe_actions(mu_cost, var_cost, known_unsafe, d: float, variance_threshold: float) -> np.ndarray:
    """Algorithm 1's safe set: not known unsafe, variance at most sigma*^2, predicted distance at least d.

    Parameters
    ----------
    mu_cost, var_cost : ndarray of shape (n_actions,)
        Predicted cost signal (distance to the nearest unsafe state) and its variance.
    known_unsafe : ndarray of bool, shape (n_actions,)
        Actions in ``S_u``: never safe.
    d : float
        Safety distance: the least predicted distance an action may have.
    variance_threshold : float
        sigma*^2, the largest cost variance an action may have (inclusive).

    Returns
    -------
    ndarray of bool, shape (n_actions,)
        The ``safe`` of :func:`choose_action`.
    """
    return choose_action(mu_cost, var_cost, np.zeros(np.shape(mu_cost)), known_unsafe, d, variance_threshold)[1]


def choose_with_backup(mu_cost, var_cost, mu_reward, known_unsafe, d: float, variance_threshold: float):
    """Algorithm 1's choice as ``(action, backup)``: :func:`choose_action` without its safe set.

    Parameters
    ----------
    mu_cost, var_cost, mu_reward : ndarray of shape (n_actions,)
        Predicted cost signal, its variance, and predicted reward.
    known_unsafe : ndarray of bool, shape (n_actions,)
        Actions in ``S_u``.
    d, variance_threshold : float
        As in :func:`safe_actions`.

    Returns
    -------
    action : int
    backup : bool
        True when no action was safe and the backup (highest predicted reward) chose.
    """
    action, _, backup = choose_action(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold)
    return action, backup


def corrects(mu_cost, var_cost, action: int, d: float, was_backup: bool) -> bool:
    """Whether a violation corrects the cost model's data (the reference code's condition).

    After a step that violated the constraint, with the cost model's
    re-predicted ``mu_cost`` and ``var_cost`` of the four actions: the model
    called the action taken safe (a predicted distance of at least ``d``,
    whatever its variance), or the action was its most certain one (every
    action tied for the lowest variance counts) and not taken as the backup.
    The reference code's precedence reads ``cost >= d or (variance ==
    min(variances) and not backup)``.

    Parameters
    ----------
    mu_cost, var_cost : ndarray of shape (n_actions,)
        The cost model's re-predicted distance and variance of each action.
    action : int
        The action taken.
    d : float
        Safety distance.
    was_backup : bool
        Whether the action was chosen by the backup rule.

    Returns
    -------
    bool
    """
    model_said_safe = mu_cost[action] >= d
    lowest_variance = var_cost[action] <= np.min(var_cost) and not was_backup
    return bool(model_said_safe or lowest_variance)
