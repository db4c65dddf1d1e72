"""The dashboards and their computations, without a browser."""

from __future__ import annotations

import html
import io
import math
import re

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
import pytest
from matplotlib.figure import Figure

from sarsp_edu.teaching import demos, plotting
from sarsp_edu.teaching.dashboards.tutorials import (
    Dashboard,
    gridworld_dashboard,
    posterior_dashboard,
    robust_dashboard,
    tail_decay_dashboard,
)
from sarsp_edu.teaching.live import markup

from .worlds import SIX_BY_SIX


# --------------------------------------------------------------------------
# the pure computations
# --------------------------------------------------------------------------
def test_regression_data_outliers():
    X, y, outliers = demos.regression_data(n=40, magnitude=10, proportion=0.1, seed=0)
    clean_X, clean_y, _ = demos.regression_data(n=40, magnitude=1, proportion=0.1, seed=0)
    assert outliers.sum() == 4 and X.shape == (40, 1)
    np.testing.assert_allclose(y[outliers], 10 * clean_y[outliers])
    np.testing.assert_array_equal(y[~outliers], clean_y[~outliers])
    Xs, _, _ = demos.regression_data(n=40, magnitude=10, proportion=0.1, seed=0, scale_inputs=True)
    np.testing.assert_allclose(Xs[outliers], 10 * clean_X[outliers])


