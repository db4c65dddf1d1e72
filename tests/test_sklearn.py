"""The models as scikit-learn regressors: its own estimator checks, and the tools a user of it reaches for."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from sklearn.base import clone, is_regressor
from sklearn.exceptions import DataConversionWarning, NotFittedError as SklearnNotFittedError
from sklearn.metrics import r2_score
from sklearn.model_selection import GridSearchCV, KFold, cross_val_score
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.utils.estimator_checks import check_estimator

from sarsp_edu import RBF, GaussianProcess, NotFittedError, StudentTProcess

MODELS = [GaussianProcess, StudentTProcess]


def wave(n=40, seed=0):
    rng = np.random.default_rng(seed)
    X = rng.uniform(0, 6, size=(n, 2))
    return X, np.sin(X[:, 0]) + 0.5 * np.cos(X[:, 1]) + 0.05 * rng.standard_normal(n)


@pytest.mark.slow  # about ten minutes on a loaded machine: the fast tier's units run without it
@pytest.mark.parametrize("model_cls", MODELS)
def test_scikit_learns_estimator_checks_pass(model_cls):
    results = check_estimator(model_cls(), on_fail=None)
    failed = [(r["check_name"], str(r["exception"])[:200]) for r in results if r["status"] == "failed"]
    assert failed == []
    assert sum(r["status"] == "passed" for r in results) >= 50


@pytest.mark.parametrize("model_cls", MODELS)
def test_a_regressor_with_r2_score_and_n_features_in(model_cls):
    X, y = wave()
    model = model_cls().fit(X, y)
    assert is_regressor(model) and model.n_features_in_ == 2
    assert model.score(X, y) == pytest.approx(r2_score(y, model.predict(X)))
    assert model.score(X, y) > 0.9


@pytest.mark.parametrize("model_cls", MODELS)
def test_return_std_is_the_square_root_of_return_var(model_cls):
    X, y = wave()
    model = model_cls().fit(X, y)
    mean, std = model.predict(X[:5], return_std=True)
    same_mean, var, cov = model.predict(X[:5], return_var=True, return_cov=True)
    np.testing.assert_array_equal(mean, same_mean)
    np.testing.assert_allclose(std, np.sqrt(var), rtol=1e-15)
    np.testing.assert_allclose(var, np.diag(cov), rtol=1e-9)


@pytest.mark.parametrize("model_cls", MODELS)
def test_in_a_pipeline_after_a_scaler(model_cls):
    X, y = wave()
    X_big = X * 1000.0  # inputs in metres, say: the scaler brings them back to unit scale
    pipeline = make_pipeline(StandardScaler(), model_cls()).fit(X_big, y)
    scaled = StandardScaler().fit(X_big)
    alone = model_cls().fit(scaled.transform(X_big), y)
    np.testing.assert_array_equal(pipeline.predict(X_big[:7]), alone.predict(scaled.transform(X_big[:7])))


def test_grid_search_over_nested_kernel_and_model_parameters():
    X, y = wave(60)
    grid = {"kernel__length_scale": [0.3, 1.0, 3.0], "nu": [3.0, 10.0]}
    search = GridSearchCV(StudentTProcess(kernel=RBF(), optimizer=None), grid, cv=KFold(3)).fit(X, y)
    scores = search.cv_results_["mean_test_score"]
    assert np.all(np.isfinite(scores)) and len(scores) == 6
    assert search.best_params_["kernel__length_scale"] == 1.0  # the wave's own scale
    assert search.best_estimator_.kernel_.length_scale == 1.0


def test_nested_kernel_parameters_work_with_the_default_kernel():
    model = GaussianProcess()  # kernel=None: RBF(1, 1)
    model.set_params(kernel__length_scale=2.0)
    assert model.kernel == RBF(1.0, 2.0)
    assert model.get_params()["kernel__length_scale"] == 2.0
    with pytest.raises(ValueError, match="length_scale must be"):
        model.set_params(kernel__length_scale=-1.0)


@pytest.mark.parametrize("model_cls", MODELS)
def test_cross_val_score_and_clone(model_cls):
    X, y = wave(45)
    scores = cross_val_score(model_cls(rng=0), X, y, cv=KFold(3))
    assert scores.shape == (3,) and np.all(scores > 0.5)
    model = model_cls(kernel=RBF(2.0, 0.5), rng=0).fit(X, y)
    copy = clone(model)
    assert not hasattr(copy, "L_") and copy.kernel == model.kernel and copy.kernel is not model.kernel
    np.testing.assert_array_equal(copy.fit(X, y).theta_, model.theta_)


@pytest.mark.parametrize("model_cls", MODELS)
def test_a_column_y_is_flattened_with_scikit_learns_warning(model_cls):
    X, y = wave()
    with pytest.warns(DataConversionWarning):
        column = model_cls(optimizer=None).fit(X, y[:, None])
    flat = model_cls(optimizer=None).fit(X, y)
    np.testing.assert_array_equal(column.predict(X[:3]), flat.predict(X[:3]))


@pytest.mark.parametrize("model_cls", MODELS)
def test_unfitted_and_sparse_input_say_so(model_cls):
    from scipy import sparse

    assert NotFittedError is SklearnNotFittedError
    with pytest.raises(NotFittedError, match="not fitted yet"):
        model_cls().predict(np.zeros((1, 2)))
    with pytest.raises(TypeError, match="[Ss]parse data was passed"):
        model_cls().fit(sparse.csr_matrix(np.eye(3)), np.zeros(3))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # storing arguments checks nothing and warns of nothing
        model_cls(noise_variance=-1.0, optimizer="no such optimiser")
