"""The Laplace approximation of a GP with Student-t noise: the posterior mode, the marginal likelihood, predictions.

Rows with equal inputs share one latent value, so the latent function lives
on the *distinct* inputs and each row adds its own log likelihood:
``log p(y | f) = sum_r log t(y_r | f_g(r))``, whose gradient and curvature
per distinct input are sums over its rows.  This is exact (the GP prior of
two equal inputs is one value), and it keeps the prior's kernel matrix
positive definite where the rows repeat.

The mode is found by Newton steps with a line search, and where the log
posterior is not concave by EM steps (the Student-t as a scale mixture of
Gaussians: each step is a GP's mean with the rows weighted by
``(nu + 1) / (nu s^2 + r^2)``, and never lowers the log posterior), the
approximate posterior's covariance is ``(K^-1 + W)^-1 = L B^-1 L^T`` with
``K = L L^T`` and ``B = I + L^T W L`` (Rasmussen and Williams 2006, ch. 3,
changed where ``W`` is negative: see
:class:`~sarsp_edu.models.processes.likelihood.StudentTLikelihoodGP`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import linalg as sla, special
from scipy.linalg import lapack

from ..linalg import cholesky_with_jitter, distinct_rows

__all__ = ["ANSWER_PATIENCE", "MAX_NEWTON", "SADDLE_ESCAPES", "LaplaceMode", "answering_mode", "laplace_mode",
           "laplace_predict", "laplace_predict_batch", "noise_variance", "student_t_log_likelihood"]


#: the steps a mode search may take: most take under 20; a prior of the agent's cost data, most of whose rows
#: start as outliers to a noise scale of 0.006 (the paper-size fit's), took 182, nearly all of them EM steps
MAX_NEWTON = 1000

#: how many times ``max_newton`` steps a search that must answer may take (a prediction's, the fitted model's
#: mode): a decision cannot turn back, as the hyperparameter search does.  A prior of the agent's cost data at
#: (40, 0.3, 10) seed 0, 32 of its 101 rows outliers, took 1,068 EM steps (0.3 s)
ANSWER_PATIENCE = 20

#: the saddles a search that must answer may leave (:func:`answering_mode`): a prior of the agent's cost
#: data at (40, 0.3, 10) seed 0 stopped the three-model sweep on one (two outliers on either side of a clean row,
#: both latent values halfway to their outliers); one escape took its search to a maximum
SADDLE_ESCAPES = 10


def student_t_log_likelihood(residual, nu: float, scale: float):
    """``log p(y | f)`` of the Student-t noise, its first derivative in ``f`` and ``W`` (minus the second).

    Returns three arrays shaped as ``residual = y - f``.

    Parameters
    ----------
    residual : ndarray
        ``y - f``.
    nu : float
        The noise's degrees of freedom (> 0).
    scale : float
        The noise's scale ``s`` (> 0).
    """
    r2 = residual * residual
    nus2 = nu * scale * scale
    value = (special.gammaln(0.5 * (nu + 1)) - special.gammaln(0.5 * nu) - 0.5 * math.log(math.pi * nus2)
             - 0.5 * (nu + 1) * np.log1p(r2 / nus2))
    gradient = (nu + 1) * residual / (nus2 + r2)
    W = (nu + 1) * (nus2 - r2) / (nus2 + r2) ** 2
    return value, gradient, W


def noise_variance(nu: float, scale: float) -> float:
    """The Student-t noise's variance, ``s^2 nu / (nu - 2)`` (refused for ``nu <= 2``, where it is infinite).

    Parameters
    ----------
    nu, scale : float
        The noise's degrees of freedom and scale.
    """
    if nu <= 2:
        raise ValueError(f"the noise has no finite variance with nu={nu} <= 2; use include_noise=False")
    return scale * scale * nu / (nu - 2.0)


def _factor(A):
    """The lower Cholesky factor of ``I + A`` (A overwritten), or None where it is not positive definite."""
    A.flat[:: A.shape[0] + 1] += 1.0
    C, info = lapack.dpotrf(A, lower=1, clean=1, overwrite_a=1)
    return C if info == 0 else None


def _solve(C, b):
    """``(C C^T)^-1 b`` for a lower Cholesky factor ``C``."""
    return lapack.dpotrs(C, b, lower=1)[0]


def _newton_factor(K, L, W):
    """The factor of Newton's ``B`` at ``W`` (None where the log posterior is not concave), with the map that
    takes ``b`` to ``W L b`` (``transpose``: ``L^T b``) in the form it was factored in.

    All ``W >= 0``: ``B = I + W^1/2 K W^1/2``, O(m^2) to build (Rasmussen and Williams, Algorithm 3.1);
    otherwise ``B = I + L^T W L``, whose inertia says whether ``K^-1 + W`` is positive definite (a
    non-positive diagonal entry, ``1 + sum_k W_k L_ki^2``, says it is not before B is built).
    """
    if W.min() >= 0.0:  # (I + W K)^-1 b = b - W^1/2 B^-1 W^1/2 K b
        w = np.sqrt(W)

        def through_w(b, transpose=False):
            return w * (K @ b) if transpose else w * b

        return _factor(w[:, None] * K * w[None, :]), through_w
    if np.any(1.0 + (L * L).T @ W <= 0.0):  # a diagonal entry of B is not positive: not concave, said in O(m^2)
        return None, None
    WL = W[:, None] * L  # (I + W K)^-1 b = b - W L B^-1 L^T b

    def through_L(b, transpose=False):
        return L.T @ b if transpose else WL @ b

    return _factor(L.T @ WL), through_L


@dataclass
class LaplaceMode:
    """The Laplace approximation at the posterior mode, on the distinct inputs.

    Attributes
    ----------
    f : ndarray of shape (m,)
        The mode of the latent function at the distinct inputs.
    a : ndarray of shape (m,)
        ``K^-1 f``: the predictive mean at ``x*`` is ``k(x*, U) a``.
    W : ndarray of shape (m,)
        Minus the log likelihood's second derivative at the mode, summed over each input's rows.
    L, C : ndarray of shape (m, m)
        Lower Cholesky factors of ``K`` (with any jitter it needed) and of ``B = I + L^T W L``.
    log_q : float
        The approximate log marginal likelihood ``-a^T f / 2 + log p(y | f) - log|B| / 2``.
    steps : int
        Steps of the search (Newton and EM), the last one tried included; a step off a saddle is not one.
    """

    f: np.ndarray
    a: np.ndarray
    W: np.ndarray
    L: np.ndarray
    C: np.ndarray
    log_q: float
    steps: int


def laplace_mode(K, y, group, nu: float, scale: float, a0=None, max_newton: int = MAX_NEWTON,
                 escapes: int = 0) -> LaplaceMode:
    """The posterior mode and the Laplace approximation at it.

    Parameters
    ----------
    K : ndarray of shape (m, m)
        The prior's kernel matrix of the distinct inputs.
    y : ndarray of shape (n,)
        The targets.
    group : ndarray of int, shape (n,)
        The distinct input of each target (``0 <= group < m``).
    nu, scale : float
        The Student-t noise's degrees of freedom and scale.
    a0 : ndarray of shape (m,), optional
        A starting point ``K^-1 f`` (a nearby mode: fewer steps); default the prior mean, 0.
    max_newton : int, default 1000
        Steps allowed (:data:`MAX_NEWTON`).
    escapes : int, default 0
        How many times the search may leave a point where it stopped that is no maximum.  The log posterior
        is not concave where ``W`` is negative, and the EM steps can stop on a saddle (where ``K^-1 + W`` is
        not positive definite): the search then steps off it where the log posterior curves upwards, to one
        of the maxima on either side (:func:`_leave_saddle` says which), and goes on.  0 raises there
        instead, as the hyperparameter search wants: it turns back from such a point, and its stored fits
        were made so.

    Raises
    ------
    RuntimeError
        If the mode is not found in ``max_newton`` steps, or the approximation has no maximum where the
        search stopped (after ``escapes`` escapes).
    """
    if escapes < 0:
        raise ValueError(f"escapes must be >= 0 (the saddles the search may leave), got escapes={escapes}")
    m = K.shape[0]
    L, jitter = cholesky_with_jitter(K)
    if jitter:  # the matrix whose factor is L, so that the two agree
        K = K.copy()
        K.flat[:: m + 1] += jitter
    # subnormal numbers (below 2.2e-308: a long length scale's factor has them) make every product with L
    # several times slower; as zeros they change nothing a float64 result can hold
    L[np.abs(L) < np.finfo(float).tiny] = 0.0

    def at(f):  # the rows' log likelihoods, and the gradient and W summed per distinct input
        value, gradient, W = student_t_log_likelihood(y - f[group], nu, scale)
        return value.sum(), np.bincount(group, gradient, m), np.bincount(group, W, m)

    a = np.zeros(m) if a0 is None else np.array(a0, dtype=float)
    state = _state(K, at, a)
    step, escaped = 0, 0
    while True:
        try:
            a, f, psi, log_lik, g, W, step = _ascend(K, L, at, y, group, nu, scale, state, step, max_newton)
        except RuntimeError as exc:  # out of steps: say so, and where it had been
            if not escaped:
                raise
            raise RuntimeError(f"{exc} (it left {escaped} saddle{'s' if escaped > 1 else ''} of the log posterior "
                               "on the way)") from exc
        C = _factor(L.T @ (W[:, None] * L))  # B = I + L^T W L: K^-1 + W = L^-T B L^-1
        if C is not None or escaped >= escapes:
            break
        state = _leave_saddle(K, L, at, a, psi, g, W)
        if state is None:
            break
        escaped += 1
    if C is None:
        raise RuntimeError("the Laplace approximation has no maximum here (K^-1 + W is not positive definite "
                           f"where the search stopped, {escaped} of escapes={escapes} saddles left before); try a "
                           "larger scale")
    log_q = float(-0.5 * a @ f + log_lik - np.log(np.diag(C)).sum())
    return LaplaceMode(f, a, W, L, C, log_q, step)


def _state(K, at, a):
    """The search's state at ``a = K^-1 f``: ``(a, f, psi, log_lik, g, W)``, psi the log posterior (up to a
    constant) and ``g, W`` the likelihood's gradient and curvature per distinct input."""
    f = K @ a
    log_lik, g, W = at(f)
    return a, f, log_lik - 0.5 * a @ f, log_lik, g, W


