"""Projector size: text the back of a lecture room can read, the default of every dashboard.

In projector size, widget labels, readouts, buttons and tables are
``PROJECTOR_TEXT_PX`` (18 px) and every picture is shown at
``PROJECTOR_PX_PER_PT`` CSS px per point of its figure or more (its 10 pt
text at 14.2 px or more), so that a lecturer need not know any switch: in
JupyterLab at 1280x720 with the file browser open (a notebook output about
850 px wide), in Voila and on a wide screen alike.  Pictures that no longer
fit side by side wrap onto the next row and share the row's width, up to
``PROJECTOR_MAX_PX_PER_PT``; the figures themselves do not change, so no
legend or label moves.  The live agent dashboard's metric curves, one wide
figure, are drawn ``PROJECTOR_SCALE`` times smaller in inches instead, their
text keeping its points.

Every dashboard carries a visible button, *Large text: on*, that switches it
alone to the compact notebook size and back (``set_projector``);
:func:`projector` switches every dashboard of the kernel, and
``SARSP_EDU_PROJECTOR=0`` in the environment starts them compact.  Whatever
the size, a slider's knob, a readout and a button that has the keyboard's
focus are outlined (``FOCUS_OUTLINE``), so that a keyboard user sees where
they are.
"""

from __future__ import annotations

import os
import weakref

import ipywidgets as widgets

__all__ = ["FOCUS_OUTLINE", "PROJECTOR_MAX_PX_PER_PT", "PROJECTOR_PX_PER_PT", "PROJECTOR_SCALE", "PROJECTOR_TEXT_PX",
           "ProjectorMixin", "projector", "projector_default", "slider_width"]

#: how much larger the agent dashboard's metric curves' text is against the same space in projector size
PROJECTOR_SCALE = 1.6
#: a dashboard picture's smallest display size in projector size, CSS px per point of the figure: 10 pt at 14.2 px
PROJECTOR_PX_PER_PT = 1.42
#: and its largest, where a picture has a row to itself: 10 pt at 16 px
PROJECTOR_MAX_PX_PER_PT = 1.6
#: widget labels, readouts, buttons and tables in projector size, in CSS px
PROJECTOR_TEXT_PX = 18
#: the outline of a control that has the keyboard's focus: dark blue on the white page, 10:1 against it
FOCUS_OUTLINE = "3px solid #0b3d91"

_CLASS = "sarsp-projector"
_SCOPE = f".{_CLASS}"
#: on every dashboard, whatever its size: the focus outline is scoped to it
_DASHBOARD_CLASS = "sarsp-dashboard"
_FOCUSABLE = ("button", "input", "select", "textarea", ".noUi-handle", ".widget-readout", ".widget-toggle-button")
_FOCUS_CSS = (
    ", ".join(f".{_DASHBOARD_CLASS} {selector}:focus-visible" for selector in _FOCUSABLE)
    + f" {{outline: {FOCUS_OUTLINE} !important; outline-offset: 2px !important;}}"
)
_PROJECTOR_CSS = (
    "<style>"
    f"{_SCOPE} .widget-label, {_SCOPE} .widget-readout, {_SCOPE} .widget-button, {_SCOPE} .widget-toggle-button,"
    f" {_SCOPE} .widget-checkbox label, {_SCOPE} .widget-html-content, {_SCOPE} .widget-htmlmath-content,"
    f" {_SCOPE} .widget-html-content span, {_SCOPE} .widget-html-content div, {_SCOPE} table,"
    f" {_SCOPE} .widget-dropdown select {{font-size: {PROJECTOR_TEXT_PX}px !important;}}"
    f" {_SCOPE} .widget-hslider, {_SCOPE} .widget-hslider .widget-label, {_SCOPE} .widget-readout,"
    f" {_SCOPE} .widget-button, {_SCOPE} .widget-toggle-button, {_SCOPE} .widget-checkbox,"
    f" {_SCOPE} .widget-dropdown, {_SCOPE} .widget-dropdown select"
    f" {{height: 36px !important; line-height: 36px !important;}}"
    f" {_SCOPE} .widget-html-content, {_SCOPE} .widget-htmlmath-content {{line-height: 1.35 !important;}}"
    f" {_SCOPE} .widget-checkbox {{width: auto !important;}}"  # its label whole, not cut at 300 px
    f" {_FOCUS_CSS}"
    "</style>"
)

_SWITCH = {"on": None}  # None: automatic (on, unless SARSP_EDU_PROJECTOR=0)
_DASHBOARDS: "weakref.WeakSet" = weakref.WeakSet()


def projector_default() -> bool:
    """Whether a new dashboard starts in projector size: as :func:`projector` last set it, else automatic.

    Automatic means on, unless the environment variable
    ``SARSP_EDU_PROJECTOR`` is ``0`` (``1`` also means on).
    """
    if _SWITCH["on"] is not None:
        return _SWITCH["on"]
    return os.environ.get("SARSP_EDU_PROJECTOR", "") != "0"


