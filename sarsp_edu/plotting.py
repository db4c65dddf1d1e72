"""Drawing functions: ``plot_*(ax, data)`` draws what it is handed and keeps no state."""

from __future__ import annotations

import numpy as np
from matplotlib import patches

__all__ = ["plot_gridworld"]

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
    for k in range(n + 1):
        ax.axhline(k - 0.5, color=COLOURS["grid"], lw=0.6, zorder=1)
        ax.axvline(k - 0.5, color=COLOURS["grid"], lw=0.6, zorder=1)
    if visits is not None:
        visits = np.asarray(visits, dtype=float)
        ax.imshow(visits, cmap="Greys", alpha=0.55, zorder=0, origin="upper",
                  extent=(-0.5, n - 0.5, n - 0.5, -0.5), vmin=0, vmax=max(visits.max(), 1))

    moved = set(int(i) for i in layout.moved) if show_moved else set()
    handles = {}
    for i, (x, y) in enumerate(layout.unsafe_states):
        is_moved = i in moved
        rect = patches.Rectangle(
            (x - 0.45, y - 0.45), 0.9, 0.9,
            facecolor=COLOURS["unsafe"], edgecolor="black" if is_moved else COLOURS["unsafe"],
            lw=1.8 if is_moved else 0.5, zorder=3,
        )
        ax.add_patch(rect)
        handles.setdefault("moved here in the shift" if is_moved else "unsafe state", rect)
    if show_moved and len(layout.moved):
        for i, (ox, oy) in zip(layout.moved, layout.moved_from):
            old = patches.Rectangle(
                (ox - 0.42, oy - 0.42), 0.84, 0.84, facecolor="none",
                edgecolor=COLOURS["unsafe"], lw=1.4, ls="--", zorder=3,
            )
            ax.add_patch(old)
            handles.setdefault("unsafe before the shift", old)
            nx, ny = layout.unsafe_states[int(i)]
            ax.annotate("", xy=(nx, ny), xytext=(ox, oy), zorder=4,
                        arrowprops=dict(arrowstyle="->", color="black", lw=0.9, alpha=0.6,
                                        shrinkA=6, shrinkB=8))
    if unsafe_pairs:
        moves = {0: (1, 0), 1: (0, 1), 2: (-1, 0), 3: (0, -1)}
        for (cx, cy), action in unsafe_pairs:
            dx, dy = moves[int(action)]
            line, = ax.plot([cx + 0.1 * dx, cx + 0.42 * dx], [cy + 0.1 * dy, cy + 0.42 * dy],
                            color=COLOURS["unsafe"], lw=2.5, solid_capstyle="butt", zorder=6)
            handles.setdefault("learned unsafe move (S_u)", line)
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
