"""One BLAS thread for the package's many small factorisations.

An agent decision factorises a ~110 x 110 matrix and a fit a few hundred
square: sizes where a multi-threaded BLAS only adds overhead, and where an
oversubscribed one (more BLAS threads than free cores: a laptop running a
sweep, a Binder pod that shows many cores and grants one) runs many times
slower.  Experiments, sweep cells, dashboards and the agent's offline fit
therefore run inside ``one_blas_thread()``; the regression models themselves, which a user may
fit on large data, do not limit anything.
"""

from __future__ import annotations

from threadpoolctl import threadpool_limits


def one_blas_thread():
    """A context manager limiting BLAS to one thread (threadpoolctl), restored on exit."""
    return threadpool_limits(limits=1, user_api="blas")
