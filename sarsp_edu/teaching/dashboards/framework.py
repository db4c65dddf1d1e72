"""The dashboards' redraw framework: a :class:`Dashboard` of controls and :class:`Panel` pictures.

Each picture (a :class:`Panel`) is a small matplotlib ``Figure`` (no pyplot
state) rendered into an ``ipywidgets.Image`` as SVG, its text left to the
browser (sharp on a projector), so a slider move redraws it in place in
JupyterLab, Voila and a static notebook alike; a move redraws only the
panels that depend on the slider.  A callback never raises: a value the
models cannot handle shows a message under the controls instead.

The speed-ups live here and nowhere else: :func:`wipe_axes` (empty an Axes
without rebuilding its ticks), :func:`fixed_layout_axes` (labels at fixed
places, nothing measured) and :func:`render_figure`.  The tutorials'
dashboards are in :mod:`sarsp_edu.teaching.dashboards.tutorials` and :mod:`sarsp_edu.teaching.live`.

Projector size (text for the back of a lecture room, the default) is in
:mod:`sarsp_edu.teaching.dashboards.projector`; every dashboard takes it from there.  A static
copy's picture carries alt text, built from each panel's ``alt``, in the
output's metadata (``{"image/png": {"alt": ...}}``), for a screen reader.
"""

from __future__ import annotations

import base64
import html
import io
import time
from collections.abc import Callable
from dataclasses import dataclass

import ipywidgets as widgets
import matplotlib
from matplotlib.figure import Figure
from matplotlib.transforms import ScaledTranslation

from ..._internal.threads import one_blas_thread
from ..._internal.validation import check_choice, check_int, check_positive, check_range
from ..plotting.display import alt_metadata
from .projector import PROJECTOR_MAX_PX_PER_PT, PROJECTOR_PX_PER_PT, ProjectorMixin, slider_width

__all__ = ["Dashboard", "Panel", "control_row", "fixed_layout_axes", "readable_png", "render_figure", "slider",
           "stitch_png", "wipe_axes"]


@dataclass(frozen=True)
class Panel:
    """One picture of a dashboard: its own small figure, redrawn only when its inputs move.

    Attributes
    ----------
    draw : callable
        ``draw(ax, result, **values)``: draws the dashboard's computed
        ``result`` on ``ax`` (through the ``plot_*`` functions).
    width : float
        Figure width in inches (all panels of a dashboard share its height).
    inputs : tuple of str, optional
        The controls this picture depends on; a move of any other control
        leaves it as it is.  None means every control.
    margins : dict, optional
        ``left``, ``right``, ``bottom``, ``top`` in inches, for long labels or
        a legend outside the Axes.
    label_offsets : (float, float)
        Distance in points from the Axes to the x label (below) and to the
        y label (left), room for the tick labels the panel can show.  Fixed
        rather than measured at each redraw, which cost a tenth of it.
    alt : str or callable
        What the picture shows, for someone who cannot see it (axes, curves,
        what to notice), or ``alt(**values)`` giving it for the controls'
        values.  Numbers only where the picture shows them.
    """

    draw: Callable
    width: float
    inputs: tuple | None = None
    margins: dict | None = None
    label_offsets: tuple = (24.0, 42.0)
    alt: str | Callable = ""

    def __post_init__(self):
        check_positive("width", self.width)

    def describe(self, values: dict) -> str:
        """The panel's alt text at these control values."""
        return (self.alt(**values) if callable(self.alt) else self.alt).strip()

    def depends_on(self, changed) -> bool:
        """Whether a move of the controls named in ``changed`` (None: any) redraws this panel."""
        return changed is None or self.inputs is None or bool(set(changed) & set(self.inputs))