def _ascend(K, L, at, y, group, nu, scale, state, step, max_newton):
    """:func:`laplace_mode`'s search from ``state = (a, f, psi, log_lik, g, W)`` after ``step`` steps, to where
    no step raises the log posterior; returns the state there and the steps taken in all."""
    a, f, psi, log_lik, g, W = state
    m = K.shape[0]
    for step in range(step + 1, max_newton + 1):
        b = W * f + g
        C, WL = _newton_factor(K, L, W)
        if C is not None:  # Newton's own step: the log posterior is concave here (K^-1 + W > 0), and
            # a = K^-1 (K^-1 + W)^-1 b = (I + W K)^-1 b
            direction = b - WL(_solve(C, WL(b, transpose=True))) - a
        else:  # not concave here: an EM step, a GP's mean with the rows weighted (it never lowers psi)
            weight = (nu + 1) / (nu * scale * scale + (y - f[group]) ** 2)  # each row's precision in the EM step
            w = np.sqrt(np.bincount(group, weight, m))
            target = np.bincount(group, weight * y, m)
            C = _factor(w[:, None] * K * w[None, :])
            direction = target - w * _solve(C, w * (K @ target)) - a
        t = 1.0
        while True:  # halve the step until the log posterior rises (or the step is negligible)
            tried = _state(K, at, a + t * direction)
            if tried[2] >= psi or t < 1e-10:
                break
            t *= 0.5
        rise = tried[2] - psi
        if rise < 0:  # no step along it raises the log posterior: the mode, to rounding
            break
        a, f, psi, log_lik, g, W = tried
        # at the mode the log posterior's gradient g - K^-1 f = g - a vanishes; a step that raises it by
        # rounding only is there too
        if np.max(np.abs(g - a)) <= 1e-9 * (1.0 + np.max(np.abs(g))) or rise <= 1e-13 * max(1.0, abs(psi)):
            break
    else:
        raise RuntimeError(f"the posterior mode was not found in max_newton={max_newton} steps; raise max_newton "
                           "or scale")
    return a, f, psi, log_lik, g, W, step


