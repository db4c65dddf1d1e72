"""The look every figure shares: colours, line styles, log axes with plain labels, the usual finish.

The GP and the TP are told apart without colour as well: the GP's lines are
dashed with square markers, the TP's solid with round ones (``LINESTYLES``,
``MARKERS``), so that a greyscale print or a reader with a red-green colour
deficiency sees which is which.  The colours themselves are chosen to stay
apart in greyscale and under simulated protanopia and deuteranopia (the
tests measure both).
"""

from __future__ import annotations

import numpy as np
from matplotlib import ticker

__all__ = ["COLOURS", "LINESTYLES", "MARKERS", "SMALL", "PlainLogFormatter", "finish_axes", "log_scale",
           "model_style"]

#: the smallest text of any figure, in points (legends, tick labels, notes): readable on a projector
SMALL = 10

#: colours shared by every figure of the package; the pairs that a figure contrasts (GP and TP, the
#: Student-t likelihood beside them, data and outliers) differ in lightness and under colour-vision deficiency
COLOURS = {
    "unsafe": "#d62728",
    "moved": "#ff9896",
    "goal": "#2ca02c",
    "start": "#1f77b4",
    "agent": "#1f77b4",
    "path": "#17becf",
    "gp": "#ff7f0e",
    "tp": "#1f77b4",
    "robust": "#00441b",  # dark: a mid green and the GP's orange look alike to a protanope
    "data": "#000000",
    "grid": "#c8c8c8",
}

#: line styles of the models, so that they differ in more than colour
LINESTYLES = {"gp": "--", "tp": "-", "robust": "-."}
#: markers of the models, where their points or lines carry markers
MARKERS = {"gp": "s", "tp": "o", "robust": "D"}


def model_style(name: str) -> dict:
    """``color`` and ``ls`` of a model ("gp", "tp", "robust", any case) for ``Axes.plot``."""
    key = name.lower()
    return {"color": COLOURS[key], "ls": LINESTYLES[key]}


class PlainLogFormatter(ticker.Formatter):
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
    times each power of ten (labelled on a short axis).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    axis : {"y", "x"}, default "y"
        Which axis (any value but ``"y"`` is the x axis).
    """
    target = ax.yaxis if axis == "y" else ax.xaxis
    (ax.set_yscale if axis == "y" else ax.set_xscale)("log")
    target.set_minor_locator(ticker.LogLocator(subs=(2.0, 5.0)))
    target.set_major_formatter(PlainLogFormatter())
    target.set_minor_formatter(PlainLogFormatter(minor=True))


def finish_axes(ax, xlabel: str, ylabel: str, title: str, legend_loc="best") -> None:
    """The labels, light grid and frameless legend every line plot here ends with.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    xlabel, ylabel, title : str
    legend_loc : str, default "best"
        The legend's ``loc``.
    """
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=SMALL, frameon=False, loc=legend_loc)
    ax.set_title(title)
