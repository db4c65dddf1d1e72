"""The live dashboard's fits in processes of their own: both sides at once, a fit nobody waits for stopped at once.

A side's offline fit is a few seconds of LAPACK calls through scipy's
wrappers, which hold the GIL: two sides fitted in two threads of one kernel
take as long as one after the other (measured: 12.5 s for both, against
7.0 s and 12.8 s one after the other), and a thread cannot be stopped
part-way when a slider leaves its settings.  Each side is therefore fitted
by a :class:`FitWorker`, a child process (``python -m sarsp_edu.teaching.live.fitting``)
that fits the side's models and stores them as a :mod:`sarsp_edu.teaching.live.fitcache`
entry; the dashboard loads that entry, which is checked bit for bit against
the data as every cache entry is, so the run is the one a fit in the kernel
would give.  A worker reports its progress (steps of the hyperparameter
search) line by line, waits for its next fit with its imports done, and is
terminated at once when its fit is no longer wanted.

The protocol on the child's pipes: the parent writes each job as an 8-byte
length and a pickle of ``(config, folder)``; the child answers with lines
``started``, ``step K N`` (N = 0 when the total is not known), then
``done SECONDS PATH`` (the fit's seconds) or ``error MESSAGE``.
"""

from __future__ import annotations

import atexit
import os
import pickle
import queue
import subprocess
import sys
import threading
import time
import weakref

__all__ = ["IDLE_WORKERS", "FitWorker", "take_worker"]

#: idle workers a queue of fits keeps for its next fits (a warm worker saves its start, about 1.3 s of imports)
IDLE_WORKERS = 2
#: every worker alive, so that a script's end ends them (an ``atexit`` hook): the module's one piece of state
_ALL = weakref.WeakSet()


class FitWorker:
    """One child process that fits one side at a time; terminated when its fit is abandoned."""

    def __init__(self):
        self.process = subprocess.Popen(
            [sys.executable, "-m", "sarsp_edu.teaching.live.fitting"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
            env=dict(os.environ, PYTHONUNBUFFERED="1"),
            # its own session: a Ctrl-C in the terminal (or a kernel's interrupt of its group) is not for the fits,
            # even while the process still imports; the kernel ends a worker itself, and its end of the pipe ends it
            start_new_session=True)
        self.steps = (0, 0)  # steps taken, steps in all (0: not known)
        self.started_at = None  # when the fit itself began (imports and data done)
        self._answers = queue.Queue()
        #: the one reader of the process's answers (it owns the pipe, and hands each answer over by a queue)
        self._reader = threading.Thread(target=self._read, name="sarsp-edu-fit-reader", daemon=True)
        self._reader.start()
        _ALL.add(self)

    def _read(self) -> None:
        for raw in self.process.stdout:
            word, _, rest = raw.decode("utf-8", "replace").rstrip("\n").partition(" ")
            if word == "step":
                done, total = rest.split()
                self.steps = (int(done), int(total))
            elif word == "started":
                self.started_at = time.perf_counter()
            elif word in ("done", "error"):
                self._answers.put((word, rest))
        self._answers.put(("error", f"the fitting process ended (exit status {self.process.wait()})"))

    @property
    def alive(self) -> bool:
        return self.process.poll() is None

    def submit(self, config, folder) -> None:
        """Fit ``config``'s models and store them in ``folder`` (a fit cache's folder); returns at once.

        Parameters
        ----------
        config : ExperimentConfig
            The side's settings (pickled to the process, which prepares their world and data itself).
        folder : str or Path
            Where the process stores the fit (:func:`~sarsp_edu.teaching.live.fitcache.store`'s ``directory``).
        """
        self.steps, self.started_at = (0, 0), None
        job = pickle.dumps((config, str(folder)))
        self.process.stdin.write(len(job).to_bytes(8, "big") + job)
        self.process.stdin.flush()

    def answer(self, timeout: float):
        """``("done", "<fit seconds> <path>")`` or ``("error", message)`` once the fit has ended, else None after
        ``timeout`` s."""
        try:
            return self._answers.get(timeout=timeout)
        except queue.Empty:
            return None

    def terminate(self) -> None:
        """Kill the process (if it still runs), wait for it and its reader thread, and close its pipes."""
        if self.alive:
            self.process.kill()
        self.process.wait()
        if self._reader is not threading.current_thread():
            self._reader.join()  # it reads to the end of the pipe, which the process's end closes
        for stream in (self.process.stdin, self.process.stdout):
            try:
                stream.close()
            except OSError:
                pass


def take_worker() -> FitWorker:
    """A new worker (a queue of fits keeps its idle ones itself: ``FitQueue``)."""
    return FitWorker()


@atexit.register
def _terminate_all() -> None:
    for worker in list(_ALL):
        worker.terminate()


# -- the child's side --------------------------------------------------------
def _fit(config, folder, say) -> str:
    from ..._internal.threads import one_blas_thread
    from ...experiments.experiment import Experiment
    from ...world.preparation import prepare
    from . import fitcache

    total = config.offline_fit_steps or 0  # 0: not known (L-BFGS takes as many as it needs)
    taken = [0]

    def step() -> None:
        taken[0] += 1
        say(f"step {taken[0]} {total}")

    def fit(agent) -> None:
        say("started")
        agent.fit(fit_model=lambda model, X, y: model.fit(X, y, on_step=step))

    with one_blas_thread():  # as the kernel fits: the same bits
        experiment = Experiment(config, prepared=prepare(config), fit=fit)
    path = fitcache.store(experiment, directory=folder)
    if path is None:
        raise OSError(f"the fit could not be written to {folder}")
    return f"{experiment.timings['offline_fit_seconds']!r} {path}"


def _serve(stdin, stdout) -> None:
    def say(line: str) -> None:
        stdout.write((line + "\n").encode("utf-8"))
        stdout.flush()

    while True:
        header = stdin.read(8)
        if len(header) < 8:  # the kernel has gone: so do we
            return
        config, folder = pickle.loads(stdin.read(int.from_bytes(header, "big")))
        try:
            say(f"done {_fit(config, folder, say)}")
        except Exception as exc:  # said to the kernel, which raises it where the side waits
            say("error " + f"{type(exc).__name__}: {exc}".replace("\n", " "))


if __name__ == "__main__":
    import signal

    # an interrupt of the kernel (its process group's Ctrl-C) is not for the fits: the kernel ends a worker
    # itself, by closing its pipe or killing it
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    import sarsp_edu.experiments.experiment  # noqa: F401  (the imports done before the first job, while the kernel waits)

    _serve(sys.stdin.buffer, sys.stdout.buffer)
