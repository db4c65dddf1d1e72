"""The live dashboard as one static picture: what a stored notebook, a static page or a handout shows of it."""

from __future__ import annotations

from matplotlib.figure import Figure

from .. import plotting
from ..dashboards.framework import SNAPSHOT_WIDTH_PX, readable_png

__all__ = ["first_episode", "picture", "picture_alt_text"]

#: the metrics the live dashboard draws, episode by episode
LIVE_METRICS = ("mean_reward", "total_cost", "task_success_rate", "mean_steps", "cost_rate")


def first_episode(prepared):
    """The world the sliders imply, its agent at the first episode's start (its goal too), not where the
    offline episodes left it.  ``prepared`` is the preview's own copy: resetting it changes no run."""
    prepared.env.reset(seed=int(prepared.episode_seeds[0]))
    return prepared.env.layout()


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
    if bottom is not None and dashboard._drawn_episodes > 0:
        axes = bottom.subplots(1, len(LIVE_METRICS))
        plotting.plot_live_metrics(axes, {m: e.records() for m, e in dashboard.experiments.items()},
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
        if dashboard._drawn_episodes > 0:
            text += ("; below, both agents' running metrics against the episode ("
                     + ", ".join(metric.replace("_", " ") for metric in LIVE_METRICS)
                     + "), the left side's solid with circles, the right side's dashed with squares")
    return text + "."
