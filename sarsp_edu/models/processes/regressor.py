"""The estimator both models share: scikit-learn's API, the fit, conditioning and prediction.

The hyperparameter search maximises :class:`~sarsp_edu.models.processes.objective.Objective`'s
log joint; the factorisations and solves are in :mod:`sarsp_edu.models.linalg`
(fast paths named as such), the two optimisers in :mod:`sarsp_edu.models.optimizers`.
"""

from __future__ import annotations

import copy
import math

import numpy as np
from scipy import stats
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.exceptions import NotFittedError
from sklearn.utils.validation import validate_data

from ..._internal.rng import as_generator, draw_subset
from ..._internal.validation import (
    check_bool,
    check_choice,
    check_int,
    check_positive,
    check_positive_pair,
    check_training,
    check_X,
)
from ...config import ADAM_STEPS, HYPERPARAMETER_BOUNDS, LEARNING_RATE, OPTIMIZERS, PRIORS
from ..kernels import RBF, DistanceLevels, squared_distances, whole_distance_bound
from ..linalg import cholesky_with_jitter, group_rows, solve_cholesky, solve_lower
from ..optimizers import best_of_starts, projected_gradient_norm, restart_points, searcher
from .conditioning import ConditioningSteps, condition_sets
from .objective import Objective

__all__ = ["NotFittedError", "ProcessRegressor"]


