"""The live dashboard's runs fitted ahead, in the background, while the lecturer talks.

A slider move requests its settings' runs; the latest request only is kept
(dragging a slider queues no work), and each side is handed over as soon as
its models are fitted, loaded from :mod:`sarsp_edu.teaching.live.fitcache` where these
settings were fitted before.
"""

from __future__ import annotations

import contextlib
import os
import threading
import time

from ..._internal.threads import one_blas_thread
from ...config import NU, DataSettings

__all__ = ["changed_settings", "prefit", "slider_config"]


def slider_config(base, *, nu, magnitude, proportion, n_switch_states, seed, episodes):
    """The settings of a live dashboard whose sliders show these values, on ``base``'s other settings.

    A slider's float carries its steps' rounding (40 + 1.0 moves to
    41.00000000000001): it is rounded away, so that the settings, and the fit
    cache's key, are those the values name.

    Parameters
    ----------
    base : ExperimentConfig
        Gives every setting the sliders do not.
    nu : float
        The TP's degrees of freedom.
    magnitude, proportion : float
        The outliers' ``m`` and ``p`` (``outlier_magnitude``, ``outlier_proportion``).
    n_switch_states : int
        nss, the unsafe states the shift moves.
    seed : int
    episodes : int
        Episodes of each run.

    Returns
    -------
    ExperimentConfig
    """
    def rounded(value):
        return round(value, 10) if isinstance(value, float) else value

    return base.replace(nu=float(rounded(nu)), outlier_magnitude=float(rounded(magnitude)),
                        outlier_proportion=float(rounded(proportion)), n_switch_states=int(n_switch_states),
                        seed=int(seed), episodes=int(episodes))


def prefit(n_switch_states=(2, 10), *, nu=NU, magnitude=DataSettings.outlier_magnitude,
           proportion=DataSettings.outlier_proportion, seed=0, episodes=30, config=None, sides=None,
           report=print) -> list:
    """Fit and keep the live dashboard's runs for these slider values, so that it starts at once in class.

    Tutorial 4's dashboard (``agent_dashboard(episodes=30)``, its sliders at
    nu, m, p, seed as given) then loads each side's fit from
    :mod:`sarsp_edu.teaching.live.fitcache` instead of fitting it: for each value of
    ``n_switch_states`` (the lecture plan moves nss from 2 to 10), both sides
    are fitted at once, as the dashboard fits them.  A fit the cache holds
    already is left as it is.  The cache is per machine, per package version
    and per Python environment: run this where the lecture will run.

    Parameters
    ----------
    n_switch_states : int or iterable of int, default (2, 10)
        The nss slider's values to fit.
    nu, magnitude, proportion, seed, episodes
        The other sliders' values (as :func:`slider_config` takes them); defaults: the dashboard's.
    config : ExperimentConfig, optional
        The settings the sliders do not give (None: ``ExperimentConfig()``, the dashboard's default).
    sides : dict, optional
        Name -> ``(label, changed settings)`` of the dashboard's sides (None: ``TP_AND_GP``).
    report : callable, default print
        Called with a line of text as each side is fitted or found.

    Returns
    -------
    list of tuple
        ``[(n_switch_states, side, "fitted in S s" or "stored before"), ...]``.

    Raises
    ------
    RuntimeError
        If the fit cache is off (nowhere to keep a fit).
    """
    from ...config import ExperimentConfig
    from . import fitcache

    if fitcache.cache_directory() is None:
        raise RuntimeError(f"the cache of fits is off ({fitcache.CACHE_VARIABLE}="
                           f"{os.environ.get(fitcache.CACHE_VARIABLE)!r}): there is nowhere to keep a fit")
    values = [n_switch_states] if isinstance(n_switch_states, int) else list(n_switch_states)
    base = ExperimentConfig() if config is None else config
    from .pick import TP_AND_GP

    queue = FitQueue(dict(TP_AND_GP if sides is None else sides))
    done = []
    try:
        for nss in values:
            settings = slider_config(base, nu=nu, magnitude=magnitude, proportion=proportion, n_switch_states=nss,
                                     seed=seed, episodes=episodes)
            queue.request(settings)
            fits = queue.claim(settings)
            for name in queue.sides:
                experiment = fits.wait_for(name)
                what = ("stored before" if experiment.loaded_from_cache
                        else f"fitted in {experiment.timings['offline_fit_seconds']:.1f} s")
                done.append((nss, name, what))
                report(f"nss = {nss}, {queue.sides[name][0]}: {what}")
    finally:
        queue.close()  # its processes end with it
    return done


