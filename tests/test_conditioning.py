"""The one conditioning loop (``models/processes/conditioning.py``): the models' own steps and a student's plug in
the same way, agree, and what a replaced step returns is checked where it is used.  Fast tier."""
from __future__ import annotations

import itertools

import numpy as np
import pytest

from sarsp_edu import RBF, GaussianProcess, StudentTProcess
from sarsp_edu.agent.parts import DecisionParts, gp_posterior, predict_from_parts, rbf, tp_factor
from sarsp_edu.models.kernels import whole_distance_bound
from sarsp_edu.models.processes.conditioning import ConditioningSteps

PACKAGE = {"kernel": rbf, "posterior": gp_posterior, "tp_factor": tp_factor}


# a student's copies, written from the textbook formulas (explicit inverse, no Cholesky)
def textbook_kernel(X, Y, amplitude, length_scale):
    return amplitude**2 * np.exp(-((X[:, None, :] - Y[None, :, :]) ** 2).sum(-1) / (2 * length_scale**2))


def textbook_posterior(K, K_star, k_star_star, y, noise_variance):
    inverse = np.linalg.inv(K + noise_variance * np.eye(len(y)))
    return K_star @ inverse @ y, k_star_star - np.einsum("qn,nm,qm->q", K_star, inverse, K_star)


def textbook_factor(K, y, noise_variance, nu):
    beta = y @ np.linalg.inv(K + noise_variance * np.eye(len(y))) @ y
    return (nu + beta - 2) / (nu + len(y) - 2)


STUDENT = {"kernel": textbook_kernel, "posterior": textbook_posterior, "tp_factor": textbook_factor}
MODELS = [(GaussianProcess, {}), (StudentTProcess, {"noise_convention": "shah"}),
          (StudentTProcess, {"noise_convention": "tfp", "nu": 4.0})]


def _fitted(model_class, **kwargs):
    rng = np.random.default_rng(0)
    X = rng.integers(0, 6, (60, 5)).astype(float)
    X[40:] = X[:20]  # repeated inputs, as a strategic prior's matching rows
    y = X[:, 1] - X[:, 3] + 0.1 * rng.standard_normal(60)
    model = model_class(RBF(1.3, 1.7), noise_variance=0.2, optimizer=None, **kwargs).fit(X, y)
    sets = [np.sort(rng.choice(60, size=size, replace=False)) for size in (12, 30, 45)]
    queries = rng.integers(0, 6, (3, 4, 5)).astype(float)
    return model, [X[r] for r in sets], [y[r] for r in sets], queries


SUBSETS = [names for k in range(1, 4) for names in itertools.combinations(("kernel", "posterior", "tp_factor"), k)]


@pytest.mark.parametrize("model_class, kwargs", MODELS)
@pytest.mark.parametrize("replaced", SUBSETS, ids="+".join)
@pytest.mark.parametrize("source", ["package, new objects", "textbook"])
def test_every_mix_of_replaced_and_own_steps_gives_the_models_numbers(model_class, kwargs, replaced, source):
    model, X, y, queries = _fitted(model_class, **kwargs)
    expected = model.predict_batch(X, y, queries, include_noise=True)
    functions = PACKAGE if source.startswith("package") else STUDENT
    # new function objects: a part is "replaced" by identity, so even the package's own go through the plug
    parts = DecisionParts(**{name: (lambda f: lambda *a: f(*a))(functions[name]) for name in replaced})
    assert sorted(parts.replaced()) == sorted(replaced) and not parts.package_models
    for got, want in zip(predict_from_parts(parts, model, X, y, queries, include_noise=True), expected):
        np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-12)


def test_the_packages_own_parts_are_the_models_own_steps_bit_for_bit():
    model, X, y, queries = _fitted(StudentTProcess)
    assert DecisionParts().conditioning_steps() == ConditioningSteps() and not ConditioningSteps().replaced
    expected = model.predict_batch(X, y, queries)
    for got, want in zip(predict_from_parts(DecisionParts(), model, X, y, queries), expected):
        np.testing.assert_array_equal(got, want)


def test_a_replaced_step_is_called_with_copies_and_the_data_stays_as_it_was():
    model, X, y, queries = _fitted(StudentTProcess)
    before = [x.copy() for x in X], [v.copy() for v in y], queries.copy()

    def vandal_kernel(A, B, amplitude, length_scale):
        K = textbook_kernel(A, B, amplitude, length_scale)
        A[:] = -1.0
        return K

    def vandal_posterior(K, K_star, k_star_star, y, noise_variance):
        result = textbook_posterior(K, K_star, k_star_star, y, noise_variance)
        K[:], y[:] = 0.0, 0.0
        return result

    steps = ConditioningSteps(kernel=vandal_kernel, posterior=vandal_posterior, tp_factor=textbook_factor)
    got = model.predict_batch(X, y, queries, steps=steps)
    np.testing.assert_allclose(got[1], model.predict_batch(X, y, queries)[1], rtol=1e-9)
    for now, then in zip((X, y, [queries]), (before[0], before[1], [before[2]])):
        for a, b in zip(now, then):
            np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("steps, said", [
    (ConditioningSteps(posterior=lambda K, Ks, kss, y, s2: (np.full(len(Ks), np.nan), kss)),
     "the posterior part returned a mean with entries that are not finite"),
    (ConditioningSteps(posterior=lambda K, Ks, kss, y, s2: (Ks @ np.ones(len(y)), -5.0 * kss)),
     r"the posterior part returned a negative variance \(-8.45\)"),
    (ConditioningSteps(posterior=lambda K, Ks, kss, y, s2: (Ks @ np.ones(len(y)),)),
     "the posterior part must return two arrays"),
    (ConditioningSteps(tp_factor=lambda K, y, s2, nu: -5.0), "the tp_factor part returned -5"),
    (ConditioningSteps(tp_factor=lambda K, y, s2, nu: np.ones(2)), r"the tp_factor part returned a factor of shape"),
    (ConditioningSteps(kernel=lambda A, B, a, ell: np.ones(len(A))), "the kernel part returned a matrix of shape"),
    (ConditioningSteps(kernel=lambda A, B, a, ell: "matrix"), "the kernel part returned a matrix that is not numbers"),
])
def test_a_replaced_steps_result_the_loop_cannot_use_is_refused_naming_the_part(steps, said):
    model, X, y, queries = _fitted(StudentTProcess)
    with pytest.raises(ValueError, match=said):
        model.predict_batch(X, y, queries, steps=steps)


def test_a_tp_factor_is_never_asked_of_a_gaussian_process():
    model, X, y, queries = _fitted(GaussianProcess)
    calls = []
    steps = ConditioningSteps(tp_factor=lambda *args: calls.append(1) or 1.0)
    model.predict_batch(X, y, queries, steps=steps)
    assert calls == []


def test_a_whole_number_bound_is_checked_not_trusted():
    model, X, y, queries = _fitted(GaussianProcess)
    bound = whole_distance_bound(*X, queries.reshape(-1, 5))
    expected = model.predict_batch(X, y, queries)
    for got, want in zip(model.predict_batch(X, y, queries, whole_bound=bound), expected):
        np.testing.assert_array_equal(got, want)  # the same numbers with a true bound
    with pytest.raises(ValueError, match=r"whole_bound=3\.0 is not a bound .*\(their ranges allow up to 125\)"):
        model.predict_batch(X, y, queries, whole_bound=3.0)
    with pytest.raises(ValueError, match="an input is not a whole number"):
        model.predict_batch(X, y, queries + 0.5, whole_bound=bound)
