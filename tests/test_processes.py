from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy import stats
from scipy.optimize import approx_fprime

from sarsp_edu import RBF, GaussianProcess, NotFittedError, StudentTProcess
from tests.conftest import make_data

HYPER = dict(amplitude=1.3, length_scale=1.7, noise_variance=0.05)


def fixed(model_cls, **kwargs):
    """A model with the HYPER hyperparameters and no optimisation."""
    params = dict(kernel=RBF(HYPER["amplitude"], HYPER["length_scale"]),
                  noise_variance=HYPER["noise_variance"], optimizer=None)
    params.update(kwargs)
    return model_cls(**params)


def sklearn_gpr(X, y, noisy_kernel: bool):
    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import RBF as SkRBF, ConstantKernel, WhiteKernel

    latent = ConstantKernel(HYPER["amplitude"] ** 2) * SkRBF(HYPER["length_scale"])
    if noisy_kernel:  # noise in the kernel: predict's variance includes it
        kernel, alpha = latent + WhiteKernel(HYPER["noise_variance"]), 0.0
    else:  # noise as alpha: predict's variance is the latent one
        kernel, alpha = latent, HYPER["noise_variance"]
    return GaussianProcessRegressor(kernel, alpha=alpha, optimizer=None).fit(X, y)


# --------------------------------------------------------------------------
# the GP against scikit-learn
# --------------------------------------------------------------------------
def test_gp_matches_scikit_learn(dataset):
    X, y = dataset
    Xq = make_data(99, n=8, d=X.shape[1])[0]
    gp = fixed(GaussianProcess).fit(X, y)
    mean, var = gp.predict(Xq, return_var=True)
    _, var_noisy = gp.predict(Xq, return_var=True, include_noise=True)
    _, cov = gp.predict(Xq, return_cov=True)

    sk_latent = sklearn_gpr(X, y, noisy_kernel=False)
    sk_mean, sk_std = sk_latent.predict(Xq, return_std=True)
    _, sk_cov = sk_latent.predict(Xq, return_cov=True)
    np.testing.assert_allclose(mean, sk_mean, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(var, sk_std**2, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(cov, sk_cov, rtol=1e-8, atol=1e-12)

    sk_noisy = sklearn_gpr(X, y, noisy_kernel=True)
    _, sk_std_noisy = sk_noisy.predict(Xq, return_std=True)
    np.testing.assert_allclose(var_noisy, sk_std_noisy**2, rtol=1e-8)

    assert gp.log_marginal_likelihood() == pytest.approx(sk_noisy.log_marginal_likelihood_value_, rel=1e-8)
    assert gp.log_marginal_likelihood() == pytest.approx(sk_latent.log_marginal_likelihood_value_, rel=1e-8)


def test_gp_gradient_matches_scikit_learn(dataset):
    """scikit-learn's theta holds log(amplitude^2): our d/dlog a is twice its d/dlog a^2."""
    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import RBF as SkRBF, ConstantKernel, WhiteKernel

    X, y = dataset
    gp = fixed(GaussianProcess).fit(X, y)
    sk = GaussianProcessRegressor(
        ConstantKernel(1.0) * SkRBF(1.0) + WhiteKernel(1.0), alpha=0.0, optimizer=None
    ).fit(X, y)
    theta = gp.theta_
    sk_theta = np.array([2 * theta[0], theta[1], theta[2]])
    value, grad = gp.log_marginal_likelihood(theta, eval_gradient=True)
    sk_value, sk_grad = sk.log_marginal_likelihood(sk_theta, eval_gradient=True)
    assert value == pytest.approx(sk_value, rel=1e-8)
    np.testing.assert_allclose(grad, sk_grad * np.array([2.0, 1.0, 1.0]), rtol=1e-7, atol=1e-9)


# --------------------------------------------------------------------------
# the TP against scipy and Shah et al. (2014)
# --------------------------------------------------------------------------
@pytest.mark.parametrize("nu", [2.5, 3.0, 5.0, 30.0])
def test_tp_likelihood_is_scipy_multivariate_t(dataset, nu):
    X, y = dataset
    tp = fixed(StudentTProcess, nu=nu).fit(X, y)
    K = RBF(HYPER["amplitude"], HYPER["length_scale"])(X) + HYPER["noise_variance"] * np.eye(len(X))
    expected = stats.multivariate_t(loc=np.zeros(len(X)), shape=(nu - 2) / nu * K, df=nu).logpdf(y)
    assert tp.log_marginal_likelihood() == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("convention", ["shah", "tfp"])
def test_tp_variance_is_scaled_gp_variance(dataset, convention):
    X, y = dataset
    Xq = make_data(7, n=6, d=X.shape[1])[0]
    nu = 3.0
    gp = fixed(GaussianProcess).fit(X, y)
    tp = fixed(StudentTProcess, nu=nu, noise_convention=convention).fit(X, y)
    n = len(y)
    beta = y @ np.linalg.solve(
        RBF(HYPER["amplitude"], HYPER["length_scale"])(X) + HYPER["noise_variance"] * np.eye(n), y
    )
    factor = (nu + beta - 2) / (nu + n - 2)  # Shah et al. 2014, eq. 7 (paper eq. 6, corrected)
    assert tp.variance_scale_ == pytest.approx(factor, rel=1e-10)
    assert tp.df_ == nu + n

    gp_mean, gp_var = gp.predict(Xq, return_var=True)
    tp_mean, tp_var = tp.predict(Xq, return_var=True)
    np.testing.assert_allclose(tp_mean, gp_mean, rtol=1e-12)  # paper eq. 4: the same mean
    np.testing.assert_allclose(tp_var, factor * gp_var, rtol=1e-10)

    _, tp_noisy = tp.predict(Xq, return_var=True, include_noise=True)
    s2 = HYPER["noise_variance"]
    expected = factor * (gp_var + s2) if convention == "shah" else factor * gp_var + s2
    np.testing.assert_allclose(tp_noisy, expected, rtol=1e-10)


def test_tp_tends_to_gp_as_nu_grows(dataset):
    X, y = dataset
    Xq = make_data(8, n=5, d=X.shape[1])[0]
    gp = fixed(GaussianProcess).fit(X, y)
    _, gp_var = gp.predict(Xq, return_var=True)
    gaps = []
    for nu in [3.0, 30.0, 3e3, 3e5, 3e7]:
        tp = fixed(StudentTProcess, nu=nu).fit(X, y)
        _, tp_var = tp.predict(Xq, return_var=True)
        gaps.append((abs(tp.log_marginal_likelihood() - gp.log_marginal_likelihood()),
                     np.max(np.abs(tp_var - gp_var))))
    lml_gaps, var_gaps = np.array(gaps).T
    assert np.all(np.diff(lml_gaps) < 0) and np.all(np.diff(var_gaps) < 0)
    assert lml_gaps[-1] < 1e-4 and var_gaps[-1] < 1e-5 * gp_var.max()


def test_predictive_distributions(dataset):
    X, y = dataset
    Xq = make_data(5, n=4, d=X.shape[1])[0]
    gp = fixed(GaussianProcess).fit(X, y)
    tp = fixed(StudentTProcess, nu=3.0).fit(X, y)
    for model in (gp, tp):
        mean, var = model.predict(Xq, return_var=True, include_noise=True)
        dist = model.predictive_distribution(Xq)
        np.testing.assert_allclose(dist.mean(), mean, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(dist.var(), var, rtol=1e-10)
    assert tp.predictive_distribution(Xq).kwds["df"] == 3.0 + len(y)


@pytest.mark.parametrize("model_cls", [GaussianProcess, StudentTProcess])
def test_samples_have_the_predicted_moments(model_cls):
    X, y = make_data(3, n=20, d=2)
    Xq = make_data(4, n=3, d=2)[0]
    model = fixed(model_cls).fit(X, y)
    mean, cov = model.predict(Xq, return_cov=True, include_noise=True)
    draws = model.sample_y(Xq, n_samples=40_000, rng=0, include_noise=True)
    assert draws.shape == (3, 40_000)
    se = np.sqrt(np.diag(cov) / 40_000)
    np.testing.assert_array_less(np.abs(draws.mean(axis=1) - mean), 5 * se)
    np.testing.assert_allclose(np.cov(draws), cov, rtol=0.08, atol=1e-3)
    np.testing.assert_array_equal(draws, model.sample_y(Xq, 40_000, rng=0, include_noise=True))


def test_tp_samples_are_student_t():
    X, y = make_data(3, n=4, d=1)  # few points: df = nu + n = 7, visibly heavy tails
    tp = fixed(StudentTProcess, nu=3.0).fit(X, y)
    Xq = np.array([[0.3]])
    draws = tp.sample_y(Xq, n_samples=20_000, rng=1, include_noise=True)[0]
    dist = tp.predictive_distribution(Xq)
    ks = stats.kstest(draws, lambda v: dist.cdf(v))
    assert ks.pvalue > 1e-3
    gauss = stats.norm(dist.mean(), dist.std())
    assert stats.kstest(draws, lambda v: gauss.cdf(v)).statistic > ks.statistic


# --------------------------------------------------------------------------
# gradients and optimisation
# --------------------------------------------------------------------------
@pytest.mark.parametrize(
    "model",
    [fixed(GaussianProcess), fixed(StudentTProcess, nu=3.0), fixed(StudentTProcess, nu=4.0, fit_nu=True)],
    ids=["gp", "tp", "tp-fit-nu"],
)
def test_gradients_match_finite_differences(dataset, model):
    X, y = dataset
    model.fit(X, y)
    rng = np.random.default_rng(0)
    for _ in range(3):
        theta = model.theta_ + rng.normal(scale=0.3, size=model.theta_.shape)
        _, grad = model.log_marginal_likelihood(theta, eval_gradient=True)
        fd = approx_fprime(theta, lambda t: model.log_marginal_likelihood(t), 1e-6)
        np.testing.assert_allclose(grad, fd, rtol=1e-4, atol=1e-4 * max(1.0, np.abs(fd).max()))


def test_prior_gradient_matches_finite_differences():
    X, y = make_data(0, n=15, d=2)
    model = StudentTProcess(optimizer=None).fit(X, y)
    theta = np.array([0.3, -0.2, -1.0])
    _, grad = model.log_joint(theta, eval_gradient=True)
    fd = approx_fprime(theta, lambda t: model.log_joint(t), 1e-6)
    np.testing.assert_allclose(grad, fd, rtol=1e-4, atol=1e-5)
    # the joint is the likelihood plus the LogNormal(0, 1) densities of the three positive values
    lognormal = sum(stats.lognorm(s=1.0).logpdf(v) for v in np.exp(theta))
    assert model.log_joint(theta) == pytest.approx(model.log_marginal_likelihood(theta) + lognormal, rel=1e-12)
    assert StudentTProcess(optimizer=None, prior=None).fit(X, y).log_joint(theta) == \
        pytest.approx(model.log_marginal_likelihood(theta), rel=1e-12)


@pytest.mark.parametrize("model_cls", [GaussianProcess, StudentTProcess])
@pytest.mark.parametrize("optimizer", ["adam", "lbfgs"])
def test_optimisers_raise_the_objective(model_cls, optimizer):
    X, y = make_data(1, n=60, d=5)
    model = model_cls(optimizer=optimizer).fit(X, y)
    trace = model.objective_trace_
    assert trace[-1] > trace[0] + 1.0
    assert model.log_marginal_likelihood() > model_cls(optimizer=None).fit(X, y).log_marginal_likelihood()
    if optimizer == "adam":
        assert model.n_iter_ == 50 and len(trace) == 51  # the paper's 50 steps


def test_lbfgs_reaches_scikit_learns_optimum():
    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import RBF as SkRBF, ConstantKernel, WhiteKernel

    X, y = make_data(2, n=80, d=5)
    ours = GaussianProcess(optimizer="lbfgs", prior=None).fit(X, y)
    sk = GaussianProcessRegressor(
        ConstantKernel(1.0, (1e-10, 1e10)) * SkRBF(1.0, (1e-5, 1e5)) + WhiteKernel(1.0, (1e-5, 1e5)),
        alpha=0.0,
    ).fit(X, y)
    assert ours.log_marginal_likelihood() >= sk.log_marginal_likelihood_value_ - 1e-4


def test_every_fit_starts_from_the_constructor_values():
    X, y = make_data(1, n=40, d=3)
    model = GaussianProcess()
    first = model.fit(X, y).theta_.copy()
    second = model.fit(X, y).theta_
    np.testing.assert_array_equal(first, second)
    assert model.kernel is None and model.noise_variance == 1.0  # the arguments, untouched by fit
    assert model.kernel_ != RBF(1.0, 1.0)  # the fitted kernel lives apart


def test_fixed_seed_is_deterministic_with_a_subset():
    X, y = make_data(4, n=300, d=5)
    a = StudentTProcess(max_fit_points=100, rng=7).fit(X, y)
    b = StudentTProcess(max_fit_points=100, rng=7).fit(X, y)
    c = StudentTProcess(max_fit_points=100, rng=8).fit(X, y)
    assert len(a.fit_indices_) == 100
    np.testing.assert_array_equal(a.fit_indices_, b.fit_indices_)
    np.testing.assert_array_equal(a.theta_, b.theta_)
    assert not np.array_equal(a.fit_indices_, c.fit_indices_)
    assert a.X_train_.shape == (300, 5)  # prediction conditions on every point


def test_fit_nu_moves_nu():
    X, y = make_data(5, n=60, d=2)
    tp = StudentTProcess(nu=3.0, fit_nu=True, optimizer="lbfgs").fit(X, y)
    assert tp.hyperparameter_names[-1] == "log_nu_minus_2"
    assert tp.nu_ != 3.0 and tp.nu_ > 2.0
    assert (tp.log_marginal_likelihood()
            >= StudentTProcess(nu=3.0, optimizer="lbfgs").fit(X, y).log_marginal_likelihood() - 1e-6)


def test_condition_equals_fit_with_kept_hyperparameters():
    X, y = make_data(6, n=50, d=5)
    tp = StudentTProcess(optimizer="adam").fit(X, y)
    Xs, ys = X[:20], y[:20] + 1.0
    conditioned = tp.condition(Xs, ys)
    refit = StudentTProcess(tp.kernel_, nu=tp.nu_, noise_variance=tp.noise_variance_, optimizer=None).fit(Xs, ys)
    Xq = X[30:34]
    np.testing.assert_allclose(conditioned.predict(Xq, return_var=True), refit.predict(Xq, return_var=True), rtol=1e-12)
    assert tp.X_train_.shape == (50, 5)  # the original is untouched


# --------------------------------------------------------------------------
# numerics
# --------------------------------------------------------------------------
@pytest.mark.parametrize("model_cls", [GaussianProcess, StudentTProcess])
def test_outliers_times_80_fit_and_predict_finitely(model_cls):
    """The paper's worst outliers: inputs and targets multiplied by m = 80."""
    X, y = make_data(9, n=100, d=5)
    X, y = X.copy(), y * 30.0
    rows = np.random.default_rng(0).choice(100, size=40, replace=False)  # p = 0.4
    X[rows] *= 80
    y[rows] *= 80
    assert np.abs(y).max() > 1000
    model = model_cls().fit(X, y)
    mean, var = model.predict(X[:50], return_var=True, include_noise=True)
    assert np.all(np.isfinite(mean)) and np.all(np.isfinite(var)) and np.all(var > 0)
    assert np.isfinite(model.log_marginal_likelihood())


def test_near_duplicate_inputs_with_tiny_noise_get_jitter():
    X = np.arange(5.0).reshape(-1, 1) * 1e-12 * np.ones((1, 2))  # distinct rows, numerically one point
    y = np.arange(5.0)
    gp = GaussianProcess(noise_variance=1e-160, optimizer=None).fit(X, y)
    assert gp.jitter_ > 0
    assert np.all(np.isfinite(gp.predict(X, return_var=True)[1]))


def test_exact_duplicates_are_folded_and_need_no_jitter():
    X = np.zeros((5, 2))
    y = np.arange(5.0)
    gp = GaussianProcess(noise_variance=1e-160, optimizer=None).fit(X, y)
    assert gp.jitter_ == 0 and gp.X_unique_.shape == (1, 2) and gp.counts_.tolist() == [5.0]
    assert gp.predict(X[:1])[0] == pytest.approx(2.0)  # the mean of the five targets


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    n=st.integers(1, 25),
    amplitude=st.floats(0.1, 10),
    length_scale=st.floats(0.1, 10),
    noise=st.floats(1e-4, 10),
    nu=st.floats(2.05, 100),
)
def test_variances_are_never_negative(seed, n, amplitude, length_scale, noise, nu):
    X, y = make_data(seed, n=n, d=3)
    Xq = np.vstack([X[: min(n, 4)], make_data(seed + 1, n=4, d=3)[0]])
    for model in (
        GaussianProcess(RBF(amplitude, length_scale), noise_variance=noise, optimizer=None),
        StudentTProcess(RBF(amplitude, length_scale), nu=nu, noise_variance=noise, optimizer=None),
    ):
        model.fit(X, y)
        _, var = model.predict(Xq, return_var=True)
        _, cov = model.predict(Xq, return_cov=True)
        assert np.all(var >= 0)
        assert np.linalg.eigvalsh(cov).min() >= -1e-8 * max(1.0, np.abs(cov).max())


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 10_000), n=st.integers(2, 20))
def test_near_interpolation_with_tiny_noise(seed, n):
    rng = np.random.default_rng(seed)
    X = rng.permutation(np.linspace(-5, 5, n)).reshape(-1, 1)  # distinct inputs
    y = rng.normal(size=n)
    kernel = RBF(1.0, 0.25)  # shorter than the spacing: K is well conditioned
    for model in (GaussianProcess(kernel, noise_variance=1e-8, optimizer=None),
                  StudentTProcess(kernel, noise_variance=1e-8, optimizer=None)):
        mean, var = model.fit(X, y).predict(X, return_var=True)
        np.testing.assert_allclose(mean, y, atol=1e-4)
        assert np.all(var < 1e-4 * max(1.0, model.variance_scale_))