def projector(on: bool | None = True) -> None:
    """Switch every dashboard of this kernel, on show and to come, to projector size (or compact with ``False``).

    Projector size: widget labels, readouts, buttons and tables at 18 px, and
    plot text at 14.2 px or more, for the back row of a lecture room at
    1280x720.  It is the default; ``projector(False)`` once at the top of a
    notebook makes all of its dashboards compact.  ``None`` makes it
    automatic again (:func:`projector_default`).  Each dashboard's *Large
    text* button switches it alone.
    """
    if on is not None and not isinstance(on, bool) and on not in (0, 1):
        raise TypeError(f"on must be True, False or None (automatic), got on={on!r}")
    _SWITCH["on"] = None if on is None else bool(on)
    for dashboard in list(_DASHBOARDS):
        dashboard.set_projector(projector_default())


def _toggle_description(on: bool) -> str:
    return f"Large text: {'on' if on else 'off'}"


class ProjectorMixin:
    """What every dashboard shares for projector size: the CSS, the slider widths, the switch and its button.

    A subclass calls ``_init_projector(on, toggle_row=row)`` once its
    children exist and implements ``_resize_pictures()``, which redraws its
    pictures at the size ``self.projector`` asks for.  The button that
    switches the size, ``self.size_toggle``, is added at the end of
    ``toggle_row`` (a row of the dashboard's controls); without one the
    subclass places it itself.
    """

    projector: bool = False

    def _init_projector(self, on, toggle_row=None) -> None:
        self.projector = projector_default() if on is None else bool(on)
        self.size_toggle = widgets.ToggleButton(
            value=self.projector, description=_toggle_description(self.projector),
            tooltip="Large text and pictures, for the back row of a lecture room; "
                    "press for the compact notebook size (and back)",
            layout=widgets.Layout(width="auto", flex="0 0 auto"))
        self.size_toggle.observe(lambda change: self.set_projector(change["new"]), names="value")
        if toggle_row is not None:
            toggle_row.children = (*toggle_row.children, self.size_toggle)
        # last, so that the children's places stay as the dashboard laid them out
        self.children = (*self.children, widgets.HTML(_PROJECTOR_CSS, layout=widgets.Layout(display="none")))
        self.add_class(_DASHBOARD_CLASS)
        _DASHBOARDS.add(self)
        self._apply_projector_classes()

    def _apply_projector_classes(self) -> None:
        (self.add_class if self.projector else self.remove_class)(_CLASS)
        toggle = getattr(self, "size_toggle", None)
        if toggle is not None:
            toggle.value = self.projector  # its observer returns at once: the size is already set
            toggle.description = _toggle_description(self.projector)
        for control in _walk(self):
            if isinstance(control, (widgets.FloatSlider, widgets.IntSlider)):
                width = slider_width(control.description, self.projector)
                # its width at most the page's: on a narrow screen (JupyterLab at 800 x 600) the track gives way,
                # not the readout
                room = "calc(100% - 4px)"  # the row's width less the widget's own margins (2 px a side)
                control.layout.width, control.layout.min_width = width, f"min({width}, {room})"
                control.layout.max_width = room

    def set_projector(self, on: bool = True) -> None:
        """This dashboard alone in projector size (text for the back row) or back to the compact notebook size."""
        on = bool(on)
        if on == self.projector:
            return
        self.projector = on
        self._apply_projector_classes()
        self._resize_pictures()

    def _resize_pictures(self) -> None:  # pragma: no cover - every dashboard overrides it
        raise NotImplementedError


def _walk(widget):
    yield widget
    for child in getattr(widget, "children", ()):
        yield from _walk(child)


#: a slider's track is at least this wide (px), its label and readout beside it
TRACK_PX = 160
LABEL_PX_PER_CHAR = 8
LABEL_PX_PAD = 30
READOUT_PX = 70


def slider_width(description: str, projector: bool = False) -> str:
    """Room for the label, a track of at least ``TRACK_PX`` and the readout: a long label never squeezes the track.

    In projector size the label and the readout are drawn at 18 px instead
    of 13, so they get that much more room.

    Parameters
    ----------
    description : str
        The slider's label; each character gets ``LABEL_PX_PER_CHAR`` px.
    projector : bool, default False
        Size for projector text (18 px) instead of 13 px.

    Returns
    -------
    str
        A CSS width such as ``"420px"``.
    """
    grow = PROJECTOR_TEXT_PX / 13 if projector else 1.0
    return f"{round(LABEL_PX_PAD + grow * (LABEL_PX_PER_CHAR * len(description) + READOUT_PX)) + TRACK_PX}px"
