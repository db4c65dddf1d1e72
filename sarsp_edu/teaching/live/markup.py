"""SVG and HTML for the live dashboard: microseconds per frame, drawn by the browser.

The same pictures as :func:`sarsp_edu.teaching.plotting.plot_gridworld` and a table of
Algorithm 1's decision, cheap enough to redraw at every agent step (a
matplotlib redraw costs tens of milliseconds).
"""

from __future__ import annotations

import html
import math
import re

from ...config import ACTION_MOVES
from ..plotting import COLOURS

__all__ = ["decision_table_html", "gridworld_svg"]

_ACTION_ARROWS = ("→", "↓", "←", "↑")


def gridworld_svg(layout, *, trajectory=None, unsafe_pairs=(), cell: int = 28, title: str = "",
                  font_size: int = 13) -> str:
    """The world as an SVG string: unsafe states, moved states, S_u, path, agent, goal.

    The same picture as :func:`sarsp_edu.teaching.plotting.plot_gridworld`, cheap enough to redraw at
    every agent step.  ``font_size`` is the title's, in px (18 on a projector).  The SVG
    carries a description for a screen reader (``role="img"`` and ``aria-label``), and its
    marks are shapes, none a character that a font may lack.

    Parameters
    ----------
    layout : GridLayout
        The world to draw (``env.layout()``); its start, goal and agent are drawn where not None.
    trajectory : sequence of (x, y), optional
        Cells of the path to draw as a line (drawn from two cells on).
    unsafe_pairs : iterable of ((x, y), action)
        The learned ``S_u``: a red tick from each cell towards the action's neighbour.
    cell : int, default 28
        A cell's side, in px.
    title : str, default ""
        Written above the grid; empty: no title and no room for one.
    font_size : int, default 13
        The title's size, in px.
    """
    n = layout.size
    size = n * cell
    top = round(font_size * 1.7) if title else 0
    # its natural size at most, smaller where its box is narrower (a side of 184 px at 800 x 600): scaled, not cut
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{size + 2}" height="{size + 2 + top}" '
             f'style="max-width:100%;height:auto" '
             f'viewBox="-1 {-1 - top} {size + 2} {size + 2 + top}" font-family="sans-serif" role="img" '
             f'aria-label="{html.escape(_describe(layout, title, trajectory, unsafe_pairs))}">']
    if title:
        parts.append(f'<text x="{size / 2}" y="{-round(font_size * 0.55)}" text-anchor="middle" '
                     f'font-size="{font_size}">{html.escape(title)}</text>')
    parts.append(f'<rect x="0" y="0" width="{size}" height="{size}" fill="#fafafa" stroke="#999"/>')
    for k in range(1, n):
        parts.append(f'<line x1="{k * cell}" y1="0" x2="{k * cell}" y2="{size}" stroke="{COLOURS["grid"]}"/>')
        parts.append(f'<line x1="0" y1="{k * cell}" x2="{size}" y2="{k * cell}" stroke="{COLOURS["grid"]}"/>')
    moved = {int(i) for i in layout.moved}
    for ox, oy in layout.moved_from:
        parts.append(f'<rect x="{ox * cell + 3}" y="{oy * cell + 3}" width="{cell - 6}" height="{cell - 6}" '
                     f'fill="none" stroke="{COLOURS["unsafe"]}" stroke-dasharray="3,2"/>')
    for i, (x, y) in enumerate(layout.unsafe_states):
        stroke = 'stroke="black" stroke-width="2"' if i in moved else ""
        parts.append(f'<rect x="{x * cell + 2}" y="{y * cell + 2}" width="{cell - 4}" height="{cell - 4}" '
                     f'fill="{COLOURS["unsafe"]}" {stroke}/>')
    half = cell / 2
    for (x, y), action in unsafe_pairs:
        dx, dy = ACTION_MOVES[int(action)]
        cx, cy = x * cell + half, y * cell + half
        parts.append(f'<line x1="{cx + dx * 4}" y1="{cy + dy * 4}" x2="{cx + dx * (half - 2)}" '
                     f'y2="{cy + dy * (half - 2)}" stroke="{COLOURS["unsafe"]}" stroke-width="4"/>')
    if trajectory is not None and len(trajectory) > 1:
        points = " ".join(f"{x * cell + half},{y * cell + half}" for x, y in trajectory)
        parts.append(f'<polyline points="{points}" fill="none" stroke="{COLOURS["path"]}" stroke-width="3" '
                     'stroke-opacity="0.8"/>')
    if layout.start is not None:
        sx, sy = layout.start
        parts.append(f'<circle cx="{sx * cell + half}" cy="{sy * cell + half}" r="{cell * 0.3}" fill="white" '
                     f'stroke="{COLOURS["start"]}" stroke-width="3"/>')
    if layout.goal is not None:
        gx, gy = layout.goal
        parts.append(f'<polygon points="{_star(gx * cell + half, gy * cell + half + 1, cell * 0.42)}" '
                     f'fill="{COLOURS["goal"]}" stroke="black" stroke-width="0.7"/>')
    if layout.agent is not None:
        ax_, ay = layout.agent
        parts.append(f'<circle cx="{ax_ * cell + half}" cy="{ay * cell + half}" r="{cell * 0.22}" '
                     f'fill="{COLOURS["agent"]}" stroke="white" stroke-width="2"/>')
    parts.append("</svg>")
    return "".join(parts)


