"""The gridworld's constants (actions, moves, the observation's fields) and ``GridLayout``, a picture of a world."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..config import ACTION_MOVES

#: action constants, numbered as in the reference implementation
RIGHT, DOWN, LEFT, UP = 0, 1, 2, 3
ACTIONS = np.array([RIGHT, DOWN, LEFT, UP])
ACTION_NAMES = ("right", "down", "left", "up")
#: (dx, dy) of each action
MOVES = np.array(ACTION_MOVES)

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
    """A snapshot of a world, for drawing (see :func:`sarsp_edu.plotting.plot_gridworld`).

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
