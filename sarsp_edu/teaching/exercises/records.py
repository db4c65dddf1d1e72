"""Coding exercises on a run's records: Table 1's % difference (5.1), eq. 12 (6.1), Definition 4 (6.2), the backup
share at each variance threshold (6.3).

Each reference calls the package's own metrics (``sarsp_edu.experiments.metrics``);
where the equations leave a case undefined, the exercise's question says the
one rule its reference follows.
"""

from __future__ import annotations

import numpy as np

from .grading import CodingExercise, Mistake

__all__ = ["RECORD_EXERCISES"]


# -- Tutorial 5: Table 1's % difference ------------------------------------------------------------
def _symmetric_cases(rng):
    return [{"a": 28.0, "b": 58.0}, {"a": 58.0, "b": 28.0}, {"a": 5.0, "b": 5.0},
            {"a": float(rng.uniform(1, 100)), "b": float(rng.uniform(1, 100))},
            {"a": 0.0, "b": 4.0},                                                 # one total of 0
            {"a": -28.0, "b": -58.0},                                             # rewards: both negative
            {"a": -float(rng.uniform(50, 150)), "b": -float(rng.uniform(50, 150))},
            {"a": -3.0, "b": 5.0},                                                # signs differ
            {"a": 0.0, "b": 0.0}]  # last: a formula's other mistakes are named before its 0/0


def _symmetric(a, b):
    """Table 1's % difference; for negative values the mean of the sizes |a| and |b| (the exercise's rule)."""
    from ...experiments.metrics import symmetric_percent_difference

    if a >= 0 and b >= 0:  # Table 1's totals: the package's own function
        return symmetric_percent_difference(a, b)
    return 0.0 if a == b else abs(a - b) / ((abs(a) + abs(b)) / 2) * 100


# -- Tutorial 6: the task success rate and eq. 12, Definition 4 -------------------------------------
def _records_cases(rng):
    cases = [
        {"episode_cost": np.array([0, 2, 0, 1]), "episode_steps": np.array([10, 30, 20, 100]),
         "task_completed": np.array([True, True, True, False])},
        # violations but no clean success: eq. 12 divides by 0; the question's rule says 0
        {"episode_cost": np.array([1, 0, 3]), "episode_steps": np.array([12, 100, 40]),
         "task_completed": np.array([True, False, False])},
        {"episode_cost": np.array([0, 0]), "episode_steps": np.array([5, 7]), "task_completed": np.array([True, True])},
        # no violation and no success: 0 over 0, 0 by the same rule
        {"episode_cost": np.array([0, 0, 0]), "episode_steps": np.array([100, 100, 100]),
         "task_completed": np.array([False, False, False])},
        {"episode_cost": np.array([2]), "episode_steps": np.array([17]), "task_completed": np.array([True])},
    ]
    for n in (25, 250):
        done = rng.random(n) < 0.7
        cases.append({"episode_cost": rng.poisson(0.3, n), "episode_steps": rng.integers(5, 101, n),
                      "task_completed": done})
    return cases


def _tsr_and_cost_rate(episode_cost, episode_steps, task_completed):
    from ...experiments.metrics import running_metrics

    last = running_metrics(np.zeros(len(episode_cost)), episode_cost, episode_steps, task_completed).iloc[-1]
    return float(last["task_success_rate"]), float(last["cost_rate"])


def _cost_rate_over(steps_of):
    def wrong(episode_cost, episode_steps, task_completed):
        tsr = _tsr_and_cost_rate(episode_cost, episode_steps, task_completed)[0]
        total, steps = float(np.sum(episode_cost)), float(np.sum(steps_of(episode_cost, episode_steps, task_completed)))
        return tsr, (total / steps if total > 0 and steps > 0 else 0.0)
    return wrong


def _undefined_as_nan(when):
    """The right results, but NaN for the cost rate where ``when(total_cost, clean_steps)``: a mistake."""
    def wrong(episode_cost, episode_steps, task_completed):
        tsr, rate = _tsr_and_cost_rate(episode_cost, episode_steps, task_completed)
        cost, done = np.asarray(episode_cost), np.asarray(task_completed, dtype=bool)
        clean = float(np.sum(np.asarray(episode_steps)[done & (cost == 0)]))
        return tsr, (float("nan") if when(float(np.sum(cost)), clean) else rate)
    return wrong


