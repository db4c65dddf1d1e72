"""Drawing functions: the choices a reader relies on (ranges, labels), checked on small data."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from sarsp_edu import plotting


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
