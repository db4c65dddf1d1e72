"""``run_sweep``: the cells run locally (joblib processes) or on a Dask cluster, each stored as it finishes.

A cell is written to a staging folder and renamed into place, so a folder
holds only whole cells; a lock keeps two sweeps out of one folder, and a
rerun of the same command skips the cells already stored.  A cell whose run
raises is named and the others run on (:mod:`~sarsp_edu.experiments.sweep.failures`).
"""

from __future__ import annotations

import json
import numbers
import shutil
import signal
import sys
import warnings
from pathlib import Path

from ..._internal.io import (
    StoredResultError,
    atomic_write_text,
    lock_folder,
    one_line_warning,
    publish_folder,
    read_json,
)
from ..._internal.validation import check_fraction, check_int, check_positive
from ..._version import __version__
from ...config import (
    DEFINITION_4_A,
    PAPER_MAGNITUDES,
    PAPER_PROPORTIONS,
    PAPER_SWITCH_STATES,
    ExperimentConfig,
    config_or_default,
)
from ..experiment import compare
from ..metrics import check_a
from ..results import Comparison
from .cells import (
    StoredResultWarning,
    _as_key,
    _cell_name,
    _check_cell,
    _shared_fields,
    _stored_base,
    cell_config,
    cell_seed,
    finished_cells,
)
from .failures import collecting, in_workers, run_guarded
from .stored import SweepResults, load_cell, stored_sweep

LOCK_NAME = ".sweep.lock"


# --------------------------------------------------------------------------
# running
# --------------------------------------------------------------------------
def _run_cell(base: ExperimentConfig, key: tuple, results_dir: str | None) -> tuple:
    """Run one paired cell; store it atomically if a folder is given.

    Returns ``(key, Comparison, None)``, or where it raised ``(key, None, (the error in one line, the
    traceback's text))`` (:func:`~sarsp_edu.experiments.sweep.failures.run_guarded`).
    """
    def run():
        comparison = compare(cell_config(base, *key), n_jobs=1)  # a sweep: one process per cell
        if results_dir is not None:
            _store_cell(Path(results_dir), key, comparison)
        return comparison

    return run_guarded(key, run)


