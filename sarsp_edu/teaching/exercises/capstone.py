"""Exercise 7.1, the capstone: the student's six functions assembled into the agent, run beside the package's.

The student hands in a :class:`~sarsp_edu.agent.parts.DecisionParts` (or a
mapping) of the functions written in exercises 2.1 to 2.3 and 4.1 to 4.3:
the kernel, the GP posterior, the TP's variance factor, the safe set, the
choice with its backup and the corrective test.  The check

1. calls each once on its exercise's first input, so that a function not
   written yet, or one that raises, is said at once;
2. runs two TP agents in lock-step on one world with the same seeds
   (:data:`CONFIG`): the package's, and one whose decisions are assembled
   from the student's functions (:class:`~sarsp_edu.agent.sarsp.SARSPAgent`'s
   ``parts``); both share the package's hyperparameter fits;
3. compares every decision (the per-action predictions to the exercises'
   tolerance, the safe set, the action, the backup) and, after each
   violation, the corrective test;
4. at the first difference, says the step, the agent's cell and what
   differs, and calls each of the student's functions that step called,
   and the package's, on the same inputs: the first that differs is named,
   with its inputs and, where one matches, its exercise's usual mistake;
5. after a run that agreed at every step, checks each function with its
   own exercise's check, since a run meets few of the edge cases (a
   known-unsafe action that passes the other tests, a variance of exactly
   sigma*^2): a right verdict means both.

Each call of a student's function runs within the exercises' time limit; a
run that takes long shows where it is (a line in a notebook, a bar in a
terminal) and empties that line when it ends.
"""

from __future__ import annotations

import copy
import sys
import time
from dataclasses import dataclass

import numpy as np

from ..._internal.threads import one_blas_thread
from ...config import ExperimentConfig
from .grading import raised
from .parting import (
    PART_ARGUMENTS,
    PART_FUNCTIONS,
    _culprit,
    _difference,
    _failed,
    _low_precision,
    _named,
    _where,
)
from .running import TimedOut, call_copies, run_limited
from .wording import describe

__all__ = ["CONFIG", "PART_ARGUMENTS", "PART_FUNCTIONS", "Capstone", "run_check"]


#: the check's run: the paper's TP agent at the package's default settings, 4 episodes of seed 0 (218
#: decisions, 4 violations, 3 of them corrected; the first violation at decision 131)
CONFIG = ExperimentConfig(seed=0, episodes=4)
class _PartFailed(Exception):
    """A student's function raised (or ran out of time) inside the agent."""

    def __init__(self, name: str, case: dict, error: BaseException):
        super().__init__(name)
        self.name, self.case, self.error = name, case, error


class _Recorder:
    """The student's parts, each wrapped to run within the time limit and to keep the step's calls."""

    def __init__(self, parts):
        from ...agent.parts import DecisionParts

        self.calls: list = []  # (name, inputs as a dict, result) of the current step, in call order
        self.yours = parts  # as the student wrote them (their exercises' checks run these)
        self.parts = DecisionParts(**{name: self._wrap(name, getattr(parts, name)) for name in PART_FUNCTIONS})

    def _wrap(self, name, function):
        def part(*args):
            case = dict(zip(PART_ARGUMENTS[name], copy.deepcopy(args)))
            try:
                result = run_limited(function, args)
            except (Exception, SystemExit) as exc:  # the student's code may raise anything: said with where
                raise _PartFailed(name, case, exc) from None
            self.calls.append((name, case, copy.deepcopy(result)))
            return result
        return part


class _SharedFits:
    """Fits on equal data given once: the student's agent takes the package's (the fits are not the student's)."""

    def __init__(self):
        self.last = None

    def fit(self, model, X, y):
        model.fit(X, y)
        self.last = (np.array(X), np.array(y), model)

    def adopt(self, model, X, y):
        if self.last is not None and np.array_equal(self.last[0], X) and np.array_equal(self.last[1], y):
            model.__dict__.update(copy.deepcopy(self.last[2].__dict__))
        else:
            model.fit(X, y)


def _copy_fits(agent, source):
    """Give ``agent`` the fitted models of ``source`` (same settings, same data): its random stream moves on the
    same."""
    def fit_model(model, X, y):
        fitted = source.cost_model if model is agent.cost_model else source.reward_model
        if np.array_equal(fitted.X_train_, X) and np.array_equal(fitted.y_train_, y):
            model.__dict__.update(copy.deepcopy(fitted.__dict__))
        else:
            model.fit(X, y)
    agent.fit(fit_model=fit_model)


def _experiments(config, parts):
    """The package's experiment and the student's, on one prepared world, sharing the package's fits."""
    from ...experiments.experiment import Experiment
    from ...world.preparation import prepare
    from ..live import fitcache

    prepared = prepare(config)
    package = fitcache.load(config, prepared)
    if package is None:
        package = Experiment(config, prepared=prepared)
        fitcache.store(package)
    yours = Experiment(config, prepared=prepared, parts=parts, fit=lambda agent: _copy_fits(agent, package.agent))
    shared = _SharedFits()
    package.agent.refit_model, yours.agent.refit_model = shared.fit, shared.adopt
    return package, yours


