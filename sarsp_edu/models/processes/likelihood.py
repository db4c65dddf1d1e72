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
algorithm (which needs ``W >= 0``) is changed
(:mod:`~sarsp_edu.models.processes.laplace`): the mode is found by Newton
steps where the log posterior is concave and EM steps where it is not, each
with a line search, and the covariance uses ``B = I + L^T W L``
(``K = L L^T``), positive definite exactly when the mode is a maximum.
Where the search stops on a point that is no maximum (a saddle: B has a
negative eigenvalue), the fitted model's mode and
:meth:`StudentTLikelihoodGP.predict_batch` step off it along that
eigenvalue's direction and go on to a maximum; the hyperparameter search
turns back from such a point instead.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize, stats
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import validate_data

from ..._internal.validation import check_bool, check_choice, check_int, check_positive, check_X
from ...config import ADAM_STEPS, LEARNING_RATE, LIKELIHOOD_NU, LIKELIHOOD_SCALE, NU_PRIOR, PRIORS
from ..kernels import RBF
from ..linalg import distinct_rows
from ..optimizers import adam, best_of_starts, projected_gradient_norm, restart_points
from .laplace import (
    MAX_NEWTON,
    answering_mode,
    laplace_predict,
    laplace_predict_batch,
    noise_variance,
    student_t_log_likelihood,
)
from .laplace_gradient import laplace_gradient

__all__ = ["StudentTLikelihoodGP", "nu_log_prior", "student_t_log_likelihood"]

#: the log hyperparameters' box in a fit: amplitude, length scale and noise scale each within [1e-3, 1e3]; a
#: fitted nu's log(nu - 2) within [log 0.01, log 1000]
_LOG_BOUNDS = np.log([[1e-3, 1e3]] * 3)
_NU_BOUNDS = np.log([[1e-2, 1e3]])


def nu_log_prior(eta: float) -> tuple:
    """The log density of :data:`~sarsp_edu.config.NU_PRIOR` (a Gamma on ``nu - 2``) in ``eta = log(nu - 2)``,
    the Jacobian included, and its derivative in ``eta``: 0 density at nu = 2 and a tail that keeps nu off its
    upper bound where the data cannot tell."""
    shape, rate = NU_PRIOR
    x = math.exp(eta)
    value = shape * math.log(rate) - math.lgamma(shape) + shape * eta - rate * x
    return value, shape - rate * x


