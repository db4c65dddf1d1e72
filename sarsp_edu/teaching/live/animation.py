"""The live dashboard's animation: each side steps in a worker thread of its own, drawing under one lock.

:class:`Animation` is the half of :class:`~sarsp_edu.teaching.live.AgentDashboard`
that runs the agents: *Run*, *Stop*, *Fast-forward*, autoplay, and the
"retraining its cost model" message of a side that waits.
"""

from __future__ import annotations

import html
import threading
import time

from ..._internal.threads import one_blas_thread

__all__ = ["WAIT_SHOWN_AFTER", "Animation"]

#: a side whose step has taken this long shows why it waits (a retrain of its cost model, usually)
WAIT_SHOWN_AFTER = 0.25


class Animation:
    """Running the agents of an :class:`~sarsp_edu.teaching.live.AgentDashboard` (a mixin)."""

    # -- stepping -----------------------------------------------------------
    def step_pair(self, draw: bool = True) -> None:
        """One step of each agent that has episodes left."""
        self._every_side()
        for model, experiment in self.experiments.items():
            if not experiment.finished:
                self._last[model] = experiment.step()
        if draw:
            self._draw_world()
            self._draw_metrics_if_new_episode(throttle=True)
            self.frames += 1
            now = time.perf_counter()
            for times in self._frame_times.values():
                times.append(now)

    def _every_side(self) -> None:
        """Both sides' runs, prepared here if no run is on show, waited for if one is still being fitted."""
        if self.experiments is None:
            self.prepare()
        for name in self.sides:
            if name not in self.experiments:
                self._await_side(name, self._generation)

    def _refuse_while_animating(self, what: str) -> None:
        """Stepping from a cell while the agents walk would step one experiment from two threads."""
        if self._running:
            raise RuntimeError(f"{what} while the agents are running: press Stop (or call stop()) first")

    def run_steps(self, n: int, draw: bool = True) -> None:
        """``n`` paired steps, synchronously (refused while the agents are animated)."""
        self._refuse_while_animating("run_steps")
        with one_blas_thread():
            for _ in range(n):
                if self.finished:
                    break
                self.step_pair(draw=draw)

    def fast_forward(self, episodes: int = 10) -> None:
        """Run whole episodes of both agents without drawing each step, synchronously (refused while the
        agents are animated: the *Fast-forward* button runs alongside the kernel instead)."""
        self._refuse_while_animating("fast_forward")
        self._every_side()
        self._forward_quietly(episodes)
        self._draw_world()
        self._draw_metrics_if_new_episode()

    @property
    def running(self) -> bool:
        """Whether the agents are animated now (after *Run* or autoplay, until *Stop* or the last episode)."""
        return self._running

    @property
    def displayed_steps_per_second(self) -> float:
        """Steps drawn per second over the current animation, on the slower side (NaN before two frames)."""
        rates = []
        for times in self._frame_times.values():
            if len(times) < 2 or times[-1] == times[0]:
                return float("nan")
            rates.append((len(times) - 1) / (times[-1] - times[0]))
        return min(rates)

    # -- running without blocking the kernel (the buttons, autoplay) ---------------
    def start(self, episodes: int | None = None):
        """Start animating (or fast-forward ``episodes`` episodes) without blocking the kernel.

        Returns the asyncio task that runs it (None if a run is already under
        way, which the status line then says).
        """
        import asyncio

        if self._running:
            self.status.value = ("Already running: press <b>Stop</b> first, then "
                                 + ("<b>Fast-forward</b>." if episodes is not None else "<b>Run</b>."))
            return None
        self._running = True
        self._task = asyncio.ensure_future(self._loop(episodes))
        return self._task

    def play_in_background(self) -> threading.Thread | None:
        """Start animating in a thread of its own: the agents move even while the notebook runs other cells.

        *Run* waits for the kernel, which handles a click only between cells;
        this does not (``autoplay=True`` calls it when the dashboard is first
        shown).  Returns the thread, or None if a run is already under way.
        """
        if self._running:
            return None
        self._running = True
        generation = self._generation
        thread = threading.Thread(target=self._play_reporting, args=(generation,), name="sarsp-edu-play",
                                  daemon=True)
        thread.start()
        return thread

    def close(self) -> None:
        """Stop the agents and the fits under way, and close the dashboard's widgets (it cannot be shown again)."""
        if hasattr(self, "_preparer"):  # ipywidgets closes a widget when it is collected, even one half-built
            with self._draw_lock:
                self._discard_run()
            self._preparer.close()
        super().close()

    def stop(self) -> None:
        with self._draw_lock:  # a side ending its step after this finds the run stopped, and says nothing more
            self._running = False
            if self.experiments is not None:
                self.status.value = "Stopped. <b>Run</b> continues, <b>New run</b> starts again from the sliders."

    def reset(self) -> None:
        with self._draw_lock:
            self._discard_run()
            self.preview()
        self._prepare_ahead()
        self.status.value = "Press <b>Run</b> to start both agents."

    async def _loop(self, episodes):
        import asyncio

        loop = asyncio.get_running_loop()
        generation = self._generation
        try:
            if episodes is None:
                await loop.run_in_executor(None, self._play, generation)
                return
            await loop.run_in_executor(None, self._claim_preparation, generation)
            if generation != self._generation:
                return
            for name in self.sides:  # fast-forward needs every side
                await loop.run_in_executor(None, self._await_side, name, generation)
            if generation != self._generation:
                return
            for done in range(episodes):  # one episode at a time: progress shown, Stop obeyed
                if not self._running or self.finished:
                    break
                self.status.value = f"Fast-forwarding: episode {done + 1} of {episodes} ..."
                await loop.run_in_executor(None, self._forward_quietly, 1)
                if generation != self._generation:
                    return
                with self._draw_lock:
                    self._draw_world()
                    self._draw_metrics_if_new_episode()
            self._say_where_it_stands(generation)
        except Exception as exc:  # the dashboard reports, the kernel lives on
            self._say_error(exc)
        finally:
            self._running = False

    def _play_reporting(self, generation) -> None:
        try:
            self._play(generation)
        except Exception as exc:  # a background thread has nobody to raise to
            self._say_error(exc)
        finally:
            self._running = False

    def _say_error(self, exc) -> None:
        self.status.value = f"<span style='color:#b00020'>Stopped by an error: {html.escape(str(exc))}</span>"

    def _say_where_it_stands(self, generation) -> None:
        if generation != self._generation:
            return
        with self._draw_lock:
            self._draw_metrics_if_new_episode()
        if self.finished:
            self.status.value = "Finished every episode. <b>New run</b> starts again from the sliders."
        elif self._running:
            self.status.value = "Paused. <b>Run</b> continues."

    def _claim_preparation(self, generation) -> None:
        """Take the runs prepared (or being prepared) for the sliders' settings; each side joins when fitted."""
        if self.experiments is not None:
            return
        config = self.config()
        if not self._preparer.busy_with(config):
            self._preparer.request(config)
        self.status.value = "Preparing: each agent starts as soon as its models are fitted (progress above its grid)."
        preparation = self._preparer.claim(config)
        with self._draw_lock:  # a slider move (which takes the lock) comes wholly before this, or wholly after
            if generation != self._generation:  # the sliders moved meanwhile: that preparation is stale
                return
            if preparation is None:  # not found (never expected): prepared here instead
                self.prepare()
            else:
                self._preparation = preparation
                self._begin({})

    def _play(self, generation) -> None:
        """Animate until stopped or finished, blocking: each side steps in a worker thread of its own.

        Run from a worker thread (by *Run* through the asyncio loop, or by
        ``play_in_background``); the drawing is serialised by a lock.
        """
        self._claim_preparation(generation)
        if generation != self._generation:
            return
        self._frame_times = {name: [] for name in self.sides}  # this animation's steps, counted afresh
        self.frames = 0
        with one_blas_thread():  # entered once for the whole animation, not per step
            # daemon threads: a script or kernel that ends while the agents walk is not kept alive by them
            sides = [_Side(self._run_side, name, generation) for name in self.sides]
            watch = _Side(self._show_waits, generation, sides)
            for side in [*sides, watch]:
                side.result()
        self._say_where_it_stands(generation)

    def _await_side(self, name, generation):
        """A side's run, waiting for its models to be fitted (in the background) if they are not yet; meanwhile
        its header says what the fit is doing."""
        if name in self.experiments:
            return self.experiments[name]
        preparation = self._preparation
        said = None
        while not preparation.ready(name):
            progress = preparation.progress.get(name, "waiting for its fit to begin")
            if progress != said and generation == self._generation:
                self._say_waiting(name, progress)
                said = progress
            preparation.wait_for(name, timeout=0.25)
        experiment = self._with_parts(name, preparation.wait_for(name))
        if experiment is None:  # abandoned part-way: only when newer settings were asked for, so stale
            return None
        with self._draw_lock:
            if generation == self._generation:
                self.experiments[name] = experiment
                self._draw_side(name)
                if self._running and len(self.experiments) == len(self.sides):
                    self.status.value = "Running: both agents step."
                elif self._running:
                    self.status.value = (f"Running: the {html.escape(self.sides[name][0])} agent steps, the other "
                                         "starts when its models are fitted.")
        return experiment

    def _run_side(self, name, generation) -> None:
        experiment = self._await_side(name, generation)
        if experiment is None:
            return
        while self._running and generation == self._generation and not experiment.finished:
            start = time.perf_counter()
            self._stepping_since[name] = start
            try:
                record = experiment.step()
            finally:
                self._stepping_since[name] = None
            with self._draw_lock:
                if generation != self._generation:  # a slider moved: the preview is on show now
                    return
                self._last[name] = record
                self._draw_side(name)
                times = self._frame_times[name]
                now = time.perf_counter()
                if times:
                    self.longest_wait_seconds[name] = max(self.longest_wait_seconds[name], now - times[-1])
                times.append(now)
                steps = min(len(t) for t in self._frame_times.values())
                if steps > self.frames:
                    self.frames = steps
                    if steps % 10 == 0 and self._running:  # not over "Stopped" when Stop came mid-step
                        self.status.value = (f"Running: {steps} steps shown, "
                                             f"{self.displayed_steps_per_second:.1f} steps per second.")
                self._draw_metrics_if_new_episode(throttle=True)
            time.sleep(max(0.0, 1.0 / self.speed.value - (time.perf_counter() - start)))

    def _show_waits(self, generation, sides) -> None:
        """Every tenth of a second: a side whose step has taken over WAIT_SHOWN_AFTER says why it waits."""
        while generation == self._generation and not all(side.done() for side in sides):
            now = time.perf_counter()
            for name, since in list(self._stepping_since.items()):
                if since is not None and now - since > WAIT_SHOWN_AFTER and name in self.experiments:
                    agent = self.experiments[name].agent
                    why = "retraining its cost model" if agent.retraining else "deciding"
                    self._say_waiting(name, f"{why} ({now - since:.1f} s)")
            time.sleep(0.1)

    def _say_waiting(self, name, why: str) -> None:
        """The side's header line says why it waits (one line, cut short rather than wrapped: nothing moves)."""
        self.headers[name].value = self._header(name, f"<span style='color:#a04c00'>{html.escape(why)}</span>")

    def _forward_quietly(self, episodes):  # every side is there: fast-forward waits for them
        with one_blas_thread():
            for experiment in self.experiments.values():
                target = min(len(experiment.episodes) + episodes, experiment.config.episodes)
                while len(experiment.episodes) < target:
                    experiment.run_episode()


class _Side(threading.Thread):
    """A daemon thread running ``target(*args)``; ``result()`` waits for it and raises what it raised."""

    def __init__(self, target, *args):
        super().__init__(name="sarsp-edu-side", daemon=True)
        self._call, self._args, self._error = target, args, None
        self.start()

    def run(self) -> None:
        try:
            self._call(*self._args)
        except BaseException as exc:  # handed to whoever waits, as a future would
            self._error = exc

    def done(self) -> bool:
        return not self.is_alive()

    def result(self) -> None:
        self.join()
        if self._error is not None:
            raise self._error
