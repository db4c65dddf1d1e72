"""The authors' own runs: loaded into the package's columns, equal to the paper's tables, set beside ours."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from sarsp_edu import paper
from sarsp_edu.experiments.metrics import SUMMARY_METRICS
from sarsp_edu.experiments.sweep import SweepResults
from sarsp_edu.experiments.tables import summary_tables
from sarsp_edu.paper.authors import AuthorsRuns, agreement, beside_authors, learning_curves, load_authors_runs

ROOT = Path(__file__).resolve().parents[1]
#: the authors' running columns -> the package's metric
THEIRS = {"mean_reward": "mean_reward", "mean_cost": "mean_cost", "total_cost": "total_cost",
          "task_success_rate": "task_success_rate", "mean_episode_steps": "mean_steps",
          "observed_cost_rate": "cost_rate"}


@pytest.fixture(scope="module")
def runs():
    return load_authors_runs()


@pytest.fixture(scope="module")
def authors_tables(runs):
    return summary_tables(AuthorsRuns(runs))


def test_the_authors_runs_load_whole(runs):
    assert len(runs) == 22_500
    counts = runs.groupby(["model", "m", "p", "nss"]).size()
    assert len(counts) == 90 and set(counts) == {250}
    assert sorted(runs["model"].unique()) == ["GP", "TP"]
    assert runs.groupby(["model", "m", "p", "nss"])["episode"].apply(lambda e: e.tolist() == list(range(1, 251))).all()
    assert runs["start"].str.fullmatch(r"\d+ \d+").all() and runs["goal"].str.fullmatch(r"\d+ \d+").all()
    # each call gives a fresh copy: a caller's edit does not reach the next caller
    mine = load_authors_runs()
    mine.loc[0, "total_cost"] = -1
    assert load_authors_runs().loc[0, "total_cost"] == runs.loc[0, "total_cost"] != -1


def test_the_recomputed_running_metrics_agree_with_the_authors_columns_to_their_three_decimals(runs):
    for theirs, ours in THEIRS.items():
        assert np.abs(runs[f"authors_{theirs}"] - runs[ours]).max() <= 0.0005 + 1e-12, ours
    # the episode's reward is recovered exactly from their (unrounded) running mean
    count = runs["episode"]
    again = runs.groupby(["model", "m", "p", "nss"])["episode_reward"].cumsum() / count
    assert np.allclose(again, runs["authors_mean_reward"], rtol=0, atol=1e-9)


def test_their_episode_250_means_are_the_papers_table_2(runs, authors_tables):
    mean = authors_tables["mean"]
    for metric, (tp, gp) in paper.TABLE2.items():
        assert round(mean.loc[metric, "TP"], 3) == pytest.approx(tp, abs=1e-9), metric
        assert round(mean.loc[metric, "GP"], 3) == pytest.approx(gp, abs=1e-9), metric
    # and its printed percentages: from the unrounded values, except the cost rate's, which comes from the
    # per-run rates as the authors' files round them (three decimals): -16.32 there, -16.03 unrounded
    for metric, percent in paper.TABLE2_PERCENT.items():
        if metric == "cost_rate":
            continue
        assert mean.loc[metric, "% change"] == pytest.approx(percent, abs=0.006), metric
    assert mean.loc["cost_rate", "% change"] == pytest.approx(-16.03, abs=0.006)
    final = runs[runs["episode"] == 250].groupby("model")["authors_observed_cost_rate"].mean()
    assert 100 * (final["TP"] - final["GP"]) / final["GP"] == pytest.approx(paper.TABLE2_PERCENT["cost_rate"],
                                                                          abs=0.006)


def test_their_medians_are_the_papers_table_3(authors_tables):
    median = authors_tables["median"]
    for metric, (tp, gp) in paper.TABLE3.items():
        for model, value in (("TP", tp), ("GP", gp)):
            assert median.loc[metric, model] == pytest.approx(value, abs=0.0006), (metric, model)


def test_their_final_rows_are_the_papers_table_1(authors_tables):
    table1 = authors_tables["table1"].set_index(["m", "p", "nss", "model"])
    for (m, p, nss), rows in paper.TABLE1.items():
        for model, values in rows.items():
            ours = table1.loc[(m, p, nss, model.upper())]
            for metric, value in values.items():
                assert ours[metric] == pytest.approx(value, abs=0.0006), (m, p, nss, model, metric)


def test_definition_4_decides_every_configuration_from_their_cost_rates(authors_tables):
    verdicts = authors_tables["table1"].query("model == 'TP'")["result"]
    assert len(verdicts) == 45
    assert set(verdicts) <= {"TP > GP", "GP > TP", "neither", "n/a (p_c undefined)"}
    # the paper's six Table 1 configurations, all of which it reports as TP preferred: at two of them the
    # authors' own TP has the higher cost rate, and Definition 4 (a strict p_c test first) prefers neither
    table1 = authors_tables["table1"].set_index(["m", "p", "nss", "model"])
    for m, p, nss in paper.TABLE1:
        tp, gp = (table1.loc[(m, p, nss, model), "cost_rate"] for model in ("TP", "GP"))
        expected = "TP > GP" if tp < gp else "neither"
        assert table1.loc[(m, p, nss, "TP"), "result"] == expected, (m, p, nss)
    neither = [key for key in paper.TABLE1 if table1.loc[(*key, "TP"), "result"] == "neither"]
    assert neither == [(60.0, 0.4, 8), (80.0, 0.4, 10)]


class _Runs:
    """A stand-in for SweepResults: ``frame()`` only."""

    def __init__(self, frame):
        self._frame = frame

    def frame(self):
        return self._frame


def _ours_from(authors_frame, seeds, flip=None):
    """Our 'runs': the authors' values for every seed, with TP and GP swapped at the configurations in ``flip``."""
    rows = []
    for seed in seeds:
        part = authors_frame.assign(seed=seed)
        for m, p, nss in (flip or {}).get(seed, ()):
            at = (part.m == m) & (part.p == p) & (part.nss == nss)
            part.loc[at, "model"] = part.loc[at, "model"].map({"TP": "GP", "GP": "TP"})
        rows.append(part)
    return pd.concat(rows, ignore_index=True)


