"""Grading a function a student wrote: fresh inputs, the package's answer, and a diagnosis.

A :class:`CodingExercise` names the function the student writes, the
package's own computation of the same quantity (the reference), a generator
of fresh inputs (several sizes and shapes, and the edge cases), and the usual
mistakes, each as the function a student who made it would have written.
Grading calls the student's function on copies of every input (within a
time limit, watching that it leaves its inputs as they were), compares it
with the reference to a tolerance set from the quantity's own scale, and
when it differs says which mistake it matches, never what the answer is.
Besides the listed mistakes, two are tried for every exercise: a number
argument fixed at one value (``d = 1`` written into the code, say), and
results rounded.
"""

from __future__ import annotations

import time
import zlib
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..._internal.threads import one_blas_thread
from . import running
from .running import TimedOut, call_copies, changed, run_limited
from .wording import describe, parts, said, several, shape_problem, shown, which_differ

__all__ = ["CodingExercise", "Mistake", "explained", "grade", "known_mistake", "raised", "same"]

#: relative tolerance of a right answer; the absolute one is this times the quantity's own scale
RTOL = 1e-6


@dataclass(frozen=True)
class Mistake:
    """A usual mistake: the function a student who made it writes, and what to tell them.

    ``wrong`` takes the exercise's arguments; ``diagnosis`` says what is wrong
    in one sentence that does not give the answer away.  ``exact``: the
    student's results must be the mistake's to the last digits (1e-12), not
    only to the exercises' tolerance, as a claim such as "your values are
    rounded" needs.
    """

    wrong: Callable
    diagnosis: str
    exact: bool = False


@dataclass(frozen=True)
class CodingExercise:
    """An exercise in which the student writes a function.

    Attributes
    ----------
    question : str
        What the function computes, in one line (with the rule for any case
        the equations leave undefined).
    signature : str
        ``name(arguments) -> what it returns``, as the notebook gives it.
    reference : callable
        The package's computation, with the student's signature.
    cases : callable
        ``cases(rng) -> list of dict``: keyword arguments of fresh inputs
        (several sizes and shapes, and the edge cases); every argument takes
        several values.
    mistakes : tuple of Mistake
        Tried in order when an answer is wrong.
    hint : str
        For a wrong answer that matches no mistake: where to look, not what to write.
    explanation : str or callable
        Said with a right answer: what it shows (a callable computes it, so
        that its numbers come from the package, never typed in).
    on_linalg_error : str, optional
        Said after a ``LinAlgError`` the student's code raised (a Cholesky
        factorisation of a matrix that is not positive definite, say).
    timing : callable, optional
        ``timing(rng) -> dict``: one large input on which a right answer
        should not be much slower than the package (a loop that refactorises
        a matrix for every query, say); only a remark, never a failure.
    examples : dict, optional
        Values of number arguments that the notebook uses (``{"d": 1.0}``):
        an answer with one of them written in is told so, as one with the
        first case's value is.
    """

    question: str
    signature: str
    reference: Callable
    cases: Callable[[np.random.Generator], list]
    mistakes: tuple = field(default_factory=tuple)
    hint: str = ""
    explanation: str | Callable[[], str] = ""
    on_linalg_error: str = ""
    timing: Callable | None = None
    examples: dict = field(default_factory=dict)


def explained(explanation) -> str:
    """An exercise's explanation as said: a callable's text (computed now) or the text itself."""
    return explanation() if callable(explanation) else explanation


def raised(exc: BaseException) -> str:
    """An exception in one line: 'ZeroDivisionError: division by zero' (a long message shortened)."""
    text = " ".join(str(exc).split())
    text = text if len(text) <= 200 else text[:197] + "..."
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def same(got, expected, rtol: float = RTOL) -> bool:
    """Whether ``got`` equals ``expected`` (arrays, numbers, tuples of them) to a scale-relative tolerance.

    Infinities must match exactly, NaN matches NaN, booleans and integers
    match exactly; any numeric type is accepted (int, float, numpy scalar,
    0-d array).  Anything that cannot be read as numbers is not equal.

    Parameters
    ----------
    got : object
        The student's result.
    expected : object
        The reference result; its structure says how ``got`` is split into parts.
    rtol : float, default :data:`RTOL`
        The relative tolerance; the absolute one is this times the largest finite ``|expected|`` of each part.
    """
    try:
        return _same(got, expected, rtol)
    except Exception:  # a student's object that cannot be read as numbers (or raises when asked to)
        return False