class StudentTLikelihoodGP(RegressorMixin, BaseEstimator):
    """GP regression with Student-t observation noise, by the Laplace approximation.

    Parameters
    ----------
    kernel : RBF, optional
        The latent function's kernel; default ``RBF(1.0, 1.0)``.
    nu : float, default 3.0
        The noise's degrees of freedom (> 0; kept fixed, as the TP's, unless
        ``fit_nu``, when it is the search's start).  Large ``nu`` gives
        Gaussian noise: the model becomes the GP with
        ``noise_variance = scale**2``.
    fit_nu : bool, default False
        Fit nu with the other hyperparameters, as ``nu = 2 + e^eta`` (the
        noise's variance stays finite) under a Gamma(2, 0.1) prior on
        ``nu - 2`` (:data:`~sarsp_edu.config.NU_PRIOR`, whatever ``prior``
        says: without it a small data set can push nu to its bound); ``nu``
        must then be above 2.
    scale : float, default 0.5
        The noise's scale ``s`` (> 0); its variance is ``s^2 nu / (nu - 2)``
        for ``nu > 2``.
    optimizer : {"lbfgs", "adam", None}, default "lbfgs"
        Fit the amplitude, the length scale and ``scale`` by maximising the
        Laplace approximation of the marginal likelihood (plus the log priors
        with ``prior="lognormal"``) over their logs, with its exact gradient
        (:func:`~sarsp_edu.models.processes.laplace_gradient.laplace_gradient`):
        L-BFGS-B to convergence, or ``max_iter`` Adam steps of
        ``learning_rate`` from the given values (as the SARSP agent fits its
        GP and TP); None keeps the given ones.
    learning_rate : float, default 0.1
        Adam's step size.
    max_iter : int, optional
        Adam's steps (default 50) or L-BFGS-B's iteration cap (default scipy's).
    prior : {"lognormal", None}, default None
        LogNormal(0, 1) priors on the amplitude, the length scale and ``scale``
        (MAP), as the agent's GP and TP have.
    n_restarts : int, default 0
        Extra starts of the hyperparameter search, the best objective kept
        (:func:`~sarsp_edu.models.optimizers.restart_points`: narrow noise
        first); deterministic.
    warm_start : bool, default False
        A refit searches from the last fit's hyperparameters, one start (as
        :class:`~sarsp_edu.models.processes.gp.GaussianProcess`); where that
        search ends at values whose posterior has no mode, the refit starts
        again from the given values, with ``n_restarts``.
    max_newton : int, default 1000
        Steps allowed to find the posterior mode in the hyperparameter search, which turns back where a
        search needs more (a prior of the agent's cost data took 182, its EM steps slow where most rows start
        as outliers to a noise scale of 0.006).  The fitted model's mode and a prediction's may take
        :data:`~sarsp_edu.models.processes.laplace.ANSWER_PATIENCE` times as many.

    Notes
    -----
    Rows with equal inputs share one latent value and add their log
    likelihoods (:mod:`~sarsp_edu.models.processes.laplace`): exact, and the
    latent prior stays positive definite where rows repeat.

    Attributes
    ----------
    f_hat_ : ndarray of shape (n,)
        The posterior mode of the latent function at the training inputs.
    W_ : ndarray of shape (n,)
        ``-d^2 log p(y_i | f_i) / d f_i^2`` at the mode: negative where a
        point is treated as an outlier (residual beyond ``sqrt(nu) scale``).
    kernel_, scale_, nu_ : the hyperparameters used (fitted unless ``optimizer=None``; ``nu_`` only with
        ``fit_nu``)
    gradient_norm_ : float
        The objective's gradient norm where the search ended (NaN without one).
    start_objectives_ : ndarray
        The final objective of each start's search, the first from the given values.
    log_marginal_likelihood_value_ : float
        The Laplace approximation ``-a^T f_hat / 2 + log p(y | f_hat) - log|B| / 2``.
    residual_ : ndarray of shape (n,)
        ``y - f_hat_``.
    n_newton_ : int
        Newton steps the last mode search took.
    mode_start_ : ndarray or None
        Where the fitted mode's search began (the search's last mode; None: the prior mean).
    n_iter_ : int
        Steps of the hyperparameter search; with ``optimizer=None``, the
        Newton steps of the mode search, the fit's only iterations.
    """

    def __init__(self, kernel: RBF | None = None, *, nu: float = LIKELIHOOD_NU, scale: float = LIKELIHOOD_SCALE,
                 optimizer: str | None = "lbfgs", learning_rate: float = LEARNING_RATE, max_iter: int | None = None,
                 prior: str | None = None, max_newton: int = MAX_NEWTON, fit_nu: bool = False, n_restarts: int = 0,
                 warm_start: bool = False):
        self.kernel = kernel
        self.nu = nu
        self.fit_nu = fit_nu
        self.n_restarts = n_restarts
        self.warm_start = warm_start
        self.scale = scale
        self.optimizer = optimizer
        self.learning_rate = learning_rate
        self.max_iter = max_iter
        self.prior = prior
        self.max_newton = max_newton

    # -- the posterior mode and the approximation at it -------------------------------
    def _laplace(self, kernel: RBF, nu: float, scale: float, U, y, group, a0=None):
        """The Laplace approximation (:func:`~sarsp_edu.models.processes.laplace.answering_mode`) at these
        hyperparameters, on the distinct inputs ``U``: a saddle the search stops on is left for a maximum, and
        the search may take longer, as a prediction's (raises if no maximum is found)."""
        return answering_mode(kernel(U), y, group, nu, scale, a0=a0, max_newton=self.max_newton)

    def _log_prior(self, theta):
        """LogNormal(0, 1) log density of the three hyperparameters and its gradient in their logs (0 without
        priors), as the GP's and TP's."""
        if self.prior is None:
            return 0.0, np.zeros(3)
        return float(np.sum(-theta - 0.5 * theta * theta - 0.5 * math.log(2.0 * math.pi))), -1.0 - theta

    # -- scikit-learn's API ----------------------------------------------------------------
    def fit(self, X, y, *, on_step=None):
        """Find the posterior mode (and, with an ``optimizer``, the hyperparameters first).

        Parameters
        ----------
        X : array-like of shape (n, d)
        y : array-like of shape (n,)
        on_step : callable, optional
            ``on_step()`` after each step of the hyperparameter search (a
            progress bar's update); what it raises ends the fit.

        Returns
        -------
        self
        """
        if self.kernel is not None and not isinstance(self.kernel, RBF):
            raise ValueError(f"kernel must be an RBF instance or None, got kernel={self.kernel!r}")
        check_positive("nu", self.nu)
        check_positive("scale", self.scale)
        check_choice("optimizer", self.optimizer, ("lbfgs", "adam", None))
        check_positive("learning_rate", self.learning_rate)
        check_int("max_iter", self.max_iter, 1, allow_none=True)
        check_choice("prior", self.prior, PRIORS)
        check_int("max_newton", self.max_newton, 1)
        check_bool("fit_nu", self.fit_nu)
        check_bool("warm_start", self.warm_start)
        if self.fit_nu and not self.nu > 2:
            raise ValueError(f"nu must be above 2 with fit_nu=True (the search fits log(nu - 2) from it), got "
                             f"nu={self.nu!r}")
        check_int("n_restarts", self.n_restarts, 0)
        X, y = validate_data(self, X, y, y_numeric=True, dtype=np.float64)
        X = check_X(X)
        U, group = self._distinct(X)
        warm = self.optimizer is not None and self.warm_start and hasattr(self, "kernel_")
        try:
            self._fit_from(X, y, U, group, warm, on_step)
        except RuntimeError:  # a warm search may end where the mode has no maximum: the fit starts again, cold
            if not warm:
                raise
            self._fit_from(X, y, U, group, False, on_step)
        return self

    def _fit_from(self, X, y, U, group, warm: bool, on_step) -> None:
        """The search (unless ``optimizer=None``), from the last fit's values where ``warm`` (one start), else
        from the given ones (with ``n_restarts``), and the fitted state at its end."""
        kernel = RBF() if self.kernel is None else self.kernel
        scale, nu = float(self.scale), float(self.nu)
        last = None
        gradient_norm, start_objectives = math.nan, np.array([])
        if self.optimizer is not None:
            if warm:  # from the last fit's values
                kernel, scale = self.kernel_, self.scale_
                nu = self.nu_ if self.fit_nu else nu
            theta0 = [kernel.amplitude, kernel.length_scale, scale] + ([nu - 2.0] if self.fit_nu else [])
            theta, last, gradient_norm, start_objectives = self._search(np.log(theta0), U, y, group, on_step,
                                                                       0 if warm else self.n_restarts)
            amplitude, length, scale = np.exp(theta[:3])
            kernel = RBF(amplitude, length)
            if self.fit_nu:
                nu = 2.0 + math.exp(theta[3])
        n_iter = None if self.optimizer is None else self.n_iter_  # None: the mode search's steps
        self._settle(X, y, kernel, float(scale), nu, last, gradient_norm, start_objectives, n_iter)

    @staticmethod
    def _distinct(X):
        first, group = distinct_rows(X)  # repeated inputs share one latent value
        return X[first], group

    def _settle(self, X, y, kernel: RBF, scale: float, nu: float, a0, gradient_norm: float, start_objectives,
                n_iter: int | None) -> None:
        """The fitted state at these hyperparameters: the posterior mode, searched from ``a0`` (where the
        hyperparameter search's last one ended; None: the prior mean).  Set together, after the search (one
        that raises leaves the last fit whole); a stored fit is restored through it too
        (:mod:`sarsp_edu.teaching.live.fitcache`), which gives the same bits."""
        U, group = self._distinct(X)
        mode = self._laplace(kernel, nu, scale, U, y, group, a0=a0)
        self.kernel_, self.scale_, self.nu_ = kernel, scale, nu
        self.gradient_norm_, self.start_objectives_ = gradient_norm, np.asarray(start_objectives, dtype=float)
        self.mode_start_ = None if a0 is None else np.array(a0, dtype=float)
        self.f_hat_ = mode.f[group]
        self.W_ = student_t_log_likelihood(y - self.f_hat_, self.nu_, self.scale_)[2]  # per row
        self.log_marginal_likelihood_value_, self.n_newton_ = mode.log_q, mode.steps
        self.n_iter_ = mode.steps if n_iter is None else n_iter
        self._mode, self.X_distinct_ = mode, U
        self.X_train_ = X
        self.residual_ = y - self.f_hat_

    def _search(self, theta0, U, y, group, on_step=None, n_restarts=0):
        """The log hyperparameters that maximise the approximate log marginal likelihood (plus the log priors),
        the last mode found (where the final one's search starts), the gradient norm where the search ended and
        each start's final objective."""
        start = {"a": None}  # the last mode, where the next evaluation's Newton search starts
        bounds = np.vstack([_LOG_BOUNDS, _NU_BOUNDS]) if self.fit_nu else _LOG_BOUNDS

        def negative(theta):
            nu = 2.0 + math.exp(theta[3]) if self.fit_nu else self.nu
            try:
                value, gradient, mode = laplace_gradient(RBF(*np.exp(theta[:2])), U, y, group, nu,
                                                         math.exp(theta[2]), a0=start["a"], max_newton=self.max_newton,
                                                         fit_nu=self.fit_nu)
            except (RuntimeError, np.linalg.LinAlgError):
                return 1e25, np.zeros(len(theta))  # no maximum there: the search turns back
            start["a"] = mode.a
            prior, prior_gradient = self._log_prior(theta[:3])
            value, gradient = value + prior, gradient + np.append(prior_gradient, [0.0] * (len(theta) - 3))
            if self.fit_nu:
                nu_prior, nu_gradient = nu_log_prior(theta[3])
                value, gradient[3] = value + nu_prior, gradient[3] + nu_gradient
            return -value, -gradient

        def search(theta):
            start["a"] = None  # each start's mode searches begin at the prior mean, as the first's
            if self.optimizer == "lbfgs":
                result = optimize.minimize(negative, theta, jac=True, method="L-BFGS-B", bounds=bounds,
                                           options={} if self.max_iter is None else {"maxiter": self.max_iter},
                                           callback=None if on_step is None else lambda *_: on_step())
                return result.x, [float(result.fun)], int(result.nit)
            steps = ADAM_STEPS if self.max_iter is None else self.max_iter
            found, trace, n_iter = adam(negative, theta, bounds, self.learning_rate, steps, on_step=on_step)
            return found, trace, n_iter

        starts = restart_points(theta0, bounds, n_restarts)
        if len(starts) == 1:
            theta, _, self.n_iter_ = search(starts[0])
            finals = None
        else:
            modes = []  # each start's last mode, in the order of the starts

            def remembered(theta):
                found = search(theta)
                modes.append(start["a"])
                return found

            theta, trace, self.n_iter_, finals = best_of_starts(remembered, starts)
            chosen = next(i for i, value in enumerate(finals) if value == trace[-1] or (value != value and
                                                                                        trace[-1] != trace[-1]))
            start["a"] = modes[chosen]  # the best start's last mode: where the fitted model's search starts
        last = start["a"]  # the fitted model's mode search starts where the search's last one ended
        value, gradient = negative(theta)
        objectives = -np.asarray([value] if finals is None else finals, dtype=float)
        return theta, last, projected_gradient_norm(gradient, theta, bounds), objectives

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
        mean, var = laplace_predict(self._mode, self.kernel_(X, self.X_distinct_), self.kernel_.diag(X))
        if not (return_std or return_var):
            return mean
        if include_noise:
            var = var + noise_variance(self.nu_, self.scale_)
        out = [mean]
        out += [np.sqrt(var)] if return_std else []
        out += [var] if return_var else []
        return tuple(out)

    def predict_batch(self, X, y, X_query, include_noise: bool = False):
        """Predict from several training sets at once, each conditioned by its own Laplace approximation
        with the fitted hyperparameters: what the SARSP agent asks for each strategic prior.  A set whose
        mode search stops on a saddle goes on from it to a maximum (up to
        :data:`~sarsp_edu.models.processes.laplace.SADDLE_ESCAPES` times).

        Parameters
        ----------
        X : sequence of B arrays of shape (n_b, d)
        y : sequence of B arrays of shape (n_b,)
        X_query : ndarray of shape (B, q, d)
        include_noise : bool, default False
            Add the noise's variance ``s^2 nu / (nu - 2)``.

        Returns
        -------
        mean, var : ndarray of shape (B, q)
        df : ndarray of shape (B,)
            ``inf`` (see :func:`~sarsp_edu.models.processes.laplace.laplace_predict_batch`).
        """
        self._check_fitted()
        return laplace_predict_batch(self.kernel_, self.nu_, self.scale_, X, y, X_query, include_noise,
                                     self.max_newton)

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
        noise = stats.t(df=self.nu_, scale=self.scale_)
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
        return (self.nu_ + 1) * s2 / (self.nu_ * s2 + self.residual_ ** 2)

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.regressor_tags.poor_score = True  # a few hundred points at most: the search is brute force
        return tags
