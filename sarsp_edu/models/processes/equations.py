"""The equations where the TP differs from the GP, one function each.

The models call them with the sufficient statistics of their training data:
``n``, ``beta = y^T K^-1 y`` and ``log|K|``.  Each is a line of the table in
:mod:`sarsp_edu.models.processes`.
"""

from __future__ import annotations

import math

from scipy import special

__all__ = [
    "gp_log_marginal_likelihood", "tp_log_marginal_likelihood", "tp_likelihood_weight",
    "tp_log_marginal_likelihood_dnu", "tp_variance_factor", "tp_predictive_variance",
]

LOG_2PI = math.log(2.0 * math.pi)


def gp_log_marginal_likelihood(n: int, beta: float, log_det: float) -> float:
    """GP: ``log N(y; 0, K) = -beta/2 - log|K|/2 - n/2 log(2 pi)`` (Rasmussen & Williams eq. 2.30).

    Parameters
    ----------
    n : int
        The number of training points.
    beta : float
        ``y^T K^-1 y``.
    log_det : float
        ``log|K|``.
    """
    return -0.5 * beta - 0.5 * log_det - 0.5 * n * LOG_2PI


def tp_log_marginal_likelihood(n: int, beta: float, log_det: float, nu: float) -> float:
    """TP: the multivariate t density of y with ``nu`` dof and covariance ``K`` (Shah et al. 2014, eq. 3).

    ``-n/2 log((nu-2) pi) - log|K|/2 + log G((nu+n)/2) - log G(nu/2)
    - (nu+n)/2 log(1 + beta/(nu-2))``.

    Parameters
    ----------
    n : int
        The number of training points.
    beta : float
        ``y^T K^-1 y``.
    log_det : float
        ``log|K|``.
    nu : float
        The degrees of freedom, above 2.
    """
    return float(
        -0.5 * n * math.log((nu - 2.0) * math.pi)
        - 0.5 * log_det
        + special.gammaln(0.5 * (nu + n))
        - special.gammaln(0.5 * nu)
        - 0.5 * (nu + n) * math.log1p(beta / (nu - 2.0))
    )


def tp_likelihood_weight(n: int, beta: float, nu: float) -> float:
    """The weight ``w = (nu + n) / (nu - 2 + beta)`` on ``alpha alpha^T`` in the TP's gradient (the GP's is 1).

    Both models' gradients with respect to a kernel hyperparameter ``t`` are
    ``0.5 tr((w alpha alpha^T - K^-1) dK/dt)``, ``alpha = K^-1 y``.

    Parameters
    ----------
    n : int
        The number of training points.
    beta : float
        ``y^T K^-1 y``.
    nu : float
        The degrees of freedom, above 2.
    """
    return (nu + n) / (nu - 2.0 + beta)


def tp_log_marginal_likelihood_dnu(n: int, beta: float, nu: float) -> float:
    """d/d nu of :func:`tp_log_marginal_likelihood`.

    Parameters
    ----------
    n : int
        The number of training points.
    beta : float
        ``y^T K^-1 y``.
    nu : float
        The degrees of freedom, above 2.
    """
    return (
        -0.5 * n / (nu - 2.0)
        + 0.5 * special.digamma(0.5 * (nu + n))
        - 0.5 * special.digamma(0.5 * nu)
        - 0.5 * math.log1p(beta / (nu - 2.0))
        + 0.5 * (nu + n) * beta / ((nu - 2.0) * (nu - 2.0 + beta))
    )


def tp_variance_factor(n: int, beta: float, nu: float) -> float:
    """``(nu + beta - 2) / (nu + n - 2)``: the TP's factor on the GP's predictive variance.

    Paper eq. 6 with Shah et al.'s ``beta``, which uses the *training*
    covariance.  It exceeds 1 exactly when ``beta > n``; under the model
    ``E[beta] = n``.

    Parameters
    ----------
    n : int
        The number of training points.
    beta : float
        ``y^T K^-1 y``.
    nu : float
        The degrees of freedom, above 2.
    """
    return (nu + beta - 2.0) / (nu + n - 2.0)


def tp_predictive_variance(latent, factor: float, noise, convention: str):
    """The TP's predictive variance from the GP's latent variance and the noise.

    ``"shah"``: ``factor * (latent + noise)``, the noise is part of the
    process (Shah et al. 2014); ``"tfp"``: ``factor * latent + noise``
    (TensorFlow Probability, which the paper's reference code used).

    Parameters
    ----------
    latent : float or ndarray
        The GP's predictive variance of the latent function.
    factor : float
        :func:`tp_variance_factor`.
    noise : float or ndarray
        The observation noise variance.
    convention : {"shah", "tfp"}
        Where the noise enters (any value but ``"shah"`` is taken as ``"tfp"``).
    """
    if convention == "shah":
        return factor * (latent + noise)
    return factor * latent + noise
