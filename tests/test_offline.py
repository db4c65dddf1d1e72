from __future__ import annotations

import numpy as np
import pytest

from sarsp_edu import ObservationBuffer, SafeGridWorld, collect_offline_data, inject_outliers


@pytest.fixture(scope="module")
def clean():
    return collect_offline_data(SafeGridWorld(seed=0), episodes=30, rng=1)


def counts(X):
    _, c = np.unique(X, axis=0, return_counts=True)
    return c


def test_duplicate_caps_hold(clean):
    assert counts(clean.cost.X).max() <= 12
    assert counts(clean.cost.X).max() > 1  # the cap of 12 lets repeats in
    assert counts(clean.reward.X).max() == 1
    assert len(clean.cost) < clean.transitions and len(clean.reward) < clean.transitions


def test_paper_size_data_matches_the_reference_sizes():
    """About 8,000 transitions, of which about 4,700 / 4,850 survive the caps (REFERENCE.md)."""
    data = collect_offline_data(SafeGridWorld(seed=3), episodes=100, rng=0)
    assert 6500 < data.transitions <= 10_000
    assert 3800 < len(data.cost) < 5600 and 3800 < len(data.reward) < 5800
    assert data.visits.sum() == data.transitions


def test_targets_are_the_environment_signals(clean):
    # cost target: distance to the nearest unsafe state after the step, i.e. at the moved cell
    env = SafeGridWorld(seed=0)
    dmap = env.distance_map()
    moves = np.array([[1, 0], [0, 1], [-1, 0], [0, -1]])
    X, y = clean.cost.X, clean.cost.y
    a = X[:, 0].astype(int)
    nxt = np.clip(X[:, 1:3].astype(int) + moves[a], 0, env.size - 1)
    np.testing.assert_allclose(y, dmap[nxt[:, 1], nxt[:, 0]])
    # reward target: minus the L2 distance from the moved cell to the goal
    X, y = clean.reward.X, clean.reward.y
    a = X[:, 0].astype(int)
    nxt = np.clip(X[:, 1:3].astype(int) + moves[a], 0, env.size - 1)
    np.testing.assert_allclose(y, -np.hypot(*(nxt - X[:, 3:5]).T))


def test_same_seed_same_data():
    a = collect_offline_data(SafeGridWorld(seed=2), episodes=5, rng=7)
    b = collect_offline_data(SafeGridWorld(seed=2), episodes=5, rng=7)
    c = collect_offline_data(SafeGridWorld(seed=2), episodes=5, rng=8)
    np.testing.assert_array_equal(a.cost.X, b.cost.X)
    np.testing.assert_array_equal(a.reward.y, b.reward.y)
    assert a.transitions == b.transitions
    assert not np.array_equal(a.cost.X[:50], c.cost.X[:50])


@pytest.mark.parametrize("m, p", [(40, 0.2), (60, 0.3), (80, 0.4)])
def test_outliers_change_exactly_the_reported_rows_by_m(clean, m, p):
    cost_X, cost_y = clean.cost.X.copy(), clean.cost.y.copy()
    dirty = inject_outliers(clean, m, p, rng=0)
    N = min(len(clean.cost), len(clean.reward))
    rows = dirty.outlier_indices
    assert len(rows) == round(p * N) and len(np.unique(rows)) == len(rows)
    assert rows.max() < N
    for name in ("cost", "reward"):
        before, after = getattr(clean, name), getattr(dirty, name)
        np.testing.assert_array_equal(after.X[rows], before.X[rows] * m)
        np.testing.assert_array_equal(after.y[rows], before.y[rows] * m)
        keep = np.setdiff1d(np.arange(len(before)), rows)
        np.testing.assert_array_equal(after.X[keep], before.X[keep])
        np.testing.assert_array_equal(after.y[keep], before.y[keep])
    # the input is not mutated
    np.testing.assert_array_equal(clean.cost.X, cost_X)
    np.testing.assert_array_equal(clean.cost.y, cost_y)
    assert len(clean.outlier_indices) == 0
    assert (dirty.outlier_magnitude, dirty.outlier_proportion, dirty.outliers_in) == (m, p, ("cost", "reward"))


def test_outliers_in_one_buffer_only(clean):
    dirty = inject_outliers(clean, 40, 0.2, rng=0, reward=False)
    np.testing.assert_array_equal(dirty.reward.X, clean.reward.X)
    assert not np.array_equal(dirty.cost.X, clean.cost.X)
    assert dirty.outliers_in == ("cost",)


def test_outliers_are_reproducible(clean):
    a = inject_outliers(clean, 40, 0.3, rng=5)
    b = inject_outliers(clean, 40, 0.3, rng=5)
    np.testing.assert_array_equal(a.outlier_indices, b.outlier_indices)


def test_outlier_buffer_index_follows_the_new_inputs(clean):
    dirty = inject_outliers(clean, 40, 0.2, rng=0)
    X = dirty.cost.X
    for row in list(dirty.outlier_indices[:20]) + [0, 1, 2]:
        expected = np.flatnonzero(np.all(X == X[row], axis=1))
        np.testing.assert_array_equal(dirty.cost.rows_of(X[row]), expected)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(magnitude=0, proportion=0.2), "magnitude must be a positive finite number, got magnitude=0"),
        (dict(magnitude=-40, proportion=0.2), "magnitude"),
        (dict(magnitude=np.inf, proportion=0.2), "magnitude"),
        (dict(magnitude=40, proportion=1.5), r"proportion must lie in \[0, 1\], got proportion=1.5"),
        (dict(magnitude=40, proportion=-0.1), "proportion"),
        (dict(magnitude=40, proportion=np.nan), "proportion"),
        (dict(magnitude=40, proportion=0.2, cost=False, reward=False), "at least one of cost and reward"),
    ],
)
def test_bad_outlier_arguments(clean, kwargs, match):
    with pytest.raises(ValueError, match=match):
        inject_outliers(clean, **kwargs)


