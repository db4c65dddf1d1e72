"""The live dashboard itself: its sliders, the world they imply, the two sides' pictures and numbers."""

from __future__ import annotations

import base64
import html
import os
import threading
import time

import ipywidgets as widgets
from matplotlib.figure import Figure

from ..._internal.threads import one_blas_thread
from ...config import NU, DataSettings
from .. import plotting
from ..dashboards.framework import (
    control_row,
    fixed_layout_axes,
    render_figure,
    slider,
    wipe_axes,
)
from ..dashboards.projector import PROJECTOR_SCALE, PROJECTOR_TEXT_PX, ProjectorMixin
from ..plotting.display import alt_metadata
from . import fitcache, markup
from .animation import Animation
from .background import Preparer, changed_settings, slider_config
from .snapshot import LIVE_METRICS, first_episode, picture, picture_alt_text

__all__ = ["AUTOPLAY_VARIABLE", "SNAPSHOT_VARIABLE", "TP_AND_GP", "AgentDashboard", "agent_dashboard"]


#: a grid cell's side in the live grids, px: both grids and their key numbers side by side in JupyterLab's
#: notebook at 1280 px with the file browser open (about 850 px), in projector size
_CELL = 22

#: tutorial 4's two sides: name -> (title, the settings that side changes)
TP_AND_GP = {
    "tp": ("Student-t process", {"model": "tp"}),
    "gp": ("Gaussian process", {"model": "gp"}),
}

#: the environment variable that, set to 0, keeps ``autoplay`` from starting: batch runs of the notebooks
#: (the test suite, ``sarsp-edu course``), where nobody watches and the agents would only compete for the cores
AUTOPLAY_VARIABLE = "SARSP_EDU_AUTOPLAY"
#: the environment variable that, set to N, makes a dashboard shown in a batch run fast-forward N episodes
#: before its picture is stored (``sarsp-edu course`` sets 10), so that a static copy shows the agents at work
SNAPSHOT_VARIABLE = "SARSP_EDU_SNAPSHOT_EPISODES"


