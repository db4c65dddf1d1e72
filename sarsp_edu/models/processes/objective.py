"""What a fit maximises: the log marginal likelihood of either model, its gradient, the priors.

:class:`Objective` is the half of the shared model that turns log
hyperparameters ``theta`` into a number and its gradient; the hooks under
"where the TP differs" are the GP's, and :class:`~sarsp_edu.models.processes.StudentTProcess`
overrides them with the TP's equations (:mod:`sarsp_edu.models.processes.equations`).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from sklearn.exceptions import ConvergenceWarning

from ..kernels import squared_distances
from ..linalg import (
    GroupedRows,
    cholesky,
    cholesky_with_jitter,
    group_rows,
    inverse_from_cholesky,
    solve_cholesky,
    trace_of_product,
)
from .equations import LOG_2PI, gp_log_marginal_likelihood

__all__ = ["ConvergenceWarning", "Objective"]


class Objective:
    """Log hyperparameters, the log marginal likelihood with its gradient, the log priors (a mixin)."""

    #: names of the log hyperparameters, in the order of ``theta``
    _base_names = ("log_amplitude", "log_length_scale", "log_noise_variance")
    #: whether the fitted amplitude and noise alone set the predictive scale
    #: (the GP's); the TP's global variance factor follows y's scale itself
    _amplitude_sets_scale = True

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
        return float(np.sum(-t - 0.5 * t * t - 0.5 * LOG_2PI)), grad

    def _lml_from_distances(self, theta, D2, data: GroupedRows, eval_gradient, work=None, levels=None):
        """Log marginal likelihood (and gradient) at ``theta`` of grouped data.

        ``D2`` holds the squared distances between the distinct inputs
        ``data.X``; the value is exactly that of all ``data.n`` rows (see
        :func:`~sarsp_edu.models.linalg.group_rows`).  ``work`` is an optional (3, G, G) workspace reused
        across a fit's steps: the kernel is written into it and factorised
        in place.  ``levels`` (:class:`~sarsp_edu.models.kernels.DistanceLevels` of
        ``D2``, optional) has the kernel evaluated on D2's distinct values.
        """
        kernel, s2, extra = self._unpack(theta)
        G, n = data.counts.shape[0], data.n
        noise = s2 / data.counts  # the diagonal of s2 N^-1
        if eval_gradient:
            K, dK = kernel.from_squared_distances(D2, eval_gradient=True, out=work, levels=levels)
        else:
            K = kernel.from_squared_distances(D2, out=work, levels=levels)
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

    def _log_joint(self, theta, D2, data, work=None, levels=None):
        value, grad = self._lml_from_distances(theta, D2, data, eval_gradient=True, work=work, levels=levels)
        prior, prior_grad = self._log_prior(theta)
        return value + prior, grad + prior_grad


    def log_marginal_likelihood(self, theta=None, eval_gradient: bool = False, *, fold_repeats: bool = True):
        """Log marginal likelihood of the training data.

        Parameters
        ----------
        theta : array-like, optional
            Log hyperparameters in the order of ``hyperparameter_names``.
            ``None`` means the fitted ones (``theta_``).
        eval_gradient : bool, default False
            Also return the gradient with respect to ``theta``.
        fold_repeats : bool, default True
            Fold rows with equal inputs into one before factorising (what a
            fit does: exact, and the size of the distinct inputs; see
            :func:`~sarsp_edu.models.linalg.group_rows`).  False takes the textbook
            path over every row, to check that the folding changes nothing.

        Returns
        -------
        value : float
        gradient : ndarray of shape (len(theta),), if ``eval_gradient``

        Notes
        -----
        This is the likelihood alone, without the LogNormal priors the fit
        adds (:meth:`log_joint` has both); it is evaluated on all the
        training data, also when the fit searched the hyperparameters on a
        subset.
        """
        if theta is None and not eval_gradient and fold_repeats:
            self._check_fitted()
            return self.log_marginal_likelihood_value_
        theta, data, D2 = self._objective_inputs(theta, fold_repeats)
        return self._lml_from_distances(theta, D2, data, eval_gradient)

    def log_joint(self, theta=None, eval_gradient: bool = False, *, fold_repeats: bool = True):
        """What a fit maximises: the log marginal likelihood plus the log priors (with ``prior="lognormal"``).

        Takes the arguments of :meth:`log_marginal_likelihood`.  A fit
        evaluates it on the rows its search uses (all of them unless
        ``max_fit_points`` binds); this is on all the training data.

        Parameters
        ----------
        theta, eval_gradient, fold_repeats
            As in :meth:`log_marginal_likelihood`.
        """
        theta, data, D2 = self._objective_inputs(theta, fold_repeats)
        value, grad = self._lml_from_distances(theta, D2, data, eval_gradient=True)
        prior, prior_grad = self._log_prior(theta)
        return (value + prior, grad + prior_grad) if eval_gradient else value + prior

    def _objective_inputs(self, theta, fold_repeats):
        """``theta`` checked (the fitted one if None), the training rows grouped, and their squared distances."""
        self._check_fitted()
        theta = self.theta_ if theta is None else np.asarray(theta, dtype=float)
        expected = len(self.hyperparameter_names)
        if theta.shape != (expected,):
            raise ValueError(
                f"theta must have shape ({expected},) for {self.hyperparameter_names}, "
                f"got shape {theta.shape}"
            )
        if not np.all(np.isfinite(theta)):
            raise ValueError(f"theta must be finite, got theta={theta}")
        rows = group_rows if fold_repeats else GroupedRows.ungrouped
        data = rows(self.X_train_, self.y_train_)
        return theta, data, squared_distances(data.X)

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
