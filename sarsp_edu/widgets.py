"""Widget dashboards for the tutorials: sliders wired to ``compute_*`` and ``plot_*``.

Each ``*_dashboard()`` returns an ipywidgets box.  The computation lives in
pure functions (:mod:`sarsp_edu.tails`, :mod:`sarsp_edu.demos`) and the drawing
in :mod:`sarsp_edu.plotting`; this module only wires them.  Each picture
(a :class:`Panel`) is a small matplotlib ``Figure`` (no pyplot state)
rendered into an ``ipywidgets.Image`` as SVG, its text left to the browser
(sharp on a projector), so a slider move redraws it in place in JupyterLab,
Voila and a static notebook alike; a move redraws only the panels that
depend on the slider.  A
callback never raises: a value the models cannot handle shows a message
under the controls instead.
"""

from __future__ import annotations

import html
import io
import time
from dataclasses import dataclass
from typing import Callable

import ipywidgets as widgets
import matplotlib
import numpy as np
from matplotlib.figure import Figure
from matplotlib.transforms import ScaledTranslation

from . import demos, plotting, tails
from ._threads import one_blas_thread
from ._validation import check_choice, check_int, check_positive, check_range

__all__ = [
    "Dashboard",
    "Panel",
    "AgentDashboard",
    "tail_decay_dashboard",
    "posterior_dashboard",
    "gridworld_dashboard",
    "agent_dashboard",
]


@dataclass(frozen=True)
class Panel:
    """One picture of a dashboard: its own small figure, redrawn only when its inputs move.

    Attributes
    ----------
    draw : callable
        ``draw(ax, result, **values)``: draws the dashboard's computed
        ``result`` on ``ax`` (through the ``plot_*`` functions).
    width : float
        Figure width in inches (all panels of a dashboard share its height).
    inputs : tuple of str, optional
        The controls this picture depends on; a move of any other control
        leaves it as it is.  None means every control.
    margins : dict, optional
        ``left``, ``right``, ``bottom``, ``top`` in inches, for long labels or
        a legend outside the Axes.
    label_offsets : (float, float)
        Distance in points from the Axes to the x label (below) and to the
        y label (left), room for the tick labels the panel can show.  Fixed
        rather than measured at each redraw, which cost a tenth of it.
    """

    draw: Callable
    width: float
    inputs: tuple | None = None
    margins: dict | None = None
    label_offsets: tuple = (24.0, 42.0)

    def __post_init__(self):
        check_positive("width", self.width)

    def depends_on(self, changed) -> bool:
        return changed is None or self.inputs is None or bool(set(changed) & set(self.inputs))


