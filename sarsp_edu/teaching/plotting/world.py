"""The gridworld and its data: ``plot_gridworld`` (tutorials 3 and 4) and ``plot_outlier_scatter``."""

from __future__ import annotations

import numpy as np
from matplotlib import patches
from matplotlib.collections import LineCollection, PatchCollection

from ..._internal.validation import check_choice
from ...config import ACTION_MOVES
from .style import COLOURS, SMALL, log_scale

__all__ = ["plot_gridworld", "plot_outlier_scatter", "plot_path_direction"]


def _layout_of(world):
    return world.layout() if hasattr(world, "layout") else world


def plot_gridworld(
    ax,
    world,
    *,
    trajectory=None,
    direction: str | None = None,
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
    direction : {None, "arrows", "steps"}, default None
        Show which way the path runs (see :func:`plot_path_direction`):
        ``"arrows"`` puts an arrowhead on each move it makes, ``"steps"``
        writes in each cell the step at which the path first reached it; both
        mark where it ends, with the steps it spent there at the end.
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
    check_choice("direction", direction, (None, "arrows", "steps"))
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
            if direction is not None:
                handles.update(plot_path_direction(ax, path, numbers=direction == "steps", size=n))
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


def plot_path_direction(ax, path, *, numbers: bool = False, size: int | None = None) -> dict:
    """Which way a drawn path runs: an arrowhead on each move (or each cell's first step), and its end.

    Parameters
    ----------
    ax : matplotlib Axes
        The Axes the path is drawn on (``plot_gridworld``).
    path : array-like of shape (T, 2)
        Cells ``(x, y)`` in the order visited; ``path[0]`` is step 0.
    numbers : bool, default False
        Write in each cell the step at which the path first reached it instead
        of the arrowheads.
    size : int, optional
        The grid's size, to keep the end's label inside it.

    Returns
    -------
    dict
        Legend label -> handle: ``"end"``.

    Each move between two cells gets one arrowhead however often it is made;
    a move made both ways gets two, each beside the path on its right.  The
    end is a square around the last cell, labelled with the steps taken from
    it once the path reached it for the last time, each of which left the
    path there (pushing against a wall, say).
    """
    path = np.asarray(path, dtype=float).reshape(-1, 2)
    if not len(path):
        return {}
    colour = "#0b6b75"  # a darker shade of the path's, to read on top of it
    if numbers:
        first = {}
        for step, cell in enumerate(map(tuple, path)):
            first.setdefault(cell, step)
        for (x, y), step in first.items():
            ax.text(x + 0.3, y - 0.28, str(step), ha="center", va="center", fontsize=SMALL - 1, color=colour,
                    zorder=6, bbox=dict(boxstyle="round,pad=0.1", facecolor="white", edgecolor="none", alpha=0.8))
    else:
        moves = {(tuple(a), tuple(b)) for a, b in zip(path[:-1], path[1:]) if tuple(a) != tuple(b)}
        for a, b in sorted(moves):
            a, b = np.array(a), np.array(b)
            d = b - a
            side = 0.13 * np.array([-d[1], d[0]]) if (tuple(b), tuple(a)) in moves else np.zeros(2)
            ax.add_artist(patches.FancyArrowPatch(
                tuple(a + 0.3 * d + side), tuple(a + 0.7 * d + side), arrowstyle="-|>", mutation_scale=13,
                color=colour, lw=1.2, shrinkA=0, shrinkB=0, zorder=6))
    end = path[-1]
    stay = 1
    while stay < len(path) and np.array_equal(path[-stay - 1], end):
        stay += 1
    handle = ax.scatter(*end, s=330, marker="s", facecolor="none", edgecolor=colour, lw=2.2, zorder=6)
    if stay > 1:  # the path reached the cell, then took stay - 1 steps that left it there
        n = size if size is not None else int(np.max(path)) + 1
        dx = -0.55 if end[0] > (n - 1) / 2 else 0.55
        dy = 0.55 if end[1] < (n - 1) / 2 else -0.55
        ax.text(end[0] + dx, end[1] + dy, f"{stay - 1} steps here", ha="right" if dx < 0 else "left", va="center",
                fontsize=SMALL, color=colour, zorder=8,
                bbox=dict(boxstyle="round,pad=0.2", facecolor="white", edgecolor=colour, lw=0.8))
    return {"end": handle}


def plot_outlier_scatter(ax, world, *, title: str | None = None):
    """The cost model's data (``demos.compute_world``): input size against target, outliers as red triangles.

    Many rows share an input (the buffers keep up to 12 copies), so each
    distinct point is drawn once, its area growing with the rows behind it.
    Clean rows are black dots: black and red differ in lightness as well as
    hue, and the triangles in shape.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    world : dict
        :func:`~sarsp_edu.teaching.demos.compute_world`'s output.
    title : str, optional
        The panel's title; default one giving how many rows are outliers.
    """
    X, y = world["dirty"]["X"], world["dirty"]["y"]
    size = np.linalg.norm(X[:, 1:], axis=1) + 1.0
    rows = np.zeros(len(y), dtype=bool)
    rows[world["outlier_rows"]] = True
    for mask, colour, marker, label in ((~rows, COLOURS["data"], "o", "clean rows"),
                                        (rows, COLOURS["unsafe"], "^", f"outliers (x {world['magnitude']:g})")):
        points, counts = np.unique(np.column_stack([size[mask], y[mask] + 1.0]), axis=0, return_counts=True)
        ax.scatter(points[:, 0], points[:, 1], s=4 + 3 * counts, alpha=0.5, color=colour, marker=marker, linewidths=0,
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