# --------------------------------------------------------------------------
# bad input
# --------------------------------------------------------------------------
@pytest.mark.parametrize("nu", [2.0, 1.5, -3, np.inf, np.nan, "three", "3", True])
def test_nu_must_exceed_two(nu):
    model = StudentTProcess(nu=nu)  # scikit-learn's convention: stored as given, checked in fit
    assert model.nu is nu
    with pytest.raises(ValueError, match=r"nu must be a finite number > 2.*got nu="):
        model.fit(np.zeros((3, 1)), np.zeros(3))


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(noise_variance=0.0), "noise_variance"),
        (dict(noise_variance=-1.0), "noise_variance"),
        (dict(noise_variance=np.nan), "noise_variance"),
        (dict(optimizer="sgd"), "optimizer"),
        (dict(learning_rate=0), "learning_rate"),
        (dict(max_iter=0), "max_iter"),
        (dict(max_fit_points=2.5), "max_fit_points"),
        (dict(prior="flat"), "prior"),
        (dict(bounds=(1.0, 0.5)), "bounds"),
        (dict(kernel="rbf"), "kernel"),
        (dict(rng="seed"), "rng"),
        (dict(noise_variance="0.1"), "noise_variance"),
        (dict(learning_rate="0.1"), "learning_rate"),
    ],
)
@pytest.mark.parametrize("model_cls", [GaussianProcess, StudentTProcess])
def test_bad_parameters_are_named(model_cls, kwargs, match):
    model = model_cls(**kwargs)
    with pytest.raises(ValueError, match=match):
        model.fit(np.zeros((3, 1)), np.zeros(3))
    assert not hasattr(model, "L_") and not hasattr(model, "n_features_in_")  # nothing half-fitted


