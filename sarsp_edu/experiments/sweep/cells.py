"""The sweep's cells: each (m, p, nss, seed) a paired run of the base config, with its own seed and folder name.

Each cell's seed is derived from the sweep seed and the cell's (m, p, nss),
never from the order in which cells run, so the numbers do not depend on how
many workers ran them.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from ..._internal.io import StoredResultError, read_json
from ..._internal.validation import check_fraction, check_positive
from ...config import ExperimentConfig


class StoredResultWarning(UserWarning):
    """A stored cell could not be used and is computed again."""


#: the fields a sweep sets per cell; the rest of the base config is shared
_SWEPT = ("model", "outlier_magnitude", "outlier_proportion", "n_switch_states", "seed")
_KEY = ["m", "p", "nss", "seed"]


def cell_seed(sweep_seed: int, m: float, p: float, nss: int) -> int:
    """The run seed of one cell: a hash of the sweep seed and the cell, not of the run order.

    Parameters
    ----------
    sweep_seed : int
        The sweep's seed (a cell key's ``seed``).
    m, p, nss : float, float, int
        The cell's outlier magnitude, outlier proportion and number of switch states; ``m`` is
        rounded to 0.001 and ``p`` to 1e-6 first, so float noise does not change the seed.
    """
    entropy = [int(sweep_seed), int(round(float(m) * 1000)), int(round(float(p) * 1_000_000)), int(nss)]
    return int(np.random.SeedSequence(entropy).generate_state(1, dtype=np.uint32)[0])


def cell_config(base: ExperimentConfig, m: float, p: float, nss: int, seed: int) -> ExperimentConfig:
    """The config of the cell (m, p, nss) for sweep seed ``seed``.

    Parameters
    ----------
    base : ExperimentConfig
        The sweep's shared settings; its ``model`` is kept.
    m, p, nss : float, float, int
        The cell's outlier magnitude, outlier proportion and number of switch states.
    seed : int
        The sweep seed; the run's own seed is :func:`cell_seed` of it and the cell.
    """
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


def _as_key(values) -> tuple:
    """A stored cell's (m, p, nss, seed); ValueError for anything a sweep never stores (NaN, 2.5 switch states)."""
    m, p, nss, seed = values
    m, p = float(m), float(p)
    if not (math.isfinite(m) and math.isfinite(p)) or any(
            isinstance(v, bool) or float(v) != int(v) for v in (nss, seed)):
        raise ValueError(f"not a cell: {values!r}")
    return m, p, int(nss), int(seed)


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
