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