class Dashboard(widgets.VBox):
    """Controls, a message line, a row of pictures and a text panel.

    A slider move calls ``compute(**values)`` once, then redraws only the
    panels whose ``inputs`` include the control that moved: matplotlib needs
    tens of milliseconds per picture whatever it shows, so a panel that
    cannot have changed is not drawn again.

    Parameters
    ----------
    controls : dict of widgets
        By name; their values are passed to ``compute`` and the panels.
    compute : callable
        ``compute(**values) -> (result, info_html)``: the numbers behind the
        pictures (through the package's ``compute_*`` functions).
    panels : list of Panel
    height : float
        Height of every panel, in inches.
    max_scale : float, default 1.5
        How far the pictures (vector graphics) may grow beyond their natural
        size (72 px per inch) to fill a wide page or a projector.
    layout_rows : list of widgets, optional
        How to arrange the controls (default: one row).

    Attributes
    ----------
    controls : dict of widgets
        By name (``"nu"``, ``"lam"``, ...), for code and tests to drive.
    figures : list of matplotlib.figure.Figure
    axes : list of Axes
        One per panel.
    images : list of ipywidgets.Image
        The rendered panels (SVG).
    result : object
        What ``compute`` returned for the values on show.
    info : ipywidgets.HTMLMath
        Numbers and formulas under the pictures.
    message : ipywidgets.HTML
        Empty, or why the last update could not be drawn.
    last_update_seconds : float
        Compute and redraw time of the last update.
    last_redrawn : list of int
        The panels the last update redrew.
    """

    def __init__(self, controls: dict, compute, panels, *, height: float, max_scale: float = 1.5,
                 layout_rows=None):
        self.controls = controls
        self.panels = list(panels)
        if not self.panels:
            raise ValueError("panels must hold at least one Panel, got panels=[]")
        height = check_positive("height", height)
        max_scale = check_positive("max_scale", max_scale)
        for panel in self.panels:
            for name in panel.inputs or ():
                check_choice("Panel inputs", name, list(controls))
        self._compute = compute
        self._names = {id(control): name for name, control in controls.items()}
        self.figures, self.axes, self.images = [], [], []
        total = sum(panel.width for panel in self.panels)
        for panel in self.panels:
            figure = Figure(figsize=(panel.width, height))
            # Fixed margins rather than constrained layout: the layout engine
            # draws the figure twice.
            inches = {"left": 0.75, "right": 0.15, "bottom": 0.55, "top": 0.35, **(panel.margins or {})}
            figure.subplots_adjust(left=inches["left"] / panel.width, right=1 - inches["right"] / panel.width,
                                   bottom=inches["bottom"] / height, top=1 - inches["top"] / height)
            self.figures.append(figure)
            self.axes.extend(_fixed_layout_axes(figure, panel.label_offsets))
            self.images.append(widgets.Image(format="svg+xml", layout=widgets.Layout(
                width=f"{100 * panel.width / total:.3f}%", max_width=f"{panel.width * 72 * max_scale:.0f}px")))
        self.info = widgets.HTMLMath()
        self.message = widgets.HTML()
        self.result = None
        self.last_update_seconds = float("nan")
        self.last_redrawn: list[int] = []
        self._stale = True
        self._used = [False] * len(self.panels)
        rows = layout_rows or [widgets.HBox(list(controls.values()))]
        pictures = widgets.HBox(self.images, layout=widgets.Layout(width="100%",
                                                                   max_width=f"{total * 72 * max_scale:.0f}px"))
        super().__init__(children=[*rows, self.message, pictures, self.info])
        for control in controls.values():
            control.observe(self._on_change, names="value")
        self.refresh()

    def _on_change(self, change):
        self.refresh(changed=(self._names[id(change["owner"])],))

    def values(self) -> dict:
        return {name: control.value for name, control in self.controls.items()}

    def refresh(self, changed=None) -> bool:
        """Recompute and redraw the panels that depend on ``changed`` (default: all).

        Returns False, and shows why under the controls, if the values could
        not be computed or drawn; the last good pictures then stay.
        """
        start = time.perf_counter()
        self.last_redrawn = []
        if self._stale:  # the last update failed part-way: every panel may be out of date
            changed = None
        values = self.values()
        try:
            with one_blas_thread():
                result, info = self._compute(**values)
            for i, panel in enumerate(self.panels):
                if panel.depends_on(changed):
                    if self._used[i]:  # a brand-new Axes is drawn on as it is
                        _wipe(self.axes[i])
                    self._used[i] = True
                    panel.draw(self.axes[i], result, **values)
                    self.images[i].value = _render(self.figures[i], "svg")
                    self.last_redrawn.append(i)
            self.result = result
            self.info.value = info or ""
            self.message.value = ""
            self._stale = False
            ok = True
        except Exception as exc:  # a dashboard must not crash on an extreme slider value
            self.message.value = (
                "<span style='color:#b00020'>Could not draw these values: "
                f"{html.escape(type(exc).__name__)}: {html.escape(str(exc))}</span>"
            )
            self._stale = True
            ok = False
        self.last_update_seconds = time.perf_counter() - start
        return ok


