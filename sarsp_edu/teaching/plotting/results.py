"""The paper's result figures: running metrics per episode (Figures 2-7), macro averages (8-9), live curves."""

from __future__ import annotations

import numpy as np

from .style import COLOURS, LINESTYLES, MARKERS, SMALL

__all__ = [
    "METRIC_LABELS",
    "plot_ablation_runs",
    "plot_beside_authors",
    "plot_curves_by_model",
    "plot_learning_curves_beside_authors",
    "plot_live_metrics",
    "plot_macro",
    "plot_metric_curves",
    "plot_paper_figure",
]

#: axis labels of the summary metrics, in the paper's symbols
METRIC_LABELS = {
    "mean_reward": "mean reward $J_r$",
    "mean_cost": "mean cost $\\mu_{cost}$",
    "total_cost": "total cost $\\Sigma_{cost}$",
    "task_success_rate": "task success rate TSR (%)",
    "mean_steps": "mean steps $\\mu_{steps}$",
    "cost_rate": "cost rate $p_c$",
}


def plot_metric_curves(ax, curves, *, metric: str, title: str | None = None, legend: bool = True,
                       settle: int = 0, band=None):
    """Per-episode values of a metric, one line per number of switch states (Figures 2-7).

    Parameters
    ----------
    ax : matplotlib Axes
    curves : pandas.DataFrame
        Index: episode; one column per nss (``SweepResults.curves``).
    metric : str
        A summary metric name, for the axis label.
    settle : int, default 0
        Set the y range from the episodes after this one: a running mean
        swings widely over its first few episodes, and a range set by those
        swings flattens the rest.  The early curve is still drawn (clipped),
        and the Axes says so.
    band : (DataFrame, DataFrame), optional
        The lowest and highest value at each episode (``SweepResults.curves``
        with ``over_seeds="min"`` and ``"max"``), shaded around each line.
    """
    from matplotlib import colormaps

    columns = list(curves.columns)
    cmap = colormaps["viridis"]
    for i, column in enumerate(columns):
        colour = cmap(i / max(len(columns) - 1, 1) * 0.9)
        ax.plot(curves.index, curves[column], color=colour, lw=1.6, label=f"nss = {column}")
        if band is not None:
            ax.fill_between(curves.index, band[0][column], band[1][column], color=colour, alpha=0.15, lw=0)
    if settle:
        _settled_ylim([ax], [curves] if band is None else [curves, *band], settle)
    ax.set_xlabel("episode")
    ax.set_ylabel(METRIC_LABELS.get(metric, metric))
    ax.grid(alpha=0.3)
    if legend:
        ax.legend(fontsize=SMALL, frameon=False)
    if title:
        ax.set_title(title)
    return ax


def plot_live_metrics(axes, records, metrics, *, labels=None, colours=None):
    """Running metrics of two or more runs side by side, one Axes per metric (the live dashboards).

    Parameters
    ----------
    axes : sequence of matplotlib Axes, one per metric
    records : dict
        Name -> the per-episode records of a run (``Experiment.records()``),
        which may be empty; e.g. ``{"tp": frame, "gp": frame}``.
    metrics : sequence of str
        Columns of the records.
    labels, colours : dict, optional
        Name -> legend label and colour; by default the name in capitals and
        the package's colour of that name (``"tp"``, ``"gp"``), else the
        matplotlib cycle.

    Each run has its own line style and marker as well as its colour: the
    package's of ``"tp"`` and ``"gp"`` (the GP dashed, drawn on top), else
    solid then dashed in the order of ``records``.
    """
    labels = labels or {}
    colours = colours or {}
    for ax, metric in zip(axes, metrics):
        for i, (name, frame) in enumerate(records.items()):
            if len(frame):
                colour = colours.get(name, COLOURS.get(name, f"C{i}"))
                key = name if name in LINESTYLES else ("tp", "gp")[i % 2]
                ax.plot(frame["episode"], frame[metric], color=colour, lw=2, ls=LINESTYLES[key],
                        zorder=2 + 0.5 * (key == "gp"), marker=MARKERS[key] if len(frame) < 15 else None, ms=4,
                        label=labels.get(name, name.upper()))
        ax.set_title(metric.replace("_", " "), fontsize=10)
        ax.set_xlabel("episode", fontsize=SMALL)
        ax.tick_params(labelsize=SMALL)
        ax.grid(alpha=0.3)
    if axes[0].lines:
        axes[0].legend(fontsize=SMALL, frameon=False)
    return axes