def test_beside_authors_and_agreement_count_what_they_say():
    authors = AuthorsRuns()
    frame = authors.frame()
    flips = {0: [(40.0, 0.2, 2), (60.0, 0.3, 6)], 1: [(40.0, 0.2, 2)]}
    ours = _Runs(_ours_from(frame, (0, 1), flips))
    table = beside_authors(ours, "total_cost", authors)
    assert len(table) == 45 and set(table["seeds"]) == {2}
    assert table.loc[(80.0, 0.4, 10), "ours TP"] == table.loc[(80.0, 0.4, 10), "authors TP"]
    shares = agreement(ours, "total_cost", authors)
    # every authors' total cost favours one model (no tie) at 45 configurations
    theirs_ties = int((beside_authors(_Runs(_ours_from(frame, (0,))), "total_cost", authors)["authors better"]
                       == "tie").sum())
    assert theirs_ties == 0
    assert shares.loc["our seed 0 vs the authors", "agree"] == 43
    assert shares.loc["our seed 1 vs the authors", "agree"] == 44
    assert shares.loc["our seed 0 vs our seed 1", "agree"] == 44
    assert shares.loc["our seed 0 vs our seed 1", "share"] == pytest.approx(100 * 44 / 45)
    with pytest.raises(ValueError, match="metric must be one of"):
        beside_authors(ours, "reward", authors)


def test_learning_curves_are_means_over_the_shared_configurations_with_a_band_over_seeds():
    results = SweepResults.load(ROOT / "results" / "sweep-default")
    curves = learning_curves(results, "total_cost")
    assert list(curves.index) == list(range(1, 251))
    authors = load_authors_runs()
    final = authors[authors.episode == 250].groupby("model")["total_cost"].mean()
    assert curves.loc[250, "authors TP"] == pytest.approx(final["TP"])
    seeds = results.frame().query("model == 'TP'").groupby("seed")["total_cost"].mean()
    assert curves.loc[250, "ours TP low"] == pytest.approx(seeds.min())
    assert curves.loc[250, "ours TP high"] == pytest.approx(seeds.max())
    assert curves.loc[250, "ours TP"] == pytest.approx(seeds.mean())
    assert (curves["ours GP low"] <= curves["ours GP"] + 1e-12).all()
    assert not math.isnan(curves.loc[1, "ours GP"])