def _summaries_cases(rng):
    def summary(reward, rate, tsr, total=None):  # a total cost ordered unlike the reward: one is not the other
        return {"mean_reward": reward, "cost_rate": rate, "task_success_rate": tsr,
                "total_cost": float(round(tsr / 4) if total is None else total)}

    cases = [
        # each branch of Definition 4 on its own against its slips: agent 2's rate at least a while agent 1's is
        # below it and agent 1 loses on reward and rate (True only for a third branch that reads agent 2's)
        {"summary_1": summary(-100, 0.01, 70), "summary_2": summary(-90, 0.02, 90), "a": 80.0},
        {"summary_1": summary(-100, 0.01, 85, 30), "summary_2": summary(-90, 0.02, 90, 40), "a": 100.0},  # total
        {"summary_1": summary(-80, 0.01, 85, 40), "summary_2": summary(-90, 0.02, 90, 30), "a": 100.0},  # reward
        # no success at all: a lower cost rate alone is not enough (and 0 is below a / 100 too)
        {"summary_1": summary(-100, 0.01, 0.0, 5), "summary_2": summary(-90, 0.02, 90, 30), "a": 100.0},
        # no success, yet preferred: a lower cost rate and a better reward (a TSR of 0 does not block the first branch)
        {"summary_1": summary(-80, 0.01, 0.0, 5), "summary_2": summary(-90, 0.02, 90, 30), "a": 100.0},
        {"summary_1": summary(-100, 0.01, 80), "summary_2": summary(-90, 0.02, 90), "a": 100.0},  # no branch
        {"summary_1": summary(-80, 0.01, 70), "summary_2": summary(-90, 0.02, 90), "a": 100.0},   # reward
        {"summary_1": summary(-100, 0.01, 95), "summary_2": summary(-90, 0.02, 90), "a": 100.0},  # TSR
        {"summary_1": summary(-100, 0.01, 85), "summary_2": summary(-90, 0.02, 90), "a": 80.0},   # TSR >= a
        {"summary_1": summary(-100, 0.01, 80), "summary_2": summary(-90, 0.02, 90), "a": 80.0},   # TSR = a exactly
        {"summary_1": summary(-80, 0.02, 95), "summary_2": summary(-90, 0.02, 90), "a": 100.0},   # equal p_c
        {"summary_1": summary(-80, 0.01, 95), "summary_2": summary(-90, 0.005, 90), "a": 100.0},  # higher p_c
        {"summary_1": summary(-90, 0.01, 80), "summary_2": summary(-90, 0.02, 90), "a": 100.0},   # equal reward
        {"summary_1": summary(-100, 0.01, 90), "summary_2": summary(-90, 0.02, 90), "a": 100.0},  # equal TSR
        {"summary_1": summary(-100, 0.01, 40), "summary_2": summary(-90, 0.02, 60), "a": 1.0},    # the lowest a
        {"summary_1": summary(-80, 0.01, 95), "summary_2": summary(-90, 0.02, 90), "a": 100.0},   # every branch
        # a hair apart is not equal: a cost rate 1e-12 lower is lower, a rate or reward 1e-12 below is below
        {"summary_1": summary(-90 - 1e-12, 0.01, 80), "summary_2": summary(-90, 0.01 + 1e-12, 90), "a": 100.0},
        {"summary_1": summary(-100, 0.01, 90 - 1e-12), "summary_2": summary(-90, 0.02, 90), "a": 90.0},
        {"summary_1": summary(-80, 0.01, 80), "summary_2": summary(-90, 0.01 + 1e-12, 90), "a": 100.0},
        # Definition 4 compares rewards as they are, whatever their sign: a larger positive reward is better
        {"summary_1": summary(10, 0.01, 80), "summary_2": summary(5, 0.02, 90), "a": 100.0},
        {"summary_1": summary(5, 0.01, 80), "summary_2": summary(-10, 0.02, 90), "a": 100.0},
    ]
    for _ in range(6):
        cases.append({"summary_1": summary(-rng.uniform(50, 150), rng.uniform(0.001, 0.03), rng.uniform(50, 100)),
                      "summary_2": summary(-rng.uniform(50, 150), rng.uniform(0.001, 0.03), rng.uniform(50, 100)),
                      "a": float(rng.uniform(60, 100))})
    return cases