def _settled_ylim(axes, frames, settle: int) -> None:
    """One y range for ``axes``, from the values of ``frames`` after episode ``settle``, said on each Axes."""
    later = np.concatenate([f[f.index > settle].to_numpy(dtype=float).ravel() for f in frames])
    low, high = float(np.nanmin(later)), float(np.nanmax(later))
    pad = 0.08 * (high - low) if high > low else max(abs(high), 1.0) * 0.1
    for ax in axes:
        ax.set_ylim(low - pad, high + pad)
        ax.text(0.01, 0.01, f"y range from episode {settle + 1}", transform=ax.transAxes, fontsize=SMALL,
                color="#666666", va="bottom")


def plot_curves_by_model(axes, curves, *, metric: str, settle: int = 0):
    """Figures 2-7 as the paper lays them out: the TP's curves beside the GP's, on one y range.

    Parameters
    ----------
    axes : two matplotlib Axes
    curves : dict
        ``{"TP": frame, "GP": frame}``, each as :func:`plot_metric_curves` takes.
    metric : str
    settle : int, default 0
        As in :func:`plot_metric_curves`, over both models' curves.
    """
    for ax, model in zip(axes, ("TP", "GP")):
        plot_metric_curves(ax, curves[model], metric=metric, title=model, legend=(model == "GP"))
    if settle:
        _settled_ylim(axes, [curves["TP"], curves["GP"]], settle)
    return axes


def plot_paper_figure(axes, figure: int, results, authors=None, *, settle: int = 10):
    """One of the paper's Figures 2-7 redrawn: ours over seeds (mean and band) above the authors' one run.

    Parameters
    ----------
    axes : 2 x 2 array of matplotlib Axes
        Top row: our runs, the TP (a) and the GP (b), a line per nss at the
        mean over the sweep's seeds and a band from its lowest to its highest
        seed.  Bottom row: the authors' one run per configuration, from which
        the paper drew the figure.  All four share one y range.
    figure : int
        2 to 7: the metric and (m, p) of ``sarsp_edu.paper.FIGURES``.
    results : SweepResults
        A sweep holding the figure's (m, p).
    authors : AuthorsRuns, optional
        By default the package's copy of the authors' runs.
    settle : int, default 10
        As in :func:`plot_metric_curves`, over all four panels.
    """
    from ...paper import published as paper
    from ...paper.authors import AuthorsRuns

    if figure not in paper.FIGURES:
        raise ValueError(f"figure must be one of the paper's Figures {min(paper.FIGURES)}-{max(paper.FIGURES)}, "
                         f"got figure={figure!r}")
    metric, m, p = paper.FIGURES[figure]
    authors = AuthorsRuns() if authors is None else authors
    seeds = sorted({key[3] for key in results.comparisons if np.isclose(key[0], m) and np.isclose(key[1], p)})
    frames = []
    for column, model in enumerate(("TP", "GP")):
        mean = results.curves(metric, model, m, p)
        band = None
        if len(seeds) > 1:
            band = (results.curves(metric, model, m, p, over_seeds="min"),
                    results.curves(metric, model, m, p, over_seeds="max"))
        theirs = authors.curves(metric, model, m, p)
        letter = "ab"[column]
        plot_metric_curves(axes[0][column], mean, metric=metric, band=band, legend=(model == "GP"),
                           title=f"({letter}) {model}, ours: mean of {len(seeds)} seed{'s' * (len(seeds) > 1)}"
                                 + (", band from lowest to highest" if band else ""))
        plot_metric_curves(axes[1][column], theirs, metric=metric, legend=False,
                           title=f"({letter}) {model}, the authors' one run (the paper's figure)")
        frames += [mean, theirs] + (list(band) if band else [])
    flat = [axes[row][column] for row in (0, 1) for column in (0, 1)]
    if settle:
        _settled_ylim(flat, frames, settle)
    else:
        low = min(ax.get_ylim()[0] for ax in flat)
        high = max(ax.get_ylim()[1] for ax in flat)
        for ax in flat:
            ax.set_ylim(low, high)
    axes[0][0].figure.suptitle(f"Figure {figure}: m = {m:g}, p = {p:g}, nss = 2-10")
    return axes


