"""Grading a function a student wrote: fresh inputs, the package's answer, and a diagnosis.

A :class:`CodingExercise` names the function the student writes, the
package's own computation of the same quantity (the reference), a generator
of fresh inputs (several sizes and the edge cases), and the usual mistakes,
each as the function a student who made it would have written.  Grading
calls the student's function on every input, compares it with the reference
to a tolerance set from the quantity's own scale, and when it differs says
which mistake it matches, never what the answer is.
"""

from __future__ import annotations

import copy
import time
import zlib
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

__all__ = ["CodingExercise", "Mistake", "explained", "grade", "same"]

#: relative tolerance of a right answer; the absolute one is this times the quantity's own scale
RTOL = 1e-6


@dataclass(frozen=True)
class Mistake:
    """A usual mistake: the function a student who made it writes, and what to tell them.

    ``wrong`` takes the exercise's arguments; ``diagnosis`` says what is wrong
    in one sentence that does not give the answer away.
    """

    wrong: Callable
    diagnosis: str


@dataclass(frozen=True)
class CodingExercise:
    """An exercise in which the student writes a function.

    Attributes
    ----------
    question : str
        What the function computes, in one line.
    signature : str
        ``name(arguments) -> what it returns``, as the notebook gives it.
    reference : callable
        The package's computation, with the student's signature.
    cases : callable
        ``cases(rng) -> list of dict``: keyword arguments of fresh inputs
        (several sizes, and the edge cases).
    mistakes : tuple of Mistake
        Tried in order when an answer is wrong.
    hint : str
        For a wrong answer that matches no listed mistake.
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


def explained(explanation) -> str:
    """An exercise's explanation as said: a callable's text (computed now) or the text itself."""
    return explanation() if callable(explanation) else explanation


def _several(value) -> bool:
    """Whether a reference result is several results (a tuple), not one array."""
    return isinstance(value, tuple)


def _parts(value, several: bool) -> list:
    """A result as a list of arrays: several parts where the reference returns a tuple, else one array."""
    if several and isinstance(value, (tuple, list)):
        return [np.asarray(v) for v in value]
    return [np.asarray(value)]


def same(got, expected, rtol: float = RTOL) -> bool:
    """Whether ``got`` equals ``expected`` (arrays, numbers, tuples of them) to a scale-relative tolerance.

    Infinities must match exactly, NaN matches NaN, booleans and integers
    match exactly; any numeric type is accepted (int, float, numpy scalar,
    0-d array).
    """
    got_parts, expected_parts = _parts(got, _several(expected)), _parts(expected, _several(expected))
    if len(got_parts) != len(expected_parts):
        return False
    for g, e in zip(got_parts, expected_parts):
        if g.shape != e.shape:
            return False
        if e.dtype == bool or np.issubdtype(e.dtype, np.integer):
            if not (np.issubdtype(g.dtype, np.number) or g.dtype == bool) or not np.array_equal(g, e):
                return False
            continue
        try:
            g = g.astype(float)
        except (TypeError, ValueError):
            return False
        e = e.astype(float)
        finite = np.isfinite(e)
        scale = float(np.max(np.abs(e[finite]))) if finite.any() else 1.0
        infinities = [np.where(np.isinf(v), np.sign(v), 0.0) for v in (g, e)]  # NaN's sign is NaN: not used
        if not np.array_equal(np.isnan(g), np.isnan(e)) or not np.array_equal(*infinities):
            return False
        if not np.allclose(g[finite], e[finite], rtol=rtol, atol=rtol * max(scale, 1e-300)):
            return False
    return True


def _shape_problem(got, expected) -> str | None:
    """A sentence about a result of the wrong structure or shape, or None."""
    got_parts, expected_parts = _parts(got, _several(expected)), _parts(expected, _several(expected))
    if len(expected_parts) > 1 and len(got_parts) != len(expected_parts):
        return f"it should return {len(expected_parts)} things (a tuple), but returns {len(got_parts)}."
    for i, (g, e) in enumerate(zip(got_parts, expected_parts)):
        if g.shape != e.shape:
            which = f"its result number {i + 1}" if len(expected_parts) > 1 else "its result"
            if e.ndim == 0:
                return f"{which} should be a single number, but has shape {g.shape}."
            return f"{which} has shape {g.shape} where {e.shape} is expected."
    return None


def _which_differ(got, expected) -> str:
    """'it gives other values than the package', naming which results differ where there are several."""
    if not _several(expected):
        return "it gives other values than the package"
    parts = list(zip(_parts(got, True), _parts(expected, True)))
    wrong = [i + 1 for i, (g, e) in enumerate(parts) if not same(g, e)]
    if len(wrong) == len(parts):
        return ("both of its results differ" if len(parts) == 2 else f"all {len(parts)} of its results differ") + \
            " from the package's"
    named = " and ".join(f"number {i}" for i in wrong)
    verb = "differs" if len(wrong) == 1 else "differ"
    rest = "the other is right" if len(parts) - len(wrong) == 1 else "the others are right"
    return f"its result {named} (of {len(parts)}) {verb} from the package's; {rest}"


#: inputs and results with at most this many numbers are said in full, so a student can redo the case by hand
SMALL = 8


def _said(value) -> str | None:
    """A value in words: small ones in full ('[0.2, 0.5]', 'True', '3.5'), else None."""
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (int, float, np.number)):
        return f"{value:g}"
    if isinstance(value, dict):
        items = [(key, _said(item)) for key, item in value.items()]
        return "{" + ", ".join(f"{key}: {text}" for key, text in items) + "}" if all(t for _, t in items) else None
    if isinstance(value, tuple):
        items = [_said(item) for item in value]
        return "(" + ", ".join(items) + ")" if all(items) else None
    array = np.asarray(value)
    if array.dtype != object and array.ndim == 1 and array.size <= SMALL:
        return "[" + ", ".join(_said(item.item()) for item in array) + "]"
    return None


def _describe(case: dict) -> str:
    """An input in words: small values in full, larger arrays by their shape ('X of shape (7, 2), nu = 3.5')."""
    parts = []
    for name, value in case.items():
        text = _said(value)
        if text is not None:
            parts.append(f"{name} = {text}")
        elif isinstance(value, np.ndarray):
            parts.append(f"{name} of shape {value.shape}")
    return ", ".join(parts)


def _seed(name: str) -> int:
    return zlib.crc32(name.encode())


def _call(function, case: dict):
    """``function`` on a copy of ``case``'s values, passed in order (a student may name them as they like)."""
    return function(*copy.deepcopy(list(case.values())))


