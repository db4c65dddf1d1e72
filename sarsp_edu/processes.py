"""Gaussian-process and Student-t-process regression in closed form.

Both models share one implementation; the Student-t process (TP) differs from
the Gaussian process (GP) only where the mathematics differs:

==========================  ==================================  =======================================
quantity                    GP (Rasmussen & Williams 2006)      TP (Shah, Wilson & Ghahramani 2014)
==========================  ==================================  =======================================
marginal likelihood         multivariate normal N(0, K)         multivariate t, nu dof, covariance K
predictive mean             k*^T K^-1 y  (paper eq. 4)          the same
predictive variance         k** - k*^T K^-1 k*  (paper eq. 5)   (nu + beta - 2) / (nu + n - 2) x GP's
predictive distribution     normal                              Student-t with nu + n dof
==========================  ==================================  =======================================

Here ``K = K(X, X) + noise_variance * I``, ``n`` is the number of training
points and ``beta = y^T K^-1 y``.  The paper's eq. 6 writes
``K(X*, X*)^-1`` inside ``beta``; that is a typo: the factor uses the
*training* covariance, as in Shah et al. (2014, eq. 7 and Lemma 3), and this
module implements the correct form.

As in the paper's reference implementation the prior mean is zero and
neither inputs nor targets are rescaled.  Hyperparameters (amplitude, length
scale, noise variance and, optionally, the TP's ``nu``) live in log space; the
fit maximises the log marginal likelihood plus, by default, LogNormal(0, 1)
log priors on the amplitude, length scale and noise variance (the reference
implementation's MAP fit), with Adam (the paper's optimiser: learning rate
0.1, 50 steps) or L-BFGS-B.

How to read it: each row of the table above is one function under "the
equations" (``gp_log_marginal_likelihood``, ``tp_log_marginal_likelihood``,
``tp_variance_factor``, ``tp_predictive_variance``); the shared model
computes the sufficient statistics ``n``, ``beta`` and ``log|K|`` once and
hands them to four hooks, which :class:`StudentTProcess` overrides under
the heading "where the TP differs".  The factorisations and solves are in
:mod:`sarsp_edu.linalg` (fast paths named as such), the two optimisers in
:mod:`sarsp_edu.optimizers`.  The module stays one file, about 900 lines,
because it is one idea (one regressor, two likelihoods); half of it is the
estimators' documentation.
"""

from __future__ import annotations

import copy
import inspect
import math
import warnings

import numpy as np
from scipy import special, stats
from sklearn import exceptions as _sklearn_exceptions
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import validate_data

from ._validation import check_choice, check_int, check_nu, check_positive, check_training, check_X
from .config import ADAM_STEPS, LEARNING_RATE, NOISE_CONVENTIONS, NU, OPTIMIZERS, PRIORS
from .kernels import RBF, squared_distances
from .linalg import (
    GroupedRows,
    cholesky,
    cholesky_with_jitter,
    group_rows,
    inverse_from_cholesky,
    solve_cholesky,
    solve_lower,
    trace_of_product,
)
from .optimizers import adam, lbfgs
from .rng import as_generator, draw_subset

__all__ = ["GaussianProcess", "StudentTProcess", "NotFittedError", "ConvergenceWarning"]

_LOG_2PI = math.log(2.0 * math.pi)


#: raised when a model is used for prediction before ``fit`` (scikit-learn's own class)
NotFittedError = _sklearn_exceptions.NotFittedError
#: the hyperparameter search did not reach an optimum (it ended on a bound, or out of reach of the data's
#: scale); scikit-learn's own class
ConvergenceWarning = _sklearn_exceptions.ConvergenceWarning


# --------------------------------------------------------------------------
# the equations where the TP differs from the GP, one function each
# (the models below call them; their inputs are the sufficient statistics
# n, beta = y^T K^-1 y and log|K| of the training data)
# --------------------------------------------------------------------------
def gp_log_marginal_likelihood(n: int, beta: float, log_det: float) -> float:
    """GP: ``log N(y; 0, K) = -beta/2 - log|K|/2 - n/2 log(2 pi)`` (Rasmussen & Williams eq. 2.30)."""
    return -0.5 * beta - 0.5 * log_det - 0.5 * n * _LOG_2PI


def tp_log_marginal_likelihood(n: int, beta: float, log_det: float, nu: float) -> float:
    """TP: the multivariate t density of y with ``nu`` dof and covariance ``K`` (Shah et al. 2014, eq. 3).

    ``-n/2 log((nu-2) pi) - log|K|/2 + log G((nu+n)/2) - log G(nu/2)
    - (nu+n)/2 log(1 + beta/(nu-2))``.
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
    """
    return (nu + n) / (nu - 2.0 + beta)


