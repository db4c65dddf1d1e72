"""What a run needs before its agent: the world, the offline data, the outliers, the shift, the seeds.

Every random choice comes from a stream spawned from ``config.seed`` for its
purpose (world, offline data, outliers, shift, episodes, agent); none depends
on the model, so the TP and the GP runs of a config are paired by
construction.  :func:`offline_world` is the slow, model-free part, which the
tutorials' dashboards cache per seed.
"""

from __future__ import annotations

import copy
import time
from dataclasses import dataclass

import numpy as np

from ..config import ExperimentConfig
from .gridworld import GridLayout, SafeGridWorld
from .offline import OfflineData, collect_offline_data, inject_outliers

__all__ = ["PREPARATION_FIELDS", "Prepared", "offline_world", "prepare"]

#: the ExperimentConfig fields a preparation reads: two configs that differ in
#: none of them (only in the model or the agent's settings) share one world,
#: one shift, one offline data set and one sequence of episodes
PREPARATION_FIELDS = (
    "seed", "grid_size", "n_unsafe", "d", "max_steps", "placement", "offline_episodes", "cost_duplicates",
    "reward_duplicates", "outlier_magnitude", "outlier_proportion", "outliers", "cost_outliers", "reward_outliers",
    "n_switch_states", "episodes",
)

_STREAMS = ("world", "offline", "outliers", "shift", "episodes", "agent")



def _streams(seed: int) -> dict:
    children = np.random.SeedSequence(seed).spawn(len(_STREAMS))
    return {name: np.random.default_rng(child) for name, child in zip(_STREAMS, children)}


@dataclass
class Prepared:
    """What paired runs share: the world after the shift, the offline data, the episodes' and agent's seeds.

    Attributes
    ----------
    env : SafeGridWorld
        The world after the covariate shift (each run steps a copy).
    data : OfflineData
        The offline data, with its outliers.
    episode_seeds : ndarray of int
        One seed per episode (starts and goals).
    agent_seed : int
    seconds : float
        How long the preparation took.
    clean_data : OfflineData
        The offline data before the outliers were injected.
    layout_before : GridLayout
        The world before the shift, as the offline data saw it.
    """

    env: SafeGridWorld
    data: OfflineData
    episode_seeds: np.ndarray
    agent_seed: int
    seconds: float
    clean_data: OfflineData
    layout_before: GridLayout


def offline_world(config: ExperimentConfig) -> tuple[SafeGridWorld, OfflineData]:
    """The world before the shift and its clean offline data, as :func:`prepare` builds them.

    This is the part of a preparation that the outliers and the shift leave
    alone (it depends on the seed, the grid and the offline settings only),
    and the slow part: a dashboard whose sliders move m, p or nss computes it
    once per seed and hands it to :func:`prepare`.
    """
    rngs = _streams(config.seed)
    env = SafeGridWorld(**config.world_settings.env_kwargs(), seed=rngs["world"])
    data_settings = config.data_settings
    data = collect_offline_data(
        env,
        data_settings.offline_episodes,
        rng=rngs["offline"],
        cost_duplicates=data_settings.cost_duplicates,
        reward_duplicates=data_settings.reward_duplicates,
    )
    return env, data


def prepare(config: ExperimentConfig, offline: tuple | None = None) -> Prepared:
    """Build what a run of ``config`` needs before the agent: world, offline data, outliers, shift.

    Every random choice comes from a stream of ``config.seed`` spawned for its
    purpose, none from the model: the TP and the GP runs of a config share
    all of it (see :func:`paired_experiments`).

    Parameters
    ----------
    config : ExperimentConfig
    offline : (SafeGridWorld, OfflineData), optional
        What :func:`offline_world` returned for a config that differs from
        ``config`` at most in the outliers, the shift, the model and the
        agent's settings; it is copied, not changed.  By default it is computed.
    """
    start = time.perf_counter()
    rngs = _streams(config.seed)
    if offline is None:
        env, clean = offline_world(config)
    else:
        env, clean = copy.deepcopy(offline[0]), offline[1]
        if (env.size, env.n_unsafe, env.placement) != (config.grid_size, config.n_unsafe, config.placement):
            raise ValueError(
                f"offline holds a {env.size}x{env.size} world with {env.n_unsafe} unsafe states and placement="
                f"{env.placement!r}, but config asks for grid_size={config.grid_size}, n_unsafe={config.n_unsafe}, "
                f"placement={config.placement!r}; compute it with offline_world(config)"
            )
    layout_before = env.layout()
    data = clean
    if config.outlier_proportion > 0 and (config.cost_outliers or config.reward_outliers):
        data = inject_outliers(
            clean,
            config.outlier_magnitude,
            config.outlier_proportion,
            rng=rngs["outliers"],
            cost=config.cost_outliers,
            reward=config.reward_outliers,
            scaled=config.outliers,
        )
    env.shift(config.n_switch_states, rng=rngs["shift"])
    episode_seeds = rngs["episodes"].integers(2**31 - 1, size=config.episodes)
    agent_seed = int(rngs["agent"].integers(2**63 - 1))
    return Prepared(env, data, episode_seeds, agent_seed, time.perf_counter() - start, clean, layout_before)
