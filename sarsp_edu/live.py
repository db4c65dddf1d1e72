"""The live dashboards: two agents stepping side by side on one world.

Tutorial 4 runs the TP agent beside the GP agent, tutorial 6 one agent as the
printed algorithm and as the reference code run it.  The runs of
:func:`sarsp_edu.experiment.experiments_on_one_world` are prepared ahead in a
worker thread (the offline fits take seconds), and each side steps in its own
worker thread under an asyncio loop, so the notebook stays responsive and one
side's retrain of its cost model does not stop the other; the pictures come
from :mod:`sarsp_edu.plotting` (``plot_live_metrics``) and
:mod:`sarsp_edu.markup` (``gridworld_svg``, ``decision_table_html``).
"""

from __future__ import annotations

import base64
import html
import os
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import ipywidgets as widgets
from matplotlib.figure import Figure

from . import markup, plotting
from ._threads import one_blas_thread
from .config import NU, DataSettings
from .dashboard import (PROJECTOR_SCALE, PROJECTOR_TEXT_PX, ProjectorMixin, control_row, fixed_layout_axes,
                        render_figure, slider, stitch_png, wipe_axes)

__all__ = ["TP_AND_GP", "AgentDashboard", "agent_dashboard"]

_LIVE_METRICS = ("mean_reward", "total_cost", "task_success_rate", "mean_steps", "cost_rate")

#: tutorial 4's two sides: name -> (title, the settings that side changes)
TP_AND_GP = {
    "tp": ("Student-t process", {"model": "tp"}),
    "gp": ("Gaussian process", {"model": "gp"}),
}

#: the environment variable that, set to 0, keeps ``autoplay`` from starting: batch runs of the notebooks
#: (the test suite, ``sarsp-edu course``), where nobody watches and the agents would only compete for the cores
AUTOPLAY_VARIABLE = "SARSP_EDU_AUTOPLAY"

#: a side whose step has taken this long shows why it waits (a retrain of its cost model, usually)
WAIT_SHOWN_AFTER = 0.25


def changed_settings(sides: dict) -> dict:
    """Name -> the settings that side changes: the dashboard's sides as ``experiments_on_one_world`` takes them."""
    return {name: changes for name, (_, changes) in sides.items()}


class _Preparation:
    """The runs of one setting as a worker thread fits them: each side appears as soon as its models are fitted."""

    def __init__(self, condition):
        self._condition = condition
        self.experiments = {}
        self.error = None
        self.done = False

    def wait_for(self, name):
        """The side's Experiment, once fitted (raises what the preparation raised; None if it was abandoned)."""
        with self._condition:
            while name not in self.experiments and self.error is None and not self.done:
                self._condition.wait()
            if self.error is not None:
                raise self.error
            return self.experiments.get(name)


