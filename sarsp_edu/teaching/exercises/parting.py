"""Where the student's agent and the package's part, and which of the student's functions made them part.

The capstone (:mod:`~sarsp_edu.teaching.exercises.capstone`) steps the two agents together; at a step that
differs, these say what differs (a prediction, the safe set, the action, the corrective test) and call each of
the student's functions that step called, and the package's, on the same inputs, to name the first that
differs beyond the rounding its inputs allow.
"""

from __future__ import annotations

import numpy as np

from .grading import known_mistake, raised, same
from .running import TimedOut, call_copies
from .wording import describe, parts as result_parts, said, several

__all__ = ["PART_ARGUMENTS", "PART_FUNCTIONS"]

#: the name the tutorials give each part's function
PART_FUNCTIONS = {"kernel": "rbf", "posterior": "gp_posterior", "tp_factor": "tp_variance_factor",
                  "safe_set": "safe_actions", "choose": "choose", "corrective": "corrects"}
#: each part's arguments, in order
PART_ARGUMENTS = {"kernel": ("X", "Y", "amplitude", "length_scale"),
                  "posterior": ("K", "K_star", "k_star_star", "y", "noise_variance"),
                  "tp_factor": ("K", "y", "noise_variance", "nu"),
                  "safe_set": ("mu_cost", "var_cost", "known_unsafe", "d", "variance_threshold"),
                  "choose": ("mu_cost", "var_cost", "mu_reward", "known_unsafe", "d", "variance_threshold"),
                  "corrective": ("mu_cost", "var_cost", "action", "d", "was_backup")}
_LABELS = {"mu_cost": "predicted distances to danger", "var_cost": "cost variances", "mu_reward": "predicted rewards",
           "var_reward": "reward variances"}


def _named(name: str) -> str:
    from ...agent.parts import EXERCISE_OF

    return f"your {PART_FUNCTIONS[name]} (exercise {EXERCISE_OF[name]})"


def _first_difference(got, expected) -> str:
    """Where ``got`` first differs from ``expected``: 'entry [2, 3]: yours 0.41, the package's 0.2'."""
    many = several(expected)
    got_parts, expected_parts = result_parts(got, many), result_parts(expected, many)
    if len(got_parts) != len(expected_parts):
        return f"yours returns {len(got_parts)} results, the package's {len(expected_parts)}"
    for number, (g, e) in enumerate(zip(got_parts, expected_parts), start=1):
        if same(g, e):
            continue
        which = f"result number {number}" if len(expected_parts) > 1 else "the result"
        if g.shape != e.shape:
            return f"{which} has shape {g.shape} where the package's has {e.shape}"
        if g.ndim == 0:
            yours = said(g.item()) or repr(g.item())
            return f"{which}: yours {yours}, the package's {said(e.item())}"
        try:
            differs = ~np.array([same(a, b) for a, b in zip(g.reshape(-1), e.reshape(-1))])
            index = tuple(int(i) for i in np.unravel_index(int(np.argmax(differs)), e.shape))
        except (TypeError, ValueError):
            return f"{which} cannot be read as numbers"
        at = f"[{', '.join(map(str, index))}]"
        return f"{which}, entry {at}: yours {said(g[index].item())}, the package's {said(e[index].item())}"
    return "the results differ"


def _rounding_allowed(name: str, case: dict, expected) -> float:
    """How far a right result of part ``name`` may lie from the package's on ``case`` by rounding alone: 100
    machine epsilons times the condition number of the training covariance ``K + noise I`` (where the part
    solves with it) times the result's scale before the solve cancels digits (``k**`` for a variance, ``|y|``
    for a mean); 0 for a part that solves nothing (a kernel, a rule)."""
    if name not in ("posterior", "tp_factor"):
        return 0.0
    try:
        K = np.asarray(case["K"], dtype=float)
        condition = float(np.linalg.cond(K + float(case["noise_variance"]) * np.eye(len(K))))
        y_scale = float(np.max(np.abs(case["y"]), initial=1.0))
        if name == "posterior":
            scale = max(y_scale, float(np.max(np.abs(case["k_star_star"]), initial=1.0)))
        else:
            scale = max(abs(float(expected)), 1.0)
    except (KeyError, TypeError, ValueError, np.linalg.LinAlgError):
        return 0.0
    return 100.0 * np.finfo(float).eps * condition * scale if np.isfinite(condition) else 0.0


def _agrees(name: str, case: dict, result, expected) -> bool:
    """Whether a part's result is the package's, to the exercises' tolerance or to the rounding its inputs'
    conditioning allows (:func:`_rounding_allowed`)."""
    if same(result, expected):
        return True
    allowed = _rounding_allowed(name, case, expected)
    if allowed <= 0:
        return False
    try:
        mine = result_parts(result, several(expected))
        theirs = result_parts(expected, several(expected))
        return len(mine) == len(theirs) and all(
            m.shape == t.shape and np.all(np.isfinite(m)) and np.allclose(m, t, rtol=0.0, atol=allowed)
            for m, t in zip(mine, theirs))
    except (TypeError, ValueError):
        return False


