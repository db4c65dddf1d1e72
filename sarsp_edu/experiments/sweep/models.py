"""Another model on every cell of a stored paired sweep: one more run on the very same worlds.

A cell's world, offline data, outlier rows, shift and episode starts depend
on its settings and seed, never on the model (``PREPARATION_FIELDS``), so a
run of a third model on a cell's settings is paired with the cell's TP and
GP runs, which are reused as stored.  :func:`run_model_sweep` runs it for
every cell of a paired sweep (in worker processes, each cell stored
atomically as it finishes; a rerun skips the cells stored; a cell that
raises is named and the others run on, :class:`CellsFailed`), and
:func:`load_model_sweep` reads the three runs of each cell back, checking
that they share their episodes.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

from ..._internal.io import StoredResultError, atomic_write_text, lock_folder, publish_folder, read_json
from ..._internal.validation import check_choice
from ..._version import __version__
from ...config import MODELS
from ..results import ExperimentResult, check_paired
from .cells import _as_key, _cell_name, _name_key, cell_config, finished_cells
from .failures import CellsFailed, collecting, in_workers, run_guarded
from .run import _check_jobs, _workers
from .stored import SweepResults, stored_sweep

__all__ = ["MODEL_SWEEP_FILE", "CellsFailed", "check_model_cell", "load_model_sweep", "run_model_sweep"]

#: the file that names the paired sweep and the model a model sweep's folder holds
MODEL_SWEEP_FILE = "model_sweep.json"
_LOCK = ".model-sweep.lock"


def _run_cell(base, key, model: str, folder: str) -> tuple:
    """Run ``model`` on one cell's settings and store it atomically in ``folder``'s cells.

    Returns ``(key, None)``, or where the run raised ``(key, (the error in one line, the traceback's text))``
    (:func:`~sarsp_edu.experiments.sweep.failures.run_guarded`).
    """
    from ..experiment import run_experiment

    def run():
        result = run_experiment(cell_config(base, *key).replace(model=model))
        publish_folder(Path(folder) / "cells" / _cell_name(*key) / model, result.save, marker="result.json")

    key, _, failure = run_guarded(key, run)
    return key, failure


def _changed(base, changes):
    """The paired sweep's settings ``base`` with a model sweep's ``changes`` (none of the world's)."""
    from ...world.preparation import PREPARATION_FIELDS

    if not changes:
        return base
    if not isinstance(changes, dict):
        raise StoredResultError(f"a model sweep's changes are a mapping of settings, got changes={changes!r}")
    shared = sorted(set(changes) & set(PREPARATION_FIELDS))
    if shared:
        raise ValueError(f"changes may change the model's and the agent's settings, not {shared}, which shape the "
                         "world the runs are paired on")
    return base.replace(**changes)


def _stored(folder: Path, model: str) -> set:
    """The cells of ``folder`` whose run of ``model`` is stored whole."""
    keys = {_name_key(cell.name) for cell in (folder / "cells").glob("m*") if (cell / model / "result.json").exists()}
    return keys - {None}


def run_model_sweep(paired_dir, results_dir, model: str = "t-likelihood", n_jobs: int | None = None,
                    cells=None, report=None, changes: dict | None = None) -> set:
    """Run ``model`` on the cells of the paired sweep in ``paired_dir``, storing each run in ``results_dir``.

    Parameters
    ----------
    paired_dir : path-like
        A stored TP-vs-GP sweep (:func:`~sarsp_edu.experiments.sweep.run_sweep`'s folder): its settings and
        cells are the ones run, its runs are reused as they are.
    results_dir : path-like
        Where the runs of ``model`` go, one per cell (``cells/<cell>/<model>/``); a rerun skips those stored.
    model : str, default "t-likelihood"
        A model of ``MODELS`` other than "tp" and "gp".
    n_jobs : int, optional
        Worker processes (one cell each at a time); default (or -1) one per core.
    cells : iterable of (m, p, nss, seed), optional
        Only these cells (each must be a cell of the paired sweep); default every one.
    report : callable, optional
        Called with a line as each cell is stored (``print`` in the command).
    changes : dict, optional
        ``ExperimentConfig`` fields the model's runs change from the paired sweep's settings (the model's own,
        or the agent's: never those of ``PREPARATION_FIELDS``, which would change the world the runs are paired
        on); stored in ``model_sweep.json``.

    Returns
    -------
    set of (m, p, nss, seed)
        The cells whose run of ``model`` is stored in ``results_dir`` now.

    Raises
    ------
    CellsFailed
        If the run of some cell raised; each is named (``report`` says so as it happens), and every other
        cell was run and stored.
    """
    check_choice("model", model, tuple(m for m in MODELS if m not in ("tp", "gp")))
    if n_jobs is not None:
        _check_jobs(n_jobs)
    paired_dir, results_dir = Path(paired_dir), Path(results_dir)
    if results_dir.resolve() == paired_dir.resolve() or (results_dir / "sweep.json").exists():
        raise ValueError(f"results_dir={str(results_dir)!r} holds a paired sweep; the model's runs go into a "
                         "folder of their own")
    base, _ = stored_sweep(paired_dir)
    changes = dict(changes or {})
    base = _changed(base, changes)
    stored = finished_cells(paired_dir)  # the cells whose TP and GP runs are there to be paired with
    keys = sorted(stored if cells is None else {_as_key(key) for key in cells})
    unknown = sorted(set(keys) - stored)
    if unknown:
        raise ValueError(f"cells {unknown} are not cells of the paired sweep in {paired_dir} (stored: "
                         f"{len(stored)})")
    results_dir.mkdir(parents=True, exist_ok=True)
    lock = lock_folder(results_dir, _LOCK, "model sweep")
    try:
        meta = results_dir / MODEL_SWEEP_FILE
        payload = {"paired": os.path.relpath(paired_dir, results_dir), "model": model,
                   "base_config": base.replace(model=model).to_dict(), "sarsp_edu_version": __version__}
        if changes:  # a folder of the model's runs on the paired settings alone holds none: as before 0.3
            payload["changes"] = changes
        if meta.exists():
            held = read_json(meta, keys=("paired", "model", "base_config"))
            same_paired = (results_dir / held["paired"]).resolve() == paired_dir.resolve()
            if (held["model"], held["base_config"], held.get("changes", {})) != (model, payload["base_config"],
                                                                                  changes) or not same_paired:
                raise ValueError(f"{results_dir} holds runs of {held['model']!r} on the paired sweep "
                                 f"{(results_dir / held['paired']).resolve()}; use another folder for {model!r} on "
                                 f"{paired_dir.resolve()}")
        else:
            atomic_write_text(meta, json.dumps(payload, indent=2) + "\n")
        for stale in (results_dir / "cells").glob(f"m*/.{model}.*"):  # a run whose storing was interrupted
            shutil.rmtree(stale, ignore_errors=True)
        todo = [key for key in keys if key not in _stored(results_dir, model)]
        if todo:
            workers = _workers(-1 if n_jobs is None else n_jobs, len(todo), stacklevel=3)
            done = len(keys) - len(todo)
            if report is not None:  # said at once: a cell's fits and episodes take minutes before its first line
                report(f"{model}: running {len(todo)} of {len(keys)} cells ({done} stored) in {workers} worker "
                       f"process{'es' if workers > 1 else ''}: each fits its models, then runs its "
                       f"{base.episodes} episodes; a line as each is stored")
            with collecting(results_dir) as failures:
                for key, failure in in_workers(_run_cell, [(base, key, model, str(results_dir)) for key in todo],
                                               workers):
                    if failure is not None:
                        failures[key] = failure
                    done += failure is None
                    if report is not None:
                        said = (f"stored ({done} of {len(keys)})" if failure is None else
                                f"raised {failure[0]} ({done} of {len(keys)} stored)")
                        report(f"{model}: {_cell_name(*key)} {said}")
        return _stored(results_dir, model)
    finally:
        if lock is not None:
            lock.close()


def load_model_sweep(results_dir) -> tuple:
    """The paired sweep and the other model's runs of a model sweep's folder, each cell's three runs paired.

    Parameters
    ----------
    results_dir : path-like
        A folder :func:`run_model_sweep` wrote.

    Returns
    -------
    (SweepResults, dict)
        The paired sweep (read from the folder ``model_sweep.json`` names) and ``{(m, p, nss, seed):
        ExperimentResult}`` of the other model, for the cells it has run.

    Raises
    ------
    StoredResultError
        A run whose settings are not its cell's, or whose episodes did not start and end where the cell's TP
        run's did (it is not paired with it).
    """
    results_dir = Path(results_dir)
    meta = read_json(results_dir / MODEL_SWEEP_FILE, keys=("paired", "model", "base_config"))
    paired = SweepResults.load(results_dir / meta["paired"], allow_partial=True)
    model, base = meta["model"], _changed(paired.base, meta.get("changes"))
    runs = {}
    for key in sorted(_stored(results_dir, model) & set(paired.comparisons)):
        folder = results_dir / "cells" / _cell_name(*key)
        result = ExperimentResult.load(folder / model)
        if result.config != cell_config(base, *key).replace(model=model):
            raise StoredResultError(f"{folder / model} ran other settings than its cell's")
        check_paired(paired.comparisons[key].tp, result, folder, names=("TP", model))
        runs[key] = result
    return paired, runs


def check_model_cell(results_dir, cell: str):
    """Recompute one stored run of a model sweep with this code on this machine and compare its records.

    As :func:`~sarsp_edu.experiments.sweep.check.check_cell` does for a paired cell: every column must be equal
    but the prediction diagnostics, whose last digits come from the processor's BLAS kernels.

    Parameters
    ----------
    results_dir : path-like
        A model sweep's folder (:func:`run_model_sweep`'s).
    cell : str
        A cell folder's name, such as ``"m40_p0.2_nss2_seed0"``.

    Returns
    -------
    SideCheck
        The columns that differ (none where the run is what this machine computes) and the largest relative
        difference of each prediction diagnostic.
    """
    from ..experiment import run_experiment
    from .check import _side

    results_dir = Path(results_dir)
    key = _name_key(str(cell))
    if key is None:
        raise ValueError(f"cell={cell!r} is not a cell's name; expected one like 'm40_p0.2_nss2_seed1'")
    meta = read_json(results_dir / MODEL_SWEEP_FILE, keys=("paired", "model", "base_config"))
    stored = ExperimentResult.load(results_dir / "cells" / str(cell) / meta["model"])
    base = _changed(stored_sweep(results_dir / meta["paired"])[0], meta.get("changes"))
    again = run_experiment(cell_config(base, *key).replace(model=meta["model"]))
    return _side(stored.records, again.records)