class _Preparer:
    """Prepares the runs of the latest requested settings in one daemon thread.

    A slider move requests new settings; settings requested while another
    preparation runs are prepared after it (the one under way stops after
    the side it is fitting), and only the latest request is kept, so a
    lecturer dragging a slider does not queue up work.  ``claim`` hands a
    preparation, finished or under way, to the dashboard once.
    """

    def __init__(self, sides: dict):
        self.sides = sides
        self._condition = threading.Condition()
        self._wanted = None
        self._pending = False
        self._preparations = {}  # key -> _Preparation (the latest only)
        self._thread = None

    @staticmethod
    def key(config):
        return repr(config)

    def request(self, config) -> None:
        """Prepare ``config`` (again), after the preparation under way."""
        with self._condition:
            self._wanted, self._pending = config, True
            if self._thread is None:
                self._thread = threading.Thread(target=self._work, name="sarsp-edu-prepare", daemon=True)
                self._thread.start()
            self._condition.notify_all()

    def busy_with(self, config) -> bool:
        """Whether a preparation of ``config`` is under way or waits to begin."""
        with self._condition:
            key = self.key(config)
            preparation = self._preparations.get(key)
            return (preparation is not None and not preparation.done) or (
                self._pending and self.key(self._wanted) == key)

    def claim(self, config):
        """The preparation of ``config`` (finished or under way), handed out once; None if it was not requested."""
        with self._condition:
            key = self.key(config)
            while self._pending and self.key(self._wanted) == key:  # requested, not begun: wait for it to begin
                self._condition.wait()
            return self._preparations.pop(key, None)

    def _work(self) -> None:
        from .experiment import each_experiment_on_one_world

        while True:
            with self._condition:
                if not self._pending:
                    self._thread = None
                    self._condition.notify_all()
                    return
                config, self._pending = self._wanted, False
                key = self.key(config)
                preparation = _Preparation(self._condition)
                self._preparations = {key: preparation}  # only the latest settings are kept
                self._condition.notify_all()
            try:
                with one_blas_thread():
                    sides = changed_settings(self.sides)
                    for name, experiment in each_experiment_on_one_world(config, sides, cache=True):
                        with self._condition:
                            preparation.experiments[name] = experiment
                            self._condition.notify_all()
                            if self._pending:  # newer settings wanted: the rest of this one is abandoned
                                break
            except Exception as exc:  # handed to whoever waits for these settings
                preparation.error = exc
            with self._condition:
                preparation.done = True
                self._condition.notify_all()


