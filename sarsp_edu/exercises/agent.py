"""Coding exercises of Tutorials 3 to 6: the world, the offline data, Algorithm 1's rules, the metrics.

Each reference calls the package's own implementation (the buffer, the
decision rule, the running metrics, Definition 4), so an exercise stays right
when the package changes.
"""

from __future__ import annotations

import numpy as np

from .grading import CodingExercise, Mistake

__all__ = ["AGENT_EXERCISES"]


# -- Tutorial 3: the offline buffer's duplicate cap, the cost signal, a move -----------------------
def _cap_cases(rng):
    cases = []
    for n, cap in ((1, 1), (12, 1), (40, 2), (60, 12)):
        X = rng.integers(0, 3, (n, 2)).astype(float)  # few distinct inputs: many copies
        cases.append({"X": X, "y": rng.integers(0, 4, n).astype(float), "cap": cap})
    return cases


def _cap_duplicates(X, y, cap):
    from ..offline import ObservationBuffer

    buffer = ObservationBuffer(np.shape(X)[1], max_duplicates=cap)
    for x, target in zip(X, y):
        buffer.add(x, target)
    return buffer.X.copy(), buffer.y.copy()


def _cap_pairs(X, y, cap):
    """The cap applied to (input, target) pairs: a mistake."""
    rows = np.column_stack([X, y])
    kept = _cap_duplicates(rows, np.zeros(len(rows)), cap)[0]
    return kept[:, :-1], kept[:, -1]


def _cap_last(X, y, cap):
    """The last copies kept instead of the first: a mistake."""
    Xr, yr = _cap_duplicates(np.asarray(X)[::-1], np.asarray(y)[::-1], cap)
    return Xr[::-1], yr[::-1]


def _cap_sorted(X, y, cap):
    Xk, yk = _cap_duplicates(X, y, cap)
    order = np.lexsort(Xk.T[::-1])
    return Xk[order], yk[order]


def _distance_cases(rng):
    cases = [{"position": np.array([0, 0]), "unsafe": np.array([[0, 0]])},
             {"position": np.array([2, 3]), "unsafe": np.array([[5, 7], [2, 1], [9, 9]])},
             {"position": np.array([0, 0]), "unsafe": np.array([[3, 4], [6, 0]])},   # 5 across, 6 along
             {"position": np.array([4, 4]), "unsafe": np.array([[5, 5], [4, 7]])},   # one diagonal step
             {"position": np.array([1, 8]), "unsafe": np.array([[4, 6], [9, 9], [1, 3]])}]
    for _ in range(3):
        cases.append({"position": rng.integers(0, 10, 2), "unsafe": rng.integers(0, 10, (int(rng.integers(2, 16)), 2))})
    return cases


def _distance(position, unsafe):
    return float(np.sqrt(((np.asarray(unsafe) - np.asarray(position)) ** 2).sum(1).min()))


def _move_cases(rng):
    cases = [{"position": np.array([0, 0]), "action": a, "size": 4} for a in range(4)]
    cases += [{"position": np.array([3, 3]), "action": a, "size": 4} for a in range(4)]
    cases += [{"position": rng.integers(0, 10, 2), "action": int(rng.integers(0, 4)), "size": 10} for _ in range(6)]
    return cases


def _move(position, action, size):
    from ..config import ACTION_MOVES

    dx, dy = ACTION_MOVES[action]
    return np.array([min(max(position[0] + dx, 0), size - 1), min(max(position[1] + dy, 0), size - 1)])


