"""StudentTLikelihoodGP against a dense Laplace approximation written here from the textbook, nothing of the package's.

The reference finds the posterior mode with scipy's optimiser on the exact log posterior (scipy's Student-t
density), polishes it with Newton steps on explicit inverses, and evaluates Rasmussen and Williams' (2006)
eqs. 3.21, 3.24 and 3.32 with ``K^-1`` written out.  Rows with equal inputs share one latent value, as they
must (two equal inputs are one value of the function); the data hold outliers whose curvature ``W`` is
negative, where the textbook's ``B = I + W^1/2 K W^1/2`` does not exist and ``det(I + K W)`` stands for it.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import optimize, stats

from sarsp_edu import RBF, StudentTLikelihoodGP


def rbf(A, B, amplitude, length_scale):
    d2 = ((A[:, None, :] - B[None, :, :]) ** 2).sum(-1)
    return amplitude**2 * np.exp(-0.5 * d2 / length_scale**2)


def dense_laplace(X, y, amplitude, length_scale, nu, scale, X_star):
    """The Laplace approximation, dense: (mean, latent variance) at X_star and log q."""
    U, group = np.unique(X, axis=0, return_inverse=True)
    group = group.ravel()
    m = len(U)
    K = rbf(U, U, amplitude, length_scale)
    K_inv = np.linalg.inv(K)
    noise = stats.t(df=nu, scale=scale)

    def log_lik(f):
        return noise.logpdf(y - f[group]).sum()

    def grad_and_w(f):  # d/df log p and minus d2/df2, each summed over an input's rows
        r = y - f[group]
        c = nu * scale**2
        g = (nu + 1) * r / (c + r * r)
        w = (nu + 1) * (c - r * r) / (c + r * r) ** 2
        return np.bincount(group, g, m), np.bincount(group, w, m)

    def negative(f):
        g, _ = grad_and_w(f)
        return -(log_lik(f) - 0.5 * f @ K_inv @ f), -(g - K_inv @ f)

    f = optimize.minimize(negative, np.zeros(m), jac=True, method="BFGS", options={"gtol": 1e-10}).x
    for _ in range(20):  # Newton's steps from there, on the explicit inverses
        g, w = grad_and_w(f)
        f = f + np.linalg.solve(K_inv + np.diag(w), g - K_inv @ f)
    g, w = grad_and_w(f)
    assert np.max(np.abs(g - K_inv @ f)) < 1e-9  # the mode
    assert np.all(np.linalg.eigvalsh(K_inv + np.diag(w)) > 0)  # a maximum
    log_q = log_lik(f) - 0.5 * f @ K_inv @ f - 0.5 * np.linalg.slogdet(np.eye(m) + K @ np.diag(w))[1]
    k_star = rbf(X_star, U, amplitude, length_scale)
    mean = k_star @ K_inv @ f
    covariance = np.linalg.inv(K_inv + np.diag(w))
    var = amplitude**2 - np.einsum("ij,jk,ik->i", k_star, K_inv, k_star) \
        + np.einsum("ij,jk,ik->i", k_star @ K_inv, covariance, k_star @ K_inv)
    r = y - f[group]
    return mean, var, log_q, (nu + 1) * (nu * scale**2 - r * r) / (nu * scale**2 + r * r) ** 2  # W per row


def data(dimension, seed):
    """Inputs on a coarse lattice (so that rows repeat), a smooth function, and outliers far off it."""
    rng = np.random.default_rng(seed)
    n = 40 if dimension == 1 else 60
    X = rng.integers(0, 24 if dimension == 1 else 3, size=(n, dimension)).astype(float) * (0.25 if dimension == 1
                                                                                           else 0.7)
    y = np.sin(X).sum(axis=1) + 0.1 * rng.standard_normal(n)
    outliers = rng.choice(n, 6, replace=False)
    y[outliers] += rng.choice([-1.0, 1.0], 6) * rng.uniform(4, 9, 6)
    return X, y


@pytest.mark.parametrize("dimension, seed, length_scale, nu, scale", [
    (1, 0, 0.5, 3.0, 0.3),
    (1, 1, 0.6, 2.5, 0.4),
    (5, 2, 0.9, 3.0, 0.4),
    (5, 3, 1.1, 5.0, 0.5),
])
def test_the_mean_the_latent_variance_and_log_q_are_the_dense_laplaces(dimension, seed, length_scale, nu, scale):
    X, y = data(dimension, seed)
    assert len(np.unique(X, axis=0)) < len(X)  # rows repeat
    rng = np.random.default_rng(seed + 10)
    X_star = np.vstack([X[:3], rng.uniform(0, 2, (5, dimension))])
    mean, var, log_q, row_w = dense_laplace(X, y, 1.3, length_scale, nu, scale, X_star)
    assert np.any(row_w < 0)  # rows of negative curvature: outliers the mode discounts
    model = StudentTLikelihoodGP(RBF(1.3, length_scale), nu=nu, scale=scale, optimizer=None).fit(X, y)
    got_mean, got_var = model.predict(X_star, return_var=True)
    np.testing.assert_allclose(got_mean, mean, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(got_var, var, rtol=1e-6, atol=1e-6)
    assert model.log_marginal_likelihood_value_ == pytest.approx(log_q, rel=1e-6, abs=1e-6)


def gpy_laplace(X, y, amplitude, length_scale, nu, scale, X_star):
    """GPy's Laplace approximation of the same model: (mean, latent variance) at X_star and its log q."""
    import warnings

    gpy = pytest.importorskip("GPy")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # GPy's own deprecation warnings, not the package's
        model = gpy.core.GP(X, y[:, None], kernel=gpy.kern.RBF(X.shape[1], variance=amplitude**2,
                                                             lengthscale=length_scale),
                            likelihood=gpy.likelihoods.StudentT(deg_free=nu, sigma2=scale**2),
                            inference_method=gpy.inference.latent_function_inference.Laplace())
        mean, var = model.predict_noiseless(X_star)
    return mean[:, 0], var[:, 0], float(model.log_likelihood())


