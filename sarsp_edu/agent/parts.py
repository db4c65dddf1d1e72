"""The parts of the agent's decision, as replaceable functions: :class:`SARSPAgent`'s plug-in point.

A decision of Algorithm 1 is assembled from six functions, the ones the
tutorials' exercises ask a student to write:

============  ===================================================  ==========
part          signature                                             exercise
============  ===================================================  ==========
kernel        ``kernel(X, Y, amplitude, length_scale) -> (n, m)``   2.1
posterior     ``posterior(K, K_star, k_star_star, y,                2.2
              noise_variance) -> (mean, latent_variance)``
tp_factor     ``tp_factor(K, y, noise_variance, nu) -> float``      2.3
safe_set      ``safe_set(mu_cost, var_cost, known_unsafe, d,        4.1
              variance_threshold) -> bool array``
choose        ``choose(mu_cost, var_cost, mu_reward, known_unsafe,  4.2
              d, variance_threshold) -> (action, backup)``
corrective    ``corrective(mu_cost, var_cost, action, d,            4.3
              was_backup) -> bool``
============  ===================================================  ==========

:class:`DecisionParts` holds them; its defaults are the package's own
functions, below.  Every prediction runs through one loop,
:meth:`ProcessRegressor.predict_batch`
(:mod:`~sarsp_edu.models.processes.conditioning`): a replaced kernel,
posterior or TP factor is called there in place of the model's own step
(:meth:`DecisionParts.conditioning_steps`), and a part left as the
package's is the model's fast implementation of it (with the kernel table),
bit for bit as without parts.  Each part is called with copies of its
inputs, so a part that changes its arguments in place cannot change the
agent's data, and its result is checked where it is used.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, fields

import numpy as np

from ..config import TAIL_DELTA
from ..models.kernels import squared_distances
from ..models.linalg import cholesky_with_jitter, solve_cholesky, solve_lower
from ..models.processes.conditioning import ConditioningSteps, beta_of
from ..models.processes.equations import tp_variance_factor
from .decision import choose_action, choose_with_backup, corrects, safe_actions

__all__ = [
    "DecisionParts",
    "corrective_applies",
    "decide",
    "gp_posterior",
    "model_parts_refusal",
    "predict_from_parts",
    "rbf",
    "tail_rule_refusal",
    "tp_factor",
]


def rbf(X, Y, amplitude, length_scale):
    """The RBF kernel matrix ``amplitude^2 exp(-|x - y|^2 / (2 length_scale^2))`` (:class:`~sarsp_edu.RBF`).

    Parameters
    ----------
    X : ndarray of shape (n, d)
    Y : ndarray of shape (m, d)
    amplitude, length_scale : float

    Returns
    -------
    ndarray of shape (n, m)

    Notes
    -----
    :class:`~sarsp_edu.RBF`'s formula, evaluated directly: ``RBF`` looks its
    values up in a table kept per kernel, which a fresh kernel per call
    would rebuild every time.
    """
    D2 = squared_distances(np.asarray(X, dtype=float), np.asarray(Y, dtype=float))
    return amplitude**2 * np.exp(D2 * (-0.5 / length_scale**2))


def gp_posterior(K, K_star, k_star_star, y, noise_variance):
    """The GP's posterior mean and latent variance at test points (paper eqs. 4-5; R&W Algorithm 2.1).

    Parameters
    ----------
    K : ndarray of shape (n, n)
        ``k(X, X)`` of the training inputs, without the noise.
    K_star : ndarray of shape (m, n)
        ``k(X*, X)``.
    k_star_star : ndarray of shape (m,)
        ``k(x*, x*)`` of each test point.
    y : ndarray of shape (n,)
    noise_variance : float

    Returns
    -------
    mean, variance : ndarray of shape (m,)
        The variance is the latent function's, without the noise.
    """
    L, _ = cholesky_with_jitter(np.asarray(K, dtype=float) + noise_variance * np.eye(len(y)))  # Alg. 2.1, line 2
    mean = K_star @ solve_cholesky(L, np.asarray(y, dtype=float))  # eq. 4; Alg. 2.1, lines 3-4
    V = solve_lower(L, np.asarray(K_star, dtype=float).T)  # Alg. 2.1, line 5
    return mean, k_star_star - np.einsum("ij,ij->j", V, V)  # eq. 5; Alg. 2.1, line 6


def tp_factor(K, y, noise_variance, nu):
    """The TP's factor ``(nu + beta - 2) / (nu + n - 2)`` on the latent variance, ``beta = y^T K_y^-1 y``.

    Paper eq. 6 with Shah et al.'s (2014) ``beta``, which uses the training
    covariance ``K_y = K + noise_variance I``.

    Parameters
    ----------
    K : ndarray of shape (n, n)
        ``k(X, X)`` of the training inputs, without the noise.
    y : ndarray of shape (n,)
        Training targets.
    noise_variance : float
        Added to the diagonal of ``K`` to form ``K_y``.
    nu : float
        The TP's degrees of freedom (greater than 2).

    Returns
    -------
    float
    """
    y = np.asarray(y, dtype=float)
    return tp_variance_factor(len(y), beta_of(np.asarray(K, dtype=float), y, noise_variance), nu)


#: the exercise in which the tutorials ask for each part
EXERCISE_OF = {"kernel": "2.1", "posterior": "2.2", "tp_factor": "2.3", "safe_set": "4.1", "choose": "4.2",
               "corrective": "4.3"}


@dataclass(frozen=True)
class DecisionParts:
    """The six functions a decision of Algorithm 1 is assembled from: ``SARSPAgent(..., parts=...)``.

    Each defaults to the package's own; replace any of them with a function
    of the same signature (the module's table; the tutorials' exercises 2.1
    to 4.3 ask for each).

    Attributes
    ----------
    kernel : callable
        ``kernel(X, Y, amplitude, length_scale)``: the kernel matrix of the
        rows of ``X`` against those of ``Y`` under a model's fitted kernel.
    posterior : callable
        ``posterior(K, K_star, k_star_star, y, noise_variance) -> (mean,
        latent_variance)`` of each query, from one strategic prior.
    tp_factor : callable
        ``tp_factor(K, y, noise_variance, nu)``: the TP's factor on the latent
        variance (used by a TP model only).
    safe_set : callable
        ``safe_set(mu_cost, var_cost, known_unsafe, d, variance_threshold)``:
        which of the four actions are safe (the decision's record, ``safe``).
    choose : callable
        ``choose(mu_cost, var_cost, mu_reward, known_unsafe, d,
        variance_threshold) -> (action, backup)``.
    corrective : callable
        ``corrective(mu_cost, var_cost, action, d, was_backup)``: whether a
        violation corrects the cost model's data.

    Examples
    --------
    >>> from sarsp_edu.agent.parts import DecisionParts
    >>> parts = DecisionParts(choose=lambda mu_cost, var_cost, mu_reward, known_unsafe, d, threshold: (0, True))
    >>> parts.replaced()
    ['choose']
    """

    kernel: Callable = rbf
    posterior: Callable = gp_posterior
    tp_factor: Callable = tp_factor
    safe_set: Callable = safe_actions
    choose: Callable = choose_with_backup
    corrective: Callable = corrects

    def __post_init__(self):
        for name in self.names():
            value = getattr(self, name)
            if not callable(value):
                raise TypeError(f"DecisionParts.{name} must be a function (exercise {EXERCISE_OF[name]}'s "
                                f"signature), got {type(value).__name__}")

    @classmethod
    def names(cls) -> list[str]:
        """The parts' names, in the order a decision uses them."""
        return [f.name for f in fields(cls)]

    @classmethod
    def of(cls, parts) -> "DecisionParts":
        """``parts`` as a DecisionParts: None gives the package's, a mapping names some parts (the rest the
        package's)."""
        if parts is None:
            return cls()
        if isinstance(parts, cls):
            return parts
        if isinstance(parts, Mapping):
            unknown = sorted(set(parts) - set(cls.names()))
            if unknown:
                raise ValueError(f"parts may name {cls.names()}, got {unknown}")
            return cls(**parts)
        raise TypeError(f"parts must be a DecisionParts, a mapping of some of {cls.names()} or None, "
                        f"got {type(parts).__name__}")

    def replaced(self) -> list[str]:
        """The names of the parts that are not the package's own."""
        return [name for name in self.names() if getattr(self, name) is not getattr(DecisionParts, name)]

    @property
    def package_models(self) -> bool:
        """Whether the kernel, posterior and TP factor are the package's (the models' own steps)."""
        return not self.conditioning_steps().replaced

    def conditioning_steps(self) -> ConditioningSteps:
        """The replaced kernel, posterior and TP factor, for the models' conditioning loop.

        A part that is the package's own is None there: the model runs its
        own fast implementation of that step (a table lookup for the kernel,
        one in-place factorisation for the posterior and the factor), the
        same numbers as the part computes, to rounding.
        """
        replaced = set(self.replaced())
        return ConditioningSteps(**{name: getattr(self, name) if name in replaced else None
                                    for name in ("kernel", "posterior", "tp_factor")})


def predict_from_parts(parts: DecisionParts, model, X_sets, y_sets, query_sets, include_noise: bool = False):
    """``model.predict_batch`` with the parts' kernel, posterior and TP factor plugged into its loop.

    Parameters
    ----------
    parts : DecisionParts
    model : GaussianProcess or StudentTProcess, fitted
        Gives the hyperparameters (amplitude, length scale, noise variance,
        ``nu_`` and the noise convention of a TP).
    X_sets, y_sets : sequences of B arrays of shapes (n_b, d) and (n_b,)
        The training rows of each strategic prior.
    query_sets : ndarray of shape (B, q, d)
    include_noise : bool, default False

    Returns
    -------
    mean, var : ndarray of shape (B, q)
    df : ndarray of shape (B,)
        As :meth:`~sarsp_edu.models.processes.regressor.ProcessRegressor.predict_batch`, which this is, with
        :meth:`DecisionParts.conditioning_steps` (the package's own parts are its own steps).
    """
    from ..models.processes import GaussianProcess, StudentTProcess

    if not isinstance(model, (GaussianProcess, StudentTProcess)):
        raise TypeError(f"an agent with its own parts predicts with a GaussianProcess or a StudentTProcess, got "
                        f"{type(model).__name__}")
    return model.predict_batch(X_sets, y_sets, query_sets, include_noise=include_noise,
                               steps=parts.conditioning_steps())


def _copies(*values):
    return [np.array(v, copy=True) if isinstance(v, np.ndarray) else v for v in values]


def decide(parts: DecisionParts, mu_cost, var_cost, mu_reward, known_unsafe, d: float, variance_threshold: float,
           tail=None, tail_delta: float = TAIL_DELTA):
    """``(action, safe, backup)`` of Algorithm 1's rule, from the parts' safe set and choice.

    With the package's two parts this is :func:`~sarsp_edu.agent.decision.choose_action`;
    otherwise each part is called with copies of its inputs and its result checked.  The tail rule
    (``tail`` given) is the package's alone: a student's parts take the variance rule's arguments.

    Parameters
    ----------
    parts : DecisionParts
        Gives the ``safe_set`` and ``choose`` parts.
    mu_cost, var_cost, mu_reward : ndarray of shape (n_actions,)
        Predicted cost signal (distance to the nearest unsafe state), its variance, and predicted reward.
    known_unsafe : ndarray of bool, shape (n_actions,)
        Actions in ``S_u``.
    d : float
        Safety distance.
    variance_threshold : float
        sigma*^2, the largest cost variance a safe action may have.
    tail : ndarray of shape (n_actions,), optional
        Each action's predictive probability of a distance below ``d``: the tail rule, with ``tail_delta``.

    Returns
    -------
    action : int
    safe : ndarray of bool, shape (n_actions,)
    backup : bool

    Raises
    ------
    ValueError
        If a replaced part returns something of the wrong shape or an action out of range, or the tail rule is
        asked of replaced parts.
    """
    if parts.safe_set is safe_actions and parts.choose is choose_with_backup:
        return choose_action(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold, tail, tail_delta)
    if tail is not None:
        raise ValueError(tail_rule_refusal(parts))
    n = len(mu_cost)
    flags = np.asarray(parts.safe_set(*_copies(mu_cost, var_cost, known_unsafe, d, variance_threshold)))
    if flags.shape != (n,) or not (flags.dtype == bool or np.isin(flags, (0, 1)).all()):
        raise ValueError(f"the safe_set part must return {n} booleans, one per action, got {flags!r}")
    chosen = parts.choose(*_copies(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold))
    if not isinstance(chosen, (tuple, list)) or len(chosen) != 2:
        raise ValueError(f"the choose part must return (action, backup), got {chosen!r}")
    action, backup = chosen
    try:
        number = float(action)
    except (TypeError, ValueError):
        number = math.nan
    if isinstance(action, (bool, np.bool_)) or not number.is_integer() or not 0 <= number < n:
        raise ValueError(f"the choose part must return an action number from 0 to {n - 1}, got {action!r}")
    return int(action), flags.astype(bool), bool(backup)


def tail_rule_refusal(parts: DecisionParts) -> str:
    """The message that refuses the tail rule to an agent whose safe set or choice is a student's."""
    mine = [name for name in ("safe_set", "choose") if name in parts.replaced()]
    return (f"safe_rule='tail' cannot use the replaced parts {mine}: they take the variance rule's arguments "
            "(var_cost, variance_threshold); use safe_rule='variance' with them, or the package's own parts")


def model_parts_refusal(parts: DecisionParts, cost_model, reward_model) -> str | None:
    """The message that refuses a replaced kernel, posterior or TP factor to a GP with Student-t noise (whose
    predictions come from its own Laplace approximation, which no part enters), or None where all can be used.

    Parameters
    ----------
    parts : DecisionParts
    cost_model, reward_model : estimator
        The agent's two models.
    """
    from ..models.processes.likelihood import StudentTLikelihoodGP

    unusable = sorted({"kernel", "posterior", "tp_factor"} & set(parts.replaced()))
    robust = [role for role, model in (("cost", cost_model), ("reward", reward_model))
              if isinstance(model, StudentTLikelihoodGP)]
    if not (unusable and robust):
        return None
    setting = " and ".join({"cost": "model", "reward": "reward_model"}[role] + "='t-likelihood'" for role in robust)
    return (f"the {' and the '.join(robust)} model {'is a' if len(robust) == 1 else 'are'} GP with Student-t noise "
            f"({setting}), which cannot use the replaced parts {unusable}: its predictions come from its own Laplace "
            "approximation; use the package's kernel, posterior and tp_factor with it, or make it 'tp' or 'gp'")


def corrective_applies(parts: DecisionParts, mu_cost, var_cost, action: int, d: float, was_backup: bool) -> bool:
    """Whether the corrective update applies, by the parts' corrective test.

    Parameters
    ----------
    parts : DecisionParts
        Gives the ``corrective`` part (called with copies of its inputs).
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
    if parts.corrective is corrects:
        return corrects(mu_cost, var_cost, action, d, was_backup)
    return bool(parts.corrective(*_copies(mu_cost, var_cost, action, d, was_backup)))
