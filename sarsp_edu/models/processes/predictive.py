"""The probability a predictive distribution gives to a value below a threshold: what the tail safety rule reads.

Each model's own predictive: a Gaussian for the GP; for the TP a Student-t
with the predictive's degrees of freedom and variance (as the reference
code's sampler draws it, also where the ``"tfp"`` noise convention adds the
noise unscaled); for the GP with Student-t noise, the Laplace approximation's
Gaussian latent value plus the Student-t noise, integrated over the latent
value (its latent predictive alone is Gaussian): by Gauss-Hermite quadrature
where the noise is the wider (the integrand is smooth on the latent value's
scale), else adaptively on either side of the threshold, where the noise
makes a step of its own width.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import integrate, special, stats

__all__ = ["HERMITE_NODES", "probability_below", "sample_moments"]

#: Gauss-Hermite nodes of the latent value's integral (as ``StudentTLikelihoodGP.predictive_density``)
HERMITE_NODES = 60


def probability_below(threshold: float, mean, var, df=math.inf, noise=None) -> np.ndarray:
    """``P(Y < threshold)`` under each predictive distribution.

    Parameters
    ----------
    threshold : float
        The value (the safety distance ``d``).
    mean, var : array-like
        The predictive's mean and variance (the latent value's where ``noise`` is given).
    df : float or array-like, default inf
        Degrees of freedom: ``inf`` for a Gaussian; finite (> 2) for a Student-t of variance ``var``.
    noise : (nu, scale), optional
        Student-t noise added to a Gaussian latent value ``N(mean, var)`` (a GP with Student-t noise): the
        probability is ``E_f[T_nu((threshold - f) / scale)]``.

    Returns
    -------
    ndarray
        Shaped as ``mean``.  Where ``var`` is 0 the predictive is a point: 1 below the threshold, else 0; where
        the mean or the variance is NaN, NaN (a rule comparing it with delta calls the action unsafe).
    """
    mean, var = np.asarray(mean, dtype=float), np.asarray(var, dtype=float)
    unknown = np.isnan(mean) | np.isnan(var)  # NaN, so that no rule calls such an action safe
    sd = np.sqrt(np.maximum(np.where(unknown, 1.0, var), 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        if noise is not None:
            return np.where(unknown, np.nan, _with_student_t_noise(threshold, np.where(unknown, 0.0, mean), sd, *noise))
        df = np.broadcast_to(np.asarray(df, dtype=float), mean.shape)
        z = np.where(sd > 0, (threshold - mean) / np.where(sd > 0, sd, 1.0), np.where(mean < threshold, np.inf,
                                                                                    -np.inf))
        heavy = np.isfinite(df)
        out = stats.norm.cdf(z)
        if heavy.any():  # a Student-t of variance var: scale sd sqrt((df - 2) / df)
            out = np.where(heavy, stats.t.cdf(z * np.sqrt(np.where(heavy, df / (df - 2.0), 1.0)),
                                              np.where(heavy, df, 3.0)), out)
        return np.where(unknown, np.nan, out)


def _with_student_t_noise(threshold: float, mean, sd, nu: float, scale: float) -> np.ndarray:
    """``P(f + e < threshold)`` for ``f ~ N(mean, sd^2)`` and ``e`` Student-t (``nu``, ``scale``), to about 1e-10."""
    nodes, weights = np.polynomial.hermite_e.hermegauss(HERMITE_NODES)  # weight exp(-z^2 / 2)
    norm = math.sqrt(2.0 * math.pi)
    out = special.stdtr(nu, (threshold - (mean[..., None] + sd[..., None] * nodes)) / scale) @ weights / norm
    for index in zip(*np.nonzero(sd > scale)):  # the latent value the wider: T_nu steps within its spread

        def integrand(z, m=float(mean[index]), s=float(sd[index])):
            return math.exp(-0.5 * z * z) / norm * special.stdtr(nu, (threshold - m - s * z) / scale)

        step = (threshold - float(mean[index])) / float(sd[index])
        out[index] = (integrate.quad(integrand, -np.inf, step, epsabs=1e-12)[0]
                      + integrate.quad(integrand, step, np.inf, epsabs=1e-12)[0])
    return out


def sample_moments(mean, var, df, n_samples: int, rng) -> tuple[np.ndarray, np.ndarray]:
    """Sample mean and variance of ``n_samples`` draws from each predictive distribution.

    The reference code's estimate (an agent's ``predictive="sample"``): normal
    draws for the GP; for the TP a Student-t with ``df`` degrees of freedom and
    variance ``var``, ``mean + sqrt(var (df - 2) / W) z`` with ``W ~ chi2(df)``.

    Parameters
    ----------
    mean, var, df : ndarray of shape (m,)
        Each predictive's mean, variance and degrees of freedom (inf: a normal).
    n_samples : int
    rng : numpy.random.Generator
        Draws the normals, then the chi-squares of the heavy-tailed rows.

    Returns
    -------
    mean, var : ndarray of shape (m,)
        The draws' mean and unbiased variance.
    """
    z = rng.standard_normal((mean.shape[0], n_samples))
    scale = np.sqrt(var)[:, None]
    heavy = np.isfinite(df)
    if heavy.any():
        chi2 = rng.chisquare(df[heavy][:, None], size=(int(heavy.sum()), n_samples))
        scale = np.broadcast_to(scale, z.shape).copy()
        scale[heavy] *= np.sqrt((df[heavy][:, None] - 2.0) / chi2)
    draws = mean[:, None] + scale * z
    return draws.mean(axis=1), draws.var(axis=1, ddof=1)