@pytest.mark.parametrize("dimension", [1, 5])
def test_gpys_laplace_agrees_where_every_curvature_is_positive(dimension):
    rng = np.random.default_rng(dimension)
    X = rng.uniform(0, 3, (30, dimension))  # no repeated rows: GPy gives each row a latent value of its own
    y = np.sin(X).sum(axis=1) + 0.1 * rng.standard_normal(30)
    X_star = rng.uniform(0, 3, (6, dimension))
    mean, var, log_q = gpy_laplace(X, y, 1.3, 0.8, 4.0, 0.3, X_star)
    model = StudentTLikelihoodGP(RBF(1.3, 0.8), nu=4.0, scale=0.3, optimizer=None).fit(X, y)
    assert np.all(model.W_ > 0)
    got_mean, got_var = model.predict(X_star, return_var=True)
    np.testing.assert_allclose(got_mean, mean, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(got_var, var, rtol=1e-6, atol=1e-6)
    assert model.log_marginal_likelihood_value_ == pytest.approx(log_q, rel=1e-6)


def test_where_a_curvature_is_negative_gpy_parts_from_the_exact_laplace_and_the_package_does_not():
    """GPy clips each row's W at 1e-6 from below (its Laplace needs W >= 0 for B = I + W^1/2 K W^1/2) and so
    finds another approximation where an outlier's curvature is negative: its variance is off by about 1% here,
    while the package keeps the negative W and agrees with the dense reference."""
    rng = np.random.default_rng(0)
    X = np.linspace(0, 6, 25)[:, None]
    y = np.sin(X[:, 0]) + 0.1 * rng.standard_normal(25)
    y[[3, 9, 15, 20]] += [5.0, -6.0, 7.0, -5.0]
    X_star = np.linspace(0.1, 5.9, 6)[:, None]
    mean, var, log_q, row_w = dense_laplace(X, y, 1.3, 0.4, 4.0, 0.3, X_star)
    assert np.sum(row_w < 0) == 4
    gpy_mean, gpy_var, gpy_log_q = gpy_laplace(X, y, 1.3, 0.4, 4.0, 0.3, X_star)
    assert np.max(np.abs(gpy_var - var) / var) > 1e-3 and abs(gpy_log_q - log_q) > 1e-3
    got_mean, got_var = StudentTLikelihoodGP(RBF(1.3, 0.4), nu=4.0, scale=0.3, optimizer=None).fit(X, y).predict(
        X_star, return_var=True)
    np.testing.assert_allclose(got_var, var, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(got_mean, mean, rtol=1e-6, atol=1e-6)
