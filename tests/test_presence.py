"""A live run stops when the page that shows it has gone (sarsp_edu.teaching.live.presence).

The page's sign of life is a hidden Play widget that counts in the browser; here a test's thread counts in its
place, as the kernel's main thread would receive the counts, while the run's thread steps the agents.
"""

from __future__ import annotations

import threading
import time

import pytest

from sarsp_edu.config import ExperimentConfig
from sarsp_edu.teaching.live import TP_AND_GP, LiveRun
from sarsp_edu.teaching.live.presence import ARM_EVERY, SILENCE_VARIABLE, PagePresence, in_a_kernel

from .test_live_run import RecordingView, _wait_until
from .worlds import SIX_BY_SIX

LONG = ExperimentConfig(**SIX_BY_SIX, episodes=200, n_switch_states=1)


class Clock:
    """A clock the test moves by hand."""

    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


def test_outside_a_kernel_no_page_is_listened_to_and_nothing_stops():
    assert not in_a_kernel()  # pytest is no kernel
    page = PagePresence()
    page.watch()
    page.arm()
    assert not page.listening and not page.gone() and page.widget.playing is False


def test_nothing_is_armed_before_the_page_draws_a_view(monkeypatch):
    """A page still loading must draw the counter with 'playing' off, or its view never starts counting."""
    clock = Clock()
    page = PagePresence(listening=True, clock=clock)
    assert page.widget._view_count == 0  # the page is asked to report its views
    page.watch()
    for _ in range(5):
        page.arm()
        clock.now += ARM_EVERY
    assert page.widget.playing is False and page.drawn_at is None


def test_a_view_drawn_turns_the_count_on_at_once_and_is_armed_again_only_while_unheard(monkeypatch):
    monkeypatch.setenv(SILENCE_VARIABLE, "30")
    clock = Clock()
    page = PagePresence(listening=True, clock=clock)
    toggles = []
    page.widget.observe(lambda change: toggles.append(change["new"]), names="playing")
    assert not page.gone()  # not watched yet: no run
    page.watch()
    page.widget._view_count = 1  # as the page reports a view drawn (the kernel's main thread)
    assert toggles == [True] and page.drawn_at == clock.now
    page.arm()  # at once: the count was just turned on
    assert toggles == [True]
    clock.now += ARM_EVERY
    page.arm()
    clock.now += ARM_EVERY
    page.arm()
    assert toggles == [True, False, True]  # not heard: off, then on at the next call
    page.widget.value += 1  # heard
    clock.now += ARM_EVERY
    page.arm()
    assert toggles == [True, False, True]
    page.widget._view_count = 0  # a view removed (a closed tab): nothing turned on or off
    assert toggles == [True, False, True]
    clock.now += 300
    page.widget._view_count = 1
    assert toggles == [True, False, True]  # a view drawn with 'playing' on (a reload in JupyterLab) ...
    page.arm()
    clock.now += ARM_EVERY
    page.arm()
    assert toggles == [True, False, True, False, True]  # ... is armed by the run's thread: off, then on


def _watched_and_drawn(monkeypatch):
    """A page whose run began (silence 30 s) and whose counter the page has drawn: (clock, page)."""
    monkeypatch.setenv(SILENCE_VARIABLE, "30")
    clock = Clock()
    page = PagePresence(listening=True, clock=clock)
    page.watch()
    page.widget._view_count = 1
    return clock, page


def test_a_page_never_heard_is_never_taken_for_gone(monkeypatch):
    clock, page = _watched_and_drawn(monkeypatch)
    clock.now += 300
    assert not page.gone()  # never heard: its counter may not have started, and a run is not stopped for that