class ProcessRegressor(Objective, RegressorMixin, BaseEstimator):
    """Shared machinery of :class:`GaussianProcess` and :class:`StudentTProcess`.

    Both are scikit-learn regressors: ``get_params``/``set_params`` (nested
    ``kernel__length_scale`` too), ``clone``, ``score`` (R^2), pipelines and
    grid searches work as for any scikit-learn estimator, and the arguments
    are checked in ``fit``, as scikit-learn's conventions ask.
    """

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
        bounds: tuple[float, float] = HYPERPARAMETER_BOUNDS,
        rng=None,
        n_restarts: int = 0,
        warm_start: bool = False,
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
        self.n_restarts = n_restarts
        self.warm_start = warm_start

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
        check_int("n_restarts", self.n_restarts, 0)
        check_bool("warm_start", self.warm_start)
        check_positive_pair("bounds", self.bounds)
        if not isinstance(self.rng, np.random.Generator):
            as_generator(self.rng)  # raises a clear error for anything else

    def _start_kernel(self) -> RBF:
        """The kernel every fit starts from: ``kernel``, or RBF(1, 1) when it is None."""
        return RBF() if self.kernel is None else self.kernel

    # -- public API --------------------------------------------------------
    def fit(self, X, y, *, on_step=None):
        """Fit the hyperparameters (unless ``optimizer=None``) and condition on the data.

        Every fit starts from the constructor's hyperparameters (with
        ``warm_start``, a refit from the last fit's, one start).  The
        hyperparameter search uses at most ``max_fit_points`` training points
        (a random subset drawn from ``rng``); the fitted model then conditions
        on *all* of ``X, y``.

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
        self._check_params()
        # scikit-learn's checks of shape, type and length (complex or sparse data refused, y of shape
        # (n, 1) flattened with a warning; sets n_features_in_), then ours, which name a non-finite entry
        X, y = validate_data(self, X, y, y_numeric=True, dtype=np.float64, ensure_all_finite=False)
        X, y = check_training(X, y)
        warm = self.warm_start and self.optimizer is not None and hasattr(self, "theta_")
        theta0 = np.array(self.theta_) if warm else self._initial_theta()
        if self.optimizer is None:
            theta, trace, n_iter = theta0, [], 0
            self.fit_indices_ = np.arange(X.shape[0])
            self.start_objectives_, self.gradient_norm_ = np.array([]), math.nan
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
            levels = self._distance_levels(data.X, D2)

            def negative(theta):
                value, grad = self._log_joint(theta, D2, data, work, levels)
                return -value, -grad

            steps = ADAM_STEPS if self.max_iter is None else self.max_iter
            if self.optimizer == "adam":
                self._warn_out_of_reach(y, steps)
            search = searcher(self.optimizer, negative, bounds, self.learning_rate, steps, self.max_iter, len(idx),
                              on_step)
            starts = restart_points(theta0, bounds, 0 if warm else self.n_restarts)
            theta, trace, n_iter, finals = best_of_starts(search, starts)
            trace = [-v for v in trace]
            self.start_objectives_, self.gradient_norm_ = -np.asarray(finals), projected_gradient_norm(
                negative(theta)[1], theta, bounds)
            self._warn_on_bounds(theta, bounds)
        self.theta_ = np.asarray(theta, dtype=float)
        self.kernel_, self.noise_variance_, extra = self._unpack(self.theta_)
        self._set_extra(extra)
        self.n_iter_ = n_iter
        #: log joint (log marginal likelihood + log prior) on the fit subset, per step
        self.objective_trace_ = np.asarray(trace, dtype=float)
        self._condition_on(X, y)
        return self

    @staticmethod
    def _distance_levels(X, D2) -> DistanceLevels | None:
        """The levels a fit evaluates its kernel on (the same bits as every entry), or None.

        Only for whole-number inputs (the grid world's), whose distances
        repeat: real-valued ones have as many values as entries, and sorting
        them to find out would cost a fit up to a second.
        """
        return DistanceLevels.if_few(D2) if whole_distance_bound(X) is not None else None

    def _condition_on(self, X, y):
        """Cholesky factor and weights for the current hyperparameters.

        Rows with equal inputs are folded together first (:func:`~sarsp_edu.models.linalg.group_rows`):
        the factor is then of the distinct inputs' size, and every quantity
        is exactly that of all the rows.
        """
        data = group_rows(X, y)
        try:
            L, jitter = cholesky_with_jitter(self._training_covariance(data))
        except np.linalg.LinAlgError as exc:
            raise np.linalg.LinAlgError(
                f"{type(self).__name__} could not factorise the training covariance "
                f"(kernel_={self.kernel_!r}, noise_variance_={self.noise_variance_:.3g}): {exc}"
            ) from None
        self._adopt_factor(X, y, data, L, jitter)

    def _training_covariance(self, data):
        """K_y of the folded rows ``data`` under the fitted hyperparameters (a group's noise over its count)."""
        K = self.kernel_.from_squared_distances(squared_distances(data.X))
        K.flat[:: data.counts.shape[0] + 1] += self.noise_variance_ / data.counts
        return K

    def _adopt_factor(self, X, y, data, L, jitter):
        """The fitted state from the training rows (``data``: folded) and their covariance's Cholesky factor."""
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

        Parameters
        ----------
        X : array-like of shape (n, d)
            Training inputs, with the fitted model's number of features.
        y : array-like of shape (n,)

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

    def predict_batch(self, X, y, X_query, include_noise: bool = False, *, whole_bound: float | None = None,
                      kernels=None, steps: ConditioningSteps | None = None):
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
        whole_bound : float, optional
            The caller's guarantee that every input is a whole number and
            every squared distance between them at most this
            (:func:`~sarsp_edu.models.kernels.whole_distance_bound` of all the rows
            the sets are drawn from and the queries): the kernel is then
            looked up without checking each distance.  The numbers are the
            same with or without it; it is checked in one pass over the rows
            (a ValueError where it does not hold), not over every distance.
        kernels : sequence of B pairs ``(K, K_star)``, optional
            The kernel matrices of each set, ``kernel_(X_b)`` of shape
            (n_b, n_b) and ``kernel_(X_query[b], X_b)`` of shape (q, n_b),
            gathered by the caller (from a :class:`~sarsp_edu.models.kernels.KernelTable`)
            instead of built here.  Each ``K`` must be a C-ordered array of
            its own: it is overwritten by its Cholesky factor.
        steps : ConditioningSteps, optional
            Replacements for the kernel, the posterior or the TP factor
            (a student's parts): the same loop calls them in place of the
            model's own steps and checks what they return
            (:mod:`~sarsp_edu.models.processes.conditioning`).

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
        return condition_sets(self, X, y, X_query, include_noise, whole_bound=whole_bound, kernels=kernels,
                              steps=steps)

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