def _prefers(summary_1, summary_2, a):
    from ...experiments.metrics import prefers

    return bool(prefers(summary_1, summary_2, a))


def _prefers_with(condition):
    def wrong(summary_1, summary_2, a):
        return bool(condition(summary_1, summary_2, a))
    return wrong


# -- Tutorial 6: the backup share at each variance threshold -----------------------------------------
def _decision_cases(rng):
    thresholds = np.array([0.1, 0.3, 0.8, 2.0, 5.0, 10.0])
    cases = [
        # one decision: action 1 passes from 0.8 on (its variance is the threshold exactly), action 0 never (d)
        {"mu_cost": np.array([[0.5, 1.0, 3.0, 2.0]]), "var_cost": np.array([[0.05, 0.8, 6.0, 12.0]]), "d": 1.0,
         "thresholds": thresholds},
        # known-unsafe actions (distance -inf, variance +inf) are never safe
        {"mu_cost": np.array([[-np.inf, 2.0, -np.inf, 2.0], [1.5, -np.inf, 2.5, 0.9]]),
         "var_cost": np.array([[np.inf, 4.0, np.inf, 0.3], [2.0, np.inf, 0.2, 0.01]]), "d": 1.0,
         "thresholds": np.array([0.1, 0.3, 2.0])},
        # every variance above every threshold: the backup decides everything
        {"mu_cost": np.full((3, 4), 5.0), "var_cost": np.full((3, 4), 50.0), "d": 1.0, "thresholds": thresholds},
        # distances exactly d pass
        {"mu_cost": np.array([[2.0, 2.0, 1.0, 1.0], [1.99, 1.99, 1.99, 1.99]]),
         "var_cost": np.full((2, 4), 0.5), "d": 2.0, "thresholds": np.array([0.5, 1.0])},
        # a hair past each knife edge does not pass (exact comparisons: no tolerance, no rounding)
        {"mu_cost": np.array([[1.0 - 1e-7, 0.5, 0.2, 0.9996], [2.0, 2.0, 2.0, 2.0]]),
         "var_cost": np.array([[0.1, 0.1, 0.1, 0.1], [0.8 + 1e-7, 0.8004, 0.9, 0.95]]), "d": 1.0,
         "thresholds": np.array([0.8, 2.0])},
        {"mu_cost": np.array([[1.0 - 1e-12, 0.5, 0.2, 0.5], [2.0, 2.0, 2.0, 2.0]]),
         "var_cost": np.array([[0.1, 0.1, 0.1, 0.1], [0.8 + 1e-12, 0.9, 0.9, 0.95]]), "d": 1.0,
         "thresholds": np.array([0.8, 2.0])},
        {"mu_cost": np.array([[np.nextafter(1.0, 0.0), 0.5, 0.2, 0.5], [2.0, 2.0, 2.0, 2.0]]),
         "var_cost": np.array([[0.1, 0.1, 0.1, 0.1], [np.nextafter(0.8, 1.0), 0.9, 0.9, 0.95]]), "d": 1.0,
         "thresholds": np.array([0.8, 2.0])},  # one unit in the last place past each edge
    ]
    # thresholds in no order: one share per threshold as given (not sorted, and the caller's array left as it is)
    cases.append({"mu_cost": np.array([[2.0, 2.0, 0.5, 0.5], [2.0, 0.5, 0.5, 0.5]]),
                  "var_cost": np.array([[1.5, 6.0, 0.1, 0.1], [0.2, 0.1, 0.1, 0.1]]), "d": 1.0,
                  "thresholds": np.array([10.0, 0.1, 2.0, 0.3])})
    for n in (7, 250):
        mu = rng.integers(-1, 5, (n, 4)).astype(float) + np.where(rng.random((n, 4)) < 0.5, 0.0, rng.random((n, 4)))
        var = np.exp(rng.normal(0.0, 1.5, (n, 4)))
        var[rng.random((n, 4)) < 0.1] = 0.8
        cases.append({"mu_cost": mu, "var_cost": var, "d": float(rng.choice([1.0, 0.5])), "thresholds": thresholds})
    return cases


