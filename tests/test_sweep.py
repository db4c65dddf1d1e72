from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from sarsp_edu import ExperimentConfig, compare, run_sweep, summary_tables
from sarsp_edu.experiments.metrics import SUMMARY_METRICS, cost_rate_undefined
from sarsp_edu.experiments.sweep import SweepResults, cell_config, cell_seed
from sarsp_edu.experiments.tables import frame_to_markdown, tables_markdown

from .worlds import FIVE_BY_FIVE

TINY = ExperimentConfig(**FIVE_BY_FIVE, episodes=3)
GRID = dict(magnitudes=(40, 80), proportions=(0.2,), n_switch_states=(1, 2))


@pytest.fixture(scope="module")
def sweep_dir(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweep")
    results = run_sweep(TINY, **GRID, seeds=(0, 1), results_dir=folder)
    return folder, results


def summaries(results):
    return results.frame().sort_values(["m", "p", "nss", "seed", "model"]).reset_index(drop=True)


def test_grid_and_pairing(sweep_dir):
    _, results = sweep_dir
    assert len(results) == 2 * 2 * 2
    assert sorted(results.comparisons) == sorted(
        (float(m), 0.2, nss, seed) for m in (40, 80) for nss in (1, 2) for seed in (0, 1)
    )
    for (m, p, nss, seed), comparison in results.comparisons.items():
        assert comparison.tp.config.outlier_magnitude == m and comparison.gp.config.n_switch_states == nss
        assert comparison.tp.config.seed == comparison.gp.config.seed == cell_seed(seed, m, p, nss)
        assert comparison.tp.records["start"].tolist() == comparison.gp.records["start"].tolist()


def test_a_cell_is_a_paired_compare(sweep_dir):
    _, results = sweep_dir
    alone = compare(cell_config(TINY, 80, 0.2, 2, 1))
    cell = results.comparisons[(80.0, 0.2, 2, 1)]
    pd.testing.assert_frame_equal(alone.tp.records, cell.tp.records, check_dtype=False)
    pd.testing.assert_frame_equal(alone.gp.records, cell.gp.records, check_dtype=False)


def test_results_do_not_depend_on_the_number_of_workers(sweep_dir):
    _, serial = sweep_dir
    parallel = run_sweep(TINY, **GRID, seeds=(0, 1), n_jobs=2)
    pd.testing.assert_frame_equal(summaries(serial), summaries(parallel))


def test_cell_seeds_depend_on_the_cell_not_the_order():
    assert cell_seed(0, 40, 0.2, 2) == cell_seed(0, 40.0, 0.2, 2)
    seeds = {cell_seed(s, m, p, n) for s in (0, 1) for m in (40, 60) for p in (0.2, 0.3) for n in (2, 4)}
    assert len(seeds) == 16


def test_rerun_skips_finished_cells(sweep_dir, monkeypatch):
    folder, results = sweep_dir
    from sarsp_edu.experiments.sweep import run as sweep_module  # where the cells are run

    def must_not_run(*args, **kwargs):
        raise AssertionError("a finished cell was run again")

    monkeypatch.setattr(sweep_module, "_run_cell", must_not_run)
    again = run_sweep(TINY, **GRID, seeds=(0, 1), results_dir=folder)
    pd.testing.assert_frame_equal(summaries(again), summaries(results), check_dtype=False)


def test_an_interrupted_sweep_resumes(tmp_path, monkeypatch):
    from sarsp_edu.experiments.sweep import run as sweep_module  # where the cells are run

    real = sweep_module._run_cell
    calls = []

    def flaky(base, key, folder):
        calls.append(key)
        if len(calls) == 3:
            raise KeyboardInterrupt  # Ctrl-C while the third cell runs
        return real(base, key, folder)

    monkeypatch.setattr(sweep_module, "_run_cell", flaky)
    with pytest.raises(KeyboardInterrupt):
        run_sweep(TINY, **GRID, results_dir=tmp_path)
    finished = sorted(p.name for p in (tmp_path / "cells").iterdir())
    assert len(finished) == 2 and not any(name.startswith(".") for name in finished)
    monkeypatch.setattr(sweep_module, "_run_cell", real)
    resumed = run_sweep(TINY, **GRID, results_dir=tmp_path)
    assert len(resumed) == 4
    fresh = run_sweep(TINY, **GRID)
    pd.testing.assert_frame_equal(summaries(resumed), summaries(fresh), check_dtype=False)


def test_stale_staging_folders_are_cleared(tmp_path):
    run_sweep(TINY, magnitudes=(40,), proportions=(0.2,), n_switch_states=(1,), results_dir=tmp_path)
    stale = tmp_path / "cells" / ".m40_p0.2_nss2_seed0.abc"
    stale.mkdir()
    (stale / "records.csv").write_text("half written")
    run_sweep(TINY, magnitudes=(40,), proportions=(0.2,), n_switch_states=(1,), results_dir=tmp_path)
    assert not stale.exists()


def test_a_folder_with_other_settings_is_refused(sweep_dir):
    folder, _ = sweep_dir
    with pytest.raises(ValueError, match=r"other settings \(episodes: folder 3, now 4\)"):
        run_sweep(TINY.replace(episodes=4), **GRID, results_dir=folder)


def test_load(sweep_dir):
    folder, results = sweep_dir
    loaded = SweepResults.load(folder)
    assert loaded.base == TINY
    pd.testing.assert_frame_equal(summaries(loaded), summaries(results), check_dtype=False)
    meta = json.loads((folder / "sweep.json").read_text())
    assert meta["base_config"]["episodes"] == 3


def test_load_of_a_non_sweep_folder(tmp_path):
    with pytest.raises(FileNotFoundError, match="not a sweep results folder"):
        SweepResults.load(tmp_path)


def test_dask_scheduler_gives_the_same_numbers(sweep_dir):
    pytest.importorskip("dask.distributed")
    from dask.distributed import Client, LocalCluster

    _, serial = sweep_dir
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            on_dask = run_sweep(TINY, **GRID, seeds=(0, 1), scheduler=client)
    pd.testing.assert_frame_equal(summaries(serial), summaries(on_dask))


def test_a_dask_sweep_stopped_leaves_nothing_running_on_the_users_cluster(monkeypatch):
    """Ctrl-C after the first cell: the cells still queued or running on a client the user gave are cancelled
    as the sweep stops, not left until their futures happen to be collected."""
    pytest.importorskip("dask.distributed")
    import time

    import tqdm.auto
    from dask.distributed import Client, LocalCluster

    class StoppedAtTheFirstCell(tqdm.auto.tqdm):
        def update(self, n=1):
            raise KeyboardInterrupt

    monkeypatch.setattr(tqdm.auto, "tqdm", StoppedAtTheFirstCell)
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            cancelled = []
            monkeypatch.setattr(client, "cancel", lambda futures, _cancel=client.cancel, **kwargs: (
                cancelled.extend(futures), _cancel(futures, **kwargs))[1])
            with pytest.raises(KeyboardInterrupt):
                run_sweep(TINY, magnitudes=(40, 60, 80), proportions=(0.2,), n_switch_states=(1, 2), seeds=(0,),
                          scheduler=client)
            assert 4 <= len(cancelled) <= 5  # the cells after the first (one may have finished meanwhile)
            stopped = time.monotonic()  # the cancel travels on the client's batched stream: let it arrive
            while True:
                states = client.run_on_scheduler(lambda dask_scheduler: [t.state for t in
                                                                         dask_scheduler.tasks.values()])
                if set(states) <= {"memory", "released", "forgotten"} or time.monotonic() - stopped > 5.0:
                    break
                time.sleep(0.02)
    assert set(states) <= {"memory", "released", "forgotten"}, states  # the first cell's result, at most
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        with Client(cluster) as client:  # a client lost as the sweep stops: its error is not the one raised

            def lost(futures, **kwargs):
                raise RuntimeError("client lost")

            monkeypatch.setattr(client, "cancel", lost)
            with pytest.raises(KeyboardInterrupt), pytest.warns(UserWarning, match=r"could not be cancelled "
                                                                                     r"\(client lost\)"):
                run_sweep(TINY, magnitudes=(40, 60), proportions=(0.2,), n_switch_states=(1,), seeds=(0,),
                          scheduler=client)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(magnitudes=()), "magnitudes must hold at least one value"),
        (dict(magnitudes=(40, -1)), "magnitudes must be a positive finite number"),
        (dict(proportions=(1.2,)), r"proportions must lie in \[0, 1\]"),
        (dict(n_switch_states=(4,)), "n_switch_states must be an integer from 0 to n_unsafe=3"),
        (dict(seeds=(0, 0)), "seeds must not repeat"),
        (dict(n_jobs=0), "n_jobs"),
        (dict(a=0), r"a must lie in \[1, 100\] \(a task success rate in %\)"),
    ],
)
def test_bad_sweep_arguments(kwargs, match):
    params = dict(GRID)
    params.update(kwargs)
    with pytest.raises(ValueError, match=match):
        run_sweep(TINY, **params)