def _wipe(ax) -> None:
    """Empty an Axes for the next redraw, keeping its tick objects.

    ``Axes.clear()`` throws away every tick, and building them again was a
    third of a slider move.  A dashboard draws the same kind of plot on the
    same Axes at every move, so the styling of the axis (tick parameters,
    grid) can stay; everything that depends on the data goes: the artists,
    the legend, the texts, the limits (autoscaling is switched back on), the
    scales, the fixed tick positions and the colour cycle.  The test suite
    checks that a redrawn panel is byte for byte the SVG that a new,
    never-wiped Axes gives at the same slider values (a dashboard draws its
    first pictures on new Axes).
    """
    for artist in [*ax.lines, *ax.collections, *ax.patches, *ax.texts, *ax.images, *ax.artists]:
        artist.remove()
    if ax.get_legend() is not None:
        ax.get_legend().remove()
    ax.set_title("")
    ax.set_xlabel("")
    ax.set_ylabel("")
    ax.set_xscale("linear")  # also restores the default locators and formatters
    ax.set_yscale("linear")
    ax.set_aspect("auto")
    ax.set_prop_cycle(None)
    ax.set_xlim(0, 1)  # a fresh Axes' limits, kept if the next picture adds no data
    ax.set_ylim(0, 1)
    ax.relim()
    ax.set_autoscale_on(True)


def _fixed_layout_axes(figure: Figure, label_offsets=None, ncols: int = 1) -> list:
    """One row of Axes in the figure's margins, with titles and labels at fixed places.

    By default matplotlib measures every tick label at each draw, to decide
    whether the title must move up and where the axis labels go: a fifth of
    a redraw.  These figures have nothing above their Axes, and the label
    distances (points, x then y) are given, so nothing needs measuring.
    """
    with matplotlib.rc_context({"axes.titley": 1.0}):
        axes = list(figure.subplots(1, ncols, squeeze=False)[0])
    if label_offsets is not None:
        below, left = label_offsets
        for ax in axes:
            ax.xaxis.set_label_coords(
                0.5, 0, transform=ax.transAxes + ScaledTranslation(0, -below / 72, figure.dpi_scale_trans))
            ax.yaxis.set_label_coords(
                0, 0.5, transform=ax.transAxes + ScaledTranslation(-left / 72, 0, figure.dpi_scale_trans))
    return axes


def _render(figure: Figure, fmt: str, dpi: int = 72) -> bytes:
    """The figure as PNG bytes, or as SVG with its text kept as text (drawn by the browser).

    In an SVG, ``dpi`` applies only to the rasterized artists (images, dense
    scatter plots), which are drawn at twice the natural resolution so that
    they stay sharp when the picture is enlarged.
    """
    buffer = io.BytesIO()
    if fmt == "svg":
        # No date and fixed element ids: the same figure gives the same bytes.
        with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "sarsp_edu"}):
            figure.savefig(buffer, format="svg", dpi=2 * dpi, metadata={"Date": None})
    else:
        figure.savefig(buffer, format=fmt, dpi=dpi)
    return buffer.getvalue()


def _slider(kind, name, description, value, lo, hi, step, expensive=True, **kwargs):
    """A slider for the argument ``name``; a value outside the slider's range is an error, not clamped."""
    if kind == "int":
        check_int(name, value, lo, hi)
    else:
        check_range(name, value, lo, hi, "the slider's range")
    cls = widgets.FloatSlider if kind == "float" else widgets.IntSlider
    return cls(value=value, min=lo, max=hi, step=step, description=description,
               continuous_update=not expensive, style={"description_width": "initial"},
               layout=widgets.Layout(width="260px"), **kwargs)


# --------------------------------------------------------------------------
# tutorial 1: tail decay
# --------------------------------------------------------------------------
_T_LIMIT = None  # lambda**(-nu - 1), derived once by sympy


def _student_t_limit_expr():
    global _T_LIMIT
    if _T_LIMIT is None:
        _T_LIMIT = tails.student_t_tail_limit()
    return _T_LIMIT


