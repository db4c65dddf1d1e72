"""The safe-navigation gridworld of the paper (sections 2.4, 5.4, 5.5), with its covariate shift.

The agent walks an ``n x n`` grid from a random start to a random goal while
avoiding unsafe cells.  After the offline phase, ``shift`` moves some of the
unsafe cells: the covariate shift of the paper.  The models' inputs are
built from its observations in :mod:`sarsp_edu.world.offline`; this module knows
nothing of the models.

The environment is in :mod:`~sarsp_edu.world.gridworld.env`, its constants and
the picture of a world (``GridLayout``) in :mod:`~sarsp_edu.world.gridworld.layout`,
its renderings in :mod:`~sarsp_edu.world.gridworld.rendering`.

Coordinates are ``(x, y)`` with ``x`` the column and ``y`` the row; ``y``
grows downwards (``DOWN`` is ``(0, +1)``), as in the reference code.
"""

from .env import SafeGridWorld
from .layout import (
    ACTION_NAMES,
    ACTIONS,
    AGENT_XY,
    DOWN,
    GOAL_XY,
    LEFT,
    MOVES,
    NEAREST_UNSAFE_XY,
    OBSERVATION_FIELDS,
    RIGHT,
    UP,
    GridLayout,
)

__all__ = [
    "SafeGridWorld",
    "GridLayout",
    "RIGHT",
    "DOWN",
    "LEFT",
    "UP",
    "ACTIONS",
    "ACTION_NAMES",
    "MOVES",
    "OBSERVATION_FIELDS",
    "AGENT_XY",
    "GOAL_XY",
    "NEAREST_UNSAFE_XY",
]