def _run_cell_in_worker(base: ExperimentConfig, key: tuple, results_dir: str | None) -> tuple:
    """``_run_cell`` in a worker process, which leaves Ctrl-C to the main process.

    A terminal sends SIGINT to every process of the command; workers that died
    of it mid-cell would print their tracebacks and leak their semaphores.
    The main process stops them instead.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    warnings.formatwarning = one_line_warning  # as the command's own process shows them
    return _run_cell(base, key, results_dir)


def _store_cell(results_dir: Path, key: tuple, comparison: Comparison) -> None:
    """Write the cell into a temporary folder, then rename it into place (atomic)."""
    def write(staging):
        comparison.save(staging)
        atomic_write_text(staging / "cell.json", json.dumps({"key": list(key)}) + "\n")

    publish_folder(results_dir / "cells" / _cell_name(*key), write, marker="cell.json")


def _prepare_folder(results_dir: Path, base: ExperimentConfig, keys: list) -> set:
    """Check (or write) the folder's base config and add ``keys`` to the cells it is asked for.

    The caller holds the folder's lock.  Returns the keys of the cells stored there.
    """
    meta = results_dir / "sweep.json"
    payload = {"base_config": base.to_dict(), "requested": [], "sarsp_edu_version": __version__}
    if meta.exists():
        stored = read_json(meta, keys=("base_config",))
        stored_sweep(results_dir)  # sweep.json and its cells agree
        ours, theirs = _shared_fields(base), _shared_fields(_stored_base(meta, stored))
        differing = sorted(k for k in ours if ours[k] != theirs.get(k))
        if differing:
            details = ", ".join(f"{k}: folder {theirs.get(k)!r}, now {ours[k]!r}" for k in differing)
            raise ValueError(
                f"{results_dir} holds a sweep with other settings ({details}); "
                "use another results_dir or the same settings"
            )
        payload = {**stored, "requested": stored.get("requested", [])}
    requested = {_as_key(key) for key in payload["requested"]}
    if not requested.issuperset(keys):
        payload["requested"] = [list(key) for key in sorted(requested.union(keys))]
        atomic_write_text(meta, json.dumps(payload, indent=2) + "\n")
    _clear_staging(results_dir)
    return finished_cells(results_dir)


def _clear_staging(results_dir: Path) -> None:
    """Remove the staging folders of cells whose storing was interrupted."""
    for stale in (results_dir / "cells").glob(".m*"):
        shutil.rmtree(stale, ignore_errors=True)


def _grid(name, values, check):
    values = tuple(values)
    if not values:
        raise ValueError(f"{name} must hold at least one value, got {name}={values!r}")
    for v in values:
        check(v)
    if len(set(values)) != len(values):
        raise ValueError(f"{name} must not repeat a value, got {name}={values!r}")
    return values


def run_sweep(
    config: ExperimentConfig | None = None,
    *,
    magnitudes=PAPER_MAGNITUDES,
    proportions=PAPER_PROPORTIONS,
    n_switch_states=PAPER_SWITCH_STATES,
    seeds=(0,),
    cells=None,
    results_dir=None,
    n_jobs: int = 1,
    scheduler=None,
    progress: bool = False,
    a: float = DEFINITION_4_A,
) -> SweepResults:
    """Run the paper's grid of paired TP-vs-GP comparisons.

    Parameters
    ----------
    config : ExperimentConfig, optional
        Shared settings (episodes, grid size, nu, ...); its ``model``,
        ``outlier_magnitude``, ``outlier_proportion``, ``n_switch_states`` and
        ``seed`` are set per cell.  Default: the paper's.
    magnitudes, proportions, n_switch_states : sequences
        The grid; defaults are the paper's 3 x 3 x 5 = 45 configurations.
    seeds : sequence of int, default (0,)
        Sweep seeds; each cell's run seed derives from one of them and the cell.
    cells : sequence of (m, p, nss), optional
        Run these configurations instead of the grid of ``magnitudes`` x
        ``proportions`` x ``n_switch_states`` (an ablation's few cells).
    results_dir : path, optional
        A folder to store each finished cell in (atomically, as it finishes).
        A rerun skips the cells already there; a folder holding a sweep with
        other shared settings is an error.
    n_jobs : int, default 1
        Local worker processes (joblib); -1 for one per core.
    scheduler : str or dask.distributed.Client, optional
        Run the cells on a Dask cluster instead (needs the ``dask`` extra);
        with ``results_dir`` the workers must see the same file system.  A
        sweep that stops early (Ctrl-C, an error) cancels its cells still
        queued or running there; the client is closed only if the sweep made it.
    progress : bool, default False
        A progress bar over cells.
    a : float, default 100.0
        Definition 4's TSR threshold, for the verdicts.

    Returns
    -------
    SweepResults
        Every cell of the grid: those run now and those found in ``results_dir``.

    Raises
    ------
    CellsFailed
        If the run of some cell raised: each is named (under the progress bar as it happens), every other
        cell was run (and stored), and the exception's ``results`` holds them.
    """
    base = config_or_default(config)
    seeds = _grid("seeds", seeds, lambda v: check_int("seeds", v, 0))
    if cells is None:
        magnitudes = _grid("magnitudes", magnitudes, lambda v: check_positive("magnitudes", v))
        proportions = _grid("proportions", proportions, lambda v: check_fraction("proportions", v))
        n_switch_states = _grid("n_switch_states", n_switch_states,
                                lambda v: base.replace(n_switch_states=v))
        cells = [(m, p, nss) for m in magnitudes for p in proportions for nss in n_switch_states]
    else:
        cells = _grid("cells", [tuple(cell) for cell in cells], lambda cell: _check_cell(base, cell))
    if scheduler is None:
        _check_jobs(n_jobs)
    check_a(a)
    # + 0.0: a proportion of -0.0 is the cell p = 0 (its own folder name would be p-0, a second copy of the cell)
    cells = [(float(m) + 0.0, float(p) + 0.0, nss) for m, p, nss in cells]
    keys = [(m, p, int(nss), int(seed)) for seed in seeds for m, p, nss in cells]
    _refuse_twins(keys)

    if scheduler is not None:
        _dask()  # before any work: a missing Dask is said at once
    results = SweepResults(base, a=a)
    folder = None if results_dir is None else Path(results_dir)
    lock = None
    try:
        if folder is not None:
            folder.mkdir(parents=True, exist_ok=True)
            lock = lock_folder(folder, LOCK_NAME, "sweep")
            _prepare_folder(folder, base, keys)
            for key in keys:
                cell = folder / "cells" / _cell_name(*key)
                if not cell.exists():
                    continue
                try:
                    results.comparisons[key] = load_cell(base, cell, key, a=a)
                except (FileNotFoundError, StoredResultError) as exc:
                    warnings.warn(f"{exc}; computing the cell again", StoredResultWarning, stacklevel=2)
                    shutil.rmtree(cell)
        todo = [key for key in keys if key not in results.comparisons]

        from tqdm.auto import tqdm

        with tqdm(total=len(keys), initial=len(keys) - len(todo), desc="sweep cells", unit="cell",
                  disable=not progress) as bar, collecting(folder, results) as failures:
            for key, comparison, failure in _execute(base, todo, None if folder is None else str(folder), n_jobs,
                                                     scheduler):
                bar.update(1)
                if failure is not None:
                    failures[key] = failure
                    bar.set_postfix_str(f"{len(failures)} raised")
                    if progress:
                        bar.write(f"{_cell_name(*key)} raised {failure[0]}", file=sys.stderr)
                    continue
                comparison.a = a
                results.comparisons[key] = comparison
    finally:
        if lock is not None:
            lock.close()
    return results


def _refuse_twins(keys) -> None:
    """Refuse two cells that share a folder name or a run seed (m to 3 decimals, p to 6): one would overwrite,
    or repeat, the other."""
    names, seeds = {}, {}
    for key in dict.fromkeys(keys):
        for seen, mark in ((names, _cell_name(*key)), (seeds, (key[2], key[3], cell_seed(key[3], *key[:3])))):
            twin = seen.setdefault(mark, key)
            if twin != key:
                raise ValueError(
                    f"the cells m={twin[0]!r} p={twin[1]!r} and m={key[0]!r} p={key[1]!r} (nss={key[2]}) would share "
                    f"the folder {_cell_name(*key)} or one run seed, and one would overwrite or repeat the other; give "
                    "magnitudes that differ in their first three decimals and proportions in their first six")


def _check_jobs(n_jobs: int) -> None:
    """Refuse a worker count other than a positive whole number or -1 (one per core)."""
    if isinstance(n_jobs, bool) or not isinstance(n_jobs, numbers.Integral) or not (n_jobs == -1 or n_jobs >= 1):
        raise ValueError(f"n_jobs must be a positive integer or -1 (one per core), got n_jobs={n_jobs!r}")


def _workers(n_jobs: int, cells: int, stacklevel: int = 4) -> int:
    """Worker processes for ``cells`` cells: at most one per cell and per core (said when fewer than asked)."""
    from ..._internal.parallel import available_cores

    cores = available_cores()
    workers = max(1, min(cores if n_jobs == -1 else n_jobs, cells, cores))
    if n_jobs != -1 and workers < n_jobs:
        warnings.warn(f"n_jobs={n_jobs}: running {workers} worker process{'es' if workers > 1 else ''}, for "
                      f"{cells} cell{'s' if cells > 1 else ''} to run on {cores} core{'s' if cores > 1 else ''} "
                      "(more would only wait)", UserWarning, stacklevel=stacklevel)
    return workers


def _execute(base, todo, folder, n_jobs, scheduler):
    """Yield (key, Comparison, None), or (key, None, failure) for a cell that raised, as cells finish, in any
    order."""
    if not todo:
        return
    if scheduler is not None:
        yield from _execute_dask(base, todo, folder, scheduler)
        return
    n_jobs = _workers(n_jobs, len(todo))
    if n_jobs == 1:
        for key in todo:
            yield _run_cell(base, key, folder)
    else:
        try:
            yield from in_workers(_run_cell_in_worker, [(base, key, folder) for key in todo], n_jobs)
        except KeyboardInterrupt:  # the workers have stopped (the finished cells are stored)
            if folder is not None:
                _clear_staging(Path(folder))
            raise


def _dask():
    """``dask.distributed``, or an ImportError that says how to install it."""
    try:
        import dask.distributed
    except ImportError:
        raise ImportError("scheduler= needs Dask, which is not installed: pip install 'sarsp_edu[dask]'") from None
    return dask.distributed


def _execute_dask(base, todo, folder, scheduler):
    distributed = _dask()
    Client, as_completed = distributed.Client, distributed.as_completed
    client = scheduler if isinstance(scheduler, Client) else Client(scheduler)
    futures = []
    try:
        futures = [client.submit(_run_cell, base, key, folder, pure=False) for key in todo]
        for future in as_completed(futures):
            yield future.result()
    finally:
        try:
            pending = [future for future in futures if not future.done()]
            if pending:  # a sweep stopped (Ctrl-C, an error): nothing of it goes on running on the cluster
                client.cancel(pending)
        except Exception as exc:  # a lost client: the error that stopped the sweep is the one to see
            warnings.warn(f"the sweep's cells left on the cluster could not be cancelled ({exc})", UserWarning,
                          stacklevel=2)
        finally:
            if client is not scheduler:
                client.close()
