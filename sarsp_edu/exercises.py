"""The tutorials' exercises: each answer is checked against what the package computes.

A student's cell holds ``my_answer = ...``; ``check("1.1", my_answer)`` says
whether it is right, with a hint when it is not, and reminds the student to
fill it in while it is still ``...``.  No answer is stored here: every check
computes its own from the package (sympy limits, fitted models, the gridworld,
Algorithm 1's rule), so the checks stay right when the package changes.  The
worked solutions are in ``tutorials/solutions/``.

Examples
--------
>>> from sarsp_edu.exercises import check
>>> check("1.1", ...)
Exercise 1.1: not answered yet; replace ... with your answer.
>>> check("1.1", 0.5)
Exercise 1.1: not yet. Use eq. 8: the limit is lambda**(-1 - nu).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from collections.abc import Callable

__all__ = ["EXERCISES", "Exercise", "check", "is_right"]


@dataclass(frozen=True)
class Exercise:
    """One checked exercise.

    Attributes
    ----------
    question : str
        What is asked, in one line (the notebook asks it in full).
    is_right : callable
        ``is_right(answer, **context) -> bool``, computed from the package
        (``context``: objects of the notebook the check needs, if any).
    hint : str
        Shown with a wrong answer.
    explanation : str or callable
        Shown with a right one; a callable computes it (its numbers come
        from the package, never typed in).
    """

    question: str
    is_right: Callable[..., bool]
    hint: str
    explanation: str | Callable[[], str]


def _close(value, expected: float, rel: float = 1e-9, abs_: float = 1e-12) -> bool:
    try:
        return math.isclose(float(value), float(expected), rel_tol=rel, abs_tol=abs_)
    except (TypeError, ValueError):
        return False


def _word(answer, *choices: str) -> str | None:
    """The choice ``answer`` names (case and spaces ignored), or None."""
    if not isinstance(answer, str):
        return None
    text = answer.strip().lower()
    return text if text in choices else None


# -- tutorial 1 ---------------------------------------------------------------
def _t_limit_nu4_lam2(answer, **_) -> bool:
    from . import tails

    return _close(answer, float(tails.student_t_tail_limit(4, 2)))


def _gaussian_limits(answer, **_) -> bool:
    """``answer`` maps "lambda < 1", "lambda = 1", "lambda > 1" to the limit (a number, inf allowed)."""
    import sympy as sp

    from . import tails

    if not isinstance(answer, dict):
        return False
    for key, lam in (("lambda < 1", sp.Rational(1, 3)), ("lambda = 1", 1), ("lambda > 1", 3)):
        limit = tails.gaussian_tail_limit(lam)
        try:
            got = float(answer.get(key))
        except (TypeError, ValueError):
            return False
        if not (got == math.inf if limit == sp.oo else _close(got, float(limit))):
            return False
    return True


def _outlier_worth(answer, **_) -> bool:
    """How many residual-1 points cost as much as one residual-40 point under the Gaussian."""
    return _close(answer, _outlier_ratio(), rel=0.01)


def _outlier_ratio() -> float:
    from scipy import stats

    return float(stats.norm.logpdf(40.0) / stats.norm.logpdf(1.0))


# -- tutorial 2 ---------------------------------------------------------------
def _tutorial2_tp(nu: float):
    """The TP of tutorial 2, section 2: fixed hyperparameters on the section's data."""
    from .demos import regression_data
    from .kernels import RBF
    from .processes import StudentTProcess

    X, y, _ = regression_data(n=40, magnitude=10.0, proportion=0.1, seed=0)
    return StudentTProcess(RBF(1.5, 0.5), nu=nu, noise_variance=0.5, optimizer=None).fit(X, y)


def _nu_for_factor_two(answer, **_) -> bool:
    try:
        nu = float(answer)
    except (TypeError, ValueError):
        return False
    if not nu > 2:
        return False
    return _close(_tutorial2_tp(nu).variance_scale_, 2.0, rel=1e-6)


def _factor_without_outliers(answer, **_) -> bool:
    from .demos import compute_posteriors

    side = _word(answer, "above", "below")
    factor = compute_posteriors(nu=3.0, magnitude=10.0, proportion=0.0, seed=0)["tp_scale"]
    return side == ("above" if factor > 1 else "below")


def _band_as_nu_grows(answer, **_) -> bool:
    """The fixed-hyperparameter TP of section 2: does its band get wider or narrower from nu = 3 to 30?"""
    side = _word(answer, "wider", "narrower")
    wider = _tutorial2_tp(30.0).variance_scale_ > _tutorial2_tp(3.0).variance_scale_
    return side == ("wider" if wider else "narrower")


