from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from hypothesis.extra.numpy import arrays
from scipy.optimize import approx_fprime

from sarsp_edu import RBF
from sarsp_edu.models.kernels import squared_distances


def test_formula_by_hand():
    k = RBF(amplitude=2.0, length_scale=0.5)
    x, y = np.array([[0.0, 1.0]]), np.array([[1.0, 2.0]])
    expected = 4.0 * np.exp(-2.0 / (2 * 0.25))
    assert k(x, y)[0, 0] == pytest.approx(expected, rel=1e-14)


def test_matches_scikit_learn():
    from sklearn.gaussian_process.kernels import RBF as SkRBF, ConstantKernel

    rng = np.random.default_rng(0)
    X, Y = rng.normal(size=(7, 3)), rng.normal(size=(4, 3))
    ours = RBF(amplitude=1.7, length_scale=0.8)
    theirs = ConstantKernel(1.7**2) * SkRBF(0.8)
    np.testing.assert_allclose(ours(X, Y), theirs(X, Y), rtol=1e-12)
    np.testing.assert_allclose(ours.diag(X), theirs.diag(X), rtol=1e-12)


def test_gradient_matches_finite_differences():
    rng = np.random.default_rng(1)
    X = rng.normal(size=(6, 2))
    kernel = RBF(amplitude=1.3, length_scale=0.7)
    _, grad = kernel(X, eval_gradient=True)
    for j in range(2):
        for a, b in [(0, 1), (2, 5), (3, 3)]:

            def entry(theta):
                return kernel.clone_with_theta(theta)(X)[a, b]

            fd = approx_fprime(kernel.theta, entry, 1e-7)
            assert grad[a, b, j] == pytest.approx(fd[j], rel=1e-5, abs=1e-8)


def test_theta_round_trip():
    kernel = RBF(amplitude=3.0, length_scale=0.2)
    clone = kernel.clone_with_theta(kernel.theta)
    assert clone.amplitude == pytest.approx(3.0)
    assert clone.length_scale == pytest.approx(0.2)


@pytest.mark.parametrize("name", ["amplitude", "length_scale"])
@pytest.mark.parametrize("value", [0.0, -1.0, np.nan, np.inf, "big"])
def test_bad_hyperparameters_are_named(name, value):
    with pytest.raises(ValueError, match=name):
        RBF(**{name: value})


def test_feature_mismatch():
    with pytest.raises(ValueError, match="same number of features"):
        RBF()(np.zeros((2, 3)), np.zeros((2, 2)))


@settings(max_examples=60, deadline=None)
@given(
    X=arrays(np.float64, st.tuples(st.integers(1, 12), st.integers(1, 4)),
             elements=st.floats(-50, 50)),
    amplitude=st.floats(0.05, 20),
    length_scale=st.floats(0.05, 20),
)
def test_kernel_matrix_symmetric_psd(X, amplitude, length_scale):
    K = RBF(amplitude, length_scale)(X)
    np.testing.assert_array_equal(K, K.T)
    np.testing.assert_allclose(np.diag(K), amplitude**2, rtol=1e-12)
    eigenvalues = np.linalg.eigvalsh(K)
    assert eigenvalues.min() >= -1e-9 * amplitude**2 * len(X)


@pytest.mark.parametrize("amplitude, length_scale", [(1.0, 1.0), (67.12, 0.9632), (102.5, 13.21), (1e-3, 500.0)])
def test_whole_number_lookup_is_bit_identical(amplitude, length_scale):
    # grid inputs (whole numbers, outliers scaled by m) take the table path;
    # it must give exactly the doubles of the exponential it replaces
    rng = np.random.default_rng(0)
    X = rng.integers(-40, 400, size=(40, 5)).astype(float)
    D2 = squared_distances(X)
    kernel = RBF(amplitude, length_scale)
    expected = np.exp(D2 * (-0.5 * (1.0 / length_scale**2))) * amplitude**2
    assert D2.size >= 256
    K = kernel.from_squared_distances(D2)
    assert "_table" in kernel.__dict__  # the lookup ran
    assert np.array_equal(K, expected)


