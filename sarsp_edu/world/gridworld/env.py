"""``SafeGridWorld``: the paper's world as a Gymnasium environment, its placement of unsafe states and its shift."""

from __future__ import annotations

import math
import numbers

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from ..._internal.rng import as_generator
from ..._internal.validation import check_choice, check_int, check_positive, check_switch_states
from ...config import LIMITS, PLACEMENTS, WorldSettings, check_n_unsafe, placement_span, unsafe_capacity
from .layout import PLACEMENT_ATTEMPTS, GridLayout, goal_reward, moved, nearest
from .rendering import Rendering


class SafeGridWorld(Rendering, gym.Env):
    """Navigate an ``n x n`` grid to a goal while avoiding unsafe states.

    ## Description
    The environment of the paper's experiments (sections 5.4-5.5), following
    the reference implementation rule by rule: an agent walks a grid from a
    start to a goal; some cells are unsafe, and a covariate shift
    (:meth:`shift`) can move them between the offline data and the online
    episodes.

    ## Action Space
    ``Discrete(4)``: ``RIGHT = 0`` (+1, 0), ``DOWN = 1`` (0, +1), ``LEFT = 2``
    (-1, 0), ``UP = 3`` (0, -1).  A move off the grid is clipped: the agent
    stays where it is.  Any integer-like action that ``action_space.contains``
    accepts is taken (``2``, ``np.int64(2)``, ``np.array(2)``).

    ## Observation Space
    ``Box`` of shape (8,): agent x, y; goal x, y; L1 distance to the goal;
    nearest unsafe state x, y; Euclidean distance to it
    (``OBSERVATION_FIELDS``).

    ## Starting State
    Start and goal are drawn uniformly at every reset; the start is never
    unsafe and never the goal, the goal is never unsafe.  Unsafe states are
    placed once, at construction, and move only through :meth:`shift`.  No
    unsafe state is on, or 4-adjacent to, another, and when they are placed
    they avoid the start and goal of that moment.

    ## Rewards
    Minus the Euclidean distance from the agent's new cell to the goal.

    ## Cost
    The state-cost signal is the Euclidean distance from the agent's cell to
    the nearest unsafe state (0 inside one).  A step violates the constraint,
    cost ``c_t = 1``, when that distance is below ``d``, i.e. the agent is
    inside an unsafe state.  Unsafe states are not terminal.

    ## Episode End
    Terminated at the goal; truncated after ``max_steps`` steps (default
    ``size * size``, the paper's ``T_max = n * n``).  The registration
    ``sarsp_edu/SafeGridWorld-v0`` sets ``max_episode_steps`` to the paper's
    ``T_max = 100``, so ``gymnasium.make`` wraps it in ``TimeLimit``, which
    truncates the same step the environment itself does on the paper's grid.

    ## Information
    ``step`` returns ``info`` with ``"distance_to_unsafe"`` (the cost signal),
    ``"cost"`` (1 for a violation, else 0), ``"task_completed"`` and
    ``"steps"``; ``reset`` returns ``"distance_to_unsafe"``, ``"start"`` and
    ``"goal"``.

    ## Arguments
    size : int, default 10
        Grid side ``n`` (>= 2).
    n_unsafe : int, default 15
        Number of unsafe states.
    d : float, default 1.0
        Safety threshold on the distance to the nearest unsafe state (> 0).
    max_steps : int, optional
        Steps before truncation; default ``size * size``.
    placement : {"full", "reference"}, default "full"
        Where start, goal and unsafe states may be drawn.  ``"full"``: the
        whole grid, as the paper describes it.  ``"reference"``: never the last
        row or column, as the reference code's ``randint(0, n - 1)`` does (an
        off-by-one).  The agent can walk everywhere in both.
    render_mode : {"ansi", "rgb_array"}, optional
    seed : int or numpy.random.Generator, optional
        Seeds the environment's generator, which places the unsafe states and
        draws starts and goals.  ``reset(seed=...)`` reseeds it later (the
        unsafe states stay where they are).  Without a seed here, the first
        ``reset(seed=...)`` draws the whole world, so ``SafeGridWorld()`` then
        ``reset(seed=3)`` holds the world of ``SafeGridWorld(seed=3)``.  As
        Gymnasium's seeding contract asks, ``reset(seed=s)`` always gives the
        same start and goal on the same environment, the first time too.

    ## Version History
    - v0: the paper's world; ``gymnasium.make`` applies ``TimeLimit`` at
      ``T_max = 100`` (sarsp_edu 0.2.2), and a seeded reset's start and goal
      no longer depend on whether it is the first (0.2.2).

    Examples
    --------
    >>> from sarsp_edu import SafeGridWorld, RIGHT
    >>> env = SafeGridWorld(seed=0)
    >>> observation, info = env.reset(seed=1)
    >>> observation.shape, env.unsafe_states.shape
    ((8,), (15, 2))
    >>> observation, reward, terminated, truncated, info = env.step(RIGHT)
    >>> sorted(info)
    ['cost', 'distance_to_unsafe', 'steps', 'task_completed']
    """

    metadata = {"render_modes": ["ansi", "rgb_array"], "render_fps": 4}

    def __init__(
        self,
        size: int = WorldSettings.grid_size,
        n_unsafe: int = WorldSettings.n_unsafe,
        d: float = WorldSettings.d,
        max_steps: int | None = WorldSettings.max_steps,
        *,
        placement: str = WorldSettings.placement,
        render_mode: str | None = None,
        seed=None,
    ):
        self.size = check_int("size", size, 2, LIMITS["grid_size"][0], why=LIMITS["grid_size"][1])
        self.placement = check_choice("placement", placement, PLACEMENTS)
        self.n_unsafe = check_n_unsafe(n_unsafe, self.size, self.placement)
        self.d = check_positive("d", d)
        max_steps = check_int("max_steps", max_steps, 1, LIMITS["max_steps"][0], allow_none=True,
                              why=LIMITS["max_steps"][1])
        self.max_steps = self.size * self.size if max_steps is None else max_steps
        self.render_mode = check_choice("render_mode", render_mode, [None, *self.metadata["render_modes"]])

        self.action_space = spaces.Discrete(4)
        far = float(self.size - 1)
        self.observation_space = spaces.Box(
            low=np.zeros(8),
            high=np.array([far, far, far, far, 2 * far, far, far, math.sqrt(2) * far]),
            dtype=np.float64,
        )

        if isinstance(seed, np.random.Generator):
            self.np_random = seed
        else:
            super().reset(seed=seed)  # Gymnasium's own seeding of np_random
        # Unseeded, the layout is provisional: the first reset(seed=...) draws it again.
        self._layout_fixed = seed is not None
        self._draw_world()
        self._steps = 0
        self._done = True  # step() needs a reset() first

    def _draw_world(self) -> None:
        """Draw the start and goal "of that moment" and the unsafe states that avoid them."""
        self._start, self._goal = self._draw_start_goal(np.empty((0, 2), dtype=int))
        self._agent = self._start
        self._unsafe = self._place(self.n_unsafe, np.empty((0, 2), dtype=int), [self._start, self._goal])
        self._moved = np.empty(0, dtype=int)
        self._moved_from = np.empty((0, 2), dtype=int)

    @staticmethod
    def max_unsafe(size: int, placement: str = WorldSettings.placement) -> int:
        """The most unsafe states the spacing rule allows on this grid (one colour of a chessboard).

        No world can hold more; :meth:`capacity` is how many it always
        places *and* shifts.

        Parameters
        ----------
        size : int
            The grid's side.
        placement : {"full", "reference"}, default ``WorldSettings.placement``
            Where objects may be placed: the whole grid, or (``"reference"``) all but the last row and column.
        """
        span = placement_span(size, placement)
        return math.ceil(span * span / 2)

    #: the most unsafe states a world always places and shifts (see ``config.unsafe_capacity``)
    capacity = staticmethod(unsafe_capacity)

    # -- read-only state ---------------------------------------------------
    @property
    def unsafe_states(self) -> np.ndarray:
        """Unsafe cells, ndarray of shape (n_unsafe, 2) of (x, y) (a read-only copy)."""
        out = self._unsafe.copy()
        out.flags.writeable = False
        return out

    @property
    def agent_position(self) -> tuple[int, int]:
        return self._agent

    @property
    def goal(self) -> tuple[int, int]:
        return self._goal

    @property
    def start(self) -> tuple[int, int]:
        return self._start

    @property
    def moved_indices(self) -> np.ndarray:
        """Indices of the unsafe states moved by the last :meth:`shift`."""
        return self._moved.copy()

    # -- geometry -------------------------------------------------------------
    def _span(self) -> int:
        """Number of rows/columns where objects may be placed."""
        return placement_span(self.size, self.placement)

    def nearest_unsafe(self, position) -> tuple[np.ndarray, float]:
        """The nearest unsafe state to ``position`` and its Euclidean distance.

        Ties go to the state listed first in ``unsafe_states``.
        """
        i, distance = nearest(position, self._unsafe)
        return self._unsafe[i].copy(), distance

    def distance_map(self) -> np.ndarray:
        """Distance to the nearest unsafe state for every cell, ndarray of shape (size, size) indexed [y, x]."""
        ys, xs = np.mgrid[0 : self.size, 0 : self.size]
        cells = np.stack([xs.ravel(), ys.ravel()], axis=1)
        diff = cells[:, None, :] - self._unsafe[None, :, :]
        return np.sqrt((diff**2).sum(-1).min(axis=1)).reshape(self.size, self.size)

    def _observation(self) -> np.ndarray:
        return self.observation_at(self._agent)

    def observation_at(self, position) -> np.ndarray:
        """The observation of the agent on ``position`` (x, y) in this world as it is now (its goal, its unsafe
        states): what :meth:`step` would return there."""
        unsafe, distance = self.nearest_unsafe(position)
        ax, ay = position
        gx, gy = self._goal
        return np.array(
            [ax, ay, gx, gy, abs(ax - gx) + abs(ay - gy), unsafe[0], unsafe[1], distance], dtype=np.float64
        )

    # -- placement ------------------------------------------------------------
    def _draw_start_goal(self, unsafe: np.ndarray):
        span = self._span()
        free = np.ones((span, span), dtype=bool)  # [x, y]
        inside = unsafe[(unsafe < span).all(axis=1)]
        free[inside[:, 0], inside[:, 1]] = False
        cells = np.argwhere(free)
        if len(cells) < 2:
            raise RuntimeError("fewer than two safe cells are left for the start and the goal")
        i, j = self.np_random.choice(len(cells), size=2, replace=False)
        return tuple(int(v) for v in cells[i]), tuple(int(v) for v in cells[j])

    def _place(self, n: int, keep: np.ndarray, avoid, rng=None, exclude=()) -> np.ndarray:
        """Draw ``n`` unsafe cells, none on or 4-adjacent to ``keep`` or to each other.

        ``avoid`` (start, goal, agent) and ``exclude`` (the cells states are
        moving away from) are forbidden but do not block their neighbours.
        Greedy uniform placement, retried when it paints itself into a corner.
        """
        rng = self.np_random if rng is None else rng
        span = self._span()
        base = np.zeros((span + 2, span + 2), dtype=bool)  # padded [x + 1, y + 1]

        def block(grid, cell):
            x, y = int(cell[0]) + 1, int(cell[1]) + 1
            grid[x, y] = True
            grid[x - 1, y] = grid[x + 1, y] = grid[x, y - 1] = grid[x, y + 1] = True

        for cell in keep:
            block(base, cell)
        for cell in list(avoid) + list(exclude):
            if cell is not None and 0 <= cell[0] < span and 0 <= cell[1] < span:
                base[int(cell[0]) + 1, int(cell[1]) + 1] = True
        for _ in range(PLACEMENT_ATTEMPTS):
            grid = base.copy()
            placed = []
            for _ in range(n):
                free = np.argwhere(~grid[1:-1, 1:-1])
                if len(free) == 0:
                    break
                cell = free[rng.integers(len(free))]
                placed.append(cell)
                block(grid, cell)
            if len(placed) == n:
                return np.array(placed, dtype=int).reshape(n, 2)
        # Cornered every time: one colour of the chessboard never touches itself,
        # and below ``capacity`` the larger colour of the free cells holds n.
        free = np.argwhere(~base[1:-1, 1:-1])
        colour = free.sum(axis=1) % 2
        cells = free[colour == np.argmax(np.bincount(colour, minlength=2))]
        if len(cells) < n:  # not reached below capacity (see config.unsafe_capacity)
            raise RuntimeError(f"could not place {n} unsafe states apart from {len(keep)} others on the "
                               f"{span}x{span} placement area")
        return cells[np.sort(rng.choice(len(cells), size=n, replace=False))]

    # -- the Gymnasium API ----------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start an episode: a new start and goal, the unsafe states kept.

        Parameters
        ----------
        seed : int, optional
            Reseeds the generator that draws starts and goals.  On a world
            made without a seed, the first reset draws the whole world from
            it, unsafe states included, so that ``reset(seed=s)`` on a fresh
            ``gymnasium.make("sarsp_edu/SafeGridWorld-v0")`` is always the
            same world, as Gymnasium users expect.
        options : dict, optional
            ``{"start": (x, y), "goal": (x, y)}`` to fix either (both must be
            safe, on the grid, and distinct); used to pair runs.
        """
        super().reset(seed=seed)
        if not self._layout_fixed and seed is not None:
            self._draw_world()
            # the world took its draws from the seed; the start and goal come from a fresh stream of it, as on
            # every later reset(seed=seed): the same seed, the same episode, the first time too
            super().reset(seed=seed)
        self._layout_fixed = True  # later resets keep the unsafe states (the paper's design)
        options = dict(options or {})
        unknown = set(options) - {"start", "goal"}
        if unknown:
            raise ValueError(f"options may hold 'start' and 'goal' only, got {sorted(unknown)}")
        drawn_start, drawn_goal = self._draw_start_goal(self._unsafe)
        start, goal = drawn_start, drawn_goal
        if "start" in options:
            start = self._checked_cell("start", options["start"])
            if "goal" not in options and goal == start:
                goal = drawn_start  # the two drawn cells differ, so this one is free
        if "goal" in options:
            goal = self._checked_cell("goal", options["goal"])
            if "start" not in options and start == goal:
                start = drawn_goal
        if start == goal:
            raise ValueError(f"start and goal must differ, got both {start}")
        self._start, self._goal, self._agent = start, goal, start
        self._steps = 0
        self._done = False
        observation = self._observation()
        info = {"distance_to_unsafe": float(observation[7]), "start": start, "goal": goal}
        return observation, info

    def _checked_cell(self, name, cell):
        whole = (isinstance(cell, (tuple, list, np.ndarray)) and len(cell) == 2
                 and all(isinstance(v, (numbers.Integral, np.integer)) and not isinstance(v, (bool, np.bool_))
                         for v in cell))
        if not whole:
            raise ValueError(f"{name} must be a pair of integers (x, y), got {name}={cell!r}")
        x, y = (int(v) for v in cell)
        if not (0 <= x < self.size and 0 <= y < self.size):
            raise ValueError(f"{name} must lie on the grid, 0 <= x, y < {self.size}, got {name}={cell!r}")
        if np.any(np.all(self._unsafe == (x, y), axis=1)):
            raise ValueError(f"{name} must not be an unsafe state, got {name}={cell!r}")
        return (x, y)

    def step(self, action):
        """Move one cell; returns ``(observation, reward, terminated, truncated, info)``."""
        if isinstance(action, np.ndarray) and action.shape == () and np.issubdtype(action.dtype, np.integer):
            action = action.item()  # a 0-d integer array, which action_space.contains accepts
        if (isinstance(action, (bool, np.bool_)) or not isinstance(action, (numbers.Integral, np.integer))
                or not 0 <= action < 4):
            raise ValueError(
                f"action must be an integer in 0..3 (RIGHT, DOWN, LEFT, UP), got action={action!r}"
            )
        if self._done:
            raise RuntimeError("the episode has ended (or not begun): call reset() before step()")
        x, y = moved(self._agent, action, self.size)
        self._agent = (x, y)
        self._steps += 1
        observation = self._observation()
        distance = float(observation[7])
        reward = goal_reward((x, y), self._goal)
        terminated = self._agent == self._goal
        truncated = not terminated and self._steps >= self.max_steps
        self._done = terminated or truncated
        info = {
            "distance_to_unsafe": distance,
            "cost": int(distance < self.d),
            "task_completed": terminated,
            "steps": self._steps,
        }
        return observation, reward, terminated, truncated, info

    # -- the covariate shift -----------------------------------------------
    def shift(self, n_switch_states: int, rng=None) -> np.ndarray:
        """Move ``n_switch_states`` unsafe states, chosen at random, to new cells.

        The covariate shift of paper section 5.4 (``nss``): the moved states
        land on cells that obey the spacing rules with respect to the states
        that stay and to each other, avoid the current start, goal and agent,
        and differ from the cells they leave.  The other states do not move.

        Parameters
        ----------
        n_switch_states : int
            From 0 to ``n_unsafe``.
        rng : None, int or numpy.random.Generator
            Default: the environment's own generator.

        Returns
        -------
        ndarray of int
            The indices of the moved states (also in ``moved_indices``).
        """
        n_switch_states = check_switch_states(n_switch_states, self.n_unsafe)
        rng = self.np_random if rng is None else as_generator(rng)
        moved = np.sort(rng.choice(self.n_unsafe, size=int(n_switch_states), replace=False))
        stay = np.setdiff1d(np.arange(self.n_unsafe), moved)
        old = self._unsafe[moved]
        new = self._place(
            len(moved), self._unsafe[stay], [self._start, self._goal, self._agent], rng=rng, exclude=old
        )
        unsafe = self._unsafe.copy()
        unsafe[moved] = new
        self._unsafe = unsafe
        self._moved, self._moved_from = moved, old
        return moved.copy()

    # -- drawing -------------------------------------------------------------
    def layout(self) -> GridLayout:
        """A snapshot of the world for :func:`sarsp_edu.teaching.plotting.plot_gridworld`."""
        return GridLayout(
            size=self.size,
            unsafe_states=self._unsafe.copy(),
            start=self._start,
            goal=self._goal,
            agent=self._agent,
            moved=self._moved.copy(),
            moved_from=self._moved_from.copy(),
            d=self.d,
        )
