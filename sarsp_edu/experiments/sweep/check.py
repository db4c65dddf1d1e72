"""Recompute a stored cell on this machine and say how its records compare.

What "reproducible" means for the package (REPRODUCTION.md, "Reproducible: what it means
here"): on one machine the same seed gives the same bytes; across machines of one kind the
trajectories are the same and the prediction diagnostics agree to their last digits, which
come from the processor's BLAS kernels.  :func:`check_cell` measures it for any stored cell,
a researcher's own machine included (``sarsp-edu check-cell``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..experiment import compare
from .cells import _name_key, cell_config, describe_cells
from .stored import load_cell, stored_sweep

#: record columns computed from predictions through matrix products (BLAS): their last digits depend on
#: the processor's kernels, so they are compared to a relative tolerance, every other column exactly.
#: The tolerance is relative to the column's largest value over the run, not to each episode's: an episode
#: whose predictions all but hit the costs has an error of 3e-6 made of terms of 1, and holds the rounding of
#: those terms (1e-10), not six more digits of its own.
PREDICTION_DIAGNOSTICS = ("reward_mse", "cost_prediction_error", "safe_action_variance")


@dataclass(frozen=True)
class SideCheck:
    """One model's stored records against the recomputed ones."""

    episodes: int
    #: the exact columns that differ anywhere, and the first episode (0-based) at which any of them does
    differing_columns: tuple = ()
    first_differing_episode: int | None = None
    #: the largest difference of each prediction diagnostic, relative to its largest value over the run
    diagnostics: dict = field(default_factory=dict)


@dataclass(frozen=True)
class CellCheck:
    """A stored cell recomputed: :attr:`same_trajectories` when every exact column is equal."""

    cell: str
    tp: SideCheck
    gp: SideCheck
    same_verdict: bool
    rtol: float

    @property
    def same_trajectories(self) -> bool:
        return not (self.tp.differing_columns or self.gp.differing_columns)

    @property
    def identical(self) -> bool:
        """The same trajectories, the diagnostics within ``rtol`` and the same Definition 4 verdict."""
        within = all(v <= self.rtol for side in (self.tp, self.gp) for v in side.diagnostics.values())
        return self.same_trajectories and within and self.same_verdict

    def __str__(self) -> str:
        lines = [f"{self.cell}: {'identical' if self.identical else 'NOT identical'} "
                 f"(exact columns equal, prediction diagnostics within a relative {self.rtol:g} of their scale)"]
        for name, side in (("TP", self.tp), ("GP", self.gp)):
            if side.differing_columns:
                where = (f"first at episode {side.first_differing_episode + 1} of {side.episodes}: "
                         + ", ".join(side.differing_columns))
            else:
                where = f"all {side.episodes} episodes equal"
            largest = ", ".join(f"{c} {v:.1e}" for c, v in side.diagnostics.items())
            lines.append(f"  {name}: {where}; largest difference relative to scale: {largest}")
        lines.append(f"  Definition 4's verdict: {'the same' if self.same_verdict else 'differs'}")
        return "\n".join(lines)


def _side(old, new) -> SideCheck:
    exact = [c for c in old.columns if c not in PREDICTION_DIAGNOSTICS]
    differing, first = [], None
    for column in exact:
        a, b = old[column].reset_index(drop=True), new[column].reset_index(drop=True)
        unequal = ~(a.eq(b) | (a.isna() & b.isna())).to_numpy()
        if unequal.any():
            differing.append(column)
            episode = int(np.argmax(unequal))
            first = episode if first is None else min(first, episode)
    diagnostics = {}
    for column in PREDICTION_DIAGNOSTICS:
        if column in old.columns:
            a, b = old[column].to_numpy(float), new[column].to_numpy(float)
            both = np.isfinite(a) & np.isfinite(b)
            scale = max(float(np.max(np.abs(a[both]), initial=0.0)), np.finfo(float).tiny)
            diagnostics[column] = float(np.max(np.abs(a[both] - b[both]), initial=0.0)) / scale
    return SideCheck(len(old), tuple(differing), first, diagnostics)


def check_cell(results_dir, cell: str, n_jobs: int | None = None, rtol: float = 1e-7) -> CellCheck:
    """Recompute one stored cell of a sweep with this code on this machine and compare its records.

    Parameters
    ----------
    results_dir : path
        A sweep's results folder (``sweep.json`` and ``cells/``).
    cell : str
        A cell folder's name, such as ``"m40_p0.2_nss2_seed1"``.
    n_jobs : {None, 1, 2}
        As for :func:`sarsp_edu.compare` (the records do not depend on it).
    rtol : float, default 1e-7
        The tolerance of the prediction diagnostics, relative to each one's largest value over the run.

    Returns
    -------
    CellCheck
        Printable; ``identical`` says whether the cell is what this machine computes.

    Raises
    ------
    ValueError
        ``cell`` is not a cell's name, or the folder holds no such cell.
    """
    results_dir = Path(results_dir)
    key = _name_key(str(cell))
    if key is None:
        raise ValueError(f"cell={cell!r} is not a cell's name; expected one like 'm40_p0.2_nss2_seed1'")
    base, _ = stored_sweep(results_dir)
    folder = results_dir / "cells" / str(cell)
    if not folder.is_dir():
        held = sorted(p.name for p in (results_dir / "cells").glob("m*_p*_nss*_seed*"))
        raise ValueError(f"cell={cell!r}: {results_dir} holds no such cell ({len(held)} stored"
                         + (f", for example {held[0]!r})" if held else ")"))
    stored = load_cell(base, folder, key)
    again = compare(cell_config(base, *key), n_jobs=n_jobs)
    return CellCheck(describe_cells([key]), _side(stored.tp.records, again.tp.records),
                     _side(stored.gp.records, again.gp.records), stored.verdict == again.verdict, rtol)
