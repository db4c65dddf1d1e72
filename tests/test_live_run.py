"""The live run's controller without widgets (sarsp_edu.teaching.live.controller.LiveRun).

It must step the very runs the paired comparison steps, refuse a second
stepper while its agents walk, stop and close for good, say which side
retrains, call its view only under its lock, and limit BLAS to one thread
only while a side steps (the notebook's own cells keep every thread between
steps).
"""

from __future__ import annotations

import threading
import time

import pandas as pd
import pytest

from sarsp_edu.config import ExperimentConfig
from sarsp_edu.experiments.experiment import paired_experiments
from sarsp_edu.teaching.live import TP_AND_GP, LiveRun

SMALL = ExperimentConfig(grid_size=6, n_unsafe=5, offline_episodes=8, cost_fit_points=80, reward_fit_points=80,
                         optimizer_steps=5, k_prior=30, episodes=3, n_switch_states=1)


class RecordingView:
    """A view that records what it is asked to show, and whether the run's lock was held each time."""

    def __init__(self):
        self.run = None
        self.calls = []
        self.unlocked = []

    def _record(self, *call):
        self.calls.append(call)
        if not self.run.lock._is_owned():
            self.unlocked.append(call)

    def show_side(self, name):
        self._record("side", name)

    def show_metrics(self, throttle=False):
        self._record("metrics", throttle)

    def show_waiting(self, name, why):
        self._record("waiting", name, why)

    def say(self, text):
        self._record("say", text)

    def said(self):
        return [call[1] for call in self.calls if call[0] == "say"]


@pytest.fixture
def run(monkeypatch):
    monkeypatch.setenv("SARSP_EDU_CACHE", "off")
    view = RecordingView()
    live = LiveRun(dict(TP_AND_GP), lambda: SMALL, view=view, steps_per_second=60)
    view.run = live
    yield live
    live.close()


def _wait_until(condition, seconds=120):
    deadline = time.monotonic() + seconds
    while not condition() and time.monotonic() < deadline:
        time.sleep(0.02)
    return condition()


def test_stepping_in_lock_step_gives_the_paired_comparisons_runs(run):
    run.run_steps(1000)  # stops at the last episode
    assert run.finished
    expected = paired_experiments(SMALL)
    for name, experiment in expected.items():
        while not experiment.finished:
            experiment.run_episode()
        pd.testing.assert_frame_equal(run.experiments[name].records(), experiment.records())
    assert run.view.calls and not run.view.unlocked


def test_a_launched_run_steps_both_sides_and_stops_when_told(run):
    run.build()
    thread = run.launch()
    assert thread is not None and run.launch() is None  # one run at a time
    assert _wait_until(lambda: run.frames >= 3)
    for call in (lambda: run.run_steps(1), lambda: run.fast_forward(1), lambda: run.step_pair()):
        with pytest.raises(RuntimeError, match="while the agents are running: press Stop"):
            call()
    run.stop()
    thread.join(60)
    assert not thread.is_alive() and not run.running
    assert run.view.said()[-1].startswith("Stopped.")
    steps = {name: len(e.act_seconds) for name, e in run.experiments.items()}
    run.run_steps(1)  # stepping from the caller's thread is allowed again once stopped
    after = {name: len(e.act_seconds) for name, e in run.experiments.items()}
    assert all(after[name] != steps[name] for name in steps)
    assert not run.view.unlocked


def test_close_ends_the_sides_threads_and_the_fits_and_refuses_a_new_launch(run):
    thread = run.launch()  # claims the fits begun for the settings, and steps each side once fitted
    assert _wait_until(lambda: run.frames >= 1)
    run.close()
    thread.join(60)
    assert not thread.is_alive() and not run.running and run.experiments is None
    assert run.fits._thread is None or not run.fits._thread.is_alive()
    assert run.launch() is None
    assert not [t for t in threading.enumerate() if t.name == "sarsp-edu-side" and t.is_alive()]
    for call in (lambda: run.run_steps(1), lambda: run.fast_forward(1), lambda: run.step_pair()):
        with pytest.raises(RuntimeError, match=r"after close\(\): this run is closed"):  # nothing rebuilt, stepped
            call()
    assert run.experiments is None


def test_a_launched_run_that_fails_says_so_and_ends(run):
    run.build()

    def broken():
        raise ValueError("a broken step")

    run.experiments["gp"].step = broken
    thread = run.launch()
    thread.join(60)
    assert not run.running
    assert any("Stopped by an error: a broken step" in text for text in run.view.said())


def test_a_retrain_is_said_while_it_lasts(run):
    run.build()
    seen = []

    class Probe:  # a model whose refit records what the run says meanwhile
        def fit(self, X, y):
            seen.append(dict(run.retraining))

    run.experiments["gp"].agent.refit_model(Probe(), None, None)  # how a corrective update refits, watched
    assert seen == [{"tp": False, "gp": True}]
    assert run.retraining == {"tp": False, "gp": False}


