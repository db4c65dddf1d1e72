"""The live dashboard as one static picture: what a stored notebook, a static page or a handout shows of it."""

from __future__ import annotations

import base64
import os
import time

from matplotlib.figure import Figure

from .. import plotting
from ..dashboards.framework import SNAPSHOT_WIDTH_PX, readable_png, render_figure, wipe_axes
from ..dashboards.projector import PROJECTOR_SCALE
from ..plotting.display import alt_metadata
from . import markup
from .pick import TP_AND_GP

__all__ = ["AUTOPLAY_VARIABLE", "SNAPSHOT_VARIABLE", "LiveMetrics", "StaticPicture", "first_episode", "key_numbers",
           "picture", "picture_alt_text"]

#: the environment variable that, set to 0, keeps ``autoplay`` from starting: batch runs of the notebooks
#: (the test suite, ``sarsp-edu course``), where nobody watches and the agents would only compete for the cores
AUTOPLAY_VARIABLE = "SARSP_EDU_AUTOPLAY"
#: the environment variable that, set to N, makes a dashboard shown in a batch run fast-forward N episodes
#: before its picture is stored (``sarsp-edu course`` sets 10), so that a static copy shows the agents at work
SNAPSHOT_VARIABLE = "SARSP_EDU_SNAPSHOT_EPISODES"

#: the metrics the live dashboard draws, episode by episode
LIVE_METRICS = ("mean_reward", "total_cost", "task_success_rate", "mean_steps", "cost_rate")


def first_episode(prepared):
    """The world the sliders imply, its agent at the first episode's start (its goal too), not where the
    offline episodes left it.  ``prepared`` is the preview's own copy: resetting it changes no run."""
    prepared.env.reset(seed=int(prepared.episode_seeds[0]))
    return prepared.env.layout()


def key_numbers(experiment) -> tuple:
    """A side's key numbers, (label, value) pairs: what its run has done so far.

    Parameters
    ----------
    experiment : Experiment
        The side's run.
    """
    records = experiment.episodes
    return (("episodes", len(records)),
            ("reached goal", sum(e["task_completed"] for e in records)),
            ("violations", sum(e["episode_cost"] for e in records)),
            ("S_u moves", len(experiment.agent.unsafe_pairs)),
            ("corrections", experiment.agent.corrective_updates),
            ("offline fit", "loaded" if experiment.loaded_from_cache
             else f"{experiment.timings['offline_fit_seconds']:.1f} s"))


def picture(dashboard) -> bytes:
    """A static picture of the dashboard as one PNG: each side's world and key numbers, and the metrics.

    After a run, each agent's path in its current episode, its ``S_u`` and
    key numbers, and the running metrics; before any run, the world the
    sliders imply (built as ``prepare`` builds it, without fitting).  Where
    ``SARSP_EDU_SNAPSHOT_EPISODES`` is set (``sarsp-edu course`` sets 10),
    a dashboard first shown in a batch run fast-forwards that many episodes
    first, so that a stored notebook shows the agents at work.  The picture
    is :data:`~sarsp_edu.teaching.dashboards.framework.SNAPSHOT_WIDTH_PX` wide, its text at
    least 14 pt at that width.
    """
    from ...world.preparation import prepare

    figure = Figure(figsize=(SNAPSHOT_WIDTH_PX / 100, 9.4 if dashboard.experiments else 5.6), layout="constrained")
    top, bottom = (figure.subfigures(2, 1, height_ratios=(5.6, 3.8)) if dashboard.experiments else (figure, None))
    sides = top.subplots(1, 4, width_ratios=(3, 1.9, 3, 1.9))
    key = ("circle: start, star: goal\nred: unsafe; outlined: moved\nby the shift (dashed: before)"
           "\nred ticks: moves in S_u\nline: this episode's path")
    # the world of a side not running yet: a running side's, else the sliders' (built once, without fits)
    waiting = (next(iter(dashboard.experiments.values())).env.layout() if dashboard.experiments
               else first_episode(prepare(dashboard.config())))
    for (name, (label, _)), ax, text in zip(dashboard.sides.items(), sides[0::2], sides[1::2]):
        text.axis("off")
        experiment = (dashboard.experiments or {}).get(name)
        if experiment is None:
            plotting.plot_gridworld(ax, waiting, legend=False, title=f"{label}: press Run")
            numbers = ()
        else:
            plotting.plot_gridworld(ax, experiment.env.layout(), trajectory=experiment.trajectory,
                                    unsafe_pairs=sorted(experiment.agent.unsafe_pairs), legend=False,
                                    title=f"{label}: episode {len(experiment.episodes)} done")
            numbers = dashboard.key_numbers(name)
        text.text(0, 0.97, "\n".join(f"{label_}: {value}" for label_, value in numbers), va="top",
                  linespacing=1.6, transform=text.transAxes)
        text.text(0, 0.0, key, va="bottom", linespacing=1.4, color="0.3", transform=text.transAxes)
    if bottom is not None and dashboard.metrics_shown:
        axes = bottom.subplots(1, len(LIVE_METRICS))
        plotting.plot_live_metrics(axes, _records_in_side_order(dashboard),
                                   LIVE_METRICS, labels=dashboard._legend_labels())
    return readable_png([figure])