class _Progress:
    """Where the check is while it runs: one line in a notebook (emptied at the end), else a tqdm bar."""

    def __init__(self, enabled: bool, episodes: int, label: str = "Exercise 7.1"):
        self.handle = self.bar = None
        self.label = label
        self.shown = 0.0
        if not enabled:
            return
        try:
            from IPython import get_ipython

            kernel = getattr(get_ipython(), "kernel", None)
        except ImportError:
            kernel = None
        if kernel is not None:
            from IPython.display import display

            # it starts and ends empty, so a stored notebook keeps the same (empty) output however long it ran
            self.handle = display({"text/plain": ""}, raw=True, display_id=True)
        else:
            from tqdm.auto import tqdm

            self.bar = tqdm(total=episodes, desc=label, unit="episode", leave=False, file=sys.stderr)

    def say(self, text: str, episodes_done: int | None = None) -> None:
        now = time.perf_counter()
        if self.handle is not None and (now - self.shown > 0.3 or episodes_done is None):
            self.handle.update({"text/plain": f"{self.label}: {text}"}, raw=True)
            self.shown = now
        if self.bar is not None:
            self.bar.set_postfix_str(text, refresh=False)
            if episodes_done is not None and episodes_done > self.bar.n:
                self.bar.update(episodes_done - self.bar.n)

    def close(self) -> None:
        if self.handle is not None:
            self.handle.update({"text/plain": ""}, raw=True)
        if self.bar is not None:
            self.bar.close()


def _read(answer):
    """``(parts, None)``, or ``(None, why not)`` for an answer that is not six functions of the student's."""
    from ...agent.parts import EXERCISE_OF, DecisionParts

    try:
        parts = DecisionParts.of(answer)
    except (TypeError, ValueError) as exc:
        return None, (f"Hand in DecisionParts(kernel=rbf, posterior=gp_posterior, tp_factor=tp_variance_factor, "
                      f"safe_set=safe_actions, choose=choose, corrective=corrects): {exc}")
    missing = [name for name in PART_FUNCTIONS if name not in parts.replaced()]
    if missing:
        named = ", ".join(f"{name} (exercise {EXERCISE_OF[name]})" for name in missing)
        return None, f"These parts are still the package's own: {named}; hand in your functions for them."
    return parts, None


def _preflight(parts) -> str | None:
    """Each function once on its exercise's first input: why the run cannot start, or None."""
    from ...agent.parts import EXERCISE_OF
    from .coding import CODING

    for name in PART_FUNCTIONS:
        exercise = EXERCISE_OF[name]
        case = CODING[exercise].cases(np.random.default_rng(0))[0]
        try:
            call_copies(getattr(parts, name), case, limited=True)
        except NotImplementedError:
            return (f"Not written yet: {_named(name)} raises NotImplementedError; paste your answer to exercise "
                    f"{exercise} into its cell and run it.")
        except TimedOut as exc:
            return (f"{_named(name)[0].upper()}{_named(name)[1:]} {exc} on {describe(case)}: "
                    "is there a loop that never ends?")
        except (Exception, SystemExit) as exc:
            return (f"{_named(name)[0].upper()}{_named(name)[1:]} raised {raised(exc)} on {describe(case)}; run "
                    f'check("{exercise}", {PART_FUNCTIONS[name]}) and fix it first.')
    return None


def run_check(answer, config=None, progress: bool = True) -> tuple[bool, str]:
    """Run the student's agent and the package's in lock-step; ``(right, what happened)``.

    Parameters
    ----------
    answer : DecisionParts or mapping
        The student's six functions.
    config : ExperimentConfig, optional
        The run; default :data:`CONFIG`.
    progress : bool, default True
        Show where the run is while it runs.
    """
    config = CONFIG if config is None else config
    parts, problem = _read(answer)
    if problem is None:
        problem = _preflight(parts)
    if problem is not None:
        return False, problem
    recorder = _Recorder(parts)
    shown = _Progress(progress, config.episodes)
    try:
        with one_blas_thread():  # as the experiments run: matrices of a few hundred rows, one thread is fastest
            right, said_ = _lock_step(config, recorder, shown)
            if right:  # a run meets few edge cases (a known-unsafe action that passes the other tests, say)
                shown.say("checking each function on its exercise's inputs ...")
                wrong = _own_checks(parts)
                if wrong is not None:
                    return False, wrong
            return right, said_
    finally:
        shown.close()