def test_outliers_are_injected_once(clean):
    dirty = inject_outliers(clean, 40, 0.2, rng=0)
    with pytest.raises(ValueError, match="already holds outliers"):
        inject_outliers(dirty, 40, 0.2, rng=0)


def test_proportion_edges(clean):
    assert len(inject_outliers(clean, 40, 0.0, rng=0).outlier_indices) == 0
    assert len(inject_outliers(clean, 40, 1.0, rng=0).outlier_indices) == min(len(clean.cost), len(clean.reward))


def test_bad_episodes():
    with pytest.raises(ValueError, match="episodes must be an integer >= 1, got episodes=0"):
        collect_offline_data(SafeGridWorld(seed=0), episodes=0)


# --------------------------------------------------------------------------
# the buffer
# --------------------------------------------------------------------------
def test_buffer_cap_overwrite_and_update():
    buffer = ObservationBuffer(2, max_duplicates=3, capacity=2)  # small capacity: it must grow
    results = [buffer.add([1, 2], float(k)) for k in range(5)]
    assert results == [True, True, True, False, False]
    assert buffer.count([1, 2]) == 3
    assert buffer.add([2, 2], 9.0)
    assert buffer.overwrite([1, 2], -1.0) == 3
    np.testing.assert_array_equal(buffer.y, [-1, -1, -1, 9])
    assert buffer.update([2, 2], 4.0) == "overwritten"
    assert buffer.update([3, 3], 5.0) == "added"
    assert len(buffer) == 5 and buffer.X.shape == (5, 2)
    np.testing.assert_array_equal(buffer.rows_of([1, 2]), [0, 1, 2])
    assert buffer.overwrite([7, 7], 1.0) == 0


def test_buffer_views_are_read_only_and_copies_independent():
    buffer = ObservationBuffer(1)
    buffer.add([0.0], 1.0)
    with pytest.raises(ValueError):
        buffer.y[0] = 3.0
    other = buffer.copy()
    other.overwrite([0.0], 5.0)
    assert buffer.y[0] == 1.0


def test_buffer_negative_zero_is_zero():
    buffer = ObservationBuffer(1, max_duplicates=1)
    buffer.add([0.0], 1.0)
    assert not buffer.add([-0.0], 2.0)


def test_buffer_bad_arguments():
    with pytest.raises(ValueError, match="max_duplicates"):
        ObservationBuffer(2, max_duplicates=0)
    with pytest.raises(ValueError, match="n_features"):
        ObservationBuffer(0)
    with pytest.raises(ValueError, match="x must have 2 features, got 3"):
        ObservationBuffer(2).add([1, 2, 3], 0.0)


def test_a_scaled_buffer_indexes_its_rows_by_their_new_inputs():
    buffer = ObservationBuffer(2, max_duplicates=None)
    for x in [(0.0, 1.0), (-0.0, 1.0), (2.0, 3.0), (0.0, 1.0), (2.0, 3.0), (5.0, 5.0)]:
        buffer.add(x, 1.0)
    scaled = buffer.scaled([1, 4], 10.0)  # one copy of (0, 1) and one of (2, 3) become new inputs
    np.testing.assert_array_equal(scaled.rows_of((0.0, 1.0)), [0, 3])
    np.testing.assert_array_equal(scaled.rows_of((-0.0, 10.0)), [1])  # -0.0 and 0.0 are one input
    np.testing.assert_array_equal(scaled.rows_of((2.0, 3.0)), [2])
    np.testing.assert_array_equal(scaled.rows_of((20.0, 30.0)), [4])
    np.testing.assert_array_equal(scaled.rows_of((5.0, 5.0)), [5])
    assert scaled.count((1.0, 1.0)) == 0
    assert scaled.overwrite((20.0, 30.0), -1.0) == 1 and scaled.y[4] == -1.0
    np.testing.assert_array_equal(buffer.rows_of((0.0, 1.0)), [0, 1, 3])  # the original is untouched


def test_the_index_of_injected_data_agrees_with_its_rows(clean):
    dirty = inject_outliers(clean, 40.0, 0.2, rng=0)
    X = dirty.cost.X + 0.0
    for i in range(0, len(X), 37):
        expected = np.flatnonzero((X == X[i]).all(axis=1))
        np.testing.assert_array_equal(dirty.cost.rows_of(X[i]), expected)


def test_an_overflowing_outlier_magnitude_is_refused():
    # magnitude=1e308 overflowed to inf
    from sarsp_edu import SafeGridWorld, collect_offline_data, inject_outliers

    data = collect_offline_data(SafeGridWorld(size=5, n_unsafe=3, seed=0), 3, rng=0)
    with pytest.raises(ValueError, match=r"magnitude=1e\+308 times the data's largest value .* overflows float64"):
        inject_outliers(data, 1e308, 0.2, rng=0)