class Dashboard(ProjectorMixin, widgets.VBox):
    """Controls, a message line, a row of pictures and a text panel.

    A slider move calls ``compute(**values)`` once, then redraws only the
    panels whose ``inputs`` include the control that moved: matplotlib needs
    tens of milliseconds per picture whatever it shows, so a panel that
    cannot have changed is not drawn again.

    Parameters
    ----------
    controls : dict of widgets
        By name; their values are passed to ``compute`` and the panels.
    compute : callable
        ``compute(**values) -> (result, info_html)``: the numbers behind the
        pictures (through the package's ``compute_*`` functions).
    panels : list of Panel
    height : float
        Height of every panel, in inches.
    max_scale : float, default 1.5
        How far the pictures (vector graphics) may grow beyond their natural
        size (72 px per inch) to fill a wide page or a projector.
    layout_rows : list of widgets, optional
        How to arrange the controls (default: one row).
    projector : bool, optional
        Start in projector size; default :func:`projector_default`.

    Attributes
    ----------
    controls : dict of widgets
        By name (``"nu"``, ``"lam"``, ...), for code and tests to drive.
    figures : list of matplotlib.figure.Figure
    axes : list of Axes
        One per panel.
    images : list of ipywidgets.Image
        The rendered panels (SVG).
    result : object
        What ``compute`` returned for the values on show.
    info : ipywidgets.HTMLMath
        Numbers and formulas under the pictures.
    message : ipywidgets.HTML
        Empty, or why the last update could not be drawn.
    last_update_seconds : float
        Compute and redraw time of the last update.
    last_redrawn : list of int
        The panels the last update redrew.
    """

    def __init__(self, controls: dict, compute, panels, *, height: float, max_scale: float = 1.5,
                 layout_rows=None, projector: bool | None = None):
        self.controls = controls
        self.panels = list(panels)
        if not self.panels:
            raise ValueError("panels must hold at least one Panel, got panels=[]")
        height = check_positive("height", height)
        max_scale = check_positive("max_scale", max_scale)
        for panel in self.panels:
            for name in panel.inputs or ():
                check_choice("Panel inputs", name, list(controls))
        self._compute = compute
        self._names = {id(control): name for name, control in controls.items()}
        self.figures, self.axes, self.images = [], [], []
        self.max_scale = max_scale
        for panel in self.panels:
            figure = Figure(figsize=(panel.width, height))
            # Fixed margins rather than constrained layout: the layout engine
            # draws the figure twice.
            inches = {"left": 0.75, "right": 0.15, "bottom": 0.55, "top": 0.35, **(panel.margins or {})}
            figure.subplots_adjust(left=inches["left"] / panel.width, right=1 - inches["right"] / panel.width,
                                   bottom=inches["bottom"] / height, top=1 - inches["top"] / height)
            self.figures.append(figure)
            self.axes.extend(fixed_layout_axes(figure, panel.label_offsets))
            self.images.append(widgets.Image(format="svg+xml"))
        self.info = widgets.HTMLMath()
        self.message = widgets.HTML()
        self.result = None
        self.last_update_seconds = float("nan")
        self.last_redrawn: list[int] = []
        self._stale = True
        self._used = [False] * len(self.panels)
        rows = layout_rows or [control_row(controls.values())]
        self.pictures = widgets.HBox(self.images, layout=widgets.Layout(width="100%"))
        super().__init__(children=[*rows, self.message, self.pictures, self.info])
        self._init_projector(projector, toggle_row=rows[-1])
        self._resize_pictures()
        for control in controls.values():
            control.observe(self._on_change, names="value")
        self.refresh()

    def _resize_pictures(self) -> None:
        """Compact size: the pictures share one row.  Projector size: each is at least PROJECTOR_PX_PER_PT CSS px
        per point wide (its 10 pt text at 14.2 px), the row wraps where they do not fit side by side, and the
        pictures of a row share its width in proportion to their own, up to PROJECTOR_MAX_PX_PER_PT.

        The browser decides the rows, so the same dashboard reads alike in
        JupyterLab beside its file browser (about 850 px), in Voila and on a
        wide screen; on a screen narrower than a picture, it shrinks to fit.
        The figures themselves are the same in both sizes: only the space
        they are given changes, so every legend and label stays where it was
        placed.
        """
        total = sum(panel.width for panel in self.panels)
        for panel, image in zip(self.panels, self.images):
            if self.projector:
                points = panel.width * 72
                image.layout = widgets.Layout(
                    flex=f"{panel.width:g} 1 0px", height="auto",
                    min_width=f"min({points * PROJECTOR_PX_PER_PT:.0f}px, 100%)",
                    max_width=f"{points * PROJECTOR_MAX_PX_PER_PT:.0f}px")
            else:
                image.layout = widgets.Layout(width=f"{100 * panel.width / total:.3f}%",
                                              max_width=f"{panel.width * 72 * self.max_scale:.0f}px")
        self.pictures.layout = widgets.Layout(
            width="100%", flex_flow="row wrap" if self.projector else "row", align_items="flex-start",
            max_width="none" if self.projector else f"{total * 72 * self.max_scale:.0f}px")

    def snapshot(self) -> bytes:
        """The pictures on show, side by side, as one PNG (what a static copy of the notebook shows).

        At least :data:`SNAPSHOT_WIDTH_PX` wide with its text readable at that width (:func:`readable_png`).
        """
        return readable_png(self.figures)

    def alt_text(self) -> str:
        """What the pictures on show draw, panel by panel, for a screen reader (the static copy's alt text)."""
        values = self.values()
        described = [panel.describe(values) for panel in self.panels]
        if len(described) == 1 or not any(described):  # "" where no panel has an alt
            return described[0] if len(described) == 1 else ""
        places = {2: ("Left", "Right"), 3: ("Left", "Middle", "Right")}.get(
            len(described), [f"Picture {i + 1}" for i in range(len(described))])
        return f"{len(described)} pictures side by side. " + " ".join(
            f"{place}: {text}" for place, text in zip(places, described))

    def _repr_mimebundle_(self, **kwargs):
        # A live front end (JupyterLab, Voila) renders the widget view; a static
        # one (GitHub, nbviewer, a printed handout) falls back to the PNG, whose
        # alt text is in the metadata.
        bundle = dict(super()._repr_mimebundle_(**kwargs))
        bundle["image/png"] = base64.b64encode(self.snapshot()).decode("ascii")
        return bundle, alt_metadata(self.alt_text() or "The dashboard's pictures (no description was given).")

    def _on_change(self, change):
        self.refresh(changed=(self._names[id(change["owner"])],))

    def values(self) -> dict:
        """The controls' current values, by name (what ``compute`` and the panels are called with)."""
        return {name: control.value for name, control in self.controls.items()}

    def refresh(self, changed=None) -> bool:
        """Recompute and redraw the panels that depend on ``changed`` (default: all).

        Returns False, and shows why under the controls, if the values could
        not be computed or drawn; the last good pictures then stay.
        """
        start = time.perf_counter()
        self.last_redrawn = []
        if self._stale:  # the last update failed part-way: every panel may be out of date
            changed = None
        values = self.values()
        try:
            with one_blas_thread():
                result, info = self._compute(**values)
            for i, panel in enumerate(self.panels):
                if panel.depends_on(changed):
                    if self._used[i]:  # a brand-new Axes is drawn on as it is
                        wipe_axes(self.axes[i])
                    self._used[i] = True
                    panel.draw(self.axes[i], result, **values)
                    self.images[i].value = render_figure(self.figures[i], "svg")
                    self.last_redrawn.append(i)
            self.result = result
            self.info.value = info or ""
            self.message.value = ""
            self._stale = False
            ok = True
        except Exception as exc:  # a dashboard must not crash on an extreme slider value
            self.message.value = (
                "<span style='color:#b00020'>Could not draw these values: "
                f"{html.escape(type(exc).__name__)}: {html.escape(str(exc))}</span>"
            )
            self._stale = True
            ok = False
        self.last_update_seconds = time.perf_counter() - start
        return ok


