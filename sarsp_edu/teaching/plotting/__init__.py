"""Drawing functions: ``plot_*(ax, data)`` draws what it is handed and keeps no state.

One module per subject, all re-exported here (``sarsp_edu.teaching.plotting.plot_*``):

- ``style``: the shared colours and line styles, log axes with plain labels, the usual finish;
- ``display``: ``show_figure(figure, alt)``, a figure shown with a description for a screen reader;
- ``models``: densities and tail ratios (tutorial 1), GP and TP posteriors (tutorial 2);
- ``world``: the gridworld and the cost model's data (tutorials 3 and 4);
- ``results``: the paper's Figures 2-9, the live dashboard's curves and ours beside the authors' runs
  (tutorials 4 and 5);
- ``third_model``: the GP with Student-t noise beside the TP and the GP: learning curves, the threshold study
  (tutorial 6).
"""

from __future__ import annotations

from .display import show_figure
from .models import (
    plot_densities,
    plot_gaussian_ratio,
    plot_outlier_weights,
    plot_posterior,
    plot_robust,
    plot_tail_ratio_comparison,
    plot_tail_ratios,
    plot_variances,
)
from .results import (
    METRIC_LABELS,
    plot_ablation_runs,
    plot_beside_authors,
    plot_curves_by_model,
    plot_learning_curves_beside_authors,
    plot_live_metrics,
    plot_macro,
    plot_metric_curves,
    plot_paper_figure,
)
from .style import COLOURS, LINESTYLES, MARKERS, PlainLogFormatter, log_scale
from .third_model import plot_model_curves, plot_rule_study, plot_threshold_study
from .world import plot_gridworld, plot_outlier_scatter

__all__ = [
    "COLOURS",
    "LINESTYLES",
    "MARKERS",
    "METRIC_LABELS",
    "PlainLogFormatter",
    "log_scale",
    "plot_ablation_runs",
    "plot_beside_authors",
    "plot_curves_by_model",
    "plot_densities",
    "plot_gaussian_ratio",
    "plot_gridworld",
    "plot_learning_curves_beside_authors",
    "plot_live_metrics",
    "plot_macro",
    "plot_metric_curves",
    "plot_model_curves",
    "plot_outlier_scatter",
    "plot_paper_figure",
    "plot_rule_study",
    "plot_threshold_study",
    "plot_outlier_weights",
    "plot_robust",
    "plot_posterior",
    "plot_tail_ratio_comparison",
    "plot_tail_ratios",
    "plot_variances",
    "show_figure",
]
