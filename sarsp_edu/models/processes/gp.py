"""Gaussian-process regression (paper eqs. 4-5): the shared estimator with the GP's own equations."""

from __future__ import annotations

from .regressor import ProcessRegressor

__all__ = ["GaussianProcess"]


class GaussianProcess(ProcessRegressor):
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
    n_restarts : int, default 0
        Extra starts of the hyperparameter search, the best log joint kept
        (:func:`~sarsp_edu.models.optimizers.restart_points`: narrow noise
        first, then wide noise, short and long length scales, low and high
        amplitude); deterministic.
    warm_start : bool, default False
        As scikit-learn's estimators: a refit searches from the last fit's
        hyperparameters, one start (``n_restarts`` count only in a first
        fit); the SARSP agent's online refits with ``warm_refits``.

    Attributes
    ----------
    gradient_norm_ : float
        The log joint's gradient norm where the search ended (NaN without
        one): near 0 at an optimum; a short Adam search may stop far from it.
    start_objectives_ : ndarray
        The final log joint of each start's search, the first from the
        constructor's values.
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