# --------------------------------------------------------------------------
# the tables
# --------------------------------------------------------------------------
def test_tables_by_hand(sweep_dir):
    _, results = sweep_dir
    tables = summary_tables(results, n_boot=200)
    assert list(tables) == ["table1", "mean", "levels", "median", "mode", "wilcoxon", "seeds"]
    per_config = results.frame().groupby(["m", "p", "nss", "model"])[list(SUMMARY_METRICS)].mean()
    defined = {label: ~per_config.xs(label, level="model").apply(cost_rate_undefined, axis=1).to_numpy()
               for label in ("TP", "GP")}
    for metric in SUMMARY_METRICS:
        tp = per_config.xs("TP", level="model")[metric].to_numpy()
        gp = per_config.xs("GP", level="model")[metric].to_numpy()
        assert tables["mean"].loc[metric, "TP"] == pytest.approx(tp.mean())
        assert tables["median"].loc[metric, "GP"] == pytest.approx(np.median(gp))
        for label, values in (("TP", tp), ("GP", gp)):
            if metric == "cost_rate":  # eq. 12's undefined rates are left out of the levels
                values = values[defined[label]]
            level = tables["levels"].loc[metric]
            assert level[f"{label} n"] == len(values)
            assert level[label] == pytest.approx(values.mean())
            # a bootstrap mean of resampled configurations lies between their extremes
            assert values.min() - 1e-12 <= level[f"{label} 95% CI low"] <= level[f"{label} 95% CI high"]
            assert level[f"{label} 95% CI high"] <= values.max() + 1e-12
        if tp.mean() != 0 and len(tp) > 1:
            assert tables["mean"].loc[metric, "CV TP (%)"] == pytest.approx(tp.std(ddof=1) / abs(tp.mean()) * 100)
        expected = (tp.mean() - gp.mean()) / abs(gp.mean()) * 100 if gp.mean() else None
        if expected is not None:
            assert tables["mean"].loc[metric, "% change"] == pytest.approx(expected)
    assert len(tables["table1"]) == 2 * 4
    both = int(np.sum(defined["TP"] & defined["GP"]))
    assert tables["wilcoxon"]["n"].tolist() == [4] * 5 + [both]
    assert tables["wilcoxon"]["left out (p_c undefined)"].tolist() == [0] * 5 + [4 - both]