def tail_decay_dashboard(nu: float = 3.0, lam: float = 5.0) -> Dashboard:
    """Sliders for nu and lambda: the densities, their tails, and the Karamata ratio's limit.

    The limit shown is derived by sympy (``tails.student_t_tail_limit``)
    and evaluated at the slider values.
    """
    import sympy as sp

    controls = {
        "nu": _slider("float", "nu", "ν (degrees of freedom)", nu, 0.5, 30.0, 0.5, expensive=False),
        "lam": _slider("float", "lam", "λ", lam, 1.5, 10.0, 0.5, expensive=False),
    }

    def compute(nu, lam):
        densities = tails.compute_densities(nu)
        x = np.linspace(0.0, 20.0, 400)  # both ratios on one axis
        ratios = tails.compute_tail_ratios((nu,), lam, x_t=x, x_gauss=x)
        expr = _student_t_limit_expr()
        value = float(expr.subs({tails.LAMBDA: lam, tails.NU: nu}))
        info = (
            f"Student-t (sympy): $\\lim_{{x\\to\\infty}} f(\\lambda x)/f(x) = {sp.latex(expr)}"
            f" = {lam:g}^{{{-1 - nu:g}}} = {value:.4g}$, regularly varying with index $-1-\\nu = {-1 - nu:g}$."
            f"<br>Gaussian: $f(\\lambda x)/f(x) = e^{{(1-\\lambda^2)x^2/2}} \\to 0$ for $\\lambda > 1$:"
            " no power of $\\lambda$, so not regularly varying; its tail is lighter than any Student-t's."
        )
        return {"densities": densities, "ratios": ratios}, info

    def draw_ratios(ax, result, nu, lam):
        ratios = result["ratios"]
        plotting.plot_tail_ratios(ax, ratios, title="Karamata ratio f(λx)/f(x)")
        ax.plot(ratios["x_gauss"], ratios["gaussian"], color=plotting.COLOURS["gp"], lw=2, ls=":", label="Gaussian")
        plotting.log_scale(ax)
        ax.set_ylim(max(ratios["limits"][nu] / 100, 1e-30), 1.5)
        ax.legend(fontsize=8, frameon=False)

    panels = [
        Panel(lambda ax, result, **_: plotting.plot_densities(ax, result["densities"]), 4.3, inputs=("nu",),
              label_offsets=(24, 34)),
        Panel(lambda ax, result, **_: plotting.plot_densities(ax, result["densities"], log=True), 4.3,
              inputs=("nu",), label_offsets=(24, 40)),
        Panel(draw_ratios, 4.4, inputs=("nu", "lam"), label_offsets=(24, 40)),
    ]
    return Dashboard(controls, compute, panels, height=3.8)


# --------------------------------------------------------------------------
# tutorial 2: GP and TP under outliers
# --------------------------------------------------------------------------
def posterior_dashboard(nu: float = 3.0, magnitude: float = 10.0, proportion: float = 0.1, seed: int = 0,
                        fit: bool = True) -> Dashboard:
    """GP and TP fitted side by side on 1-D data with outliers; sliders for nu, m, p and the seed.

    Shows the posterior mean and 2-sigma band, both variances on one axis
    (paper eq. 5 against eq. 6), marks the outliers, and prints
    the TP's variance factor (nu + beta - 2)/(nu + n - 2) (paper eq. 6 in
    its correct form) and both models' hyperparameters.
    """
    controls = {
        "nu": _slider("float", "nu", "ν", nu, 2.1, 50.0, 0.1),
        "magnitude": _slider("float", "magnitude", "outlier magnitude m", magnitude, 1.0, 100.0, 1.0),
        "proportion": _slider("float", "proportion", "outlier proportion p", proportion, 0.0, 0.5, 0.05),
        "seed": _slider("int", "seed", "seed", seed, 0, 20, 1),
        "fit": widgets.Checkbox(value=fit, description="fit hyperparameters (50 Adam steps)", indent=False),
        "scale_inputs": widgets.Checkbox(value=False, description="scale the outliers' inputs too (paper 5.3)",
                                         indent=False),
    }
    rows = [widgets.HBox([controls[k] for k in ("nu", "magnitude", "proportion", "seed")]),
            widgets.HBox([controls["fit"], controls["scale_inputs"]])]

    def compute(nu, magnitude, proportion, seed, fit, scale_inputs):
        data = demos.compute_posteriors(nu, magnitude, proportion, seed, fit=fit, scale_inputs=scale_inputs)
        rows = []
        for name in ("gp", "tp"):
            post = data[name]
            rows.append(f"{name.upper()}: amplitude {post['kernel'].amplitude:.3g}, length scale "
                        f"{post['kernel'].length_scale:.3g}, noise variance {post['noise_variance']:.3g}, "
                        f"log marginal likelihood {post['log_marginal_likelihood']:.2f}")
        factor = (f"TP variance factor $\\frac{{\\nu + \\beta - 2}}{{\\nu + n - 2}} = "
                  f"\\frac{{{data['nu']:g} + {data['beta']:.4g} - 2}}{{{data['nu']:g} + {data['n']} - 2}} = "
                  f"{data['tp_scale']:.4g}$, with $\\beta = y^T (K + \\sigma^2 I)^{{-1}} y$")
        return data, "<br>".join([factor, *rows])

    def draw_posterior(model):
        def draw(ax, data, **_):
            inlier_y = data["y"][~data["outliers"]]
            span = max(float(abs(inlier_y).max()), 1.0)
            plotting.plot_posterior(ax, data, model, ylim=(-3 * span, 3 * span))
        return draw

    # The GP does not depend on nu: moving nu redraws the TP and the variances only.
    gp_inputs = ("magnitude", "proportion", "seed", "fit", "scale_inputs")
    panels = [
        Panel(draw_posterior("gp"), 5.0, inputs=gp_inputs, margins={"left": 0.6}, label_offsets=(24, 30)),
        Panel(draw_posterior("tp"), 5.0, margins={"left": 0.6}, label_offsets=(24, 30)),
        Panel(lambda ax, data, **_: plotting.plot_variances(ax, data), 5.0, label_offsets=(24, 38)),
    ]
    return Dashboard(controls, compute, panels, height=4.2, layout_rows=rows)