def _leave_saddle(K, L, at, a, psi, g, W):
    """A step off a point that is no maximum, along which the log posterior curves upwards most (relative to
    the prior), halved until it rises; None if it never does.

    With ``K^-1 + W = L^-T B L^-1``, the eigenvector ``u`` of B's lowest eigenvalue ``lam < 0`` gives the
    direction ``L u`` in ``f`` (``L^-T u`` in ``a = K^-1 f``), where the log posterior's second-order term
    is ``-lam t^2 / 2 > 0``: both ways rise, to maxima on either side.  The way is the gradient's (``g - a``
    in ``f``) where its first-order term counts (over 1e-3 of that second-order term at ``t = 1``); at a
    stationary point it does not, and a fixed convention chooses, so that rounding (or the arbitrary sign of
    an eigenvector, which differs between LAPACK builds) never does: the lowest-indexed entry of ``L u``
    whose size is within 1e-6 of the largest is made positive.
    """
    lam, vectors = np.linalg.eigh(np.eye(len(W)) + L.T @ (W[:, None] * L))
    u = vectors[:, 0]
    step_f = L @ u
    size = np.abs(step_f)
    first = int(np.flatnonzero(size >= (1 - 1e-6) * size.max())[0])
    slope = (g - a) @ step_f  # the log posterior's gradient in f is g - a
    sign = np.sign(slope) if abs(slope) > 1e-3 * 0.5 * abs(lam[0]) else np.sign(step_f[first])
    direction = sign * sla.solve_triangular(L, u, lower=True, trans="T")  # L^-T u, the way chosen
    t = 1.0
    while t >= 1e-10:
        tried = _state(K, at, a + t * direction)
        if tried[2] > psi:
            return tried
        t *= 0.5
    return None