def plot_macro(ax, frame, *, metric: str, title: str | None = None):
    """A metric averaged over outlier settings, against nss, TP beside GP (Figures 8-9); the y axis includes 0.

    Parameters
    ----------
    ax : matplotlib Axes
    frame : pandas.DataFrame
        Index: nss; columns ``TP`` and ``GP`` (``SweepResults.macro``).
    """
    for model in ("TP", "GP"):
        if model in frame:
            ax.plot(frame.index, frame[model], marker=MARKERS[model.lower()], ls=LINESTYLES[model.lower()], lw=2,
                    color=COLOURS[model.lower()], label=model)
    # the axis reaches 0, so that the gap between the lines is read against the values themselves
    low, high = ax.get_ylim()
    ax.set_ylim(min(low, 0.0), max(high, 0.0))
    ax.set_xlabel("number of switch states nss")
    ax.set_xticks(list(frame.index))
    ax.set_ylabel(METRIC_LABELS.get(metric, metric))
    ax.grid(alpha=0.3)
    ax.legend(frameon=False)
    if title:
        ax.set_title(title)
    return ax


#: the ablation's per-run measures, as axis labels
ABLATION_LABELS = {
    "task_success_rate": "task success rate TSR (%)",
    "total_cost": "total cost (violations)",
    "trapped_share": "failures that ended trapped (%)",
    "backup_share": "decisions by the backup rule (%)",
}


def plot_ablation_runs(ax, runs, metric: str, *, title: str | None = None, ylim=None):
    """One ablation setting's runs: a dot per (configuration, seed) run and a bar at the mean, TP beside GP.

    Parameters
    ----------
    ax : matplotlib Axes
    runs : pandas.DataFrame
        ``AblationResults.runs()`` rows of one setting (``model``, the metric;
        for ``"trapped_share"``, ``failures`` and ``trapped_failures``).
    metric : str
        A column of ``runs``, or ``"trapped_share"``: trapped failures over
        failures, pooled over the runs.
    ylim : (float, float), optional
        Fixed limits, so that moving between settings compares like with like.

    When ``runs`` hold one setting (a ``setting`` column with one value), the
    title names it after ``title``: "violations: per step, 500 rows" (the
    settings of ``ablation.PRIOR_AND_FITS`` by their two choices).
    """
    for i, model in enumerate(("TP", "GP")):
        part = runs[runs["model"] == model]
        if not len(part):
            continue
        if metric == "trapped_share":
            failures = part["failures"].to_numpy(dtype=float)
            values = np.divide(100.0 * part["trapped_failures"].to_numpy(dtype=float), failures,
                               out=np.full(len(part), np.nan), where=failures > 0)
            mean = 100.0 * part["trapped_failures"].sum() / max(part["failures"].sum(), 1)
        else:
            values = part[metric].to_numpy(dtype=float)
            mean = float(np.nanmean(values))
        ax.bar(i, mean, width=0.6, color=COLOURS[model.lower()], alpha=0.35)
        jitter = np.linspace(-0.15, 0.15, len(values)) if len(values) > 1 else np.zeros(1)
        ax.scatter(i + jitter, values, s=18, color=COLOURS[model.lower()], marker=MARKERS[model.lower()], zorder=3)
        ax.text(i, mean, f"{mean:.0f}", ha="center", va="bottom", fontsize=SMALL)
    ax.set_xticks([0, 1])
    ax.set_xticklabels(["TP", "GP"])
    ax.set_xlim(-0.6, 1.6)
    if ylim is not None:
        ax.set_ylim(*ylim)
    ax.set_ylabel(ABLATION_LABELS.get(metric, metric))
    ax.grid(alpha=0.3, axis="y")
    settings = runs["setting"].unique() if "setting" in runs else ()
    if len(settings) == 1:
        from ...experiments.ablation import PRIOR_AND_FITS

        short = {name: f"{prior}, {fits}" for (prior, fits), name in PRIOR_AND_FITS.items()}
        setting = short.get(settings[0], settings[0])
        title = f"{title}: {setting}" if title else setting
    if title:
        ax.set_title(title, fontsize=SMALL if len(settings) == 1 else None)
    return ax