def grade(name: str, exercise: CodingExercise, function, rng=None) -> tuple[bool, str]:
    """Call ``function`` on the exercise's fresh inputs; return (right, one or two sentences).

    ``rng`` (a seed or Generator) draws the inputs; by default a seed of the
    exercise's name, so that a verdict is the same every time it is asked.
    A wrong answer is matched against the usual mistakes on every input; the
    first mistake that reproduces all of its results gives the diagnosis.
    """
    if not callable(function):
        return False, f"This exercise asks for a function, {exercise.signature}; got {type(function).__name__}."
    rng = np.random.default_rng(_seed(name) if rng is None else rng)
    cases = exercise.cases(rng)
    answers, failed = [], None
    for case in cases:
        expected = _call(exercise.reference, case)
        try:
            got = _call(function, case)
        except NotImplementedError:
            return False, "Not written yet; replace the line raise NotImplementedError(...) with your code."
        except Exception as exc:  # the student's code may raise anything: say what and where
            said = f"Your function raised {type(exc).__name__}: {exc} (on {_describe(case)})."
            if isinstance(exc, np.linalg.LinAlgError) and exercise.on_linalg_error:
                said = f"{said} {exercise.on_linalg_error}"
            return False, said
        answers.append(got)
        if failed is None and not same(got, expected):
            failed = (case, got, expected)
    if failed is not None:
        for mistake in exercise.mistakes:
            if _reproduces(mistake, cases, answers):
                return False, mistake.diagnosis
        case, got, expected = failed
        if got is None:  # a right result is never None: a return is missing
            return False, f"Your function returned None (is its return statement missing?) on {_describe(case)}."
        problem = _shape_problem(got, expected)
        if problem:
            return False, f"{problem[0].upper()}{problem[1:]} (On {_describe(case)}.)"
        yours = _said(got)
        yours = f" (yours: {yours})" if yours is not None else ""
        return False, f"On {_describe(case)}, {_which_differ(got, expected)}{yours}. {exercise.hint}".strip()
    message = explained(exercise.explanation)
    if exercise.timing is not None:
        slow = _slowness(exercise, function, rng)
        if slow:
            message = f"{message} {slow}".strip()
    return True, message


def _reproduces(mistake: Mistake, cases: list, answers: list) -> bool:
    """Whether ``mistake`` gives the student's result on every input it applies to (and on one at least)."""
    applied = 0
    for case, got in zip(cases, answers):
        try:
            wrong = _call(mistake.wrong, case)
        except Exception:  # a mistake that does not apply to this input
            continue
        if not same(got, wrong):
            return False
        applied += 1
    return applied > 0


def _slowness(exercise: CodingExercise, function, rng) -> str:
    """A remark when ``function`` is far slower than the package on a large input ('' otherwise)."""
    case = exercise.timing(rng)

    def seconds(f):
        start = time.perf_counter()
        _call(f, case)
        return time.perf_counter() - start

    ours = min(seconds(exercise.reference) for _ in range(3))
    try:
        theirs = seconds(function)
    except Exception:
        return ""
    if theirs > 0.5 and theirs > 30 * ours:
        return (f"It is right but slow: {theirs:.0f} s on {_describe(case)}, {theirs / ours:.0f} times the package's "
                "time. Factorise once and solve for every query together, not one query at a time.")
    return ""