def test_level_intervals_leave_the_change_intervals_as_they_were(sweep_dir):
    # the levels' resamples are drawn after every other interval, so adding
    # them changed no interval that stored results and docs quote
    from sarsp_edu.experiments.metrics import percent_difference
    from sarsp_edu.experiments.tables import bootstrap_ci, paired, per_configuration

    _, results = sweep_dir
    tables = summary_tables(results, n_boot=100, rng=3)
    per_config = per_configuration(results.frame())
    rng = np.random.default_rng(3)
    for metric in SUMMARY_METRICS:
        tp, gp = paired(per_config, metric)
        low, high = bootstrap_ci(tp, gp, lambda t, g: percent_difference(t.mean(), g.mean()), 100, rng)
        np.testing.assert_equal([tables["mean"].loc[metric, "95% CI low"], tables["mean"].loc[metric, "95% CI high"]],
                                [low, high])


def test_table1_uses_definition_4_and_the_symmetric_difference():
    from sarsp_edu.experiments.metrics import symmetric_percent_difference

    assert symmetric_percent_difference(28, 58) == pytest.approx(69.77, abs=0.01)  # the paper's 69.8%
    assert symmetric_percent_difference(31, 58) == pytest.approx(60.67, abs=0.01)  # and 60.7%
    assert symmetric_percent_difference(5, 5) == 0.0


