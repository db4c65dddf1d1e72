"""Running a student's code safely: a time limit, and a watch on the inputs it was given.

A student's function runs in a daemon thread and is waited for
:data:`TIME_LIMIT` seconds at most, so that a check always returns (an
endless loop is then asked to stop, which a loop of Python code does at its
next step).  It is called on copies of the inputs; comparing the copies with
the originals afterwards tells whether it changed its inputs in place.
"""

from __future__ import annotations

import copy
import ctypes
import threading

import numpy as np

__all__ = ["TIME_LIMIT", "TimedOut", "call_copies", "changed", "run_limited"]

#: seconds a student's function (or prediction) may run on one input before the check gives up on it
TIME_LIMIT = 10.0


class TimedOut(Exception):
    """A student's code did not return within the time limit."""

    def __init__(self, limit: float):
        super().__init__(f"did not return within {limit:g} s")
        self.limit = limit


class _Stopped(BaseException):
    """Raised inside a thread that ran past its time limit, to end it."""


def _stop(thread: threading.Thread) -> None:
    """Ask ``thread`` to raise :class:`_Stopped` at its next Python step (CPython; a C call finishes first)."""
    try:
        ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(thread.ident), ctypes.py_object(_Stopped))
    except Exception:  # another interpreter: the daemon thread is left to end with the process
        pass


def run_limited(function, args=(), limit: float | None = None):
    """``function(*args)``, waited for ``limit`` seconds (default :data:`TIME_LIMIT`).

    Returns its result or raises what it raised; raises :class:`TimedOut`
    when it runs longer.

    Parameters
    ----------
    function : callable
        The student's function, run in a daemon thread.
    args : sequence, default ()
        Its positional arguments.
    limit : float, optional
        Seconds to wait; None: :data:`TIME_LIMIT`.
    """
    limit = TIME_LIMIT if limit is None else limit
    box: dict = {}

    def target():
        try:
            box["value"] = function(*args)
        except _Stopped:
            pass
        except BaseException as exc:  # noqa: BLE001 - the student's code may raise anything; said by the caller
            box["error"] = exc

    thread = threading.Thread(target=target, name="sarsp_edu-exercise", daemon=True)
    thread.start()
    try:
        thread.join(limit)
    except BaseException:  # the check interrupted (Ctrl-C): the student's code stops with it
        _stop(thread)
        raise
    if thread.is_alive():
        _stop(thread)
        raise TimedOut(limit)
    if "error" in box:
        raise box["error"]
    return box.get("value")


def call_copies(function, case: dict, limited: bool = False):
    """``function`` on copies of ``case``'s values, passed in order (a student may name them as they like).

    Returns ``(result, copies)``; the copies show what the function did to its inputs.

    Parameters
    ----------
    function : callable
    case : dict
        The inputs, by name, in the signature's order (deep-copied before the call).
    limited : bool, default False
        Run it with :func:`run_limited`'s time limit.
    """
    args = copy.deepcopy(list(case.values()))
    result = run_limited(function, args) if limited else function(*args)
    return result, args


def changed(before, after) -> bool:
    """Whether ``after`` (a copy of ``before`` that a function was given) was changed in place.

    Parameters
    ----------
    before : object
        The input as it was (arrays, dicts, lists and tuples compared item by item; NaN equals NaN).
    after : object
        The copy after the call.
    """
    if isinstance(before, np.ndarray):
        if not isinstance(after, np.ndarray) or after.shape != before.shape or after.dtype != before.dtype:
            return True
        if before.dtype.kind in "fc":
            return not np.array_equal(before, after, equal_nan=True)
        return not np.array_equal(before, after)
    if isinstance(before, dict):
        return (not isinstance(after, dict) or list(before) != list(after)
                or any(changed(before[key], after[key]) for key in before))
    if isinstance(before, (list, tuple)):
        return (not isinstance(after, type(before)) or len(before) != len(after)
                or any(changed(b, a) for b, a in zip(before, after)))
    if isinstance(before, (float, np.floating)) and isinstance(after, (float, np.floating)):
        return not (before == after or (before != before and after != after))  # NaN stays NaN
    try:
        return bool(before != after)
    except Exception:  # an object that cannot compare itself: not ours to judge
        return False