def changed_settings(sides: dict) -> dict:
    """Name -> the settings that side changes: the dashboard's sides as ``experiments_on_one_world`` takes them."""
    return {name: changes for name, (_, changes) in sides.items()}


class _Abandoned(Exception):
    """Raised through a fit in the queue's thread that newer settings (or ``close``) made unwanted."""


class PendingFits:
    """The runs of one setting as they are fitted: each side appears as soon as its models are."""

    def __init__(self, condition):
        self._condition = condition
        self.experiments = {}
        self.progress = {}  # name -> what the side's fit is doing, in words
        self.error = None
        self.done = False

    def wait_for(self, name, timeout: float | None = None):
        """The side's Experiment, once fitted (raises what its fit raised; None if it was abandoned,
        or if ``timeout`` seconds passed first: ``ready`` then tells the two apart).

        Parameters
        ----------
        name : str
            The side, as named in the queue's ``sides``.
        timeout : float, optional
            Seconds to wait at most; None: until the side is fitted, has failed or is abandoned.
        """
        with self._condition:
            self._condition.wait_for(lambda: self.ready(name), timeout)
            if self.error is not None:
                raise self.error
            return self.experiments.get(name)

    def ready(self, name) -> bool:
        """Whether waiting for ``name`` is over (fitted, failed or abandoned)."""
        return name in self.experiments or self.error is not None or self.done


def _describe(worker, config) -> str:
    """A fit's progress in words: its phase, its steps, the time it has taken and, once it can tell, how long
    it has left."""
    if worker.started_at is None:
        return "starting its fit (imports, data)"
    done, total = worker.steps
    elapsed = time.perf_counter() - worker.started_at
    if not total:
        return f"fitting models: step {done}, {elapsed:.0f} s so far"
    model = "cost" if done <= total // 2 else "reward"
    left = f", {elapsed / done * (total - done):.0f} s left" if done >= 5 else ""
    return f"fitting {model} model: step {done} of {total}, {elapsed:.0f} s{left}"


