"""The paper's experiment grid: m x p x nss (x seeds), each cell a paired TP-vs-GP run.

``run_sweep`` runs the cells locally (joblib processes) or on a Dask cluster,
storing each finished cell in a results folder as soon as it finishes, and
``SweepResults`` reads a folder back, checking every file.  The tables
built from it (:func:`sarsp_edu.tables.summary_tables`) are in
:mod:`sarsp_edu.tables`, which imports nothing from here.

Each cell's seed is derived from the sweep seed and the cell's (m, p, nss),
never from the order in which cells run, so the numbers do not depend on how
many workers ran them.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import signal
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ._io import StoredResultError, atomic_write_text, one_line_warning, read_json, staging_directory
from ._validation import check_fraction, check_int, check_positive
from ._version import __version__
from .provenance import code_label
from .config import DEFINITION_4_A, PAPER_MAGNITUDES, PAPER_PROPORTIONS, PAPER_SWITCH_STATES
from .config import ExperimentConfig
from .experiment import compare
from .metrics import SUMMARY_METRICS, check_a
from .results import Comparison

__all__ = [
    "StoredResultWarning",
    "run_sweep",
    "SweepResults",
    "cell_config",
    "describe_cells",
    "load_cell",
    "stored_sweep",
]


class StoredResultWarning(UserWarning):
    """A stored cell could not be used and is computed again."""


#: the fields a sweep sets per cell; the rest of the base config is shared
_SWEPT = ("model", "outlier_magnitude", "outlier_proportion", "n_switch_states", "seed")
_KEY = ["m", "p", "nss", "seed"]


def cell_seed(sweep_seed: int, m: float, p: float, nss: int) -> int:
    """The run seed of one cell: a hash of the sweep seed and the cell, not of the run order."""
    entropy = [int(sweep_seed), int(round(float(m) * 1000)), int(round(float(p) * 1_000_000)), int(nss)]
    return int(np.random.SeedSequence(entropy).generate_state(1, dtype=np.uint32)[0])


def cell_config(base: ExperimentConfig, m: float, p: float, nss: int, seed: int) -> ExperimentConfig:
    """The config of the cell (m, p, nss) for sweep seed ``seed``."""
    return base.replace(
        outlier_magnitude=float(m),
        outlier_proportion=float(p),
        n_switch_states=int(nss),
        seed=cell_seed(seed, m, p, nss),
    )


def describe_cells(keys) -> str:
    """Cell keys ``(m, p, nss, seed)`` in a line: those of one (m, p, seed) together.

    >>> describe_cells([(40.0, 0.2, 6, 0), (40.0, 0.2, 8, 0), (60.0, 0.3, 2, 1)])
    'm=40 p=0.2 nss=6,8 seed=0; m=60 p=0.3 nss=2 seed=1'
    """
    groups: dict = {}
    for m, p, nss, seed in keys:
        groups.setdefault((float(m), float(p), int(seed)), []).append(int(nss))
    return "; ".join(f"m={m:g} p={p:g} nss={','.join(str(n) for n in nss)} seed={seed}"
                     for (m, p, seed), nss in groups.items())


def _cell_name(m, p, nss, seed) -> str:
    return f"m{float(m):g}_p{float(p):g}_nss{int(nss)}_seed{int(seed)}"


def _name_key(name: str):
    """The key ``(m, p, nss, seed)`` that a cell folder's name gives, or None (the inverse of ``_cell_name``)."""
    match = re.fullmatch(r"m([^_]+)_p([^_]+)_nss(\d+)_seed(\d+)", name)
    try:
        return _as_key(match.groups()) if match else None
    except ValueError:
        return None


def _shared_fields(config: ExperimentConfig) -> dict:
    values = config.to_dict()
    return {k: v for k, v in values.items() if k not in _SWEPT}


