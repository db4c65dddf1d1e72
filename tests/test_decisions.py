"""Who took a sweep's decisions (sarsp_edu.experiments.decisions and the tables command's block)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from sarsp_edu.experiments.decisions import backup_levels, backup_shares


def run(rates, steps):
    """A stored run as far as the backup share reads it: each episode's backup rate and steps."""
    return SimpleNamespace(records=pd.DataFrame({"backup_rate": rates, "episode_steps": steps}))


def test_a_runs_share_weights_each_episodes_rate_by_its_steps():
    shares = backup_shares([((40, 0.2, 2, 0), "TP", run([1.0, 0.0], [30, 10]))])
    assert shares["backup_share"].tolist() == [75.0]  # 30 of 40 decisions
    assert shares.columns.tolist() == ["m", "p", "nss", "seed", "model", "backup_share"]


def test_levels_average_seeds_within_a_configuration_then_count_configurations():
    runs = []
    for config, gp_rates in (((40, 0.2, 2), (1.0, 1.0)), ((60, 0.3, 6), (1.0, 0.0)), ((80, 0.4, 10), (0.2, 0.2))):
        for seed, rate in enumerate(gp_rates):
            runs.append(((*config, seed), "TP", run([0.1], [50])))
            runs.append(((*config, seed), "GP", run([rate], [50])))
    levels = backup_levels(backup_shares(runs), n_boot=200, rng=1)
    assert levels.index.tolist() == ["TP", "GP"]
    gp = levels.loc["GP"]
    assert gp["backup share %"] == pytest.approx((100 + 50 + 20) / 3)
    assert gp["configurations"] == 3 and gp["every decision the backup's"] == 1 and gp["under half"] == 1
    assert gp["95% CI low"] <= gp["backup share %"] <= gp["95% CI high"]
    tp = levels.loc["TP"]
    assert tp["backup share %"] == pytest.approx(10.0) and tp["95% CI low"] == pytest.approx(10.0)
    assert tp["every decision the backup's"] == 0 and tp["under half"] == 3
    again = backup_levels(backup_shares(runs), n_boot=200, rng=1)
    assert np.array_equal(again.to_numpy(), levels.to_numpy())  # the same seed, the same interval


def test_the_tables_command_says_who_took_the_decisions(capsys):
    from pathlib import Path

    from sarsp_edu.cli import main

    folder = Path(__file__).resolve().parents[1] / "results" / "sweep-reduced"
    assert main(["tables", str(folder)]) == 0
    out = capsys.readouterr().out
    block = out[out.index("Decisions left to the backup rule"):]
    assert "TP" in block and "GP" in block and "every decision the backup's" in block
