"""The gridworld's constants (actions, moves, the observation's fields) and ``GridLayout``, a picture of a world."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...config import ACTION_MOVES

#: action constants, numbered as in the reference implementation
RIGHT, DOWN, LEFT, UP = 0, 1, 2, 3
ACTIONS = np.array([RIGHT, DOWN, LEFT, UP])
ACTION_NAMES = ("right", "down", "left", "up")
#: (dx, dy) of each action
MOVES = np.array(ACTION_MOVES)

def moved(position, action: int, size: int) -> tuple[int, int]:
    """The cell an action leads to from ``position`` on a ``size`` x ``size`` grid: a move into a wall stays put.

    The world's step (:meth:`SafeGridWorld.step`) and exercise 3.3's answer key both move by it.

    Parameters
    ----------
    position : (int, int)
        The cell ``(x, y)``.
    action : int
        One of :data:`ACTIONS` (``RIGHT``, ``DOWN``, ``LEFT``, ``UP``).
    size : int
        The grid's side.
    """
    dx, dy = MOVES[int(action)]
    return (min(max(int(position[0]) + int(dx), 0), size - 1), min(max(int(position[1]) + int(dy), 0), size - 1))


def goal_reward(position, goal) -> float:
    """The reward of arriving at ``position``: minus its Euclidean distance to ``goal``.

    The world's step (:meth:`SafeGridWorld.step`) pays it; the audit and the reward ranking
    (:mod:`sarsp_edu.experiments.audit`, :mod:`sarsp_edu.experiments.ranking`) hold predictions to it.

    Parameters
    ----------
    position, goal : (int, int)
        Cells ``(x, y)``.
    """
    return -math.hypot(position[0] - goal[0], position[1] - goal[1])


def nearest(position, unsafe) -> tuple[int, float]:
    """The index of the unsafe state nearest to ``position`` (ties: the first listed) and its Euclidean distance.

    The world's cost signal (:meth:`SafeGridWorld.nearest_unsafe`) and exercise 3.2's answer key both use it.

    Parameters
    ----------
    position : (int, int)
        The cell ``(x, y)``.
    unsafe : array-like of shape (k, 2)
        The unsafe cells, k >= 1.
    """
    diff = np.asarray(unsafe) - np.asarray(position)
    d2 = np.einsum("ij,ij->i", diff, diff)
    i = int(np.argmin(d2))
    return i, math.sqrt(d2[i])


#: the entries of an observation, in order (the reference implementation's)
OBSERVATION_FIELDS = (
    "agent_x",
    "agent_y",
    "goal_x",
    "goal_y",
    "goal_l1_distance",
    "unsafe_x",
    "unsafe_y",
    "unsafe_distance",
)
#: where an observation holds the agent's, the goal's and the nearest unsafe state's (x, y)
AGENT_XY, GOAL_XY, NEAREST_UNSAFE_XY = slice(0, 2), slice(2, 4), slice(5, 7)

#: greedy placements tried before falling back to a chessboard colour, which cannot fail below the capacity
PLACEMENT_ATTEMPTS = 200


@dataclass(frozen=True)
class GridLayout:
    """A snapshot of a world, for drawing (see :func:`sarsp_edu.teaching.plotting.plot_gridworld`).

    Attributes
    ----------
    size : int
    unsafe_states : ndarray of shape (n_unsafe, 2)
    start, goal, agent : tuple of int or None
    moved : ndarray of int
        Indices (into ``unsafe_states``) of the states moved by the last shift.
    moved_from : ndarray of shape (len(moved), 2)
        Where those states were before the shift.
    d : float
        The safety threshold.
    """

    size: int
    unsafe_states: np.ndarray
    start: tuple | None
    goal: tuple | None
    agent: tuple | None
    moved: np.ndarray
    moved_from: np.ndarray
    d: float = 1.0