@dataclass
class SweepResults:
    """The paired comparisons of a sweep, keyed by ``(m, p, nss, seed)``.

    Attributes
    ----------
    base : ExperimentConfig
        The shared settings (the swept fields of it are ignored).
    comparisons : dict
        ``(m, p, nss, seed) -> Comparison``.
    a : float
        The TSR threshold of Definition 4.
    missing : list
        Keys of the cells a partial sweep still lacks (see :meth:`load`).
    """

    base: ExperimentConfig
    comparisons: dict = field(default_factory=dict)
    a: float = DEFINITION_4_A
    missing: list = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.comparisons)

    def code_versions(self) -> dict:
        """How many runs each version of the code computed: ``{code_label: runs}`` (see ``sarsp_edu.provenance``).

        More than one entry means the cells come from different code, whose numbers may differ.
        """
        counts: dict = {}
        for comparison in self.comparisons.values():
            for result in (comparison.tp, comparison.gp):
                label = code_label(result.code)
                counts[label] = counts.get(label, 0) + 1
        return counts

    def frame(self) -> pd.DataFrame:
        """One row per cell and model: m, p, nss, seed, model and the six summary metrics."""
        rows = []
        for (m, p, nss, seed), comparison in sorted(self.comparisons.items()):
            for model, result in (("TP", comparison.tp), ("GP", comparison.gp)):
                rows.append({"m": m, "p": p, "nss": nss, "seed": seed, "model": model, **result.summary})
        columns = _KEY + ["model", *SUMMARY_METRICS]
        return pd.DataFrame(rows, columns=columns)

    def curves(self, metric: str, model: str, m: float, p: float, seed: int | None = None) -> pd.DataFrame:
        """Per-episode values of ``metric`` for one (m, p), one column per nss (Figures 2-7).

        With several seeds, the mean over seeds (or one seed if given).
        """
        if metric not in self._record_columns():
            raise ValueError(f"metric must be a records column such as {SUMMARY_METRICS}, got metric={metric!r}")
        model = model.lower()
        columns = {}
        for (cm, cp, nss, cs), comparison in sorted(self.comparisons.items()):
            if not (math.isclose(cm, m) and math.isclose(cp, p)) or (seed is not None and cs != seed):
                continue
            records = getattr(comparison, model).records
            columns.setdefault(nss, []).append(records.set_index("episode")[metric])
        if not columns:
            raise ValueError(f"the sweep holds no cell with m={m}, p={p}")
        return pd.DataFrame({nss: pd.concat(series, axis=1).mean(axis=1) for nss, series in columns.items()})

    def macro(self, metric: str) -> pd.DataFrame:
        """``metric`` averaged over every (m, p, seed), against nss: columns TP and GP (Figures 8-9)."""
        if metric not in SUMMARY_METRICS:
            raise ValueError(f"metric must be one of {SUMMARY_METRICS}, got metric={metric!r}")
        table = self.frame().pivot_table(index="nss", columns="model", values=metric, aggfunc="mean")
        return table[["TP", "GP"]]

    def _record_columns(self):
        first = next(iter(self.comparisons.values()))
        return set(first.tp.records.columns)

    @classmethod
    def load(cls, results_dir, a: float = DEFINITION_4_A, allow_partial: bool = False,
             seeds=None) -> "SweepResults":
        """Every cell of a results folder, each checked as it is read.

        Parameters
        ----------
        results_dir : path
        a : float, default 100.0
            Definition 4's TSR threshold.
        allow_partial : bool, default False
            Accept a sweep with cells still to run; ``missing`` lists them.
            ``sweep.json`` records every cell a sweep was asked for, so a
            table never averages over an unnoticed subset.  (Folders written
            before version 0.2.1 hold no such record; their cells are taken
            as the whole sweep.)
        seeds : sequence of int, optional
            Read only the cells of these sweep seeds (a sweep still running
            its later seeds can be read whole for the first).

        Raises
        ------
        StoredResultError
            A file that cannot be read or holds what no run writes (named).
        ValueError
            The sweep is partial and ``allow_partial`` is False.
        """
        results_dir = Path(results_dir)
        base, requested = stored_sweep(results_dir)
        results = cls(base, a=a)
        wanted = None if seeds is None else {int(s) for s in seeds}
        cells = sorted((results_dir / "cells").glob("m*_p*_nss*_seed*"))
        if wanted is not None:
            present = sorted({key[3] for key in map(_stored_key, cells) if key is not None} | {k[3] for k in requested})
            absent = sorted(wanted - set(present))
            if absent:
                raise ValueError(f"{results_dir} holds no cell of seed{'s' if len(absent) > 1 else ''} "
                                 f"{', '.join(map(str, absent))}; its seeds are {', '.join(map(str, present))}")
        for cell in cells:
            key = _name_key(cell.name)
            if key is None:
                raise StoredResultError(f"{cell} is not named as a cell (m40_p0.2_nss2_seed0, say)")
            if wanted is None or key[3] in wanted:
                results.comparisons[key] = load_cell(base, cell, key, a=a)
        expected = set(requested)
        if wanted is not None:
            expected = {key for key in expected if key[3] in wanted}
        results.missing = sorted(expected - set(results.comparisons))
        if results.missing and not allow_partial:
            first = ", ".join(f"{n}={v:g}" for n, v in zip(_KEY, results.missing[0]))
            raise ValueError(
                f"{results_dir} holds a partial sweep: {len(results.missing)} of {len(expected)} cells are "
                f"missing (the first: {first}); rerun its sweep command to finish it, or allow a partial sweep "
                "(allow_partial=True, or --allow-partial)"
            )
        return results


