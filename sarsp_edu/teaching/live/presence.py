"""Whether the page that shows a live run is still there: the run stops when its page has gone.

A kernel is not told when the browser tab that shows it is closed or
reloaded: a Voila page's kernel, or a notebook's closed in JupyterLab, would
go on animating its agents at about a core each until the server ends it.
:class:`PagePresence` asks the page for a sign of life instead: a hidden
``ipywidgets.Play`` counts up once a second *in the browser*, and each count
reaches the kernel as a change of its value.  While a live run runs, its
thread looks at the time of the last count (:meth:`PagePresence.gone`); when
the page, heard before, has said nothing for :data:`SILENCE_SECONDS` (a page in a hidden tab
is still heard: browsers slow a hidden tab's timers to about one a minute, not
to none) the run stops and says why, and the kernel, idle now, is left to the
server's idle culling (``voila.json``).  *Run* starts it again where the page
is still there (after a reload in JupyterLab, say).

A ``Play`` widget starts counting only when its ``playing`` turns on after its
view is drawn.  The widget asks the page to report its views (ipywidgets'
``_view_count``): when the page says it has drawn one, the kernel turns the
count on (a Voila page: at once, since its new kernel's ``playing`` is off).  A
view drawn while ``playing`` is already on (a notebook reloaded in JupyterLab,
whose page rebuilds the widget as the kernel left it) does not count; the run's
thread then turns it off, then on, one change every :data:`ARM_EVERY` seconds,
until the page is heard (:meth:`PagePresence.arm`).  Before any view is drawn
nothing is touched, so that a page that is still loading draws ``playing`` off.
Outside a kernel (a script, a test without a browser) there is no page to hear,
and nothing stops.

While the kernel runs a cell (a *Run All* of the cells below the dashboard),
it reads no message, the page's counts included: that silence is not the
page's, and it does not count (IPython's ``pre_run_cell`` and
``post_run_cell`` events say when a cell runs).

Who owns what: the counts, the views drawn and the cells' beginnings and ends
are written by the kernel's main thread (the widget's observers and the
events' callbacks) and read by the run's thread; each is a float or a bool
replaced whole, so the reader sees the last value or the one before.  The
widget's ``playing`` is changed by the main thread when a view is drawn and by
the run's thread in :meth:`~PagePresence.arm`, never both for one view: the
run's thread leaves it alone for :data:`ARM_EVERY` seconds after the main
thread has set it.
"""

from __future__ import annotations

import os
import time

__all__ = ["ARM_EVERY", "SILENCE_SECONDS", "PagePresence", "in_a_kernel"]

#: the page counts once a second; a count every ``ARM_EVERY`` s or less is needed for the page to be heard
INTERVAL_MS = 1000
#: seconds between two attempts to start the page's count, while it is not heard
ARM_EVERY = 2.0
#: seconds of silence after which the page is taken for gone (``SARSP_EDU_PAGE_SILENCE`` overrides it)
SILENCE_SECONDS = 90.0
SILENCE_VARIABLE = "SARSP_EDU_PAGE_SILENCE"


def in_a_kernel() -> bool:
    """Whether this code runs in a Jupyter kernel (where a page may show the run)."""
    try:
        from IPython import get_ipython
    except ImportError:
        return False
    shell = get_ipython()
    return shell is not None and getattr(shell, "kernel", None) is not None


def silence_seconds() -> float:
    """:data:`SILENCE_SECONDS`, or the positive number of seconds ``SARSP_EDU_PAGE_SILENCE`` gives."""
    given = os.environ.get(SILENCE_VARIABLE)
    if given is None:
        return SILENCE_SECONDS
    try:
        seconds = float(given)
    except ValueError:
        seconds = float("nan")
    if not seconds > 0 or seconds == float("inf"):
        raise ValueError(f"{SILENCE_VARIABLE} must be a positive number of seconds, got {SILENCE_VARIABLE}={given!r}")
    return seconds