def test_tp_specific_parameters():
    with pytest.raises(ValueError, match="noise_convention"):
        StudentTProcess(noise_convention="gpy").fit(np.zeros((3, 1)), np.zeros(3))
    with pytest.raises(ValueError, match="fit_nu"):
        StudentTProcess(fit_nu="yes").fit(np.zeros((3, 1)), np.zeros(3))


@pytest.mark.parametrize(
    "X, y, match",
    [
        # shapes, types and lengths: scikit-learn's own messages
        (np.zeros(5), np.zeros(5), r"(?s)Expected 2D array.*reshape\(-1, 1\)"),
        (np.zeros((2, 2, 2)), np.zeros(2), "Found array with dim 3"),
        (np.zeros((0, 3)), np.zeros(0), "0 sample"),
        (np.zeros((4, 2)), np.zeros(3), r"inconsistent numbers of samples: \[4, 3\]"),
        (np.zeros((4, 2)), np.zeros((4, 2)), "y should be a 1d array"),
        (np.zeros((2, 1)) + 1j, np.zeros(2), "Complex data not supported"),
        # which entry is not finite: ours
        (np.array([[0.0], [np.nan]]), np.zeros(2), r"X must be finite \(no NaN or inf\), got nan at row 1"),
        (np.array([[0.0], [np.inf]]), np.zeros(2), "X must be finite"),
        (np.zeros((2, 1)), np.array([0.0, np.nan]), "Input y contains NaN"),
    ],
)
@pytest.mark.parametrize("model_cls", [GaussianProcess, StudentTProcess])
def test_bad_data_is_named(model_cls, X, y, match):
    with pytest.raises(ValueError, match=match):
        model_cls(optimizer=None).fit(X, y)


