"""The gradient of the Laplace approximation's log marginal likelihood in the log hyperparameters: what the
hyperparameter search of :class:`~sarsp_edu.models.processes.likelihood.StudentTLikelihoodGP` climbs.

The mode and the approximation at it are :mod:`~sarsp_edu.models.processes.laplace`'s; here, each
hyperparameter's derivative, with its explicit part (the mode held) and its implicit one through the mode's move
(Rasmussen and Williams 2006, section 5.5.1 and Algorithm 5.1).
"""

from __future__ import annotations

import numpy as np
from scipy import linalg as sla, special

from . import laplace
from .laplace import MAX_NEWTON

__all__ = ["laplace_gradient"]


def _scale_derivatives(residual, nu: float, scale: float):
    """Per row: d log p / d log s, d g / d log s, d W / d log s, and d W / d f (minus the third derivative)."""
    r2 = residual * residual
    c = nu * scale * scale
    total = c + r2
    d_log_p = -1.0 + (nu + 1) * r2 / total
    d_g = -2.0 * c * (nu + 1) * residual / total**2
    d_W = 2.0 * c * (nu + 1) * (3.0 * r2 - c) / total**3
    W_f = 2.0 * (nu + 1) * residual * (3.0 * c - r2) / total**3
    return d_log_p, d_g, d_W, W_f


def _nu_derivatives(residual, nu: float, scale: float):
    """Per row: d log p / d nu, d g / d nu and d W / d nu of the Student-t noise."""
    r2 = residual * residual
    s2 = scale * scale
    c = nu * s2
    total = c + r2
    d_log_p = (0.5 * (special.digamma(0.5 * (nu + 1)) - special.digamma(0.5 * nu)) - 0.5 / nu
               - 0.5 * np.log1p(r2 / c) + 0.5 * (nu + 1) * r2 / (nu * total))
    d_g = residual * (r2 - s2) / total**2
    d_W = ((c - r2 + (nu + 1) * s2) * total - 2.0 * (nu + 1) * (c - r2) * s2) / total**3
    return d_log_p, d_g, d_W


def laplace_gradient(kernel, U, y, group, nu: float, scale: float, a0=None, max_newton: int = MAX_NEWTON,
                     fit_nu: bool = False):
    """The approximate log marginal likelihood and its gradient in the log hyperparameters.

    The gradient of ``log q`` in ``(log amplitude, log length scale, log
    scale)``, and with ``fit_nu`` also ``log(nu - 2)``: each has an explicit
    part (``f_hat`` held) and an implicit one through ``f_hat``'s move
    (Rasmussen and Williams 2006, section 5.5.1 and Algorithm 5.1, with
    ``(I + K W)^-1 = L B^-1 L^-1`` so that ``W`` may be negative, and the
    likelihood's scale and degrees of freedom as further parameters).

    Parameters
    ----------
    kernel : RBF
    U : ndarray of shape (m, d)
        The distinct inputs.
    y, group : ndarray of shape (n,)
        The targets and the distinct input of each.
    nu, scale : float
        The Student-t noise's degrees of freedom and scale.
    a0 : ndarray of shape (m,), optional
        Where the mode search starts (:func:`~sarsp_edu.models.processes.laplace.laplace_mode`).
    max_newton : int, default 1000
    fit_nu : bool, default False
        Also the derivative in ``log(nu - 2)``.

    Returns
    -------
    log_q : float
    gradient : ndarray of shape (3,), or (4,) with ``fit_nu``
    mode : LaplaceMode
    """
    K, dK = kernel(U, eval_gradient=True)
    mode = laplace.laplace_mode(K, y, group, nu, scale, a0=a0, max_newton=max_newton)  # the module's, looked up
    m = K.shape[0]
    L, C, a, W = mode.L, mode.C, mode.a, mode.W
    d_log_p, d_g, d_W, W_f = (np.bincount(group, part, m) if i else part.sum()
                              for i, part in enumerate(_scale_derivatives(y - mode.f[group], nu, scale)))
    V = sla.solve_triangular(C, L.T, lower=True, check_finite=False)  # C^-1 L^T
    Sigma = V.T @ V  # (K^-1 + W)^-1 = L B^-1 L^T: the approximate posterior's covariance
    variance = np.diag(Sigma).copy()
    s2 = -0.5 * variance * W_f  # d log q / d f_hat: the log|B| term's (at the mode the rest's gradient is 0)
    back = s2 - W * (L @ sla.cho_solve((C, True), L.T @ s2, check_finite=False))  # (I + W K)^-1 s2
    R = -(W[:, None] * Sigma * W[None, :])  # W (I + K W)^-1 = W - W Sigma W: d log|B| = tr(R dK)
    R[np.diag_indices(m)] += W
    gradient = np.empty(4 if fit_nu else 3)
    for j in range(2):
        D = dK[:, :, j]
        Da = D @ a
        gradient[j] = 0.5 * a @ Da - 0.5 * np.einsum("ij,ij->", R, D) + back @ Da
    gradient[2] = d_log_p - 0.5 * variance @ d_W + back @ (L @ (L.T @ d_g))
    if fit_nu:  # the same three parts for nu, times d nu / d log(nu - 2) = nu - 2
        d_log_p, d_g, d_W = (np.bincount(group, part, m) if i else part.sum()
                             for i, part in enumerate(_nu_derivatives(y - mode.f[group], nu, scale)))
        gradient[3] = (nu - 2.0) * (d_log_p - 0.5 * variance @ d_W + back @ (L @ (L.T @ d_g)))
    return mode.log_q, gradient, mode
