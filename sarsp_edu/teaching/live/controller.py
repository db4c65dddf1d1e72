"""The live run without its widgets: the sides' runs, who steps them, one lock, a cancel event, ``close()``.

:class:`LiveRun` holds what the live dashboard runs, and runs it: each side steps in a daemon thread of its own,
one lock orders the steps' results and every change of the run (a slider move, *Stop*, *New run*), and an event
cancels the sides' threads at once.  It draws nothing: it tells a *view*
(:class:`~sarsp_edu.teaching.live.view.AgentDashboard`, or a test's recorder) what to show, through five methods::

    view.show_side(name)                # a side's run changed: its grid, its numbers, its decision
    view.show_metrics(throttle)         # an episode may have ended: the metric curves
    view.show_waiting(name, why)        # a side waits: for its fit, a retrain of its cost model ...
    view.say(html)                      # the status line
    view.preview()                      # no run: the world the settings imply

Every call into the view is made under :attr:`LiveRun.lock`, so a view need not lock anything itself.
"""

from __future__ import annotations

import html
import threading
import time

from ..._internal.threads import DaemonCall, one_blas_thread
from .background import FitQueue, changed_settings

__all__ = ["WAIT_SHOWN_AFTER", "LiveRun", "QuietView"]

#: a side whose step has taken this long shows why it waits (a retrain of its cost model, usually)
WAIT_SHOWN_AFTER = 0.25


class QuietView:
    """A view that shows nothing: a :class:`LiveRun` in a script or a test."""

    def show_side(self, name) -> None:
        """Nothing: a side's run changed."""

    def show_metrics(self, throttle: bool = False) -> None:
        """Nothing: an episode may have ended."""

    def show_waiting(self, name, why: str) -> None:
        """Nothing: the side ``name`` waits, ``why`` says for what (in words).

        Parameters
        ----------
        name : str
        why : str
        """

    def say(self, text: str) -> None:
        """Nothing: the status line."""

    def preview(self) -> None:
        """Nothing: the world the settings imply."""