@pytest.mark.parametrize("model_cls", [GaussianProcess, StudentTProcess])
def test_predict_before_fit_says_so(model_cls):
    with pytest.raises(NotFittedError, match="not fitted yet: call fit"):
        model_cls().predict(np.zeros((1, 2)))
    with pytest.raises(NotFittedError):
        model_cls().log_marginal_likelihood()


def test_predict_with_wrong_number_of_features():
    gp = GaussianProcess(optimizer=None).fit(np.zeros((3, 2)), np.zeros(3))
    with pytest.raises(ValueError, match="X has 3 features, but GaussianProcess is expecting 2 features"):
        gp.predict(np.zeros((1, 3)))
    with pytest.raises(ValueError, match=r"theta must have shape \(3,\)"):
        gp.log_marginal_likelihood(np.zeros(4))


def test_initial_value_outside_bounds():
    with pytest.raises(ValueError, match="noise_variance=1e-08 lies outside bounds"):
        GaussianProcess(noise_variance=1e-8).fit(np.zeros((3, 1)), np.zeros(3))


# --------------------------------------------------------------------------
# repeated inputs folded together: exact, at the distinct inputs' size
# --------------------------------------------------------------------------
def repeated_rows(seed, n_distinct=40, max_copies=12):
    """Cost-buffer-like data: integer inputs, each repeated 1 to 12 times with different targets."""
    rng = np.random.default_rng(seed)
    U = np.unique(rng.integers(0, 6, size=(n_distinct, 5)).astype(float), axis=0)
    copies = rng.integers(1, max_copies + 1, size=len(U))
    X = np.repeat(U, copies, axis=0)
    y = np.hypot(X[:, 1] - X[:, 3], X[:, 2] - X[:, 4]) + 0.3 * rng.standard_normal(len(X))
    order = rng.permutation(len(X))  # copies scattered through the rows, as in a buffer
    return X[order], y[order]