@pytest.mark.parametrize("amplitude, length_scale", [(1.0, 1.0), (67.12, 0.9632), (102.5, 13.21), (1e-3, 500.0)])
def test_the_kernel_on_distance_levels_is_bit_identical(amplitude, length_scale):
    # a fit evaluates the kernel on D2's distinct values and gathers: the doubles of every entry's exponential,
    # the gradient's planes too, into the fit's workspace or a new array
    from sarsp_edu.models.kernels import DistanceLevels

    rng = np.random.default_rng(1)
    X = rng.integers(0, 30, size=(120, 5)).astype(float)
    X[:7] *= 40.0  # outliers' inputs, far from the rest
    D2 = squared_distances(X)
    levels = DistanceLevels.if_few(D2)
    assert levels is not None and levels.values.size < D2.size / 4
    assert np.array_equal(levels.values[levels.index], D2)
    kernel = RBF(amplitude, length_scale)
    K, dK = kernel.from_squared_distances(D2, eval_gradient=True, out=np.empty((3,) + D2.shape))
    K_l, dK_l = kernel.from_squared_distances(D2, eval_gradient=True, out=np.empty((3,) + D2.shape), levels=levels)
    assert np.array_equal(K, K_l) and np.array_equal(dK, dK_l)
    assert np.array_equal(kernel.from_squared_distances(D2, levels=levels), K)
    # float32 distances stay float32 on both paths, and whole-number integer ones are computed as float64
    D2_32 = D2.astype(np.float32)
    K_32 = kernel.from_squared_distances(D2_32)
    K_32_l = kernel.from_squared_distances(D2_32, levels=DistanceLevels(D2_32))
    assert K_32.dtype == K_32_l.dtype == np.float32 and np.array_equal(K_32, K_32_l)
    D2_int = D2.astype(np.int64)
    assert np.array_equal(kernel.from_squared_distances(D2_int, levels=DistanceLevels(D2_int)), K)


def test_distance_levels_are_kept_only_where_few():
    from sarsp_edu.models.kernels import DistanceLevels

    X = np.random.default_rng(2).normal(size=(60, 3))  # real-valued inputs: every distance its own value
    assert DistanceLevels.if_few(squared_distances(X)) is None
    whole = np.arange(60.0).reshape(20, 3)
    assert DistanceLevels.if_few(squared_distances(whole)) is not None
    assert DistanceLevels.if_few(squared_distances(whole), max_size=399) is None  # 400 entries: too many
    assert DistanceLevels.if_few(np.empty((0, 0))) is None
    with pytest.raises(ValueError, match=r"max_fraction must lie in \[0, 1\], got max_fraction=1.5"):
        DistanceLevels.if_few(squared_distances(whole), max_fraction=1.5)
    with pytest.raises(ValueError, match=r"max_size must be an integer >= 0, got max_size=-1"):
        DistanceLevels.if_few(squared_distances(whole), max_size=-1)


def test_lookup_falls_back_and_follows_the_hyperparameters():
    kernel = RBF(2.0, 1.5)
    X = np.arange(60.0).reshape(20, 3)
    D2 = squared_distances(X)
    first = kernel.from_squared_distances(D2)
    # fractional distances take the general path and still agree with __call__'s formula
    half = D2 + 0.5
    assert np.array_equal(kernel.from_squared_distances(half), np.exp(half * (-0.5 * (1.0 / 1.5**2))) * 4.0)
    # a changed hyperparameter must not reuse the old table
    kernel.length_scale = 3.0
    second = kernel.from_squared_distances(D2)
    assert not np.array_equal(first, second)
    assert np.allclose(second, 4.0 * np.exp(-D2 / 18.0), rtol=1e-14)