def stored_sweep(results_dir) -> tuple:
    """The shared settings and the requested cells of a sweep's results folder, checked against its cells.

    Returns
    -------
    (ExperimentConfig, set of (m, p, nss, seed))

    Raises
    ------
    FileNotFoundError
        No ``sweep.json``.
    StoredResultError
        ``sweep.json`` cannot be read, lacks settings, or says what none of
        the cells stored beside it ran (it was edited, or belongs to another
        sweep): the message names the setting and both values.
    """
    results_dir = Path(results_dir)
    meta = results_dir / "sweep.json"
    if not meta.exists():
        raise FileNotFoundError(f"{results_dir} is not a sweep results folder (no sweep.json)")
    payload = read_json(meta, keys=("base_config",))
    base = _stored_base(meta, payload)
    try:
        requested = {_as_key(key) for key in payload.get("requested", [])}
    except (TypeError, ValueError):
        raise StoredResultError(f"{meta} holds an invalid list of requested cells") from None
    _check_base_against_cells(meta, base)
    return base, requested


def _check_base_against_cells(meta: Path, base: ExperimentConfig) -> None:
    """Refuse a ``sweep.json`` whose shared settings no stored cell ran.

    A setting in which *every* stored cell (two or more) differs from
    ``sweep.json`` is ``sweep.json``'s fault (edited, or copied from another
    sweep); a cell that differs alone is that cell's (see :func:`load_cell`).
    """
    ours = _shared_fields(base)
    seen: dict = {}
    n = 0
    for cell in (meta.parent / "cells").glob("m*_p*_nss*_seed*"):
        try:
            config = read_json(cell / "tp" / "result.json", keys=("config",))["config"]
        except (FileNotFoundError, StoredResultError):
            continue  # a damaged cell is named when it is loaded
        if not isinstance(config, dict):
            continue
        n += 1
        for name, value in ours.items():
            if config.get(name, value) != value:
                seen.setdefault(name, set()).add(repr(config.get(name)))
            else:
                seen.setdefault(name, set()).add(None)
    # with a single cell the two cannot be told apart: load_cell names that cell instead
    wrong = {name: values for name, values in seen.items() if n >= 2 and None not in values}
    if wrong:
        details = "; ".join(f"{name}={ours[name]!r} where they ran {name}={' or '.join(sorted(values))}"
                            for name, values in sorted(wrong.items()))
        raise StoredResultError(
            f"{meta} does not describe the {n} cell{'s' if n > 1 else ''} stored beside it ({details}): it was "
            "edited or belongs to another sweep; restore it, or move the cells to their own folder")


def load_cell(base: ExperimentConfig, cell: Path, key: tuple, a: float = DEFINITION_4_A) -> Comparison:
    """The comparison stored in ``cell``, checked to be the sweep's cell ``key``.

    Raises
    ------
    StoredResultError
        The folder's ``cell.json`` names another cell, or a run's settings
        differ from what the sweep's settings give for this cell (a result
        edited, or left from another run): the message names the cell, the
        setting and both values.
    """
    stored = _stored_key(cell)
    if stored is None:
        raise StoredResultError(f"{cell / 'cell.json'} is missing or cannot be read")
    if stored != tuple(key):
        raise StoredResultError(f"{cell} belongs to another cell: its cell.json says "
                                f"{describe_cells([stored])}, its place {describe_cells([key])}")
    comparison = Comparison.load(cell, a=a)
    expected = cell_config(base, *key)
    for model in ("tp", "gp"):
        ran = getattr(comparison, model).config.to_dict()
        wanted = expected.replace(model=model).to_dict()
        differing = sorted(name for name in wanted if ran[name] != wanted[name])
        if differing:
            details = ", ".join(f"{name}={ran[name]!r} where the sweep gives {wanted[name]!r}" for name in differing)
            raise StoredResultError(f"{cell / model / 'result.json'} is not this sweep's cell "
                                    f"{describe_cells([key])}: it ran {details}")
    return comparison


#: the lock a running sweep holds on its results folder (a hidden file, kept between runs)
LOCK_NAME = ".sweep.lock"


def _lock_folder(results_dir: Path):
    """Hold ``results_dir``'s lock for this process, or say that another sweep holds it.

    Returns the open lock file (closing it releases the lock); None where the
    platform has no ``fcntl`` (Windows), which then runs without one.
    """
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not on Linux or macOS
        return None
    handle = open(results_dir / LOCK_NAME, "a+")
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        handle.seek(0)
        holder = handle.read().strip()
        handle.close()
        raise ValueError(f"another sweep is running in {results_dir}{f' (process {holder})' if holder else ''}; "
                         "wait for it to finish, or use another folder") from None
    handle.seek(0)
    handle.truncate()
    handle.write(f"{os.getpid()}\n")
    handle.flush()
    return handle


