"""A stored sweep read back: every file checked, the cells' records as one table."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from ..._internal.io import StoredResultError, read_json
from ...config import DEFINITION_4_A, ExperimentConfig
from ..metrics import SUMMARY_METRICS
from ..provenance import code_versions
from ..results import Comparison, ExperimentResult, check_paired
from .cells import _KEY, _as_key, _name_key, _shared_fields, _stored_base, _stored_key, cell_config, describe_cells


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
        """How many runs each version of the code computed: ``{code_label: runs}`` (see
        :mod:`sarsp_edu.experiments.provenance`).

        More than one entry means the cells come from different code, whose numbers may differ.
        """
        return code_versions(result for comparison in self.comparisons.values()
                             for result in (comparison.tp, comparison.gp))

    def frame(self) -> pd.DataFrame:
        """One row per cell and model: m, p, nss, seed, model and the six summary metrics."""
        rows = []
        for (m, p, nss, seed), comparison in sorted(self.comparisons.items()):
            for model, result in (("TP", comparison.tp), ("GP", comparison.gp)):
                rows.append({"m": m, "p": p, "nss": nss, "seed": seed, "model": model, **result.summary})
        columns = _KEY + ["model", *SUMMARY_METRICS]
        return pd.DataFrame(rows, columns=columns)

    def curves(self, metric: str, model: str, m: float, p: float, seed: int | None = None,
               over_seeds: str = "mean") -> pd.DataFrame:
        """Per-episode values of ``metric`` for one (m, p), one column per nss (Figures 2-7).

        With several seeds, the mean over seeds (or one seed if given);
        ``over_seeds="min"`` or ``"max"`` gives the lowest or highest seed's
        value at each episode instead: the band over seeds.

        Parameters
        ----------
        metric : str
            A records column, such as one of ``SUMMARY_METRICS``.
        model : str
            ``"TP"`` or ``"GP"`` (either case).
        m, p : float
            The outlier magnitude and proportion of the cells (compared with ``math.isclose``).
        seed : int, optional
            Only this sweep seed's cells; None: every seed's.
        over_seeds : {"mean", "min", "max"}, default "mean"
            How the seeds' values at each episode are combined.

        Returns
        -------
        pandas.DataFrame
            Indexed by episode, one column per nss.
        """
        if metric not in self._record_columns():
            raise ValueError(f"metric must be a records column such as {SUMMARY_METRICS}, got metric={metric!r}")
        if over_seeds not in ("mean", "min", "max"):
            raise ValueError(f"over_seeds must be 'mean', 'min' or 'max', got over_seeds={over_seeds!r}")
        model = model.lower()
        columns = {}
        for (cm, cp, nss, cs), comparison in sorted(self.comparisons.items()):
            if not (math.isclose(cm, m) and math.isclose(cp, p)) or (seed is not None and cs != seed):
                continue
            records = getattr(comparison, model).records
            columns.setdefault(nss, []).append(records.set_index("episode")[metric])
        if not columns:
            raise ValueError(f"the sweep holds no cell with m={m}, p={p}")
        return pd.DataFrame({nss: getattr(pd.concat(series, axis=1), over_seeds)(axis=1)
                             for nss, series in columns.items()})

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
            complete = sorted({key[3] for key in expected} - {key[3] for key in results.missing})
            whole = (f", read only its complete seed{'s' if len(complete) > 1 else ''} "
                     f"(seeds={complete}, or --seeds {' '.join(map(str, complete))})" if complete else "")
            raise ValueError(
                f"{results_dir} holds a partial sweep: {len(results.missing)} of {len(expected)} cells are "
                f"missing (the first: {first}); rerun its sweep command to finish it{whole}, or allow a partial "
                "sweep (allow_partial=True, or --allow-partial)"
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
    version = tuple(int(part) for part in str(payload.get("sarsp_edu_version", "0")).split(".")[:3]
                    if part.isdigit())
    if "requested" not in payload and version >= (0, 2, 1):  # written by every version since: cut or edited
        raise StoredResultError(f"{meta} lacks 'requested' (the cells the sweep was asked for), which sarsp_edu "
                                f"{payload['sarsp_edu_version']} always writes: it was edited; restore it")
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
        try:  # read as loading reads it: an older format's settings in today's terms
            ran = _shared_fields(ExperimentConfig.from_dict(config))
        except (TypeError, ValueError):
            continue  # a damaged cell is named when it is loaded
        n += 1
        for name, value in ours.items():
            if ran.get(name, value) != value:
                seen.setdefault(name, set()).add(repr(ran.get(name)))
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

    Parameters
    ----------
    base : ExperimentConfig
        The sweep's shared settings, from which the cell's are derived (:func:`cell_config`).
    cell : pathlib.Path
        The cell's folder, holding ``cell.json``, ``tp/`` and ``gp/``.
    key : tuple
        The cell's ``(m, p, nss, seed)``.
    a : float, default ``DEFINITION_4_A``
        Definition 4's TSR threshold (%).

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
    sides = {model: ExperimentResult.load(cell / model) for model in ("tp", "gp")}
    expected = cell_config(base, *key)
    for model in ("tp", "gp"):
        ran = sides[model].config.to_dict()
        wanted = expected.replace(model=model).to_dict()
        differing = sorted(name for name in wanted if ran[name] != wanted[name])
        if differing:
            details = ", ".join(f"{name}={ran[name]!r} where the sweep gives {wanted[name]!r}" for name in differing)
            raise StoredResultError(f"{cell / model / 'result.json'} is not this sweep's cell "
                                    f"{describe_cells([key])}: it ran {details}")
    check_paired(sides["tp"], sides["gp"], cell)
    return Comparison(sides["tp"], sides["gp"], a)


#: the lock a running sweep holds on its results folder (a hidden file, kept between runs)
