"""The live dashboards: two agents stepping side by side on one world.

Tutorial 4 runs the TP agent beside the GP agent, tutorial 6 one agent as the
printed algorithm and as the reference code run it.  An asyncio loop animates
the runs of :func:`sarsp_edu.experiment.experiments_on_one_world` without
blocking the notebook; the pictures come from :mod:`sarsp_edu.plotting`
(``plot_live_metrics``) and :mod:`sarsp_edu.markup` (``gridworld_svg``,
``decision_table_html``).
"""

from __future__ import annotations

import base64
import html
import time

import ipywidgets as widgets
from matplotlib.figure import Figure

from . import markup, plotting
from ._threads import one_blas_thread
from .dashboard import control_row, fixed_layout_axes, render_figure, slider, stitch_png, wipe_axes

__all__ = ["TP_AND_GP", "AgentDashboard", "agent_dashboard"]

_LIVE_METRICS = ("mean_reward", "total_cost", "task_success_rate", "mean_steps", "cost_rate")

#: tutorial 4's two sides: name -> (title, the settings that side changes)
TP_AND_GP = {
    "tp": ("Student-t process", {"model": "tp"}),
    "gp": ("Gaussian process", {"model": "gp"}),
}


class AgentDashboard(widgets.VBox):
    """Two agents running paired on one world, side by side, live: by default the TP agent and the GP agent.

    Sliders for nu, m, p, nss, the seed and the number of episodes: a move
    redraws at once the world they imply (the shift, and how many rows are
    outliers) and the agents start on it at the next *Run*; *Run* animates
    both agents step by step, *Stop* pauses, *Fast-forward* runs whole
    episodes without drawing each step (episode by episode, with progress),
    *New run* starts again from the sliders.  Each side shows the world after the shift (moved states
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
    sides : dict, optional
        Name -> (title, the settings that side changes), two of them; default
        ``TP_AND_GP``.  The sides share the world, the data and the episodes,
        so they may change only the model and the agent's settings
        (:func:`~sarsp_edu.experiment.experiments_on_one_world`).
    """

    def __init__(self, nu=3.0, magnitude=40.0, proportion=0.2, n_switch_states=2, seed=0, episodes=30,
                 steps_per_second=30.0, config=None, sides=None):
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
                                      layout=widgets.Layout(width="210px")),
            "new": widgets.Button(description="New run", icon="refresh"),
        }
        self.buttons["run"].on_click(lambda _: self.start())
        self.buttons["stop"].on_click(lambda _: self.stop())
        self.buttons["forward"].on_click(lambda _: self.start(episodes=10))
        self.buttons["new"].on_click(lambda _: self.reset())
        self.status = widgets.HTML("Press <b>Run</b> to prepare the data, fit the agents' models and start.")
        self.worlds = {name: widgets.HTML() for name in self.sides}
        self.decisions = {name: widgets.HTML() for name in self.sides}
        self.summaries = {name: widgets.HTML() for name in self.sides}
        # A fixed layout and plain-text titles: constrained layout and mathtext
        # would cost several times the whole agent step at each redraw.
        self.metrics_figure = Figure(figsize=(14, 2.5))
        self.metrics_figure.subplots_adjust(left=0.04, right=0.99, bottom=0.2, top=0.86, wspace=0.28)
        self.metrics_axes = fixed_layout_axes(self.metrics_figure, ncols=len(_LIVE_METRICS))
        self.metrics_image = widgets.Image(format="png", layout=widgets.Layout(width="100%"))
        sides = []
        for name, (label, _) in self.sides.items():
            sides.append(widgets.VBox([widgets.HTML(f"<b>{html.escape(label)}</b>"), self.worlds[name],
                                       self.decisions[name], self.summaries[name]],
                                      layout=widgets.Layout(width="50%")))
        super().__init__(children=[
            control_row([self.controls[k] for k in ("nu", "magnitude", "proportion")]),
            control_row([self.controls[k] for k in ("n_switch_states", "seed", "episodes")]),
            control_row([*self.buttons.values(), self.speed]),
            self.status,
            widgets.HBox(sides),
            self.metrics_image,
        ])
        self.experiments = None
        self._last = dict.fromkeys(self.sides)
        self._task = None
        self._running = False
        self.frames = 0
        self._frame_times: list[float] = []
        self._drawn_episodes = -1
        self._metrics_drawn_at = -float("inf")
        self._offline = {}  # seed -> the offline world and its clean data (a slider move reuses them)
        self._generation = 0  # counts setting changes: a preparation begun before one is discarded
        self.last_preview_seconds = float("nan")
        for control in self.controls.values():
            control.observe(self._on_setting, names="value")
        self.preview()

    # -- configuration ------------------------------------------------------
    def config(self):
        values = {k: c.value for k, c in self.controls.items()}
        return self.base_config.replace(
            nu=float(values["nu"]), outlier_magnitude=float(values["magnitude"]),
            outlier_proportion=float(values["proportion"]), n_switch_states=int(values["n_switch_states"]),
            seed=int(values["seed"]), episodes=int(values["episodes"]),
        )

    def preview(self) -> None:
        """Draw on both sides the world the sliders imply, before any run: the shift, and the outliers' count.

        A slider move calls it, so the picture follows the sliders at once
        (the offline world of a seed is computed once and reused); the
        models are fitted only when **Run** starts the agents.
        """
        from .preparation import offline_world, prepare

        start = time.perf_counter()
        config = self.config()
        if config.seed not in self._offline:
            self._offline[config.seed] = offline_world(config)
        prepared = prepare(config, offline=self._offline[config.seed])
        picture = markup.gridworld_svg(prepared.env.layout(), title="the world after the shift: press Run")
        rows = len(prepared.data.cost)
        outliers = len(prepared.data.outlier_indices)
        note = (f"<span style='font-size:12px'>nss = {config.n_switch_states}: {len(prepared.env.moved_indices)} "
                f"unsafe states moved (outlined; dashed: where they were). Outliers: {outliers} of {rows} rows "
                f"of the cost model's data multiplied by m = {config.outlier_magnitude:g}.</span>")
        for name in self.sides:
            self.worlds[name].value = picture
            self.decisions[name].value = ""
            self.summaries[name].value = note
        self.last_preview_seconds = time.perf_counter() - start

    def _on_setting(self, change) -> None:
        """A slider moved: stop what runs, show the new world, and say the agents start on it at the next Run."""
        interrupted = self._running or self.experiments is not None
        self._discard_run()
        try:
            self.preview()
        except ValueError as exc:  # a combination the world cannot hold: said, not raised
            self.status.value = f"<span style='color:#b00020'>{html.escape(str(exc))}</span>"
            return
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
        self.metrics_image.value = b""

    def prepare(self):
        """Build the paired runs from the sliders (offline data, outliers, fits, shift)."""
        from .experiment import experiments_on_one_world

        self.experiments = experiments_on_one_world(
            self.config(), {name: changes for name, (_, changes) in self.sides.items()})
        self._last = dict.fromkeys(self.sides)
        self._drawn_episodes = -1
        self.frames = 0
        self._frame_times = []

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
        if self.experiments is None:
            env = prepare(self.config()).env
            title = "the world after the shift (press Run)"
        else:
            first = next(iter(self.experiments.values()))
            env = first.env
            done = len(first.episodes)
            title = f"after {done} episode{'' if done == 1 else 's'}"
        plotting.plot_gridworld(ax, env.layout(), title=title)
        images = [render_figure(figure, "png", dpi)]
        if self.experiments is not None and self._drawn_episodes > 0:
            images.append(render_figure(self.metrics_figure, "png", dpi))
        return stitch_png(images)

    def _repr_mimebundle_(self, **kwargs):
        # the widget view for live front ends, a PNG for static ones (GitHub, nbviewer)
        bundle = dict(super()._repr_mimebundle_(**kwargs))
        bundle["image/png"] = base64.b64encode(self.snapshot()).decode("ascii")
        return bundle

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
            self.status.value = ("Already running: press <b>Stop</b> first, then "
                                 + ("<b>Fast-forward</b>." if episodes is not None else "<b>Run</b>."))
            return None
        self._running = True
        self._task = asyncio.ensure_future(self._loop(episodes))
        return self._task

    def stop(self) -> None:
        self._running = False
        if self.experiments is not None:
            self.status.value = "Stopped. <b>Run</b> continues, <b>New run</b> starts again from the sliders."

    def reset(self) -> None:
        self._discard_run()
        self.preview()
        self.status.value = "Press <b>Run</b> to prepare the data, fit the agents' models and start."

    async def _loop(self, episodes):
        import asyncio

        loop = asyncio.get_running_loop()
        generation = self._generation
        try:
            if self.experiments is None:
                self.status.value = (f"Preparing: {self.base_config.offline_episodes} offline episodes, outliers, "
                                     "fitting the agents' models (a few seconds) ...")
                await loop.run_in_executor(None, self.prepare)
                if generation != self._generation:  # the sliders moved meanwhile: that preparation is stale
                    self.experiments = None
                    return
            if episodes is not None:
                for done in range(episodes):  # one episode at a time: progress shown, Stop obeyed
                    if not self._running or self.finished:
                        break
                    self.status.value = f"Fast-forwarding: episode {done + 1} of {episodes} ..."
                    await loop.run_in_executor(None, self._forward_quietly, 1)
                    if generation != self._generation:
                        return
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
        if self.experiments is None:  # before a run: the world the sliders imply
            self.preview()
            return
        for model in self.sides:
            experiment = self.experiments[model]
            record = self._last[model]
            title = (f"episode {len(experiment.episodes) + (0 if record is None or record.done else 1)}"
                     f" of {experiment.config.episodes}")
            self.worlds[model].value = markup.gridworld_svg(
                experiment.env.layout(), trajectory=experiment.trajectory,
                unsafe_pairs=sorted(experiment.agent.unsafe_pairs), title=title,
            )
            decision = None if record is None else record.decision
            self.decisions[model].value = markup.decision_table_html(
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
        for ax in self.metrics_axes:
            wipe_axes(ax)
        plotting.plot_live_metrics(self.metrics_axes, {m: e.records() for m, e in self.experiments.items()},
                                   _LIVE_METRICS, labels=self._legend_labels())
        self.metrics_image.value = render_figure(self.metrics_figure, "png", 80)


    def _legend_labels(self) -> dict | None:
        return None if self.sides == TP_AND_GP else {name: name for name in self.sides}


def agent_dashboard(**kwargs) -> AgentDashboard:
    """The live TP-versus-GP dashboard of tutorial 4; see :class:`AgentDashboard` for the arguments."""
    return AgentDashboard(**kwargs)
