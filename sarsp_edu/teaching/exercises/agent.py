"""Coding exercises of Tutorials 3 and 4: the world, the offline data, Algorithm 1's rules.

Each reference calls the package's own implementation (the buffer, the
world's moves, the decision rule, the corrective update's condition), so an
exercise stays right when the package changes.  The metrics' exercises of
Tutorials 5 and 6 are in :mod:`.records`.
"""

from __future__ import annotations

import numpy as np

from ...agent.decision import corrects
from ...world.gridworld.layout import moved, nearest
from .grading import CodingExercise, Mistake

__all__ = ["AGENT_EXERCISES"]

#: the floats next to the knife edges d = 1 and sigma*^2 = 0.8, on their unsafe sides (a tolerance as small as
#: 1e-13 lets them pass)
_BELOW_ONE, _ABOVE_0_8 = float(np.nextafter(1.0, 0.0)), float(np.nextafter(0.8, 1.0))


# -- Tutorial 3: the offline buffer's duplicate cap, the cost signal, a move -----------------------
def _cap_cases(rng):
    cases = []
    for n, cap, features in ((1, 1, 2), (12, 1, 2), (40, 2, 1), (60, 12, 2), (30, 3, 3)):
        X = rng.integers(0, 3 if features < 3 else 2, (n, features)).astype(float)  # few distinct inputs: many copies
        cases.append({"X": X, "y": rng.integers(0, 4, n).astype(float), "cap": cap})
    # no rows at all: nothing to keep, in the inputs' shape
    cases.append({"X": np.zeros((0, 2)), "y": np.zeros(0), "cap": 3})
    # inputs that are not whole numbers: 0.2 and 0.4 are two inputs, whatever they round to
    cases.append({"X": np.array([[0.2, 1.0], [0.4, 1.0], [0.2, 1.0], [0.4, 1.0]]), "y": np.array([1.0, 2.0, 3.0, 4.0]),
                  "cap": 1})
    cases.append({"X": np.array([[0.21, 1.0], [0.24, 1.0], [0.21, 1.0]]), "y": np.array([1.0, 2.0, 3.0]), "cap": 1})
    # and a hair apart: 0.2 and 0.2 + 1e-12 are two inputs too (distinct is exact: no rounding, no tolerance)
    cases.append({"X": np.array([[0.2, 1.0], [0.2 + 1e-12, 1.0], [0.2, 1.0], [0.2001, 1.0]]),
                  "y": np.array([1.0, 2.0, 3.0, 4.0]), "cap": 1})
    return cases


def _cap_duplicates(X, y, cap):
    from ...world.offline import ObservationBuffer

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
             {"position": np.array([1, 8]), "unsafe": np.array([[4, 6], [9, 9], [1, 3]])},
             # the nearest last of four, after a farther one than the first (a loop that stops early misses it)
             {"position": np.array([0, 0]), "unsafe": np.array([[9, 9], [5, 5], [7, 7], [0, 1]])},
             {"position": np.array([5, 5]), "unsafe": np.array([[0, 0], [9, 9], [2, 8], [1, 1], [5, 6]])}]
    for _ in range(3):
        cases.append({"position": rng.integers(0, 10, 2), "unsafe": rng.integers(0, 10, (int(rng.integers(2, 16)), 2))})
    return cases


def _distance(position, unsafe):
    return nearest(position, unsafe)[1]  # the world's own cost signal (sarsp_edu.world.gridworld.layout.nearest)


def _move_cases(rng):
    cases = [{"position": np.array([0, 0]), "action": a, "size": 4} for a in range(4)]
    cases += [{"position": np.array([3, 3]), "action": a, "size": 4} for a in range(4)]
    # at the far walls of grids of 10 and 12 cells: a wall at size - 1 from size alone, whatever size is
    cases += [{"position": np.array([9, 9]), "action": a, "size": 10} for a in (0, 1)]
    cases += [{"position": np.array([11, 5]), "action": 0, "size": 12}]
    # one cell from each wall, a step onto the wall's own row or column is allowed (a guard one cell short is not)
    cases += [{"position": np.array([8, 4]), "action": 0, "size": 10}, {"position": np.array([4, 8]), "action": 1,
                                                                         "size": 10},
              {"position": np.array([1, 6]), "action": 2, "size": 10}, {"position": np.array([6, 1]), "action": 3,
                                                                         "size": 10}]
    cases += [{"position": rng.integers(0, 10, 2), "action": int(rng.integers(0, 4)), "size": 10} for _ in range(6)]
    return cases


