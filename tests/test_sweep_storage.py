"""A sweep's stored cells damaged, cut short or partial: named where they are read, and computed again by
the sweep."""

from __future__ import annotations

import pandas as pd
import pytest

from sarsp_edu import run_sweep
from sarsp_edu.experiments.sweep import SweepResults

from .test_sweep import TINY, summaries

ONE = dict(magnitudes=(40,), proportions=(0.2,), n_switch_states=(1, 2))


def _truncate(path, keep):
    text = path.read_text()
    path.write_text(text[: int(len(text) * keep)])


def _header_only(path):
    path.write_text(path.read_text().splitlines()[0] + "\n")


def _bad_cell(path):
    path.write_text("not a number,x\n")


@pytest.mark.parametrize(
    "damage, file, message",
    [
        (lambda p: _truncate(p, 0.8), "tp/records.csv", r"(has no number in column|holds \d+ episodes where)"),
        (_header_only, "gp/records.csv", r"holds 0 episodes where its config ran 3"),
        (lambda p: _truncate(p, 0.5), "tp/result.json", r"cannot be read .*cut short"),
        (lambda p: p.write_text(p.read_text().replace(",start,", ",begin,", 1)), "gp/records.csv",
         r"lacks the columns \['start'\]"),
        (lambda p: p.write_text(p.read_text().replace("False", "maybe", 1).replace("True", "maybe", 1)),
         "tp/records.csv", "task_completed value other than True or False"),
    ],
)
def test_a_damaged_cell_is_named_by_load_and_recomputed_by_the_sweep(tmp_path, damage, file, message):
    from sarsp_edu import StoredResultError
    from sarsp_edu.experiments.sweep import StoredResultWarning

    first = run_sweep(TINY, **ONE, results_dir=tmp_path)
    cell = tmp_path / "cells" / "m40_p0.2_nss1_seed0"
    damage(cell / file)
    with pytest.raises(StoredResultError, match=message) as info:
        SweepResults.load(tmp_path)
    assert str(cell / file) in str(info.value)
    with pytest.warns(StoredResultWarning, match=rf"{file}.*computing the cell again"):
        again = run_sweep(TINY, **ONE, results_dir=tmp_path)
    pd.testing.assert_frame_equal(summaries(again), summaries(first), check_dtype=False)
    pd.testing.assert_frame_equal(summaries(SweepResults.load(tmp_path)), summaries(first), check_dtype=False)


def test_damaged_sweep_and_cell_json_are_named(tmp_path):
    from sarsp_edu import StoredResultError

    run_sweep(TINY, **ONE, results_dir=tmp_path)
    cell_json = tmp_path / "cells" / "m40_p0.2_nss2_seed0" / "cell.json"
    _truncate(cell_json, 0.5)
    with pytest.raises(StoredResultError, match="cell.json is missing or cannot be read"):
        SweepResults.load(tmp_path)
    _truncate(tmp_path / "sweep.json", 0.3)
    for call in (lambda: SweepResults.load(tmp_path), lambda: run_sweep(TINY, **ONE, results_dir=tmp_path)):
        with pytest.raises(StoredResultError, match=r"sweep.json cannot be read"):
            call()


def test_a_partial_sweep_is_refused_unless_allowed(tmp_path):
    run_sweep(TINY, **ONE, results_dir=tmp_path)
    run_sweep(TINY, **ONE, seeds=(1,), results_dir=tmp_path)  # a later call asks for more
    import shutil

    shutil.rmtree(tmp_path / "cells" / "m40_p0.2_nss2_seed1")
    with pytest.raises(ValueError, match=r"partial sweep: 1 of 4 cells are missing \(the first: m=40, p=0.2, "
                                         r"nss=2, seed=1\)"):
        SweepResults.load(tmp_path)
    partial = SweepResults.load(tmp_path, allow_partial=True)
    assert len(partial) == 3 and partial.missing == [(40.0, 0.2, 2, 1)]
