"""Random helpers shared by the world, the data, the models and the agent.

Every stochastic function of the package takes ``rng``: ``None``, an int
seed or a ``numpy.random.Generator``; :func:`as_generator` turns each into a
Generator, so that the same seed gives the same numbers in any process.
"""

from __future__ import annotations

import numbers

import numpy as np

__all__ = ["as_generator", "draw_row_mask", "draw_rows", "draw_subset"]


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
    return np.flatnonzero(draw_row_mask(n, k, rng))


def draw_row_mask(n: int, k: int, rng: np.random.Generator) -> np.ndarray:
    """The rows of :func:`draw_rows` as a boolean mask of length ``n`` (the same draws).

    The agent marks the matching rows of a query in the same mask, so that
    the union of the two is one ``np.flatnonzero`` instead of a sort: the
    indices, and the numbers drawn from ``rng``, are those of ``draw_rows``
    followed by ``np.union1d``.
    """
    mask = np.zeros(n, dtype=bool)
    if k >= n:
        mask[:] = True
        return mask
    mask[rng.integers(n, size=k)] = True
    drawn = int(np.count_nonzero(mask))
    while drawn < k:
        mask[rng.integers(n, size=k - drawn)] = True
        drawn = int(np.count_nonzero(mask))
    return mask


def draw_subset(n: int, max_points: int | None, rng) -> np.ndarray:
    """Sorted row indices: all ``n`` rows, or ``max_points`` drawn without replacement."""
    if max_points is None or n <= max_points:
        return np.arange(n)
    return np.sort(as_generator(rng).choice(n, size=max_points, replace=False))