# --------------------------------------------------------------------------
# running
# --------------------------------------------------------------------------
def _run_cell(base: ExperimentConfig, key: tuple, results_dir: str | None) -> tuple:
    """Run one paired cell; store it atomically if a folder is given."""
    m, p, nss, seed = key
    comparison = compare(cell_config(base, m, p, nss, seed), n_jobs=1)  # a sweep: one process per cell
    if results_dir is not None:
        _store_cell(Path(results_dir), key, comparison)
    return key, comparison


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
    cells = results_dir / "cells"
    cells.mkdir(parents=True, exist_ok=True)
    final = cells / _cell_name(*key)
    staging = staging_directory(cells, final.name)
    try:
        comparison.save(staging)
        atomic_write_text(staging / "cell.json", json.dumps({"key": list(key)}) + "\n")
        try:
            os.rename(staging, final)
        except OSError:
            if not (final / "cell.json").exists():
                raise
            shutil.rmtree(staging)  # another worker finished the same cell first
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise


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


def _as_key(values) -> tuple:
    m, p, nss, seed = values
    return float(m), float(p), int(nss), int(seed)


def _stored_base(meta: Path, payload: dict) -> ExperimentConfig:
    try:
        return ExperimentConfig.from_dict(payload["base_config"])
    except (TypeError, ValueError) as exc:
        raise StoredResultError(f"{meta} holds an invalid base_config: {exc}") from None


def _stored_key(cell: Path):
    """The key in ``cell/cell.json``, or None when it is missing or unreadable."""
    try:
        return _as_key(read_json(cell / "cell.json", keys=("key",))["key"])
    except (FileNotFoundError, StoredResultError, TypeError, ValueError):
        return None


def _clear_staging(results_dir: Path) -> None:
    """Remove the staging folders of cells whose storing was interrupted."""
    for stale in (results_dir / "cells").glob(".m*"):
        shutil.rmtree(stale, ignore_errors=True)


def finished_cells(results_dir) -> set:
    """Keys ``(m, p, nss, seed)`` of the cells stored in a sweep's results folder (with a readable cell.json)."""
    keys = (_stored_key(cell) for cell in (Path(results_dir) / "cells").glob("m*_p*_nss*_seed*"))
    return {key for key in keys if key is not None}


def _check_cell(base: ExperimentConfig, cell) -> None:
    if len(cell) != 3:
        raise ValueError(f"cells must hold (m, p, nss) triples, got {cell!r}")
    m, p, nss = cell
    check_positive("m", m)
    check_fraction("p", p)
    base.replace(n_switch_states=nss)


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
        with ``results_dir`` the workers must see the same file system.
    progress : bool, default False
        A progress bar over cells.
    a : float, default 100.0
        Definition 4's TSR threshold, for the verdicts.

    Returns
    -------
    SweepResults
        Every cell of the grid: those run now and those found in ``results_dir``.
    """
    base = ExperimentConfig() if config is None else config
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
        check_int("n_jobs", n_jobs, -1)
        if n_jobs == 0:
            raise ValueError("n_jobs must be a positive integer or -1 (one per core), got n_jobs=0")
    check_a(a)
    keys = [(float(m), float(p), int(nss), int(seed)) for seed in seeds for m, p, nss in cells]

    if scheduler is not None:
        _dask()  # before any work: a missing Dask is said at once
    results = SweepResults(base, a=a)
    folder = None if results_dir is None else Path(results_dir)
    lock = None
    try:
        if folder is not None:
            folder.mkdir(parents=True, exist_ok=True)
            lock = _lock_folder(folder)
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
                  disable=not progress) as bar:
            for key, comparison in _execute(base, todo, None if folder is None else str(folder), n_jobs, scheduler):
                comparison.a = a
                results.comparisons[key] = comparison
                bar.update(1)
    finally:
        if lock is not None:
            lock.close()
    return results


def _execute(base, todo, folder, n_jobs, scheduler):
    """Yield (key, Comparison) as cells finish, in any order."""
    if not todo:
        return
    if scheduler is not None:
        yield from _execute_dask(base, todo, folder, scheduler)
    elif n_jobs == 1:
        for key in todo:
            yield _run_cell(base, key, folder)
    else:
        from joblib import Parallel, delayed

        parallel = Parallel(n_jobs=n_jobs, return_as="generator_unordered")
        try:
            yield from parallel(delayed(_run_cell_in_worker)(base, key, folder) for key in todo)
        except KeyboardInterrupt:
            # stop the workers now, so that no process outlives the command or
            # leaves its semaphores behind (the finished cells are stored)
            from joblib.externals.loky import get_reusable_executor

            get_reusable_executor().shutdown(wait=True, kill_workers=True)
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
    try:
        futures = [client.submit(_run_cell, base, key, folder, pure=False) for key in todo]
        for future in as_completed(futures):
            yield future.result()
    finally:
        if client is not scheduler:
            client.close()