class AgentDashboard(Animation, ProjectorMixin, widgets.VBox):
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

    Each side steps in its own worker thread: when a corrective update makes
    one agent refit its cost model (a second or more), that side says so
    and the other goes on.  ``run_steps`` and ``fast_forward`` do the same
    work synchronously and in step, for scripts and tests.

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
    prepare_ahead : bool, default True
        Prepare the runs of the sliders' settings in a worker thread as soon
        as they are set, so that *Run* need not wait for the fits.
    projector : bool, optional
        Projector size (see :func:`sarsp_edu.teaching.dashboards.projector.projector`); default
        :func:`~sarsp_edu.teaching.dashboards.projector.projector_default`.
    autoplay : bool, default False
        Start the agents when the dashboard is first shown, in a thread of
        their own (``play_in_background``): they then move while the notebook
        runs its later cells, where a click on *Run* waits for the kernel to
        finish them.  ``SARSP_EDU_AUTOPLAY=0`` in the environment keeps it off
        (batch runs of the notebooks, where nobody watches).
    parts : dict, optional
        Side name -> the functions its agent decides with
        (:class:`~sarsp_edu.agent.parts.DecisionParts`, or a mapping of some of
        them): Tutorial 7's "your agent" beside the package's, on the same
        world.  The fits do not use them, so each side is fitted (or loaded)
        as any other and given its parts before its first step.
    """

    def __init__(self, nu=NU, magnitude=DataSettings.outlier_magnitude, proportion=DataSettings.outlier_proportion,
                 n_switch_states=2, seed=0, episodes=30,
                 steps_per_second=30.0, config=None, sides=None, prepare_ahead: bool = True,
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
        self.prepare_ahead = bool(prepare_ahead)
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
        self.headers = {name: widgets.HTML(layout=widgets.Layout(height="54px", overflow="hidden", width="100%"))
                        for name in self.sides}
        self.worlds = {name: widgets.HTML(layout=widgets.Layout(flex="0 0 auto")) for name in self.sides}
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
        self.metrics_image = widgets.Image(format="svg+xml", layout=widgets.Layout(width="100%", display="none"))
        pictures, tables = [], []
        for name in self.sides:
            pictures.append(widgets.VBox(
                [self.headers[name], widgets.HBox([self.worlds[name], self.summaries[name]],
                                                  layout=widgets.Layout(align_items="flex-start",
                                                                        flex_flow="row wrap"))],
                layout=widgets.Layout(width="50%", min_width="0")))
            tables.append(widgets.VBox([self.decisions[name]], layout=widgets.Layout(width="50%", min_width="0")))
        self.settings_rows = [
            control_row([self.controls[k] for k in ("nu", "magnitude", "proportion", "n_switch_states")]),
            control_row([*self.buttons.values(), *(self.controls[k] for k in ("seed", "episodes")), self.speed]),
        ]
        super().__init__(children=[
            *self.settings_rows,
            self.status,
            widgets.HBox(pictures, layout=widgets.Layout(width="100%")),  # the grids and key numbers: one screen
            widgets.HBox(tables, layout=widgets.Layout(width="100%")),
            self.metrics_image,
        ])
        self.experiments = None
        self._last = dict.fromkeys(self.sides)
        self._task = None
        self._running = False
        self.frames = 0
        self._frame_times = {name: [] for name in self.sides}
        self._stepping_since = dict.fromkeys(self.sides)
        self.longest_wait_seconds = dict.fromkeys(self.sides, 0.0)
        self._drawn_episodes = -1
        self._drawn_key = None
        self._metrics_drawn_at = -float("inf")
        self._offline = {}  # seed -> the offline world and its clean data (a slider move reuses them)
        self._generation = 0  # counts setting changes: a preparation begun before one is discarded
        self._preparer = Preparer(self.sides, offline=self._offline)
        self._preparation = None
        self._draw_lock = threading.RLock()  # the sides' threads draw; one picture at a time
        self.autoplay = bool(autoplay)
        self._autoplayed = False
        self.last_preview_seconds = float("nan")
        self._init_projector(projector, toggle_row=self.settings_rows[-1])
        self._size_metrics_figure()
        for control in self.controls.values():
            control.observe(self._on_setting, names="value")
        self.preview()
        self._prepare_ahead()

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
        models are fitted in the background (``prepare_ahead``) or when
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

    def _prepare_ahead(self) -> None:
        if self.prepare_ahead:
            self._preparer.request(self.config())

    def _on_setting(self, change) -> None:
        """A slider moved: stop what runs, show the new world, prepare its runs, say the agents start on it at Run."""
        interrupted = self._running or self.experiments is not None
        try:
            with self._draw_lock:  # a side's thread drawing its last step draws before this, or not at all
                self._discard_run()
                self.preview()
        except ValueError as exc:  # a combination the world cannot hold: said, not raised
            self.status.value = f"<span style='color:#b00020'>{html.escape(str(exc))}</span>"
            return
        self._prepare_ahead()
        self.status.value = ((f"{change['owner'].description} = {round(change['new'], 10):g}: " if change else "")
                             + "both agents start on this world at the next <b>Run</b>"
                             + (" (the run under way was stopped)." if interrupted else "."))

    def _discard_run(self) -> None:
        """Stop and forget the runs; a preparation still under way is discarded when it ends."""
        self._generation += 1
        self._running = False
        self.experiments = None
        self._last = dict.fromkeys(self.sides)
        self._drawn_episodes = -1
        self._drawn_key = None
        self.metrics_image.value = b""
        self.metrics_image.layout.display = "none"

    def prepare(self):
        """Build the paired runs from the sliders (offline data, outliers, fits, shift).

        Uses the runs prepared ahead for these settings when there are some
        (waiting for them if they are under way).
        """
        from ...experiments.experiment import experiments_on_one_world

        config = self.config()
        preparation = self._preparer.claim(config)
        experiments = None if preparation is None else {name: preparation.wait_for(name) for name in self.sides}
        if experiments is None or None in experiments.values():  # not prepared ahead, or abandoned part-way
            with one_blas_thread():
                experiments = experiments_on_one_world(config, changed_settings(self.sides), cache=fitcache)
        self._begin(experiments)

    def _with_parts(self, name, experiment):
        """The side's run, its agent given the side's decision parts (if it has its own)."""
        if experiment is not None and name in self.parts:
            experiment.agent.parts = self.parts[name]
        return experiment

    def _begin(self, experiments) -> None:
        """Show these runs (all sides, or those fitted so far) from their start."""
        for name, experiment in experiments.items():
            self._with_parts(name, experiment)
        self.experiments = experiments
        self._last = dict.fromkeys(self.sides)
        self._drawn_episodes = -1
        self._drawn_key = None
        self.frames = 0
        self._frame_times = {name: [] for name in self.sides}
        self.longest_wait_seconds = dict.fromkeys(self.sides, 0.0)

    def snapshot(self) -> bytes:
        """A static picture of the dashboard as one PNG (:func:`~sarsp_edu.teaching.live.snapshot.picture`)."""
        return picture(self)

    def alt_text(self) -> str:
        """What the static picture (``snapshot``) shows, for a screen reader: its alt text."""
        return picture_alt_text(self)

    def _snapshot_run(self) -> None:
        """In a batch run that asks for it (SARSP_EDU_SNAPSHOT_EPISODES), run that many episodes for the picture."""
        episodes = int(os.environ.get(SNAPSHOT_VARIABLE, "0") or 0)
        if episodes > 0 and self.experiments is None and not self._running:
            self.prepare()
            self.fast_forward(min(episodes, self.config().episodes))

    def _repr_mimebundle_(self, **kwargs):
        # the widget view for live front ends; for static ones (GitHub, nbviewer, the course's pages) a PNG with
        # its alt text.  Voila shows the live view only, and its page waits for this cell: no PNG there.
        bundle = dict(super()._repr_mimebundle_(**kwargs))
        self._snapshot_run()
        if not os.environ.get("VOILA_KERNEL_ID"):
            bundle["image/png"] = base64.b64encode(self.snapshot()).decode("ascii")
        if self.autoplay and not self._autoplayed and os.environ.get(AUTOPLAY_VARIABLE, "1") != "0":
            self._autoplayed = True
            self.play_in_background()
        return bundle, alt_metadata(self.alt_text())

    @property
    def finished(self) -> bool:
        return (self.experiments is not None and len(self.experiments) == len(self.sides)
                and all(e.finished for e in self.experiments.values()))

    # -- projector size ---------------------------------------------------------
    def _size_metrics_figure(self) -> None:
        """The metric curves' figure: in projector size PROJECTOR_SCALE times narrower in inches, its text
        the same in points, so that the text is that much larger in the page's full width."""
        width, height = (14 / PROJECTOR_SCALE, 2.6) if self.projector else (14, 2.5)
        self.metrics_figure.set_size_inches(width, height)
        self.metrics_figure.subplots_adjust(left=0.5 / width, right=1 - 0.15 / width, bottom=0.5 / height,
                                            top=1 - 0.35 / height, wspace=0.32 if self.projector else 0.28)

    def _resize_pictures(self) -> None:
        self._size_metrics_figure()
        if self.experiments is None:
            self.preview()
        else:
            self._draw_world()
            self._drawn_key = None
            self._draw_metrics_if_new_episode()

    # -- drawing ------------------------------------------------------------
    def _draw_world(self) -> None:
        if self.experiments is None:  # before a run: the world the sliders imply
            self.preview()
            return
        for name in self.sides:
            if name in self.experiments:  # a side still being fitted keeps its message
                self._draw_side(name)

    def _draw_side(self, name) -> None:
        experiment = self.experiments[name]
        record = self._last[name]
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
            + "".join(f"<tr><td style='padding:1px 8px 1px 0;white-space:nowrap'>"
                      f"{label.replace('S_u', 'S<sub>u</sub>')}</td>"
                      f"<td style='text-align:right;white-space:nowrap'>"
                      f"<b>{value}</b></td></tr>" for label, value in numbers)
            + "</table>")

    def key_numbers(self, name) -> tuple:
        """A side's key numbers, (label, value) pairs: what its run has done so far."""
        experiment = self.experiments[name]
        records = experiment.episodes
        return (("episodes", len(records)),
                ("reached goal", sum(e["task_completed"] for e in records)),
                ("violations", sum(e["episode_cost"] for e in records)),
                ("S_u moves", len(experiment.agent.unsafe_pairs)),
                ("corrections", experiment.agent.corrective_updates),
                ("offline fit", "loaded" if experiment.loaded_from_cache
                 else f"{experiment.timings['offline_fit_seconds']:.1f} s"))

    def _draw_metrics_if_new_episode(self, throttle: bool = False) -> None:
        """Redraw the metric curves if an episode ended; while animating, at most every 1.5 s."""
        if self.experiments is None:
            return
        count = sum(len(e.episodes) for e in self.experiments.values())
        if (len(self.experiments), count) == self._drawn_key:
            return
        now = time.perf_counter()
        if throttle and now - self._metrics_drawn_at < 1.5 and not self.finished:
            return
        self._drawn_episodes = count
        self._drawn_key = (len(self.experiments), count)
        self._metrics_drawn_at = now
        for ax in self.metrics_axes:
            wipe_axes(ax)
        plotting.plot_live_metrics(self.metrics_axes, {m: e.records() for m, e in self.experiments.items()},
                                   LIVE_METRICS, labels=self._legend_labels())
        self.metrics_image.value = render_figure(self.metrics_figure, "svg")
        self.metrics_image.layout.display = None

    def _legend_labels(self) -> dict | None:
        return None if self.sides == TP_AND_GP else {name: name for name in self.sides}


def agent_dashboard(**kwargs) -> AgentDashboard:
    """The live TP-versus-GP dashboard of tutorial 4; see :class:`AgentDashboard` for the arguments."""
    return AgentDashboard(**kwargs)
