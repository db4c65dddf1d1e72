"""The two hyperparameter searches: Adam (the paper's) and L-BFGS-B (to convergence).

Both minimise ``fun(theta) -> (value, gradient)`` over a box of log
hyperparameters and return ``(theta, trace, n_iter)``, ``trace`` holding the
objective's values along the way.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy import optimize

__all__ = ["RESTART_OFFSETS", "adam", "best_of_starts", "lbfgs", "projected_gradient_norm", "restart_points",
           "searcher"]


def adam(fun, theta0, bounds, learning_rate, n_steps, beta_1=0.9, beta_2=0.999, epsilon=1e-7, on_step=None):
    """Adam as TensorFlow/Keras implements it, projected onto ``bounds``.

    Returns the last iterate and the objective value at each step's start.

    Parameters
    ----------
    fun : callable
        ``fun(theta) -> (value, gradient)``, the objective to minimise.
    theta0 : array-like of shape (k,)
        The starting log hyperparameters.
    bounds : ndarray of shape (k, 2)
        Lower and upper bound of each; every step is clipped into them.
    learning_rate : float
        Adam's step size.
    n_steps : int
        The number of steps (no convergence test).
    beta_1, beta_2, epsilon : float, default 0.9, 0.999, 1e-7
        Adam's moment decay rates and its denominator's offset (Keras's defaults).
    on_step : callable, optional
        ``on_step()`` after each step (a progress bar's update); what it raises ends the search.

    Returns
    -------
    tuple
        ``(theta, trace, n_steps)``; ``trace`` ends with the value at the last iterate.
    """
    theta = np.array(theta0, dtype=float)
    m = np.zeros_like(theta)
    v = np.zeros_like(theta)
    trace = []
    for t in range(1, n_steps + 1):
        value, grad = fun(theta)
        trace.append(value)
        m += (grad - m) * (1.0 - beta_1)
        v += (grad * grad - v) * (1.0 - beta_2)
        step = learning_rate * math.sqrt(1.0 - beta_2**t) / (1.0 - beta_1**t)
        theta = np.clip(theta - step * m / (np.sqrt(v) + epsilon), bounds[:, 0], bounds[:, 1])
        if on_step is not None:
            on_step()
    trace.append(fun(theta)[0])
    return theta, trace, n_steps


def lbfgs(fun, theta0, bounds, max_iter, scale, on_step=None):
    """L-BFGS-B on ``fun / scale``.

    L-BFGS-B starts from an identity Hessian, so its first step is as long as
    the gradient; with a likelihood summed over hundreds of points that
    throws the search onto the corner of ``bounds`` (seen with the TP, whose
    likelihood is numerically flat there).  Dividing by the number of points
    leaves the optimum where it is and keeps the first step O(1) in log space.

    Parameters
    ----------
    fun : callable
        ``fun(theta) -> (value, gradient)``, the objective to minimise.
    theta0 : array-like of shape (k,)
        The starting log hyperparameters.
    bounds : sequence of (low, high) pairs
        The box searched.
    max_iter : int or None
        L-BFGS-B's ``maxiter``; None: scipy's default.
    scale : float
        The divisor of the objective and its gradient (the number of points).
    on_step : callable, optional
        ``on_step()`` after each iteration; what it raises ends the search.

    Returns
    -------
    tuple
        ``(theta, [start value, final value], iterations)``; a search that did not converge warns.
    """
    options = {} if max_iter is None else {"maxiter": max_iter}

    def scaled(theta):
        value, grad = fun(theta)
        return value / scale, grad / scale

    start = fun(theta0)[0]
    result = optimize.minimize(
        scaled, theta0, method="L-BFGS-B", jac=True, bounds=bounds, options=options,
        callback=None if on_step is None else lambda *_: on_step(),
    )
    if not result.success:
        warnings.warn(
            f"L-BFGS-B stopped before converging: {result.message}", RuntimeWarning, stacklevel=4
        )
    return result.x, [start, float(result.fun) * scale], int(result.nit)


#: the extra starts of a search with restarts, in order: (index of the log hyperparameter, offset from the first
#: start).  The indices are those every model shares, 0 the amplitude, 1 the length scale, 2 the noise (a GP's
#: and TP's log noise variance, the Student-t likelihood's log scale).  Narrow noise comes first: a short search
#: that starts at wide noise may never reach the regime where the outliers are discounted.  A second round
#: moves twice as far, a third three times.
RESTART_OFFSETS = ((2, -4.0), (2, 4.0), (1, -2.0), (1, 2.0), (0, -2.0), (0, 2.0))


def searcher(optimizer: str, fun, bounds, learning_rate: float, steps: int, max_iter, scale: float, on_step=None):
    """``search(theta0) -> (theta, trace, n_iter)``: the named optimiser's search from one start, minimising
    ``fun`` (``"adam"``: ``steps`` steps of ``learning_rate``; else L-BFGS-B with ``max_iter`` and ``scale``, as
    :func:`lbfgs`), for :func:`best_of_starts`.

    Parameters
    ----------
    optimizer : {"adam", "lbfgs"}
    fun : callable
        ``fun(theta) -> (value, gradient)``.
    bounds : ndarray of shape (k, 2)
    learning_rate : float
    steps : int
        Adam's steps.
    max_iter : int or None
        L-BFGS-B's ``maxiter``.
    scale : float
        L-BFGS-B's divisor of the objective (the number of points).
    on_step : callable, optional
        Called after each step of either search (:func:`adam`, :func:`lbfgs`).
    """
    if optimizer == "adam":
        return lambda start: adam(fun, start, bounds, learning_rate, steps, on_step=on_step)
    return lambda start: lbfgs(fun, start, bounds, max_iter, scale, on_step=on_step)


def restart_points(theta0, bounds, n_restarts: int) -> list:
    """The starts of a search with ``n_restarts`` restarts: ``theta0``, then one per :data:`RESTART_OFFSETS`
    (cycled; round r, from 0, moves by r + 1 times the offsets), each clipped into ``bounds``.

    Deterministic: a fit's restarts draw nothing from a random stream, so a run's random draws are the same with
    or without them.

    Parameters
    ----------
    theta0 : array-like of shape (k,)
        The first start (the constructor's log hyperparameters).
    bounds : ndarray of shape (k, 2)
    n_restarts : int
        Extra starts (0: ``theta0`` alone).
    """
    theta0 = np.asarray(theta0, dtype=float)
    starts = [theta0]
    for i in range(n_restarts):
        index, offset = RESTART_OFFSETS[i % len(RESTART_OFFSETS)]
        start = theta0.copy()
        start[index] += offset * (1 + i // len(RESTART_OFFSETS))
        starts.append(np.clip(start, bounds[:, 0], bounds[:, 1]))
    return starts


def best_of_starts(search, starts) -> tuple:
    """Run ``search(theta0) -> (theta, trace, n_iter)`` from each start; keep the lowest final value.

    Ties keep the earliest start, so that with one start the result is ``search(starts[0])``'s exactly.

    Parameters
    ----------
    search : callable
        ``search(theta0) -> (theta, trace, n_iter)``, ``trace[-1]`` the minimised objective's final value.
    starts : sequence of ndarray
        The starting points (:func:`restart_points`).

    Returns
    -------
    tuple
        ``(theta, trace, n_iter, finals)``: the best search's result and the final value of every start's search.
    """
    best, finals = None, []
    for start in starts:
        theta, trace, n_iter = search(start)
        finals.append(float(trace[-1]) if len(trace) else math.nan)
        if best is None or finals[-1] < best[1][-1]:
            best = (theta, trace, n_iter)
    return (*best, finals)


def projected_gradient_norm(gradient, theta, bounds, tolerance: float = 1e-3) -> float:
    """The gradient's Euclidean norm, a component left out where its hyperparameter rests on a bound (within
    ``tolerance`` in log space) and the gradient of the minimised objective points out of the box: what a search
    that ended there still had to go.

    Parameters
    ----------
    gradient : array-like of shape (k,)
        The minimised objective's gradient at ``theta``.
    theta : array-like of shape (k,)
    bounds : ndarray of shape (k, 2)
    """
    gradient = np.asarray(gradient, dtype=float).copy()
    theta = np.asarray(theta, dtype=float)
    at_low = (theta - bounds[:, 0] <= tolerance) & (gradient > 0)  # descent would go below the bound
    at_high = (bounds[:, 1] - theta <= tolerance) & (gradient < 0)
    gradient[at_low | at_high] = 0.0
    return float(np.linalg.norm(gradient))