def wipe_axes(ax) -> None:
    """Empty an Axes for the next redraw, keeping its tick objects.

    ``Axes.clear()`` throws away every tick, and building them again was a
    third of a slider move.  A dashboard draws the same kind of plot on the
    same Axes at every move, so the styling of the axis (tick parameters,
    grid) can stay; everything that depends on the data goes: the artists,
    the legend, the texts, the limits (autoscaling is switched back on), the
    scales, the fixed tick positions and the colour cycle.  The test suite
    checks that a redrawn panel is byte for byte the SVG that a new,
    never-wiped Axes gives at the same slider values (a dashboard draws its
    first pictures on new Axes).
    """
    for artist in [*ax.lines, *ax.collections, *ax.patches, *ax.texts, *ax.images, *ax.artists]:
        artist.remove()
    if ax.get_legend() is not None:
        ax.get_legend().remove()
    ax.set_title("")
    ax.set_xlabel("")
    ax.set_ylabel("")
    ax.set_xscale("linear")  # also restores the default locators and formatters
    ax.set_yscale("linear")
    ax.set_aspect("auto")
    ax.set_prop_cycle(None)
    ax.set_xlim(0, 1)  # a fresh Axes' limits, kept if the next picture adds no data
    ax.set_ylim(0, 1)
    ax.relim()
    ax.set_autoscale_on(True)


def fixed_layout_axes(figure: Figure, label_offsets=None, ncols: int = 1) -> list:
    """One row of Axes in the figure's margins, with titles and labels at fixed places.

    By default matplotlib measures every tick label at each draw, to decide
    whether the title must move up and where the axis labels go: a fifth of
    a redraw.  These figures have nothing above their Axes, and the label
    distances (points, x then y) are given, so nothing needs measuring.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        The figure to add the Axes to.
    label_offsets : (float, float), optional
        Distance in points from each Axes to its x label (below) and its y label (left).  None: matplotlib
        places the labels as usual.
    ncols : int, default 1
        Number of Axes, side by side.

    Returns
    -------
    list of matplotlib.axes.Axes
    """
    with matplotlib.rc_context({"axes.titley": 1.0}):
        axes = list(figure.subplots(1, ncols, squeeze=False)[0])
    if label_offsets is not None:
        below, left = label_offsets
        for ax in axes:
            ax.xaxis.set_label_coords(
                0.5, 0, transform=ax.transAxes + ScaledTranslation(0, -below / 72, figure.dpi_scale_trans))
            ax.yaxis.set_label_coords(
                0, 0.5, transform=ax.transAxes + ScaledTranslation(-left / 72, 0, figure.dpi_scale_trans))
    return axes