def picture_alt_text(dashboard) -> str:
    """What :func:`picture` shows, for a screen reader: the dashboard picture's alt text."""
    labels = [label for label, _ in dashboard.sides.values()]
    text = (f"Two grid worlds side by side, {labels[0]} on the left and {labels[1]} on the right, each the world "
            f"after the shift with nss = {dashboard.config().n_switch_states}: red squares are unsafe states "
            "(outlined in black: moved by the shift; dashed outlines: where they were), a ring is the start, a "
            "star the goal; a key beside each grid names the marks")
    if dashboard.experiments is not None:
        text += ("; on each grid, the agent's path in its current episode and red ticks for the moves it has "
                 "learned are unsafe (S_u), its key numbers beside it")
        if dashboard.metrics_shown:
            text += ("; below, both agents' running metrics against the episode ("
                     + ", ".join(metric.replace("_", " ") for metric in LIVE_METRICS)
                     + "), the left side's solid with circles, the right side's dashed with squares")
    return text + "."


def _records_in_side_order(dashboard) -> dict:
    """Each side's records in the order of the dashboard's sides (left first), whichever side's fit ended first:
    the left side is drawn solid with circles, the right dashed with squares."""
    experiments = dashboard.experiments or {}
    return {name: experiments[name].records() for name in dashboard.sides if name in experiments}


def metrics_alt_text(dashboard) -> str:
    """What the metric curves show, for a screen reader: the metrics, how each side is drawn, and where each side's
    running values stand at its last episode."""
    labels = dashboard._legend_labels() or {name: label for name, (label, _) in dashboard.sides.items()}
    names = [metric.replace("_", " ") for metric in LIVE_METRICS]
    text = (f"Both agents' running metrics against the episode ({', '.join(names)}), the left side's solid with "
            "circles, the right side's dashed with squares")
    for name, records in _records_in_side_order(dashboard).items():
        if len(records):
            last = records.iloc[-1]
            text += (f"; {labels[name]} after {len(records)} episodes: "
                     + ", ".join(f"{label} {float(last[metric]):.3g}" for label, metric in zip(names, LIVE_METRICS)))
    return text + "."


class StaticPicture:
    """The live dashboard's static half (a mixin): its picture and alt text, and what it shows where.

    Live front ends show the widgets; static ones (GitHub, nbviewer, the
    course's pages) a PNG of :func:`picture` with its alt text.  Voila shows
    the live view only, and its page waits for the cell: no PNG there.
    """

    def snapshot(self) -> bytes:
        """A static picture of the dashboard as one PNG (:func:`picture`)."""
        return picture(self)

    def alt_text(self) -> str:
        """What the static picture (``snapshot``) shows, for a screen reader: its alt text."""
        return picture_alt_text(self)

    def _snapshot_run(self) -> None:
        """In a batch run that asks for it (SARSP_EDU_SNAPSHOT_EPISODES), run that many episodes for the picture."""
        episodes = int(os.environ.get(SNAPSHOT_VARIABLE, "0") or 0)
        if episodes > 0 and self.experiments is None and not self.running:
            self.build_runs()
            self.fast_forward(min(episodes, self.config().episodes))

    def _repr_mimebundle_(self, **kwargs):
        bundle = dict(super()._repr_mimebundle_(**kwargs))
        self._snapshot_run()
        if not os.environ.get("VOILA_KERNEL_ID"):
            bundle["image/png"] = base64.b64encode(self.snapshot()).decode("ascii")
        if self.autoplay and not self._autoplayed and os.environ.get(AUTOPLAY_VARIABLE, "1") != "0":
            self._autoplayed = True
            self.play_in_background()
        return bundle, alt_metadata(self.alt_text())


class LiveMetrics:
    """The live dashboard's metric curves (a mixin): drawn when an episode ends, sized for the projector."""

    def _size_metrics_figure(self) -> None:
        """The metric curves' figure: in projector size PROJECTOR_SCALE times narrower in inches, its text
        the same in points, so that the text is that much larger in the page's full width."""
        width, height = (14 / PROJECTOR_SCALE, 2.6) if self.projector else (14, 2.5)
        self.metrics_figure.set_size_inches(width, height)
        self.metrics_figure.subplots_adjust(left=0.5 / width, right=1 - 0.15 / width, bottom=0.5 / height,
                                            top=1 - 0.35 / height, wspace=0.32 if self.projector else 0.28)

    def show_metrics(self, throttle: bool = False) -> None:
        """Redraw the metric curves if an episode ended; while animating (``throttle``), at most every 1.5 s."""
        if self.experiments is None:
            return
        count = sum(len(e.episodes) for e in self.experiments.values())
        if (len(self.experiments), count) == self._drawn_key:
            return
        now = time.perf_counter()
        if throttle and now - self._metrics_drawn_at < 1.5 and not self.finished:
            return
        self._drawn_key = (len(self.experiments), count)
        self._metrics_drawn_at = now
        for ax in self.metrics_axes:
            wipe_axes(ax)
        plotting.plot_live_metrics(self.metrics_axes, _records_in_side_order(self),
                                   LIVE_METRICS, labels=self._legend_labels())
        svg = render_figure(self.metrics_figure, "svg")
        self.metrics_image.value = markup.labelled_svg(svg, metrics_alt_text(self))
        self.metrics_image.layout.display = None

    @property
    def metrics_shown(self) -> bool:
        """Whether the metric curves are on show (an episode has ended since the run began)."""
        return self._drawn_key is not None and self._drawn_key[1] > 0

    def _legend_labels(self) -> dict | None:
        # a side that changes the model alone is named by it (a pick changes it); any other by its short name
        return None if self.sides == TP_AND_GP else {
            name: title if set(changes) == {"model"} else name for name, (title, changes) in self.sides.items()}
