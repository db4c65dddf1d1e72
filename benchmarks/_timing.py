"""Shared helpers for the benchmark scripts (not part of the package)."""

from __future__ import annotations

import statistics
import time


def median_seconds(fn, repeats: int, warmup: int = 3) -> float:
    """Median wall-clock seconds of ``fn()`` over ``repeats`` calls."""
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def one_core():
    """Limit BLAS/OpenMP to one thread, as the speed targets are stated for one core.

    Small matrices (the agent's 110 x 110) are slower with several BLAS
    threads than with one.  Returns a context manager.
    """
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1)
