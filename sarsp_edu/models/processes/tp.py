"""Student-t-process regression (Shah et al. 2014): the shared estimator with the TP's equations."""

from __future__ import annotations

import math

import numpy as np

from ..._internal.validation import check_bool, check_choice, check_nu
from ...config import HYPERPARAMETER_BOUNDS, LEARNING_RATE, NOISE_CONVENTIONS, NU
from ..kernels import RBF
from .equations import (
    tp_likelihood_weight,
    tp_log_marginal_likelihood,
    tp_log_marginal_likelihood_dnu,
    tp_predictive_variance,
    tp_variance_factor,
)
from .regressor import ProcessRegressor

__all__ = ["StudentTProcess"]


class StudentTProcess(ProcessRegressor):
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
    n_restarts : int, default 0
        Extra starts of the hyperparameter search (:class:`GaussianProcess`).
    warm_start : bool, default False
        Refits search from the last fit's hyperparameters (:class:`GaussianProcess`).

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
        bounds: tuple[float, float] = HYPERPARAMETER_BOUNDS,
        rng=None,
        n_restarts: int = 0,
        warm_start: bool = False,
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
            n_restarts=n_restarts,
            warm_start=warm_start,
        )

    def _check_params(self):
        super()._check_params()
        check_nu(self.nu)
        check_bool("fit_nu", self.fit_nu)
        check_choice("noise_convention", self.noise_convention, NOISE_CONVENTIONS)

    # -- where the TP differs (the GP's versions are in Objective) --
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