# --------------------------------------------------------------------------
# tutorial 3: the world and its shift
# --------------------------------------------------------------------------
def gridworld_dashboard(seed: int = 0, n_switch_states: int = 6, magnitude: float = 40.0,
                        proportion: float = 0.2) -> Dashboard:
    """The world before and after the covariate shift, the offline coverage and the outliers.

    Sliders for nss, the seed, m and p.  The world and its 100 offline
    episodes are cached per seed, so the nss, m and p sliders are quick.
    """
    controls = {
        "seed": _slider("int", "seed", "seed", seed, 0, 50, 1),
        "n_switch_states": _slider("int", "n_switch_states", "nss (switch states)", n_switch_states, 0, 15, 1),
        "magnitude": _slider("float", "magnitude", "outlier magnitude m", magnitude, 1.0, 100.0, 1.0),
        "proportion": _slider("float", "proportion", "outlier proportion p", proportion, 0.0, 0.5, 0.05),
    }

    def compute(seed, n_switch_states, magnitude, proportion):
        world = demos.compute_world(seed, n_switch_states, magnitude, proportion)
        info = (f"{world['transitions']} random-policy transitions kept as {world['cost_rows']} cost-model "
                f"rows (at most 12 copies of an input) and {world['reward_rows']} reward-model rows (1 copy); "
                f"{len(world['outlier_rows'])} rows (p = {proportion:g}) had inputs and targets multiplied "
                f"by m = {magnitude:g}. States moved by the shift: {len(world['moved'])}.")
        return world, info

    panels = [
        Panel(lambda ax, world, **_: plotting.plot_gridworld(
            ax, world["before"], visits=world["visits"], legend=False, title="offline world and its coverage"),
            4.0, inputs=("seed",), margins={"left": 0.5, "right": 0.2}, label_offsets=(16, 16)),
        Panel(lambda ax, world, n_switch_states, **_: plotting.plot_gridworld(
            ax, world["after"], title=f"after the shift, nss = {n_switch_states}"),
            5.6, inputs=("seed", "n_switch_states"), margins={"left": 0.5, "right": 1.8}, label_offsets=(16, 16)),
        Panel(lambda ax, world, **_: plotting.plot_outlier_scatter(
            ax, world, title="cost-model data, outliers in red"),
            5.0, inputs=("seed", "magnitude", "proportion"), margins={"left": 0.7}, label_offsets=(24, 30)),
    ]
    return Dashboard(controls, compute, panels, height=4.4)