def _same(got, expected, rtol: float) -> bool:
    got_parts, expected_parts = parts(got, several(expected)), parts(expected, several(expected))
    if len(got_parts) != len(expected_parts):
        return False
    for g, e in zip(got_parts, expected_parts):
        if g.shape != e.shape:
            return False
        if e.dtype == bool or np.issubdtype(e.dtype, np.integer):
            if not (np.issubdtype(g.dtype, np.number) or g.dtype == bool) or not np.array_equal(g, e):
                return False
            continue
        if g.dtype.kind not in "biuf":
            return False
        g, e = g.astype(float), e.astype(float)
        finite = np.isfinite(e)
        scale = float(np.max(np.abs(e[finite]))) if finite.any() else 1.0
        infinities = [np.where(np.isinf(v), np.sign(v), 0.0) for v in (g, e)]  # NaN's sign is NaN: not used
        if not np.array_equal(np.isnan(g), np.isnan(e)) or not np.array_equal(*infinities):
            return False
        if not np.allclose(g[finite], e[finite], rtol=rtol, atol=rtol * max(scale, 1e-300)):
            return False
    return True


def _seed(name: str) -> int:
    return zlib.crc32(name.encode())


def _number(value) -> bool:
    return isinstance(value, (bool, int, float, np.number, np.bool_))


def _fixed_arguments(exercise: CodingExercise, cases: list) -> list:
    """A mistake for each number argument written in as a fixed value: the first case's, or a notebook example's."""
    mistakes = []
    for i, (name, value) in enumerate(cases[0].items()):
        if not _number(value):
            continue
        values = [value] + [v for v in np.atleast_1d(exercise.examples.get(name, ())).tolist() if v != value]
        for fixed in values:
            def wrong(*args, i=i, fixed=fixed):
                args = list(args)
                args[i] = fixed
                return exercise.reference(*args)

            mistakes.append(Mistake(wrong, f"Your results are the ones {name} = {said(fixed)} gives, whatever "
                                           f"{name} is: use the {name} your function is given."))
    return mistakes


def _round_to(value, digits: int, significant: bool):
    """``value``'s floating-point parts rounded to ``digits`` decimals (or significant digits)."""
    def one(part):
        array = np.asarray(part)
        if array.dtype.kind != "f":
            return part
        if not significant:
            return np.round(array, digits)
        return np.vectorize(lambda x: float(f"{x:.{digits}g}") if np.isfinite(x) else x, otypes=[float])(array)

    return tuple(one(p) for p in value) if several(value) else one(value)


def _rounding(exercise: CodingExercise) -> list:
    """Mistakes: results rounded to 0 to 6 decimals, or to 1 to 6 significant digits."""
    mistakes = []
    for digits, significant in [(k, False) for k in range(7)] + [(k, True) for k in range(1, 7)]:
        unit = "significant digit" if significant else "decimal"
        unit = unit if digits == 1 else unit + "s"
        mistakes.append(Mistake(
            lambda *args, digits=digits, significant=significant: _round_to(exercise.reference(*args), digits,
                                                                           significant),
            f"Your values are rounded (to {digits} {unit}): return them as computed; round only where you "
            "print them.", exact=True))  # said only of values that are rounded, not of values a little off
    return mistakes


def grade(name: str, exercise: CodingExercise, function, rng=None) -> tuple[bool, str]:
    """Call ``function`` on the exercise's fresh inputs; return (right, one or two sentences).

    ``rng`` (a seed or Generator) draws the inputs; by default a seed of the
    exercise's name, so that a verdict is the same every time it is asked.
    Every call gets copies of the inputs and :data:`running.TIME_LIMIT`
    seconds.  A wrong answer is matched against the usual mistakes on every
    input; the first mistake that reproduces all of its results gives the
    diagnosis.

    Parameters
    ----------
    name : str
        The exercise's name, such as ``"2.1"``; it seeds the default ``rng``.
    exercise : CodingExercise
        Its reference function, inputs, usual mistakes and hint.
    function : callable
        The student's function.
    rng : None, int or numpy.random.Generator
        Draws the inputs; None: a seed of ``name``.
    """
    if not callable(function):
        return False, f"This exercise asks for a function, {exercise.signature}; got {type(function).__name__}."
    rng = np.random.default_rng(_seed(name) if rng is None else rng)
    cases = exercise.cases(rng)
    answers, failed = [], None
    for case in cases:
        expected = call_copies(exercise.reference, case)[0]
        try:
            got, copies = call_copies(function, case, limited=True)
        except NotImplementedError:
            return False, "Not written yet; replace the line raise NotImplementedError(...) with your code."
        except TimedOut as exc:
            return False, (f"Your function {exc} (on {describe(case)}), so the check stopped waiting: is there a "
                           "loop that never ends?")
        except (Exception, SystemExit) as exc:  # the student's code may raise anything: say what and where
            said_ = f"Your function raised {raised(exc)} (on {describe(case)})."
            if isinstance(exc, np.linalg.LinAlgError) and exercise.on_linalg_error:
                said_ = f"{said_} {exercise.on_linalg_error}"
            if failed is not None:  # wrong before it raised: what was wrong first says more
                return False, f"{_diagnosis(exercise, cases[:len(answers)], answers, failed)} {said_}"
            return False, said_
        moved = [key for (key, before), after in zip(case.items(), copies) if changed(before, after)]
        if moved:
            which = " and ".join(moved)
            return False, (f"Your function changed its input {which} in place (on {describe(case)}): the caller's "
                           f"data must stay as they were, so work on a copy.")
        answers.append(got)
        if failed is None and not same(got, expected):
            failed = (case, got, expected)
    if failed is not None:
        return False, _diagnosis(exercise, cases, answers, failed)
    message = explained(exercise.explanation)
    if exercise.timing is not None:
        slow = _slowness(exercise, function, rng)
        if slow:
            message = f"{message} {slow}".strip()
    return True, message


