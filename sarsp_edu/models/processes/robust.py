"""A GP whose *likelihood* is a Student-t: a model that does discount outliers (Laplace approximation).

The Student-t *process* of this package keeps the GP's posterior mean and
changes the variance by one factor: it does not change which points the
mean believes.  A GP with a Student-t likelihood does.  The latent function
has the GP prior ``f ~ GP(0, k)``; each observation is the function plus
Student-t noise with ``nu`` degrees of freedom and scale ``s``:

``log p(y_i | f_i) = log G((nu+1)/2) - log G(nu/2) - log(nu pi s^2)/2 - (nu+1)/2 log(1 + r_i^2 / (nu s^2))``,
``r_i = y_i - f_i``.

Its gradient ``(nu+1) r / (nu s^2 + r^2)`` grows with a residual up to
``|r| = sqrt(nu) s`` and then *falls*: a point far from the function pulls
on it less the farther it is.  That is what discounts an outlier.

The posterior is not Gaussian; the Laplace approximation (Rasmussen and
Williams 2006, ch. 3; Vanhatalo, Jylanki and Vehtari 2009) replaces it by the
Gaussian at its mode ``f_hat`` with precision ``K^-1 + W``,
``W = diag(-d^2 log p(y_i | f_i) / d f_i^2)``.  For the Student-t, ``W`` is
negative for a point whose residual exceeds ``sqrt(nu) s``, so the textbook
algorithm (which needs ``W >= 0``) is changed in two places: the mode is
found by Newton steps with ``max(W, 0)`` and a line search (an ascent
direction every step, the same fixed point), and the covariance uses
``B = I + L^T W L`` (``K = L L^T``), positive definite exactly when the mode
is a maximum.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import linalg as sla, optimize, special, stats
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import validate_data

from ..._internal.validation import check_choice, check_int, check_positive, check_X
from ..kernels import RBF
from ..linalg import cholesky_with_jitter

__all__ = ["StudentTLikelihoodGP", "student_t_log_likelihood"]


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


class StudentTLikelihoodGP(RegressorMixin, BaseEstimator):
    """GP regression with Student-t observation noise, by the Laplace approximation.

    Parameters
    ----------
    kernel : RBF, optional
        The latent function's kernel; default ``RBF(1.0, 1.0)``.
    nu : float, default 3.0
        The noise's degrees of freedom (> 0; kept fixed, as the TP's).  Large
        ``nu`` gives Gaussian noise: the model becomes the GP with
        ``noise_variance = scale**2``.
    scale : float, default 0.5
        The noise's scale ``s`` (> 0); its variance is ``s^2 nu / (nu - 2)``
        for ``nu > 2``.
    optimizer : {"lbfgs", None}, default "lbfgs"
        Fit the amplitude, the length scale and ``scale`` by maximising the
        Laplace approximation of the marginal likelihood (L-BFGS-B on their
        logs, gradients by finite differences: meant for the hundreds of
        points of a tutorial), or keep the given ones.
    max_newton : int, default 100
        Newton steps allowed to find the posterior mode.

    Attributes
    ----------
    f_hat_ : ndarray of shape (n,)
        The posterior mode of the latent function at the training inputs.
    W_ : ndarray of shape (n,)
        ``-d^2 log p(y_i | f_i) / d f_i^2`` at the mode: negative where a
        point is treated as an outlier (residual beyond ``sqrt(nu) scale``).
    kernel_, scale_ : the hyperparameters used (fitted unless ``optimizer=None``)
    log_marginal_likelihood_value_ : float
        The Laplace approximation ``-a^T f_hat / 2 + log p(y | f_hat) - log|B| / 2``.
    residual_ : ndarray of shape (n,)
        ``y - f_hat_``.
    n_newton_ : int
        Newton steps the last mode search took.
    """

    def __init__(self, kernel: RBF | None = None, *, nu: float = 3.0, scale: float = 0.5,
                 optimizer: str | None = "lbfgs", max_newton: int = 100):
        self.kernel = kernel
        self.nu = nu
        self.scale = scale
        self.optimizer = optimizer
        self.max_newton = max_newton

    # -- the posterior mode and the approximation at it -------------------------------
    def _laplace(self, kernel: RBF, scale: float, X, y):
        """(f_hat, a, W, L, B's factor, log q(y)) for these hyperparameters (raises if no maximum is found)."""
        n = len(y)
        K = kernel(X)
        L, _ = cholesky_with_jitter(K)
        K = L @ L.T  # the matrix whose factor is L (the jitter included), so the two agree
        f = np.zeros(n)
        a = np.zeros(n)
        psi = self._psi(a, f, y, scale)
        log_lik, g, W = student_t_log_likelihood(y - f, self.nu, scale)
        for step in range(1, self.max_newton + 1):
            w = np.sqrt(np.maximum(W, 0.0))  # Newton with max(W, 0): an ascent direction every step
            B = np.eye(n) + w[:, None] * K * w[None, :]
            C = sla.cholesky(B, lower=True)
            b = np.maximum(W, 0.0) * f + g
            a_new = b - w * sla.cho_solve((C, True), w * (K @ b))
            direction = a_new - a
            t = 1.0
            while True:  # halve the step until the log posterior rises (or the step is negligible)
                a_try = a + t * direction
                f_try = K @ a_try
                psi_try = self._psi(a_try, f_try, y, scale)
                if psi_try >= psi or t < 1e-10:
                    break
                t *= 0.5
            rise = psi_try - psi
            a, f, psi = a_try, f_try, psi_try
            # at the mode the log posterior's gradient g - K^-1 f = g - a vanishes; a full Newton step that
            # raises it by rounding only, or a step the line search cannot make rise, is there too
            log_lik, g, W = student_t_log_likelihood(y - f, self.nu, scale)  # the next step's too
            if (np.max(np.abs(g - a)) <= 1e-9 * (1.0 + np.max(np.abs(g)))
                    or (t == 1.0 and rise <= 1e-13 * max(1.0, abs(psi))) or t < 1e-10):
                break
        else:
            raise RuntimeError(f"{type(self).__name__}: the posterior mode was not found in max_newton="
                               f"{self.max_newton} Newton steps; raise max_newton or scale")
        B = np.eye(n) + L.T @ (W[:, None] * L)  # K^-1 + W = L^-T B L^-1
        try:
            C = sla.cholesky(B, lower=True)
        except np.linalg.LinAlgError:
            raise RuntimeError(f"{type(self).__name__}: the Laplace approximation has no maximum here (K^-1 + W "
                               "is not positive definite at the mode); try a larger scale") from None
        log_q = float(-0.5 * a @ f + log_lik.sum() - np.log(np.diag(C)).sum())
        return f, a, W, L, C, log_q, step

    def _psi(self, a, f, y, scale):
        """The log posterior of f up to a constant: ``log p(y | f) - f^T K^-1 f / 2`` with ``f = K a``."""
        return float(student_t_log_likelihood(y - f, self.nu, scale)[0].sum() - 0.5 * a @ f)

    # -- scikit-learn's API ----------------------------------------------------------------
    def fit(self, X, y):
        """Find the posterior mode (and, with ``optimizer="lbfgs"``, the hyperparameters first).

        Parameters
        ----------
        X : array-like of shape (n, d)
        y : array-like of shape (n,)

        Returns
        -------
        self
        """
        if self.kernel is not None and not isinstance(self.kernel, RBF):
            raise ValueError(f"kernel must be an RBF instance or None, got kernel={self.kernel!r}")
        check_positive("nu", self.nu)
        check_positive("scale", self.scale)
        check_choice("optimizer", self.optimizer, ("lbfgs", None))
        check_int("max_newton", self.max_newton, 1)
        X, y = validate_data(self, X, y, y_numeric=True, dtype=np.float64)
        X = check_X(X)
        kernel = RBF() if self.kernel is None else self.kernel
        scale = float(self.scale)
        if self.optimizer == "lbfgs":
            def negative(theta):
                a, length, s = np.exp(theta)
                try:
                    return -self._laplace(RBF(a, length), s, X, y)[5]
                except (RuntimeError, np.linalg.LinAlgError):
                    return 1e25  # no maximum there: the search turns back

            start = np.log([kernel.amplitude, kernel.length_scale, scale])
            bounds = [(math.log(1e-3), math.log(1e3))] * 3
            result = optimize.minimize(negative, start, method="L-BFGS-B", bounds=bounds)
            amplitude, length, scale = np.exp(result.x)
            kernel = RBF(amplitude, length)
        self.kernel_, self.scale_ = kernel, scale
        (self.f_hat_, self._a, self.W_, self._L, self._C, self.log_marginal_likelihood_value_,
         self.n_newton_) = self._laplace(kernel, scale, X, y)
        self.X_train_ = X
        self.residual_ = y - self.f_hat_
        return self

    def _check_fitted(self):
        if not hasattr(self, "f_hat_"):
            from sklearn.exceptions import NotFittedError

            raise NotFittedError(f"This {type(self).__name__} is not fitted yet: call fit(X, y) before predicting")

    def predict(self, X, return_std: bool = False, return_var: bool = False, include_noise: bool = False):
        """The Laplace approximation's predictive mean of f*, and optionally its standard deviation or variance.

        ``include_noise`` adds the Student-t noise's variance ``s^2 nu / (nu - 2)``
        (finite only for ``nu > 2``): the variance of a new observation.

        Parameters
        ----------
        X : array-like of shape (m, d)
            Query points.
        return_std, return_var : bool, default False
            Also return the standard deviation, the variance, of each prediction.
        include_noise : bool, default False
            Add the noise's variance (refused when ``nu <= 2``).

        Returns
        -------
        mean : ndarray of shape (m,)
            Alone, or a tuple ``(mean, std, var)`` of those asked for, in that order.
        """
        self._check_fitted()
        X = check_X(validate_data(self, X, reset=False, dtype=np.float64))
        K_star = self.kernel_(X, self.X_train_)  # (m, n)
        mean = K_star @ self._a  # k*^T K^-1 f_hat, as K^-1 f_hat = a (R&W eq. 3.21)
        if not (return_std or return_var):
            return mean
        v = sla.solve_triangular(self._L, K_star.T, lower=True)  # L^-1 k*
        u = sla.solve_triangular(self._C, v, lower=True)  # C^-1 L^-1 k*, so u^T u = v^T B^-1 v
        # V[f*] = k** - k*^T K^-1 k* + k*^T K^-1 (K^-1 + W)^-1 K^-1 k* = k** - v^T v + v^T B^-1 v
        var = np.maximum(self.kernel_.diag(X) - np.einsum("ij,ij->j", v, v) + np.einsum("ij,ij->j", u, u), 0.0)
        if include_noise:
            if self.nu <= 2:
                raise ValueError(f"the noise has no finite variance with nu={self.nu} <= 2; use include_noise=False")
            var = var + self.scale_ ** 2 * self.nu / (self.nu - 2.0)
        out = [mean]
        out += [np.sqrt(var)] if return_std else []
        out += [var] if return_var else []
        return tuple(out)

    def predictive_density(self, X, y_values):
        """The approximate predictive density of a new observation, ``int t(y* | f*) N(f* | mean, var) df*``.

        Evaluated by Gauss-Hermite quadrature (60 nodes) at each point of ``X``
        for each value in ``y_values``; returns an array ``(len(X), len(y_values))``.

        Parameters
        ----------
        X : array-like of shape (m, d)
            Query points.
        y_values : array-like of shape (k,)
            Values of the new observation ``y*`` at which the density is evaluated.
        """
        mean, var = self.predict(X, return_var=True)
        nodes, weights = np.polynomial.hermite_e.hermegauss(60)  # for the weight exp(-x^2 / 2)
        f = mean[:, None] + np.sqrt(var)[:, None] * nodes[None, :]  # (m, q)
        y_values = np.asarray(y_values, dtype=float)
        noise = stats.t(df=self.nu, scale=self.scale_)
        dens = noise.pdf(y_values[None, :, None] - f[:, None, :])  # (m, k, q)
        return dens @ weights / math.sqrt(2.0 * math.pi)

    def outlier_weights(self):
        """How much each training point's residual pulls on the function, relative to a Gaussian's pull.

        ``(nu + 1) s^2 / (nu s^2 + r^2)`` at the mode: a Gaussian likelihood of
        variance ``s^2`` pulls with weight 1 at every residual; this one with
        ``(nu + 1) / nu`` for a point on the function, 1 at ``|r| = s``, and
        less and less beyond, towards 0.
        """
        self._check_fitted()
        s2 = self.scale_ ** 2
        return (self.nu + 1) * s2 / (self.nu * s2 + self.residual_ ** 2)

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.regressor_tags.poor_score = True  # a few hundred points at most: the search is brute force
        return tags
