"""Drawing functions: ``plot_*(ax, data)`` draws what it is handed and keeps no state."""

from __future__ import annotations

import numpy as np
from matplotlib import patches, ticker
from matplotlib.collections import LineCollection, PatchCollection

from .config import ACTION_MOVES

__all__ = [
    "plot_gridworld",
    "plot_metric_curves",
    "plot_macro",
    "plot_densities",
    "plot_tail_ratios",
    "plot_gaussian_ratio",
    "plot_posterior",
    "plot_variances",
    "plot_outlier_scatter",
    "plot_live_metrics",
    "plot_curves_by_model",
    "plot_tail_ratio_comparison",
    "METRIC_LABELS",
    "COLOURS",
]

#: colours shared by every figure of the package
COLOURS = {
    "unsafe": "#d62728",
    "moved": "#ff9896",
    "goal": "#2ca02c",
    "start": "#1f77b4",
    "agent": "#1f77b4",
    "path": "#17becf",
    "gp": "#ff7f0e",
    "tp": "#1f77b4",
    "grid": "#c8c8c8",
}


class _PlainLogFormatter(ticker.Formatter):
    """Tick labels of a log axis as plain numbers ("0.5", "20") from 0.001 to 10,000, else as "1e-06".

    matplotlib's default labels are mathtext, whose parsing was a sixth of a
    dashboard redraw.  With ``minor=True`` the ticks at 2 and 5 times a power
    of ten are labelled when the axis spans less than two decades, so a short
    axis never shows a single number.
    """

    def __init__(self, minor: bool = False):
        self.minor = minor

    def __call__(self, value, pos=None):
        if value <= 0:
            return ""
        if self.minor:
            low, high = sorted(abs(v) for v in self.axis.get_view_interval())
            mantissa = round(value / 10 ** np.floor(np.log10(value)), 6)
            if low <= 0 or high / low >= 100 or mantissa not in (2.0, 5.0):
                return ""
        if 1e-3 <= value < 1e4:
            return f"{value:g}"
        return f"{value:.0e}".replace("e-0", "e-").replace("e+0", "e")


def log_scale(ax, axis: str = "y") -> None:
    """A log axis with plain tick labels ("0.5", "20", "1e-06"), minor ticks at 2 and 5
    times each power of ten (labelled on a short axis)."""
    target = ax.yaxis if axis == "y" else ax.xaxis
    (ax.set_yscale if axis == "y" else ax.set_xscale)("log")
    target.set_minor_locator(ticker.LogLocator(subs=(2.0, 5.0)))
    target.set_major_formatter(_PlainLogFormatter())
    target.set_minor_formatter(_PlainLogFormatter(minor=True))