def test_blas_is_limited_while_a_side_steps_not_between_steps(run, monkeypatch):
    """The limit is process-wide: held for the whole animation, the notebook's own cells would run on one BLAS
    thread too.  Counted here through the controller's own context manager."""
    import contextlib

    from sarsp_edu.teaching.live import controller

    held = []

    @contextlib.contextmanager
    def counted():
        held.append(threading.current_thread().name)
        try:
            yield
        finally:
            held.remove(threading.current_thread().name)

    monkeypatch.setattr(controller, "one_blas_thread", counted)
    run.build()
    run.steps_per_second = 2  # mostly waiting between steps
    steps = []
    plain = run.experiments["tp"].step
    run.experiments["tp"].step = lambda: steps.append(list(held)) or plain()
    thread = run.launch()
    assert _wait_until(lambda: run.frames >= 1)
    free = []
    for _ in range(20):
        free.append(not held)
        time.sleep(0.05)
    run.stop()
    thread.join(60)
    assert steps and all(holders for holders in steps), "each step runs under the limit"
    assert any(free), "between steps nothing holds the limit: the notebook's own cells keep every BLAS thread"


def test_run_again_right_after_stop_never_steps_one_side_from_two_threads(run):
    """Stop, then Run, while a side is inside a long step (a retrain): the earlier launch's thread ends that step
    and no other; the new launch's thread waits for it, and the earlier thread does not stop the new run."""
    run.build()
    experiment = run.experiments["gp"]
    plain, inside, release, concurrent, most = experiment.step, threading.Event(), threading.Event(), [0], [0]

    def long_step():
        concurrent[0] += 1
        most[0] = max(most[0], concurrent[0])
        try:
            if not release.is_set():
                inside.set()
                release.wait(60)
            return plain()
        finally:
            concurrent[0] -= 1

    experiment.step = long_step
    first = run.launch()
    assert inside.wait(60)
    run.stop()
    second = run.launch()
    assert second is not None and run.running
    release.set()
    first.join(60)
    assert not first.is_alive() and run.running, "the earlier launch's end must not stop the new run"
    steps = len(experiment.act_seconds)
    assert _wait_until(lambda: len(experiment.act_seconds) >= steps + 3)
    run.stop()
    second.join(60)
    assert most[0] == 1, "two threads stepped one side at once"
    watched = experiment.agent.refit_model
    run._adopt("gp", experiment)  # adopted again (both launches' threads adopt a side that joins): one watch
    assert experiment.agent.refit_model is watched and watched.watched_by is run


def test_a_side_awaited_after_its_run_was_discarded_is_none_not_an_error(run):
    token = run._token()
    run.discard()  # a slider moved while a side's thread was about to wait for its fit
    assert run._await_side("tp", token) is None  # was: TypeError, argument of type 'NoneType' is not iterable


def test_an_error_of_a_run_discarded_meanwhile_is_not_said(run, monkeypatch):
    def play_then_fail(generation):
        run.discard()  # a slider moved while the run was preparing
        raise TypeError("argument of type 'NoneType' is not iterable")

    monkeypatch.setattr(run, "_play", play_then_fail)
    thread = run.launch()
    thread.join(60)
    assert not any("Stopped by an error" in text for text in run.view.said()), run.view.said()


def test_fast_forward_steps_each_side_holding_its_step_lock(run, monkeypatch):
    run.build()
    held = []
    for name, experiment in run.experiments.items():
        def episode(original=experiment.run_episode, name=name):
            held.append(run._step_locks[name].locked())  # a stopped side's thread cannot be in a step meanwhile
            return original()

        monkeypatch.setattr(experiment, "run_episode", episode)
    run.fast_forward(1)
    assert len(held) == 2 and all(held)


def test_closing_the_fit_queue_starts_no_process(monkeypatch):
    from sarsp_edu.teaching.live import fitting
    from sarsp_edu.teaching.live.background import FitQueue

    monkeypatch.setenv("SARSP_EDU_CACHE", "off")
    queue = FitQueue(dict(TP_AND_GP))
    queue.request(SMALL.replace(optimizer_steps=400))  # long enough to be under way when closed
    assert _wait_until(lambda: any(fits.progress for fits in list(queue._pending_fits.values())))
    started = []
    real = fitting.FitWorker

    def counted():
        started.append(1)
        return real()

    monkeypatch.setattr(fitting, "FitWorker", counted)
    thread = queue._thread
    queue.close()
    thread.join(60)
    assert not thread.is_alive() and started == []  # was: one replacement process per abandoned worker
