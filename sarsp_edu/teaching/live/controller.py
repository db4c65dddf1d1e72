"""The live run without its widgets: one thread owns it, every other thread sends it commands.

:class:`LiveRun` holds what the live dashboard runs, and runs it.  Who owns what:

- **The run's thread** (``sarsp-edu-live``, started with the run, ended by :meth:`LiveRun.close`) owns both
  sides' experiments, what is on show (``experiments``, ``last``, the frame counts) and the view: it alone
  steps an experiment and it alone calls the view.  It takes commands from one queue, between two steps, so
  *Stop* ends the step under way and no command ever meets a half-taken step.
- **Every other thread** (a button's or a slider's handler, a notebook cell, a test) only puts commands on that
  queue (:meth:`LiveRun.submit`); the synchronous ones (``step_pair``, ``run_steps``, ``fast_forward``,
  ``build``, :meth:`LiveRun.call`) wait for the run's thread to have done them and raise what it raised.
  Such a thread may read ``experiments``, ``running``, ``frames`` and ``finished`` as a snapshot of a moment
  ago, never to decide to step.  ``steps_per_second`` is a float any thread may replace.
- **The fits** are :class:`~sarsp_edu.teaching.live.background.FitQueue`'s (its thread and its processes):
  it posts a message on the run's queue whenever a side's fit advances or ends, and the run's thread takes
  the fitted sides from it.

The view is told what to show through five methods, always from the run's thread::

    view.show_side(name)                # a side's run changed: its grid, its numbers, its decision
    view.show_metrics(throttle)         # an episode may have ended: the metric curves
    view.show_waiting(name, why)        # a side waits: for its fit, a retrain of its cost model ...
    view.say(html)                      # the status line
    view.preview()                      # no run: the world the settings imply

A view's own work that touches what the run shows (a redraw at another size, a slider's new world) is handed
to the run's thread with :meth:`LiveRun.call`: the one hand-off between the two.
"""

from __future__ import annotations

import html
import time
from concurrent.futures import Future

from ..._internal.owner import Closed, Owner
from ..._internal.threads import one_blas_thread
from .background import FitQueue
from .quiet import QuietView

__all__ = ["LiveRun", "QuietView"]

#: how often (s) the run's thread looks at a fit's progress while a synchronous command waits for it
_PROGRESS_EVERY = 0.25


