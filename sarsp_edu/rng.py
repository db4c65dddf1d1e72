"""Random helpers shared by the world, the data, the models and the agent.

Every stochastic function of the package takes ``rng``: ``None``, an int
seed or a ``numpy.random.Generator``; :func:`as_generator` turns each into a
Generator, so that the same seed gives the same numbers in any process.
"""

from __future__ import annotations

import numbers

import numpy as np

__all__ = ["as_generator", "draw_rows", "draw_subset", "sorted_unique"]


def as_generator(rng) -> np.random.Generator:
    """``numpy.random.Generator`` from a seed, a Generator or ``None``.

    A Generator is returned unchanged (so successive calls draw fresh
    numbers); an int or ``None`` seeds a new one.
    """
    if isinstance(rng, np.random.Generator):
        return rng
    if rng is None or isinstance(rng, (numbers.Integral, np.random.SeedSequence)):
        return np.random.default_rng(rng)
    raise ValueError(
        f"rng must be None, an int seed or a numpy.random.Generator, got rng={rng!r}"
    )


def draw_rows(n: int, k: int, rng: np.random.Generator) -> np.ndarray:
    """``min(k, n)`` distinct indices of ``range(n)``, uniformly at random, sorted.

    Draws with replacement and redraws the repeats: the first ``k`` distinct
    values of a sequence of uniform draws form a uniformly random ``k``-subset
    (by symmetry between the values).  For ``k`` much smaller than ``n`` this
    avoids ``Generator.choice``'s permutation of all ``n`` indices, which
    dominated the strategic prior's cost.
    """
    if k >= n:
        return np.arange(n)
    rows = sorted_unique(rng.integers(n, size=k))
    while rows.shape[0] < k:
        rows = sorted_unique(np.concatenate([rows, rng.integers(n, size=k - rows.shape[0])]))
    return rows


def sorted_unique(values: np.ndarray) -> np.ndarray:
    """``np.unique(values)`` of a 1-D integer array: sorted, each value once.

    The same array as ``np.unique``, in a sort and a comparison: on the
    agent's arrays of about a hundred rows it costs half as much, and the
    agent calls it twice per action and model at every decision.
    """
    values = np.sort(values)
    if values.shape[0] < 2:
        return values
    keep = np.empty(values.shape[0], dtype=bool)
    keep[0] = True
    np.not_equal(values[1:], values[:-1], out=keep[1:])
    return values[keep]


def draw_subset(n: int, max_points: int | None, rng) -> np.ndarray:
    """Sorted row indices: all ``n`` rows, or ``max_points`` drawn without replacement."""
    if max_points is None or n <= max_points:
        return np.arange(n)
    return np.sort(as_generator(rng).choice(n, size=max_points, replace=False))
