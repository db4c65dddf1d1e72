"""Drawing functions: the choices a reader relies on (ranges, labels), checked on small data."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from sarsp_edu.teaching import plotting


def curves(early: float, late: float) -> pd.DataFrame:
    episodes = np.arange(1, 101)
    values = np.where(episodes <= 5, early, late + 0.01 * episodes)
    return pd.DataFrame({2: values, 10: values + 1.0}, index=episodes)


def test_figures_2_to_7_share_one_range_set_after_the_transient():
    axes = Figure().subplots(1, 2)
    plotting.plot_curves_by_model(axes, {"TP": curves(-700.0, -100.0), "GP": curves(50.0, -200.0)},
                                  metric="mean_reward", settle=10)
    assert axes[0].get_ylim() == axes[1].get_ylim()
    low, high = axes[0].get_ylim()
    assert -200 > low > -230 and -98 < high < -80  # both models' later values, not the early -700 or 50
    assert any("from episode 11" in t.get_text() for t in axes[0].texts)


def test_figures_8_and_9_reach_zero():
    ax = Figure().subplots()
    frame = pd.DataFrame({"TP": [17.0, 45.0], "GP": [57.0, 56.0]}, index=[2, 10])
    plotting.plot_macro(ax, frame, metric="total_cost")
    assert ax.get_ylim()[0] == 0.0
    ax = Figure().subplots()
    plotting.plot_macro(ax, -frame, metric="mean_reward")
    assert ax.get_ylim()[1] == 0.0


def test_log_ticks_read_as_plain_numbers():
    formatter = plotting.PlainLogFormatter()
    assert [formatter(v) for v in (0.5, 2.0, 10.0, 5000.0)] == ["0.5", "2", "10", "5000"]
    assert formatter(1e-6) == "1e-6" and formatter(1e5) == "1e5"


def test_the_visits_colour_bar_is_opt_in():
    from sarsp_edu import SafeGridWorld

    figure = Figure()
    ax = figure.subplots()
    world = SafeGridWorld(seed=0)
    plotting.plot_gridworld(ax, world, visits=np.arange(100).reshape(10, 10), legend=False)
    assert len(figure.axes) == 1
    plotting.plot_gridworld(ax, world, visits=np.arange(100).reshape(10, 10), legend=False, colorbar=True)
    assert len(figure.axes) == 2


def _legend_covers_no_curve(ax):
    box = ax.get_legend().get_window_extent()
    low = ax.get_ylim()[0]
    for line in ax.get_lines():
        xy = line.get_xydata()
        xy = xy[np.isfinite(xy).all(axis=1) & (xy[:, 1] >= low)]
        points = ax.transData.transform(xy)
        inside = (points[:, 0] >= box.x0) & (points[:, 0] <= box.x1) & (points[:, 1] >= box.y0) & \
            (points[:, 1] <= box.y1)
        if inside.any():
            return False
    return True


def test_tutorial_1s_legends_cover_no_curve():
    from sarsp_edu.models import tails

    for nu, lam in ((3.0, 5.0), (30.0, 5.0), (0.5, 1.5), (10.0, 2.0)):
        for log in (False, True):  # the dashboard's density panels
            figure = Figure(figsize=(4.0, 3.8))  # the dashboard's density panels
            ax = figure.subplots()
            plotting.plot_densities(ax, tails.compute_densities(nu), log=log)
            figure.canvas.draw()
            assert _legend_covers_no_curve(ax), (nu, "log" if log else "linear")
        figure = Figure(figsize=(4.4, 3.8))
        ax = figure.subplots()
        x = np.linspace(0.0, 20.0, 400)
        plotting.plot_tail_ratio_comparison(ax, tails.compute_tail_ratios((nu,), lam, x_t=x, x_gauss=x), nu)
        figure.canvas.draw()
        assert _legend_covers_no_curve(ax), (nu, lam)
        assert max(ax.get_yticks()) <= 1.0  # no tick in the legend's strip above the ratios


def _learning_curves(seeds: int = 3) -> pd.DataFrame:
    """Learning curves as ``sarsp_edu.paper.authors.learning_curves`` returns them, the models' bands overlapping."""
    base = np.linspace(90.0, 85.0, 50)
    curves = pd.DataFrame({"authors TP": base + 1.0, "authors GP": base - 1.0}, index=np.arange(1, 51))
    for model, shift in (("TP", 0.5), ("GP", -0.5)):
        spread = 2.0 if seeds > 1 else 0.0
        curves[f"ours {model}"] = base + shift
        curves[f"ours {model} low"], curves[f"ours {model} high"] = base + shift - spread, base + shift + spread
    return curves


def test_the_learning_curves_name_every_line_and_band_and_no_band_hides_another():
    ax = Figure().subplots()
    plotting.plot_learning_curves_beside_authors(ax, _learning_curves(), metric="task_success_rate",
                                                 label="ours, 3 seeds")
    drawn = [artist.get_label() for artist in [*ax.get_lines(), *ax.collections]]
    assert len(drawn) == 6 and not any(label.startswith("_") for label in drawn)
    assert sorted(text.get_text() for text in ax.get_legend().get_texts()) == sorted(drawn)
    assert "TP, ours, 3 seeds: lowest to highest seed" in drawn and "GP, the authors' runs" in drawn
    bands = ax.collections
    assert all(band.get_facecolor()[0][3] < 0.5 for band in bands)  # translucent: what lies beneath shows
    assert all(band.get_edgecolor()[0][3] > 0 and band.get_linewidth()[0] > 0 for band in bands)  # outlined
    assert [bool(band.get_hatch()) for band in bands] == [False, True]  # and the GP's hatched


def test_the_learning_curves_draw_no_band_for_one_seed_and_can_share_one_legend():
    ax = Figure().subplots()
    plotting.plot_learning_curves_beside_authors(ax, _learning_curves(seeds=1), metric="total_cost", legend=False)
    assert ax.get_legend() is None and not ax.collections
    assert len(ax.get_legend_handles_labels()[1]) == 4