def _culprit(calls: list, parts=None) -> str | None:
    """The first of the step's calls whose result differs from the package's on the same inputs (beyond the
    rounding its inputs allow), in words; with the student's ``parts``, the diagnosis is its exercise's check's
    (every input of the exercise, where one input may fit two mistakes)."""
    from ...agent.parts import EXERCISE_OF, DecisionParts
    from .coding import CODING
    from .grading import grade

    for name, case, result in calls:
        try:
            expected = call_copies(getattr(DecisionParts, name), case)[0]
        except Exception:  # the package's function cannot take inputs the student's earlier functions made
            continue
        if _agrees(name, case, result, expected):
            continue
        exercise = EXERCISE_OF[name]
        checked = None if parts is None else grade(exercise, CODING[exercise], getattr(parts, name))
        if checked is not None and not checked[0]:  # wrong on its exercise's inputs too: that check's diagnosis
            advice = f'Its own check, check("{exercise}", {PART_FUNCTIONS[name]}), says: {checked[1]}'
        elif checked is not None:  # right there: this input is one its exercise's inputs miss
            advice = (f'It passes its own check, check("{exercise}", {PART_FUNCTIONS[name]}): this input is one '
                      "that check's inputs miss.")
        else:
            mistake = known_mistake(CODING[exercise], [case], [result])
            advice = mistake or f'Run check("{exercise}", {PART_FUNCTIONS[name]}) for its own check.'
        return (f"{_named(name)[0].upper()}{_named(name)[1:]} gives other values than the package's on the inputs "
                f"this step gave it ({describe(case)}): {_first_difference(result, expected)}. {advice}")
    return None


def _low_precision(calls: list) -> str | None:
    """The first of the step's calls that returned numbers of less than double precision (float32), in words."""
    for name, _, result in calls:
        kinds = {part.dtype for part in result_parts(result, isinstance(result, (tuple, list)))}
        if any(kind.kind == "f" and kind.itemsize < 8 for kind in kinds):
            return (f"{_named(name)[0].upper()}{_named(name)[1:]} returns single-precision numbers (float32): "
                    "close enough for its own exercise, but the agent solves with matrices near singular, which "
                    "magnify the rounding. Compute in float64, numpy's default.")
    return None


def _where(record, experiment, decisions: int) -> str:
    goal = tuple(int(v) for v in experiment.env.goal)
    return (f"Episode {record.episode}, step {record.t} (decision {decisions} of the run), the agent at "
            f"{tuple(int(v) for v in record.position)} with its goal at {goal}")


def _action_words(decision) -> str:
    from ...world.gridworld import ACTION_NAMES

    safe = ", ".join(ACTION_NAMES[a].upper() for a in np.flatnonzero(decision.safe)) or "none"
    rule = "the backup" if decision.backup else "a safe action"
    return f"{ACTION_NAMES[decision.action].upper()} ({rule}; safe: {safe})"


def _difference(mine, theirs, rounding_only: bool = False) -> str | None:
    """What differs between the package's step record and the student's, in words, or None.

    With ``rounding_only`` (every part's result within the rounding its inputs allow), predictions that differ
    are not a difference: what a decision uses (the safe set, the action, the backup, the corrective test) is
    compared alone.
    """
    ours, yours = mine.decision, theirs.decision
    for field, label in _LABELS.items():
        if not rounding_only and not same(getattr(yours, field), getattr(ours, field)):
            shown_yours, shown_ours = _apart(getattr(yours, field), getattr(ours, field))
            return f"the {label} of the four actions differ: yours {shown_yours}, the package's {shown_ours}"
    if (yours.action != ours.action or yours.backup != ours.backup
            or not np.array_equal(yours.safe, ours.safe)):
        return f"your agent took {_action_words(yours)}, the package's {_action_words(ours)}"
    if theirs.outcome.corrected != mine.outcome.corrected:
        return (f"after the violation, your agent {'corrected' if theirs.outcome.corrected else 'did not correct'} "
                f"the cost model's data, the package's {'did' if mine.outcome.corrected else 'did not'}")
    return None


def _apart(yours, ours) -> tuple:
    """Both arrays in words, to 4 significant digits or as many more as it takes for them to read apart."""
    yours, ours = np.ravel(np.asarray(yours, dtype=float)), np.ravel(np.asarray(ours, dtype=float))
    for digits in range(4, 18):
        shown = tuple("[" + ", ".join(f"{v:.{digits}g}" for v in values) + "]" for values in (yours, ours))
        if shown[0] != shown[1]:
            return shown
    return shown


def _failed(failed, where: str) -> str:
    """A student's function that raised or ran out of time inside the agent, in words."""
    from ...agent.parts import EXERCISE_OF
    from .coding import CODING

    error = failed.error
    if isinstance(error, TimedOut):
        return f"{where}: {_named(failed.name)} {error} on {describe(failed.case)}: is there a loop that never ends?"
    advice = ""
    if isinstance(error, np.linalg.LinAlgError):
        advice = " " + CODING[EXERCISE_OF[failed.name]].on_linalg_error
    return f"{where}: {_named(failed.name)} raised {raised(error)} on {describe(failed.case)}.{advice}".rstrip()
