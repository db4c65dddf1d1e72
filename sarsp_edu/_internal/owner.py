"""One thread owns some state; every other thread sends it calls through one queue.

:class:`Owner` is a mixin for an object whose state only one thread may touch (the live run's experiments and
its view, :class:`~sarsp_edu.teaching.live.controller.LiveRun`).  The object starts that thread with
:meth:`Owner._start_owner`; any thread hands it work with :meth:`Owner.submit` (a future of the result) or
:meth:`Owner.call` (waits, and raises what the work raised); a producer of news (a fit that advanced) posts
with :meth:`Owner.post_news`.  Between two items the thread does work of its own: the subclass says when
(``_due``: seconds from now, or None for none) and what (``_advance``), and what news means (``_news``).
Work submitted from the owning thread itself is done at once, so that it never waits for itself.

The owning thread is a daemon (a notebook never waits for it), so a script may reach its end while the thread
is inside numpy or a lock; the interpreter then ends under it, which may abort the process.  So every owner
still open when the interpreter begins to exit is closed then (an ``atexit`` hook): its thread ends the item
under way and stops, and the interpreter ends after it.
"""

from __future__ import annotations

import atexit
import queue
import threading
import weakref
from concurrent.futures import Future

__all__ = ["Closed", "Owner"]


class Closed(RuntimeError):
    """Work sent to an owner whose thread has ended."""


#: a news item on the queue (``post_news``)
_NEWS = object()
#: every owner whose thread was started, closed at the interpreter's exit (:func:`_close_all`)
_OWNERS = weakref.WeakSet()


class Owner:
    """The mixin: one owning thread, one queue of work (see the module's docstring)."""

    #: what a call to a closed owner raises (the subclass may say more)
    closed_message = "the owner's thread has ended"

    def _start_owner(self, name: str) -> None:
        self._inbox = queue.Queue()
        self._owner_ending = False
        self._owner_thread = threading.Thread(target=self._own, name=name, daemon=True)
        self._owner_thread.start()
        _OWNERS.add(self)

    @property
    def in_owner_thread(self) -> bool:
        """Whether the calling thread is the owning one."""
        return threading.current_thread() is self._owner_thread

    def submit(self, function, *args) -> Future:
        """Have the owning thread call ``function(*args)`` between two items of its work; a future of the result.

        Parameters
        ----------
        function : callable
        *args
            Its arguments.
        """
        future = Future()
        if self.in_owner_thread:  # the owning thread itself: at once (it would wait for itself)
            _settle(future, function, args)
        elif self._owner_ending or not self._owner_thread.is_alive():
            future.set_exception(Closed(self.closed_message))
        else:
            self._inbox.put((function, args, future))
        return future

    def call(self, function, *args):
        """:meth:`submit`, then wait: what ``function(*args)`` returned, or raise what it raised.

        Parameters
        ----------
        function : callable
        *args
            Its arguments.
        """
        return self.submit(function, *args).result()

    def settle(self) -> None:
        """Wait until the owning thread has taken every item sent before this call (at once if it has ended)."""
        try:
            self.call(lambda: None)
        except Closed:
            pass

    def post_news(self) -> None:
        """Tell the owning thread that something it follows has changed (any thread; never waits)."""
        self._inbox.put(_NEWS)

    def _end_owner(self) -> None:
        """In the owning thread: end it once the item under way is done; later work is refused (``Closed``)."""
        self._owner_ending = True

    def _join_owner(self) -> None:
        if not self.in_owner_thread:
            self._owner_thread.join()

    def close(self) -> None:
        """End the owning thread once the item under way is done, and wait for it (a subclass says more)."""
        self.submit(self._end_owner)
        self._join_owner()

    # -- what the subclass defines ----------------------------------------------------------
    def _due(self) -> float | None:
        """Seconds until the owning thread has work of its own (0: now; None: none until an item comes)."""
        return None

    def _advance(self) -> None:
        """One unit of the owning thread's own work."""

    def _news(self) -> None:
        """What the owning thread does with news."""

    # -- the owning thread ------------------------------------------------------------------
    def _own(self) -> None:
        while True:
            due = self._due()
            try:
                item = self._inbox.get_nowait() if due == 0 else self._inbox.get(timeout=due)
            except queue.Empty:
                item = None
            if item is _NEWS:
                self._news()
            elif item is not None:
                _settle(item[2], item[0], item[1])
            else:
                self._advance()
            if self._owner_ending:
                self._refuse_the_rest()
                return

    def _refuse_the_rest(self) -> None:
        while True:
            try:
                item = self._inbox.get_nowait()
            except queue.Empty:
                return
            if item is not _NEWS:
                item[2].set_exception(Closed(self.closed_message))


@atexit.register
def _close_all() -> None:
    for owner in list(_OWNERS):
        if owner._owner_thread.is_alive():
            owner.close()


def _settle(future: Future, function, args) -> None:
    """Call ``function(*args)``; its result, or what it raised, into ``future``."""
    if not future.set_running_or_notify_cancel():
        return
    try:
        future.set_result(function(*args))
    except BaseException as exc:  # handed to whoever waits (or, for work nobody waits for, kept in the future)
        future.set_exception(exc)