def _backup_shares(mu_cost, var_cost, d, thresholds):
    from ...agent.decision import safe_actions

    mu_cost, var_cost = np.atleast_2d(mu_cost), np.atleast_2d(var_cost)
    none_known = np.zeros(mu_cost.shape[1], dtype=bool)
    return np.array([100.0 * np.mean([not safe_actions(mu, var, none_known, d, threshold).any()
                                      for mu, var in zip(mu_cost, var_cost)]) for threshold in thresholds])


def _shares_where(safe_of, share_of=lambda safe: ~safe.any(axis=1), scale=100.0):
    """The shares computed with another safety test or another count: a mistake."""
    def wrong(mu_cost, var_cost, d, thresholds):
        mu_cost, var_cost = np.atleast_2d(mu_cost), np.atleast_2d(var_cost)
        return np.array([scale * np.mean(share_of(safe_of(mu_cost, var_cost, d, t))) for t in thresholds])
    return wrong


_SAFE = lambda mu, var, d, t: (var <= t) & (mu >= d)  # noqa: E731 (the rule, for the mistakes to vary)


RECORD_EXERCISES = {
    "5.1": CodingExercise(
        question="Table 1's '% difference' of a and b: |a - b| over the mean of their sizes, (|a| + |b|) / 2, "
                 "in %, 0 when a = b (for Table 1's totals, never negative, the mean of a and b itself; for "
                 "negative values such as rewards the sizes keep it from 0 to 200)",
        signature="symmetric_percent_difference(a, b) -> float",
        reference=_symmetric,
        cases=_symmetric_cases,
        mistakes=(
            Mistake(lambda a, b: (a - b) / abs(b) * 100, "That is the change of a relative to b (Table 2's "
                                                        "convention); Table 1's has no reference model."),
            Mistake(lambda a, b: (a - b) / ((abs(a) + abs(b)) / 2) * 100,
                    "Your result is negative where a lies below b: a % difference has no direction."),
            Mistake(lambda a, b: (a - b) / ((a + b) / 2) * 100,
                    "Your result is negative where a lies below b: a % difference has no direction."),
            Mistake(lambda a, b: abs(a - b) / ((a + b) / 2) * 100,
                    "Right for Table 1's totals, not for negative values (rewards): read the question's rule for "
                    "them; a % difference is never negative."),
            Mistake(lambda a, b: abs(a - b) / abs((a + b) / 2) * 100,
                    "Right while a and b share a sign; where their signs differ, read the question's rule: "
                    "(a + b) / 2 can be near 0 there."),
            *(Mistake(lambda a, b, size=size: abs(a - b) / max(size(a), size(b)) * 100,
                      "Your denominator is the larger of the two: for 28 against 58 it gives 51.7, where Table 1 "
                      "prints 69.8%.") for size in (float, abs)),
            *(Mistake(lambda a, b, size=size: abs(a - b) / (size(a) + size(b)) * 100,
                      "Your denominator is the two added up: for 28 against 58 it gives 34.9, where Table 1 prints "
                      "69.8%.") for size in (float, abs)),
            *(Mistake(lambda a, b, size=size: abs(a - b) / ((size(a) + size(b)) / 2),
                      "Your values are those of a fraction; Table 1 prints a percentage.") for size in (float, abs)),
        ),
        hint="Redo the case named above by hand: 28 against 58 gives Table 1's 69.8% (rounded), a = b gives 0 "
             "(0 against 0 included); check the numerator, the denominator and the factor 100.",
        explanation="For the paper's (40, 0.2, 2) row, 28 against 58 gives the 69.8% it prints.",
    ),
    "6.1": CodingExercise(
        question="the task success rate (%) and the cost rate of eq. 12, the violations over the steps of the "
                 "successful episodes without a violation; the cost rate is 0 where either of the two is 0, as "
                 "the package's running_metrics keeps it (the tables print the case of violations without a "
                 "clean success as n/a)",
        signature="tsr_and_cost_rate(episode_cost, episode_steps, task_completed) -> (tsr, cost_rate)",
        reference=_tsr_and_cost_rate,
        cases=_records_cases,
        mistakes=(
            Mistake(lambda episode_cost, episode_steps, task_completed: (
                _tsr_and_cost_rate(episode_cost, episode_steps, task_completed)[0] / 100,
                _tsr_and_cost_rate(episode_cost, episode_steps, task_completed)[1]),
                "The success rate is in %, as the paper prints it."),
            Mistake(lambda episode_cost, episode_steps, task_completed: (
                float(np.sum(task_completed)), _tsr_and_cost_rate(episode_cost, episode_steps, task_completed)[1]),
                "The cost rate is right; the success rate is a share of the episodes, in %, not their count."),
            Mistake(_cost_rate_over(lambda c, s, done: s), "Eq. 12 divides by the steps of the successful "
                                                           "episodes without a violation, not of all episodes."),
            Mistake(_cost_rate_over(lambda c, s, done: np.where(done, s, 0)),
                    "Eq. 12 counts only the successful episodes that had no violation."),
            Mistake(_undefined_as_nan(lambda total, clean: total > 0 and clean == 0),
                    "Where eq. 12 divides by zero, the question asks for 0 (the package's records keep 0; only "
                    "the tables print n/a)."),
            Mistake(_undefined_as_nan(lambda total, clean: clean == 0),
                    "Where eq. 12 divides by zero, the question asks for 0 (the package's records keep 0; only "
                    "the tables print n/a)."),
        ),
        hint="Redo the case above by hand: which episodes succeeded without a violation, and how many steps "
             "do they hold?",
        explanation="A trapped agent that never reaches the goal has few violations and a cost rate of 0: "
                    "low total cost alone can reward failure, which is why Definition 4 also asks for success.",
    ),
    "6.2": CodingExercise(
        question="Definition 4: agent 1 is preferred to agent 2 (success rates and a in %)",
        signature="prefers(summary_1, summary_2, a) -> bool",
        reference=_prefers,
        cases=_summaries_cases,
        examples={"a": 100.0},
        mistakes=(
            Mistake(_prefers_with(lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"] and (
                s1["mean_reward"] >= s2["mean_reward"] and s1["task_success_rate"] >= s2["task_success_rate"])),
                "Agent 1 needs a lower cost rate and any one of the three: or, not and."),
            Mistake(_prefers_with(lambda s1, s2, a: s1["cost_rate"] <= s2["cost_rate"] and (
                s1["mean_reward"] >= s2["mean_reward"] or s1["task_success_rate"] >= s2["task_success_rate"]
                or s1["task_success_rate"] >= a)), "The cost rate must be strictly lower."),
            Mistake(_prefers_with(lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"] and (
                s1["mean_reward"] >= s2["mean_reward"] or s1["task_success_rate"] >= s2["task_success_rate"])),
                "Your answer never lets a success rate of at least a decide on its own: is the third branch "
                "missing, a fixed at 100, or the rate compared as a fraction where a is in %?"),
            Mistake(_prefers_with(lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"]),
                    "A lower cost rate is not enough on its own: Definition 4 also asks one of three things of "
                    "agent 1."),
            Mistake(_prefers_with(lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"] and (
                s1["mean_reward"] >= s2["mean_reward"] or s1["task_success_rate"] >= s2["task_success_rate"]
                or s1["task_success_rate"] >= a / 100)),
                "The success rate and a are both in %: compare them as they are."),
            *(Mistake(_prefers_with(lambda s1, s2, a, third=third: s1["cost_rate"] < s2["cost_rate"] and (
                s1["mean_reward"] >= s2["mean_reward"] or s1["task_success_rate"] >= s2["task_success_rate"]
                or third(s1["task_success_rate"], s2["task_success_rate"], a))),
                "The third branch asks agent 1's own success rate to reach a: agent 2's rate does not make agent 1 "
                "preferred.") for third in (lambda t1, t2, a: t2 >= a, lambda t1, t2, a: max(t1, t2) >= a)),
            *(Mistake(_prefers_with(lambda s1, s2, a, better=better: s1["cost_rate"] < s2["cost_rate"] and (
                better(s1["total_cost"], s2["total_cost"]) or s1["task_success_rate"] >= s2["task_success_rate"]
                or s1["task_success_rate"] >= a)),
                "The first branch compares the mean rewards (mean_reward), not the total costs.")
              for better in (lambda c1, c2: c1 <= c2, lambda c1, c2: c1 >= c2)),
            Mistake(_prefers_with(lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"] and (
                s1["mean_reward"] >= s2["mean_reward"] or s1["task_success_rate"] >= s2["task_success_rate"]
                or s1["task_success_rate"] > a)), "A success rate equal to a is enough: TSR >= a."),
            Mistake(_prefers_with(lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"] and (
                s1["mean_reward"] > s2["mean_reward"] or s1["task_success_rate"] > s2["task_success_rate"]
                or s1["task_success_rate"] >= a)), "A reward or a success rate equal to agent 2's is enough: >=."),
            Mistake(_prefers_with(lambda s1, s2, a: s1["cost_rate"] > s2["cost_rate"] and (
                s1["mean_reward"] >= s2["mean_reward"] or s1["task_success_rate"] >= s2["task_success_rate"]
                or s1["task_success_rate"] >= a)), "A lower cost rate is better."),
        ),
        hint="Redo the case above by hand, one condition of Definition 4 at a time.",
        explanation="It matches sarsp_edu.prefers; with a = 100 the third branch needs a perfect success rate.",
    ),
    "6.3": CodingExercise(
        question="the share (%) of decisions the backup rule takes at each variance threshold sigma*^2 of "
                 "thresholds: a decision (a row; its four actions the columns, as the agent saw them, known-unsafe "
                 "ones at distance -inf and variance +inf) goes to the backup when no action is safe, that is "
                 "when no action has a variance at most sigma*^2 and a predicted distance at least d",
        signature="backup_shares(mu_cost, var_cost, d, thresholds) -> ndarray, one share (%) per threshold",
        reference=_backup_shares,
        cases=_decision_cases,
        examples={"d": 1.0},
        mistakes=(
            Mistake(_shares_where(lambda mu, var, d, t: (var < t) & (mu >= d)),
                    "A variance equal to sigma*^2 is safe enough: at most, not below."),
            Mistake(_shares_where(lambda mu, var, d, t: (var <= t) & (mu > d)),
                    "A predicted distance equal to d is safe enough: at least, not above."),
            Mistake(_shares_where(lambda mu, var, d, t: var <= t),
                    "A safe action also needs a predicted distance of at least d."),
            Mistake(_shares_where(lambda mu, var, d, t: mu >= d),
                    "A safe action also needs a variance of at most sigma*^2."),
            Mistake(_shares_where(_SAFE, share_of=lambda safe: ~safe),
                    "Count decisions, not actions: a decision goes to the backup when none of its four is safe."),
            Mistake(_shares_where(_SAFE, share_of=lambda safe: ~safe.all(axis=1)),
                    "One safe action is enough to keep a decision from the backup."),
            Mistake(_shares_where(_SAFE, share_of=lambda safe: safe.any(axis=1)),
                    "That is the share of decisions with a safe action; the question asks for the others."),
            Mistake(_shares_where(_SAFE, scale=1.0), "The share is in %."),
        ),
        hint="Redo the first case above by hand, one threshold at a time: which actions pass both tests?",
        explanation="Where every variance a model predicts lies above sigma*^2, the backup takes every decision "
                    "whatever the model predicts: the threshold, set against the model's fitted noise, decides.",
    ),
}