def test_mode_is_scipys_rule():
    from sarsp_edu.experiments.tables import paper_mode

    assert paper_mode(np.array([3.0, 1.0, 3.0, 2.0])) == 3.0  # the most frequent
    assert paper_mode(np.array([-145.3, -60.2, -88.8])) == -145.3  # all unique: the smallest


def test_markdown_export(sweep_dir):
    _, results = sweep_dir
    tables = summary_tables(results, n_boot=50)
    text = frame_to_markdown(tables["mean"])
    lines = text.splitlines()
    assert lines[0].startswith("| metric | TP | GP |") and lines[1].startswith("|---|")
    assert len(lines) == 2 + 6
    doc = tables_markdown(tables)
    assert doc.count("## ") == len(tables)


def test_table1_beside_the_paper_holds_only_the_configurations_both_have():
    from sarsp_edu.experiments.tables import table1_beside_paper
    from sarsp_edu.paper import TABLE1

    ours = pd.DataFrame([
        {"m": 40.0, "p": 0.2, "nss": 2, "model": "TP", **{k: 1.0 for k in SUMMARY_METRICS}},
        {"m": 40.0, "p": 0.2, "nss": 2, "model": "GP", **{k: 2.0 for k in SUMMARY_METRICS}},
        {"m": 40.0, "p": 0.3, "nss": 4, "model": "TP", **{k: 3.0 for k in SUMMARY_METRICS}},  # not in Table 1
        {"m": 40.0, "p": 0.3, "nss": 4, "model": "GP", **{k: 4.0 for k in SUMMARY_METRICS}},
    ])
    rows = table1_beside_paper(ours, TABLE1)
    paper = TABLE1[(40.0, 0.2, 2)]
    assert list(rows.columns) == ["ours TP", "paper TP", "ours GP", "paper GP"]
    assert len(rows) == len(paper["tp"])  # one configuration, each metric the paper gives (no cost rate)
    row = rows.loc[(40.0, 0.2, 2, "task_success_rate")]
    assert (row["ours TP"], row["paper TP"], row["ours GP"], row["paper GP"]) == (1.0, 96.4, 2.0, 90.8)
    none = table1_beside_paper(ours.iloc[2:], TABLE1)
    assert len(none) == 0 and list(none.columns) == ["ours TP", "paper TP", "ours GP", "paper GP"]