def test_a_whole_distance_bound_skips_the_checks_and_changes_no_bit():
    """predict_batch with the caller's whole-number bound gives the very numbers it gives without."""
    from sarsp_edu import GaussianProcess, StudentTProcess
    from sarsp_edu.models.kernels import whole_distance_bound

    rng = np.random.default_rng(3)
    X = rng.integers(0, 10, size=(300, 4)).astype(float)
    X[:30] *= 40.0  # outlier rows far from the grid, as the agent's buffers hold
    y = rng.normal(size=300)
    queries = rng.integers(0, 10, size=(5, 2, 4)).astype(float)
    bound = whole_distance_bound(X, queries.reshape(-1, 4))
    assert bound == float(np.sum((X.max(0) - X.min(0)) ** 2))
    assert squared_distances(X).max() <= bound
    for model in (GaussianProcess(RBF(2.0, 1.5), noise_variance=0.1, optimizer=None),
                  StudentTProcess(RBF(2.0, 1.5), nu=3.0, noise_variance=0.1, optimizer=None)):
        model.fit(X[:40], y[:40])
        sets = [rng.choice(300, 120, replace=False) for _ in range(5)]
        plain = model.predict_batch([X[s] for s in sets], [y[s] for s in sets], queries, include_noise=True)
        hinted = model.predict_batch([X[s] for s in sets], [y[s] for s in sets], queries, include_noise=True,
                                     whole_bound=bound)
        for a, b in zip(plain, hinted):
            assert np.array_equal(a, b)
    assert whole_distance_bound(X + 0.5) is None
    assert whole_distance_bound(np.empty((0, 3))) == 0.0
    with pytest.raises(ValueError, match=r"arrays\[1\] must be 2-D"):
        whole_distance_bound(X, queries)
    # a bound too loose for a table: the distances are checked, and the small ones still looked up
    kernel = RBF(2.0, 1.5)
    D2 = squared_distances(X[30:60])
    loose = kernel.from_squared_distances(D2, whole_bound=2.0**30)
    assert np.array_equal(loose, kernel.from_squared_distances(D2))
    assert kernel._table[1].shape[0] > 0  # the lookup ran (a table was built for these hyperparameters)
    # the hint is taken at its word: a bound below the true distances is the caller's error, not a check
    with pytest.raises(IndexError):
        RBF(2.0, 1.5).from_squared_distances(D2 + 2.0**19, whole_bound=10.0)


def test_draw_rows_consumes_the_generator_as_a_redraw_of_repeats():
    """The mask-based draw gives the indices, and leaves the generator, as drawing and redrawing repeats."""
    from sarsp_edu._internal.rng import draw_row_mask, draw_rows

    def by_redraw(n, k, rng):  # the specification, written out: uniform draws, repeats redrawn
        if k >= n:
            return np.arange(n)
        rows = np.unique(rng.integers(n, size=k))
        while rows.shape[0] < k:
            rows = np.union1d(rows, rng.integers(n, size=k - rows.shape[0]))
        return rows

    for n, k in ((50, 10), (120, 100), (4709, 400), (5, 10), (7, 7)):
        ours, spec = np.random.default_rng(n + k), np.random.default_rng(n + k)
        for _ in range(20):
            rows = draw_rows(n, k, ours)
            assert np.array_equal(rows, by_redraw(n, k, spec))
            mask = draw_row_mask(n, k, ours)
            assert mask.dtype == bool and np.array_equal(np.flatnonzero(mask), by_redraw(n, k, spec))
        assert ours.integers(2**62) == spec.integers(2**62)  # the same numbers were drawn


def test_kernel_table_gathers_the_kernels_bits():
    from sarsp_edu.models.kernels import KernelTable, whole_distance_bound

    rng = np.random.default_rng(2)
    X = rng.integers(0, 6, size=(300, 3)).astype(float)  # whole numbers, many repeated rows
    Q = rng.integers(0, 8, size=(4, 3)).astype(float)
    kernel = RBF(1.7, 2.3)
    for bound in (None, whole_distance_bound(X, Q)):
        table = KernelTable(kernel, X, whole_bound=bound)
        assert table.X_unique.shape[0] == len(np.unique(X, axis=0)) < len(X)
        assert np.array_equal(table.X_unique[table.index], X)
        rows = np.sort(rng.choice(len(X), size=40, replace=False))
        K, K_star = table.gather(rows, table.cross(Q, whole_bound=bound))
        assert np.array_equal(K, kernel(X[rows])) and K.flags.c_contiguous
        assert np.array_equal(K_star, kernel(Q, X[rows]))
        assert np.array_equal(table.gram(rows), K)
    assert KernelTable.if_small(kernel, X, max_distinct=10) is None
    assert KernelTable.if_small(kernel, X, max_distinct=300).K.shape == (table.X_unique.shape[0],) * 2
    with pytest.raises(ValueError, match="X must be 2-D"):
        KernelTable(kernel, np.zeros(3))