def plot_beside_authors(ax, table, *, metric: str, label: str = "ours"):
    """Per configuration, our value against the authors': a dot per configuration and model, the diagonal.

    Parameters
    ----------
    ax : matplotlib Axes
    table : pandas.DataFrame
        :func:`sarsp_edu.paper.authors.beside_authors` (columns ``ours TP``,
        ``authors TP``, ``ours GP``, ``authors GP``).
    metric : str
        For the axis labels.
    label : str, default "ours"
        What our runs are, for the y axis (e.g. "ours, reference preset").
    """
    values = [table[f"{who} {model}"].to_numpy(dtype=float) for who in ("ours", "authors") for model in ("TP", "GP")]
    low, high = float(np.nanmin(values)), float(np.nanmax(values))
    pad = 0.05 * (high - low) if high > low else 1.0
    ax.plot([low - pad, high + pad], [low - pad, high + pad], color="#888888", lw=1, zorder=1,
            label="ours = the authors'")
    for model in ("TP", "GP"):
        ax.scatter(table[f"authors {model}"], table[f"ours {model}"], s=22, alpha=0.8,
                   color=COLOURS[model.lower()], marker=MARKERS[model.lower()], label=model, zorder=3)
    ax.set_xlim(low - pad, high + pad)
    ax.set_ylim(low - pad, high + pad)
    ax.set_aspect("equal")
    name = METRIC_LABELS.get(metric, metric)
    ax.set_xlabel(f"the authors' run: {name}")
    ax.set_ylabel(f"{label}: {name}")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=SMALL, frameon=False)
    return ax


#: how each model's band over seeds is hatched, so that overlapping bands both stay visible
_BAND_HATCH = {"TP": "", "GP": "////"}


def plot_learning_curves_beside_authors(ax, curves, *, metric: str, label: str = "ours", settle: int = 0,
                                        legend: bool = True):
    """A running metric per episode, mean over configurations: ours (band over seeds) beside the authors'.

    Each model's band runs from its lowest to its highest seed.  It is drawn
    translucent with its edges outlined, and the GP's is hatched, so where the
    two models' bands overlap both stay visible; the legend names every line
    and band.  Our means are solid, the authors' dashed; the model's marker
    (the TP's circles, the GP's squares) sits on both at a tenth of the episodes.

    Parameters
    ----------
    ax : matplotlib Axes
    curves : pandas.DataFrame
        :func:`sarsp_edu.paper.authors.learning_curves`.
    metric : str
        For the y label.
    label : str, default "ours"
        What our runs are, for the legend (e.g. "ours, 3 seeds").
    settle : int, default 0
        As in :func:`plot_metric_curves`.
    legend : bool, default True
        Draw the legend on ``ax``; with False, take ``ax.get_legend_handles_labels()``
        for one legend shared by several Axes.
    """
    from matplotlib.colors import to_rgba

    every = max(len(curves) // 10, 1)
    for model in ("TP", "GP"):
        colour = COLOURS[model.lower()]
        marks = {"marker": MARKERS[model.lower()], "ms": 5, "markevery": (every // 2 if model == "GP" else 0, every)}
        low, high = curves[f"ours {model} low"], curves[f"ours {model} high"]
        if not np.allclose(low, high, equal_nan=True):
            ax.fill_between(curves.index, low, high, facecolor=to_rgba(colour, 0.12),
                            edgecolor=to_rgba(colour, 0.55), lw=0.7, hatch=_BAND_HATCH[model],
                            label=f"{model}, {label}: lowest to highest seed")
        ax.plot(curves.index, curves[f"ours {model}"], color=colour, lw=2, label=f"{model}, {label}: mean", **marks)
        ax.plot(curves.index, curves[f"authors {model}"], color=colour, lw=1.6, ls="--",
                label=f"{model}, the authors' runs", markerfacecolor="white", **marks)
    if settle:
        _settled_ylim([ax], [curves], settle)
    ax.set_xlabel("episode")
    ax.set_ylabel(METRIC_LABELS.get(metric, metric))
    ax.grid(alpha=0.3)
    if legend:
        ax.legend(fontsize=SMALL, frameon=False)
    return ax