def _own_checks(parts) -> str | None:
    """After a run that agreed: the first function its exercise's own check finds wrong, in words, or None."""
    from ...agent.parts import EXERCISE_OF
    from .coding import CODING
    from .grading import grade

    for name in PART_FUNCTIONS:
        exercise = EXERCISE_OF[name]
        right, said_ = grade(exercise, CODING[exercise], getattr(parts, name))
        if not right:
            return (f"Your agent took the package's decisions in this run, but its inputs never tested "
                    f"{_named(name)} where it goes wrong; its own check says: {said_}\nFix it, run "
                    f'check("{exercise}", {PART_FUNCTIONS[name]}), then this check again.')
    return None


def _lock_step(config, recorder: _Recorder, shown: _Progress) -> tuple[bool, str]:
    """The two agents step by step; the verdict at the first difference or at the end."""
    shown.say("fitting the models (about ten seconds, once for each setting on this computer) ...")
    package, yours = _experiments(config, recorder.parts)
    decisions = violations = corrected = 0
    while not package.finished:
        recorder.calls.clear()
        mine = package.step()
        decisions += 1
        try:
            theirs = yours.step()
        except _PartFailed as failed:
            return False, _failed(failed, _where(mine, package, decisions))
        except Exception as exc:  # a result the agent cannot use (a wrong shape, not numbers ...)
            culprit = _culprit(recorder.calls, recorder.yours)
            return False, f"{_where(mine, package, decisions)}: your agent stopped: {raised(exc)}." + (
                f"\n{culprit}" if culprit else "")
        difference = _difference(mine, theirs)
        culprit = rounding_only = None
        if difference is not None:  # only then are the step's calls checked one by one (each costs a solve)
            culprit = _culprit(recorder.calls, recorder.yours)
            rounding_only = culprit is None and not _low_precision(recorder.calls)  # every part right to rounding
            difference = _difference(mine, theirs, rounding_only=rounding_only)
        if difference is not None:
            if rounding_only:
                return _parted_by_rounding(recorder.parts, _where(mine, package, decisions), difference,
                                           decisions - 1)
            culprit = culprit or _low_precision(recorder.calls) or (
                "Each of your functions gives the package's values on the inputs this step gave it: does one of "
                "them keep something from call to call, or draw random numbers?")
            return False, f"{_where(mine, package, decisions)}: {difference}.\n{culprit}"
        violations += mine.outcome.violation
        corrected += mine.outcome.corrected
        shown.say(f"episode {mine.episode} of {config.episodes}, decision {decisions}: every decision agreed so far",
                  len(package.episodes))
    return True, (f"Your agent and the package's took the same {decisions} decisions in {config.episodes} episodes "
                  f"(seed {config.seed}, the {config.model.upper()} agent): the same predictions to the exercises' "
                  f"tolerance, safe sets, actions and backups, and the same corrective test after each of the "
                  f"{violations} violations ({corrected} corrected). Your six functions are Algorithm 1's decision.")


def _parted_by_rounding(parts, where: str, difference: str, agreed: int) -> tuple[bool, str]:
    """The verdict where the two agents part on a decision while each of the student's functions gave the
    package's values to the rounding its inputs allow: a decision at the margin of its threshold, which the last
    digits of an ill-conditioned prior tip.  The functions' own checks decide, as exercise 2.2's would."""
    own = _own_checks(parts)
    if own is not None:
        return False, f"{where}: {difference}.\n{own}"
    return True, (f"Your agent and the package's took the same {agreed} decisions; then ({where}) {difference}, "
                  "although each of your functions gave the package's values to the rounding its inputs allow "
                  "(a prior whose matrix is nearly singular leaves only the first digits of a variance certain): "
                  "that decision lay at the margin of its threshold. Your six functions pass their own checks: "
                  "they are Algorithm 1's decision.")


@dataclass(frozen=True)
class Capstone:
    """Exercise 7.1: the student's six functions as the agent's decision (:func:`run_check`)."""

    question: str
    hint: str

    def verdict(self, answer, reuse: bool = False, config=None, progress: bool = True) -> tuple[bool, str]:
        """:func:`run_check`'s verdict; with ``reuse``, the last one given for the very same functions and run.

        ``is_right`` reuses the verdict of the ``check`` just before it (an
        nbgrader test cell calls both), since a run takes seconds.

        Parameters
        ----------
        answer, config, progress
            As in :func:`run_check`.
        reuse : bool, default False
        """
        parts, _ = _read(answer)
        key = None if parts is None else (tuple(getattr(parts, name) for name in PART_FUNCTIONS),
                                          CONFIG if config is None else config)
        if reuse and key is not None and _LAST.get("key") == key:
            return _LAST["verdict"]
        result = run_check(answer, config, progress)
        if key is not None:
            _LAST.update(key=key, verdict=result)  # holds the functions: their ids are not reused while kept
        return result


_LAST: dict = {}

CAPSTONE = {
    "7.1": Capstone(
        question="your agent: the six functions of exercises 2.1-2.3 and 4.1-4.3 as Algorithm 1's decision, run "
                 "beside the package's agent",
        hint="The first difference names the function: check it on its own with its exercise's check.",
    ),
}
