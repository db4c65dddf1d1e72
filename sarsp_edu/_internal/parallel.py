"""A second process for the second half of a paired run (``compare``'s GP side).

The two models of a comparison share nothing while they run, so on a machine
with two free cores the GP's run goes to a worker process (loky, as joblib
uses: a fresh interpreter, safe where threads are running) while this
process runs the TP's.  Each runs with one BLAS thread.  The worker is kept
for the next comparison; the warnings it raises are raised again here, in
order, after the TP's own.
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
import warnings

__all__ = ["available_cores", "in_second_process", "stop_workers", "workers_deaf_to_interrupts"]


@contextlib.contextmanager
def workers_deaf_to_interrupts():
    """Within the block, worker processes start with Ctrl-C ignored; this process hears it when the block ends.

    A Ctrl-C reaches every process of the terminal's group: a worker still importing would print its own
    ``KeyboardInterrupt`` traceback above the command's one-line message.  SIGINT is ignored for the block, and
    an ignored signal stays ignored through ``exec``: the workers started in it never see one, and the command,
    which alone hears it, stops them.  It is also blocked in this thread for the block, so that a Ctrl-C pressed
    meanwhile waits (Linux keeps a blocked signal pending even while it is ignored) and arrives when the block
    ends.  The block lasts while the workers are started, not while they import: about 50 ms measured for
    ``in_second_process`` and for ``in_workers``' two workers.  Where another thread of this process takes the
    signal in those milliseconds (BLAS's own threads do not block it), that Ctrl-C is dropped and a second one
    stops the command.  Off the main thread, where no handler can be set, it does nothing.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    masks = hasattr(signal, "pthread_sigmask")
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT}) if masks else None
    handler = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, handler)
        if masks:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # a Ctrl-C pressed meanwhile arrives here


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system says, else the CPU count)."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def _call_recording_warnings(function, args, kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        value = function(*args, **kwargs)
    return value, [(w.message, w.category) for w in caught]


class _Pending:
    def __init__(self, future):
        self._future = future

    def result(self):
        """The call's value, once its warnings were raised again here."""
        value, caught = self._future.result()
        for message, category in caught:
            warnings.warn(message, category, stacklevel=2)
        return value


_WORKER = {"executor": None}  # the comparison's own worker, apart from joblib's (a sweep's) reusable pool


def in_second_process(function, *args, **kwargs) -> _Pending:
    """Start ``function(*args, **kwargs)`` in a worker process; ``.result()`` waits for its value.

    The worker is this module's own loky executor, kept for the next call; it
    is not joblib's reusable pool, which a sweep's ``Parallel`` expects to
    have made itself.
    """
    from joblib.externals.loky import ProcessPoolExecutor

    with workers_deaf_to_interrupts():  # the worker starts within submit
        if _WORKER["executor"] is None:
            _WORKER["executor"] = ProcessPoolExecutor(max_workers=1)
        return _Pending(_WORKER["executor"].submit(_call_recording_warnings, function, args, kwargs))


def stop_workers() -> None:
    """Stop the worker now (after Ctrl-C: none outlives the command or keeps its semaphores)."""
    executor, _WORKER["executor"] = _WORKER["executor"], None
    if executor is not None:
        executor.shutdown(wait=True, kill_workers=True)