@pytest.mark.parametrize("model_cls", [GaussianProcess, StudentTProcess])
def test_grouped_likelihood_and_gradient_equal_the_expanded_rows(model_cls):
    """Folding repeated inputs is exact: the value and gradient a fit follows are those of every row on its own,
    so Adam's path is the same folded or not."""
    X, y = repeated_rows(0)
    model = model_cls(optimizer=None).fit(X, y)
    assert len(model.X_unique_) < len(X) / 3  # the folding does something here
    for theta in (np.array([0.3, -0.2, -1.0]), np.array([1.2, 0.5, -3.0]), np.array([-0.5, 1.0, 0.7])):
        for objective in (model.log_marginal_likelihood, model.log_joint):
            v_g, g_g = objective(theta, eval_gradient=True)
            v_p, g_p = objective(theta, eval_gradient=True, fold_repeats=False)  # the textbook path
            assert v_g == pytest.approx(v_p, rel=1e-8, abs=1e-8)
            np.testing.assert_allclose(g_g, g_p, rtol=1e-8, atol=1e-8 * np.abs(g_p).max())


@pytest.mark.parametrize("model_cls", [GaussianProcess, StudentTProcess])
def test_grouped_model_equals_scipy_density_and_predicts_as_the_expanded_rows(model_cls):
    X, y = repeated_rows(1)
    kernel, noise = RBF(1.3, 1.7), 0.2
    model = model_cls(kernel, noise_variance=noise, optimizer=None).fit(X, y)
    assert model.X_unique_.shape[0] < X.shape[0] and model.counts_.sum() == X.shape[0]
    K = kernel(X) + noise * np.eye(len(X))
    if model_cls is GaussianProcess:
        expected = stats.multivariate_normal(np.zeros(len(X)), K).logpdf(y)
    else:
        expected = stats.multivariate_t(np.zeros(len(X)), (3.0 - 2.0) / 3.0 * K, df=3.0).logpdf(y)
    assert model.log_marginal_likelihood() == pytest.approx(expected, rel=1e-9)
    # prediction with the rows expanded, by the textbook formulas
    Xq = np.array([[0, 1, 2, 3, 4.0], [3, 3, 3, 0, 0.0], [1.5, 2, 2.5, 0, 5]])
    k_star = kernel(Xq, X)
    mean = k_star @ np.linalg.solve(K, y)
    latent = kernel.diag(Xq) - np.einsum("ij,ji->i", k_star, np.linalg.solve(K, k_star.T))
    if model_cls is StudentTProcess:
        beta = y @ np.linalg.solve(K, y)
        latent = latent * (3.0 + beta - 2.0) / (3.0 + len(X) - 2.0)
        assert model.beta_ == pytest.approx(beta, rel=1e-9)
    got_mean, got_var = model.predict(Xq, return_var=True)
    np.testing.assert_allclose(got_mean, mean, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(got_var, latent, rtol=1e-7, atol=1e-10)


@pytest.mark.parametrize("model_cls,convention", [(GaussianProcess, None), (StudentTProcess, "tfp"),
                                                  (StudentTProcess, "shah")])
@pytest.mark.parametrize("include_noise", [False, True])
def test_predict_batch_equals_condition_then_predict(model_cls, convention, include_noise):
    X, y = repeated_rows(3)
    extra = {} if convention is None else {"noise_convention": convention}
    model = model_cls(RBF(2.0, 1.5), noise_variance=0.3, optimizer=None, **extra).fit(X, y)
    rng = np.random.default_rng(0)
    sets = [np.sort(rng.choice(len(X), size=size, replace=False)) for size in (30, 45, 12, 45)]
    X_query = rng.integers(0, 6, size=(4, 3, 5)).astype(float)
    mean, var, df = model.predict_batch([X[r] for r in sets], [y[r] for r in sets], X_query, include_noise)
    assert mean.shape == var.shape == (4, 3) and df.shape == (4,)
    for b, rows in enumerate(sets):
        conditioned = model.condition(X[rows], y[rows])
        m, v = conditioned.predict(X_query[b], return_var=True, include_noise=include_noise)
        np.testing.assert_allclose(mean[b], m, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(var[b], v, rtol=1e-8, atol=1e-12)
        assert df[b] == (np.inf if model_cls is GaussianProcess else 3.0 + len(rows))


def test_predict_batch_checks_shapes():
    X, y = repeated_rows(3)
    model = GaussianProcess(optimizer=None).fit(X, y)
    with pytest.raises(ValueError, match="X_query must have shape"):
        model.predict_batch([X], [y], np.zeros((2, 1, 5)))
    with pytest.raises(ValueError, match="X_query must have shape"):
        model.predict_batch([X], [y], np.zeros((1, 5)))


def test_draw_rows_is_a_uniform_subset():
    from sarsp_edu._internal.rng import draw_rows

    rng = np.random.default_rng(0)
    counts = np.zeros(50)
    for _ in range(4000):
        rows = draw_rows(50, 10, rng)
        assert len(rows) == 10 and len(np.unique(rows)) == 10 and np.all(np.diff(rows) > 0)
        counts[rows] += 1
    # each index is in a subset with probability 10/50: 800 +- 25 of 4000
    assert stats.chisquare(counts).pvalue > 1e-3
    assert draw_rows(5, 10, rng).tolist() == [0, 1, 2, 3, 4]


# --------------------------------------------------------------------------
# extreme data: huge, tiny, constant, repeated
# --------------------------------------------------------------------------
def _wave(n=60):
    rng = np.random.default_rng(0)
    X = rng.uniform(0, 10, size=(n, 1))
    return X, np.sin(X[:, 0]) + 0.1 * rng.standard_normal(n)


def test_a_fit_that_ends_on_a_bound_warns_once_naming_it():
    from sarsp_edu import ConvergenceWarning

    X, y = _wave()
    with pytest.warns(ConvergenceWarning, match=r"amplitude=1e\+05 on its upper bound 1e\+05") as record:
        GaussianProcess(optimizer="lbfgs").fit(X, y * 1e8)
    assert len([w for w in record if issubclass(w.category, ConvergenceWarning)]) == 1


def test_data_out_of_adams_reach_warns_for_the_gp_only():
    import warnings

    from sarsp_edu import ConvergenceWarning

    X, y = _wave()
    with pytest.warns(ConvergenceWarning, match=r"out of reach of 50 Adam steps of 0.1 from amplitude=1"):
        GaussianProcess().fit(X, y * 1e8)
    # the TP's variance factor follows y's scale: its predictions stay calibrated, no warning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tp = StudentTProcess().fit(X, y * 1e8)
    mean, var = tp.predict(X, return_var=True, include_noise=True)
    assert 0.3 < np.mean((mean - y * 1e8) ** 2 / var) < 3


def test_ordinary_fits_do_not_warn():
    import warnings

    X, y = _wave()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for model_cls in (GaussianProcess, StudentTProcess):
            for optimizer in ("adam", "lbfgs"):
                model_cls(optimizer=optimizer).fit(X, y * 40)


@pytest.mark.parametrize("scale, name", [(1e200, "y"), (1.0, "X")])
def test_data_that_overflows_is_refused_by_name(scale, name):
    X, y = _wave()
    X = X * (1e200 if name == "X" else 1.0)
    with pytest.raises(ValueError, match=rf"{name} holds values as large as .*overflow float64"):
        GaussianProcess().fit(X, y * scale)


# --------------------------------------------------------------------------
# scikit-learn's estimator API
# --------------------------------------------------------------------------
def test_sklearn_clone_round_trips_the_parameters():
    from sklearn.base import clone

    for model in (StudentTProcess(nu=5, noise_variance=0.5, bounds=(1e-3, 1e3), max_fit_points=None),
                  GaussianProcess(RBF(2.0, 0.5), optimizer="lbfgs", rng=3)):
        copy_ = clone(model)
        assert type(copy_) is type(model) and copy_ is not model
        params, copied = model.get_params(), copy_.get_params()
        assert params.keys() == copied.keys()
        for name, value in params.items():
            assert copied[name] == value or (isinstance(value, RBF) and copied[name] == value), name
    assert StudentTProcess(nu=5).get_params()["nu"] == 5  # stored as given
    assert StudentTProcess().get_params()["kernel"] is None


def test_set_params_stores_and_fit_checks():
    model = StudentTProcess(nu=4.0)
    assert model.set_params(nu=6.0, learning_rate=0.05) is model and model.nu == 6.0
    model.set_params(nu=1.5)  # scikit-learn's convention: checked in fit, not here
    with pytest.raises(ValueError, match=r"nu must be a finite number > 2.*got nu=1.5"):
        model.fit(np.zeros((3, 1)), np.zeros(3))
    with pytest.raises(ValueError, match=r"Invalid parameter 'gamma' for estimator StudentTProcess"):
        model.set_params(gamma=1.0)


def test_a_cloned_model_fits_to_the_same_numbers():
    from sklearn.base import clone

    X, y = _wave()
    first = StudentTProcess(nu=4.0, rng=0).fit(X, y)
    second = clone(StudentTProcess(nu=4.0, rng=0)).fit(X, y)
    assert np.array_equal(first.theta_, second.theta_)


@pytest.mark.parametrize("model_cls", [GaussianProcess, StudentTProcess])
def test_a_fit_on_distance_levels_is_the_fit_on_every_distance(model_cls, monkeypatch):
    # whole-number inputs with repeats (the cost buffer's kind): the fit's kernel comes from D2's distinct
    # values; turned off, every entry is exponentiated: the same steps, to the bit
    import sarsp_edu.models.kernels as kernels

    rng = np.random.default_rng(3)
    X = rng.integers(0, 12, size=(300, 3)).astype(float)
    y = np.sin(X.sum(axis=1) / 5.0) + 0.1 * rng.normal(size=300)
    calls = []
    if_few = kernels.DistanceLevels.if_few.__func__
    monkeypatch.setattr(kernels.DistanceLevels, "if_few",
                        classmethod(lambda cls, D2, **kw: calls.append(if_few(cls, D2, **kw)) or calls[-1]))
    with_levels = model_cls(rng=0, max_iter=15).fit(X, y)
    assert calls and calls[-1] is not None  # the levels were used
    monkeypatch.setattr(kernels.DistanceLevels, "if_few", classmethod(lambda cls, D2, **kw: None))
    without = model_cls(rng=0, max_iter=15).fit(X, y)
    assert np.array_equal(with_levels.theta_, without.theta_)
    assert np.array_equal(with_levels.objective_trace_, without.objective_trace_)
    # real-valued inputs: every distance its own value, so the fit does not sort them to find out
    monkeypatch.setattr(kernels.DistanceLevels, "if_few",
                        classmethod(lambda cls, D2, **kw: pytest.fail("levels sought for real-valued inputs")))
    model_cls(rng=0, max_iter=3).fit(X + rng.uniform(0.1, 0.9, size=X.shape), y)


def test_a_nu_beyond_float64s_reach_is_refused_naming_nu_not_the_targets():
    X = np.linspace(0, 1, 10)[:, None]
    with pytest.raises(ValueError, match=r"nu must be at most 1e\+12 \(beyond it float64 loses"):
        StudentTProcess(nu=1e308).fit(X, np.sin(X[:, 0]))


@pytest.mark.parametrize("model", [GaussianProcess(optimizer="adam", max_iter=7),
                                   StudentTProcess(optimizer="adam", max_iter=7),
                                   GaussianProcess(optimizer="lbfgs")])
def test_a_fit_reports_each_step_of_its_search_to_its_own_callback(model):
    """The progress of a fit is an argument of that fit (no hook set elsewhere): Adam calls it once per step,
    L-BFGS-B once per iteration, and what it raises ends the fit."""
    X, y = make_data(0)
    calls = []
    model.fit(X, y, on_step=lambda: calls.append(1))
    assert len(calls) == model.n_iter_ and len(calls) > 0
    model.fit(X, y)  # no callback: nothing else is called
    assert len(calls) == model.n_iter_

    class Enough(Exception):
        pass

    def stop_at_the_third():
        calls.append(1)
        if len(calls) == model.n_iter_ + 3:
            raise Enough

    with pytest.raises(Enough):
        model.fit(X, y, on_step=stop_at_the_third)