def test_beside_the_paper_with_and_without_the_level_intervals():
    from sarsp_edu.experiments.tables import beside_paper
    from sarsp_edu.paper import TABLE2

    metrics = list(TABLE2)
    ours = pd.DataFrame({"TP": [1.0] * 6, "GP": [2.0] * 6, "% change": [-50.0] * 6}, index=metrics)
    plain = beside_paper(ours, TABLE2)
    assert list(plain.columns) == ["ours TP", "ours GP", "ours %", "paper TP", "paper GP", "paper %"]
    assert plain.loc["total_cost", "paper TP"] == TABLE2["total_cost"][0]
    levels = pd.DataFrame({"TP 95% CI low": [0.51234] * 6, "TP 95% CI high": [1.5] * 6,
                           "GP 95% CI low": [-1.0] * 6, "GP 95% CI high": [2000.4] * 6}, index=metrics)
    wide = beside_paper(ours, TABLE2, levels=levels)
    assert list(wide.columns) == ["ours TP", "TP 95% CI", "ours GP", "GP 95% CI", "ours %", "paper TP", "paper GP",
                                  "paper %"]
    assert (wide.loc["task_success_rate", "TP 95% CI"], wide.loc["task_success_rate", "GP 95% CI"]) == (
        "[0.512, 1.50]", "[-1.00, 2000]")
    pd.testing.assert_frame_equal(wide[plain.columns], plain)


def test_cells_are_described_grouped_by_configuration_and_seed():
    from sarsp_edu.experiments.sweep import describe_cells

    keys = [(40.0, 0.2, 6, 0), (40.0, 0.2, 8, 0), (40.0, 0.2, 6, 1), (80.0, 0.4, 10, 0)]
    assert describe_cells(keys) == "m=40 p=0.2 nss=6,8 seed=0; m=40 p=0.2 nss=6 seed=1; m=80 p=0.4 nss=10 seed=0"
    assert describe_cells([]) == ""


def test_curves_and_macro(sweep_dir):
    _, results = sweep_dir
    curves = results.curves("total_cost", "TP", 40, 0.2)
    assert list(curves.columns) == [1, 2] and list(curves.index) == [1, 2, 3]
    macro = results.macro("mean_cost")
    assert list(macro.columns) == ["TP", "GP"] and list(macro.index) == [1, 2]
    frame = results.frame()
    expected = frame[(frame.model == "TP") & (frame.nss == 1)]["mean_cost"].mean()
    assert macro.loc[1, "TP"] == pytest.approx(expected)
    with pytest.raises(ValueError, match="no cell with m=60"):
        results.curves("total_cost", "tp", 60, 0.2)
    low, high = (results.curves("total_cost", "TP", 40, 0.2, over_seeds=how) for how in ("min", "max"))
    assert (low <= curves).all().all() and (curves <= high).all().all()
    assert (low < high).any().any()  # the two seeds differ somewhere, so the band is not the mean twice
    with pytest.raises(ValueError, match="over_seeds must be"):
        results.curves("total_cost", "TP", 40, 0.2, over_seeds="median")
    with pytest.raises(ValueError, match="metric must be one of"):
        results.macro("speed")


def test_tables_refuse_an_empty_sweep():
    with pytest.raises(ValueError, match="no finished cell"):
        summary_tables(SweepResults(TINY))


@pytest.mark.parametrize("umask", [0o022, 0o077])
def test_stored_files_honour_the_umask(tmp_path, umask):
    # atomic writes go through temporary files (0600) and folders (0700);
    # what is left must have the modes an ordinary write would give
    import os
    import stat

    old = os.umask(umask)
    try:
        run_sweep(TINY, magnitudes=(40,), proportions=(0.2,), n_switch_states=(1,), results_dir=tmp_path / "s")
    finally:
        os.umask(old)
    paths = [p for p in (tmp_path / "s").rglob("*")]
    assert any(p.name == "records.csv" for p in paths) and any(p.is_dir() for p in paths)
    for path in paths:
        expected = (0o777 if path.is_dir() else 0o666) & ~umask
        assert stat.S_IMODE(path.stat().st_mode) == expected, path


def _hand_made_sweep(rows):
    """What summary_tables reads from a sweep (frame, a, len), built from per-model metric rows."""
    frame = pd.DataFrame(rows)
    n = len(frame[frame.model == "TP"])
    return type("R", (), {"frame": staticmethod(lambda: frame.copy()), "a": 100.0, "__len__": lambda self: n})()


