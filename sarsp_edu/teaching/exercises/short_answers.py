"""The tutorials' short-answer exercises: predict, then run.

Where predicting a value or a direction before computing it is the point,
the student answers with a value; each check computes its own answer from
the package (sympy limits, fitted models, the gridworld, Algorithm 1's rule),
so the checks stay right when the package changes.  An answer is read first
(:mod:`.answers`: any numeric type, numbers as text, the usual spellings of
a direction); one that cannot be read is told the accepted forms, never the
hint meant for a wrong idea.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from .action_lists import read_actions
from .counts import read_count
from .limits import read_limits
from .sides import read_band, read_side

__all__ = ["Exercise", "LOOKUPS"]


@dataclass(frozen=True)
class Exercise:
    """One checked exercise.

    Attributes
    ----------
    question : str
        What is asked, in one line (the notebook asks it in full).
    is_right : callable
        ``is_right(value, **context) -> bool`` on the answer as ``read`` gives
        it, computed from the package (``context``: objects of the notebook
        the check needs, if any).
    hint : str
        Shown with a wrong answer (one that could be read).
    explanation : str or callable
        Shown with a right one; a callable computes it (its numbers come
        from the package, never typed in).
    read : callable
        ``read(answer) -> value``: the answer in one canonical form, from the
        spellings a student would use; raises :class:`~.answers.Unreadable`.
    accepted : str
        The accepted forms, listed with an answer that could not be read.
    """

    question: str
    is_right: Callable[..., bool]
    hint: str
    explanation: str | Callable[[], str]
    read: Callable = lambda answer: answer
    accepted: str = ""


# -- tutorial 1 ---------------------------------------------------------------

def _gaussian_limits(answer, **_) -> bool:
    """``answer`` (read) maps '<1', '=1', '>1' to the limit (a number, inf allowed)."""
    import sympy as sp

    from ...models import tails

    for side, lam in (("<1", sp.Rational(1, 3)), ("=1", 1), (">1", 3)):
        limit, got = tails.gaussian_tail_limit(lam), answer[side]
        # the limits are exact numbers (infinity, 1, 0): a guess of 1.01 or 1e-300 is not one of them
        if not (got == math.inf if limit == sp.oo else got == float(limit)):
            return False
    return True


# -- tutorial 2 ---------------------------------------------------------------
#: the degrees of freedom of Tutorial 2, section 3's fit (exercise 2.5)
_SECTION_3_NU = 3.0


def _factor_without_outliers(answer, **_) -> bool:
    from ..demos import compute_posteriors

    factor = compute_posteriors(nu=_SECTION_3_NU, magnitude=10.0, proportion=0.0, seed=0)["tp_scale"]
    return answer == ("above" if factor > 1 else "below")


def _factor_without_outliers_explained() -> str:
    nu = _SECTION_3_NU
    return (f"Below. The cell below fits it and prints beta_ / n and variance_scale_: clean targets lie "
            f"within the scale the priors hold, so the fit settles near the likelihood's own beta = n (nu - 2) / nu "
            f"(beta / n = {(nu - 2) / nu:.2f} at nu = {nu:g}), below n; only data spread far beyond that scale, "
            f"such as the outliers, push the factor above 1.")


def _band_as_nu_grows(answer, **_) -> bool:
    """The fixed-hyperparameter TP of section 2: does its band get wider or narrower from nu = 3 to 30?"""
    from ..demos import section2_factor

    wider = section2_factor(30.0) > section2_factor(3.0)
    return answer == ("wider" if wider else "narrower")


# -- tutorial 3 ---------------------------------------------------------------
def _chessboard(answer, **_) -> bool:
    return answer == _max_unsafe()[0]


def _max_unsafe() -> tuple[int, int]:
    """The spacing rule's bound on a 10 x 10 grid, and the capacity the package guarantees."""
    from ...world.gridworld import SafeGridWorld

    return SafeGridWorld.max_unsafe(10), SafeGridWorld.capacity(10)


