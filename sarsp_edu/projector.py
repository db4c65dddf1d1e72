"""Projector size: text the back of a lecture room can read, for every dashboard, with one switch.

:func:`projector` switches every dashboard of the
kernel, those on show and those to come, to text the back of a lecture room
can read: widget labels, readouts, buttons and tables at
``PROJECTOR_TEXT_PX`` (18 px), and pictures shown at ``PROJECTOR_PX_PER_PT``
CSS px per point, so that their 10 pt text is 14.5 px, wrapping onto a
second row where they no longer fit side by side (the figures themselves do
not change, so no legend or label moves).  The live agent dashboard's
metric curves, one wide figure, are drawn ``PROJECTOR_SCALE`` times smaller
in inches instead, their text keeping its points.  Projector size is on by
default in Voila (which sets ``VOILA_KERNEL_ID`` in the kernel) and wherever
``SARSP_EDU_PROJECTOR=1``; each dashboard's ``set_projector`` switches it
alone.
"""

from __future__ import annotations

import os
import weakref

import ipywidgets as widgets

__all__ = ["PROJECTOR_PX_PER_PT", "PROJECTOR_SCALE", "PROJECTOR_TEXT_PX", "ProjectorMixin", "projector", "projector_default",
           "slider_width"]

#: how much larger the agent dashboard's metric curves' text is against the same space in projector size
PROJECTOR_SCALE = 1.6
#: a dashboard picture's display size in projector size, CSS px per point of the figure: its 10 pt text at 14.5 px
PROJECTOR_PX_PER_PT = 1.45
#: widget labels, readouts, buttons and tables in projector size, in CSS px
PROJECTOR_TEXT_PX = 18

_CLASS = "sarsp-projector"
_SCOPE = f".{_CLASS}"
_PROJECTOR_CSS = (
    "<style>"
    f"{_SCOPE} .widget-label, {_SCOPE} .widget-readout, {_SCOPE} .widget-button, {_SCOPE} .widget-toggle-button,"
    f" {_SCOPE} .widget-checkbox label, {_SCOPE} .widget-html-content, {_SCOPE} .widget-htmlmath-content,"
    f" {_SCOPE} .widget-html-content span, {_SCOPE} .widget-html-content div, {_SCOPE} table"
    f" {{font-size: {PROJECTOR_TEXT_PX}px !important;}}"
    f" {_SCOPE} .widget-hslider, {_SCOPE} .widget-hslider .widget-label, {_SCOPE} .widget-readout,"
    f" {_SCOPE} .widget-button, {_SCOPE} .widget-toggle-button, {_SCOPE} .widget-checkbox"
    f" {{height: 36px !important; line-height: 36px !important;}}"
    f" {_SCOPE} .widget-html-content, {_SCOPE} .widget-htmlmath-content {{line-height: 1.35 !important;}}"
    f" {_SCOPE} .widget-checkbox {{width: auto !important;}}"  # its label whole, not cut at 300 px
    "</style>"
)

_SWITCH = {"on": None}  # None: automatic (on in Voila or with SARSP_EDU_PROJECTOR=1)
_DASHBOARDS: "weakref.WeakSet" = weakref.WeakSet()


def projector_default() -> bool:
    """Whether a new dashboard starts in projector size: as :func:`projector` last set it, else automatic.

    Automatic means on in Voila (its kernels have ``VOILA_KERNEL_ID``) or
    where the environment variable ``SARSP_EDU_PROJECTOR`` is ``1``, off
    otherwise.
    """
    if _SWITCH["on"] is not None:
        return _SWITCH["on"]
    switch = os.environ.get("SARSP_EDU_PROJECTOR", "")
    if switch in ("0", "1"):
        return switch == "1"
    return "VOILA_KERNEL_ID" in os.environ


def projector(on: bool | None = True) -> None:
    """Switch every dashboard of this kernel, on show and to come, to projector size (or back with ``False``).

    Projector size: widget labels, readouts, buttons and tables at 18 px, and
    plot text at 14.5 px or more, for the back row of a lecture room at
    1280x720.  One call at the top of a notebook switches all of its
    dashboards.  ``None`` makes it automatic again (:func:`projector_default`).
    """
    if on is not None and not isinstance(on, bool) and on not in (0, 1):
        raise TypeError(f"on must be True, False or None (automatic), got on={on!r}")
    _SWITCH["on"] = None if on is None else bool(on)
    for dashboard in list(_DASHBOARDS):
        dashboard.set_projector(projector_default())


class ProjectorMixin:
    """What every dashboard shares for projector size: the CSS, the slider widths, the switch.

    A subclass calls ``_init_projector(on)`` once its children exist and
    implements ``_resize_pictures()``, which redraws its pictures at the size
    ``self.projector`` asks for.
    """

    projector: bool = False

    def _init_projector(self, on) -> None:
        self.projector = projector_default() if on is None else bool(on)
        # last, so that the children's places stay as the dashboard laid them out
        self.children = (*self.children, widgets.HTML(_PROJECTOR_CSS, layout=widgets.Layout(display="none")))
        _DASHBOARDS.add(self)
        self._apply_projector_classes()

    def _apply_projector_classes(self) -> None:
        (self.add_class if self.projector else self.remove_class)(_CLASS)
        for control in _walk(self):
            if isinstance(control, (widgets.FloatSlider, widgets.IntSlider)):
                width = slider_width(control.description, self.projector)
                control.layout.width = control.layout.min_width = width

    def set_projector(self, on: bool = True) -> None:
        """This dashboard alone in projector size (text for the back row) or back to notebook size."""
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
    """
    grow = PROJECTOR_TEXT_PX / 13 if projector else 1.0
    return f"{round(LABEL_PX_PAD + grow * (LABEL_PX_PER_CHAR * len(description) + READOUT_PX)) + TRACK_PX}px"
