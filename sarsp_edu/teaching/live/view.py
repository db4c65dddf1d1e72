"""The live dashboard itself: its sliders, the world they imply, the two sides' pictures and numbers."""

from __future__ import annotations

import html
import time

import ipywidgets as widgets
from matplotlib.figure import Figure

from ...config import NU, DataSettings
from ..dashboards.framework import (
    control_row,
    fixed_layout_axes,
    slider,
)
from ..dashboards.projector import PROJECTOR_TEXT_PX, ProjectorMixin
from . import markup
from .background import slider_config
from .controller import LiveRun
from .pick import TP_AND_GP, model_pickers, picked_side
from .presence import PagePresence
from .snapshot import (
    AUTOPLAY_VARIABLE,
    LIVE_METRICS,
    SNAPSHOT_VARIABLE,
    LiveMetrics,
    StaticPicture,
    first_episode,
    key_numbers,
)

__all__ = ["AUTOPLAY_VARIABLE", "SNAPSHOT_VARIABLE", "TP_AND_GP", "AgentDashboard", "agent_dashboard"]


#: a grid cell's side in the live grids, px: both grids and their key numbers side by side in JupyterLab's
#: notebook at 1280 px with the file browser open (about 850 px), in projector size
_CELL = 22


def _of_the_run(name: str, doc: str) -> property:
    """A read-only attribute of the dashboard that is its run's (:class:`LiveRun`)."""
    return property(lambda self: getattr(self.run, name), doc=doc)