# -- tutorial 3 ---------------------------------------------------------------
def _chessboard(answer, **_) -> bool:
    return isinstance(answer, int) and not isinstance(answer, bool) and answer == _max_unsafe()[0]


def _max_unsafe() -> tuple[int, int]:
    """The spacing rule's bound on a 10 x 10 grid, and the capacity the package guarantees."""
    from .gridworld import SafeGridWorld

    return SafeGridWorld.max_unsafe(10), SafeGridWorld.capacity(10)


def _three_moves(answer, **_) -> bool:
    """Three actions that take the agent from (0, 0) to (2, 1)."""
    from .config import ACTION_MOVES

    try:
        moves = [int(a) for a in answer]
    except (TypeError, ValueError):
        return False
    if len(moves) != 3 or not all(0 <= a < len(ACTION_MOVES) for a in moves):
        return False
    x, y = 0, 0
    for a in moves:
        dx, dy = ACTION_MOVES[a]
        x, y = min(max(x + dx, 0), 3), min(max(y + dy, 0), 3)  # the 4 x 4 world of the exercise
    return (x, y) == (2, 1)


# -- tutorial 4 ---------------------------------------------------------------
def _gp_safe_at_ten(answer, decision=None, **_) -> bool:
    """Which actions the GP's decision calls safe with sigma*^2 = 10 (``decision``: the notebook's)."""
    from .config import D
    from .sarsp import choose_action

    if decision is None:
        raise ValueError("exercise 4.1 checks against the GP's decision: check('4.1', answer, decision=gp_decision)")
    _, safe, _ = choose_action(decision.mu_cost, decision.var_cost, decision.mu_reward, decision.known_unsafe,
                               D, 10.0)
    try:
        named = sorted({int(a) for a in answer})
    except (TypeError, ValueError):
        return False
    return named == [int(a) for a in safe.nonzero()[0]]


# -- tutorial 6 ---------------------------------------------------------------
def _trapped_share(answer, results=None, **_) -> bool:
    """The share (%) of the GP's failures that ended trapped, per step with 500-row fits (``results``: the ablation)."""
    if results is None:
        raise ValueError("exercise 6.1 checks against the stored ablation: check('6.1', answer, results=ablation)")
    return _close(answer, _trapped_value(results), rel=0, abs_=1.0)


def _trapped_value(results) -> float:
    from .ablation import PRIOR_AND_FITS

    runs = results.runs()
    part = runs[(runs["setting"] == PRIOR_AND_FITS[("per step", "500 rows")]) & (runs["model"] == "GP")]
    return 100.0 * part["stuck_failures"].sum() / part["failures"].sum()


# -- tutorial 5 ---------------------------------------------------------------
def _table1_percent(answer, **_) -> bool:
    return _close(answer, _table1_value(), rel=0, abs_=0.05)


def _table1_value() -> float:
    from .metrics import symmetric_percent_difference
    from .paper import TABLE1

    first = TABLE1[(40.0, 0.2, 2)]
    return symmetric_percent_difference(first["tp"]["total_cost"], first["gp"]["total_cost"])