class AgentDashboard(ProjectorMixin, widgets.VBox):
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
        (:func:`~sarsp_edu.experiment.experiments_on_one_world`).
    prepare_ahead : bool, default True
        Prepare the runs of the sliders' settings in a worker thread as soon
        as they are set, so that *Run* need not wait for the fits.
    projector : bool, optional
        Projector size (see :func:`sarsp_edu.dashboard.projector`); default
        :func:`~sarsp_edu.dashboard.projector_default`.
    autoplay : bool, default False
        Start the agents when the dashboard is first shown, in a thread of
        their own (``play_in_background``): they then move while the notebook
        runs its later cells, where a click on *Run* waits for the kernel to
        finish them.  ``SARSP_EDU_AUTOPLAY=0`` in the environment keeps it off
        (batch runs of the notebooks, where nobody watches).
    """

    def __init__(self, nu=NU, magnitude=DataSettings.outlier_magnitude, proportion=DataSettings.outlier_proportion,
                 n_switch_states=2, seed=0, episodes=30,
                 steps_per_second=30.0, config=None, sides=None, prepare_ahead: bool = True,
                 projector: bool | None = None, autoplay: bool = False):
        from .config import ExperimentConfig
        from .preparation import PREPARATION_FIELDS

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
        self.headers = {name: widgets.HTML() for name in self.sides}
        self.worlds = {name: widgets.HTML(layout=widgets.Layout(flex="0 0 auto")) for name in self.sides}
        self.decisions = {name: widgets.HTML() for name in self.sides}
        # beside the grid where there is room for it, under it on a narrow screen
        self.summaries = {name: widgets.HTML(layout=widgets.Layout(flex="1 1 180px", min_width="180px"))
                          for name in self.sides}
        # A fixed layout and plain-text titles: constrained layout and mathtext
        # would cost several times the whole agent step at each redraw.
        self.metrics_figure = Figure(figsize=(14, 2.5))
        self.metrics_axes = fixed_layout_axes(self.metrics_figure, ncols=len(_LIVE_METRICS))
        # SVG: the browser draws the text, sharp at any size
        self.metrics_image = widgets.Image(format="svg+xml", layout=widgets.Layout(width="100%"))
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
        self._preparer = _Preparer(self.sides)
        self._pool = None
        self._preparation = None
        self._draw_lock = threading.RLock()  # the sides' threads draw; one picture at a time
        self.autoplay = bool(autoplay)
        self._autoplayed = False
        self.last_preview_seconds = float("nan")
        self._init_projector(projector)
        self._size_metrics_figure()
        for control in self.controls.values():
            control.observe(self._on_setting, names="value")
        self.preview()
        self._prepare_ahead()

    # -- configuration ------------------------------------------------------
    def config(self):
        values = {k: c.value for k, c in self.controls.items()}
        return self.base_config.replace(
            nu=float(values["nu"]), outlier_magnitude=float(values["magnitude"]),
            outlier_proportion=float(values["proportion"]), n_switch_states=int(values["n_switch_states"]),
            seed=int(values["seed"]), episodes=int(values["episodes"]),
        )

    @property
    def _text_px(self) -> int:
        return PROJECTOR_TEXT_PX if self.projector else 13

    def _small(self, text: str) -> str:
        return f"<span style='font-size:{self._text_px - 1}px'>{text}</span>"

    def preview(self) -> None:
        """Draw on both sides the world the sliders imply, before any run: the shift, and the outliers' count.

        A slider move calls it, so the picture follows the sliders at once
        (the offline world of a seed is computed once and reused); the
        models are fitted in the background (``prepare_ahead``) or when
        **Run** starts the agents.
        """
        from .preparation import offline_world, prepare

        start = time.perf_counter()
        config = self.config()
        if config.seed not in self._offline:
            self._offline[config.seed] = offline_world(config)
        prepared = prepare(config, offline=self._offline[config.seed])
        picture = markup.gridworld_svg(prepared.env.layout(), title="the world after the shift: press Run",
                                       font_size=self._text_px)
        rows = len(prepared.data.cost)
        outliers = len(prepared.data.outlier_indices)
        note = self._small(
            f"nss = {config.n_switch_states}: {len(prepared.env.moved_indices)} unsafe states moved (outlined; "
            f"dashed: where they were).<br>Outliers: {outliers} of {rows} rows of the cost model's data "
            f"multiplied by m = {config.outlier_magnitude:g}.")
        for name, (label, _) in self.sides.items():
            self.headers[name].value = f"<b>{html.escape(label)}</b>"
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
        self.status.value = ((f"{change['owner'].description} = {change['new']}: " if change else "")
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

    def prepare(self):
        """Build the paired runs from the sliders (offline data, outliers, fits, shift).

        Uses the runs prepared ahead for these settings when there are some
        (waiting for them if they are under way).
        """
        from .experiment import experiments_on_one_world

        config = self.config()
        preparation = self._preparer.claim(config)
        experiments = None if preparation is None else {name: preparation.wait_for(name) for name in self.sides}
        if experiments is None or None in experiments.values():  # not prepared ahead, or abandoned part-way
            with one_blas_thread():
                experiments = experiments_on_one_world(config, changed_settings(self.sides), cache=True)
        self._begin(experiments)

    def _begin(self, experiments) -> None:
        """Show these runs (all sides, or those fitted so far) from their start."""
        self.experiments = experiments
        self._last = dict.fromkeys(self.sides)
        self._drawn_episodes = -1
        self._drawn_key = None
        self.frames = 0
        self._frame_times = {name: [] for name in self.sides}
        self.longest_wait_seconds = dict.fromkeys(self.sides, 0.0)

    def snapshot(self, dpi: int = 72) -> bytes:
        """A static picture of the dashboard as one PNG: the world the agents walk, and their metrics once they ran.

        Before a run the world is built from the sliders (as ``prepare`` builds
        it, without fitting the models), so a static copy of the notebook shows
        where the agents will start.
        """
        from .preparation import prepare

        figure = Figure(figsize=(5.6, 4.4))
        figure.subplots_adjust(left=0.09, right=1 - 1.8 / 5.6, bottom=0.11, top=0.9)
        ax = figure.subplots()
        if not self.experiments:  # no run yet, or its sides still being fitted
            env = prepare(self.config()).env
            title = "the world after the shift (press Run)"
        else:
            first = next(iter(self.experiments.values()))
            env = first.env
            done = len(first.episodes)
            title = f"after {done} episode{'' if done == 1 else 's'}"
        plotting.plot_gridworld(ax, env.layout(), title=title)
        images = [render_figure(figure, "png", dpi)]
        if self.experiments and self._drawn_episodes > 0:
            images.append(render_figure(self.metrics_figure, "png", dpi))
        return stitch_png(images)

    def _repr_mimebundle_(self, **kwargs):
        # the widget view for live front ends, a PNG for static ones (GitHub, nbviewer): the world before the run
        bundle = dict(super()._repr_mimebundle_(**kwargs))
        bundle["image/png"] = base64.b64encode(self.snapshot()).decode("ascii")
        if self.autoplay and not self._autoplayed and os.environ.get(AUTOPLAY_VARIABLE, "1") != "0":
            self._autoplayed = True
            self.play_in_background()
        return bundle

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

    # -- stepping -----------------------------------------------------------
    def step_pair(self, draw: bool = True) -> None:
        """One step of each agent that has episodes left."""
        self._every_side()
        for model, experiment in self.experiments.items():
            if not experiment.finished:
                self._last[model] = experiment.step()
        if draw:
            self._draw_world()
            self._draw_metrics_if_new_episode(throttle=True)
            self.frames += 1
            now = time.perf_counter()
            for times in self._frame_times.values():
                times.append(now)

    def _every_side(self) -> None:
        """Both sides' runs, prepared here if no run is on show, waited for if one is still being fitted."""
        if self.experiments is None:
            self.prepare()
        for name in self.sides:
            if name not in self.experiments:
                self._await_side(name, self._generation)

    def run_steps(self, n: int, draw: bool = True) -> None:
        """``n`` paired steps, synchronously."""
        with one_blas_thread():
            for _ in range(n):
                if self.finished:
                    break
                self.step_pair(draw=draw)

    def fast_forward(self, episodes: int = 10) -> None:
        """Run whole episodes of both agents without drawing each step, synchronously."""
        self._every_side()
        self._forward_quietly(episodes)
        self._draw_world()
        self._draw_metrics_if_new_episode()

    @property
    def displayed_steps_per_second(self) -> float:
        """Steps drawn per second over the current animation, on the slower side (NaN before two frames)."""
        rates = []
        for times in self._frame_times.values():
            if len(times) < 2 or times[-1] == times[0]:
                return float("nan")
            rates.append((len(times) - 1) / (times[-1] - times[0]))
        return min(rates)

    # -- running without blocking the kernel (the buttons, autoplay) ---------------
    def start(self, episodes: int | None = None):
        """Start animating (or fast-forward ``episodes`` episodes) without blocking the kernel.

        Returns the asyncio task that runs it (None if a run is already under
        way, which the status line then says).
        """
        import asyncio

        if self._running:
            self.status.value = ("Already running: press <b>Stop</b> first, then "
                                 + ("<b>Fast-forward</b>." if episodes is not None else "<b>Run</b>."))
            return None
        self._running = True
        self._task = asyncio.ensure_future(self._loop(episodes))
        return self._task

    def play_in_background(self) -> threading.Thread | None:
        """Start animating in a thread of its own: the agents move even while the notebook runs other cells.

        *Run* waits for the kernel, which handles a click only between cells;
        this does not (``autoplay=True`` calls it when the dashboard is first
        shown).  Returns the thread, or None if a run is already under way.
        """
        if self._running:
            return None
        self._running = True
        generation = self._generation
        thread = threading.Thread(target=self._play_reporting, args=(generation,), name="sarsp-edu-play",
                                  daemon=True)
        thread.start()
        return thread

    def stop(self) -> None:
        self._running = False
        if self.experiments is not None:
            self.status.value = "Stopped. <b>Run</b> continues, <b>New run</b> starts again from the sliders."

    def reset(self) -> None:
        with self._draw_lock:
            self._discard_run()
            self.preview()
        self._prepare_ahead()
        self.status.value = "Press <b>Run</b> to start both agents."

    async def _loop(self, episodes):
        import asyncio

        loop = asyncio.get_running_loop()
        generation = self._generation
        try:
            if episodes is None:
                await loop.run_in_executor(None, self._play, generation)
                return
            await loop.run_in_executor(None, self._claim_preparation, generation)
            if generation != self._generation:
                return
            for name in self.sides:  # fast-forward needs every side
                await loop.run_in_executor(None, self._await_side, name, generation)
            if generation != self._generation:
                return
            for done in range(episodes):  # one episode at a time: progress shown, Stop obeyed
                if not self._running or self.finished:
                    break
                self.status.value = f"Fast-forwarding: episode {done + 1} of {episodes} ..."
                await loop.run_in_executor(None, self._forward_quietly, 1)
                if generation != self._generation:
                    return
                with self._draw_lock:
                    self._draw_world()
                    self._draw_metrics_if_new_episode()
            self._say_where_it_stands(generation)
        except Exception as exc:  # the dashboard reports, the kernel lives on
            self._say_error(exc)
        finally:
            self._running = False

    def _play_reporting(self, generation) -> None:
        try:
            self._play(generation)
        except Exception as exc:  # a background thread has nobody to raise to
            self._say_error(exc)
        finally:
            self._running = False

    def _say_error(self, exc) -> None:
        self.status.value = f"<span style='color:#b00020'>Stopped by an error: {html.escape(str(exc))}</span>"

    def _say_where_it_stands(self, generation) -> None:
        if generation != self._generation:
            return
        with self._draw_lock:
            self._draw_metrics_if_new_episode()
        if self.finished:
            self.status.value = "Finished every episode. <b>New run</b> starts again from the sliders."
        elif self._running:
            self.status.value = "Paused. <b>Run</b> continues."

    def _claim_preparation(self, generation) -> None:
        """Take the runs prepared (or being prepared) for the sliders' settings; each side joins when fitted."""
        if self.experiments is not None:
            return
        config = self.config()
        ahead = self._preparer.busy_with(config)
        self.status.value = ("Preparing: " + ("the fits begun in the background are finishing" if ahead else
                                              f"{self.base_config.offline_episodes} offline episodes, outliers, "
                                              "fitting the agents' models")
                             + "; each agent starts as soon as its models are fitted ...")
        if not ahead:
            self._preparer.request(config)
        preparation = self._preparer.claim(config)
        if generation != self._generation:  # the sliders moved meanwhile: that preparation is stale
            return
        if preparation is None:  # not found (never expected): prepared here instead
            self.prepare()
        else:
            self._preparation = preparation
            self._begin({})

    def _play(self, generation) -> None:
        """Animate until stopped or finished, blocking: each side steps in a worker thread of its own.

        Run from a worker thread (by *Run* through the asyncio loop, or by
        ``play_in_background``); the drawing is serialised by a lock.
        """
        self._claim_preparation(generation)
        if generation != self._generation:
            return
        self.status.value = "Running ..."
        if self._pool is None:  # the sides and the watch on them
            self._pool = ThreadPoolExecutor(max_workers=len(self.sides) + 1, thread_name_prefix="sarsp-edu-side")
        self._frame_times = {name: [] for name in self.sides}  # this animation's steps, counted afresh
        self.frames = 0
        with one_blas_thread():  # entered once for the whole animation, not per step
            sides = [self._pool.submit(self._run_side, name, generation) for name in self.sides]
            watch = self._pool.submit(self._show_waits, generation, sides)
            for future in [*sides, watch]:
                future.result()
        self._say_where_it_stands(generation)

    def _await_side(self, name, generation):
        """A side's run, waiting for its models to be fitted (in the background) if they are not yet."""
        if name in self.experiments:
            return self.experiments[name]
        self._say_waiting(name, "fitting its models ...")
        experiment = self._preparation.wait_for(name)
        if experiment is None:  # abandoned part-way: only when newer settings were asked for, so stale
            return None
        with self._draw_lock:
            if generation == self._generation:
                self.experiments[name] = experiment
                self._draw_side(name)
        return experiment

    def _run_side(self, name, generation) -> None:
        experiment = self._await_side(name, generation)
        if experiment is None:
            return
        while self._running and generation == self._generation and not experiment.finished:
            start = time.perf_counter()
            self._stepping_since[name] = start
            try:
                record = experiment.step()
            finally:
                self._stepping_since[name] = None
            with self._draw_lock:
                if generation != self._generation:  # a slider moved: the preview is on show now
                    return
                self._last[name] = record
                self._draw_side(name)
                times = self._frame_times[name]
                now = time.perf_counter()
                if times:
                    self.longest_wait_seconds[name] = max(self.longest_wait_seconds[name], now - times[-1])
                times.append(now)
                steps = min(len(t) for t in self._frame_times.values())
                if steps > self.frames:
                    self.frames = steps
                    if steps % 10 == 0:
                        self.status.value = (f"Running: {steps} steps shown, "
                                             f"{self.displayed_steps_per_second:.1f} steps per second.")
                self._draw_metrics_if_new_episode(throttle=True)
            time.sleep(max(0.0, 1.0 / self.speed.value - (time.perf_counter() - start)))

    def _show_waits(self, generation, sides) -> None:
        """Every tenth of a second: a side whose step has taken over WAIT_SHOWN_AFTER says why it waits."""
        while generation == self._generation and not all(side.done() for side in sides):
            now = time.perf_counter()
            for name, since in list(self._stepping_since.items()):
                if since is not None and now - since > WAIT_SHOWN_AFTER and name in self.experiments:
                    agent = self.experiments[name].agent
                    why = ("retraining the cost model after a corrective update" if agent.retraining
                           else "deciding")
                    self._say_waiting(name, f"{why} ({now - since:.1f} s); the other side goes on")
            time.sleep(0.1)

    def _say_waiting(self, name, why: str) -> None:
        self.headers[name].value = (f"<b>{html.escape(self.sides[name][0])}</b> "
                                    f"<span style='color:#b35900'>⏳ {html.escape(why)}</span>")

    def _forward_quietly(self, episodes):  # every side is there: fast-forward waits for them
        with one_blas_thread():
            for experiment in self.experiments.values():
                target = min(len(experiment.episodes) + episodes, experiment.config.episodes)
                while len(experiment.episodes) < target:
                    experiment.run_episode()

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
        self.headers[name].value = f"<b>{html.escape(self.sides[name][0])}</b>"
        self.worlds[name].value = markup.gridworld_svg(
            experiment.env.layout(), trajectory=experiment.trajectory,
            unsafe_pairs=sorted(experiment.agent.unsafe_pairs),
            title=f"episode {episode} of {experiment.config.episodes}", font_size=self._text_px,
        )
        decision = None if record is None else record.decision
        self.decisions[name].value = markup.decision_table_html(
            decision, experiment.config.d, experiment.config.variance_threshold, font_size=self._text_px - 1)
        records = experiment.episodes
        numbers = (("episodes done", len(records)),
                   ("reached the goal", sum(e["task_completed"] for e in records)),
                   ("violations", sum(e["episode_cost"] for e in records)),
                   ("|S_u|", len(experiment.agent.unsafe_pairs)),
                   ("corrective updates", experiment.agent.corrective_updates),
                   ("offline fit", "loaded, fitted earlier" if experiment.loaded_from_cache
                    else f"{experiment.timings['offline_fit_seconds']:.1f} s"))
        self.summaries[name].value = (
            f"<table style='font-size:{self._text_px}px;border-collapse:collapse;margin-left:8px'>"
            + "".join(f"<tr><td style='padding:1px 8px 1px 0'>{label}</td><td style='text-align:right'>"
                      f"<b>{value}</b></td></tr>" for label, value in numbers)
            + "</table>")

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
                                   _LIVE_METRICS, labels=self._legend_labels())
        self.metrics_image.value = render_figure(self.metrics_figure, "svg")

    def _legend_labels(self) -> dict | None:
        return None if self.sides == TP_AND_GP else {name: name for name in self.sides}


def agent_dashboard(**kwargs) -> AgentDashboard:
    """The live TP-versus-GP dashboard of tutorial 4; see :class:`AgentDashboard` for the arguments."""
    return AgentDashboard(**kwargs)