def test_a_page_heard_is_not_armed_again_and_is_gone_only_after_its_last_count(monkeypatch):
    clock, page = _watched_and_drawn(monkeypatch)
    page.arm()
    clock.now += 1
    page.widget.value += 1  # the page counts
    armed = page._armed
    clock.now += 25
    page.arm()
    assert page._armed == armed  # heard since the watch: left as it is
    assert not page.gone()  # the count is 25 s old
    clock.now += 4
    page.widget.value += 1  # and again
    clock.now += 29
    assert not page.gone()  # 29 s since the last count, 58 since the watch
    clock.now += 2
    assert page.gone()


@pytest.mark.parametrize("value", ["0", "-3", "soon", "inf", "nan"])
def test_a_silence_that_is_not_a_positive_number_of_seconds_is_refused(monkeypatch, value):
    monkeypatch.setenv(SILENCE_VARIABLE, value)
    with pytest.raises(ValueError, match=f"SARSP_EDU_PAGE_SILENCE must be a positive number of seconds, got "
                                         f"SARSP_EDU_PAGE_SILENCE='{value}'"):
        PagePresence(listening=True)


def test_a_run_whose_page_counts_from_another_thread_steps_and_stops_when_the_counting_stops(monkeypatch):
    """Two threads: the run's, stepping, and this one, counting as the kernel's main thread receives the page's
    counts; when the counts stop, the run stops by itself and says why, and *Run* continues it."""
    monkeypatch.setenv("SARSP_EDU_CACHE", "off")
    monkeypatch.setenv(SILENCE_VARIABLE, "1.5")
    page = PagePresence(listening=True)
    view = RecordingView()
    run = LiveRun(dict(TP_AND_GP), lambda: LONG, view=view, steps_per_second=40, page=page)
    counting = threading.Event()
    counting.set()

    def count():
        while counting.is_set():
            page.widget.value += 1
            time.sleep(0.2)

    counter = threading.Thread(target=count, name="test-page")
    counter.start()
    try:
        launched = run.launch()
        assert _wait_until(lambda: run.frames >= 5)
        time.sleep(2.5)  # longer than the silence: the counts keep it going
        assert run.running and not launched.done()
        counting.clear()
        counter.join()
        stopped_at = run.frames
        assert launched.result(30) is True  # the run's thread stopped it
        assert not run.running and run.frames >= stopped_at
        assert any("has not been heard from in 2 s" in said for said in view.said()), view.said()
        assert not run.finished
        page.widget.value += 1  # the page is back (reloaded in JupyterLab): Run continues
        again = run.launch()
        assert _wait_until(lambda: run.frames >= 3)
        run.stop().result(30)
        assert again.result(30) is True
    finally:
        counting.clear()
        counter.join()
        run.close()


class Events:
    """IPython's ``shell.events``, as far as a page's presence uses them."""

    def __init__(self):
        self.callbacks = {"pre_run_cell": [], "post_run_cell": []}

    def register(self, event, callback):
        self.callbacks[event].append(callback)

    def unregister(self, event, callback):
        self.callbacks[event].remove(callback)

    def trigger(self, event):
        for callback in list(self.callbacks[event]):
            callback(None)


class Shell:
    def __init__(self):
        self.events = Events()


def test_a_kernel_busy_with_a_cell_is_not_a_silent_page(monkeypatch):
    """While the kernel runs a cell (Run All of the cells below the dashboard) it reads none of the page's counts:
    the run must not stop for that silence, which restarts when the cell ends."""
    monkeypatch.setenv(SILENCE_VARIABLE, "30")
    clock, shell = Clock(), Shell()
    page = PagePresence(listening=True, clock=clock, shell=shell)
    page.watch()
    clock.now += 1
    page.widget.value += 1  # heard once
    shell.events.trigger("pre_run_cell")
    clock.now += 300  # five minutes of cells: no count read
    assert not page.gone()
    shell.events.trigger("post_run_cell")
    clock.now += 29
    assert not page.gone()  # 29 s since the cell ended
    clock.now += 2
    assert page.gone()
    page.close()
    assert shell.events.callbacks == {"pre_run_cell": [], "post_run_cell": []}
    page.close()  # twice: nothing left to unregister