class PagePresence:
    """A hidden counter in the page, and how long ago it was last heard.

    Parameters
    ----------
    listening : bool, optional
        Whether a page can be heard at all; default: :func:`in_a_kernel`.
    clock : callable, default time.monotonic
        The seconds the silences are measured in (a test's own clock).
    """

    def __init__(self, listening: bool | None = None, clock=time.monotonic, shell=None):
        import ipywidgets as widgets

        self.listening = in_a_kernel() if listening is None else bool(listening)
        #: while the kernel runs a cell it reads no message, the page's counts included: silence then is the
        #: kernel's, not the page's (a Run All of the cells below the dashboard can take minutes)
        self.busy, self._idle_since = False, None
        self._shell = shell
        if self._shell is None and self.listening and in_a_kernel():
            from IPython import get_ipython

            self._shell = get_ipython()
        if self._shell is not None:
            self._shell.events.register("pre_run_cell", self._cell_began)
            self._shell.events.register("post_run_cell", self._cell_ended)
        self.silence = silence_seconds()
        self._clock = clock
        self.widget = widgets.Play(value=0, min=0, max=2**31 - 1, interval=INTERVAL_MS, playing=False,
                                   show_repeat=False, description="page presence",
                                   layout=widgets.Layout(width="0px", height="0px", overflow="hidden",
                                                         visibility="hidden", margin="0px"),
                                   _view_count=0)  # 0, not None: the page reports each view it draws
        self.widget.observe(self._heard, names="value")
        self.widget.observe(self._drawn, names="_view_count")
        self.drawn_at = None  # when the page last drew a view of the counter (the clock's seconds); None: never
        self.last_heard = None  # when the page last counted (the clock's seconds); None: never
        self._since = None  # when the current watch began (a run's start)
        self._armed = None  # when the count was last (re)started

    def _heard(self, change) -> None:  # the kernel's main thread: a count from the page
        self.last_heard = self._clock()

    def _drawn(self, change) -> None:  # the kernel's main thread: the page drew (or removed) a view
        if not self.listening or (change["new"] or 0) <= (change["old"] or 0):
            return  # a view removed (a closed notebook tab): its silence will tell
        self.drawn_at = self._clock()
        if not self.widget.playing:
            self._armed = self.drawn_at
            self.widget.playing = True  # the view, drawn, sees 'playing' turn on: it counts from now

    def _cell_began(self, info=None) -> None:  # the kernel's main thread, as it begins a cell
        self.busy = True

    def _cell_ended(self, result=None) -> None:  # the kernel's main thread, as a cell ends: the silence restarts
        self.busy, self._idle_since = False, self._clock()

    def close(self) -> None:
        """Stop listening to the kernel's cells (the dashboard is closed)."""
        if self._shell is not None:
            for event, callback in (("pre_run_cell", self._cell_began), ("post_run_cell", self._cell_ended)):
                try:
                    self._shell.events.unregister(event, callback)
                except ValueError:  # not registered (closed twice)
                    pass
            self._shell = None

    def watch(self) -> None:
        """A run begins: the page must be heard from now on (the run's thread)."""
        self._since = self._clock()

    def arm(self) -> None:
        """Start the page's count where a view is drawn but not heard since (the run's thread)."""
        now = self._clock()
        if not self.listening or self.drawn_at is None or self._since is None:
            return  # no view drawn yet: 'playing' is left off for the page to draw it so
        heard = self.last_heard is not None and self.last_heard >= self.drawn_at  # the view drawn last counts
        if heard or (self._armed is not None and now - self._armed < ARM_EVERY):
            return
        self._armed = now
        # off at one call, on at the next: the view sees 'playing' turn on.  Both at once raced with the page's
        # own answer to 'off' (its pause sends playing = False back), which could stop the count just started
        self.widget.playing = not self.widget.playing

    def gone(self) -> bool:
        """Whether the page, heard since the watch began, has said nothing for ``silence`` seconds since (False
        where no page can be heard, before :meth:`watch`, while a cell runs, and while the page has not been heard:
        a counter that did not start is not a page that went away)."""
        if not self.listening or self._since is None or self.busy:
            return False
        if self.last_heard is None or self.last_heard < self._since:
            return False  # never heard since the run began: its counter may not have started; no run stops for that
        last = max(t for t in (self.last_heard, self._idle_since) if t is not None)
        return self._clock() - last > self.silence