def _finish(ax, xlabel: str, ylabel: str, title: str, legend_loc="best") -> None:
    """The labels, light grid and frameless legend every line plot here ends with."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, frameon=False, loc=legend_loc)
    ax.set_title(title)


def _layout_of(world):
    return world.layout() if hasattr(world, "layout") else world


def plot_gridworld(
    ax,
    world,
    *,
    trajectory=None,
    show_moved: bool = True,
    visits=None,
    unsafe_pairs=None,
    show_agent: bool = False,
    legend: bool = True,
    title: str | None = None,
    colorbar: bool = False,
):
    """Draw a :class:`~sarsp_edu.SafeGridWorld`: unsafe states, start, goal, the shift.

    Parameters
    ----------
    ax : matplotlib Axes
    world : GridLayout or SafeGridWorld
        A snapshot (``env.layout()``) or the environment itself.
    trajectory : array-like of shape (T, 2), optional
        Cells ``(x, y)`` visited in order, drawn as a path.
    show_moved : bool, default True
        Mark the states moved by the last shift: their old cells dashed, an
        arrow to the new cell.
    visits : ndarray of shape (size, size), optional
        Visit counts indexed [y, x] (for example ``OfflineData.visits``),
        drawn as a grey heat map under everything else.
    unsafe_pairs : iterable of ((x, y), action), optional
        State-action pairs known to be unsafe (SARSP's ``S_u``); each is
        drawn as a short red tick from the cell towards the move.
    show_agent : bool, default False
        Mark the agent's current cell.
    legend : bool, default True
    title : str, optional
    colorbar : bool, default False
        With ``visits``, add a colour bar of the visit counts beside the Axes
        (for a figure drawn once: a redrawn Axes would gain a bar each time).

    Returns
    -------
    ax
    """
    layout = _layout_of(world)
    n = layout.size
    ax.set_xlim(-0.5, n - 0.5)
    ax.set_ylim(n - 0.5, -0.5)  # row 0 at the top: DOWN is +y
    ax.set_aspect("equal")
    ax.set_xticks(range(n))
    ax.set_yticks(range(n))
    ax.tick_params(length=0, labelsize=8)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    # One artist per kind of thing (a collection), not one per cell: a
    # dashboard redraws this at every slider move.
    edges = np.arange(n + 1) - 0.5
    ax.vlines(edges, -0.5, n - 0.5, color=COLOURS["grid"], lw=0.6, zorder=1)
    ax.hlines(edges, -0.5, n - 0.5, color=COLOURS["grid"], lw=0.6, zorder=1)
    if visits is not None:
        visits = np.asarray(visits, dtype=float)
        shading = ax.imshow(visits, cmap="Greys", alpha=0.55, zorder=0, origin="upper",
                            extent=(-0.5, n - 0.5, n - 0.5, -0.5), vmin=0, vmax=max(visits.max(), 1))
        if colorbar:
            ax.figure.colorbar(shading, ax=ax, fraction=0.046, pad=0.03, label="offline visits of the cell")

    moved = set(int(i) for i in layout.moved) if show_moved else set()
    handles = {}
    styles = {
        False: dict(facecolor=COLOURS["unsafe"], edgecolor=COLOURS["unsafe"], lw=0.5),
        True: dict(facecolor=COLOURS["unsafe"], edgecolor="black", lw=1.8),
    }
    is_moved = [i in moved for i in range(len(layout.unsafe_states))]
    if len(layout.unsafe_states):
        squares = [patches.Rectangle((x - 0.45, y - 0.45), 0.9, 0.9) for x, y in layout.unsafe_states]
        ax.add_collection(PatchCollection(
            squares, zorder=3, facecolors=COLOURS["unsafe"],
            edgecolors=[styles[m]["edgecolor"] for m in is_moved], linewidths=[styles[m]["lw"] for m in is_moved],
        ), autolim=False)
    for flag in sorted(set(is_moved)):
        handles["moved here in the shift" if flag else "unsafe state"] = patches.Patch(**styles[flag])
    if show_moved and len(layout.moved):
        ax.add_collection(PatchCollection(
            [patches.Rectangle((ox - 0.42, oy - 0.42), 0.84, 0.84) for ox, oy in layout.moved_from],
            zorder=3, facecolors="none", edgecolors=COLOURS["unsafe"], linewidths=1.4, linestyles="--",
        ), autolim=False)
        handles["unsafe before the shift"] = patches.Patch(facecolor="none", edgecolor=COLOURS["unsafe"], lw=1.4,
                                                           ls="--")
        for i, (ox, oy) in zip(layout.moved, layout.moved_from):
            nx, ny = layout.unsafe_states[int(i)]
            # curved, so that crossing moves stay apart
            ax.add_artist(patches.FancyArrowPatch(
                (ox, oy), (nx, ny), arrowstyle="->", mutation_scale=10, color="black", lw=0.9, alpha=0.5,
                shrinkA=6, shrinkB=8, zorder=4, connectionstyle="arc3,rad=0.25"))
    if unsafe_pairs:
        ticks = []
        for (cx, cy), action in unsafe_pairs:
            dx, dy = ACTION_MOVES[int(action)]
            ticks.append([(cx + 0.1 * dx, cy + 0.1 * dy), (cx + 0.42 * dx, cy + 0.42 * dy)])
        handles["learned unsafe move (S_u)"] = ax.add_collection(LineCollection(
            ticks, colors=COLOURS["unsafe"], linewidths=2.5, capstyle="butt", zorder=6), autolim=False)
    if trajectory is not None:
        path = np.asarray(trajectory, dtype=float).reshape(-1, 2)
        if len(path):
            line, = ax.plot(path[:, 0], path[:, 1], color=COLOURS["path"], lw=2, alpha=0.9,
                            marker="o", ms=3, zorder=5)
            handles["path"] = line
    if layout.start is not None:
        handles["start"] = ax.scatter(*layout.start, s=140, marker="o", facecolor="white",
                                      edgecolor=COLOURS["start"], lw=2.5, zorder=7)
    if layout.goal is not None:
        handles["goal"] = ax.scatter(*layout.goal, s=260, marker="*", color=COLOURS["goal"],
                                     edgecolor="black", lw=0.6, zorder=7)
    if show_agent and layout.agent is not None:
        handles["agent"] = ax.scatter(*layout.agent, s=90, marker="o", color=COLOURS["agent"],
                                      edgecolor="white", lw=1.2, zorder=8)
    if legend:
        ax.legend(handles.values(), handles.keys(), loc="upper left", bbox_to_anchor=(1.02, 1.0),
                  fontsize=8, frameon=False, borderaxespad=0)
    if title:
        ax.set_title(title)
    return ax


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
                       settle: int = 0):
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
    """
    from matplotlib import colormaps

    columns = list(curves.columns)
    cmap = colormaps["viridis"]
    for i, column in enumerate(columns):
        colour = cmap(i / max(len(columns) - 1, 1) * 0.9)
        ax.plot(curves.index, curves[column], color=colour, lw=1.6, label=f"nss = {column}")
    if settle:
        _settled_ylim([ax], [curves], settle)
    ax.set_xlabel("episode")
    ax.set_ylabel(METRIC_LABELS.get(metric, metric))
    ax.grid(alpha=0.3)
    if legend:
        ax.legend(fontsize=8, frameon=False)
    if title:
        ax.set_title(title)
    return ax


def plot_live_metrics(axes, records, metrics):
    """Running metrics of a TP and a GP run, one Axes per metric (tutorial 4's live dashboard).

    Parameters
    ----------
    axes : sequence of matplotlib Axes, one per metric
    records : dict
        ``{"tp": frame, "gp": frame}``, each the per-episode records of a run
        (``Experiment.records()``), which may be empty.
    metrics : sequence of str
        Columns of the records.
    """
    for ax, metric in zip(axes, metrics):
        for model in ("tp", "gp"):
            frame = records[model]
            if len(frame):
                ax.plot(frame["episode"], frame[metric], color=COLOURS[model], lw=2,
                        marker="o" if len(frame) < 15 else None, ms=3, label=model.upper())
        ax.set_title(metric.replace("_", " "), fontsize=10)
        ax.set_xlabel("episode", fontsize=9)
        ax.tick_params(labelsize=8)
        ax.grid(alpha=0.3)
    if axes[0].lines:
        axes[0].legend(fontsize=8, frameon=False)
    return axes


def _settled_ylim(axes, frames, settle: int) -> None:
    """One y range for ``axes``, from the values of ``frames`` after episode ``settle``, said on each Axes."""
    later = np.concatenate([f[f.index > settle].to_numpy(dtype=float).ravel() for f in frames])
    low, high = float(np.nanmin(later)), float(np.nanmax(later))
    pad = 0.08 * (high - low) if high > low else max(abs(high), 1.0) * 0.1
    for ax in axes:
        ax.set_ylim(low - pad, high + pad)
        ax.text(0.01, 0.01, f"y range from episode {settle + 1}", transform=ax.transAxes, fontsize=7,
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
            ax.plot(frame.index, frame[model], marker="o", lw=2, color=COLOURS[model.lower()], label=model)
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


def plot_densities(ax, data, *, log: bool = False):
    """Student-t and Gaussian densities (``tails.compute_densities``), linear or log scale."""
    ax.plot(data["x"], data["gaussian"], color=COLOURS["gp"], lw=2, label="Gaussian N(0, 1)")
    ax.plot(data["x"], data["student_t"], color=COLOURS["tp"], lw=2, label=f"Student-t, nu = {data['nu']:g}")
    if log:
        log_scale(ax)
        ax.set_ylim(1e-16, 1.0)
        ax.set_title("log scale: the tails")
    else:
        ax.set_title("linear scale")
    ax.set_xlabel("x")
    ax.set_ylabel("density f(x)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, frameon=False)
    return ax


def plot_tail_ratios(ax, data, *, show_limits: bool = True, title: str | None = None):
    """Paper Figure 1(a): the Student-t ratio f(lambda x)/f(x) against x, with its limit lambda^(-1-nu)."""
    from matplotlib import colormaps

    cmap = colormaps["Blues"]
    nus = list(data["student_t"])
    for i, nu in enumerate(nus):
        colour = cmap(0.5 + 0.5 * i / max(len(nus) - 1, 1))
        limit = data["limits"][nu]
        label = f"Student-t, nu = {nu:g}"
        if show_limits:
            ax.axhline(limit, color=colour, ls="--", lw=1)
            label += f" (limit λ^(-1-ν) = {limit:.3g})"
        ax.plot(data["x_t"], data["student_t"][nu], color=colour, lw=2, label=label)
    _finish(ax, "x", f"f({data['lam']:g} x) / f(x)", title or f"Student-t ratio, lambda = {data['lam']:g}")
    return ax


def plot_tail_ratio_comparison(ax, data, nu: float):
    """The Student-t ratio for one nu beside the Gaussian's, on a log scale (tutorial 1's dashboard)."""
    plot_tail_ratios(ax, data, title="Karamata ratio f(λx)/f(x)")
    ax.plot(data["x_gauss"], data["gaussian"], color=COLOURS["gp"], lw=2, ls=":", label="Gaussian")
    log_scale(ax)
    ax.set_ylim(max(data["limits"][nu] / 100, 1e-30), 1.5)
    ax.legend(fontsize=8, frameon=False)
    return ax


def plot_gaussian_ratio(ax, data, *, title: str | None = None):
    """Paper Figure 1(b): the Gaussian ratio f(lambda x)/f(x) = exp((1 - lambda^2) x^2 / 2) on [0, 1]."""
    ax.plot(data["x_gauss"], data["gaussian"], color=COLOURS["gp"], lw=2, label="Gaussian")
    _finish(ax, "x", f"f({data['lam']:g} x) / f(x)", title or f"Gaussian ratio, lambda = {data['lam']:g}")
    return ax


def plot_posterior(ax, data, model: str, *, title: str | None = None, ylim=None):
    """Posterior mean, latent 2-sd band and the wider band of a new observation, outliers marked.

    ``data`` is ``demos.compute_posteriors``'s output.  The outer band (``var_noisy``)
    shows the fitted noise, where the GP and the TP differ most visibly.

    Outliers outside ``ylim`` are drawn as triangles on the edge they lie beyond.
    """
    post = data[model]
    colour = COLOURS[model]
    x = data["x_grid"]
    if "var_noisy" in post:  # the band of a new observation y*: the fitted noise made visible
        sd_y = np.sqrt(post["var_noisy"])
        ax.fill_between(x, post["mean"] - 2 * sd_y, post["mean"] + 2 * sd_y, color=colour, alpha=0.08,
                        label=f"± 2 sd of y* (noise {post['noise_variance']:.2g})")
    sd = np.sqrt(post["var"])
    ax.fill_between(x, post["mean"] - 2 * sd, post["mean"] + 2 * sd, color=colour, alpha=0.25,
                    label="mean ± 2 sd (latent f)")
    ax.plot(x, post["mean"], color=colour, lw=2, label="posterior mean")
    inliers = ~data["outliers"]
    ax.scatter(data["X"][inliers], data["y"][inliers], s=14, color="black", zorder=3, label="data")
    if ylim is not None:
        ax.set_ylim(*ylim)
    low, high = ax.get_ylim()
    in_view = data["outliers"] & (data["X"] <= x[-1])
    ys = data["y"]
    inside = in_view & (ys >= low) & (ys <= high)
    if inside.any():
        ax.scatter(data["X"][inside], ys[inside], s=40, marker="x", color=COLOURS["unsafe"], zorder=4,
                   label="outliers")
    label = "outliers off scale"
    for mask, edge, marker in ((in_view & (ys > high), high, "^"), (in_view & (ys < low), low, "v")):
        if mask.any():
            ax.scatter(data["X"][mask], np.full(mask.sum(), edge), s=60, marker=marker, color=COLOURS["unsafe"],
                       zorder=5, clip_on=False, label=label)
            label = None
    hidden = int((data["outliers"] & (data["X"] > x[-1])).sum())
    if hidden:
        ax.text(0.99, 0.02, f"{hidden} outliers beyond x = {x[-1]:g}", transform=ax.transAxes, ha="right",
                fontsize=8, color=COLOURS["unsafe"])
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, frameon=False, loc="upper left")
    ax.set_title(title or {"gp": "Gaussian process", "tp": f"Student-t process, nu = {data['nu']:g}"}[model])
    return ax


def plot_variances(ax, data, *, title: str | None = None):
    """The two posterior variances on one log axis: paper eq. 5 (GP) against eq. 6 (TP)."""
    x = data["x_grid"]
    ax.plot(x, data["gp"]["var"], color=COLOURS["gp"], lw=2, label="GP, eq. 5")
    ax.plot(x, data["tp"]["var"], color=COLOURS["tp"], lw=2, label="TP, eq. 6 (corrected)")
    for model in ("gp", "tp"):
        if "var_noisy" in data[model]:
            ax.plot(x, data[model]["var_noisy"], color=COLOURS[model], lw=1.2, ls="--",
                    label=f"{model.upper()}, of y* (with noise)")
    ax.vlines(data["X"][data["outliers"] & (data["X"] <= x[-1])], 0, 1, transform=ax.get_xaxis_transform(),
              color=COLOURS["unsafe"], lw=0.8, alpha=0.5, label="outlier inputs")
    log_scale(ax)
    ax.set_xlabel("x")
    ax.set_ylabel("posterior variance")
    ax.grid(alpha=0.3)
    low, high = ax.get_ylim()
    ax.set_ylim(low, high * (high / low) ** 0.7)  # headroom for the legend, above the curves
    ax.legend(fontsize=7, frameon=False, loc="upper right", ncols=2, handlelength=1.5, columnspacing=1.0)
    ax.set_title(title or "posterior variance: eq. 5 (GP) and eq. 6 (TP)")
    return ax


def plot_outlier_scatter(ax, world, *, title: str | None = None):
    """The cost model's data (``demos.compute_world``): input size against target, outliers in red.

    Many rows share an input (the buffers keep up to 12 copies), so each
    distinct point is drawn once, its area growing with the rows behind it.
    """
    X, y = world["dirty"]["X"], world["dirty"]["y"]
    size = np.linalg.norm(X[:, 1:], axis=1) + 1.0
    rows = np.zeros(len(y), dtype=bool)
    rows[world["outlier_rows"]] = True
    for mask, colour, label in ((~rows, COLOURS["tp"], "clean rows"),
                                (rows, COLOURS["unsafe"], f"outliers (x {world['magnitude']:g})")):
        points, counts = np.unique(np.column_stack([size[mask], y[mask] + 1.0]), axis=0, return_counts=True)
        ax.scatter(points[:, 0], points[:, 1], s=4 + 3 * counts, alpha=0.5, color=colour, linewidths=0,
                   label=f"{label}: {int(mask.sum())}", rasterized=True)  # pixels even in an SVG: hundreds of dots
    log_scale(ax, "x")
    log_scale(ax, "y")
    ax.set_xlabel("1 + |(x, y, unsafe x, unsafe y)| of the input")
    ax.set_ylabel("1 + target (distance to danger)")
    ax.grid(alpha=0.3)
    legend = ax.legend(fontsize=8, frameon=False, loc="upper left", title="marker area: rows at that point",
                       title_fontsize=8)
    for handle in legend.legend_handles:
        handle.set_sizes([20])
    ax.set_title(title or f"cost-model data: {len(world['outlier_rows'])} of {len(y)} rows are outliers")
    return ax
