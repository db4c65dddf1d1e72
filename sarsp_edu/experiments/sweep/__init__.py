"""The paper's experiment grid: m x p x nss (x seeds), each cell a paired TP-vs-GP run.

``run_sweep`` runs the cells locally (joblib processes) or on a Dask cluster,
storing each finished cell in a results folder as soon as it finishes, and
``SweepResults`` reads a folder back, checking every file.  The tables
built from it (:func:`sarsp_edu.experiments.tables.summary_tables`) are in
:mod:`sarsp_edu.experiments.tables`, which imports nothing from here.

Each cell's seed is derived from the sweep seed and the cell's (m, p, nss),
never from the order in which cells run, so the numbers do not depend on how
many workers ran them.

The cells are in :mod:`~sarsp_edu.experiments.sweep.cells`, reading a stored sweep back
in :mod:`~sarsp_edu.experiments.sweep.stored`, running one in :mod:`~sarsp_edu.experiments.sweep.run`.
"""

from .cells import StoredResultWarning, cell_config, cell_seed, describe_cells, finished_cells
from .check import CellCheck, check_cell
from .failures import CellsFailed
from .run import LOCK_NAME, run_sweep
from .stored import SweepResults, load_cell, stored_sweep

__all__ = [
    "LOCK_NAME", "CellCheck", "CellsFailed", "StoredResultWarning", "SweepResults", "cell_config", "cell_seed",
    "check_cell", "describe_cells", "finished_cells", "load_cell", "run_sweep", "stored_sweep",
]