def test_tables_say_n_a_where_eq_12_is_undefined():
    # a hand-made sweep: in one configuration the GP violated but never succeeded cleanly
    rows = []
    for i, (m, nss) in enumerate([(40, 2), (40, 4), (60, 2)]):
        for model, rate, cost in (("TP", 0.01 * (i + 1), 3.0), ("GP", 0.0 if i == 0 else 0.03, 9.0)):
            rows.append({"m": m, "p": 0.2, "nss": nss, "seed": 0, "model": model, "mean_reward": -50.0,
                         "mean_cost": cost / 10, "total_cost": cost, "task_success_rate": 80.0,
                         "mean_steps": 20.0, "cost_rate": rate})
    results = _hand_made_sweep(rows)
    tables = summary_tables(results, n_boot=50)
    t1 = tables["table1"]
    first = t1[(t1.m == 40) & (t1.nss == 2)]
    assert first.loc[first.model == "TP", "result"].item() == "n/a (p_c undefined)"
    assert np.isnan(first.loc[first.model == "GP", "cost_rate"].item())
    assert tables["mean"].loc["cost_rate", "p_c undefined in"] == 1
    assert tables["mean"].loc["total_cost", "p_c undefined in"] == 0


def test_one_configuration_has_no_bootstrap_interval():
    # one pair has no spread to resample: its interval is undefined, not the value itself
    row = {"m": 40, "p": 0.2, "nss": 2, "seed": 0, "mean_reward": -50.0, "mean_cost": 0.2,
           "total_cost": 3.0, "task_success_rate": 80.0, "mean_steps": 20.0, "cost_rate": 0.01}
    rows = [{**row, "model": "TP"}, {**row, "model": "GP", "total_cost": 9.0, "mean_cost": 0.6}]
    results = _hand_made_sweep(rows)
    tables = summary_tables(results, n_boot=50)
    assert tables["mean"].loc["total_cost", "% change"] == pytest.approx(-66.667, abs=1e-3)
    assert tables["mean"][["95% CI low", "95% CI high"]].isna().all().all()
    assert tables["levels"].filter(like="95% CI").isna().all().all()
    assert tables["levels"].loc["total_cost", "TP"] == 3.0


def test_load_one_seed_of_a_sweep(sweep_dir):
    folder, results = sweep_dir
    first = SweepResults.load(folder, seeds=[0])
    assert len(first) == 4 and {key[3] for key in first.comparisons} == {0}
    assert not first.missing


def test_the_paper_percent_column_can_be_the_papers_printed_one():
    from sarsp_edu import paper
    from sarsp_edu.experiments.metrics import percent_difference
    from sarsp_edu.experiments.tables import beside_paper

    for table, printed in ((paper.TABLE2, paper.TABLE2_PERCENT), (paper.TABLE3, paper.TABLE3_PERCENT),
                           (paper.TABLE4, paper.TABLE4_PERCENT)):
        assert set(printed) == set(table)
        for metric, (tp, gp) in table.items():  # the printed sign and size, up to the table's rounding
            assert np.sign(printed[metric]) == np.sign(percent_difference(tp, gp))
            assert abs(printed[metric] - percent_difference(tp, gp)) < 0.6
    ours = pd.DataFrame({"TP": [1.0] * 6, "GP": [2.0] * 6, "% change": [-50.0] * 6}, index=list(paper.TABLE2))
    printed = beside_paper(ours, paper.TABLE2, percents=paper.TABLE2_PERCENT)["paper %"]
    recomputed = beside_paper(ours, paper.TABLE2)["paper %"]
    assert (printed["mean_cost"], printed["cost_rate"]) == (-39.93, -16.32)  # the paper's text and table
    assert round(recomputed["mean_cost"], 1) == -39.7 and round(recomputed["cost_rate"], 1) == -16.7