def known_mistake(exercise: CodingExercise, cases: list, answers: list) -> str | None:
    """The diagnosis of the first usual mistake that gives every one of ``answers`` on its case, or None.

    ``cases`` are the inputs (dicts in the signature's order), ``answers``
    what the student's function returned on each; the mistakes are the
    exercise's own, then a number argument written in and rounded results.

    Parameters
    ----------
    exercise : CodingExercise
    cases : list of dict
        The inputs.
    answers : list
        The student's result on each case.
    """
    for mistake in (*exercise.mistakes, *_fixed_arguments(exercise, cases), *_rounding(exercise)):
        if _reproduces(mistake, cases, answers):
            return mistake.diagnosis
    return None


def _diagnosis(exercise: CodingExercise, cases: list, answers: list, failed: tuple) -> str:
    """What is wrong: a mistake the answers reproduce, else where they differ first, and the hint."""
    mistake = known_mistake(exercise, cases, answers)
    if mistake is not None:
        return mistake
    case, got, expected = failed
    if got is None:  # a right result is never None: a return is missing
        return f"Your function returned None (is its return statement missing?) on {describe(case)}."
    if any(part.dtype.kind not in "biuf" for part in parts(got, several(expected))):
        return (f"Your function returned {shown(got)} on {describe(case)}, which cannot be read as "
                f"{'numbers' if several(expected) or np.ndim(expected) else 'a number'}.")
    problem = shape_problem(got, expected)
    if problem:
        return f"{problem[0].upper()}{problem[1:]} (On {describe(case)}.)"
    yours = said(got)
    yours = f" (yours: {yours})" if yours is not None else ""
    return f"On {describe(case)}, {which_differ(got, expected, same)}{yours}. {exercise.hint}".strip()


def _reproduces(mistake: Mistake, cases: list, answers: list) -> bool:
    """Whether ``mistake`` gives the student's result on every input it applies to (and on one at least)."""
    applied = 0
    for case, got in zip(cases, answers):
        try:
            with np.errstate(all="ignore"):
                wrong = call_copies(mistake.wrong, case)[0]
        except Exception:  # a mistake that does not apply to this input
            continue
        if not same(got, wrong, rtol=1e-12 if mistake.exact else RTOL):
            return False
        applied += 1
    return applied > 0


def _slowness(exercise: CodingExercise, function, rng) -> str:
    """A remark when ``function`` is far slower than the package on a large input ('' otherwise)."""
    case = exercise.timing(rng)

    def seconds(f, limited=False):
        start = time.perf_counter()
        call_copies(f, case, limited=limited)
        return time.perf_counter() - start

    # both on one BLAS thread: a package's time measured on several threads of a busy machine (the other half of
    # a two-core machine running tests, a Binder pod) grows many times, and a slow answer was then called fast
    with one_blas_thread():
        ours = min(seconds(exercise.reference) for _ in range(3))
        try:
            theirs = seconds(function, limited=True)
        except TimedOut:
            theirs = float(running.TIME_LIMIT)
        except Exception:
            return ""
    if theirs > 0.5 and theirs > 30 * ours:
        took = f"{theirs:.0f} s" if theirs < running.TIME_LIMIT else f"over {running.TIME_LIMIT:g} s"
        return (f"It is right but slow: {took} on {describe(case)}, {theirs / ours:.0f} times the package's "
                "time (on a busy machine, a few times more). If it loops over the queries or factorises again, "
                "factorise once and solve for every query together.")
    return ""


def run_prediction(prediction):
    """A prediction written as a function, called within the time limit: ``(value, None)`` or ``(None, reply)``."""
    try:
        return run_limited(prediction), None
    except NotImplementedError:
        return None, "Not written yet; replace the line raise NotImplementedError(...) with your answer."
    except TimedOut as exc:
        return None, f"Your function {exc}, so the check stopped waiting: is there a loop that never ends?"
    except (Exception, SystemExit) as exc:
        return None, f"Your answer raised {raised(exc)}."