def tp_log_marginal_likelihood_dnu(n: int, beta: float, nu: float) -> float:
    """d/d nu of :func:`tp_log_marginal_likelihood`."""
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
    """
    return (nu + beta - 2.0) / (nu + n - 2.0)


def tp_predictive_variance(latent, factor: float, noise, convention: str):
    """The TP's predictive variance from the GP's latent variance and the noise.

    ``"shah"``: ``factor * (latent + noise)``, the noise is part of the
    process (Shah et al. 2014); ``"tfp"``: ``factor * latent + noise``
    (TensorFlow Probability, which the paper's reference code used).
    """
    if convention == "shah":
        return factor * (latent + noise)
    return factor * latent + noise

# --------------------------------------------------------------------------
# the shared model
# --------------------------------------------------------------------------
class _ProcessRegressor(RegressorMixin, BaseEstimator):
    """Shared machinery of :class:`GaussianProcess` and :class:`StudentTProcess`.

    Both are scikit-learn regressors: ``get_params``/``set_params`` (nested
    ``kernel__length_scale`` too), ``clone``, ``score`` (R^2), pipelines and
    grid searches work as for any scikit-learn estimator, and the arguments
    are checked in ``fit``, as scikit-learn's conventions ask.
    """

    #: names of the log hyperparameters, in the order of ``theta``
    _base_names = ("log_amplitude", "log_length_scale", "log_noise_variance")
    #: whether the fitted amplitude and noise alone set the predictive scale
    #: (the GP's); the TP's global variance factor follows y's scale itself
    _amplitude_sets_scale = True

    def __init__(
        self,
        kernel: RBF | None = None,
        *,
        noise_variance: float = 1.0,
        optimizer: str | None = "adam",
        learning_rate: float = LEARNING_RATE,
        max_iter: int | None = None,
        prior: str | None = "lognormal",
        max_fit_points: int | None = 1000,
        bounds: tuple[float, float] = (1e-5, 1e5),
        rng=None,
    ):
        self.kernel = kernel
        self.noise_variance = noise_variance
        self.optimizer = optimizer
        self.learning_rate = learning_rate
        self.max_iter = max_iter
        self.prior = prior
        self.max_fit_points = max_fit_points
        self.bounds = bounds
        self.rng = rng

    def set_params(self, **params):
        """Set constructor arguments by name, ``kernel__length_scale`` too; checked at the next ``fit``.

        With ``kernel=None`` (the default RBF(1, 1)), a nested kernel
        argument makes the default kernel explicit first.
        """
        if self.kernel is None and "kernel" not in params and any(k.startswith("kernel__") for k in params):
            self.kernel = RBF()
        return super().set_params(**params)

    def _check_params(self):
        """Check every constructor argument (in ``fit``); changes none of them."""
        if self.kernel is not None and not isinstance(self.kernel, RBF):
            raise ValueError(f"kernel must be an RBF instance or None, got kernel={self.kernel!r}")
        check_positive("noise_variance", self.noise_variance)
        check_choice("optimizer", self.optimizer, (*OPTIMIZERS, None))
        check_positive("learning_rate", self.learning_rate)
        check_int("max_iter", self.max_iter, 1, allow_none=True)
        check_choice("prior", self.prior, PRIORS)
        check_int("max_fit_points", self.max_fit_points, 1, allow_none=True)
        try:
            low, high = (float(b) for b in self.bounds)
        except (TypeError, ValueError):
            raise ValueError(
                f"bounds must be a pair (low, high) with 0 < low < high, got bounds={self.bounds!r}"
            ) from None
        if not (0 < low < high < math.inf):
            raise ValueError(
                f"bounds must be a pair (low, high) with 0 < low < high, got bounds={self.bounds!r}"
            )
        if not isinstance(self.rng, np.random.Generator):
            as_generator(self.rng)  # raises a clear error for anything else

    def _start_kernel(self) -> RBF:
        """The kernel every fit starts from: ``kernel``, or RBF(1, 1) when it is None."""
        return RBF() if self.kernel is None else self.kernel

    @property
    def hyperparameter_names(self) -> tuple[str, ...]:
        """Names of the entries of ``theta`` (log hyperparameters)."""
        return self._base_names + tuple(name for name, _, _ in self._extra_hyperparameters())

    def _initial_theta(self) -> np.ndarray:
        extra = [start for _, start, _ in self._extra_hyperparameters()]
        return np.concatenate([self._start_kernel().theta, [math.log(self.noise_variance)], extra])

    def _theta_bounds(self) -> np.ndarray:
        b = np.tile(np.log(self.bounds), (len(self._base_names), 1))
        extra = [bounds for _, _, bounds in self._extra_hyperparameters()]
        return np.vstack([b, *extra]) if extra else b

    def _unpack(self, theta):
        """(kernel, noise variance, extra) from log hyperparameters."""
        theta = np.asarray(theta, dtype=float)
        return self._start_kernel().clone_with_theta(theta[:2]), math.exp(theta[2]), theta[3:]

    # -- where the TP differs: the GP's versions here, the TP's in StudentTProcess --
    def _extra_hyperparameters(self) -> list:
        """Log hyperparameters beyond the kernel's and the noise: ``(name, start, (low, high))`` each."""
        return []

    def _lml_terms(self, n, beta, log_det, extra):
        """Log marginal likelihood from its sufficient statistics.

        Returns ``(value, w, extra_gradient)`` where the gradient of the log
        marginal likelihood with respect to a kernel hyperparameter ``t`` is
        ``0.5 * tr((w alpha alpha^T - K^-1) dK/dt)``.
        """
        return gp_log_marginal_likelihood(n, beta, log_det), 1.0, np.empty(0)

    def _predictive_scale(self, n, beta) -> tuple[float, float]:
        """The factor on the latent variance, and the predictive distribution's degrees of freedom.

        GP: 1 and infinity (a normal).
        """
        return 1.0, math.inf

    def _predictive_variance(self, latent, factor, noise):
        """Predictive variance from the latent variance (GP: ``factor`` is 1 and unused)."""
        return latent + noise

    def _set_extra(self, extra) -> None:
        """Keep the fitted extra hyperparameters (GP: none)."""

    # -- objective ---------------------------------------------------------
    def _log_prior(self, theta):
        """LogNormal(0, 1) log density of amplitude, length scale and noise.

        In log space ``t = log x`` this is ``-t - t**2 / 2 - log(2 pi) / 2``
        per hyperparameter: the density of the positive value itself, as the
        reference implementation sums ``prior.log_prob(value)``.
        """
        if self.prior is None:
            return 0.0, np.zeros_like(theta)
        t = theta[:3]
        grad = np.zeros_like(theta)
        grad[:3] = -1.0 - t
        return float(np.sum(-t - 0.5 * t * t - 0.5 * _LOG_2PI)), grad

    def _lml_from_distances(self, theta, D2, data: GroupedRows, eval_gradient, work=None):
        """Log marginal likelihood (and gradient) at ``theta`` of grouped data.

        ``D2`` holds the squared distances between the distinct inputs
        ``data.X``; the value is exactly that of all ``data.n`` rows (see
        :func:`~sarsp_edu.linalg.group_rows`).  ``work`` is an optional (3, G, G) workspace reused
        across a fit's steps: the kernel is written into it and factorised
        in place.
        """
        kernel, s2, extra = self._unpack(theta)
        G, n = data.counts.shape[0], data.n
        noise = s2 / data.counts  # the diagonal of s2 N^-1
        if eval_gradient:
            K, dK = kernel.from_squared_distances(D2, eval_gradient=True, out=work)
        else:
            K = kernel.from_squared_distances(D2, out=work)
        K.flat[:: G + 1] += noise
        # the fast path: factorise K in the workspace, without checks
        L = cholesky(K, overwrite=True) if work is not None else None
        if L is None:  # rare: rebuild K (a failed fast attempt overwrote it) and add jitter
            if work is not None:
                K = kernel.from_squared_distances(D2)
                K.flat[:: G + 1] += noise
            L, _ = cholesky_with_jitter(K)
        # Rasmussen & Williams Alg. 2.1, line 3, on the group means: alpha = A^-1 ybar
        alpha = solve_cholesky(L, data.mean)
        beta, log_det = data.beta_and_log_det(L, alpha, s2)
        value, w, extra_grad = self._lml_terms(n, beta, log_det, extra)
        if not eval_gradient:
            return value
        # R&W eq. 5.9, generalised: dL/dt = 0.5 (w alpha^T dK/dt alpha - tr(A^-1 dK/dt))
        K_inv_lower = inverse_from_cholesky(L, overwrite=work is not None)
        grad = np.empty(3 + len(extra))
        for j in range(dK.shape[2]):
            dK_j = dK[:, :, j]
            grad[j] = 0.5 * (w * float(alpha @ (dK_j @ alpha)) - trace_of_product(K_inv_lower, dK_j))
        # d beta / d log s2 = -rss / s2 - s2 alpha^T N^-1 alpha;
        # d log|K| / d log s2 = (n - G) + s2 tr(A^-1 N^-1)
        inv_counts = 1.0 / data.counts
        grad[2] = 0.5 * (
            w * (data.rss / s2 + s2 * float(alpha @ (alpha * inv_counts)))
            - (n - G)
            - s2 * float(np.diag(K_inv_lower) @ inv_counts)
        )
        grad[3:] = extra_grad
        return value, grad

    def _log_joint(self, theta, D2, data, work=None):
        value, grad = self._lml_from_distances(theta, D2, data, eval_gradient=True, work=work)
        prior, prior_grad = self._log_prior(theta)
        return value + prior, grad + prior_grad

    # -- public API --------------------------------------------------------
    def fit(self, X, y):
        """Fit the hyperparameters (unless ``optimizer=None``) and condition on the data.

        Every fit starts from the constructor's hyperparameters.  The
        hyperparameter search uses at most ``max_fit_points`` training points
        (a random subset drawn from ``rng``); the fitted model then conditions
        on *all* of ``X, y``.

        Parameters
        ----------
        X : array-like of shape (n, d)
        y : array-like of shape (n,)

        Returns
        -------
        self
        """
        self._check_params()
        # scikit-learn's checks of shape, type and length (complex or sparse data refused, y of shape
        # (n, 1) flattened with a warning; sets n_features_in_), then ours, which name a non-finite entry
        X, y = validate_data(self, X, y, y_numeric=True, dtype=np.float64, ensure_all_finite=False)
        X, y = check_training(X, y)
        theta0 = self._initial_theta()
        if self.optimizer is None:
            theta, trace, n_iter = theta0, [], 0
            self.fit_indices_ = np.arange(X.shape[0])
        else:
            bounds = self._theta_bounds()
            outside = (theta0 < bounds[:, 0]) | (theta0 > bounds[:, 1])
            if np.any(outside):
                i = int(np.flatnonzero(outside)[0])
                raise ValueError(
                    f"the initial {self.hyperparameter_names[i][4:]}={math.exp(theta0[i]):.3g} "
                    f"lies outside bounds={self.bounds}; widen bounds or change the initial value"
                )
            idx = draw_subset(X.shape[0], self.max_fit_points, self.rng)
            self.fit_indices_ = idx
            data = group_rows(X[idx], y[idx])  # repeated inputs folded, exactly
            D2 = squared_distances(data.X)
            work = np.empty((3,) + D2.shape)  # one workspace for every step of this fit

            def negative(theta):
                value, grad = self._log_joint(theta, D2, data, work)
                return -value, -grad

            if self.optimizer == "adam":
                steps = ADAM_STEPS if self.max_iter is None else self.max_iter
                self._warn_out_of_reach(y, steps)
                theta, trace, n_iter = adam(negative, theta0, bounds, self.learning_rate, steps)
            else:
                theta, trace, n_iter = lbfgs(negative, theta0, bounds, self.max_iter, len(idx))
            trace = [-v for v in trace]
            self._warn_on_bounds(theta, bounds)
        self.theta_ = np.asarray(theta, dtype=float)
        self.kernel_, self.noise_variance_, extra = self._unpack(self.theta_)
        self._set_extra(extra)
        self.n_iter_ = n_iter
        #: log joint (log marginal likelihood + log prior) on the fit subset, per step
        self.objective_trace_ = np.asarray(trace, dtype=float)
        self._condition_on(X, y)
        return self

    def _warn_out_of_reach(self, y, steps: int) -> None:
        """Warn when Adam cannot bring the amplitude near y's scale.

        Adam moves a log hyperparameter by about ``learning_rate`` per step,
        so ``steps`` steps change the amplitude by a factor of at most
        ``exp(learning_rate * steps)`` (148 for the paper's 50 steps of 0.1).
        """
        if not self._amplitude_sets_scale:
            return
        spread = float(np.std(y))
        reach = math.exp(self.learning_rate * steps)
        start = self._start_kernel().amplitude
        if spread > 0 and not start / (10 * reach) <= spread <= 10 * start * reach:
            warnings.warn(
                f"{type(self).__name__}.fit: y's standard deviation {spread:.3g} is out of reach of {steps} Adam "
                f"steps of {self.learning_rate:g} from amplitude={start:.3g} (they can scale it by at most "
                f"{reach:.3g}); the fitted variances will not match the data: rescale y, or start from an "
                "amplitude near its scale",
                ConvergenceWarning,
                stacklevel=3,
            )

    def _warn_on_bounds(self, theta, bounds) -> None:
        """One warning naming every hyperparameter that ended on its bound: the fit is then no optimum."""
        ended = []
        for i, name in enumerate(self.hyperparameter_names):
            for side, edge in (("lower", bounds[i, 0]), ("upper", bounds[i, 1])):
                if abs(theta[i] - edge) <= 1e-3:  # log space: within 0.1% of the bound
                    ended.append(f"{name[4:]}={math.exp(theta[i]):.3g} on its {side} bound {math.exp(edge):.3g}")
        if ended:
            warnings.warn(
                f"{type(self).__name__}.fit ended with {', '.join(ended)}, so the fit is no optimum; rescale "
                "the data (its scale sets the amplitude and the noise) or widen bounds",
                ConvergenceWarning,
                stacklevel=3,
            )

    def _condition_on(self, X, y):
        """Cholesky factor and weights for the current hyperparameters.

        Rows with equal inputs are folded together first (:func:`~sarsp_edu.linalg.group_rows`):
        the factor is then of the distinct inputs' size, and every quantity
        is exactly that of all the rows.
        """
        data = group_rows(X, y)
        G = data.counts.shape[0]
        K = self.kernel_.from_squared_distances(squared_distances(data.X))
        K.flat[:: G + 1] += self.noise_variance_ / data.counts
        try:
            L, jitter = cholesky_with_jitter(K)
        except np.linalg.LinAlgError as exc:
            raise np.linalg.LinAlgError(
                f"{type(self).__name__} could not factorise the training covariance "
                f"(kernel_={self.kernel_!r}, noise_variance_={self.noise_variance_:.3g}): {exc}"
            ) from None
        self.X_train_ = X
        self.y_train_ = y
        self.X_unique_ = data.X
        self.counts_ = data.counts
        self.L_ = L
        self.jitter_ = jitter
        # Alg. 2.1, line 3, on the group means
        self.alpha_ = solve_cholesky(L, data.mean)
        self.beta_, log_det = data.beta_and_log_det(L, self.alpha_, self.noise_variance_)
        self.log_marginal_likelihood_value_, _, _ = self._lml_terms(data.n, self.beta_, log_det, self.theta_[3:])
        # every row counts, repeated inputs too
        self.variance_scale_, self.df_ = self._predictive_scale(data.n, self.beta_)
        if not (np.all(np.isfinite(self.alpha_)) and np.isfinite(self.log_marginal_likelihood_value_)):
            raise FloatingPointError(
                f"{type(self).__name__} produced non-finite weights on this data "
                f"(kernel_={self.kernel_!r}, noise_variance_={self.noise_variance_:.3g}); "
                "rescale the targets or increase noise_variance"
            )

    def condition(self, X, y):
        """A copy of this fitted model conditioned on other data, hyperparameters kept.

        This is how SARSP predicts: the hyperparameters come from the last
        fit, the training points from a strategic prior drawn per decision.
        No optimisation is run, so the call costs one Cholesky factorisation.

        Returns
        -------
        model : same type as ``self``, fitted
        """
        self._check_fitted()
        X, y = check_training(X, y)
        if X.shape[1] != self.X_train_.shape[1]:
            raise ValueError(
                f"X has {X.shape[1]} features but the model was fitted on {self.X_train_.shape[1]}"
            )
        other = copy.copy(self)
        other._condition_on(X, y)
        other.fit_indices_ = None
        return other

    def predict_batch(self, X, y, X_query, include_noise: bool = False):
        """Predict from several training sets at once, with the fitted hyperparameters.

        SARSP conditions each model on a fresh *strategic prior* for every
        action (as the paper's reference code does): eight small, independent
        conditionings per decision.  This is what ``condition`` followed by
        ``predict`` computes for each, without copying the model.

        Parameters
        ----------
        X : sequence of B arrays of shape (n_b, d)
            Training inputs of each set (sizes may differ).
        y : sequence of B arrays of shape (n_b,)
        X_query : ndarray of shape (B, q, d)
            The query points of each set.
        include_noise : bool, default False
            As in :meth:`predict`.

        Returns
        -------
        mean, var : ndarray of shape (B, q)
        df : ndarray of shape (B,)
            Degrees of freedom of each predictive distribution (``inf`` for
            the GP; ``nu_ + n_b`` for the TP).

        Notes
        -----
        The kernel matrices are built in one vectorised pass each and
        factorised with direct LAPACK calls, one per set: at these sizes
        (8 sets of n = 110 or 410) that loop was measured about twice as fast
        as numpy's stacked ``linalg.cholesky``/``linalg.solve`` (0.39 against
        0.67-0.99 ms at n = 110; 7.9 against 14.6-22.2 ms at n = 410).
        Repeated rows are kept as they are (not folded as in ``fit``): the
        noise keeps the matrix positive definite, and the numbers agree with
        :meth:`condition` to rounding.
        """
        self._check_fitted()
        X_query = np.asarray(X_query, dtype=float)
        d = self.X_train_.shape[1]
        if X_query.ndim != 3 or X_query.shape[2] != d or not len(X) == len(y) == X_query.shape[0]:
            raise ValueError(
                f"X_query must have shape (B, q, {d}) and X, y one training set per row of it, got "
                f"X_query of shape {X_query.shape} with {len(X)} input and {len(y)} target sets"
            )
        kernel, s2 = self.kernel_, self.noise_variance_
        B, q = X_query.shape[:2]
        mean, var, df = np.empty((B, q)), np.empty((B, q)), np.empty(B)
        prior_var = kernel.amplitude**2  # k(x, x) of the RBF
        for b in range(B):
            X_b, y_b = X[b], y[b]
            n = y_b.shape[0]
            # one pass for K(X_b, X_b) and K(X*, X_b): the rows of [X_b; X*] against X_b
            both = kernel.from_squared_distances(squared_distances(np.concatenate([X_b, X_query[b]]), X_b))
            K, K_star = both[:n], both[n:]  # (n, n) and (q, n)
            K.flat[:: n + 1] += s2
            L = cholesky(K)  # the fast path
            if L is None:
                L, _ = cholesky_with_jitter(K)
            rhs = np.empty((n, q + 1))
            rhs[:, 0] = y_b
            rhs[:, 1:] = K_star.T
            solved = solve_cholesky(L, rhs)  # K^-1 [y, k*]
            # paper eq. 4 and eq. 5 (Alg. 2.1, lines 4-6)
            mean[b] = K_star @ solved[:, 0]
            latent = np.maximum(prior_var - np.einsum("qn,nq->q", K_star, solved[:, 1:]), 0.0)
            factor, df[b] = self._predictive_scale(n, float(y_b @ solved[:, 0]))
            var[b] = self._predictive_variance(latent, factor, s2 if include_noise else 0.0)
        return mean, var, df

    def _check_fitted(self):
        if not hasattr(self, "L_"):
            raise NotFittedError(
                f"This {type(self).__name__} is not fitted yet: call fit(X, y) before predicting"
            )

    def predict(self, X, return_std: bool = False, return_var: bool = False, return_cov: bool = False,
                include_noise: bool = False):
        """Posterior predictive mean, and optionally standard deviation, variance or covariance.

        Parameters
        ----------
        X : array-like of shape (m, d)
            Query points.
        return_std : bool, default False
            Also return the predictive standard deviation at each query point
            (as scikit-learn's ``GaussianProcessRegressor.predict``).
        return_var : bool, default False
            Also return the predictive variance at each query point
            (paper eq. 5 for the GP, eq. 6 in Shah et al.'s form for the TP).
        return_cov : bool, default False
            Also return the full predictive covariance matrix.
        include_noise : bool, default False
            Add the observation noise: the variance of a new observation ``y*``
            rather than of the latent function ``f*``.

        Returns
        -------
        mean : ndarray of shape (m,)
        std : ndarray of shape (m,), if ``return_std``
        var : ndarray of shape (m,), if ``return_var``
        cov : ndarray of shape (m, m), if ``return_cov``
            In this order, each only if asked for.
        """
        self._check_fitted()
        X = check_X(validate_data(self, X, reset=False, dtype=np.float64, ensure_all_finite=False))
        K_trans = self.kernel_.from_squared_distances(squared_distances(X, self.X_unique_))
        # paper eq. 4; Alg. 2.1, line 4
        mean = K_trans @ self.alpha_
        if not (return_std or return_var or return_cov):
            return mean
        out = [mean]
        # Alg. 2.1, line 5: v = L \ k*
        V = solve_lower(self.L_, K_trans.T)
        if return_std or return_var:
            # paper eq. 5; Alg. 2.1, line 6
            latent = self.kernel_.diag(X) - np.einsum("ij,ij->j", V, V)
            var = self._scale(np.maximum(latent, 0.0), include_noise, np.ones(len(mean)))
            out += [np.sqrt(var)] if return_std else []
            out += [var] if return_var else []
        if return_cov:
            latent = self.kernel_(X) - V.T @ V
            out.append(self._scale(0.5 * (latent + latent.T), include_noise, np.eye(len(mean))))
        return tuple(out)

    def _scale(self, latent, include_noise, noise_shape):
        noise = self.noise_variance_ * noise_shape if include_noise else 0.0
        return self._predictive_variance(latent, self.variance_scale_, noise)

    def log_marginal_likelihood(self, theta=None, eval_gradient: bool = False):
        """Log marginal likelihood of the training data.

        Parameters
        ----------
        theta : array-like, optional
            Log hyperparameters in the order of ``hyperparameter_names``.
            ``None`` means the fitted ones (``theta_``).
        eval_gradient : bool, default False
            Also return the gradient with respect to ``theta``.

        Returns
        -------
        value : float
        gradient : ndarray of shape (len(theta),), if ``eval_gradient``

        Notes
        -----
        This is the likelihood alone, without the LogNormal priors the fit
        adds; it is evaluated on all the training data, also when the fit
        searched the hyperparameters on a subset.
        """
        self._check_fitted()
        if theta is None:
            if not eval_gradient:
                return self.log_marginal_likelihood_value_
            theta = self.theta_
        theta = np.asarray(theta, dtype=float)
        expected = len(self.hyperparameter_names)
        if theta.shape != (expected,):
            raise ValueError(
                f"theta must have shape ({expected},) for {self.hyperparameter_names}, "
                f"got shape {theta.shape}"
            )
        if not np.all(np.isfinite(theta)):
            raise ValueError(f"theta must be finite, got theta={theta}")
        data = group_rows(self.X_train_, self.y_train_)
        return self._lml_from_distances(theta, squared_distances(data.X), data, eval_gradient)

    def predictive_distribution(self, X, include_noise: bool = True):
        """Marginal predictive distribution at each query point (scipy frozen).

        Parameters
        ----------
        X : array-like of shape (m, d)
        include_noise : bool, default True
            The distribution of a new observation ``y*`` (True) or of the
            latent function value ``f*`` (False).

        Returns
        -------
        scipy.stats frozen distribution, vectorised over the m points:
        normal for the GP, Student-t with ``nu + n`` degrees of freedom for
        the TP, with the variances that ``predict`` returns.
        """
        mean, var = self.predict(X, return_var=True, include_noise=include_noise)
        df = self.df_
        if math.isinf(df):
            return stats.norm(loc=mean, scale=np.sqrt(var))
        # a Student-t with df dof and scale s has variance s^2 df / (df - 2)
        return stats.t(df=df, loc=mean, scale=np.sqrt(var * (df - 2.0) / df))

    def sample_y(self, X, n_samples: int = 1, rng=None, include_noise: bool = False):
        """Draw functions from the posterior predictive.

        Parameters
        ----------
        X : array-like of shape (m, d)
        n_samples : int, default 1
        rng : None, int or numpy.random.Generator
        include_noise : bool, default False
            Add observation noise to each draw (the reference implementation's
            150-sample estimate draws with noise).

        Returns
        -------
        ndarray of shape (m, n_samples)
        """
        n_samples = check_int("n_samples", n_samples, 1)
        rng = as_generator(rng)
        mean, cov = self.predict(X, return_cov=True, include_noise=include_noise)
        L, _ = cholesky_with_jitter(cov)
        z = L @ rng.standard_normal((len(mean), n_samples))
        df = self.df_
        if math.isinf(df):
            return mean[:, None] + z
        # y = mean + sqrt((df - 2) / W) z, W ~ chi2(df), z ~ N(0, cov): a
        # multivariate t with covariance cov (Shah et al.'s parameterisation)
        return mean[:, None] + np.sqrt((df - 2.0) / rng.chisquare(df, size=n_samples))[None, :] * z


class GaussianProcess(_ProcessRegressor):
    """Gaussian-process regression with an RBF kernel (paper eqs. 4-5).

    Parameters
    ----------
    kernel : RBF, optional
        Initial kernel; default ``RBF(1.0, 1.0)``, the reference
        implementation's initial values.
    noise_variance : float, default 1.0
        Initial observation-noise variance ``s2`` (> 0).
    optimizer : {"adam", "lbfgs", None}, default "adam"
        ``"adam"``: the paper's optimiser (``learning_rate`` 0.1, 50 steps).
        ``"lbfgs"``: scipy's L-BFGS-B with the analytic gradient, run to
        convergence.  ``None``: keep the given hyperparameters.
    learning_rate : float, default 0.1
        Adam's step size.
    max_iter : int, optional
        Adam steps (default 50) or L-BFGS-B's iteration cap (default scipy's).
    prior : {"lognormal", None}, default "lognormal"
        Add LogNormal(0, 1) log priors on amplitude, length scale and noise
        variance to the objective (a MAP fit, as in the reference code).
    max_fit_points : int or None, default 1000
        Cap on the training points the hyperparameter search uses; above it a
        random subset is drawn from ``rng``.  Each Adam step costs
        O(points^3), so the cap keeps fits on thousands of points fast.
        Prediction always conditions on all the points given to ``fit``.
    bounds : (float, float), default (1e-5, 1e5)
        Box for every positive hyperparameter during the search.
    rng : None, int or numpy.random.Generator
        Source of the subset drawn when ``max_fit_points`` binds.

    Attributes
    ----------
    kernel_ : RBF
        The fitted kernel.
    noise_variance_ : float
    theta_ : ndarray of shape (3,)
        Fitted log hyperparameters, in the order of ``hyperparameter_names``.
    X_train_, y_train_ : ndarray
        The data the model conditions on.
    X_unique_ : ndarray of shape (G, d)
        The distinct rows of ``X_train_``, in order of first appearance
        (``X_train_`` itself when no input repeats).
    counts_ : ndarray of shape (G,)
        How many training rows share each distinct input.
    L_ : ndarray of shape (G, G)
        Lower Cholesky factor of ``K(U, U) + noise_variance_ diag(1 / counts_)``
        (plus ``jitter_`` on the diagonal), ``U = X_unique_``: with distinct
        inputs, of ``K(X, X) + noise_variance_ I``.  Repeated inputs are folded
        together exactly (the predictions and the likelihood are those of all
        the rows), so a cost buffer of ~4,700 rows with ~800 distinct inputs
        is factorised at the size of 800.
    alpha_ : ndarray of shape (G,)
        ``L_ L_^T`` solved against the mean target of each distinct input
        (with distinct inputs, ``K^-1 y``).
    beta_ : float
        ``y^T K^-1 y`` over all the training rows.
    variance_scale_ : float
        1.0: the factor the TP puts on the latent variance, which the GP does not.
    df_ : float
        ``inf``: the predictive distribution is a normal (the TP's has ``nu_ + n`` dof).
    log_marginal_likelihood_value_ : float
    objective_trace_ : ndarray
        The log joint (likelihood + prior) on the fit subset during the search.
    n_iter_ : int
    fit_indices_ : ndarray
        Rows of ``X`` the hyperparameter search used.
    jitter_ : float
        Diagonal jitter the final factorisation needed (usually 0).

    Examples
    --------
    >>> import numpy as np
    >>> from sarsp_edu import GaussianProcess
    >>> X = np.linspace(0, 5, 20).reshape(-1, 1)
    >>> gp = GaussianProcess(optimizer="lbfgs", prior=None).fit(X, np.sin(X[:, 0]))
    >>> mean, var = gp.predict(X[:3], return_var=True)
    >>> mean.shape, bool(np.all(var >= 0))
    ((3,), True)
    """



class StudentTProcess(_ProcessRegressor):
    """Student-t-process regression with an RBF kernel (Shah et al. 2014).

    Takes every parameter of :class:`GaussianProcess`, and:

    Parameters
    ----------
    nu : float, default 3.0
        Degrees of freedom (> 2, so that the covariance is finite).  The
        paper fixes nu = 3 (section 3.2).  As nu -> infinity the TP becomes
        the GP.
    fit_nu : bool, default False
        Also learn nu, as ``log(nu - 2)``, by maximising the marginal
        likelihood (no prior on nu).  On small data sets this tends to drive
        nu towards infinity, i.e. back to the GP, which is why the paper
        fixes it.
    noise_convention : {"shah", "tfp"}, default "shah"
        How the observation noise enters the predictive variance when
        ``include_noise=True``.  ``"shah"``: the noise is part of the
        process's covariance and is scaled with it,
        ``factor * (latent + s2)`` (Shah et al. 2014; GPy).  ``"tfp"``:
        only the latent part is scaled and the noise added unscaled,
        ``factor * latent + s2`` (TensorFlow Probability's
        ``StudentTProcessRegressionModel``, which the paper's reference code
        used).  The latent variance (``include_noise=False``) and the
        likelihood are the same in both.

    Attributes
    ----------
    nu_ : float
        The degrees of freedom used (fitted if ``fit_nu``).
    variance_scale_ : float
        ``(nu_ + beta_ - 2) / (nu_ + n - 2)``: the factor on the GP's
        predictive variance (paper eq. 6, corrected).
    df_ : float
        Degrees of freedom of the predictive distribution, ``nu_ + n``.

    Notes
    -----
    The marginal likelihood is the multivariate Student-t density with
    ``nu`` degrees of freedom and *covariance* ``K`` (shape matrix
    ``(nu - 2) / nu * K``), Shah et al. (2014), eq. 3:

    ``-n/2 log((nu-2) pi) - 1/2 log|K| + log G((nu+n)/2) - log G(nu/2)
    - (nu+n)/2 log(1 + beta/(nu-2))``.

    The paper's eq. 6 has ``K(X*, X*)^-1`` in ``beta``; the correct factor
    uses the training covariance: ``beta = y^T (K(X, X) + s2 I)^-1 y``.
    """

    _amplitude_sets_scale = False  # the variance factor grows with beta, so with y's scale

    def __init__(
        self,
        kernel: RBF | None = None,
        *,
        nu: float = NU,
        fit_nu: bool = False,
        noise_variance: float = 1.0,
        noise_convention: str = "shah",
        optimizer: str | None = "adam",
        learning_rate: float = LEARNING_RATE,
        max_iter: int | None = None,
        prior: str | None = "lognormal",
        max_fit_points: int | None = 1000,
        bounds: tuple[float, float] = (1e-5, 1e5),
        rng=None,
    ):
        self.nu = nu
        self.fit_nu = fit_nu
        self.noise_convention = noise_convention
        super().__init__(
            kernel,
            noise_variance=noise_variance,
            optimizer=optimizer,
            learning_rate=learning_rate,
            max_iter=max_iter,
            prior=prior,
            max_fit_points=max_fit_points,
            bounds=bounds,
            rng=rng,
        )

    def _check_params(self):
        super()._check_params()
        check_nu(self.nu)
        if not isinstance(self.fit_nu, (bool, np.bool_)):
            raise ValueError(f"fit_nu must be True or False, got fit_nu={self.fit_nu!r}")
        check_choice("noise_convention", self.noise_convention, NOISE_CONVENTIONS)

    # -- where the TP differs (the GP's versions are in _ProcessRegressor) --
    def _extra_hyperparameters(self):
        # nu - 2 in [1e-3, 1e8]: from very heavy tails to practically Gaussian
        return [("log_nu_minus_2", math.log(self.nu - 2.0), np.log([1e-3, 1e8]))] if self.fit_nu else []

    def _nu_from(self, extra):
        return 2.0 + math.exp(extra[0]) if len(extra) else float(self.nu)

    def _set_extra(self, extra):
        self.nu_ = self._nu_from(extra)

    def _lml_terms(self, n, beta, log_det, extra):
        nu = self._nu_from(extra)
        value = tp_log_marginal_likelihood(n, beta, log_det, nu)
        w = tp_likelihood_weight(n, beta, nu)
        if len(extra):  # chain rule: nu = 2 + exp(t)
            extra_grad = np.array([tp_log_marginal_likelihood_dnu(n, beta, nu) * (nu - 2.0)])
        else:
            extra_grad = np.empty(0)
        return value, w, extra_grad

    def _predictive_scale(self, n, beta):
        return tp_variance_factor(n, beta, self.nu_), self.nu_ + n

    def _predictive_variance(self, latent, factor, noise):
        return tp_predictive_variance(latent, factor, noise, self.noise_convention)