#: every checked exercise, by "tutorial.number"
EXERCISES: dict[str, Exercise] = {
    "1.1": Exercise(
        "the limit of the Student-t ratio f(lambda x)/f(x) for nu = 4, lambda = 2",
        _t_limit_nu4_lam2,
        "Use eq. 8: the limit is lambda**(-1 - nu).",
        "2**(-5) = 1/32: the ratio settles on lambda**(-1 - nu).",
    ),
    "1.2": Exercise(
        "the Gaussian ratio's limit for lambda < 1, lambda = 1 and lambda > 1",
        _gaussian_limits,
        "Write the ratio as exp((1 - lambda**2) x**2 / 2) and look at the sign of 1 - lambda**2; "
        "answer a dict with the keys 'lambda < 1', 'lambda = 1', 'lambda > 1' (math.inf is allowed).",
        "inf, 1 and 0: no single power of lambda fits, so the Gaussian is not regularly varying.",
    ),
    "1.3": Exercise(
        "how many residual-1 points cost as much as one residual-40 point under the Gaussian",
        _outlier_worth,
        "Divide the two costs -log f(40) and -log f(1) of the standard normal; the constant log(2 pi)/2 "
        "is part of each.",
        lambda: (f"About {_outlier_ratio():.0f}: the cost is x**2/2 + log(2 pi)/2, so the ratio is "
                 "(1600 + 1.84) / (1 + 1.84), not 1600."),
    ),
    "2.1": Exercise(
        "the nu that makes the TP's variance factor exactly 2 (section 2's data and kernel)",
        _nu_for_factor_two,
        "Solve (nu + beta - 2) / (nu + n - 2) = 2 for nu, with beta = tp.beta_ and n = 40.",
        "nu = beta - 2n + 2: as nu grows the factor falls from its value at nu = 3 towards 1, passing 2 there.",
    ),
    "2.2": Exercise(
        "without outliers, is the fitted TP's variance factor 'above' or 'below' 1?",
        _factor_without_outliers,
        "The factor exceeds 1 exactly when beta > n. Without outliers, does the fitted model explain y "
        "better or worse than it expects to?",
        "Below: the fitted model over-explains clean data (beta < n), and the TP narrows its band.",
    ),
    "2.3": Exercise(
        "section 2's TP at nu = 30 against nu = 3: is its band 'wider' or 'narrower'?",
        _band_as_nu_grows,
        "The factor (nu + beta - 2) / (nu + n - 2) tends to 1 as nu grows; is it above 1 here?",
        "Narrower: with beta > n the factor is above 1 and falls towards 1 (the GP) as nu grows.",
    ),
    "3.1": Exercise(
        "the most unsafe states a 10 x 10 grid can hold with no two 4-adjacent",
        _chessboard,
        "Think of a chessboard: no two squares of one colour share an edge.",
        lambda: (f"{_max_unsafe()[0]}, one colour of the chessboard; the package promises fewer "
                 f"({_max_unsafe()[1]}), the most it can always place and shift apart."),
    ),
    "3.2": Exercise(
        "three actions from (0, 0) to (2, 1) (RIGHT = 0, DOWN = 1, LEFT = 2, UP = 3)",
        _three_moves,
        "Two steps right and one step down, in any order; y grows downwards.",
        "Any order of RIGHT, RIGHT, DOWN reaches (2, 1).",
    ),
    "4.1": Exercise(
        "which actions the GP's decision calls safe with sigma*^2 = 10 (a list of action numbers)",
        _gp_safe_at_ten,
        "An action is safe when its cost variance is at most sigma*^2 and its predicted distance at least "
        "d = 1; read both columns of the GP's decision.",
        "Its variances now pass, and the predicted distances decide, as they do for the TP at sigma*^2 = 0.8.",
    ),
    "5.1": Exercise(
        "the formula behind Table 1's 69.8% (TP total cost 28, GP 58)",
        _table1_percent,
        "Not (TP - GP)/GP; try the difference over the two values' mean.",
        lambda: (f"|28 - 58| / ((28 + 58) / 2) x 100 = {_table1_value():.1f}%: a symmetric % difference, "
                 "not the TP-vs-GP change."),
    ),
    "6.1": Exercise(
        "the share (%) of the GP's failures that ended trapped with one prior per step and 500-row fits",
        _trapped_share,
        "Divide the trapped failures by all failures in the GP's row of 'per step, k=100, 500-row fits', "
        "times 100.",
        "Most of them: with one shared prior the GP loops on the same choice until the step limit.",
    ),
}

def is_right(exercise: str, answer, **context) -> bool:
    """Whether ``answer`` to ``exercise`` is right (silent; :func:`check` says so in words).

    Parameters
    ----------
    exercise : str
        ``"tutorial.number"``, e.g. ``"1.1"``.
    answer : object
        The student's answer; ``...`` (Ellipsis) is never right.
    **context
        Objects of the notebook some checks need (named in the exercise).
    """
    if exercise not in EXERCISES:
        raise ValueError(f"exercise must be one of {sorted(EXERCISES)}, got exercise={exercise!r}")
    return answer is not Ellipsis and bool(EXERCISES[exercise].is_right(answer, **context))


def check(exercise: str, answer, **context) -> None:
    """Say whether ``answer`` to ``exercise`` is right: with why if it is, a hint if not.

    Takes the arguments of :func:`is_right`; prints one line and returns
    nothing, so that a notebook cell shows only the verdict.
    """
    right = is_right(exercise, answer, **context)
    item = EXERCISES[exercise]
    if answer is Ellipsis:
        print(f"Exercise {exercise}: not answered yet; replace ... with your answer.")
    elif right:
        explanation = item.explanation() if callable(item.explanation) else item.explanation
        print(f"Exercise {exercise}: right. {explanation}")
    else:
        print(f"Exercise {exercise}: not yet. {item.hint}")
