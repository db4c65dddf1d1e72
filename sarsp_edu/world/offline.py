"""Offline data: a uniform random policy's transitions, and injected outliers.

Paper sections 5.2-5.3.  Before deployment the agent learns from 100
episodes of a uniform random policy.  Each transition feeds two training sets:

- the cost model's, inputs ``(action, x, y, nearest-unsafe x, y)`` and target
  the distance to the nearest unsafe state after the step, at most 12 copies
  of one input;
- the reward model's, inputs ``(action, x, y, goal x, y)`` and target the
  reward after the step, at most 1 copy of one input.

Outliers (section 5.3): ``k = round(p * N)`` rows drawn uniformly without
replacement (``N`` = the smaller buffer's size), whose inputs *and* targets
are multiplied by ``m``; the same rows in both buffers.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .._internal.rng import as_generator
from .._internal.validation import LARGEST, check_choice, check_fraction, check_int, check_positive
from ..config import COST_DUPLICATES, OFFLINE_EPISODES, OUTLIER_MODELS, REWARD_DUPLICATES
from .gridworld import ACTIONS, AGENT_XY, GOAL_XY, NEAREST_UNSAFE_XY

__all__ = [
    "ObservationBuffer", "OfflineData", "collect_offline_data", "inject_outliers", "cost_inputs", "reward_inputs",
]



# --------------------------------------------------------------------------
# the models' inputs
# --------------------------------------------------------------------------
def _model_inputs(observation, actions, position_columns: slice) -> np.ndarray:
    observation = np.asarray(observation, dtype=float)
    actions = ACTIONS if actions is None else np.atleast_1d(np.asarray(actions, dtype=float))
    out = np.empty((actions.shape[0], 5))
    out[:, 0] = actions
    out[:, 1:3] = observation[AGENT_XY]
    out[:, 3:5] = observation[position_columns]
    return out


def cost_inputs(observation, actions=None) -> np.ndarray:
    """Cost-model inputs ``(action, agent x, agent y, nearest-unsafe x, nearest-unsafe y)``.

    The reference implementation's cost model: its target is the distance to
    the nearest unsafe state *after* the step.

    Parameters
    ----------
    observation : array-like of shape (8,)
        An observation of :class:`SafeGridWorld`.
    actions : int or array-like of ints, optional
        Default: all four actions.

    Returns
    -------
    ndarray of shape (n_actions, 5)
    """
    return _model_inputs(observation, actions, NEAREST_UNSAFE_XY)


def reward_inputs(observation, actions=None) -> np.ndarray:
    """Reward-model inputs ``(action, agent x, agent y, goal x, goal y)``.

    The target is the reward after the step (minus the L2 distance to the goal).

    Parameters
    ----------
    observation : array-like of shape (8,)
        An observation of :class:`SafeGridWorld`.
    actions : int or array-like of ints, optional
        Default: all four actions.

    Returns
    -------
    ndarray of shape (n_actions, 5)
    """
    return _model_inputs(observation, actions, GOAL_XY)


class ObservationBuffer:
    """A growing training set ``(X, y)`` that caps how often one input may appear.

    Parameters
    ----------
    n_features : int
    max_duplicates : int or None
        At most this many rows may share one input (``None``: no cap).

    Notes
    -----
    Inputs are matched exactly (the grid's inputs are whole numbers).  An
    index from input to rows makes ``add``, ``count`` and ``overwrite`` O(1)
    per call, which the agent's online update relies on.

    Examples
    --------
    >>> buffer = ObservationBuffer(2, max_duplicates=1)
    >>> buffer.add([0, 1], 3.0), buffer.add([0, 1], 4.0), len(buffer)
    (True, False, 1)
    >>> buffer.overwrite([0, 1], 5.0), float(buffer.y[0])
    (1, 5.0)
    """

    def __init__(self, n_features: int, max_duplicates: int | None = None, capacity: int = 1024):
        self.n_features = check_int("n_features", n_features, 1)
        self.max_duplicates = check_int("max_duplicates", max_duplicates, 1, allow_none=True)
        self._X = np.empty((max(int(capacity), 1), self.n_features))
        self._y = np.empty(max(int(capacity), 1))
        self._n = 0
        self._rows: dict[bytes, list[int]] = {}
        self._row_arrays: dict[bytes, np.ndarray] = {}  # rows_of's arrays, dropped when their input gains a row

    def __len__(self) -> int:
        return self._n

    @property
    def X(self) -> np.ndarray:
        """Inputs, ndarray of shape (n, n_features) (a read-only view)."""
        view = self._X[: self._n]
        view.flags.writeable = False
        return view

    @property
    def y(self) -> np.ndarray:
        """Targets, ndarray of shape (n,) (a read-only view)."""
        view = self._y[: self._n]
        view.flags.writeable = False
        return view

    def _key(self, x) -> bytes:
        x = np.asarray(x, dtype=float).reshape(-1)
        if x.shape[0] != self.n_features:
            raise ValueError(f"x must have {self.n_features} features, got {x.shape[0]}")
        return (x + 0.0).tobytes()  # + 0.0 folds -0.0 into 0.0

    def rows_of(self, x) -> np.ndarray:
        """Indices of the rows whose input equals ``x`` (a read-only array, kept until ``x`` gains a row)."""
        key = self._key(x)
        rows = self._row_arrays.get(key)
        if rows is None:  # the agent asks for the same few inputs at every decision
            rows = np.array(self._rows.get(key, []), dtype=int)
            rows.flags.writeable = False
            self._row_arrays[key] = rows
        return rows

    def count(self, x) -> int:
        """How many rows hold input ``x``."""
        return len(self._rows.get(self._key(x), ()))

    def add(self, x, target: float) -> bool:
        """Append ``(x, target)`` unless ``x`` already fills its duplicate cap.

        Parameters
        ----------
        x : array-like of shape (n_features,)
            The input.
        target : float

        Returns
        -------
        bool
            Whether the row was added.
        """
        key = self._key(x)
        rows = self._rows.setdefault(key, [])
        if self.max_duplicates is not None and len(rows) >= self.max_duplicates:
            return False
        if self._n == self._X.shape[0]:
            self._X = np.concatenate([self._X, np.empty_like(self._X)])
            self._y = np.concatenate([self._y, np.empty_like(self._y)])
        self._X[self._n] = np.frombuffer(key)
        self._y[self._n] = float(target)
        rows.append(self._n)
        self._n += 1
        self._row_arrays.pop(key, None)
        return True

    def overwrite(self, x, target: float) -> int:
        """Set the target of every row with input ``x``; returns how many rows changed.

        Algorithm 1's corrective update: the observed cost replaces what the
        offline data said about this state-action pair.

        Parameters
        ----------
        x : array-like of shape (n_features,)
            The input.
        target : float
            The new target of each of those rows.
        """
        rows = self._rows.get(self._key(x), [])
        self._y[rows] = float(target)
        return len(rows)

    def update(self, x, target: float) -> str:
        """Overwrite the rows with input ``x``, or add one if there is none.

        Returns ``"overwritten"`` when a stored target changed,
        ``"unchanged"`` when every row with input ``x`` already held
        ``target`` (nothing to learn), or ``"added"``.  (A new input is
        always under its cap, so the add cannot be refused.)

        Parameters
        ----------
        x : array-like of shape (n_features,)
            The input.
        target : float
        """
        rows = self._rows.get(self._key(x), [])
        if not rows:
            self.add(x, target)
            return "added"
        if np.all(self._y[rows] == float(target)):
            return "unchanged"
        self._y[rows] = float(target)
        return "overwritten"

    def copy(self) -> "ObservationBuffer":
        """An independent copy: the same rows, caps and index."""
        other = ObservationBuffer(self.n_features, self.max_duplicates, capacity=max(self._n, 1))
        other._X[: self._n] = self._X[: self._n]
        other._y[: self._n] = self._y[: self._n]
        other._n = self._n
        other._rows = {k: list(v) for k, v in self._rows.items()}
        return other

    def scaled(self, rows, factor: float, inputs: bool = True) -> "ObservationBuffer":
        """A copy whose ``rows`` have inputs and targets (or the targets alone) multiplied by ``factor``.

        Parameters
        ----------
        rows : array-like of int
            Row indices (as :func:`inject_outliers` draws them).
        factor : float
            The multiplier (the outliers' magnitude ``m``).
        inputs : bool, default True
            Scale the rows' inputs too (False: the targets alone, at their clean inputs).
        """
        other = self.copy()
        rows = np.asarray(rows, dtype=int)
        other._y[rows] *= factor
        if inputs:
            other._X[rows] *= factor
            other._reindex()
        return other

    def _reindex(self):
        """Rebuild the input -> rows index from the stored inputs, as ``add`` would have built it."""
        X = np.ascontiguousarray(self._X[: self._n] + 0.0)  # + 0.0 folds -0.0, as _key does
        keys = X.view(np.dtype((np.void, X.dtype.itemsize * self.n_features))).ravel()
        unique, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
        rows = np.split(np.argsort(inverse, kind="stable"), np.cumsum(np.bincount(inverse))[:-1])
        # keys in order of first appearance, rows ascending: the same dict a loop over the rows gives
        self._rows = {unique[u].tobytes(): rows[u].tolist() for u in np.argsort(first)}
        self._row_arrays = {}

    def __repr__(self) -> str:
        return f"ObservationBuffer(n={self._n}, n_features={self.n_features}, max_duplicates={self.max_duplicates})"


@dataclass
class OfflineData:
    """The two training sets of the offline phase.

    Attributes
    ----------
    cost : ObservationBuffer
        Inputs ``(action, x, y, nearest-unsafe x, y)``, target the distance to
        the nearest unsafe state after the step.
    reward : ObservationBuffer
        Inputs ``(action, x, y, goal x, y)``, target the reward after the step.
    episodes : int
    transitions : int
        Transitions collected, before the duplicate caps.
    visits : ndarray of shape (size, size)
        How often the random policy stood on each cell, indexed [y, x].
    outlier_indices : ndarray of int
        Rows changed by :func:`inject_outliers` (empty for clean data).
    outlier_magnitude, outlier_proportion : float or None
    outliers_in : tuple of str
        Which buffers hold the outliers: ``"cost"``, ``"reward"``.
    """

    cost: ObservationBuffer
    reward: ObservationBuffer
    episodes: int
    transitions: int
    visits: np.ndarray
    outlier_indices: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=int))
    outlier_magnitude: float | None = None
    outlier_proportion: float | None = None
    outliers_in: tuple = ()

    def copy(self) -> "OfflineData":
        """A copy whose buffers and arrays are copies too, so changing it leaves this one as it is."""
        return replace(
            self,
            cost=self.cost.copy(),
            reward=self.reward.copy(),
            visits=self.visits.copy(),
            outlier_indices=self.outlier_indices.copy(),
        )


def collect_offline_data(
    env,
    episodes: int = OFFLINE_EPISODES,
    rng=None,
    *,
    cost_duplicates: int | None = COST_DUPLICATES,
    reward_duplicates: int | None = REWARD_DUPLICATES,
) -> OfflineData:
    """Run a uniform random policy and keep its transitions (paper section 5.2).

    Parameters
    ----------
    env : SafeGridWorld
        The world before the shift.  Its episodes are reset with seeds drawn
        from ``rng``, so the data depend only on the world and ``rng``.
    episodes : int, default 100
    rng : None, int or numpy.random.Generator
        Chooses the actions and seeds the resets.
    cost_duplicates, reward_duplicates : int or None, default 12 and 1
        The duplicate caps of the two buffers (the reference implementation's).

    Returns
    -------
    OfflineData
    """
    episodes = check_int("episodes", episodes, 1)
    rng = as_generator(rng)
    env = getattr(env, "unwrapped", env)
    cost = ObservationBuffer(5, cost_duplicates, capacity=8192)
    reward = ObservationBuffer(5, reward_duplicates, capacity=8192)
    visits = np.zeros((env.size, env.size), dtype=int)
    transitions = 0
    for _ in range(episodes):
        observation, _ = env.reset(seed=int(rng.integers(2**31 - 1)))
        done = False
        while not done:
            action = int(rng.integers(4))
            x_cost = cost_inputs(observation, action)[0]
            x_reward = reward_inputs(observation, action)[0]
            visits[int(observation[1]), int(observation[0])] += 1
            observation, r, terminated, truncated, info = env.step(action)
            cost.add(x_cost, info["distance_to_unsafe"])
            reward.add(x_reward, r)
            transitions += 1
            done = terminated or truncated
    return OfflineData(cost=cost, reward=reward, episodes=episodes, transitions=transitions, visits=visits)


def inject_outliers(
    data: OfflineData,
    magnitude: float,
    proportion: float,
    rng=None,
    cost: bool = True,
    reward: bool = True,
    scaled: str = "inputs-and-targets",
) -> OfflineData:
    """Multiply the inputs and targets of ``round(p * N)`` random rows by ``m`` (paper section 5.3).

    Parameters
    ----------
    data : OfflineData
        Clean data; it is not changed.
    magnitude : float
        ``m`` (> 0); the paper uses 40, 60 and 80.
    proportion : float
        ``p`` in [0, 1]; the paper uses 0.2, 0.3 and 0.4.
    rng : None, int or numpy.random.Generator
    cost, reward : bool, default True
        Which buffers get the outliers (the paper: both).  The same row
        indices are used in each.
    scaled : {"inputs-and-targets", "targets"}, default "inputs-and-targets"
        What is multiplied: a row's inputs and targets (the paper's text and
        the reference code: a far-away, high-leverage row), or its targets
        alone, at its clean inputs (the outliers a Student-t likelihood is
        made for).  The rows drawn are the same either way.

    Returns
    -------
    OfflineData
        A new object; ``outlier_indices`` lists the changed rows.

    Notes
    -----
    ``N`` is the size of the smaller buffer, so every drawn index exists in
    both.  ``round`` is Python's (halves go to the even number).
    """
    m = check_positive("magnitude", magnitude)
    p = check_fraction("proportion", proportion)
    if not (cost or reward):
        raise ValueError("at least one of cost and reward must be True, got cost=False, reward=False")
    check_choice("scaled", scaled, OUTLIER_MODELS)
    inputs = scaled == "inputs-and-targets"
    if len(data.outlier_indices):
        raise ValueError("data already holds outliers: inject them into the clean data once")
    largest = max(float(np.max(np.abs(buffer.X), initial=0.0)) + float(np.max(np.abs(buffer.y), initial=0.0))
                  for buffer in (data.cost, data.reward))
    if not np.isfinite(m * largest) or m * largest > LARGEST:
        raise ValueError(
            f"magnitude={magnitude!r} times the data's largest value ({largest:.3g}) overflows float64 once the "
            f"models square it; use a magnitude below {LARGEST / max(largest, 1.0):.0e} (the paper's are 40, 60 and 80)"
        )
    rng = as_generator(rng)
    N = min(len(data.cost), len(data.reward))
    k = int(round(p * N))
    rows = np.sort(rng.choice(N, size=k, replace=False))
    return replace(
        data,
        cost=data.cost.scaled(rows, m, inputs) if cost else data.cost.copy(),
        reward=data.reward.scaled(rows, m, inputs) if reward else data.reward.copy(),
        visits=data.visits.copy(),
        outlier_indices=rows,
        outlier_magnitude=m,
        outlier_proportion=p,
        outliers_in=tuple(name for name, flag in (("cost", cost), ("reward", reward)) if flag),
    )
