"""One cell's error does not stop a sweep of hours: each cell runs guarded, and the failures are raised at the end.

The paired sweep (:func:`~sarsp_edu.experiments.sweep.run_sweep`), the
ablation and the model sweep share this: a worker runs its cell through
:func:`run_guarded`, the sweep collects the cells that raised in
:func:`collecting` and runs the others on, and :class:`CellsFailed` names each
at the end with its traceback.  An error of the machine (out of memory, or of
the disk when storing) and Ctrl-C stop a sweep at once; the failures collected
before are then said on stderr, not lost.  :func:`in_workers` runs the cells
in joblib's worker processes and stops them at once on Ctrl-C.
"""

from __future__ import annotations

import sys
import traceback
from contextlib import contextmanager

from .cells import _cell_name

__all__ = ["CellsFailed", "collecting", "failure_name", "in_workers", "run_guarded", "tracebacks"]

#: how many failing cells an error message names before it counts the rest
_NAMED = 5


class CellsFailed(RuntimeError):
    """Cells of a sweep whose run raised; the sweep ran every other cell (and stored it, where it stores).

    Attributes
    ----------
    failures : dict
        ``{(m, p, nss, seed): (the error in one line, the traceback's text)}`` of each cell that raised; an
        ablation's keys begin with the setting's folder, ``(folder, m, p, nss, seed)``.
    results_dir : str or None
        Where the other cells are stored (None where the sweep stores nothing).
    results : object or None
        What the sweep returns, holding the cells that ran (None where it returns only what is stored).
    """

    def __init__(self, failures: dict, results_dir=None, results=None):
        self.failures = _in_order(failures)
        self.results_dir = None if results_dir is None else str(results_dir)
        self.results = results
        where = ("" if results_dir is None else
                 f" and are stored in {results_dir}, and a rerun runs only the cells missing")
        super().__init__(f"{_count(self.failures)} raised ({_lines(self.failures)}); the other cells ran{where}")

    def __reduce__(self):  # pickled as it was made (a Dask or joblib caller may send it between processes)
        return type(self), (self.failures, self.results_dir, self.results)


def _in_order(failures: dict) -> dict:
    try:
        return dict(sorted(failures.items()))
    except TypeError:  # keys of different shapes: as they came
        return dict(failures)


def _count(failures: dict) -> str:
    return f"{len(failures)} cell{'s' if len(failures) != 1 else ''}"


def _lines(failures: dict) -> str:
    """Each cell's name and error line, the first few of many (a systematic error raises in every cell)."""
    said = [f"{failure_name(key)}: {line}" for key, (line, _) in list(failures.items())[:_NAMED]]
    rest = len(failures) - _NAMED
    return "; ".join(said) + (f"; and {rest} more" if rest > 0 else "")


def failure_name(key) -> str:
    """A cell's name in :class:`CellsFailed`: its folder's, after its setting's folder where it has one."""
    return "/".join([*map(str, key[:-4]), _cell_name(*key[-4:])])


def tracebacks(failures: dict) -> str:
    """Each distinct traceback once, after the names of the cells that raised it."""
    cells = {}
    for key, (_, text) in failures.items():
        cells.setdefault(text, []).append(failure_name(key))
    return "\n".join(f"{', '.join(names)}:\n{text}" for text, names in cells.items())


def run_guarded(key, run):
    """``(key, run(), None)``, or where ``run`` raised ``(key, None, (the error in one line, its traceback))``.

    An error of the machine (out of memory, or of the disk when storing) raises at once, as a
    KeyboardInterrupt does: every other cell would meet it too.

    Parameters
    ----------
    key : tuple
        The cell's key, returned with the outcome.
    run : callable
        Runs the cell (and stores it), called with no argument.
    """
    try:
        return key, run(), None
    except (MemoryError, OSError):
        raise
    except Exception as exc:  # named with its cell, and raised once the other cells have run
        return key, None, (f"{type(exc).__name__}: {exc}".splitlines()[0], traceback.format_exc())


@contextmanager
def collecting(results_dir=None, results=None):
    """A dict for each failing cell's ``(line, traceback)``, raised as :class:`CellsFailed` where the block ends.

    Where the block stops on another error first (Ctrl-C, a full disk), the cells collected are said on stderr
    before that error goes on.

    Parameters
    ----------
    results_dir : path-like, optional
        Where the sweep stores its cells, for the error's message.
    results : object, optional
        What the sweep returns, for the error's ``results``.
    """
    failures = {}
    try:
        yield failures
    except BaseException:
        if failures:
            print(f"before the sweep stopped, {_count(failures)} had raised: {_lines(_in_order(failures))}",
                  file=sys.stderr)
        raise
    if failures:
        raise CellsFailed(failures, results_dir, results)


def in_workers(function, calls, n_jobs: int):
    """Yield ``function(*args)`` for each ``args`` of ``calls``, in joblib's worker processes, as each finishes.

    Ctrl-C stops the workers at once, so that no process outlives the command or leaves its semaphores behind
    (the cells stored stay; a rerun resumes).

    Parameters
    ----------
    function : callable
        What each worker runs (picklable: a module's function).
    calls : iterable of tuple
        The arguments of each call.
    n_jobs : int
        Worker processes.
    """
    from joblib import Parallel, delayed
    from joblib.externals.loky import get_reusable_executor

    from ..._internal.parallel import workers_deaf_to_interrupts

    try:
        with workers_deaf_to_interrupts():  # joblib's workers (and its threads) start within this call
            results = Parallel(n_jobs=n_jobs, return_as="generator_unordered")(delayed(function)(*args)
                                                                               for args in calls)
        yield from results
    except KeyboardInterrupt:
        get_reusable_executor().shutdown(wait=True, kill_workers=True)
        raise