def _move(position, action, size):
    return np.array(moved(position, action, size))  # the world's own step (sarsp_edu.world.gridworld.layout.moved)


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
        # nothing safe, and the best reward is an action whose variance fails sigma*^2 while others' pass: the
        # backup takes it all the same (the backup ignores the cost model, variance included)
        case([0.5, 0.5, 0.5, 0.5], [0.5, 2.0, 0.5, 0.5], [-3.0, -1.0, -2.0, -4.0], [False] * 4),
        case([0.9, 0.5, 0.2, 3.0], [0.3, 0.2, 0.1, 5.0], [-2.0, -4.0, -3.0, -0.5], [False] * 4),
        # every action known unsafe: every reward is -inf, and the backup takes action 0 (whichever reward
        # was the best before the override)
        case([2.0] * 4, [0.1] * 4, [-1.0, -2.0, -3.0, -4.0], [True] * 4),
        case([2.0] * 4, [0.1] * 4, [-4.0, -3.0, -2.0, -1.0], [True] * 4),
        # rewards a hair apart are no tie: the higher wins (no tolerance, no rounding)
        case([2.0, 1.5, 1.2, 3.0], [0.1, 0.2, 0.3, 0.4], [-1.0000001, -1.0, -3.0, -4.0], [False] * 4),
        case([2.0, 1.5, 1.2, 3.0], [0.1, 0.2, 0.3, 0.4], [-1.0 - 1e-12, -1.0, -3.0, -4.0], [False] * 4),
        # other thresholds and distances than the notebook's sigma*^2 = 0.8 and d = 1, each deciding the choice
        case([1.5, 2.0, 0.5, 3.0], [0.5, 0.2, 0.1, 0.9], [-1.0, -2.0, -3.0, -0.5], [False] * 4, 1.0, 0.4),
        case([1.5, 2.0, 0.5, 3.0], [1.2, 1.4, 0.1, 2.0], [-1.0, -2.0, -3.0, -0.5], [False] * 4, 1.0, 1.5),
        case([1.5, 2.5, 0.7, 3.0], [0.2, 0.3, 0.1, 0.4], [-1.0, -2.0, -0.5, -3.0], [False] * 4, 2.0),
        case([0.7, 2.5, 0.3, 3.0], [0.2, 0.3, 0.1, 0.4], [-1.0, -2.0, -0.5, -3.0], [False] * 4, 0.5),
        # just past each knife edge, the best reward there: a distance a hair below d and a variance a hair
        # above sigma*^2 are not safe (the rule compares exact values: no tolerance, no rounding)
        case([1.0 - 1e-7, 2.0, 0.5, 0.9996], [0.1, 0.8 + 1e-7, 0.1, 0.1], [-0.5, -0.6, -3.0, -0.7], [False] * 4),
        case([2.0, 1.5, 0.5, 3.0], [0.8004, 0.1, 0.2, 0.3], [-0.5, -1.0, -3.0, -2.0], [False] * 4),
        case([1.0 - 1e-12, 2.0, 0.5, 3.0], [0.1, 0.8 + 1e-12, 0.1, 0.1], [-0.5, -0.6, -3.0, -0.7], [False] * 4),
        # one unit in the last place past each edge: the nearest floats to d and sigma*^2 on the wrong side
        case([_BELOW_ONE, 2.0, 0.5, 3.0], [0.1, _ABOVE_0_8, 0.1, 0.1], [-0.5, -0.6, -3.0, -0.7], [False] * 4),
    ]
    for _ in range(5):
        cases.append(case(rng.uniform(0, 3, 4), rng.uniform(0, 1.5, 4), -rng.uniform(0, 5, 4), rng.random(4) < 0.2,
                          float(rng.uniform(0.5, 2)), float(rng.uniform(0.3, 1.2))))
    return cases


