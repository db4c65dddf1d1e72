"""Who took a sweep's decisions: each model's share of decisions left to the backup rule.

A model whose safe set is empty at a decision hands it to the backup rule
(Algorithm 1's corrective fallback).  Where that is every decision, the
model's own judgement of moves never acts, and a comparison of two models is
a comparison of their backups: Table 2 alone cannot tell the two apart.
This table says which it is, over the configurations of a sweep.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .metrics import backup_share
from .tables import bootstrap_ci

__all__ = ["ALL_BACKUP", "backup_levels", "backup_shares"]

#: a configuration whose backup share (%) is at least this is "every decision the backup's"
ALL_BACKUP = 99.95


def backup_shares(runs) -> pd.DataFrame:
    """One row per run: m, p, nss, seed, model and ``backup_share`` (% of its decisions).

    Parameters
    ----------
    runs : iterable of (tuple, str, ExperimentResult)
        ``((m, p, nss, seed), model name, result)`` for each stored run.
    """
    rows = [{"m": m, "p": p, "nss": nss, "seed": seed, "model": model,
             "backup_share": 100.0 * backup_share(result.records)} for (m, p, nss, seed), model, result in runs]
    return pd.DataFrame(rows, columns=["m", "p", "nss", "seed", "model", "backup_share"])


def backup_levels(shares: pd.DataFrame, n_boot: int = 2000, rng=0) -> pd.DataFrame:
    """Each model's backup share over configurations (each the mean over its seeds), with a 95% bootstrap
    interval (configurations resampled, as Table 2's levels), and how many configurations left every decision,
    or fewer than half, to the backup.

    Parameters
    ----------
    shares : DataFrame
        :func:`backup_shares`'s rows.
    n_boot : int, default 2000
    rng : None, int or numpy.random.Generator
        For the bootstrap.
    """
    boot_rng = np.random.default_rng(rng)
    per_config = shares.groupby(["model", "m", "p", "nss"], sort=False)["backup_share"].mean()
    rows = []
    for model in dict.fromkeys(shares["model"]):
        values = per_config.xs(model, level="model").to_numpy()
        low, high = bootstrap_ci(values, values, lambda t, g: np.mean(t), n_boot, boot_rng)
        rows.append({"model": model, "backup share %": float(np.mean(values)), "95% CI low": low,
                     "95% CI high": high, "configurations": len(values),
                     "every decision the backup's": int(np.sum(values >= ALL_BACKUP)),
                     "under half": int(np.sum(values < 50))})
    return pd.DataFrame(rows).set_index("model")