class LiveRun:
    """Two agents run paired on one world, live, with no widgets: the live dashboard's controller.

    Parameters
    ----------
    sides : dict
        Name -> (title, changed settings), as :class:`~sarsp_edu.teaching.live.view.AgentDashboard` takes them.
    config : callable
        Returns the settings (``ExperimentConfig``) the next run starts from (the sliders' values).
    parts : dict, optional
        Side name -> :class:`~sarsp_edu.agent.parts.DecisionParts` its agent decides with.
    offline : dict, optional
        Seed -> the offline world and its clean data, shared with the view's preview (computed once per seed).
    view : optional
        What shows the run (see the module's docstring); default :class:`QuietView`.
    steps_per_second : float, default 30
        Animation speed per side; the view may change it at any time.
    """

    def __init__(self, sides: dict, config, *, parts=None, offline=None, view=None, steps_per_second=30.0):
        self.sides = sides
        self.config = config
        self.parts = dict(parts or {})
        self.view = QuietView() if view is None else view
        self.steps_per_second = float(steps_per_second)
        #: one lock around every change of the run and every call into the view
        self.lock = threading.RLock()
        self.fits = FitQueue(sides, offline=offline)
        self.generation = 0  # counts the run's discards: a thread of an older generation ends quietly
        self._launches = 0  # counts launches: a thread of an earlier launch (Stop, then Run) ends quietly too
        self._step_locks = {name: threading.Lock() for name in sides}  # one stepper per side, whoever launched it
        self._cancel = threading.Event()  # set when the run is stopped or discarded: sleeping sides wake up
        self.pending = None  # the fits under way for the current settings (FitQueue.claim)
        self.experiments = None
        self.running = False
        self.closed = False
        #: name -> True while that side's agent refits its cost model after a correction
        self.retraining = dict.fromkeys(sides, False)
        self._begin({})
        self.experiments = None

    # -- the run's state -------------------------------------------------------------
    def _begin(self, experiments) -> None:
        """Show these runs (all sides, or those fitted so far) from their start."""
        for name, experiment in experiments.items():
            self._adopt(name, experiment)
        self.experiments = experiments
        self.last = dict.fromkeys(self.sides)
        self.frames = 0
        self.frame_times = {name: [] for name in self.sides}
        self.stepping_since = dict.fromkeys(self.sides)
        self.longest_wait_seconds = dict.fromkeys(self.sides, 0.0)

    def _adopt(self, name, experiment):
        """The side's run, its agent given the side's parts and its refits watched (the view says "retraining")."""
        if experiment is None:
            return None
        agent = experiment.agent
        if name in self.parts:
            agent.parts = self.parts[name]
        inner = agent.refit_model
        if getattr(inner, "watched_by", None) is self:  # adopted before (by an earlier launch's thread)
            return experiment

        def watched(model, X, y):
            self.retraining[name] = True
            try:
                model.fit(X, y) if inner is None else inner(model, X, y)
            finally:
                self.retraining[name] = False

        watched.watched_by = self
        agent.refit_model = watched
        return experiment

    def discard(self) -> None:
        """Stop and forget the runs (settings changed); fits still under way are discarded when they end."""
        with self.lock:
            self.generation += 1
            self._cancel.set()
            self.running = False
            self._begin({})
            self.experiments = None

    def request_fits(self) -> None:
        """Start fitting the current settings' runs in the background (a newer request replaces an older one)."""
        self.fits.request(self.config())

    def build(self) -> None:
        """The runs of the current settings, now: those fitted ahead, waited for, or fitted here."""
        from ...experiments.experiment import experiments_on_one_world
        from . import fitcache

        config = self.config()
        pending = self.fits.claim(config)
        experiments = None if pending is None else {name: pending.wait_for(name) for name in self.sides}
        if experiments is None or None in experiments.values():  # not fitted ahead, or abandoned part-way
            with one_blas_thread():
                experiments = experiments_on_one_world(config, changed_settings(self.sides), cache=fitcache)
        with self.lock:
            self._begin(experiments)

    @property
    def finished(self) -> bool:
        """Whether every side has run all its episodes."""
        return (self.experiments is not None and len(self.experiments) == len(self.sides)
                and all(e.finished for e in self.experiments.values()))

    @property
    def displayed_steps_per_second(self) -> float:
        """Steps shown per second over the current animation, on the slower side (NaN before two frames)."""
        rates = []
        for times in self.frame_times.values():
            if len(times) < 2 or times[-1] == times[0]:
                return float("nan")
            rates.append((len(times) - 1) / (times[-1] - times[0]))
        return min(rates)

    # -- stepping from the caller's thread -----------------------------------------------
    def _refuse_while_animating(self, what: str) -> None:
        """Stepping from a cell while the agents walk would step one experiment from two threads (or a closed run)."""
        if self.closed:
            raise RuntimeError(f"{what} after close(): this run is closed; make a new dashboard to run again")
        if self.running:
            raise RuntimeError(f"{what} while the agents are running: press Stop (or call stop()) first")

    def _every_side(self) -> None:
        """Every side's run: built here if none is on show, waited for if one is still being fitted."""
        if self.experiments is None:
            self.build()
        for name in self.sides:
            if name not in self.experiments:
                self._await_side(name, self._token())

    def step_pair(self, draw: bool = True) -> None:
        """One step of each agent that has episodes left (refused while the agents are animated)."""
        self._refuse_while_animating("step_pair")
        self._every_side()
        with one_blas_thread(), self.lock:
            for name, experiment in self.experiments.items():
                if not experiment.finished:
                    with self._step_locks[name]:  # a stopped side's thread ends the step it was in first
                        self.last[name] = experiment.step()
            if draw:
                now = time.perf_counter()
                for name in self.sides:
                    self.frame_times[name].append(now)
                    self.view.show_side(name)
                self.frames += 1
                self.view.show_metrics(throttle=True)

    def run_steps(self, n: int, draw: bool = True) -> None:
        """``n`` paired steps, synchronously (refused while the agents are animated).

        Parameters
        ----------
        n : int
            Paired steps at most (fewer once every side has finished).
        draw : bool, default True
            Show each step, as :meth:`step_pair` does.
        """
        self._refuse_while_animating("run_steps")
        for _ in range(n):
            if self.finished:
                break
            self.step_pair(draw=draw)

    def fast_forward(self, episodes: int = 10) -> None:
        """Whole episodes of every side, synchronously, drawn once at the end (refused while animated)."""
        self._refuse_while_animating("fast_forward")
        self._every_side()
        self._forward_quietly(episodes)
        with self.lock:
            self._show_all()

    def _forward_quietly(self, episodes) -> None:
        with one_blas_thread():
            for name, experiment in self.experiments.items():
                target = min(len(experiment.episodes) + episodes, experiment.config.episodes)
                with self._step_locks[name]:  # a side's thread still ending its step after Stop ends it first
                    while len(experiment.episodes) < target:
                        experiment.run_episode()

    def _show_all(self) -> None:
        for name in self.sides:
            if name in self.experiments:  # a side still being fitted keeps its message
                self.view.show_side(name)
        self.view.show_metrics()

    # -- running in the background ------------------------------------------------------
    def launch(self, episodes: int | None = None, on_end=None) -> threading.Thread | None:
        """Animate (or fast-forward ``episodes`` episodes) in a daemon thread; None if a run is under way.

        Parameters
        ----------
        episodes : int, optional
            Fast-forward this many episodes, episode by episode; None: animate step by step until stopped or finished.
        on_end : callable, optional
            Called without arguments when the thread ends, however it ends.
        """
        with self.lock:
            if self.running or self.closed:
                return None
            self.running = True
            self._cancel.clear()
            self._launches += 1
            generation = self._token()
        thread = threading.Thread(target=self._launched, args=(generation, episodes, on_end),
                                  name="sarsp-edu-live-run", daemon=True)
        thread.start()
        return thread

    def _launched(self, generation, episodes, on_end) -> None:
        try:
            if episodes is None:
                self._play(generation)
            else:
                self._forward(generation, episodes)
        except Exception as exc:  # a background thread has nobody to raise to: the view says it
            with self.lock:
                if self._current(generation):  # an error of a run discarded meanwhile is no longer news
                    self.view.say(f"<span style='color:#b00020'>Stopped by an error: {html.escape(str(exc))}</span>")
        finally:
            with self.lock:
                if self._current(generation):
                    self.running = False
            if on_end is not None:
                on_end()

    def stop(self) -> None:
        """Pause: each side ends the step it is in and steps no more (*Run* continues)."""
        with self.lock:  # a side ending its step after this finds the run stopped, and says nothing more
            self.running = False
            self._cancel.set()
            if self.experiments is not None:
                self.view.say("Stopped. <b>Run</b> continues, <b>New run</b> starts again from the sliders.")

    def close(self) -> None:
        """Stop the agents and the fits under way for good (the sides' threads end after their step)."""
        with self.lock:
            self.closed = True
        self.discard()
        self.fits.close()

    def _token(self) -> tuple:
        """What a thread of the run now carries: the settings' generation and the launch."""
        return self.generation, self._launches

    def _current(self, generation) -> bool:
        """Whether a thread carrying ``generation`` (a :meth:`_token`) still belongs to the run on show."""
        return generation == self._token() and not self.closed

    def _claim(self, generation) -> None:
        """Take the runs fitted (or being fitted) for the current settings; each side joins when fitted."""
        if self.experiments is not None:
            return
        config = self.config()
        if not self.fits.busy_with(config):
            self.fits.request(config)
        with self.lock:
            if self._current(generation):
                self.view.say("Preparing: each agent starts as soon as its models are fitted (progress above its "
                              "grid).")
        pending = self.fits.claim(config)
        with self.lock:  # a slider move (which takes the lock) comes wholly before this, or wholly after
            if not self._current(generation):  # the settings changed meanwhile: those fits are stale
                return
            if pending is None:  # not found (never expected): built here instead
                self.build()
            else:
                self.pending = pending
                self._begin({})

    def _await_side(self, name, generation):
        """A side's run, waited for until its models are fitted (its header says how far); None if discarded since."""
        with self.lock:
            experiments = self.experiments if self._current(generation) else None
        if experiments is None:
            return None
        if name in experiments:
            return experiments[name]
        pending, said = self.pending, None
        while not pending.ready(name) and self._current(generation):
            progress = pending.progress.get(name, "waiting for its fit to begin")
            if progress != said:
                with self.lock:
                    if self._current(generation):
                        self.view.show_waiting(name, progress)
                said = progress
            pending.wait_for(name, timeout=0.25)
        experiment = self._adopt(name, pending.wait_for(name, timeout=0))
        if experiment is None:  # abandoned part-way: only when newer settings were asked for, so stale
            return None
        with self.lock:
            if self._current(generation):
                self.experiments[name] = experiment
                self.view.show_side(name)
                if self.running and len(self.experiments) == len(self.sides):
                    self.view.say("Running: both agents step.")
                elif self.running:
                    self.view.say(f"Running: the {html.escape(self.sides[name][0])} agent steps, the other "
                                  "starts when its models are fitted.")
        return experiment

    def _play(self, generation) -> None:
        """Animate until stopped or finished: each side steps in a daemon thread of its own."""
        self._claim(generation)
        if not self._current(generation):
            return
        with self.lock:
            self.frame_times = {name: [] for name in self.sides}  # this animation's steps, counted afresh
            self.frames = 0
        sides = [DaemonCall(self._run_side, name, generation) for name in self.sides]
        watch = DaemonCall(self._show_waits, generation, sides)
        for side in [*sides, watch]:
            side.result()
        self._say_where_it_stands(generation)

    def _forward(self, generation, episodes) -> None:
        self._claim(generation)
        for name in self.sides:  # fast-forward needs every side
            if not self._current(generation) or self._await_side(name, generation) is None:
                return
        for done in range(episodes):  # one episode at a time: progress shown, Stop obeyed
            if not self.running or self.finished or not self._current(generation):
                break
            with self.lock:
                self.view.say(f"Fast-forwarding: episode {done + 1} of {episodes} ...")
            self._forward_quietly(1)
            with self.lock:
                if not self._current(generation):
                    return
                self._show_all()
        self._say_where_it_stands(generation)

    def _say_where_it_stands(self, generation) -> None:
        with self.lock:
            if not self._current(generation):
                return
            self.view.show_metrics()
            if self.finished:
                self.view.say("Finished every episode. <b>New run</b> starts again from the sliders.")
            elif self.running:
                self.view.say("Paused. <b>Run</b> continues.")

    def _run_side(self, name, generation) -> None:
        experiment = self._await_side(name, generation)
        if experiment is None:
            return
        while self.running and self._current(generation) and not experiment.finished:
            start = time.perf_counter()
            with self._step_locks[name]:  # an earlier launch's thread ends its step first
                if not self._current(generation):
                    return
                self.stepping_since[name] = start
                try:
                    with one_blas_thread():  # per step: the notebook's own cells keep every BLAS thread meanwhile
                        record = experiment.step()
                finally:
                    self.stepping_since[name] = None
            with self.lock:
                if not self._current(generation):  # the settings changed: the preview is on show now
                    return
                self._count_frame(name, record)
            self._cancel.wait(max(0.0, 1.0 / self.steps_per_second - (time.perf_counter() - start)))

    def _count_frame(self, name, record) -> None:
        """A side's step is shown: its picture, its frame time, every tenth common step the rate."""
        self.last[name] = record
        self.view.show_side(name)
        times = self.frame_times[name]
        now = time.perf_counter()
        if times:
            self.longest_wait_seconds[name] = max(self.longest_wait_seconds[name], now - times[-1])
        times.append(now)
        steps = min(len(t) for t in self.frame_times.values())
        if steps > self.frames:
            self.frames = steps
            if steps % 10 == 0 and self.running:  # not over "Stopped" when Stop came mid-step
                self.view.say(f"Running: {steps} steps shown, {self.displayed_steps_per_second:.1f} steps per second.")
        self.view.show_metrics(throttle=True)

    def _show_waits(self, generation, sides) -> None:
        """Every tenth of a second: a side whose step has taken over WAIT_SHOWN_AFTER says why it waits."""
        while self._current(generation) and not all(side.done() for side in sides):
            now = time.perf_counter()
            for name, since in list(self.stepping_since.items()):
                if since is not None and now - since > WAIT_SHOWN_AFTER and name in (self.experiments or {}):
                    why = "retraining its cost model" if self.retraining[name] else "deciding"
                    with self.lock:
                        if self._current(generation):
                            self.view.show_waiting(name, f"{why} ({now - since:.1f} s)")
            time.sleep(0.1)