def laplace_predict(mode: LaplaceMode, K_star, k_star_star):
    """The approximate posterior's mean and variance of the latent function at queries.

    Parameters
    ----------
    mode : LaplaceMode
    K_star : ndarray of shape (q, m)
        The kernel between the queries and the distinct inputs.
    k_star_star : ndarray of shape (q,)
        The kernel's diagonal at the queries.

    Returns
    -------
    mean, var : ndarray of shape (q,)
        ``k*^T a`` and ``k** - k*^T K^-1 k* + k*^T K^-1 (K^-1 + W)^-1 K^-1 k*`` (R&W eqs. 3.21, 3.24).
    """
    mean = K_star @ mode.a
    v = sla.solve_triangular(mode.L, K_star.T, lower=True)  # L^-1 k*
    u = sla.solve_triangular(mode.C, v, lower=True)  # C^-1 L^-1 k*, so u^T u = v^T B^-1 v
    var = k_star_star - np.einsum("ij,ij->j", v, v) + np.einsum("ij,ij->j", u, u)
    return mean, np.maximum(var, 0.0)


def answering_mode(K, y, group, nu: float, scale: float, a0=None, max_newton: int = MAX_NEWTON) -> LaplaceMode:
    """The mode of a search that must answer: a prediction's, or the fitted model's.

    :func:`laplace_mode` as the hyperparameter search calls it, except that
    a saddle of the log posterior the search stops on is left for a maximum
    (up to :data:`SADDLE_ESCAPES` times) and a slow search may take
    :data:`ANSWER_PATIENCE` times ``max_newton`` steps: a decision cannot
    turn back from such a point, as the hyperparameter search does.  Raises
    as :func:`laplace_mode` does if no maximum is found even so.

    Parameters
    ----------
    K, y, group, nu, scale, a0
        As :func:`laplace_mode`'s.
    max_newton : int, default 1000
        The steps the hyperparameter search allows; this search may take
        :data:`ANSWER_PATIENCE` times as many.
    """
    return laplace_mode(K, y, group, nu, scale, a0=a0, max_newton=ANSWER_PATIENCE * max_newton,
                        escapes=SADDLE_ESCAPES)


def laplace_predict_batch(kernel, nu: float, scale: float, X, y, X_query, include_noise: bool = False,
                          max_newton: int = MAX_NEWTON):
    """Predict from several training sets at once, each by its own Laplace approximation.

    What the agent asks of the model for each strategic prior: condition on
    the prior's rows (repeated inputs folded: one latent value each), then
    predict the queries.  Each mode is a search that must answer
    (:func:`answering_mode`).

    Parameters
    ----------
    kernel : RBF
        The latent function's kernel (fitted).
    nu, scale : float
        The Student-t noise's degrees of freedom and scale (fitted).
    X : sequence of B arrays of shape (n_b, d)
        Training inputs of each set.
    y : sequence of B arrays of shape (n_b,)
    X_query : ndarray of shape (B, q, d)
    include_noise : bool, default False
        Add the noise's variance (:func:`noise_variance`): a new observation's.
    max_newton : int, default 1000

    Returns
    -------
    mean, var : ndarray of shape (B, q)
    df : ndarray of shape (B,)
        ``inf``: the approximation's predictive is summarised by its mean and variance.
    """
    X_query = np.asarray(X_query, dtype=float)
    B, q = X_query.shape[:2]
    mean, var = np.empty((B, q)), np.empty((B, q))
    noise = noise_variance(nu, scale) if include_noise else 0.0
    for b in range(B):
        first, group = distinct_rows(X[b])
        U = X[b][first]
        mode = answering_mode(kernel(U), np.asarray(y[b], dtype=float), group, nu, scale, max_newton=max_newton)
        mean[b], var[b] = laplace_predict(mode, kernel(X_query[b], U), kernel.diag(X_query[b]))
    return mean, var + noise, np.full(B, np.inf)