# -- Tutorial 4: Algorithm 1's safe set, decision and corrective update ---------------------------
def _decision_cases(rng):
    """Inputs in the order of the signature: mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold."""
    d, threshold = 1.0, 0.8

    def case(mu_cost, var_cost, mu_reward, known_unsafe, d=d, variance_threshold=threshold):
        return {"mu_cost": np.asarray(mu_cost, float), "var_cost": np.asarray(var_cost, float),
                "mu_reward": np.asarray(mu_reward, float), "known_unsafe": np.asarray(known_unsafe, bool),
                "d": d, "variance_threshold": variance_threshold}

    cases = [
        # the knife edges: a distance of exactly d and a variance of exactly sigma*^2 are safe
        case([1.0, 2.0, 0.5, 3.0], [0.8, 0.9, 0.1, 0.8], [-3.0, -1.0, -2.0, -0.5], [False, False, False, True]),
        # nothing safe: the backup decides
        case([0.2, 0.5, 0.9, 0.1], [0.1, 0.2, 0.3, 0.05], [-2.0, -2.0, -4.0, -1.0], [False, True, False, False]),
        # every variance too large (a GP with a large fitted noise)
        case([2.0, 1.5, 3.0, 1.2], [4.2, 4.1, 4.3, 4.0], [-1.0, -3.0, -2.0, -0.5], [False] * 4),
        # two safe actions tie on the best reward: the lower action number wins (action 0's variance, 0.7,
        # passes sigma*^2 = 0.8 but its square root does not)
        case([2.0, 1.5, 0.5, 3.0], [0.7, 0.3, 0.1, 0.4], [-1.0, -1.0, -2.0, -3.0], [False] * 4),
        # nothing safe, and the known-unsafe action has the best reward: the backup passes it over; the best
        # reward allowed (0), the lowest variance (3), the largest distance (1) and S_u forgotten (2) all differ
        case([0.2, 0.5, 0.9, 0.1], [0.1, 0.2, 0.3, 0.05], [-1.0, -3.0, -0.5, -2.0], [False, False, True, False]),
        # every action known unsafe: every reward is -inf, and the backup takes action 0
        case([2.0] * 4, [0.1] * 4, [-1.0, -2.0, -3.0, -4.0], [True] * 4),
    ]
    for _ in range(5):
        cases.append(case(rng.uniform(0, 3, 4), rng.uniform(0, 1.5, 4), -rng.uniform(0, 5, 4), rng.random(4) < 0.2,
                          float(rng.uniform(0.5, 2)), float(rng.uniform(0.3, 1.2))))
    return cases


def _safe(mu_cost, var_cost, known_unsafe, d, variance_threshold, mu_reward=None):
    from ..sarsp import choose_action

    return choose_action(mu_cost, var_cost, np.zeros(len(mu_cost)), known_unsafe, d, variance_threshold)[1]


def _safe_cases(rng):
    return [{k: v for k, v in case.items() if k != "mu_reward"} for case in _decision_cases(rng)]


def _choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold):
    from ..sarsp import choose_action

    action, _, backup = choose_action(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold)
    return action, backup


def _choose_ignoring_safety(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold):
    return int(np.argmax(np.where(known_unsafe, -np.inf, mu_reward))), False


def _backup_by(score):
    """A decision whose backup takes the action that maximises ``score(case)``: a mistake."""
    def choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold):
        action, backup = _choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold)
        if backup:
            action = int(np.argmax(score(mu_cost, var_cost, known_unsafe)))
        return action, backup
    return choose


def _correction_cases(rng):
    cases = [
        {"mu_cost": np.array([1.5, 0.2, 0.3, 0.4]), "var_cost": np.array([0.5, 0.1, 0.2, 0.3]), "action": 0,
         "d": 1.0, "was_backup": False},   # the model called it safe
        {"mu_cost": np.array([0.5, 0.2, 0.3, 0.4]), "var_cost": np.array([0.05, 0.1, 0.2, 0.3]), "action": 0,
         "d": 1.0, "was_backup": False},   # the most certain action, chosen as safe
        {"mu_cost": np.array([0.5, 0.2, 0.3, 0.4]), "var_cost": np.array([0.05, 0.1, 0.2, 0.3]), "action": 0,
         "d": 1.0, "was_backup": True},    # the same, but taken as the backup
        {"mu_cost": np.array([0.5, 0.2, 0.3, 0.4]), "var_cost": np.array([0.5, 0.1, 0.2, 0.3]), "action": 0,
         "d": 1.0, "was_backup": False},   # neither
        {"mu_cost": np.array([1.0, 0.2, 0.3, 0.4]), "var_cost": np.array([0.5, 0.1, 0.2, 0.3]), "action": 0,
         "d": 1.0, "was_backup": False},   # a distance of exactly d: the model called it safe
        {"mu_cost": np.array([0.5, 0.2, 0.3, 0.4]), "var_cost": np.array([0.1, 0.1, 0.2, 0.3]), "action": 1,
         "d": 1.0, "was_backup": False},   # tied for the lowest variance: each tied action is the most certain
    ]
    for _ in range(6):
        cases.append({"mu_cost": rng.uniform(0, 2, 4), "var_cost": rng.uniform(0, 1, 4),
                      "action": int(rng.integers(0, 4)), "d": 1.0, "was_backup": bool(rng.random() < 0.5)})
    return cases