def _safe(mu_cost, var_cost, known_unsafe, d, variance_threshold, mu_reward=None):
    from ...agent.sarsp import choose_action

    return choose_action(mu_cost, var_cost, np.zeros(len(mu_cost)), known_unsafe, d, variance_threshold)[1]


#: the diagnosis of a safe set compared with a tolerance
_EXACT = ("A distance a hair below d, or a variance a hair above sigma*^2, is not safe: the rule compares the "
          "exact values, with no tolerance and no rounding.")


def _safe_cases(rng):
    return [{k: v for k, v in case.items() if k != "mu_reward"} for case in _decision_cases(rng)]


def _choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold):
    from ...agent.sarsp import choose_action

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
    def case(mu_cost, var_cost, action, d, was_backup):
        return {"mu_cost": np.asarray(mu_cost, float), "var_cost": np.asarray(var_cost, float), "action": action,
                "d": d, "was_backup": was_backup}

    cases = [
        case([1.5, 0.2, 0.3, 0.4], [0.5, 0.1, 0.2, 0.3], 0, 1.0, False),   # the model called it safe
        case([0.5, 0.2, 0.3, 0.4], [0.05, 0.1, 0.2, 0.3], 0, 1.0, False),  # the most certain action, chosen as safe
        case([0.5, 0.2, 0.3, 0.4], [0.05, 0.1, 0.2, 0.3], 0, 1.0, True),   # the same, but taken as the backup
        case([0.5, 0.2, 0.3, 0.4], [0.5, 0.1, 0.2, 0.3], 0, 1.0, False),   # neither
        case([1.0, 0.2, 0.3, 0.4], [0.5, 0.1, 0.2, 0.3], 0, 1.0, False),   # a distance of exactly d: called safe
        case([0.5, 0.2, 0.3, 0.4], [0.1, 0.1, 0.2, 0.3], 1, 1.0, False),   # tied for the lowest variance: each counts
        # called safe by its distance alone, with a variance above sigma*^2 = 0.8 (so not in Algorithm 1's safe
        # set): not the most certain action, then the most certain one but taken as the backup
        case([2.5, 0.2, 0.3, 0.4], [1.6, 0.1, 0.2, 0.3], 0, 2.0, False),
        case([0.8, 1.2, 0.1, 0.4], [1.5, 1.1, 1.4, 1.3], 1, 0.5, True),
        # other d: a distance of 1.2 is below d = 1.5; one of 0.7 is at least d = 0.5
        case([1.2, 0.2, 0.3, 0.4], [0.5, 0.1, 0.2, 0.3], 0, 1.5, False),
        case([0.7, 0.2, 0.3, 0.4], [0.5, 0.1, 0.2, 0.3], 0, 0.5, False),
        # both reasons at once: called safe and the most certain, chosen as safe (an 'and' slip says True too)
        case([1.5, 0.2, 0.3, 0.4], [0.05, 0.1, 0.2, 0.3], 0, 1.0, False),
        # variances that part in their second decimal: 0.84 is not the lowest of 0.81 and 0.84
        case([0.5, 0.2, 0.3, 0.4], [0.84, 0.81, 0.9, 0.95], 0, 1.0, False),
        # and in their fourth and sixth: 0.5004 and 0.500001 are not tied with 0.5 (a tie is equality, with no
        # tolerance, np.isclose's defaults included)
        case([0.5, 0.2, 0.3, 0.4], [0.5004, 0.5, 0.9, 0.95], 0, 1.0, False),
        case([0.5, 0.2, 0.3, 0.4], [0.500001, 0.5, 0.9, 0.95], 0, 1.0, False),  # within np.isclose's defaults
        case([0.5, 0.2, 0.3, 0.4], [0.5 + 1e-12, 0.5, 0.9, 0.95], 0, 1.0, False),  # within math.isclose's
        case([1.0 - 1e-12, 0.2, 0.3, 0.4], [0.5, 0.1, 0.2, 0.3], 0, 1.0, False),
        case([_BELOW_ONE, 0.2, 0.3, 0.4], [0.5, 0.1, 0.2, 0.3], 0, 1.0, False),
        case([0.5, 0.2, 0.3, 0.4], [np.nextafter(0.5, 1.0), 0.5, 0.9, 0.95], 0, 1.0, False),
        # a predicted distance a hair below d is not one the model called safe (no tolerance, no rounding)
        case([1.0 - 1e-7, 0.2, 0.3, 0.4], [0.5, 0.1, 0.2, 0.3], 0, 1.0, False),
        case([0.9996, 0.2, 0.3, 0.4], [0.5, 0.1, 0.2, 0.3], 0, 1.0, False),
        # the lowest variance at each action, the taken one lowest or not (a minimum over some actions only fails)
        case([0.5, 0.2, 0.3, 0.4], [0.5, 0.4, 0.3, 0.1], 3, 1.0, False),
        case([0.5, 0.2, 0.3, 0.4], [0.4, 0.3, 0.1, 0.2], 2, 1.0, False),
        case([0.5, 0.2, 0.3, 0.4], [0.4, 0.3, 0.2, 0.1], 2, 1.0, False),
        case([0.5, 0.2, 0.3, 0.4], [0.1, 0.2, 0.3, 0.4], 1, 1.0, False),
    ]
    for _ in range(6):
        cases.append(case(rng.uniform(0, 2, 4), rng.uniform(0, 1.5, 4), int(rng.integers(0, 4)),
                          float(rng.uniform(0.5, 1.5)), bool(rng.random() < 0.5)))
    return cases