class AgentDashboard(LiveMetrics, StaticPicture, ProjectorMixin, widgets.VBox):
    """Two agents running paired on one world, side by side, live: by default the TP agent and the GP agent.

    Sliders for nu, m, p, nss, the seed and the number of episodes: a move
    redraws at once the world they imply (the shift, and how many rows are
    outliers), and the runs on it are prepared in the background so that
    *Run* starts them at once; *Run* animates both agents step by step,
    *Stop* pauses, *Fast-forward* runs whole episodes without drawing each
    step (episode by episode, with progress), *New run* starts again from the
    sliders.  Each side shows the world after the shift (moved states
    outlined), the agent's path in the current episode, the moves it has
    learned are unsafe (``S_u``, red ticks) and its key numbers; below them
    Algorithm 1's view of the current decision, and the paper's running
    metrics of both agents, growing episode by episode.

    The dashboard is a view of a :class:`~sarsp_edu.teaching.live.controller.LiveRun`
    (``dashboard.run``), which runs the agents with no widgets in one thread
    of its own, the only one that steps them or draws them: the buttons and
    sliders send it commands, taken between two steps; when a corrective
    update makes one agent refit its cost model (a second or more), that
    side says so while both wait.  ``run_steps`` and ``fast_forward`` do the
    same work synchronously, for scripts and tests (refused while the agents
    are animated).

    Parameters
    ----------
    nu, magnitude, proportion, n_switch_states, seed, episodes : initial slider values
    steps_per_second : float, default 30
        Animation speed per side (a slider); the displayed rate is
        ``displayed_steps_per_second``.
    config : ExperimentConfig, optional
        Other settings (grid size, k_prior, ...); the sliders override theirs.
    sides : dict, optional
        Name -> (title, the settings that side changes), two of them; default
        ``TP_AND_GP``.  The sides share the world, the data and the episodes,
        so they may change only the model and the agent's settings
        (:func:`~sarsp_edu.experiments.experiment.experiments_on_one_world`).
    fit_ahead : bool, default True
        Fit the runs of the sliders' settings in the background as soon as
        they are set, so that *Run* need not wait for the fits.
    projector : bool, optional
        Projector size (see :func:`sarsp_edu.teaching.dashboards.projector.projector`); default
        :func:`~sarsp_edu.teaching.dashboards.projector.projector_default`.
    autoplay : bool, default False
        Start the agents when the dashboard is first shown, in a thread of their own (``play_in_background``): they then
        move while the notebook runs its later cells, where a click on *Run* waits for the kernel to finish them.
        ``SARSP_EDU_AUTOPLAY=0`` in the environment keeps it off (batch runs of the notebooks, where nobody watches).
    parts : dict, optional
        Side name -> the functions its agent decides with (:class:`~sarsp_edu.agent.parts.DecisionParts`, or a mapping
        of some of them): Tutorial 7's "your agent" beside the package's, on the same world.  The fits do not use them,
        so each side is fitted (or loaded) as any other and given its parts before its first step.
    """

    def __init__(self, nu=NU, magnitude=DataSettings.outlier_magnitude, proportion=DataSettings.outlier_proportion,
                 n_switch_states=2, seed=0, episodes=30,
                 steps_per_second=30.0, config=None, sides=None, fit_ahead: bool = True,
                 projector: bool | None = None, autoplay: bool = False, parts=None):
        from ...config import ExperimentConfig
        from ...world.preparation import PREPARATION_FIELDS

        self.base_config = ExperimentConfig() if config is None else config
        self.sides = dict(TP_AND_GP if sides is None else sides)
        if len(self.sides) != 2 or not all(isinstance(v, tuple) and len(v) == 2 for v in self.sides.values()):
            raise ValueError(f"sides must map two names to (title, changed settings), got sides={sides!r}")
        for title, changes in self.sides.values():
            wrong = sorted(set(changes) & set(PREPARATION_FIELDS))
            if wrong:
                raise ValueError(f"sides may change only the model and the agent's settings, got {wrong} "
                                 f"in {title!r}; those shape the world: set them in config")
            self.base_config.replace(**changes)  # refused now, not at the first Run
        from ...agent.parts import DecisionParts

        unknown = sorted(set(parts or {}) - set(self.sides))
        if unknown:
            raise ValueError(f"parts names sides {unknown}, but the sides are {sorted(self.sides)}")
        self.parts = {name: DecisionParts.of(value) for name, value in (parts or {}).items()}
        self.fit_ahead = bool(fit_ahead)
        self.controls = {
            "nu": slider("float", "nu", "ν", nu, 2.1, 30.0, 0.1),
            "magnitude": slider("float", "magnitude", "m", magnitude, 1.0, 100.0, 1.0),
            "proportion": slider("float", "proportion", "p", proportion, 0.0, 0.5, 0.05),
            "n_switch_states": slider("int", "n_switch_states", "nss", n_switch_states, 0,
                                       self.base_config.n_unsafe, 1),
            "seed": slider("int", "seed", "seed", seed, 0, 100, 1),
            "episodes": slider("int", "episodes", "episodes", episodes, 1, 250, 1),
        }
        self.speed = slider("float", "steps_per_second", "steps per second", steps_per_second, 1.0, 60.0, 1.0,
                             expensive=False)
        self.buttons = {
            "run": widgets.Button(description="Run", icon="play", button_style="success"),
            "stop": widgets.Button(description="Stop", icon="stop", button_style="warning"),
            "forward": widgets.Button(description="Fast-forward 10 episodes", icon="forward",
                                      layout=widgets.Layout(width="auto")),
            "new": widgets.Button(description="New run", icon="refresh"),
        }
        self.buttons["run"].on_click(lambda _: self.start())
        self.buttons["stop"].on_click(lambda _: self.stop())
        self.buttons["forward"].on_click(lambda _: self.start(episodes=10))
        self.buttons["new"].on_click(lambda _: self.reset())
        self.status = widgets.HTML("Press <b>Run</b> to start both agents.")
        # one line of fixed height: a side's "fitting ..." or "retraining ..." never moves its grid
        # at least two lines high (a side's title and its phase), more where a narrow screen wraps them: never cut
        self.headers = {name: widgets.HTML(layout=widgets.Layout(min_height="54px", width="100%"))
                        for name in self.sides}
        self.worlds = {name: widgets.HTML(layout=widgets.Layout(flex="0 1 auto", min_width="0", max_width="100%"))
                       for name in self.sides}
        self.decisions = {name: widgets.HTML() for name in self.sides}
        # beside the grid where there is room for it, under it on a narrow screen
        self.summaries = {name: widgets.HTML(layout=widgets.Layout(flex="1 1 150px", min_width="150px"))
                          for name in self.sides}
        # A fixed layout and plain-text titles: constrained layout and mathtext
        # would cost several times the whole agent step at each redraw.
        self.metrics_figure = Figure(figsize=(14, 2.5))
        self.metrics_axes = fixed_layout_axes(self.metrics_figure, ncols=len(LIVE_METRICS))
        # SVG: the browser draws the text, sharp at any size
        # hidden until first drawn: an empty image shows as a broken one
        # an SVG with its alt text, as wide as the dashboard less its margins ("auto" in a column)
        self.metrics_image = widgets.HTML(layout=widgets.Layout(width="auto", display="none"))
        pictures, tables = [], []
        for name in self.sides:
            pictures.append(widgets.VBox(
                [self.headers[name], widgets.HBox([self.worlds[name], self.summaries[name]],
                                                  layout=widgets.Layout(align_items="flex-start",
                                                                        flex_flow="row wrap"))],
                layout=widgets.Layout(width="50%", min_width="0")))
            # side by side where they fit, one under the other on a narrow screen
            tables.append(widgets.VBox([self.decisions[name]], layout=widgets.Layout(flex="1 1 340px", min_width="0")))
        self.settings_rows = [
            control_row([self.controls[k] for k in ("nu", "magnitude", "proportion", "n_switch_states")]),
            control_row([*self.buttons.values(), *(self.controls[k] for k in ("seed", "episodes")), self.speed]),
        ]
        self.model_pickers = model_pickers(self)  # each side's model, the TP against the GP unless picked
        if self.model_pickers:
            self.settings_rows.insert(1, control_row(list(self.model_pickers.values())))
        self.page = PagePresence()  # a run stops when the page that shows it has gone
        super().__init__(children=[
            *self.settings_rows,
            self.status,
            widgets.HBox(pictures, layout=widgets.Layout(width="100%")),  # the grids and key numbers: one screen
            widgets.HBox(tables, layout=widgets.Layout(width="100%", flex_flow="row wrap")),
            self.metrics_image,
            self.page.widget,  # hidden: the page's sign of life, once a second
        ])
        self._drawn_key = None
        self._metrics_drawn_at = -float("inf")
        self._offline = {}  # seed -> the offline world and its clean data (a slider move reuses them)
        #: the run itself, no widgets: this dashboard is its view
        self.run = LiveRun(self.sides, self.config, parts=self.parts, offline=self._offline, view=self,
                           steps_per_second=steps_per_second, page=self.page)
        self.speed.observe(lambda change: setattr(self.run, "steps_per_second", float(change["new"])), names="value")
        self.autoplay = bool(autoplay)
        self._autoplayed = False
        self.last_preview_seconds = float("nan")
        self._init_projector(projector, toggle_row=self.settings_rows[-1])
        self._size_metrics_figure()
        for control in self.controls.values():
            control.observe(self._on_setting, names="value")
        self.run.call(self.preview)
        self._fit_ahead()

    # -- configuration ------------------------------------------------------
    def config(self):
        """The settings the sliders imply (:func:`~sarsp_edu.teaching.live.background.slider_config`)."""
        values = {k: c.value for k, c in self.controls.items()}
        return slider_config(self.base_config, n_switch_states=values.pop("n_switch_states"), **values)

    @property
    def _text_px(self) -> int:
        return PROJECTOR_TEXT_PX if self.projector else 13

    def _header(self, name, note: str = "") -> str:
        """A side's title, and under it ``note`` (HTML): what the side waits for; each one line, cut short with an
        ellipsis if too long, in a box of fixed height, so that nothing below moves."""
        line = "white-space:nowrap;overflow:hidden;text-overflow:ellipsis"
        return (f"<div style='{line}'><b>{html.escape(self.sides[name][0])}</b></div>"
                f"<div style='{line}'><small>{note or '&nbsp;'}</small></div>")

    def _small(self, text: str) -> str:
        return f"<small>{text}</small>"  # a size below the dashboard's text, whichever size that is

    def preview(self) -> None:
        """Draw on both sides the world the sliders imply, before any run: the shift, and the outliers' count.

        A slider move calls it, so the picture follows the sliders at once
        (the offline world of a seed is computed once and reused); the
        models are fitted in the background (``fit_ahead``) or when
        **Run** starts the agents.
        """
        from ...world.preparation import offline_world, prepare

        start = time.perf_counter()
        config = self.config()
        if config.seed not in self._offline:
            self._offline[config.seed] = offline_world(config)
        prepared = prepare(config, offline=self._offline[config.seed])
        picture = markup.gridworld_svg(first_episode(prepared), title="the world after the shift", cell=_CELL,
                                       font_size=self._text_px)
        rows = len(prepared.data.cost)
        outliers = len(prepared.data.outlier_indices)
        note = self._small(
            f"nss = {config.n_switch_states}: {len(prepared.env.moved_indices)} unsafe states moved (outlined; "
            f"dashed: before).<br>Outliers: {outliers} of the cost model's {rows} rows, times "
            f"m = {config.outlier_magnitude:g}.")
        for name in self.sides:
            self.headers[name].value = self._header(name)
            self.worlds[name].value = picture
            self.decisions[name].value = ""
            self.summaries[name].value = note
        self.last_preview_seconds = time.perf_counter() - start

    def _fit_ahead(self) -> None:
        if self.fit_ahead:
            self.run.request_fits()

    def _on_setting(self, change) -> None:
        """A slider moved: stop what runs, show the new world, prepare its runs, say the agents start on it at Run
        (in the run's thread, between two steps: the step under way ends first)."""
        self.run.call(self._new_settings, change)

    def _new_settings(self, change) -> None:
        interrupted = self.running or self.experiments is not None
        try:
            self._discard_run()
            self.preview()
        except ValueError as exc:  # a combination the world cannot hold: said, not raised
            self.status.value = f"<span style='color:#b00020'>{html.escape(str(exc))}</span>"
            return
        self._fit_ahead()
        self.status.value = ((f"{change['owner'].description} = {round(change['new'], 10):g}: " if change else "")
                             + "both agents start on this world at the next <b>Run</b>"
                             + (" (the run under way was stopped)." if interrupted else "."))

    def _discard_run(self) -> None:
        """Stop and forget the runs; fits still under way are discarded when they end."""
        self.run.discard()
        self._drawn_key = None
        self.metrics_image.value = ""
        self.metrics_image.layout.display = "none"

    def build_runs(self) -> None:
        """Build the paired runs of the sliders' settings now: fitted ahead, or waited for until fitted."""
        self.run.call(self._build_runs)

    def _build_runs(self) -> None:
        self.run.build()
        self._drawn_key = None

    # -- what the run does: the controller's, here for a cell's convenience -------------
    experiments = _of_the_run("experiments", "Side name -> its Experiment on show (None before a run).")
    running = _of_the_run("running", "Whether the agents are animated now (after Run or autoplay, until Stop or the "
                                     "last episode).")
    finished = _of_the_run("finished", "Whether both agents have run all their episodes.")
    frames = _of_the_run("frames", "Steps shown on both sides in the current animation.")
    longest_wait_seconds = _of_the_run("longest_wait_seconds", "Side name -> the longest time between two of its "
                                                               "steps shown, s.")
    displayed_steps_per_second = _of_the_run("displayed_steps_per_second", "Steps shown per second in the current "
                                             "animation, on the slower side (NaN before two frames).")

    def step_pair(self, draw: bool = True) -> None:
        """One step of each agent that has episodes left (:meth:`LiveRun.step_pair`)."""
        self.run.step_pair(draw=draw)

    def run_steps(self, n: int, draw: bool = True) -> None:
        """``n`` paired steps, synchronously (:meth:`LiveRun.run_steps`).

        Parameters
        ----------
        n : int
            Paired steps at most.
        draw : bool, default True
            Show each step.
        """
        self.run.run_steps(n, draw=draw)

    def fast_forward(self, episodes: int = 10) -> None:
        """Whole episodes of both agents, drawn once at the end (:meth:`LiveRun.fast_forward`)."""
        self.run.fast_forward(episodes)

    def start(self, episodes: int | None = None):
        """*Run* (or *Fast-forward* ``episodes`` episodes) without blocking the kernel.

        Returns an asyncio future done when the run ends (None if a run is
        under way already, which the status line then says).
        """
        import asyncio

        loop = asyncio.get_event_loop()
        done = loop.create_future()
        launched = self.run.launch(episodes, on_end=lambda: loop.call_soon_threadsafe(
            lambda: done.done() or done.set_result(None)))
        return None if launched is None else done  # None: the run's thread said why (already running)

    def play_in_background(self):
        """Animate in a thread of its own, the agents moving while the notebook runs other cells (*Run* waits
        for the kernel, which handles a click only between cells); ``autoplay=True`` calls it when the dashboard
        is first shown.  Returns the run's future (done when it ends), or None if a run is already under way."""
        return self.run.launch()

    def stop(self) -> None:
        """Pause: each agent ends the step it is in (*Run* continues)."""
        self.run.stop()

    def reset(self) -> None:
        """*New run*: forget the runs and start again from the sliders."""
        self.run.call(self._reset)

    def _reset(self) -> None:
        self._discard_run()
        self.preview()
        self._fit_ahead()
        self.status.value = "Press <b>Run</b> to start both agents."

    def close(self) -> None:
        """Stop the agents and the fits under way, and close the dashboard's widgets (it cannot be shown again)."""
        if hasattr(self, "run"):  # ipywidgets closes a widget when it is collected, even one half-built
            self.run.close()
        if hasattr(self, "page"):
            self.page.close()
        super().close()

    # -- the view's half of the controller -------------------------------------------------
    def say(self, text: str) -> None:
        """The status line (HTML)."""
        self.status.value = text

    def show_waiting(self, name, why: str) -> None:
        """The side's header line says why it waits (one line, cut short rather than wrapped: nothing moves).

        Parameters
        ----------
        name : str
        why : str
            Plain text (escaped here).
        """
        self.headers[name].value = self._header(name, f"<span style='color:#a04c00'>{html.escape(why)}</span>")

    def _resize_pictures(self) -> None:
        self.run.call(self._redraw)

    def _redraw(self) -> None:
        self._size_metrics_figure()
        if self.experiments is None:
            self.preview()
        else:
            self._drawn_key = None
            self.run._show_all()

    # -- drawing ------------------------------------------------------------
    def show_side(self, name) -> None:
        """Draw a side's run: its grid and path, its decision, its key numbers."""
        experiment = self.experiments[name]
        record = self.run.last[name]
        episode = len(experiment.episodes) + (0 if record is None or record.done else 1)
        self.headers[name].value = self._header(name)
        self.worlds[name].value = markup.gridworld_svg(
            experiment.env.layout(), cell=_CELL, trajectory=experiment.trajectory,
            unsafe_pairs=sorted(experiment.agent.unsafe_pairs),
            title=f"episode {episode} of {experiment.config.episodes}", font_size=self._text_px,
        )
        decision = None if record is None else record.decision
        self.decisions[name].value = markup.decision_table_html(
            decision, experiment.config.d, experiment.config.variance_threshold, font_size=self._text_px - 1)
        numbers = self.key_numbers(name)
        self.summaries[name].value = (
            f"<table style='font-size:{self._text_px - 2}px;border-collapse:collapse;margin:0 12px 0 6px'>"
            # a label wraps where the box is narrow (at 800 x 600); a value is never split
            + "".join(f"<tr><td style='padding:1px 8px 1px 0;overflow-wrap:anywhere'>"
                      f"{label.replace('S_u', 'S<sub>u</sub>')}</td>"
                      f"<td style='text-align:right;white-space:nowrap'>"
                      f"<b>{value}</b></td></tr>" for label, value in numbers)
            + "</table>")

    def key_numbers(self, name) -> tuple:
        """A side's key numbers, (label, value) pairs (:func:`~sarsp_edu.teaching.live.snapshot.key_numbers`)."""
        return key_numbers(self.experiments[name])

    def pick_model(self, name, model: str) -> None:
        """Side ``name`` runs ``model`` (a side's dropdown calls it): the run on show stops, the new one is fitted.

        Parameters
        ----------
        name : str
            A side of the dashboard.
        model : str
            One of :data:`~sarsp_edu.teaching.live.pick.MODEL_TITLES`.
        """
        picked_side(self.sides, name, model)
        self._on_setting(None)


def agent_dashboard(**kwargs) -> AgentDashboard:
    """The live TP-versus-GP dashboard of tutorial 4; see :class:`AgentDashboard` for the arguments."""
    return AgentDashboard(**kwargs)
