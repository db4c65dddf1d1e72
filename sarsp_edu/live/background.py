"""The live dashboard's runs prepared ahead: fitted in a worker thread while the lecturer talks.

A slider move requests its settings' runs; the latest request only is kept
(dragging a slider queues no work), and each side is handed over as soon as
its models are fitted, loaded from :mod:`sarsp_edu.fitcache` where these
settings were fitted before.
"""

from __future__ import annotations

import threading

from .._threads import one_blas_thread

__all__ = ["changed_settings"]


def changed_settings(sides: dict) -> dict:
    """Name -> the settings that side changes: the dashboard's sides as ``experiments_on_one_world`` takes them."""
    return {name: changes for name, (_, changes) in sides.items()}


class Preparation:
    """The runs of one setting as a worker thread fits them: each side appears as soon as its models are fitted."""

    def __init__(self, condition):
        self._condition = condition
        self.experiments = {}
        self.error = None
        self.done = False

    def wait_for(self, name):
        """The side's Experiment, once fitted (raises what the preparation raised; None if it was abandoned)."""
        with self._condition:
            while name not in self.experiments and self.error is None and not self.done:
                self._condition.wait()
            if self.error is not None:
                raise self.error
            return self.experiments.get(name)


class Preparer:
    """Prepares the runs of the latest requested settings in one daemon thread.

    A slider move requests new settings; settings requested while another
    preparation runs are prepared after it (the one under way stops after
    the side it is fitting), and only the latest request is kept, so a
    lecturer dragging a slider does not queue up work.  ``claim`` hands a
    preparation, finished or under way, to the dashboard once.
    """

    def __init__(self, sides: dict):
        self.sides = sides
        self._condition = threading.Condition()
        self._wanted = None
        self._pending = False
        self._preparations = {}  # key -> Preparation (the latest only)
        self._thread = None

    @staticmethod
    def key(config):
        return repr(config)

    def request(self, config) -> None:
        """Prepare ``config`` (again), after the preparation under way."""
        with self._condition:
            self._wanted, self._pending = config, True
            if self._thread is None:
                self._thread = threading.Thread(target=self._work, name="sarsp-edu-prepare", daemon=True)
                self._thread.start()
            self._condition.notify_all()

    def busy_with(self, config) -> bool:
        """Whether a preparation of ``config`` is under way or waits to begin."""
        with self._condition:
            key = self.key(config)
            preparation = self._preparations.get(key)
            return (preparation is not None and not preparation.done) or (
                self._pending and self.key(self._wanted) == key)

    def claim(self, config):
        """The preparation of ``config`` (finished or under way), handed out once; None if it was not requested."""
        with self._condition:
            key = self.key(config)
            while self._pending and self.key(self._wanted) == key:  # requested, not begun: wait for it to begin
                self._condition.wait()
            return self._preparations.pop(key, None)

    def _work(self) -> None:
        from ..experiment import each_experiment_on_one_world

        while True:
            with self._condition:
                if not self._pending:
                    self._thread = None
                    self._condition.notify_all()
                    return
                config, self._pending = self._wanted, False
                key = self.key(config)
                preparation = Preparation(self._condition)
                self._preparations = {key: preparation}  # only the latest settings are kept
                self._condition.notify_all()
            try:
                with one_blas_thread():
                    sides = changed_settings(self.sides)
                    for name, experiment in each_experiment_on_one_world(config, sides, cache=True):
                        with self._condition:
                            preparation.experiments[name] = experiment
                            self._condition.notify_all()
                            if self._pending:  # newer settings wanted: the rest of this one is abandoned
                                break
            except Exception as exc:  # handed to whoever waits for these settings
                preparation.error = exc
            with self._condition:
                preparation.done = True
                self._condition.notify_all()
