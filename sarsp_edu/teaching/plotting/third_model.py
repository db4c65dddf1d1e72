"""Beyond the paper: the GP with Student-t noise beside the TP and the GP (learning curves, the threshold study,
the rule study)."""

from __future__ import annotations

from .results import METRIC_LABELS, _settled_ylim
from .style import COLOURS, LINESTYLES, MARKERS, SMALL, finish_axes, log_scale

__all__ = ["plot_model_curves", "plot_rule_study", "plot_threshold_study"]

#: the style keys of the threshold study's models (the GP with Student-t noise is drawn as "robust" everywhere)
_STUDY_STYLES = {"TP": "tp", "GP": "gp", "t-likelihood GP": "robust"}
_STUDY_LABELS = {"backup_share": "decisions by the backup rule (%)", "total_cost": METRIC_LABELS["total_cost"],
                 "task_success_rate": METRIC_LABELS["task_success_rate"], "mean_steps": METRIC_LABELS["mean_steps"]}


def plot_threshold_study(axes, runs, *, measures=("backup_share", "total_cost", "task_success_rate"),
                         reference_threshold: float = 0.8):
    """Each model's runs (faint dots) and their mean (a line) against the variance threshold sigma*^2.

    The runs mix the ablation's configurations, whose levels differ more than a run's noise: the dots show
    that spread, which a t-interval over so few runs would hide behind a band wider than the measure's range.

    Parameters
    ----------
    axes : sequence of matplotlib Axes
        One per measure.
    runs : pandas.DataFrame
        :attr:`~sarsp_edu.experiments.thresholds.ThresholdStudy.runs`: ``threshold``, ``model`` and the
        measures, a row per run.
    measures : sequence of str
        Columns of ``runs`` to draw.
    reference_threshold : float, default 0.8
        Marked with a dotted line: the reference code's sigma*^2 (the paper prints no value; it calls the
        threshold "empirically estimated").
    """
    present = set(runs["model"])
    models = [m for m in _STUDY_STYLES if m in present] + sorted(present - set(_STUDY_STYLES))
    for ax, measure in zip(axes, measures):
        for i, model in enumerate(models):
            part = runs[runs["model"] == model]
            key = _STUDY_STYLES.get(model, "tp")
            shift = 1.0 + 0.06 * (i - (len(models) - 1) / 2)  # the models' dots side by side on the log axis
            ax.scatter(part["threshold"] * shift, part[measure], s=14, color=COLOURS[key], marker=MARKERS[key],
                       alpha=0.35, lw=0)
            mean = part.groupby("threshold")[measure].mean()
            ax.plot(mean.index * shift, mean.to_numpy(), color=COLOURS[key], ls=LINESTYLES[key],
                    marker=MARKERS[key], lw=1.8, label=model)
        ax.axvline(reference_threshold, color="0.4", ls=":", lw=1.2)
        ax.annotate(f"the reference code's {reference_threshold:g}", (reference_threshold, 1.0),
                    xycoords=("data", "axes fraction"), xytext=(3, -3), textcoords="offset points", ha="left",
                    va="top", fontsize=SMALL, color="0.3")
        log_scale(ax, "x")
        finish_axes(ax, "variance threshold $\\sigma_*^2$", _STUDY_LABELS.get(measure, measure),
                    _STUDY_LABELS.get(measure, measure).split(" (")[0].split(" $")[0])
        if ax is not axes[0]:
            ax.get_legend().remove()
    return axes


def plot_model_curves(ax, curves, *, metric: str, title: str | None = None, settle: int = 0):
    """Learning curves of two or three models on one Axes, each in its own colour, line style and markers.

    Parameters
    ----------
    ax : matplotlib Axes
    curves : pandas.DataFrame
        Indexed by episode, a column per model ("TP", "GP", "t-likelihood GP";
        :func:`~sarsp_edu.experiments.sweep.model_tables.model_sweep_curves`).
    metric : str
        A summary metric name, for the axis label.
    settle : int, default 0
        As in :func:`plot_metric_curves`.
    """
    for model in curves.columns:
        key = _STUDY_STYLES.get(model, "tp")
        ax.plot(curves.index, curves[model], color=COLOURS[key], ls=LINESTYLES[key], lw=1.8, label=model,
                marker=MARKERS[key], markevery=max(len(curves) // 8, 1))
    if settle and len(curves) > settle:  # a run of fewer episodes has nothing to settle on
        _settled_ylim([ax], [curves], settle)
    finish_axes(ax, "episode", METRIC_LABELS.get(metric, metric), title or "")
    return ax


def plot_rule_study(axes, runs, *, measures=("total_cost", "backup_share", "task_success_rate")):
    """Each setting's runs (faint dots) and their mean (a marker) per model, the settings down the vertical axis.

    One row of dots per setting and model: the six runs of a setting mix three configurations, whose levels
    differ more than a run's noise, and the dots show that spread as it is.

    Parameters
    ----------
    axes : sequence of matplotlib Axes
        One per measure.
    runs : pandas.DataFrame
        :attr:`~sarsp_edu.experiments.rules.RuleStudy.runs` (of one question or several): ``setting``,
        ``model`` and the measures, a row per run.
    measures : sequence of str
        Columns of ``runs`` to draw.
    """
    settings = list(dict.fromkeys(runs["setting"]))
    present = set(runs["model"])
    models = [m for m in _STUDY_STYLES if m in present] + sorted(present - set(_STUDY_STYLES))
    for ax, measure in zip(axes, measures):
        for i, model in enumerate(models):
            key = _STUDY_STYLES.get(model, "tp")
            offset = 0.22 * (i - (len(models) - 1) / 2)  # the models' rows side by side within a setting
            part = runs[runs["model"] == model]
            rows = [settings.index(s) + offset for s in part["setting"]]
            ax.scatter(part[measure], rows, s=14, color=COLOURS[key], marker=MARKERS[key], alpha=0.35, lw=0)
            mean = part.groupby("setting", sort=False)[measure].mean()
            ax.scatter(mean.to_numpy(), [settings.index(s) + offset for s in mean.index], s=46,
                       color=COLOURS[key], marker=MARKERS[key], label=model, zorder=3)
        ax.set_yticks(range(len(settings)))
        ax.set_yticklabels(settings if ax is axes[0] else [""] * len(settings))
        ax.invert_yaxis()
        finish_axes(ax, _STUDY_LABELS.get(measure, measure), "", _STUDY_LABELS.get(measure, measure).split(" (")[0])
        if ax is not axes[0] and ax.get_legend() is not None:
            ax.get_legend().remove()
    return axes