def _star(cx: float, cy: float, radius: float) -> str:
    """The corners of a five-pointed star, point up, as an SVG polygon's ``points``."""
    corners = []
    for k in range(10):
        r = radius if k % 2 == 0 else 0.45 * radius
        angle = math.pi * (k / 5 - 0.5)
        corners.append(f"{cx + r * math.cos(angle):.1f},{cy + r * math.sin(angle):.1f}")
    return " ".join(corners)


def _describe(layout, title: str, trajectory, unsafe_pairs) -> str:
    """What :func:`gridworld_svg` draws, in words: its alt text."""
    parts = [f"{title}: " if title else "", f"a {layout.size} by {layout.size} grid world; red squares are "
             "unsafe states (outlined in black: moved by the shift; dashed outlines: where they were), "
             "a ring is the start, a star the goal"]
    if layout.agent is not None:
        parts.append(", a filled circle the agent")
    if trajectory is not None and len(trajectory) > 1:
        parts.append(", a line its path this episode")
    if len(unsafe_pairs):
        parts.append(", red ticks the moves it has learned are unsafe (S_u)")
    return "".join(parts) + "."


def decision_table_html(decision, d: float, variance_threshold: float, font_size: int = 12) -> str:
    """Algorithm 1's view of one decision: per-action predictions, S_u, safe set, the choice (text in px).

    Parameters
    ----------
    decision : Decision or None
        The decision to show; None: "no decision yet".
    d : float
        Safety distance, shown in the safety rule under the table.
    variance_threshold : float
        sigma*^2, shown in the same rule.
    font_size : int, default 12
        Text size of the table and the rule, in px.

    Returns
    -------
    str
        An HTML fragment.
    """
    if decision is None:
        return "<i>no decision yet</i>"
    rows = []
    for a in range(4):
        known = bool(decision.known_unsafe[a])
        safe = bool(decision.safe[a])
        chosen = a == decision.action
        status = "in S_u" if known else ("safe" if safe else "not safe")
        style = "font-weight:bold;background:#e8f1fa" if chosen else ""
        rows.append(
            f'<tr style="{style}"><td>{_ACTION_ARROWS[a]}</td><td>{decision.mu_cost[a]:.2f}</td>'
            f"<td>{decision.var_cost[a]:.3g}</td><td>{decision.mu_reward[a]:.2f}</td><td>{status}</td></tr>"
        )
    rule = "backup: no action safe, highest reward" if decision.backup else "safe action with the highest reward"
    return (
        f'<table style="font-size:{font_size}px;border-collapse:collapse" cellpadding="2">'
        "<tr><th>a</th><th>cost μ</th><th>cost σ²</th><th>reward μ</th><th>status</th></tr>"
        + "".join(rows)
        + f'</table><div style="font-size:{font_size}px">safe: σ² ≤ {variance_threshold:g} and μ ≥ d = {d:g}; '
        f"chosen: {_ACTION_ARROWS[decision.action]} ({rule})</div>"
    )


def labelled_svg(svg: bytes, label: str) -> str:
    """Matplotlib's SVG as markup to put in a page: its XML header and doctype dropped, scaled to the width it is
    given, with ``role="img"`` and ``label`` as its ``aria-label`` (a screen reader's alt text).

    Parameters
    ----------
    svg : bytes
        A whole SVG document (``render_figure(figure, "svg")``).
    label : str
        What it shows, in words.
    """
    text = svg.decode("utf-8")
    start = text.index("<svg")
    head_end = text.index(">", start)
    head = re.sub(r'\s(width|height)="[^"]*"', "", text[start:head_end])
    return (f'{head} style="display:block;width:100%;max-width:100%;height:auto" role="img" '
            f'aria-label="{html.escape(label)}"'
            + text[head_end:])