def test_every_summary_metric_has_an_authors_level(authors_tables):
    assert set(authors_tables["levels"].index) == set(SUMMARY_METRICS)
    assert authors_tables["levels"].loc["task_success_rate", "TP n"] == 45


def test_a_shorter_sweep_is_set_beside_the_authors_at_its_own_episode(runs):
    at_80 = AuthorsRuns(episode=80).frame()
    means = at_80.groupby("model")[["task_success_rate", "total_cost", "mean_steps"]].mean()
    for metric, (tp, gp) in paper.EPISODE_80.items():  # the package's episode-80 levels come from these records
        assert round(means.loc["TP", metric], 1) == tp and round(means.loc["GP", metric], 1) == gp, metric
    assert len(AuthorsRuns(episode=80).only([(40, 0.2, 2), (80, 0.4, 10)])) == 2
    for bad in (0, 251, 2.5):
        with pytest.raises(ValueError, match=r"episode must be a whole number in \[1, 250\].*got episode="):
            AuthorsRuns(runs, episode=bad)


def test_sarsp_edu_tables_sets_a_stored_sweep_beside_the_authors_runs(capsys):
    from sarsp_edu.cli import main

    assert main(["tables", str(ROOT / "results" / "sweep-reference"), "--seeds", "0", "--all"]) == 0
    out = capsys.readouterr().out
    assert "beside the authors' own runs: Table 2 (mean over all 45 configurations)" in out
    assert "beside the authors' own runs: Table 3 (median), computed the same way" in out
    verdicts = summary_tables(AuthorsRuns())["table1"].query("model == 'TP'")
    line = next(line for line in out.splitlines() if line.startswith("Definition 4 per configuration"))
    assert line.endswith(" of 45)")
    # the authors' verdict at (80, 0.4, 10): their TP's cost rate is the higher one
    row = verdicts.set_index(["m", "p", "nss"]).loc[(80.0, 0.4, 10)]
    assert row["result"] == "neither"


def test_the_paper_figures_configurations_are_the_authors_runs_ending_as_the_paper_says(runs):
    """Figures 2-7 as the authors' records draw them: a column per nss, ending at the per-run values."""
    authors = AuthorsRuns(runs)
    last = authors.frame().set_index(["m", "p", "nss", "model"])
    for figure, (metric, m, p) in paper.FIGURES.items():
        for model in ("TP", "GP"):
            curves = authors.curves(metric, model, m, p)
            assert list(curves.columns) == [2, 4, 6, 8, 10] and list(curves.index) == list(range(1, 251))
            for nss in curves.columns:
                assert curves[nss].iloc[-1] == last.loc[(m, p, nss, model), metric]
    # what the paper's text reads off two of them
    assert authors.curves("total_cost", "GP", 80, 0.4).iloc[-1].idxmax() == 8  # Figure 4(b): "~65 at nss = 8"
    assert authors.curves("total_cost", "TP", 80, 0.4).iloc[-1].max() < 40  # Figure 4(a): "remains < 40"
    assert authors.curves("task_success_rate", "TP", 40, 0.3).iloc[-1][4] == pytest.approx(81.2)  # Figure 6
    with pytest.raises(ValueError, match="no configuration with m=50"):
        authors.curves("total_cost", "TP", 50, 0.2)
    with pytest.raises(ValueError, match="model must be"):
        authors.curves("total_cost", "SVM", 40, 0.2)


def test_a_paper_figure_redrawn_puts_ours_over_seeds_above_the_authors_on_one_range():
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from sarsp_edu import stored_results
    from sarsp_edu.teaching.plotting import plot_paper_figure

    default = SweepResults.load(stored_results("sweep-default"))
    axes = Figure().subplots(2, 2)
    plot_paper_figure(axes, 4, default)
    ranges = {ax.get_ylim() for row in axes for ax in row}
    assert len(ranges) == 1
    assert "3 seeds" in axes[0][0].get_title() and "authors" in axes[1][1].get_title()
    assert len(axes[0][0].collections) == 5  # a band per nss
    with pytest.raises(ValueError, match="figure must be one of the paper's Figures 2-7, got figure=8"):
        plot_paper_figure(Figure().subplots(2, 2), 8, default)