def test_compute_posteriors_is_consistent_with_the_models():
    data = demos.compute_posteriors(nu=3.0, magnitude=10, proportion=0.1, seed=0, fit=False)
    # same hyperparameters (no fit): same mean, variance scaled by the TP's factor
    np.testing.assert_allclose(data["tp"]["mean"], data["gp"]["mean"], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(data["tp"]["var"], data["tp_scale"] * data["gp"]["var"], rtol=1e-10)
    assert data["tp_scale"] == pytest.approx((3 + data["beta"] - 2) / (3 + 40 - 2))


def test_more_outliers_raise_the_tp_factor():
    factors = [demos.compute_posteriors(3.0, m, 0.1, 0, fit=False)["tp_scale"] for m in (1, 10, 40)]
    assert factors[0] < factors[1] < factors[2]


def test_nu_path_tends_to_the_gp():
    from sarsp_edu import RBF

    path = demos.compute_nu_path([3, 30, 3e6], kernel=RBF(1.5, 0.5), noise_variance=0.5)
    assert np.all(np.diff(path["scale"]) < 0) and path["scale"][-1] == pytest.approx(1, abs=1e-2)
    assert abs(path["lml"][-1] - path["gp_lml"]) < abs(path["lml"][0] - path["gp_lml"])


def test_compute_world():
    world = demos.compute_world(seed=1, n_switch_states=4, magnitude=40, proportion=0.2, offline_episodes=10)
    assert len(world["moved"]) == 4
    moved = world["moved"]
    assert not np.array_equal(world["before"].unsafe_states[moved], world["after"].unsafe_states[moved])
    stay = np.setdiff1d(np.arange(15), moved)
    np.testing.assert_array_equal(world["before"].unsafe_states[stay], world["after"].unsafe_states[stay])
    rows = world["outlier_rows"]
    np.testing.assert_array_equal(world["dirty"]["X"][rows], 40 * world["clean"]["X"][rows])
    again = demos.compute_world(seed=1, n_switch_states=0, magnitude=40, proportion=0.2, offline_episodes=10)
    np.testing.assert_array_equal(again["after"].unsafe_states, world["before"].unsafe_states)


def test_the_dashboards_seed_is_the_experiments_seed():
    """Seed 3 in tutorial 3's dashboard is the world, data, outliers and shift of a run with seed 3."""
    from sarsp_edu.config import ExperimentConfig
    from sarsp_edu.world.preparation import prepare

    world = demos.compute_world(seed=3, n_switch_states=6, magnitude=60, proportion=0.3, offline_episodes=10)
    config = ExperimentConfig(seed=3, n_switch_states=6, outlier_magnitude=60.0, outlier_proportion=0.3,
                              offline_episodes=10)
    prepared = prepare(config)
    np.testing.assert_array_equal(world["after"].unsafe_states, prepared.env.unsafe_states)
    np.testing.assert_array_equal(world["before"].unsafe_states, prepared.layout_before.unsafe_states)
    np.testing.assert_array_equal(world["dirty"]["X"], prepared.data.cost.X)
    np.testing.assert_array_equal(world["dirty"]["y"], prepared.data.cost.y)
    np.testing.assert_array_equal(world["outlier_rows"], prepared.data.outlier_indices)
    # a second call with other sliders reuses the cached world and leaves it unshifted
    again = demos.compute_world(seed=3, n_switch_states=0, magnitude=60, proportion=0.3, offline_episodes=10)
    np.testing.assert_array_equal(again["after"].unsafe_states, prepared.layout_before.unsafe_states)


# --------------------------------------------------------------------------
# the dashboards
# --------------------------------------------------------------------------
@pytest.mark.parametrize("factory", [tail_decay_dashboard, posterior_dashboard, gridworld_dashboard])
def test_dashboard_draws_and_redraws(factory):
    dashboard = factory()
    assert isinstance(dashboard, Dashboard)
    assert dashboard.message.value == ""
    assert dashboard.last_redrawn == [0, 1, 2]
    first = [image.value for image in dashboard.images]
    for image, data in zip(dashboard.images, first):
        assert image.format == "svg+xml" and bytes(data).startswith(b"<?xml")
    name, control = next((n, c) for n, c in dashboard.controls.items() if hasattr(c, "max"))
    import time

    start = time.perf_counter()
    control.value = control.max
    elapsed = time.perf_counter() - start
    assert dashboard.message.value == "", dashboard.message.value
    assert dashboard.last_redrawn
    for i in dashboard.last_redrawn:
        assert dashboard.images[i].value != first[i]
    assert 0 < dashboard.last_update_seconds <= elapsed  # the dashboard times the update it made
    assert dashboard.info.value


@pytest.mark.parametrize(
    "factory, control, redrawn",
    [
        (tail_decay_dashboard, "lam", [2]),
        (tail_decay_dashboard, "nu", [0, 1, 2]),
        (posterior_dashboard, "nu", [1, 2]),  # the GP does not depend on nu
        (posterior_dashboard, "magnitude", [0, 1, 2]),
        (gridworld_dashboard, "n_switch_states", [1]),
        (gridworld_dashboard, "magnitude", [2]),
        (gridworld_dashboard, "seed", [0, 1, 2]),
    ],
)
def test_a_move_redraws_only_the_panels_that_depend_on_it(factory, control, redrawn):
    dashboard = factory()
    before = [image.value for image in dashboard.images]
    slider = dashboard.controls[control]
    slider.value = slider.value + slider.step
    assert dashboard.last_redrawn == redrawn
    for i, (old, image) in enumerate(zip(before, dashboard.images)):
        assert (image.value != old) == (i in redrawn), i


def _pixels(image) -> np.ndarray:
    """A panel's picture as something to compare: PNG pixels, or the SVG text."""
    import io

    import matplotlib.image

    data = bytes(image.value)
    if image.format == "svg+xml":
        return np.array(data.decode())
    return matplotlib.image.imread(io.BytesIO(data), format="png")


@pytest.mark.parametrize(
    "factory, moves",
    [
        (tail_decay_dashboard, [("nu", 12.0), ("lam", 2.0), ("nu", 1.5)]),
        (posterior_dashboard, [("fit", False), ("magnitude", 60.0), ("proportion", 0.3), ("nu", 9.0),
                               ("scale_inputs", True)]),
        (gridworld_dashboard, [("n_switch_states", 0), ("magnitude", 90.0), ("seed", 2), ("proportion", 0.05),
                               ("n_switch_states", 9)]),
    ],
)
def test_a_redrawn_figure_equals_a_fresh_one(factory, moves):
    # Slider moves reuse the Axes (only their contents are wiped) and skip the
    # panels that cannot have changed: nothing of an earlier picture may
    # survive into a later one, and no panel may be left showing old values.
    moved = factory()
    for name, value in moves:
        moved.controls[name].value = value
        assert moved.message.value == "", moved.message.value
    fresh = factory(**{name: value for name, value in moves if name != "scale_inputs"})
    if "scale_inputs" in moved.controls:
        fresh.controls["scale_inputs"].value = moved.controls["scale_inputs"].value
    assert fresh.values() == moved.values()
    for i, (a, b) in enumerate(zip(moved.images, fresh.images)):
        np.testing.assert_array_equal(_pixels(a), _pixels(b), err_msg=f"panel {i}")
    assert moved.info.value == fresh.info.value


def _one_panel_dashboard(draw, x: float, inputs=None) -> Dashboard:
    from ipywidgets import FloatSlider

    from sarsp_edu.teaching.dashboards.tutorials import Panel

    return Dashboard({"x": FloatSlider(value=x, min=0, max=2), "y": FloatSlider(value=0, min=0, max=1)},
                     lambda x, y: (x, f"x = {x}"), [Panel(draw, 3.0, inputs=inputs)], height=2.0)


def test_a_wiped_axes_forgets_titles_limits_scales_and_colours():
    def draw(ax, result, x, **_):
        if x > 1:  # state a later, plainer picture must not inherit
            ax.set_title("big")
            ax.set_xlabel("x")
            ax.set_ylabel("y")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_ylim(1e-3, 1e3)
            ax.set_aspect("equal")
            ax.text(0.5, 0.5, "note")
            ax.legend(*ax.plot([1, 20], [1, 2], label="first"))
        if x < 0.25:  # no data at all: the default limits, not the last picture's
            ax.text(0.1, 0.1, "empty")
        else:
            ax.plot([0.1, 1], [1, 1 + x])

    moved = _one_panel_dashboard(draw, 2.0)
    for x in (0.1, 0.5):
        moved.controls["x"].value = x
        np.testing.assert_array_equal(_pixels(moved.images[0]), _pixels(_one_panel_dashboard(draw, x).images[0]))


EXTREMES = [
    (tail_decay_dashboard, {}),
    (tail_decay_dashboard, {"nu": 0.5, "lam": 10.0}),
    (tail_decay_dashboard, {"nu": 30.0, "lam": 1.5}),
    (posterior_dashboard, {}),
    (posterior_dashboard, {"nu": 2.1, "magnitude": 100.0, "proportion": 0.5}),
    (posterior_dashboard, {"nu": 50.0, "magnitude": 1.0, "proportion": 0.0, "fit": False}),
    (gridworld_dashboard, {}),
    (gridworld_dashboard, {"n_switch_states": 15, "magnitude": 100.0, "proportion": 0.5}),
]


@pytest.mark.parametrize("factory, values", EXTREMES)
def test_axis_labels_never_touch_tick_labels(factory, values):
    # The axis labels sit at fixed distances (Panel.label_offsets) instead of
    # being placed after measuring the tick labels: check those distances hold
    # the widest tick labels each panel shows, and stay inside the picture.
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    dashboard = factory(**values)
    assert dashboard.message.value == ""
    for i, (figure, ax) in enumerate(zip(dashboard.figures, dashboard.axes)):
        canvas = FigureCanvasAgg(figure)
        canvas.draw()
        renderer = canvas.get_renderer()
        for axis in (ax.xaxis, ax.yaxis):
            label = axis.label.get_window_extent(renderer)
            assert label.x0 >= 0 and label.y0 >= 0, (i, axis.axis_name, label)
            low, high = sorted(axis.get_view_interval())
            for tick in [*axis.get_major_ticks(), *axis.get_minor_ticks()]:
                if not (tick.label1.get_visible() and tick.label1.get_text()):
                    continue
                if not low <= tick.get_loc() <= high:
                    continue
                box = tick.label1.get_window_extent(renderer)
                assert not box.overlaps(label), (i, axis.axis_name, tick.label1.get_text())


def test_expensive_sliders_update_on_release():
    dashboard = posterior_dashboard()
    assert all(not c.continuous_update for n, c in dashboard.controls.items() if hasattr(c, "continuous_update"))


@pytest.mark.parametrize(
    "factory, changes",
    [
        (posterior_dashboard, {"nu": 2.1, "magnitude": 100.0, "proportion": 0.5}),
        (posterior_dashboard, {"proportion": 0.0, "fit": False, "scale_inputs": True}),
        (tail_decay_dashboard, {"nu": 0.5, "lam": 10.0}),
        (robust_dashboard, {"nu": 2.1, "magnitude": 100.0, "proportion": 0.5}),
        (robust_dashboard, {"proportion": 0.0, "nu": 50.0, "seed": 20}),
        (gridworld_dashboard, {"n_switch_states": 15, "magnitude": 100.0, "proportion": 0.5}),
    ],
)
def test_extreme_values_are_drawn(factory, changes):
    # refresh() turns any exception into a message (a dashboard must not crash in class), so the
    # test asks for more: every extreme corner of the sliders draws, with no message at all
    dashboard = factory()
    for name, value in changes.items():
        dashboard.controls[name].value = value
        assert dashboard.message.value == "", (name, value, dashboard.message.value)
        assert dashboard.last_redrawn and not dashboard._stale
        assert all(bytes(dashboard.images[i].value).startswith(b"<?xml") for i in dashboard.last_redrawn)


def test_a_failing_update_shows_a_message_not_a_traceback():
    def draw(ax, result, x, **_):
        if x > 1:
            raise np.linalg.LinAlgError("not positive definite")
        ax.plot([0, 1], [0, x])

    dashboard = _one_panel_dashboard(draw, 0.5, inputs=("x",))
    good = dashboard.images[0].value
    dashboard.controls["x"].value = 2.0
    assert "LinAlgError: not positive definite" in dashboard.message.value
    assert dashboard.images[0].value == good  # the last good picture stays
    assert dashboard.info.value == "x = 0.5"
    dashboard.controls["x"].value = 0.7
    assert dashboard.message.value == ""
    assert dashboard.info.value == "x = 0.7"


def test_after_a_failure_the_next_move_redraws_every_panel():
    from ipywidgets import FloatSlider

    from sarsp_edu.teaching.dashboards.tutorials import Panel

    def draw_x(ax, result, x, **_):
        if x > 1:
            raise ValueError("x too large")
        ax.plot([0, 1], [0, x])

    def draw_y(ax, result, y, **_):
        ax.plot([0, 1], [0, y])

    dashboard = Dashboard({"x": FloatSlider(value=0.5, min=0, max=2), "y": FloatSlider(value=0, min=0, max=1)},
                          lambda x, y: (None, ""),
                          [Panel(draw_x, 3.0, inputs=("x",)), Panel(draw_y, 3.0, inputs=("y",))],
                          height=2.0)
    dashboard.controls["x"].value = 2.0  # the x panel fails and keeps its x = 0.5 picture
    assert "x too large" in dashboard.message.value
    # Moving y alone would redraw only the y panel and clear the message,
    # leaving the x panel silently out of date; after a failure every panel is tried.
    dashboard.controls["y"].value = 0.5
    assert "x too large" in dashboard.message.value
    dashboard.controls["x"].value = 0.25
    assert dashboard.message.value == ""
    assert dashboard.last_redrawn == [0, 1]


# --------------------------------------------------------------------------
# the drawing functions
# --------------------------------------------------------------------------
def test_plot_gridworld_draws_what_it_is_handed():
    from matplotlib import patches

    from sarsp_edu import SafeGridWorld

    env = SafeGridWorld(seed=0)
    env.shift(3, rng=0)
    ax = Figure().subplots()
    plotting.plot_gridworld(ax, env, trajectory=[(0, 0), (1, 0)], unsafe_pairs=[((1, 0), 1)], show_agent=True)
    from matplotlib.collections import PatchCollection

    squares = [c for c in ax.collections if isinstance(c, PatchCollection)]
    solid = [c for c in squares if len(c.get_facecolor()) and c.get_facecolor()[0][3] > 0]
    dashed = [c for c in squares if c.get_linestyle()[0][1] is not None]  # (offset, dash pattern)
    assert [len(c.get_paths()) for c in solid] == [15] and [len(c.get_paths()) for c in dashed] == [3]
    assert len([p for p in ax.patches if isinstance(p, patches.FancyArrowPatch)]) == 3  # old cell -> new cell
    edges = [tuple(e) for e in solid[0].get_edgecolor()]
    assert edges.count((0.0, 0.0, 0.0, 1.0)) == 3  # the moved states are outlined in black
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert {"start", "goal", "path", "moved here", "learned unsafe move (S_u)"} <= set(labels)
    assert ax.get_ylim()[0] > ax.get_ylim()[1]  # row 0 at the top


def test_curve_and_macro_plots():
    import pandas as pd

    curves = pd.DataFrame({2: [1.0, 2.0], 4: [2.0, 3.0]}, index=[1, 2])
    ax = Figure().subplots()
    plotting.plot_metric_curves(ax, curves, metric="total_cost")
    assert len(ax.lines) == 2 and ax.get_ylabel() == plotting.METRIC_LABELS["total_cost"]
    macro = pd.DataFrame({"TP": [0.1, 0.2], "GP": [0.3, 0.3]}, index=[2, 4])
    ax = Figure().subplots()
    plotting.plot_macro(ax, macro, metric="mean_cost")
    assert [line.get_label() for line in ax.lines] == ["TP", "GP"]


# --------------------------------------------------------------------------
# the live agent dashboard
# --------------------------------------------------------------------------
SMALL = dict(SIX_BY_SIX)


@pytest.fixture
def live():
    from sarsp_edu import ExperimentConfig
    from sarsp_edu.teaching.dashboards.tutorials import agent_dashboard

    return agent_dashboard(episodes=3, n_switch_states=2, config=ExperimentConfig(**SMALL))


def test_live_dashboard_steps_both_agents_paired(live):
    live.run_steps(5)
    tp, gp = live.experiments["tp"], live.experiments["gp"]
    np.testing.assert_array_equal(tp.env.unsafe_states, gp.env.unsafe_states)
    assert tp.config.model == "tp" and gp.config.model == "gp"
    assert live.frames == 5
    for model in ("tp", "gp"):
        assert live.worlds[model].value.startswith("<svg") and "polyline" in live.worlds[model].value
        assert "cost σ²" in live.decisions[model].value


def test_live_dashboard_runs_to_the_end_and_matches_a_plain_run(live):
    from sarsp_edu import run_experiment

    live.run_steps(2)
    live.fast_forward(10)
    assert live.finished
    svg = live.metrics_image.value  # inline, with its alt text: the final running values of both sides
    assert svg.startswith("<svg") and 'role="img"' in svg and "<?xml" not in svg
    episodes = len(live.experiments["tp"].records())
    last = live.experiments["tp"].records().iloc[-1]
    assert (f"Student-t process after {episodes} episodes: mean reward {float(last['mean_reward']):.3g}, total cost "
            f"{float(last['total_cost']):.3g}") in html.unescape(svg.split('aria-label="')[1].split('"')[0])
    plain = run_experiment(live.config().replace(model="tp"))
    import pandas as pd

    pd.testing.assert_frame_equal(live.experiments["tp"].records(), plain.records)


def test_a_live_dashboard_of_two_settings_of_one_model():
    from sarsp_edu import ExperimentConfig
    from sarsp_edu.teaching.dashboards.tutorials import agent_dashboard

    sides = {"per step": ("one prior per step", {"model": "gp", "prior_draw": "per_step"}),
             "per action": ("a prior per action", {"model": "gp", "prior_draw": "per_action"})}
    live = agent_dashboard(episodes=2, n_switch_states=2, config=ExperimentConfig(**SMALL), sides=sides)
    assert "one prior per step" in live.headers["per step"].value
    live.fast_forward(2)
    step, action = live.experiments["per step"], live.experiments["per action"]
    assert (step.config.model, step.config.prior_draw) == ("gp", "per_step")
    assert (action.config.model, action.config.prior_draw) == ("gp", "per_action")
    np.testing.assert_array_equal(step.env.unsafe_states, action.env.unsafe_states)
    assert live.metrics_axes[0].get_legend_handles_labels()[1] == ["per step", "per action"]
    with pytest.raises(ValueError, match="those shape the world"):
        agent_dashboard(sides={"a": ("A", {"model": "tp"}), "b": ("B", {"n_switch_states": 3})})
    with pytest.raises(ValueError, match="two names"):
        agent_dashboard(sides={"a": ("A", {"model": "tp"})})
    with pytest.raises(ValueError, match="prior_draw"):
        agent_dashboard(sides={"a": ("A", {"model": "tp"}), "b": ("B", {"prior_draw": "per_episode"})})


def test_live_dashboard_reads_the_sliders(live):
    live.controls["nu"].value = 5.0
    live.controls["n_switch_states"].value = 3
    config = live.config()
    assert config.nu == 5.0 and config.n_switch_states == 3 and config.grid_size == 6
    live.build_runs()
    assert len(live.experiments["gp"].env.moved_indices) == 3


def test_live_dashboard_async_run_and_stop(live):
    import asyncio

    async def scenario():
        live.speed.value = 60
        task = live.start()
        for _ in range(600):  # preparation runs in a worker thread; then frames appear
            await asyncio.sleep(0.1)
            if live.frames >= 3 or task.done():
                break
        live.stop()
        await task
        return live.frames

    frames = asyncio.run(scenario())
    assert frames > 0 and not live.running
    # what Stop says (or the run's end), and not "Stopped by an error: ..."
    assert re.match(r"(Stopped\. <b>Run</b> continues|Paused\.|Finished every episode\.)", live.status.value), \
        live.status.value


def test_stop_pressed_while_a_side_steps_stays_said(live):
    # Stop while a side is inside a step (a retrain takes seconds): when that step ends, the status line must
    # still say the run stopped, not "Running: 10 steps shown", and no step follows
    import threading

    live.build_runs()
    entered, release, calls = threading.Event(), threading.Event(), []
    step = live.experiments["gp"].step

    def slow_tenth_step():
        calls.append(1)
        if len(calls) == 10:  # the frame that makes 10 steps shown on both sides
            entered.set()
            release.wait(60)
        return step()

    live.experiments["gp"].step = slow_tenth_step
    live.speed.value = 60
    launched = live.play_in_background()
    assert entered.wait(60)
    live.stop()
    release.set()
    assert launched.result(60) is True
    assert live.frames == 10 and not live.running and len(calls) == 10
    assert live.status.value.startswith("Stopped."), live.status.value


def test_svg_and_table_drawings():
    from sarsp_edu import SafeGridWorld
    from sarsp_edu.agent.sarsp import Decision

    env = SafeGridWorld(seed=0)
    env.shift(2, rng=0)
    svg = markup.gridworld_svg(env.layout(), trajectory=[(0, 0), (1, 0)], unsafe_pairs=[((1, 0), 1)], title="t")
    assert svg.count('stroke-dasharray="3,2"') == 2  # the two cells states moved away from
    assert svg.count(f'fill="{plotting.COLOURS["unsafe"]}"') == 15
    decision = Decision((0, 0), np.array([2.0, 0.5, 3, 1]), np.array([0.1, 0.1, 2, 0.5]), np.zeros(4),
                        np.zeros(4), np.array([False, False, False, True]), np.array([True, False, False, False]),
                        0, False)
    table = markup.decision_table_html(decision, 1.0, 0.8)
    assert table.count("<tr") == 5 and "in S_u" in table and "safe action with the highest reward" in table


def test_bad_panels_are_refused_with_the_parameter_named():
    from ipywidgets import FloatSlider

    from sarsp_edu.teaching.dashboards.tutorials import Panel

    def draw(ax, result, **_):
        ax.plot([0, 1])

    controls = {"x": FloatSlider(value=0.5)}
    with pytest.raises(ValueError, match="width"):
        Panel(draw, 0.0)
    with pytest.raises(ValueError, match="Panel inputs must be one of 'x', got Panel inputs='nu'"):
        Dashboard(controls, lambda x: (x, ""), [Panel(draw, 3.0, inputs=("nu",))], height=2.0)
    with pytest.raises(ValueError, match="height"):
        Dashboard(controls, lambda x: (x, ""), [Panel(draw, 3.0)], height=-1)
    with pytest.raises(ValueError, match="panels"):
        Dashboard(controls, lambda x: (x, ""), [], height=2.0)


@pytest.mark.parametrize(
    "make, kwargs, message",
    [
        ("posterior_dashboard", dict(proportion=0.8), r"proportion must lie in \[0, 0.5\] \(the slider's range\)"),
        ("posterior_dashboard", dict(nu=2.0), r"nu must lie in \[2.1, 50\]"),
        ("tail_decay_dashboard", dict(lam=20.0), r"lam must lie in \[1.5, 10\]"),
        ("gridworld_dashboard", dict(n_switch_states=16), "n_switch_states must be an integer from 0 to 15"),
        ("gridworld_dashboard", dict(seed=2.5), "seed must be an integer from 0 to 50"),
    ],
)
def test_dashboards_refuse_values_their_sliders_cannot_show(make, kwargs, message):
    # a slider silently clamped posterior_dashboard(proportion=0.8) to 0.5
    import sarsp_edu.teaching.dashboards.tutorials as widgets_module

    with pytest.raises(ValueError, match=message):
        getattr(widgets_module, make)(**kwargs)


def _png_size(data: bytes) -> tuple[int, int]:
    """(width, height) of a PNG, from its header."""
    import struct

    return struct.unpack(">II", data[16:24])


@pytest.mark.parametrize("factory", [tail_decay_dashboard, posterior_dashboard, gridworld_dashboard])
def test_a_static_copy_of_a_dashboard_shows_its_pictures_projector_wide(factory):
    """GitHub and nbviewer render no widgets: the output also carries the panels as one PNG, 1,600 px wide."""
    import base64

    import matplotlib.image as mpimg
    from matplotlib.text import Text

    from sarsp_edu.teaching.dashboards.framework import SNAPSHOT_WIDTH_PX

    dashboard = factory()
    sizes = [t.get_fontsize() for f in dashboard.figures for t in f.findobj(Text)]
    bundle, metadata = dashboard._repr_mimebundle_()
    assert "application/vnd.jupyter.widget-view+json" in bundle  # live front ends keep the widget
    alt = metadata["image/png"]["alt"]  # what a screen reader says of the static copy's picture
    assert alt == dashboard.alt_text() and alt.startswith("3 pictures side by side. Left: ")
    assert alt.count(": ") >= 3 and "No description" not in alt
    data = base64.b64decode(bundle["image/png"])
    image = mpimg.imread(io.BytesIO(data), format="png")
    width = _png_size(data)[0]
    assert SNAPSHOT_WIDTH_PX <= width < SNAPSHOT_WIDTH_PX + 10  # every panel, side by side
    assert image[..., :3].std() > 0.05  # not a blank picture
    assert [t.get_fontsize() for f in dashboard.figures for t in f.findobj(Text)] == sizes  # the live view unchanged


def test_a_stored_picture_enlarges_small_text_to_14_pt_at_1600_px_and_gives_it_back():
    from matplotlib.figure import Figure
    from matplotlib.text import Text

    from sarsp_edu.teaching.dashboards.framework import SNAPSHOT_TEXT_PT, readable_png

    figure = Figure(figsize=(8, 3))
    ax = figure.subplots()
    ax.set_title("small", fontsize=6)
    drawn = []
    original = Text.draw

    def spy(self, renderer):
        if self.get_text() == "small":
            drawn.append(self.get_fontsize() * renderer.dpi / 72)  # its height in pixels as drawn
        return original(self, renderer)

    Text.draw = spy
    try:
        data = readable_png([figure])
    finally:
        Text.draw = original
    assert _png_size(data)[0] >= 1600
    assert drawn and drawn[0] >= SNAPSHOT_TEXT_PT * 96 / 72 - 1e-9  # 14 pt at a browser's 96 px per inch
    assert ax.title.get_fontsize() == 6


def test_the_live_dashboards_static_picture_before_and_after_a_run(monkeypatch):
    import base64

    from sarsp_edu import ExperimentConfig
    from sarsp_edu.teaching.dashboards.tutorials import agent_dashboard
    from sarsp_edu.teaching.live import SNAPSHOT_VARIABLE

    dashboard = agent_dashboard(episodes=1, n_switch_states=1, config=ExperimentConfig(**SMALL))
    bundle, metadata = dashboard._repr_mimebundle_()
    before = base64.b64decode(bundle["image/png"])
    assert metadata["image/png"]["alt"].startswith("Two grid worlds side by side")
    assert before.startswith(b"\x89PNG") and _png_size(before)[0] >= 1600
    assert dashboard.experiments is None  # shown outside a course build: nothing ran for the picture
    dashboard.fast_forward(1)
    after = dashboard.snapshot()
    assert _png_size(after)[1] > _png_size(before)[1]  # the metric curves are added below the worlds
    assert [label for label, _ in dashboard.key_numbers("tp")][:3] == ["episodes", "reached goal",
                                                                        "violations"]
    monkeypatch.setenv(SNAPSHOT_VARIABLE, "2")  # a course build: the stored picture shows the agents at work
    built = agent_dashboard(episodes=3, n_switch_states=1, config=ExperimentConfig(**SMALL))
    built._repr_mimebundle_()
    assert all(len(e.episodes) == 2 for e in built.experiments.values())


# --------------------------------------------------------------------------
# tutorial 6: the stored ablation, one setting at a time
# --------------------------------------------------------------------------
@pytest.fixture(scope="module")
def ablation():
    from pathlib import Path

    from sarsp_edu.experiments.ablation import AblationResults

    return AblationResults.load(Path(__file__).resolve().parents[1] / "results" / "ablation")


def test_the_ablation_dashboard_shows_the_setting_its_toggles_name(ablation):
    from sarsp_edu.experiments.ablation import PRIOR_AND_FITS
    from sarsp_edu.teaching.dashboards.tutorials import ablation_dashboard

    dashboard = ablation_dashboard(ablation)
    assert dashboard.message.value == ""
    assert "per step, k=100, 500-row fits" in dashboard.info.value
    runs = ablation.runs()
    gp = runs[(runs.setting == PRIOR_AND_FITS[("per step", "500 rows")]) & (runs.model == "GP")]
    assert f"GP {gp.trapped_failures.sum()} of {gp.failures.sum()}" in dashboard.info.value
    before = [image.value for image in dashboard.images]
    dashboard.controls["prior"].value = "per action"
    assert dashboard.message.value == ""
    assert "per action, k=100, 500-row fits" in dashboard.info.value
    assert all(image.value != old for image, old in zip(dashboard.images, before))


def test_the_ablation_dashboard_says_which_runs_are_missing(ablation):
    from sarsp_edu.experiments.ablation import PRIOR_AND_FITS, AblationResults
    from sarsp_edu.teaching.dashboards.tutorials import ablation_dashboard

    only = PRIOR_AND_FITS[("per step", "500 rows")]
    partial = AblationResults(sweeps={only: ablation.sweeps[only]}, settings={only: ablation.settings[only]})
    dashboard = ablation_dashboard(partial)
    dashboard.controls["fits"].value = "default fits"
    message = html.unescape(dashboard.message.value)
    assert "holds no finished run of 'per step, k=100, default fits'" in message
    assert "sarsp-edu ablation --settings 'per step, k=100, default fits'" in message
    with pytest.raises(ValueError, match="prior must be one of"):
        ablation_dashboard(ablation, prior="per episode")


# -- the live dashboard's sliders act at once --------------------------------------------------------
from sarsp_edu import ExperimentConfig  # noqa: E402
from sarsp_edu.teaching.dashboards.tutorials import agent_dashboard  # noqa: E402


def test_a_slider_move_redraws_the_world_it_implies_and_says_when_the_agents_use_it():
    live = agent_dashboard(episodes=2, n_switch_states=1, config=ExperimentConfig(**SMALL))
    before = {name: widget.value for name, widget in live.worlds.items()}
    assert "1 unsafe states moved" in live.summaries["tp"].value
    first_preview = live.last_preview_seconds
    live.controls["n_switch_states"].value = 4
    assert all(live.worlds[name].value != before[name] for name in live.sides)
    assert live.worlds["tp"].value == live.worlds["gp"].value  # one world for both agents
    assert "4 unsafe states moved" in live.summaries["gp"].value
    assert "both agents start on this world at the next <b>Run</b>." in live.status.value
    live.controls["proportion"].value = 0.4
    assert "Outliers: " in live.summaries["tp"].value and "times m = 40" in live.summaries["tp"].value
    # each move's preview timed anew (measured, not judged: benchmarks/bench_dashboards.py times it)
    assert 0 < live.last_preview_seconds < math.inf and live.last_preview_seconds != first_preview


def test_a_slider_move_during_a_run_stops_it_and_the_next_run_uses_the_new_world():
    live = agent_dashboard(episodes=2, n_switch_states=1, config=ExperimentConfig(**SMALL))
    live.run_steps(3)
    assert live.experiments is not None
    live.controls["seed"].value = 5
    assert live.experiments is None and "(the run under way was stopped)" in live.status.value
    live.run_steps(1)
    assert next(iter(live.experiments.values())).config.seed == 5


def test_fast_forward_shows_its_progress_and_a_second_press_while_running_is_answered():
    import asyncio

    live = agent_dashboard(episodes=3, n_switch_states=1, config=ExperimentConfig(**SMALL))
    seen = []
    live.status.observe(lambda change: seen.append(change["new"]), names="value")

    async def press_twice():
        task = live.start(episodes=2)
        live.start(episodes=2)
        assert "Already running: press <b>Stop</b> first, then <b>Fast-forward</b>." in live.status.value
        await task

    asyncio.run(press_twice())
    assert any("Fast-forwarding: episode 1 of 2" in text for text in seen)
    assert any("Fast-forwarding: episode 2 of 2" in text for text in seen)
    assert all(len(e.episodes) == 2 for e in live.experiments.values())


# -- no silent freezes, a quick start, projector size -------------------------------------------------
def test_the_runs_fitted_ahead_run_as_the_plain_paired_runs():
    from sarsp_edu.experiments.experiment import paired_experiments

    live = agent_dashboard(episodes=2, n_switch_states=1, config=ExperimentConfig(**SMALL))
    fits = live.run.fits.claim(live.config())  # begun in the background at construction
    assert fits is not None
    ahead = {name: fits.wait_for(name) for name in live.sides}
    plain = paired_experiments(live.config())
    for name in live.sides:
        ahead[name].run_episode()
        plain[name].run_episode()
        pd.testing.assert_frame_equal(ahead[name].records(), plain[name].records())


def test_a_side_that_retrains_says_so_while_both_wait(monkeypatch):
    import asyncio

    from sarsp_edu.agent import sarsp

    live = agent_dashboard(episodes=3, n_switch_states=1, config=ExperimentConfig(**SMALL))
    live.speed.value = 60
    live.build_runs()
    agent = live.experiments["gp"].agent
    plain_fit, seen, during = agent._fit, [], []

    def watched_fit(*args):  # a corrective update's refit: what the header says meanwhile, and the other side
        during.append((live.headers["gp"].value, len(live.run.frame_times["tp"])))
        return plain_fit(*args)

    monkeypatch.setattr(agent, "_fit", watched_fit)
    monkeypatch.setattr(sarsp, "corrective_applies", lambda *args: True)  # every violation is corrected
    agent.settings = agent.settings.replace(retrain="always")
    live.headers["gp"].observe(lambda change: seen.append(change["new"]), names="value")

    async def scenario():
        task = live.start()
        while not during and not task.done():
            await asyncio.sleep(0.05)
        live.stop()
        await task

    asyncio.run(scenario())
    if not during:
        pytest.skip("no violation in this run's first episodes: nothing to retrain")
    assert all("retraining its cost model" in header for header, _ in during), during
    assert any("retraining its cost model" in text for text in seen), seen


def test_projector_size_is_one_switch_for_every_dashboard(monkeypatch):
    from sarsp_edu.teaching.dashboards.tutorials import projector, tail_decay_dashboard

    projector(None)  # automatic: on unless SARSP_EDU_PROJECTOR=0
    monkeypatch.delenv("VOILA_KERNEL_ID", raising=False)
    monkeypatch.setenv("SARSP_EDU_PROJECTOR", "0")
    tails = tail_decay_dashboard()
    live = agent_dashboard(episodes=2, n_switch_states=1, config=ExperimentConfig(**SMALL), fit_ahead=False)
    assert not tails.projector and "sarsp-projector" not in tails._dom_classes
    normal_width = tails.controls["nu"].layout.width
    assert 'font-size="13"' in live.worlds["tp"].value
    projector(True)
    for board in (tails, live):
        assert board.projector and "sarsp-projector" in board._dom_classes
    assert int(tails.controls["nu"].layout.width[:-2]) > int(normal_width[:-2])
    assert tails.images[0].layout.min_width.endswith("px, 100%)") and tails.pictures.layout.flex_flow == "row wrap"
    assert tails.size_toggle.value and tails.size_toggle.description == "Large text: on"
    assert 'font-size="18"' in live.worlds["tp"].value  # the grid's title, redrawn
    later = tail_decay_dashboard()
    assert later.projector  # and those made after the switch
    projector(False)
    assert not tails.projector and tails.controls["nu"].layout.width == normal_width
    assert tails.images[0].layout.width.endswith("%")
    from sarsp_edu.teaching.dashboards.projector import projector_default

    projector(None)  # automatic again: on, wherever the notebook runs
    monkeypatch.delenv("SARSP_EDU_PROJECTOR")
    assert projector_default() and tail_decay_dashboard().projector
    monkeypatch.setenv("SARSP_EDU_PROJECTOR", "1")
    assert projector_default()
    monkeypatch.delenv("SARSP_EDU_PROJECTOR")
    monkeypatch.setenv("VOILA_KERNEL_ID", "any")
    assert projector_default()  # Voila's kernels
    monkeypatch.delenv("VOILA_KERNEL_ID")
    with pytest.raises(TypeError, match="on must be True, False or None"):
        projector("yes")


def test_autoplay_starts_the_agents_when_shown_in_a_thread_of_their_own(monkeypatch):
    import time as clock

    monkeypatch.setenv("SARSP_EDU_AUTOPLAY", "0")  # a batch run: shown, not started
    quiet = agent_dashboard(episodes=2, n_switch_states=1, config=ExperimentConfig(**SMALL), autoplay=True)
    quiet._repr_mimebundle_()
    assert not quiet.running
    monkeypatch.setenv("SARSP_EDU_AUTOPLAY", "1")

    live = agent_dashboard(episodes=2, n_switch_states=1, config=ExperimentConfig(**SMALL), autoplay=True)
    live.speed.value = 60
    assert not live.running  # made, not yet shown
    bundle, _ = live._repr_mimebundle_()
    assert "image/png" in bundle  # the stored picture is the world before the run
    assert live.running and live.play_in_background() is None  # started once, on the first showing
    live._repr_mimebundle_()  # a second showing starts nothing more
    deadline = clock.time() + 120
    while live.frames < 3 and not live.finished and clock.time() < deadline:
        clock.sleep(0.05)  # no asyncio loop runs here: the thread moves the agents by itself
    live.stop()
    while live.running and clock.time() < deadline:
        clock.sleep(0.05)
    assert live.frames >= 3 or live.finished
    assert not live.running


def test_the_robust_dashboard_says_what_its_pictures_show():
    dashboard = robust_dashboard()  # Tutorial 2's section 9 at its stored settings
    data = demos.compute_robust()
    assert data["rmse"]["robust"] < data["rmse"]["gp"] / 5 and data["rmse"]["robust"] < data["rmse"]["tp"] / 5
    flagged = int((data["weights"] < 0.1).sum())
    assert flagged == int(data["outliers"].sum()) == 4 and data["weights"][data["outliers"]].max() < 0.04
    assert f"{flagged} of 40 points pull with less than a tenth" in dashboard.info.value
    assert f"Student-t likelihood {data['rmse']['robust']:.2f}" in dashboard.info.value
    dashboard.controls["nu"].value = 50.0  # a thin tail: nothing discounted, the mean drifts to the outliers
    thin = demos.compute_robust(nu=50.0)
    assert (thin["weights"] < 0.1).sum() == 0 and thin["rmse"]["robust"] > 2 * data["rmse"]["robust"]
    assert "0 of 40 points" in dashboard.info.value


def test_a_slider_moved_by_steps_gives_the_number_it_shows():
    """40 + 1.0 steps and 0.1 + 0.2 reach 41.00000000000001 and 0.30000000000000004: shown and used as 41, 0.3."""
    from sarsp_edu import ExperimentConfig
    from sarsp_edu.teaching.dashboards.tutorials import agent_dashboard

    dashboard = agent_dashboard(episodes=1, n_switch_states=1, config=ExperimentConfig(**SMALL), fit_ahead=False)
    dashboard.controls["proportion"].value = 0.1 + 0.2
    assert dashboard.config().outlier_proportion == 0.3
    assert dashboard.status.value.startswith("p = 0.3: ")
    dashboard.controls["magnitude"].value = 40 + 0.1 * 10
    assert "41.00000000000001" not in dashboard.status.value and dashboard.config().outlier_magnitude == 41.0


def test_each_side_picks_its_model_and_a_pick_stops_the_run_and_fits_the_new_one():
    from sarsp_edu.teaching.live.pick import MODEL_TITLES

    live = agent_dashboard(episodes=2, n_switch_states=1, config=ExperimentConfig(**SMALL), fit_ahead=False)
    assert [picker.value for picker in live.model_pickers.values()] == ["tp", "gp"]
    live.run_steps(2)
    assert live.experiments is not None
    live.model_pickers["tp"].value = "t-likelihood"  # the left side now runs the GP with Student-t noise
    assert live.experiments is None and "next <b>Run</b>" in live.status.value
    assert live.sides["tp"] == (MODEL_TITLES["t-likelihood"], {"model": "t-likelihood"})
    assert MODEL_TITLES["t-likelihood"] in live.headers["tp"].value
    live.run_steps(3)
    assert live.experiments["tp"].config.model == "t-likelihood" and live.experiments["gp"].config.model == "gp"
    assert live._legend_labels() == {"tp": MODEL_TITLES["t-likelihood"], "gp": MODEL_TITLES["gp"]}
    with pytest.raises(ValueError, match="model must be one of"):
        live.pick_model("gp", "svm")
    live.close()
