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

How to read it, one module per job:

- :mod:`~sarsp_edu.models.processes.equations`: each row of the table above as one
  function of the sufficient statistics ``n``, ``beta`` and ``log|K|``;
- :mod:`~sarsp_edu.models.processes.objective`: what a fit maximises, the log
  marginal likelihood with its gradient and the priors, through four hooks
  (the GP's there, the TP's in :class:`StudentTProcess` under "where the TP
  differs");
- :mod:`~sarsp_edu.models.processes.regressor`: the estimator both share, a
  scikit-learn regressor: the fit, conditioning and prediction (the
  factorisations and solves are in :mod:`sarsp_edu.models.linalg`, the optimisers
  in :mod:`sarsp_edu.models.optimizers`);
- :mod:`~sarsp_edu.models.processes.gp` and :mod:`~sarsp_edu.models.processes.tp`: the two
  models, mostly their documentation;
- :mod:`~sarsp_edu.models.processes.likelihood`: for contrast, a GP with a Student-t
  *likelihood* (Laplace approximation), a model whose mean does discount
  outliers, which neither of the two above does.
"""

from .equations import (
    gp_log_marginal_likelihood,
    tp_likelihood_weight,
    tp_log_marginal_likelihood,
    tp_log_marginal_likelihood_dnu,
    tp_predictive_variance,
    tp_variance_factor,
)
from .gp import GaussianProcess
from .likelihood import StudentTLikelihoodGP, student_t_log_likelihood
from .objective import ConvergenceWarning
from .regressor import NotFittedError
from .tp import StudentTProcess

__all__ = [
    "ConvergenceWarning", "GaussianProcess", "NotFittedError", "StudentTLikelihoodGP", "StudentTProcess",
    "gp_log_marginal_likelihood",
    "tp_likelihood_weight", "tp_log_marginal_likelihood", "tp_log_marginal_likelihood_dnu",
    "student_t_log_likelihood", "tp_predictive_variance", "tp_variance_factor",
]
