"""The tutorials' exercises, checked by the package.

Most exercises ask the student to **write a function** (the RBF kernel, the
GP posterior from a Cholesky factor, the TP's variance factor, Algorithm 1's
safe set ...): ``check("2.1", rbf)`` calls it on fresh random inputs of
several sizes and the edge cases, compares it with the package's own
computation to a tolerance set from the quantity's scale, and answers in one
or two sentences; a wrong answer gets a diagnosis of the usual mistake it
matches (a missing noise term, a standard deviation for a variance, a
misprinted equation ...), never the answer.  A few short "predict, then run"
questions take a value, or a function returning it (:mod:`.short_answers`).  The
capstone, exercise 7.1 (:mod:`.capstone`), takes the six functions of
exercises 2.1 to 2.3 and 4.1 to 4.3 as the agent's decision and runs that
agent beside the package's; exercise 7.2 (:mod:`.own_rule`) runs a safety rule the
student designs beside the package's agent and checks that it is a valid part and that its run was made (the
choice of agent is argued in writing).  In a Voila page (a dashboard served as an app)
``check`` prints nothing: a page shows no exercise.

Examples
--------
>>> import numpy as np
>>> from sarsp_edu.teaching.exercises import check
>>> def rbf(X, Y, amplitude, length_scale):
...     raise NotImplementedError("write your answer here")
>>> check("2.1", rbf)
Exercise 2.1: not yet. Not written yet; replace the line raise NotImplementedError(...) with your code.
>>> def rbf(X, Y, amplitude, length_scale):  # a classic slip: the length scale not squared
...     d2 = ((X[:, None, :] - Y[None, :, :]) ** 2).sum(-1)
...     return amplitude**2 * np.exp(-d2 / (2 * length_scale))
>>> check("2.1", rbf)
Exercise 2.1: not yet. Divide the squared distance by 2 l^2: the length scale is squared too.
>>> check("3.4", "a few")  # doctest: +NORMALIZE_WHITESPACE
Exercise 3.4: not yet. Could not read 'a few' as a whole number. Accepted: a whole number: 12, 12.0,
'12' or a numpy integer.
"""

from __future__ import annotations

import os

from .capstone import CAPSTONE
from .coding import CODING  # the exercises in which the student writes a function, by "tutorial.number"
from .grading import CodingExercise, Mistake, explained, grade, run_prediction, same
from .own_rule import OWN_RULE
from .parsing import Unreadable
from .short_answers import LOOKUPS, Exercise

__all__ = ["CODING", "EXERCISES", "CodingExercise", "Exercise", "Mistake", "check", "grade", "is_right", "same"]

#: every exercise, by "tutorial.number": the coding ones, the short answers and the capstone
EXERCISES: dict = dict(sorted({**CODING, **LOOKUPS, **CAPSTONE, **OWN_RULE}.items(),
                              key=lambda item: tuple(map(int, item[0].split(".")))))
#: set in a kernel that Voila runs: a page served as an app shows no exercise, so ``check`` prints nothing there
VOILA_VARIABLE = "VOILA_KERNEL_ID"


def _verdict(exercise: str, answer, reuse: bool = False, **context) -> tuple[bool, str]:
    if exercise not in EXERCISES:
        raise ValueError(f"exercise must be one of {list(EXERCISES)}, got exercise={exercise!r}")
    if answer is Ellipsis:
        return False, "not answered yet; replace ... with your answer."
    if exercise in CODING:
        return grade(exercise, CODING[exercise], answer)
    if exercise in CAPSTONE:  # config= and progress= may come in the context
        return CAPSTONE[exercise].verdict(answer, reuse=reuse, **context)
    if exercise in OWN_RULE:  # run= comes in the context
        return OWN_RULE[exercise].verdict(answer, reuse=reuse, **context)
    item = LOOKUPS[exercise]
    returned = ""
    if callable(answer):  # a prediction written as a function: my_prediction() returns it
        answer, problem = run_prediction(answer)
        if problem:
            return False, problem
        if answer is Ellipsis:
            return False, "Not answered yet: your function returns ...; replace it with your answer."
        returned = " (is your function's return statement missing?)"
    if answer is None:
        return False, f"Your answer is None{returned}. Accepted: {item.accepted}."
    try:
        value = item.read(answer)
    except Unreadable as unread:
        return False, f"{unread} Accepted: {item.accepted}."
    if item.is_right(value, **context):
        return True, explained(item.explanation)
    return False, item.hint


def is_right(exercise: str, answer, **context) -> bool:
    """Whether ``answer`` to ``exercise`` is right (silent; :func:`check` says so in words).

    Parameters
    ----------
    exercise : str
        ``"tutorial.number"``, e.g. ``"2.1"``.
    answer : object
        The student's function (coding exercises) or value; ``...`` is never right.
    **context
        Objects of the notebook some short-answer checks need (named in the exercise).

    For the capstone (7.1), the verdict of a :func:`check` of the very same
    functions just before is reused rather than run again.
    """
    return _verdict(exercise, answer, reuse=True, **context)[0]


def check(exercise: str, answer, **context) -> None:
    """Say whether ``answer`` to ``exercise`` is right: with why if it is, a diagnosis if not.

    Takes the arguments of :func:`is_right`; prints one line (the capstone's
    diagnosis: a second) and returns nothing, so that a notebook cell shows
    only the verdict.  In a kernel that Voila runs (``VOILA_KERNEL_ID`` set)
    it checks and prints nothing.

    Parameters
    ----------
    exercise, answer, **context
        As in :func:`is_right`.
    """
    if os.environ.get(VOILA_VARIABLE):
        return
    right, message = _verdict(exercise, answer, **context)
    if answer is Ellipsis:
        print(f"Exercise {exercise}: {message}")
        return
    print(f"Exercise {exercise}: {'right' if right else 'not yet'}. {message}".rstrip())