# -- tutorial 4 ---------------------------------------------------------------
def _gp_safe_at_ten(answer, decision=None, **_) -> bool:
    """Which actions the GP's decision calls safe with sigma*^2 = 10 (``decision``: the notebook's)."""
    from ...agent.sarsp import choose_action
    from ...config import D

    if decision is None:
        raise ValueError("exercise 4.4 checks against the GP's decision: check('4.4', answer, decision=gp_decision)")
    lacking = [name for name in ("mu_cost", "var_cost", "known_unsafe") if not hasattr(decision, name)]
    if lacking:
        raise ValueError(f"decision must be section 3b's gp_decision (it has mu_cost, var_cost and known_unsafe), got "
                         f"a {type(decision).__name__} without {', '.join(lacking)}")
    rewards = getattr(decision, "mu_reward", None)  # the safe set does not use them: a decision may leave them out
    _, safe, _ = choose_action(decision.mu_cost, decision.var_cost,
                               [0.0] * len(decision.mu_cost) if rewards is None else rewards, decision.known_unsafe,
                               D, 10.0)
    return answer == [int(a) for a in safe.nonzero()[0]]


#: the short-answer exercises, by "tutorial.number" (the coding ones: models.py, agent.py, evidence.py, records.py)
LOOKUPS: dict[str, Exercise] = {
    "1.4": Exercise(
        "predict, then run: the Gaussian ratio's limit for lambda < 1, lambda = 1 and lambda > 1",
        _gaussian_limits,
        "Write out the ratio of the density at lambda x to the density at x, simplify its exponent, and ask how "
        "the exponent's sign depends on lambda as x grows.",
        "inf, 1 and 0: no single power of lambda fits, so the Gaussian is not regularly varying.",
        read=read_limits,
        accepted="a dict with the keys 'lambda < 1', 'lambda = 1' and 'lambda > 1' (also spelt 'lambda<1', "
                 "'λ < 1' ...), each a number: 0.5, '2', math.inf or 'infinity'",
    ),
    "2.5": Exercise(
        "predict, then compute: without outliers, is the fitted TP's variance factor 'above' or 'below' 1?",
        _factor_without_outliers,
        "Compute the factor of section 3's fit on clean targets from the model's own numbers (it holds beta_, nu_ "
        "and its rows) before you answer again.",
        _factor_without_outliers_explained,
        read=read_side,
        accepted="'above' or 'below' (also 'Above.', 'above 1', 'greater', '>', 'it goes up' or 'below 1', "
                 "'smaller', '<', 'it goes down', or a number on that side of 1)",
    ),
    "2.6": Exercise(
        "predict, then run: section 2's TP at nu = 30 against nu = 3: is its band 'wider' or 'narrower'?",
        _band_as_nu_grows,
        "Compute the factor (nu + beta - 2) / (nu + n - 2) of section 2's fit at nu = 3 and at nu = 30 (beta_ and "
        "the rows are on the model): which way does the band move between them?",
        "Narrower: with beta > n the factor is above 1 and falls towards 1 (the GP) as nu grows.",
        read=read_band,
        accepted="'wider' or 'narrower' (also 'Wider.', 'larger', '>', 'it grows' or 'Narrower.', 'smaller', '<', "
                 "'it decreases', 'less than before')",
    ),
    "3.4": Exercise(
        "predict, then run: the most unsafe states a 10 x 10 grid can hold with no two 4-adjacent",
        _chessboard,
        "Mark cells by hand on small grids first (2 x 2, 3 x 3, 4 x 4), as many as you can with no two sharing "
        "an edge: what pattern do the counts follow?",
        lambda: (f"{_max_unsafe()[0]}, one colour of the chessboard. The package accepts far fewer "
                 f"({_max_unsafe()[1]}): the question below asks why."),
        read=read_count,
        accepted="a whole number: 12, 12.0, '12' or a numpy integer",
    ),
    "4.4": Exercise(
        "predict, then compute: which actions the GP's decision calls safe with sigma*^2 = 10 "
        "(a list of action numbers)",
        _gp_safe_at_ten,
        "An action is safe when it is not known unsafe, its cost variance is at most sigma*^2 and its predicted "
        "distance at least d = 1: which of these does raising sigma*^2 leave to decide, for each action?",
        "A variance up to 10 now passes (for the notebook's GP decision, every one), so the predicted distances "
        "decide, as they do for the TP at sigma*^2 = 0.8.",
        read=read_actions,
        accepted="a list of action numbers such as [0, 2] (RIGHT = 0, DOWN = 1, LEFT = 2, UP = 3; [] for none), "
                 "a set, an array, a boolean array of the four actions, or text such as '0, 2'",
    ),
}