# --------------------------------------------------------------------------
# tutorial 4: the agent, live
# --------------------------------------------------------------------------
_LIVE_METRICS = ("mean_reward", "total_cost", "task_success_rate", "mean_steps", "cost_rate")


class AgentDashboard(widgets.VBox):
    """The TP agent and the GP agent running paired, side by side, live.

    Sliders for nu, m, p, nss, the seed and the number of episodes; *Run*
    animates both agents step by step, *Stop* pauses, *Fast-forward* runs
    whole episodes without drawing each step, *New run* starts again from
    the sliders.  Each side shows the world after the shift (moved states
    outlined), the agent's path in the current episode, the moves it has
    learned are unsafe (``S_u``, red ticks) and Algorithm 1's view of the
    current decision; under them, the paper's running metrics of both agents
    grow episode by episode.

    The run loop is an asyncio task, so the notebook stays responsive while
    it runs; the preparation (offline data, outliers, fits) runs in a worker
    thread.  ``run_steps`` and ``fast_forward`` do the same work
    synchronously, for scripts and tests.

    Parameters
    ----------
    nu, magnitude, proportion, n_switch_states, seed, episodes : initial slider values
    steps_per_second : float, default 30
        Animation speed (a slider); the displayed rate is
        ``displayed_steps_per_second``.
    config : ExperimentConfig, optional
        Other settings (grid size, k_prior, ...); the sliders override theirs.
    """

    def __init__(self, nu=3.0, magnitude=40.0, proportion=0.2, n_switch_states=2, seed=0, episodes=30,
                 steps_per_second=30.0, config=None):
        from .config import ExperimentConfig

        self.base_config = ExperimentConfig() if config is None else config
        self.controls = {
            "nu": _slider("float", "nu", "ν", nu, 2.1, 30.0, 0.1),
            "magnitude": _slider("float", "magnitude", "m", magnitude, 1.0, 100.0, 1.0),
            "proportion": _slider("float", "proportion", "p", proportion, 0.0, 0.5, 0.05),
            "n_switch_states": _slider("int", "n_switch_states", "nss", n_switch_states, 0,
                                       self.base_config.n_unsafe, 1),
            "seed": _slider("int", "seed", "seed", seed, 0, 100, 1),
            "episodes": _slider("int", "episodes", "episodes", episodes, 1, 250, 1),
        }
        self.speed = _slider("float", "steps_per_second", "steps per second", steps_per_second, 1.0, 60.0, 1.0,
                             expensive=False)
        self.buttons = {
            "run": widgets.Button(description="Run", icon="play", button_style="success"),
            "stop": widgets.Button(description="Stop", icon="stop", button_style="warning"),
            "forward": widgets.Button(description="Fast-forward 10 episodes", icon="forward",
                                      layout=widgets.Layout(width="210px")),
            "new": widgets.Button(description="New run", icon="refresh"),
        }
        self.buttons["run"].on_click(lambda _: self.start())
        self.buttons["stop"].on_click(lambda _: self.stop())
        self.buttons["forward"].on_click(lambda _: self.start(episodes=10))
        self.buttons["new"].on_click(lambda _: self.reset())
        self.status = widgets.HTML("Press <b>Run</b> to prepare the data, fit both models and start.")
        self.worlds = {m: widgets.HTML() for m in ("tp", "gp")}
        self.decisions = {m: widgets.HTML() for m in ("tp", "gp")}
        self.summaries = {m: widgets.HTML() for m in ("tp", "gp")}
        # A fixed layout and plain-text titles: constrained layout and mathtext
        # would cost several times the whole agent step at each redraw.
        self.metrics_figure = Figure(figsize=(14, 2.5))
        self.metrics_figure.subplots_adjust(left=0.04, right=0.99, bottom=0.2, top=0.86, wspace=0.28)
        self.metrics_axes = _fixed_layout_axes(self.metrics_figure, ncols=len(_LIVE_METRICS))
        self.metrics_image = widgets.Image(format="png", layout=widgets.Layout(width="100%"))
        sides = []
        for model, label in (("tp", "Student-t process"), ("gp", "Gaussian process")):
            sides.append(widgets.VBox([widgets.HTML(f"<b>{label}</b>"), self.worlds[model],
                                       self.decisions[model], self.summaries[model]],
                                      layout=widgets.Layout(width="50%")))
        super().__init__(children=[
            widgets.HBox([self.controls[k] for k in ("nu", "magnitude", "proportion")]),
            widgets.HBox([self.controls[k] for k in ("n_switch_states", "seed", "episodes")]),
            widgets.HBox([*self.buttons.values(), self.speed]),
            self.status,
            widgets.HBox(sides),
            self.metrics_image,
        ])
        self.experiments = None
        self._last = {"tp": None, "gp": None}
        self._task = None
        self._running = False
        self.frames = 0
        self._frame_times: list[float] = []
        self._drawn_episodes = -1
        self._metrics_drawn_at = -float("inf")
        self._draw_world()

    # -- configuration ------------------------------------------------------
    def config(self):
        values = {k: c.value for k, c in self.controls.items()}
        return self.base_config.replace(
            nu=float(values["nu"]), outlier_magnitude=float(values["magnitude"]),
            outlier_proportion=float(values["proportion"]), n_switch_states=int(values["n_switch_states"]),
            seed=int(values["seed"]), episodes=int(values["episodes"]),
        )

    def prepare(self):
        """Build the paired runs from the sliders (offline data, outliers, fits, shift)."""
        from .experiment import paired_experiments

        self.experiments = paired_experiments(self.config())
        self._last = {"tp": None, "gp": None}
        self._drawn_episodes = -1
        self.frames = 0
        self._frame_times = []

    @property
    def finished(self) -> bool:
        return self.experiments is not None and all(e.finished for e in self.experiments.values())

    # -- stepping -----------------------------------------------------------
    def step_pair(self, draw: bool = True) -> None:
        """One step of each agent that has episodes left."""
        if self.experiments is None:
            self.prepare()
        for model, experiment in self.experiments.items():
            if not experiment.finished:
                self._last[model] = experiment.step()
        if draw:
            self._draw_world()
            self._draw_metrics_if_new_episode(throttle=True)
            self.frames += 1
            self._frame_times.append(time.perf_counter())

    def run_steps(self, n: int, draw: bool = True) -> None:
        """``n`` paired steps, synchronously."""
        with one_blas_thread():
            for _ in range(n):
                if self.finished:
                    break
                self.step_pair(draw=draw)

    def fast_forward(self, episodes: int = 10) -> None:
        """Run whole episodes of both agents without drawing each step, synchronously."""
        if self.experiments is None:
            self.prepare()
        self._forward_quietly(episodes)
        self._draw_world()
        self._draw_metrics_if_new_episode()

    @property
    def displayed_steps_per_second(self) -> float:
        """Frames drawn per second over the current animation (NaN before two frames)."""
        times = self._frame_times
        if len(times) < 2 or times[-1] == times[0]:
            return float("nan")
        return (len(times) - 1) / (times[-1] - times[0])

    # -- asynchronous running (the buttons) ----------------------------------
    def start(self, episodes: int | None = None):
        """Start animating (or fast-forward ``episodes`` episodes) without blocking the kernel."""
        import asyncio

        if self._running:
            return None
        self._running = True
        self._task = asyncio.ensure_future(self._loop(episodes))
        return self._task

    def stop(self) -> None:
        self._running = False
        if self.experiments is not None:
            self.status.value = "Stopped. <b>Run</b> continues, <b>New run</b> starts again from the sliders."

    def reset(self) -> None:
        self.stop()
        self.experiments = None
        self._last = {"tp": None, "gp": None}
        self._draw_world()
        self.metrics_image.value = b""
        self.status.value = "Press <b>Run</b> to prepare the data, fit both models and start."

    async def _loop(self, episodes):
        import asyncio

        try:
            if self.experiments is None:
                self.status.value = "Preparing: 100 offline episodes, outliers, fitting both models ..."
                await asyncio.get_running_loop().run_in_executor(None, self.prepare)
            if episodes is not None:
                self.status.value = f"Fast-forwarding {episodes} episodes ..."
                await asyncio.get_running_loop().run_in_executor(None, self._forward_quietly, episodes)
                self._draw_world()
                self._draw_metrics_if_new_episode()
            else:
                self._frame_times = []
                self.status.value = "Running ..."
                with one_blas_thread():  # entered once for the whole animation, not per frame
                    await self._animate()
            self._draw_metrics_if_new_episode()
            if self.finished:
                self.status.value = "Finished every episode. <b>New run</b> starts again from the sliders."
            elif self._running:
                self.status.value = "Paused. <b>Run</b> continues."
        except Exception as exc:  # the dashboard reports, the kernel lives on
            self.status.value = f"<span style='color:#b00020'>Stopped by an error: {html.escape(str(exc))}</span>"
        finally:
            self._running = False

    async def _animate(self):
        import asyncio

        while self._running and not self.finished:
            start = time.perf_counter()
            self.step_pair(draw=True)
            if self.frames % 10 == 0:
                self.status.value = (f"Running: {self.frames} steps shown, "
                                     f"{self.displayed_steps_per_second:.1f} steps per second.")
            await asyncio.sleep(max(0.0, 1.0 / self.speed.value - (time.perf_counter() - start)))

    def _forward_quietly(self, episodes):
        with one_blas_thread():
            for experiment in self.experiments.values():
                target = min(len(experiment.episodes) + episodes, experiment.config.episodes)
                while len(experiment.episodes) < target:
                    experiment.run_episode()

    # -- drawing ------------------------------------------------------------
    def _draw_world(self) -> None:
        for model in ("tp", "gp"):
            if self.experiments is None:
                self.worlds[model].value = ""
                self.decisions[model].value = ""
                self.summaries[model].value = ""
                continue
            experiment = self.experiments[model]
            record = self._last[model]
            title = (f"episode {len(experiment.episodes) + (0 if record is None or record.done else 1)}"
                     f" of {experiment.config.episodes}")
            self.worlds[model].value = plotting.gridworld_svg(
                experiment.env.layout(), trajectory=experiment.trajectory,
                unsafe_pairs=sorted(experiment.agent.unsafe_pairs), title=title,
            )
            decision = None if record is None else record.decision
            self.decisions[model].value = plotting.decision_table_html(
                decision, experiment.config.d, experiment.config.variance_threshold)
            records = experiment.episodes
            violations = sum(e["episode_cost"] for e in records)
            done = sum(e["task_completed"] for e in records)
            self.summaries[model].value = (
                f"<span style='font-size:12px'>{len(records)} episodes done: {done} reached the goal, "
                f"{violations} violations, |S_u| = {len(experiment.agent.unsafe_pairs)}, "
                f"corrective updates {experiment.agent.corrective_updates}</span>")

    def _draw_metrics_if_new_episode(self, throttle: bool = False) -> None:
        """Redraw the metric curves if an episode ended; while animating, at most every 1.5 s."""
        if self.experiments is None:
            return
        count = sum(len(e.episodes) for e in self.experiments.values())
        if count == self._drawn_episodes:
            return
        now = time.perf_counter()
        if throttle and now - self._metrics_drawn_at < 1.5 and not self.finished:
            return
        self._drawn_episodes = count
        self._metrics_drawn_at = now
        for ax, metric in zip(self.metrics_axes, _LIVE_METRICS):
            _wipe(ax)
            for model in ("tp", "gp"):
                records = self.experiments[model].records()
                if len(records):
                    ax.plot(records["episode"], records[metric], color=plotting.COLOURS[model], lw=2,
                            marker="o" if len(records) < 15 else None, ms=3, label=model.upper())
            ax.set_title(metric.replace("_", " "), fontsize=10)
            ax.set_xlabel("episode", fontsize=9)
            ax.tick_params(labelsize=8)
            ax.grid(alpha=0.3)
        if self.metrics_axes[0].lines:
            self.metrics_axes[0].legend(fontsize=8, frameon=False)
        self.metrics_image.value = _render(self.metrics_figure, "png", 80)


def agent_dashboard(**kwargs) -> AgentDashboard:
    """The live TP-versus-GP dashboard of tutorial 4; see :class:`AgentDashboard` for the arguments."""
    return AgentDashboard(**kwargs)