class FitQueue:
    """Fits the runs of the latest requested settings: one thread, and a process per side for its fit.

    A slider move requests new settings.  A side fitted before (the
    :mod:`sarsp_edu.teaching.live.fitcache`) is loaded at once; the others are fitted at
    the same time, each in a process of its own
    (:class:`~sarsp_edu.teaching.live.fitting.FitWorker`), and handed over as each
    ends.  A newer request terminates the fits of the settings it replaces,
    so that the wanted fit never waits behind one nobody waits for; only the
    latest request is kept.  ``claim`` hands the pending fits, finished or
    under way, to the dashboard once.  Where a process cannot be started,
    the sides are fitted in the thread, one after the other, each abandoned
    at its next optimiser step when newer settings are requested.
    """

    def __init__(self, sides: dict, offline: dict | None = None, on_news=None):
        self.sides = sides
        self._offline = {} if offline is None else offline  # seed -> offline world and data (shared with the view)
        self._condition = threading.Condition()
        self._on_news = on_news  # told (no arguments, under the condition) whenever a fit advances or ends
        self._idle = []  # this queue's workers that wait for a fit (their imports done); ended by close()
        self._closed = False
        self._wanted = None
        self._pending = False
        self._pending_fits = {}  # key -> PendingFits (the latest only)
        self._thread = None
        self._handover = None  # a folder for fits handed over from the workers where the cache is off

    @staticmethod
    def key(config):
        """The key the queue keeps ``config``'s fits under: its ``repr`` (equal settings, equal key)."""
        return repr(config)

    def close(self) -> None:
        """Abandon what is under way (its fitting processes stopped at once), end the queue's thread and every
        process it started, and keep nothing; starts no process."""
        with self._condition:
            self._closed = True
            self._wanted, self._pending = None, True  # the thread sees newer wishes: it stops its fits
            self._pending_fits = {}
            self._tell()
            thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join()
        with self._condition:
            idle, self._idle = self._idle, []
        for worker in idle:
            worker.terminate()
        if self._handover is not None:
            self._handover.cleanup()
            self._handover = None

    def request(self, config) -> None:
        """Fit the runs of ``config`` (again); fits under way of other settings are abandoned.

        Parameters
        ----------
        config : ExperimentConfig
            The settings whose runs (one per side) are fitted.
        """
        with self._condition:
            if self._closed:
                raise RuntimeError("this queue of fits is closed")
            self._wanted, self._pending = config, True
            if self._thread is None:
                self._thread = threading.Thread(target=self._work, name="sarsp-edu-fit-queue", daemon=True)
                self._thread.start()
            self._condition.notify_all()

    def busy_with(self, config) -> bool:
        """Whether the fits of ``config`` are under way or wait to begin."""
        with self._condition:
            key = self.key(config)
            fits = self._pending_fits.get(key)
            return (fits is not None and not fits.done) or (
                self._pending and self.key(self._wanted) == key)

    def claim(self, config):
        """The fits of ``config`` (finished or under way), handed out once; None if it was not requested."""
        with self._condition:
            key = self.key(config)
            while self._pending and self.key(self._wanted) == key:  # requested, not begun: wait for it to begin
                self._condition.wait()
            return self._pending_fits.pop(key, None)

    def _work(self) -> None:
        while True:
            with self._condition:
                if not self._pending:
                    self._thread = None
                    self._condition.notify_all()
                    return
                config, self._pending = self._wanted, False
                if config is None:  # closed
                    self._thread = None
                    self._condition.notify_all()
                    return
                fits = PendingFits(self._condition)
                self._pending_fits = {self.key(config): fits}  # only the latest settings are kept
                self._condition.notify_all()
            try:
                self._fit_settings(config, fits)
            except _Abandoned:  # newer settings wanted: the fits of these are not waited for
                pass
            except Exception as exc:  # handed to whoever waits for these settings
                fits.error = exc
            with self._condition:
                fits.done = True
                self._tell()

    def _tell(self) -> None:
        """Under the condition: wake whoever waits on it, and tell the owner of the fits (``on_news``)."""
        self._condition.notify_all()
        if self._on_news is not None:
            self._on_news()

    def _hand_over(self, fits, name, experiment) -> None:
        with self._condition:
            fits.experiments[name] = experiment
            fits.progress.pop(name, None)
            self._tell()

    def _fit_settings(self, config, fits) -> None:
        from ...world.preparation import offline_world, prepare
        from . import fitcache

        with one_blas_thread():
            if config.seed not in self._offline:
                self._offline[config.seed] = offline_world(config)
            prepared = prepare(config, offline=self._offline[config.seed])
            sides = {name: config.replace(**changes) for name, changes in changed_settings(self.sides).items()}
            folder = self._folder()
            for name, side in list(sides.items()):
                experiment = fitcache.load(side, prepared, directory=folder)
                if experiment is not None:
                    self._hand_over(fits, name, experiment)
                    del sides[name]
            workers = self._workers(sides, folder) if sides else {}
            here = {}
            if workers is None:  # no process could be started: fitted here, one side after the other
                here, workers = sides, {}
            if workers:
                self._follow(workers, sides, prepared, folder, fits)
            for name, side in here.items():
                if self._pending:
                    return
                self._hand_over(fits, name, self._fit_here(fits, name, side, prepared))

    def _fit_here(self, fits, name, side, prepared):
        """A side fitted in this thread (kept in the fit cache where it is on): where no worker could fit it.

        Its progress is said step by step; a newer request (or ``close``) abandons it at the next step of its
        hyperparameter search, which raises :class:`_Abandoned` through the fit.
        """
        from ...experiments.experiment import Experiment
        from . import fitcache

        total, taken, began = side.offline_fit_steps or 0, [0], time.perf_counter()

        def step() -> None:
            if self._pending:  # newer settings wanted: nobody waits for this fit any more
                raise _Abandoned
            taken[0] += 1
            with self._condition:
                fits.progress[name] = (f"fitting its models here: step {taken[0]}" + (f" of {total}" if total else "")
                                       + f", {time.perf_counter() - began:.0f} s")
                self._tell()

        with self._condition:
            fits.progress[name] = "fitting its models here"
        def fit(agent) -> None:
            agent.fit(fit_model=lambda model, X, y: model.fit(X, y, on_step=step))

        experiment = Experiment(side, prepared=prepared, fit=fit)
        if fitcache.cache_directory() is not None:
            fitcache.store(experiment)
        return experiment

    def _folder(self):
        """Where the workers store their fits: the fit cache's folder (named to them: a worker started earlier
        may have another setting), or a folder of this queue's where the cache is off."""
        import tempfile

        from . import fitcache

        if fitcache.cache_directory() is not None:
            return fitcache.cache_directory()
        if self._handover is None:
            self._handover = tempfile.TemporaryDirectory(prefix="sarsp-edu-fits-")
        return self._handover.name

    def _workers(self, sides: dict, folder) -> dict | None:
        workers = {}
        try:
            for name, side in sides.items():
                workers[name] = self._take_worker()
                workers[name].submit(side, folder)
        except OSError:  # no process can be started here (or its pipe broke at once)
            for worker in workers.values():
                worker.terminate()
            return None
        return workers

    def _take_worker(self):
        """An idle worker of this queue's, or a new one."""
        from . import fitting

        with self._condition:
            while self._idle:
                worker = self._idle.pop()
                if worker.alive:
                    return worker
        return fitting.take_worker()

    def _give_back(self, worker, finished: bool) -> None:
        """Keep a worker whose fit ``finished`` for the next fits (at most ``IDLE_WORKERS``); terminate one whose
        fit was abandoned, and start a fresh one in its place unless the queue is closed."""
        from . import fitting

        if not finished:
            worker.terminate()
            with self._condition:
                if self._closed:
                    return
            worker = fitting.take_worker()
        with self._condition:
            if not self._closed and len(self._idle) < fitting.IDLE_WORKERS and worker.alive:
                self._idle.append(worker)
                return
        worker.terminate()

    def _follow(self, workers, sides, prepared, folder, fits) -> None:
        """Hand each side over as its worker ends; terminate them all if newer settings are wanted."""
        from . import fitcache

        try:
            while workers:
                if self._pending:  # newer settings wanted: nobody waits for these fits any more
                    return
                for name, worker in list(workers.items()):
                    answer = worker.answer(timeout=0.1 / len(workers))
                    with self._condition:
                        progress = _describe(worker, sides[name])
                        if fits.progress.get(name) != progress:
                            fits.progress[name] = progress
                            self._tell()
                    if answer is None:
                        continue
                    del workers[name]
                    self._give_back(worker, finished=True)
                    word, text = answer
                    if word == "error":
                        raise RuntimeError(f"fitting the {sides[name].model.upper()} side's models failed: {text}")
                    seconds, _, path = text.partition(" ")
                    experiment = fitcache.load(sides[name], prepared, directory=folder)
                    if fitcache.cache_directory() is None:  # handed over, not kept
                        with contextlib.suppress(OSError):
                            os.unlink(path)
                    if experiment is None:  # not this kernel's bits (its package changed since it started, say)
                        experiment = self._fit_here(fits, name, sides[name], prepared)
                    else:
                        experiment.loaded_from_cache = False  # fitted just now, for this run: the fit's time
                        experiment.timings["offline_fit_seconds"] = float(seconds)
                    self._hand_over(fits, name, experiment)
        finally:
            for worker in workers.values():  # abandoned or failed: stopped at once
                self._give_back(worker, finished=False)