class LiveRun(Owner):
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
        Animation speed (paired steps per second); any thread may change it at any time.
    page : PagePresence, optional
        The page that shows the run (:mod:`~sarsp_edu.teaching.live.presence`): a launched run stops when it has
        gone.  None: no page is listened to.
    """

    def __init__(self, sides: dict, config, *, parts=None, offline=None, view=None, steps_per_second=30.0,
                 page=None):
        self.sides = sides
        self.page = page
        self.config = config
        self.parts = dict(parts or {})
        self.view = QuietView() if view is None else view
        self.steps_per_second = float(steps_per_second)
        self.fits = FitQueue(sides, offline=offline, on_news=self.post_news)
        # -- the run's thread's own (see the module's docstring) --
        self.experiments = None  # side name -> its Experiment on show (those fitted so far); None: no run
        self.running = False  # animating (Run) or fast-forwarding (the button), until Stop, the end or a discard
        self.closed = False
        self._pending = None  # the fits this run waits for (FitQueue.claim)
        self._forward_left = None  # episodes the Fast-forward button has left to run; None: animating
        self._launch = None  # (future, on_end) of the animation or fast-forward under way
        self._next_frame = 0.0
        #: name -> True while that side's agent refits its cost model after a correction (its event says so)
        self.retraining = dict.fromkeys(sides, False)
        self._begin(None)
        self._start_owner("sarsp-edu-live")

    # -- commands: any thread (submit, call and settle are Owner's) -----------------------------
    def request_fits(self) -> None:
        """Start fitting the current settings' runs in the background (a newer request replaces an older one)."""
        self.fits.request(self.config())

    def build(self) -> None:
        """The runs of the current settings, now: those fitted ahead, or waited for until they are fitted."""
        self.call(self._build)

    def discard(self) -> Future:
        """Stop and forget the runs (the settings changed); the fits still under way go on for the new ones."""
        return self.submit(self._discard)

    def step_pair(self, draw: bool = True) -> None:
        """One step of each agent that has episodes left (refused while the agents are animated)."""
        self.call(self._synchronous, "step_pair", self._step_pair, draw)

    def run_steps(self, n: int, draw: bool = True) -> None:
        """``n`` paired steps, synchronously (refused while the agents are animated).

        Parameters
        ----------
        n : int
            Paired steps at most (fewer once every side has finished).
        draw : bool, default True
            Show each step, as :meth:`step_pair` does.
        """
        self.call(self._synchronous, "run_steps", self._run_steps, n, draw)

    def fast_forward(self, episodes: int = 10) -> None:
        """Whole episodes of every side, synchronously, drawn once at the end (refused while animated).

        Parameters
        ----------
        episodes : int, default 10
            Episodes of each side at most (fewer where its run ends first).
        """
        self.call(self._synchronous, "fast_forward", self._fast_forward, episodes)

    def launch(self, episodes: int | None = None, on_end=None) -> Future | None:
        """Animate (or fast-forward ``episodes`` episodes, with progress) in the run's thread.

        Returns once the run's thread has begun it (at most a step's wait): a future that holds True once the
        run ends (finished, stopped or discarded); None if a run was under way already (the status line then
        says so) or the run is closed.

        Parameters
        ----------
        episodes : int, optional
            Fast-forward this many episodes, episode by episode; None: animate step by step until stopped or
            finished.
        on_end : callable, optional
            Called without arguments (in the run's thread) when the run ends, however it ends.
        """
        if self.closed:
            return None
        future = Future()
        try:
            launched = self.call(self._start, episodes, future, on_end)
        except Closed:
            return None
        return future if launched else None

    def stop(self) -> Future:
        """Pause: the step under way ends and no other follows (*Run* continues)."""
        return self.submit(self._stop)

    def close(self) -> None:
        """Stop the agents and the fits for good: the run's thread, the fits' thread and their processes end."""
        if self.closed:
            return
        self.fits.close()  # first: a synchronous command waiting for a fit is released
        self.submit(self._close)
        self._join_owner()

    # -- what other threads may read -----------------------------------------------------------------
    @property
    def finished(self) -> bool:
        """Whether every side has run all its episodes."""
        experiments = self.experiments
        return (experiments is not None and len(experiments) == len(self.sides)
                and all(e.finished for e in experiments.values()))

    @property
    def displayed_steps_per_second(self) -> float:
        """Steps shown per second over the current animation, on the slower side (NaN before two frames)."""
        rates = []
        for times in list(self.frame_times.values()):
            if len(times) < 2 or times[-1] == times[0]:
                return float("nan")
            rates.append((len(times) - 1) / (times[-1] - times[0]))
        return min(rates)

    # -- the run's thread ----------------------------------------------------------------------------
    def _news(self) -> None:
        self._take_fitted()

    def _due(self) -> float | None:
        """Seconds until the run's thread has work of its own (None: none until a command or the fits' news)."""
        if not self.running:
            return None
        listening = self.page is not None and self.page.listening  # its page looked at every second
        if self._forward_left is not None:
            due = 0 if self._all_sides() else None  # fast-forward needs every side: it waits for their fits
        else:
            due = max(0.0, self._next_frame - time.perf_counter()) if self.experiments else None
        return min(due, 1.0) if listening and due is not None else (1.0 if listening else due)

    def _advance(self) -> None:
        """One unit of the launched run: a paired frame of the animation, or one step of the fast-forward (where
        it is due, and its page is still there)."""
        if not self.running:
            return
        if self.page is not None:
            self.page.arm()
            if self.page.gone():
                self.view.say(f"Stopped: this page has not been heard from in {self.page.silence:.0f} s (closed or "
                              "reloaded?). <b>Run</b> continues.")
                return self._settle_launch()
        try:
            if self._forward_left is None:
                if self.experiments and time.perf_counter() >= self._next_frame:
                    self._frame()
            elif self._all_sides():
                self._forward_step()
        except Exception as exc:  # nobody to raise to: the view says it, and the run ends
            self.view.say(f"<span style='color:#b00020'>Stopped by an error: {html.escape(str(exc))}</span>")
            self._end_launch()

    closed_message = "this run is closed; make a new dashboard to run again"

    def _begin(self, experiments) -> None:
        """Show these runs (all sides, or those fitted so far; None: no run) from their start."""
        self.experiments = experiments
        self.last = dict.fromkeys(self.sides)
        self.frames = 0
        self.frame_times = {name: [] for name in self.sides}
        self.longest_wait_seconds = dict.fromkeys(self.sides, 0.0)
        self._said_waiting = {}

    def _adopt(self, name, experiment) -> None:
        """A side joins the run: its agent given the side's parts, its retrains said while they last."""
        agent = experiment.agent
        if name in self.parts:
            agent.parts = self.parts[name]

        def retraining(event: str) -> None:  # the agent's event, in this thread: it steps here
            self.retraining[name] = event == "begin"
            if event == "begin":
                self.view.show_waiting(name, "retraining its cost model")

        agent.retrain_listeners.append(retraining)
        self.experiments[name] = experiment
        self.view.show_side(name)

    def _all_sides(self) -> bool:
        return self.experiments is not None and len(self.experiments) == len(self.sides)

    def _claim(self) -> None:
        """The runs of the current settings, fitted ahead or being fitted: each side joins when fitted."""
        if self.experiments is not None:
            return
        config = self.config()
        for _ in range(2):  # a second time where a newer request (another thread's) took the first one's place
            if not self.fits.busy_with(config):
                self.fits.request(config)
            self._pending = self.fits.claim(config)
            if self._pending is not None:
                break
        else:
            raise RuntimeError("the fits of these settings were taken by another run; move a slider or press "
                               "New run")
        self._begin({})
        self._take_fitted()

    def _take_fitted(self) -> None:
        """Every side fitted since last time joins; those still fitting say how far they are."""
        pending = self._pending
        if pending is None or self.experiments is None:
            return
        for name in self.sides:
            if name in self.experiments:
                continue
            if pending.ready(name):
                experiment = pending.wait_for(name, timeout=0)  # raises what its fit raised
                if experiment is None:  # abandoned (the fits were closed): never joins
                    continue
                self._adopt(name, experiment)
                if self.running and self._forward_left is None:
                    self.view.say("Running: both agents step." if self._all_sides() else
                                  f"Running: the {html.escape(self.sides[name][0])} agent steps, the other "
                                  "starts when its models are fitted.")
            else:
                progress = pending.progress.get(name, "waiting for its fit to begin")
                if self._said_waiting.get(name) != progress:
                    self._said_waiting[name] = progress
                    self.view.show_waiting(name, progress)

    def _build(self) -> None:
        """Wait (saying how far each side's fit is) until every side of the current settings is fitted."""
        self._claim()
        while not self._all_sides():
            name = next(name for name in self.sides if name not in self.experiments)
            self._pending.wait_for(name, timeout=_PROGRESS_EVERY)  # raises what its fit raised
            self._take_fitted()
            if self._pending.ready(name) and name not in self.experiments:
                raise RuntimeError("the fits of this run were abandoned (the run was closed, or other settings "
                                   "were asked for) before every side was fitted")

    def _synchronous(self, what, function, *args) -> None:
        """A cell's command: refused while the agents are launched, else done on every side's run."""
        if self.running:
            raise RuntimeError(f"{what} while the agents are running: press Stop (or call stop()) first")
        self._build()
        with one_blas_thread():
            function(*args)

    def _step_pair(self, draw: bool) -> None:
        for name, experiment in self.experiments.items():
            if not experiment.finished:
                self.last[name] = experiment.step()
        if draw:
            now = time.perf_counter()
            for name in self.sides:
                self.frame_times[name].append(now)
                self.view.show_side(name)
            self.frames += 1
            self.view.show_metrics(throttle=True)

    def _run_steps(self, n, draw) -> None:
        for _ in range(n):
            if self.finished:
                break
            self._step_pair(draw)

    def _fast_forward(self, episodes) -> None:
        for name, experiment in self.experiments.items():
            target = min(len(experiment.episodes) + episodes, experiment.config.episodes)
            while len(experiment.episodes) < target:
                self.last[name] = experiment.step()
        self._show_all()

    def _show_all(self) -> None:
        for name in self.sides:
            if name in (self.experiments or {}):  # a side still being fitted keeps its message
                self.view.show_side(name)
        self.view.show_metrics()

    def _start(self, episodes, future, on_end) -> bool:
        if self.closed:
            return False
        if self.running:
            self.view.say("Already running: press <b>Stop</b> first, then "
                          + ("<b>Fast-forward</b>." if episodes is not None else "<b>Run</b>."))
            return False
        if self.experiments is None:
            self.view.say("Preparing: each agent starts as soon as its models are fitted (progress above its grid).")
        self._claim()
        self.running, self._forward_left, self._launch = True, episodes, (future, on_end)
        self._forward_from, self._forward_shown = None, 0
        self.frame_times = {name: [] for name in self.sides}  # this animation's steps, counted afresh
        self.frames = 0
        self._next_frame = time.perf_counter()
        if self.page is not None:
            self.page.watch()
        if self.finished:
            self._end_launch()
        return True

    def _frame(self) -> None:
        """A paired frame of the animation: each side fitted so far takes a step, and is drawn."""
        start = time.perf_counter()
        with one_blas_thread():  # per step: the notebook's own cells keep every BLAS thread meanwhile
            for name, experiment in list(self.experiments.items()):
                if not experiment.finished:
                    self._count_frame(name, experiment.step())
        self._next_frame = start + 1.0 / self.steps_per_second
        self.view.show_metrics(throttle=True)
        if self.finished:
            self._end_launch()

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
            if steps % 10 == 0:
                self.view.say(f"Running: {steps} steps shown, {self.displayed_steps_per_second:.1f} steps per second.")

    def _forward_step(self) -> None:
        """One step of the fast-forward (commands are taken between its steps); each episode's end drawn."""
        wanted = self._forward_left
        if self._forward_from is None:  # the fast-forward's start and end, once
            self._forward_from = {name: len(e.episodes) for name, e in self.experiments.items()}
            self._forward_target = {name: min(self._forward_from[name] + wanted, e.config.episodes)
                                    for name, e in self.experiments.items()}
            self.view.say(f"Fast-forwarding: episode 1 of {wanted} ...")
        target = self._forward_target
        behind = [name for name, e in self.experiments.items() if len(e.episodes) < target[name]]
        with one_blas_thread():
            for name in behind:
                self.last[name] = self.experiments[name].step()
        done = min(len(e.episodes) - self._forward_from[name] if len(e.episodes) < target[name] else wanted
                   for name, e in self.experiments.items())
        if done > self._forward_shown:  # an episode of every side has ended: drawn, the progress said
            self._forward_shown = done
            self._show_all()
            if done < wanted:
                self.view.say(f"Fast-forwarding: episode {done + 1} of {wanted} ...")
        if done >= wanted:
            self._end_launch()

    def _end_launch(self) -> None:
        """The launched run has ended (finished, or its fast-forward done): said, and its future settled."""
        self.view.show_metrics()
        if self.finished:
            self.view.say("Finished every episode. <b>New run</b> starts again from the sliders.")
        else:
            self.view.say("Paused. <b>Run</b> continues.")
        self._settle_launch()

    def _settle_launch(self) -> None:
        self.running, self._forward_left = False, None
        if self._launch is not None:
            (future, on_end), self._launch = self._launch, None
            if on_end is not None:
                on_end()
            future.done() or future.set_result(True)

    def _stop(self) -> None:
        if self.experiments is not None:  # said before the launch's end is told: its waiter reads it then
            self.view.say("Stopped. <b>Run</b> continues, <b>New run</b> starts again from the sliders.")
        self._settle_launch()

    def _discard(self) -> None:
        self._settle_launch()
        self._pending = None
        self._begin(None)

    def _close(self) -> None:
        self._discard()
        self.closed = True
        self._end_owner()