def _safe_test_for_called_safe(mu_cost, var_cost, action, d, was_backup):
    """'Called it safe' read as Algorithm 1's whole safe test, variance included: a mistake."""
    from ...config import VARIANCE_THRESHOLD

    called_safe = mu_cost[action] >= d and var_cost[action] <= VARIANCE_THRESHOLD
    return bool(called_safe or (var_cost[action] <= var_cost.min() and not was_backup))


AGENT_EXERCISES = {
    "3.1": CodingExercise(
        question="the offline buffer's duplicate cap: keep at most `cap` rows of every distinct input",
        signature="cap_duplicates(X, y, cap) -> (X_kept, y_kept), the rows kept in their order",
        reference=_cap_duplicates,
        examples={"cap": (1, 12)},
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
        hint="Redo the case above by hand, row by row: which rows are copies of an input seen before, and "
             "which of them stay?",
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
        hint="Redo the case above by hand: which unsafe cell is nearest, and how long is the straight line to it?",
        explanation="The agent is safe when this distance is at least d = 1: on the unsafe cell itself it is 0.",
    ),
    "3.3": CodingExercise(
        question="one move on the grid: RIGHT = 0, DOWN = 1, LEFT = 2, UP = 3, walls stop the agent",
        signature="move(position, action, size) -> (x, y)",
        reference=_move,
        examples={"size": 10},
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
        hint="Redo the case above by hand on the grid as drawn: x grows to the right, y downwards.",
        explanation="It matches SafeGridWorld.step on every action, at walls and corners too.",
    ),
    "4.1": CodingExercise(
        question="Algorithm 1's safe set: known-unsafe pairs excluded, variance at most sigma*^2, distance at least d",
        signature="safe_actions(mu_cost, var_cost, known_unsafe, d, variance_threshold) -> ndarray of bool, shape (4,)",
        reference=_safe,
        examples={"d": 1.0, "variance_threshold": 0.8},
        cases=_safe_cases,
        mistakes=(
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    (var_cost <= variance_threshold) & (mu_cost >= d),
                    "A pair in S_u (known unsafe) is never safe, whatever the model predicts."),
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    (var_cost < variance_threshold) & (mu_cost > d) & ~known_unsafe,
                    "An action exactly at a threshold (a variance equal to sigma*^2, a distance equal to d) is "
                    "judged wrongly: which comparison keeps it?"),
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    (np.sqrt(var_cost) <= variance_threshold) & (mu_cost >= d) & ~known_unsafe,
                    "sigma*^2 bounds the variance itself: compare the variance with sigma*^2 as it is (no square root, "
                    "no square)."),
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    (var_cost <= variance_threshold) & (mu_cost <= d) & ~known_unsafe,
                    "The cost model predicts the distance to danger: safe needs a large distance, at least d."),
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    ((var_cost <= variance_threshold) | (mu_cost >= d)) & ~known_unsafe,
                    "Both conditions must hold: a confident prediction and a safe distance."),
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    ((var_cost <= variance_threshold) | np.isclose(var_cost, variance_threshold))
                    & ((mu_cost >= d) | np.isclose(mu_cost, d)) & ~known_unsafe, _EXACT),
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    (var_cost <= variance_threshold) & ((mu_cost >= d) | np.isclose(mu_cost, d)) & ~known_unsafe,
                    _EXACT),
            Mistake(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
                    ((var_cost <= variance_threshold) | np.isclose(var_cost, variance_threshold))
                    & (mu_cost >= d) & ~known_unsafe, _EXACT),
        ),
        hint="Redo the case above by hand, action by action: which of the three conditions does each meet?",
        explanation="This is the set S of Algorithm 1; an empty S sends the agent to the backup.",
    ),
    "4.2": CodingExercise(
        question="Algorithm 1's choice: the safe action of highest predicted reward, else the backup",
        signature="choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold) -> (action, backup)",
        reference=_choose,
        examples={"d": 1.0, "variance_threshold": 0.8},
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
                    _safe(mu_cost, var_cost, known_unsafe, d, variance_threshold))
                else (int(np.argmax(mu_reward)), True)),
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
        hint="Redo the case above by hand: which actions are safe, and which one does Algorithm 1 take then?",
        explanation="It matches sarsp_edu.agent.sarsp.choose_action, ties and the backup included.",
    ),
    "4.3": CodingExercise(
        question="the corrective update's condition after a violation (the reference code's rule): the model "
                 "called the action safe, which the reference code reads as a predicted distance of at least d "
                 "whatever the variance, or it was the most certain action (every action tied for the lowest "
                 "variance counts) and not taken as the backup",
        signature="corrects(mu_cost, var_cost, action, d, was_backup) -> bool",
        reference=corrects,  # the agent's own condition (sarsp_edu.agent.decision.corrects)
        examples={"d": 1.0},
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
            # after the 'and' slip: on one input both may say False (the capstone names a part from one input)
            Mistake(lambda mu_cost, var_cost, action, d, was_backup: False,
                    "Your test never corrects the data: after a violation, the question gives two reasons that do."),
            Mistake(_safe_test_for_called_safe,
                    "The reference code's 'called it safe' is the predicted distance alone (at least d): a variance "
                    "above sigma*^2 does not stop the correction."),
            Mistake(lambda mu_cost, var_cost, action, d, was_backup:
                    bool(mu_cost[action] > d or (var_cost[action] <= var_cost.min() and not was_backup)),
                    "A predicted distance of exactly d is one the model called safe: at least d, >=."),
            Mistake(lambda mu_cost, var_cost, action, d, was_backup:
                    bool(mu_cost[action] >= d or (action == int(np.argmin(var_cost)) and not was_backup)),
                    "When several actions tie for the lowest variance, each of them is the most certain "
                    "(np.argmin names only the first): compare the action's variance with the minimum."),
            Mistake(lambda mu_cost, var_cost, action, d, was_backup:
                    bool(mu_cost[action] >= d or (np.isclose(var_cost[action], var_cost.min(), rtol=1e-3)
                                                  and not was_backup)),
                    "A variance a little above the lowest is not tied with it: the most certain action has the "
                    "lowest variance itself (a tie is equality), not one within a tolerance of it."),
        ),
        hint="Redo the case above by hand, one reason for a correction at a time, as the question states them.",
        explanation="Only then did the model mislead the agent: its stored cost is overwritten by what was seen.",
    ),
}
