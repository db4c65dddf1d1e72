"""The two hyperparameter searches: Adam (the paper's) and L-BFGS-B (to convergence).

Both minimise ``fun(theta) -> (value, gradient)`` over a box of log
hyperparameters and return ``(theta, trace, n_iter)``, ``trace`` holding the
objective's values along the way.
"""

from __future__ import annotations

import contextlib
import contextvars
import math
import warnings

import numpy as np
from scipy import optimize

__all__ = ["adam", "lbfgs", "reporting_steps"]

#: called after each step of a search (a progress bar's update), where :func:`reporting_steps` sets one
_STEP_HOOK: contextvars.ContextVar = contextvars.ContextVar("sarsp_edu_step_hook", default=None)


@contextlib.contextmanager
def reporting_steps(callback):
    """Within the block, every step of a search in this thread calls ``callback()`` (to show progress)."""
    token = _STEP_HOOK.set(callback)
    try:
        yield
    finally:
        _STEP_HOOK.reset(token)


def _stepped() -> None:
    hook = _STEP_HOOK.get()
    if hook is not None:
        hook()


def adam(fun, theta0, bounds, learning_rate, n_steps, beta_1=0.9, beta_2=0.999, epsilon=1e-7):
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
        _stepped()
    trace.append(fun(theta)[0])
    return theta, trace, n_steps


def lbfgs(fun, theta0, bounds, max_iter, scale):
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
        callback=lambda *_: _stepped(),
    )
    if not result.success:
        warnings.warn(
            f"L-BFGS-B stopped before converging: {result.message}", RuntimeWarning, stacklevel=4
        )
    return result.x, [start, float(result.fun) * scale], int(result.nit)