def _corrects(mu_cost, var_cost, action, d, was_backup):
    """The reference code's corrective-update condition, as ``SARSPAgent.learn`` applies it."""
    model_said_safe = mu_cost[action] >= d
    most_certain = var_cost[action] <= var_cost.min() and not was_backup
    return bool(model_said_safe or most_certain)


# -- Tutorials 5 and 6: the metrics and Definition 4 ----------------------------------------------
def _symmetric_cases(rng):
    return [{"a": 28.0, "b": 58.0}, {"a": 58.0, "b": 28.0}, {"a": 5.0, "b": 5.0},
            {"a": float(rng.uniform(1, 100)), "b": float(rng.uniform(1, 100))}]


def _symmetric(a, b):
    from ..metrics import symmetric_percent_difference

    return symmetric_percent_difference(a, b)


def _records_cases(rng):
    cases = [
        {"episode_cost": np.array([0, 2, 0, 1]), "episode_steps": np.array([10, 30, 20, 100]),
         "task_completed": np.array([True, True, True, False])},
        # violations but no clean success: eq. 12 is undefined, kept as the paper's 0
        {"episode_cost": np.array([1, 0, 3]), "episode_steps": np.array([12, 100, 40]),
         "task_completed": np.array([True, False, False])},
        {"episode_cost": np.array([0, 0]), "episode_steps": np.array([5, 7]), "task_completed": np.array([True, True])},
    ]
    for n in (25, 250):
        done = rng.random(n) < 0.7
        cases.append({"episode_cost": rng.poisson(0.3, n), "episode_steps": rng.integers(5, 101, n),
                      "task_completed": done})
    return cases


def _tsr_and_cost_rate(episode_cost, episode_steps, task_completed):
    from ..metrics import running_metrics

    last = running_metrics(np.zeros(len(episode_cost)), episode_cost, episode_steps, task_completed).iloc[-1]
    return float(last["task_success_rate"]), float(last["cost_rate"])


def _cost_rate_over(steps_of):
    def wrong(episode_cost, episode_steps, task_completed):
        tsr = _tsr_and_cost_rate(episode_cost, episode_steps, task_completed)[0]
        total, steps = float(np.sum(episode_cost)), float(np.sum(steps_of(episode_cost, episode_steps, task_completed)))
        return tsr, (total / steps if total > 0 and steps > 0 else 0.0)
    return wrong


def _summaries_cases(rng):
    def summary(reward, rate, tsr):
        return {"mean_reward": reward, "cost_rate": rate, "task_success_rate": tsr, "total_cost": 10.0}

    cases = [
        {"summary_1": summary(-100, 0.01, 80), "summary_2": summary(-90, 0.02, 90), "a": 100.0},  # no branch
        {"summary_1": summary(-80, 0.01, 70), "summary_2": summary(-90, 0.02, 90), "a": 100.0},   # reward
        {"summary_1": summary(-100, 0.01, 95), "summary_2": summary(-90, 0.02, 90), "a": 100.0},  # TSR
        {"summary_1": summary(-100, 0.01, 85), "summary_2": summary(-90, 0.02, 90), "a": 80.0},   # TSR >= a
        {"summary_1": summary(-100, 0.01, 80), "summary_2": summary(-90, 0.02, 90), "a": 80.0},   # TSR = a exactly
        {"summary_1": summary(-80, 0.02, 95), "summary_2": summary(-90, 0.02, 90), "a": 100.0},   # equal p_c
        {"summary_1": summary(-80, 0.01, 95), "summary_2": summary(-90, 0.005, 90), "a": 100.0},  # higher p_c
        {"summary_1": summary(-90, 0.01, 80), "summary_2": summary(-90, 0.02, 90), "a": 100.0},   # equal reward
        {"summary_1": summary(-100, 0.01, 90), "summary_2": summary(-90, 0.02, 90), "a": 100.0},  # equal TSR
    ]
    for _ in range(6):
        cases.append({"summary_1": summary(-rng.uniform(50, 150), rng.uniform(0, 0.03), rng.uniform(50, 100)),
                      "summary_2": summary(-rng.uniform(50, 150), rng.uniform(0, 0.03), rng.uniform(50, 100)),
                      "a": float(rng.uniform(60, 100))})
    return cases


