"""The gridworld and its data: ``plot_gridworld`` (tutorials 3 and 4) and ``plot_outlier_scatter``."""

from __future__ import annotations

import numpy as np
from matplotlib import patches
from matplotlib.collections import LineCollection, PatchCollection

from ..config import ACTION_MOVES
from .style import COLOURS, SMALL, log_scale

__all__ = ["plot_gridworld", "plot_outlier_scatter"]


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
    ax.tick_params(length=0, labelsize=SMALL)
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
        handles["moved here" if flag else "unsafe state"] = patches.Patch(**styles[flag])
    if show_moved and len(layout.moved):
        ax.add_collection(PatchCollection(
            [patches.Rectangle((ox - 0.42, oy - 0.42), 0.84, 0.84) for ox, oy in layout.moved_from],
            zorder=3, facecolors="none", edgecolors=COLOURS["unsafe"], linewidths=1.4, linestyles="--",
        ), autolim=False)
        handles["was unsafe"] = patches.Patch(facecolor="none", edgecolor=COLOURS["unsafe"], lw=1.4,
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
                  fontsize=SMALL, frameon=False, borderaxespad=0)
    if title:
        ax.set_title(title)
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
    legend = ax.legend(fontsize=SMALL, frameon=False, loc="upper left", title="marker area: rows at that point",
                       title_fontsize=SMALL)
    for handle in legend.legend_handles:
        handle.set_sizes([20])
    ax.set_title(title or f"cost-model data: {len(world['outlier_rows'])} of {len(y)} rows are outliers")
    return ax
