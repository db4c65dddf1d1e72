"""One BLAS thread for the package's many small factorisations.

An agent decision factorises a ~110 x 110 matrix and a fit a few hundred
square: sizes where a multi-threaded BLAS only adds overhead, and where an
oversubscribed one (more BLAS threads than free cores: a laptop running a
sweep, a Binder pod that shows many cores and grants one) runs many times
slower.  Experiments, sweep cells, dashboards and the agent's offline fit
therefore run inside ``one_blas_thread()``; the regression models themselves, which a user may
fit on large data, do not limit anything.

The limit is process-wide (BLAS has one thread pool), so the context is
counted: a dashboard preparing its agents in a worker thread while the
notebook runs another experiment keeps one BLAS thread until the last of
them leaves, whatever the order they leave in.
"""

from __future__ import annotations

import contextlib
import threading

from threadpoolctl import threadpool_limits

_LOCK = threading.Lock()
_STATE = {"depth": 0, "limiter": None}


@contextlib.contextmanager
def one_blas_thread():
    """A context manager limiting BLAS to one thread (threadpoolctl), restored when the last user leaves."""
    with _LOCK:
        if _STATE["depth"] == 0:
            _STATE["limiter"] = threadpool_limits(limits=1, user_api="blas")
        _STATE["depth"] += 1
    try:
        yield
    finally:
        with _LOCK:
            _STATE["depth"] -= 1
            if _STATE["depth"] == 0:
                _STATE["limiter"].restore_original_limits()
                _STATE["limiter"] = None