def _prefers(summary_1, summary_2, a):
    from ..metrics import prefers

    return bool(prefers(summary_1, summary_2, a))


def _prefers_with(condition):
    def wrong(summary_1, summary_2, a):
        return bool(condition(summary_1, summary_2, a))
    return wrong


AGENT_EXERCISES = {
    "3.1": CodingExercise(
        question="the offline buffer's duplicate cap: keep at most `cap` rows of every distinct input",
        signature="cap_duplicates(X, y, cap) -> (X_kept, y_kept), the rows kept in their order",
        reference=_cap_duplicates,
        cases=_cap_cases,
        mistakes=(
            Mistake(_cap_pairs, "Count copies of the input x alone: the same input with another target is still a "
                                "copy of it."),
            Mistake(lambda X, y, cap: _cap_duplicates(X, y, max(cap - 1, 0)) if cap > 1 else (X[:0], y[:0]),
                    "It keeps one copy too few: up to cap copies stay."),
            Mistake(lambda X, y, cap: _cap_duplicates(X, y, cap + 1),
                    "It keeps one copy too many: a row is kept while fewer than cap copies are stored."),
            Mistake(_cap_last, "Keep the first copies, in the order they came, as the buffer does when the data "
                               "arrive one step at a time."),
            Mistake(_cap_sorted, "Keep the rows in the order they came (np.unique sorts them)."),
        ),
        hint="Walk through the rows once, counting each input's copies in a dict keyed by tuple(x).",
        explanation="With cap = 12 the cost model keeps repeated observations of a state; with cap = 1 the "
                    "reward model keeps one row per input, as the reference code does.",
    ),
    "3.2": CodingExercise(
        question="the cost signal: the Euclidean distance from a cell to the nearest unsafe cell",
        signature="distance_to_unsafe(position, unsafe) -> float",
        reference=_distance,
        cases=_distance_cases,
        mistakes=(
            Mistake(lambda position, unsafe: float(np.abs(np.asarray(unsafe) - position).sum(1).min()),
                    "That is the Manhattan distance; the world measures the straight-line (Euclidean) one."),
            Mistake(lambda position, unsafe: float(((np.asarray(unsafe) - position) ** 2).sum(1).min()),
                    "That is the squared distance."),
            Mistake(lambda position, unsafe: float(np.sqrt(((np.asarray(unsafe) - position) ** 2).sum(1).max())),
                    "That is the farthest unsafe cell; the cost signal is about the nearest."),
            Mistake(lambda position, unsafe: float(np.abs(np.asarray(unsafe) - position).max(1).min()),
                    "That is the Chebyshev (king's move) distance; the world uses the Euclidean one."),
        ),
        hint="Subtract the position from every unsafe cell, then take the smallest length.",
        explanation="The agent is safe when this distance is at least d = 1: on the unsafe cell itself it is 0.",
    ),
    "3.3": CodingExercise(
        question="one move on the grid: RIGHT = 0, DOWN = 1, LEFT = 2, UP = 3, walls stop the agent",
        signature="move(position, action, size) -> (x, y)",
        reference=_move,
        cases=_move_cases,
        mistakes=(
            Mistake(lambda position, action, size: _move(position, [0, 3, 2, 1][action], size),
                    "y grows downwards, as the grid is drawn: DOWN adds 1 to y."),
            Mistake(lambda position, action, size: np.asarray(position) + [(1, 0), (0, 1), (-1, 0), (0, -1)][action],
                    "A move into a wall leaves the agent where it is: clip to 0 .. size - 1."),
            Mistake(lambda position, action, size: (np.asarray(position) + [(1, 0), (0, 1), (-1, 0), (0, -1)][action])
                    % size, "The grid has walls, not wrap-around edges."),
            Mistake(lambda position, action, size: _move(position, [1, 0, 3, 2][action], size),
                    "Check which action moves along x: RIGHT and LEFT change x, DOWN and UP change y."),
            Mistake(lambda position, action, size: _move(position, action, size + 1),
                    "Cells are numbered 0 .. size - 1: clip to size - 1, not size."),
        ),
        hint="Look up the action's (dx, dy) in sarsp_edu.config.ACTION_MOVES, add it, and clip each coordinate.",
        explanation="It matches SafeGridWorld.step on every action, at walls and corners too.",
    ),
    "4.1": CodingExercise(
        question="Algorithm 1's safe set: known-unsafe pairs excluded, variance at most sigma*^2, distance at least d",
        signature="safe_actions(mu_cost, var_cost, known_unsafe, d, variance_threshold) -> ndarray of bool, shape (4,)",
        reference=_safe,
        cases=_safe_cases,
        mistakes=(
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    (var_cost <= variance_threshold) & (mu_cost >= d),
                    "A pair in S_u (known unsafe) is never safe, whatever the model predicts."),
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    (var_cost < variance_threshold) & (mu_cost > d) & ~known_unsafe,
                    "At the thresholds themselves an action is safe: variance <= sigma*^2 and distance >= d."),
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    (np.sqrt(var_cost) <= variance_threshold) & (mu_cost >= d) & ~known_unsafe,
                    "sigma*^2 bounds the variance, not the standard deviation."),
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    (var_cost <= variance_threshold) & (mu_cost <= d) & ~known_unsafe,
                    "The cost model predicts the distance to danger: safe needs a large distance, at least d."),
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    ((var_cost <= variance_threshold) | (mu_cost >= d)) & ~known_unsafe,
                    "Both conditions must hold: a confident prediction and a safe distance."),
        ),
        hint="Combine three boolean arrays with &: not known unsafe, the variance test and the distance test.",
        explanation="This is the set S of Algorithm 1; an empty S sends the agent to the backup.",
    ),
    "4.2": CodingExercise(
        question="Algorithm 1's choice: the safe action of highest predicted reward, else the backup",
        signature="choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold) -> (action, backup)",
        reference=_choose,
        cases=_decision_cases,
        mistakes=(
            Mistake(_choose_ignoring_safety, "The reward decides only among the safe actions; with none safe, "
                                             "say so (backup = True)."),
            Mistake(_backup_by(lambda mu, var, known: np.where(known, -np.inf, -var)),
                    "The backup (no action safe) takes the highest predicted reward among the actions not known "
                    "unsafe, not the most certain one."),
            Mistake(_backup_by(lambda mu, var, known: np.where(known, -np.inf, mu)),
                    "The backup takes the highest predicted reward, not the largest predicted distance."),
            Mistake(lambda mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold: (
                _choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold) if any(
                    _safe(mu_cost, var_cost, known_unsafe, d, variance_threshold)) else (int(np.argmax(mu_reward)), True)),
                    "The backup, too, passes over the actions known unsafe (in S_u): their reward counts as -inf."),
            Mistake(lambda mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold: (
                _choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold)[0],
                not _choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold)[1]),
                    "The action is right; the second value is upside down: backup is True when no action was safe."),
            Mistake(lambda mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold: (
                3 - _choose(mu_cost[::-1], var_cost[::-1], mu_reward[::-1], known_unsafe[::-1], d,
                            variance_threshold)[0], _choose(mu_cost, var_cost, mu_reward, known_unsafe, d,
                                                           variance_threshold)[1]),
                    "On a tie the lowest action number wins (the paper's loop replaces its choice only on a "
                    "strictly higher reward; np.argmax does the same)."),
        ),
        hint="Decide first whether any action is safe (your safe_actions); then take the best reward among the "
             "actions allowed in that case.",
        explanation="It matches sarsp_edu.sarsp.choose_action, ties and the backup included.",
    ),
    "4.3": CodingExercise(
        question="the corrective update's condition after a violation (the reference code's rule)",
        signature="corrects(mu_cost, var_cost, action, d, was_backup) -> bool",
        reference=_corrects,
        cases=_correction_cases,
        mistakes=(
            Mistake(lambda mu_cost, var_cost, action, d, was_backup:
                    bool(mu_cost[action] >= d or var_cost[action] <= var_cost.min()),
                    "An action taken as the backup is not corrected for being the most certain: it was not "
                    "chosen as safe."),
            Mistake(lambda mu_cost, var_cost, action, d, was_backup: bool(mu_cost[action] >= d),
                    "There is a second reason to correct: the action was the model's most certain one."),
            Mistake(lambda mu_cost, var_cost, action, d, was_backup:
                    bool(mu_cost[action] >= d and var_cost[action] <= var_cost.min() and not was_backup),
                    "Either reason is enough: or, not and."),
            Mistake(lambda mu_cost, var_cost, action, d, was_backup:
                    bool(mu_cost[action] > d or (var_cost[action] <= var_cost.min() and not was_backup)),
                    "A predicted distance of exactly d is one the model called safe: at least d, >=."),
            Mistake(lambda mu_cost, var_cost, action, d, was_backup:
                    bool(mu_cost[action] >= d or (action == int(np.argmin(var_cost)) and not was_backup)),
                    "When several actions tie for the lowest variance, each of them is the most certain "
                    "(np.argmin names only the first): compare the action's variance with the minimum."),
        ),
        hint="Correct when the model said the action was safe, or when it was the lowest-variance action and "
             "not the backup.",
        explanation="Only then did the model mislead the agent: its stored cost is overwritten by what was seen.",
    ),
    "5.1": CodingExercise(
        question="Table 1's '% difference' in total cost: |a - b| over the mean of a and b, in %",
        signature="symmetric_percent_difference(a, b) -> float",
        reference=_symmetric,
        cases=_symmetric_cases,
        mistakes=(
            Mistake(lambda a, b: (a - b) / abs(b) * 100, "That is the change of a relative to b (Table 2's "
                                                        "convention); Table 1's has no reference model."),
            Mistake(lambda a, b: (a - b) / ((a + b) / 2) * 100, "It has no sign: take the absolute difference."),
            Mistake(lambda a, b: abs(a - b) / max(a, b) * 100, "Divide by the mean of the two, not the larger."),
            Mistake(lambda a, b: abs(a - b) / (a + b) * 100 if a + b else 0.0,
                    "Divide by the mean of the two, (a + b) / 2, not by their sum."),
            Mistake(lambda a, b: abs(a - b) / ((a + b) / 2) if a + b else 0.0, "It is a percentage: times 100."),
        ),
        hint="Table 1's 69.8% for 28 against 58 is the target: check the numerator, the denominator and the "
             "factor 100 against it.",
        explanation="For the paper's (40, 0.2, 2) row, 28 against 58 gives the 69.8% it prints.",
    ),
    "6.1": CodingExercise(
        question="the task success rate (%) and the cost rate of eq. 12 after a run's episodes",
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
            Mistake(lambda episode_cost, episode_steps, task_completed: (
                _tsr_and_cost_rate(episode_cost, episode_steps, task_completed)[0],
                float("nan") if _tsr_and_cost_rate(episode_cost, episode_steps, task_completed)[1] == 0
                and np.sum(episode_cost) > 0 else
                _tsr_and_cost_rate(episode_cost, episode_steps, task_completed)[1]),
                "Where eq. 12 is undefined (violations, but no clean success) the paper's records keep 0; "
                "the tables show it as n/a."),
        ),
        hint="Total violations over the steps of clean successful episodes; 0 when either is 0.",
        explanation="A trapped agent that never reaches the goal has few violations and a cost rate of 0: "
                    "low total cost alone can reward failure, which is why Definition 4 also asks for success.",
    ),
    "6.2": CodingExercise(
        question="Definition 4: agent 1 is preferred to agent 2",
        signature="prefers(summary_1, summary_2, a) -> bool",
        reference=_prefers,
        cases=_summaries_cases,
        mistakes=(
            Mistake(_prefers_with(lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"] and (
                s1["mean_reward"] >= s2["mean_reward"] and s1["task_success_rate"] >= s2["task_success_rate"])),
                "Agent 1 needs a lower cost rate and any one of the three: or, not and."),
            Mistake(_prefers_with(lambda s1, s2, a: s1["cost_rate"] <= s2["cost_rate"] and (
                s1["mean_reward"] >= s2["mean_reward"] or s1["task_success_rate"] >= s2["task_success_rate"]
                or s1["task_success_rate"] >= a)), "The cost rate must be strictly lower."),
            Mistake(_prefers_with(lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"] and (
                s1["mean_reward"] >= s2["mean_reward"] or s1["task_success_rate"] >= s2["task_success_rate"])),
                "The third branch is missing: a success rate of at least a is enough on its own."),
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
        hint="p_c(1) < p_c(2), and at least one of: J_r(1) >= J_r(2), TSR(1) >= TSR(2), TSR(1) >= a.",
        explanation="It matches sarsp_edu.prefers; with a = 100 the third branch needs a perfect success rate.",
    ),
}