def stitch_png(images: list) -> bytes:
    """PNG images (bytes) placed side by side on white, tops aligned, as one PNG."""
    import matplotlib.image as mpimg
    import numpy as np

    arrays = [mpimg.imread(io.BytesIO(image), format="png")[..., :3] for image in images]
    height = max(a.shape[0] for a in arrays)
    padded = [np.vstack([a, np.ones((height - a.shape[0], a.shape[1], 3), dtype=a.dtype)]) for a in arrays]
    buffer = io.BytesIO()
    mpimg.imsave(buffer, np.hstack(padded), format="png")
    return buffer.getvalue()


#: a dashboard's stored picture: at least this wide, its text at least SNAPSHOT_TEXT_PT when shown this wide
SNAPSHOT_WIDTH_PX, SNAPSHOT_TEXT_PT = 1600, 14
_SCREEN_PX_PER_PT = 96 / 72  # a browser's CSS pixels per point


def readable_png(figures) -> bytes:
    """Figures side by side as one PNG at least SNAPSHOT_WIDTH_PX wide, every text at least SNAPSHOT_TEXT_PT there.

    The figures are rendered at the resolution that makes their row
    ``SNAPSHOT_WIDTH_PX`` wide; a text smaller than 14 pt would be at that
    width is enlarged for the picture and given back its size afterwards (the
    live view is not changed).
    """
    from matplotlib.text import Text

    inches = sum(figure.get_figwidth() for figure in figures)
    dpi = (SNAPSHOT_WIDTH_PX + len(figures)) / inches  # each figure's pixels are rounded down
    floor = SNAPSHOT_TEXT_PT * _SCREEN_PX_PER_PT * 72 / dpi  # in points of the figure
    texts = [text for figure in figures for text in figure.findobj(Text) if text.get_text()]
    sizes = [text.get_fontsize() for text in texts]
    try:
        for text, size in zip(texts, sizes):
            text.set_fontsize(max(size, floor))
        return stitch_png([render_figure(figure, "png", dpi) for figure in figures])
    finally:
        for text, size in zip(texts, sizes):
            text.set_fontsize(size)


def render_figure(figure: Figure, fmt: str, dpi: float = 72) -> bytes:
    """The figure as PNG bytes, or as SVG with its text kept as text (drawn by the browser).

    In an SVG, ``dpi`` applies only to the rasterized artists (images, dense
    scatter plots), which are drawn at twice the natural resolution so that
    they stay sharp when the picture is enlarged.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
    fmt : str
        ``"svg"``, or any other format ``Figure.savefig`` writes (``"png"``).
    dpi : float, default 72
        Resolution in dots per inch (72: one pixel per point); in an SVG, half the rasterized artists' resolution.
    """
    buffer = io.BytesIO()
    if fmt == "svg":
        # No date and fixed element ids: the same figure gives the same bytes.
        with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "sarsp_edu"}):
            figure.savefig(buffer, format="svg", dpi=2 * dpi, metadata={"Date": None})
    else:
        figure.savefig(buffer, format=fmt, dpi=dpi)
    return buffer.getvalue()


def slider(kind, name, description, value, lo, hi, step, expensive=True, **kwargs):
    """A slider for the argument ``name``; a value outside the slider's range is an error, not clamped.

    Parameters
    ----------
    kind : {"int", "float"}
        An ``IntSlider`` or a ``FloatSlider``.
    name : str
        The argument the slider sets, named in the error for a bad ``value``.
    description : str
        The slider's label; its length sets the slider's width (:func:`slider_width`).
    value : int or float
        Starting value, from ``lo`` to ``hi`` (a ValueError otherwise; an integer for ``kind="int"``).
    lo, hi : int or float
        The slider's range, both ends included.
    step : int or float
        The slider's increment.
    expensive : bool, default True
        True: the value changes only when the slider is released (no ``continuous_update``).
    **kwargs
        Passed on to the ipywidgets slider.
    """
    if kind == "int":
        check_int(name, value, lo, hi)
    else:
        check_range(name, value, lo, hi, "the slider's range")
    cls = widgets.FloatSlider if kind == "float" else widgets.IntSlider
    width = slider_width(description)
    return cls(value=value, min=lo, max=hi, step=step, description=description,
               continuous_update=not expensive, style={"description_width": "initial"},
               layout=widgets.Layout(width=width, min_width=width, flex="0 0 auto"), **kwargs)


def control_row(children) -> widgets.HBox:
    """Controls side by side that wrap onto the next line on a narrow screen instead of shrinking or spilling."""
    return widgets.HBox(list(children), layout=widgets.Layout(flex_flow="row wrap", width="100%"))
