"""One experiment of the paper, run as the paper runs it.

``ExperimentConfig -> run_experiment -> ExperimentResult`` (per-episode records and a summary); ``compare`` runs
the TP and the GP *paired* on the same world, shift, offline data, outliers and episode starts and goals, and
applies the paper's preference criterion (Definition 4).  The settings live in :mod:`sarsp_edu.config`, the metrics
in :mod:`sarsp_edu.experiments.metrics`, the results and their files in :mod:`sarsp_edu.experiments.results`; their
names are importable from here too.

Every random choice comes from streams spawned from ``config.seed`` by purpose (world, offline data, outliers,
shift, episodes, agent); none depends on the model, so a TP run and a GP run with the same seed are paired by
construction, and the same seed gives the same numbers in any process.
"""

from __future__ import annotations

import copy
import math
import time
from dataclasses import dataclass

import numpy as np
import pandas as pd

from .._internal.threads import one_blas_thread
from ..agent.sarsp import Decision, LearnOutcome, SARSPAgent
from ..config import DEFINITION_4_A, ExperimentConfig, config_or_default
from ..models.processes.factory import make_model
from ..models.processes.summary import fit_summary
from ..world.preparation import Prepared, prepare
from .metrics import RECORD_COLUMNS, check_a, running_metrics
from .results import Comparison, ExperimentResult

__all__ = [
    "Experiment",
    "StepRecord",
    "make_model",
    "experiments_on_one_world",
    "each_experiment_on_one_world",
    "paired_experiments",
    "run_experiment",
    "compare",
]


#: positions at the end of an episode inspected for a trap (``final_cells``)
FINAL_WINDOW = 10


@dataclass
class StepRecord:
    """One agent step, as the live dashboard shows it."""

    episode: int
    t: int
    position: tuple
    next_position: tuple
    action: int
    decision: Decision
    reward: float
    info: dict
    outcome: LearnOutcome
    done: bool


class Experiment:
    """One run, advanced step by step or episode by episode.

    ``run_experiment`` drives it to the end; the live dashboard drives it a step at a time.  Construction collects
    the offline data, injects the outliers, fits both models and shifts the world.  ``parts`` (a
    :class:`~sarsp_edu.agent.parts.DecisionParts`) gives the agent other functions to assemble its decisions from
    (:class:`~sarsp_edu.agent.sarsp.SARSPAgent`).
    """

    def __init__(self, config: ExperimentConfig, *, prepared: Prepared | None = None, fit=None, parts=None):
        if not isinstance(config, ExperimentConfig):
            raise TypeError(f"config must be an ExperimentConfig, got {type(config).__name__}")
        if fit is not None and not callable(fit):
            raise TypeError(f"fit must be a function fit(agent) that fits the agent's models, or None (the agent's "
                            f"own fit), got {fit!r}")
        self.config = config
        prepared = prepare(config) if prepared is None else prepared
        self.env = copy.deepcopy(prepared.env)
        self.data = prepared.data
        self._episode_seeds = prepared.episode_seeds
        self.agent = SARSPAgent(make_model(config), make_model(config, "reward"), prepared.data,
                                config.agent_settings, parts=parts, rng=prepared.agent_seed)
        start = time.perf_counter()
        with one_blas_thread():  # fit: a function that gives the agent its fitted models (the fit cache's)
            self.agent.fit() if fit is None else fit(self.agent)
        self.timings = {"data_seconds": prepared.seconds, "offline_fit_seconds": time.perf_counter() - start,
                        "episode_seconds": 0.0, "retrain_seconds": 0.0}
        #: the offline fits' hyperparameters (:func:`~sarsp_edu.models.processes.summary.fit_summary`)
        self.fits = {"offline": {"cost": fit_summary(self.agent.cost_model),
                                 "reward": fit_summary(self.agent.reward_model)}}
        #: True when loaded from the fit cache (:mod:`sarsp_edu.teaching.live.fitcache`): fitted before, same settings
        self.loaded_from_cache = False
        self.act_seconds: list[float] = []  # one decision (both models, 4 actions)
        self.step_seconds: list[float] = []  # decision, environment step and learn (with any retrain)
        self.episodes: list[dict] = []
        self._observation = None
        self.trajectory: list[tuple] = []

    @property
    def finished(self) -> bool:
        return len(self.episodes) >= self.config.episodes

    def _begin_episode(self):
        seed = int(self._episode_seeds[len(self.episodes)])
        self._observation, _ = self.env.reset(seed=seed)
        self._episode = {
            "start": self.env.start,
            "goal": self.env.goal,
            "reward": 0.0,
            "cost": 0,
            "steps": 0,
            "sq_reward_errors": [],
            "abs_cost_errors": [],
            "safe_variances": [],
            "backups": 0,
            "t0": time.perf_counter(),
        }
        self.trajectory = [self.env.agent_position]

    def step(self) -> StepRecord:
        """Advance one agent step (starting an episode if none is running)."""
        if self.finished:
            raise RuntimeError(f"the run has finished its {self.config.episodes} episodes")
        if self._observation is None:
            self._begin_episode()
        observation = self._observation
        position = self.env.agent_position
        start = time.perf_counter()
        action, decision = self.agent.act(observation)
        self.act_seconds.append(time.perf_counter() - start)
        next_observation, reward, terminated, truncated, info = self.env.step(action)
        outcome = self.agent.learn(observation, action, info, decision)
        self.step_seconds.append(time.perf_counter() - start)
        if outcome.retrained:
            self.timings["retrain_seconds"] += outcome.retrain_seconds

        ep = self._episode
        ep["reward"] += reward
        ep["cost"] += info["cost"]
        ep["steps"] += 1
        ep["sq_reward_errors"].append((decision.mu_reward[action] - reward) ** 2)
        ep["abs_cost_errors"].append(abs(decision.mu_cost[action] - info["distance_to_unsafe"]))
        if decision.backup:
            ep["backups"] += 1
        else:
            ep["safe_variances"].append(decision.var_cost[action])
        self.trajectory.append(self.env.agent_position)
        done = terminated or truncated
        record = StepRecord(
            episode=len(self.episodes) + 1,
            t=ep["steps"],
            position=position,
            next_position=self.env.agent_position,
            action=action,
            decision=decision,
            reward=reward,
            info=info,
            outcome=outcome,
            done=done,
        )
        self._observation = next_observation
        if done:
            self._end_episode(terminated)
        return record

    def _end_episode(self, completed: bool):
        ep = self._episode
        self.timings["episode_seconds"] += time.perf_counter() - ep["t0"]
        self.episodes.append(
            {
                "episode_reward": ep["reward"],
                "episode_cost": ep["cost"],
                "episode_steps": ep["steps"],
                "task_completed": bool(completed),
                "start": ep["start"],
                "goal": ep["goal"],
                "reward_mse": float(np.mean(ep["sq_reward_errors"])),
                "cost_prediction_error": float(np.mean(ep["abs_cost_errors"])),
                "safe_action_variance": float(np.mean(ep["safe_variances"])) if ep["safe_variances"] else math.nan,
                "backup_rate": ep["backups"] / ep["steps"],
                "corrective_updates": self.agent.corrective_updates,
                "retrains": self.agent.retrains,
                "final_cells": len(set(self.trajectory[-FINAL_WINDOW:])),
            }
        )
        self._observation = None

    def run_episode(self) -> dict:
        """Run steps until the current episode ends; returns its log."""
        with one_blas_thread():
            while True:
                if self.step().done:
                    return self.episodes[-1]

    def records(self) -> pd.DataFrame:
        """Per-episode records so far (the columns of ``RECORD_COLUMNS``)."""
        if not self.episodes:
            return pd.DataFrame(columns=list(RECORD_COLUMNS))
        logs = pd.DataFrame(self.episodes)
        running = running_metrics(
            logs["episode_reward"], logs["episode_cost"], logs["episode_steps"], logs["task_completed"]
        )
        table = pd.concat([running, logs], axis=1)
        table.insert(0, "episode", np.arange(1, len(table) + 1))
        return table[list(RECORD_COLUMNS)]

    def result(self) -> "ExperimentResult":
        """The run so far: its records, and its timings with the median act and step seconds and the step count."""
        records = self.records()
        timings = dict(self.timings)
        if self.act_seconds:
            timings["median_act_seconds"] = float(np.median(self.act_seconds))
            timings["median_step_seconds"] = float(np.median(self.step_seconds))
        timings["steps"] = len(self.act_seconds)
        fits = {**self.fits, "final": {"cost": fit_summary(self.agent.cost_model)}}
        return ExperimentResult(self.config, records, timings, fits=fits)


class _NoProgress:
    """What ``_progress`` gives when no bar is wanted: a context manager whose ``update`` does nothing."""

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> bool:
        return False

    def update(self, n: int = 1) -> None:
        pass


def _progress(total: int | None, desc: str, enabled: bool, unit: str = "episode", position: int = 0):
    """A tqdm bar, or a stand-in that does nothing.

    Even a disabled tqdm bar creates a multiprocessing lock, which a sweep's worker stopped by Ctrl-C would leave
    behind (with a warning); quiet runs create none.
    """
    if not enabled:
        return _NoProgress()
    from tqdm.auto import tqdm

    return tqdm(total=total, desc=desc, unit=unit, leave=False, position=position)


def _fit_showing_progress(config: ExperimentConfig, progress: bool, position: int = 0):
    """A ``fit`` for :class:`Experiment` that shows the offline fits' progress, step by step of the search;
    None (the agent's own fit) without ``progress``."""
    if not progress:
        return None

    def fit(agent):
        steps = config.offline_fit_steps
        rows = len(agent.cost_data) if agent.cost_fit_points is None else min(agent.cost_fit_points,
                                                                               len(agent.cost_data))
        desc = f"{config.model.upper()}: fitting the cost model ({rows} rows) and the reward model"
        with _progress(steps, desc, True, unit="step", position=position) as bar:
            agent.fit(fit_model=lambda model, X, y: model.fit(X, y, on_step=bar.update))
    return fit


def _finish(experiment: "Experiment", progress: bool, position: int = 0) -> ExperimentResult:
    """Run ``experiment``'s remaining episodes; its result."""
    config = experiment.config
    with one_blas_thread(), _progress(config.episodes, f"{config.model.upper()} episodes", progress,
                                      position=position) as bar:
        while not experiment.finished:
            experiment.run_episode()
            bar.update(1)
    return experiment.result()


def experiments_on_one_world(config: ExperimentConfig, sides: dict, *, cache=None,
                             progress: bool = False, parts: dict | None = None) -> dict:
    """Experiments of ``config`` with some settings changed, all on one prepared world: name -> :class:`Experiment`.

    Every experiment shares the world, its shift, the offline data with its outlier rows, the sequence of episode
    starts and goals and the agent's seed (:func:`prepare` builds them once), so that the runs differ only in what
    ``sides`` changes: the model, or a setting of the agent.

    Parameters
    ----------
    config : ExperimentConfig
    sides : dict
        Name -> the ``ExperimentConfig`` fields to change for that experiment, e.g. ``{"tp": {"model": "tp"},
        "gp": {"model": "gp"}}``.  A field that the preparation reads (``PREPARATION_FIELDS``) cannot differ
        between sides: change it in ``config``.
    cache : optional
        Where fits are kept between runs: anything with ``load(config, prepared)`` (an :class:`Experiment`, or None
        when it has none) and ``store(experiment)``, as the live dashboards' fit cache
        (:mod:`sarsp_edu.teaching.live.fitcache`) has.  None: every side is fitted here.
    progress : bool, default False
        Show each side's offline fits as a progress bar.
    parts : dict, optional
        Name -> the :class:`~sarsp_edu.agent.parts.DecisionParts` (or a mapping of some parts) of that side's agent,
        e.g. ``{"yours": student_parts}``; a side not named uses the package's own.  A fit does not depend on the
        parts: a side loaded from the cache gets them as well.
    """
    return dict(each_experiment_on_one_world(config, sides, cache=cache, progress=progress, parts=parts))


def each_experiment_on_one_world(config: ExperimentConfig, sides: dict, *, cache=None,
                                 progress: bool = False, parts: dict | None = None):
    """:func:`experiments_on_one_world` one experiment at a time: yields ``(name, Experiment)`` as each is fitted.

    The live dashboard starts a side as soon as its models are fitted, while the other's are still fitting.

    Parameters
    ----------
    config : ExperimentConfig
    sides : dict
        Name -> the ``ExperimentConfig`` fields to change for that experiment (not ``PREPARATION_FIELDS``).
    cache : optional
        Has ``load`` and ``store`` (the live dashboards hand in :mod:`sarsp_edu.teaching.live.fitcache`): a side
        fitted before with the same settings, code and machine is loaded (the same bits as a new fit), and each side
        fitted here is stored.  None: every side is fitted here.
    progress : bool, default False
        Show each side's offline fits as a progress bar.
    parts : dict, optional
        Name -> that side's DecisionParts (or a mapping of some parts); a side loaded from the cache gets them too.
    """
    from ..agent.parts import DecisionParts
    from ..world.preparation import PREPARATION_FIELDS

    if not isinstance(sides, dict) or not sides:
        raise ValueError(f"sides must be a non-empty dict of name -> changed settings, got sides={sides!r}")
    if cache is not None and not (callable(getattr(cache, "load", None)) and callable(getattr(cache, "store", None))):
        raise TypeError(f"cache must be None or have load(config, prepared) and store(experiment) (as "
                        f"sarsp_edu.teaching.live.fitcache has), got cache={cache!r}")
    unknown = sorted(set(parts or {}) - set(sides), key=str)
    if unknown:
        raise ValueError(f"parts names sides {unknown} that sides does not have ({sorted(sides, key=str)})")
    parts = {name: DecisionParts.of(side_parts) for name, side_parts in (parts or {}).items()}
    shared = sorted({name for changes in sides.values() for name in changes if name in PREPARATION_FIELDS})
    if shared:
        raise ValueError(
            f"sides may change only the model and the agent's settings; {shared} shape the world and its data, "
            f"so change them in config (the fields of PREPARATION_FIELDS)"
        )
    configs = {name: config.replace(**changes) for name, changes in sides.items()}  # validated before any work
    prepared = prepare(config)  # one world, data and episode seeds for every side
    for name, side in configs.items():
        experiment = cache.load(side, prepared) if cache is not None else None
        if experiment is None:
            experiment = Experiment(side, prepared=prepared, fit=_fit_showing_progress(side, progress),
                                    parts=parts.get(name))
            if cache is not None:
                cache.store(experiment)
        elif name in parts:  # the stored fit is the same whatever the parts: the agent gets them before its first step
            experiment.agent.parts = parts[name]
        yield name, experiment


def paired_experiments(config: ExperimentConfig, progress: bool = False) -> dict:
    """The TP and the GP experiment of ``config``, paired: ``{"tp": Experiment, "gp": Experiment}``.

    Both share the world, its shift, the offline data with its outlier rows, the sequence of episode starts and
    goals and the agent's seed; only the regression model differs (:func:`experiments_on_one_world`).

    Parameters
    ----------
    config : ExperimentConfig
    progress : bool, default False
        Show each side's offline fits as a progress bar.
    """
    return experiments_on_one_world(config, {model: {"model": model} for model in ("tp", "gp")}, progress=progress)


def run_experiment(config: ExperimentConfig | None = None, progress: bool = False, *,
                   progress_position: int = 0) -> ExperimentResult:
    """Run one experiment: world, offline data, outliers, fits, shift, episodes.

    Parameters
    ----------
    config : ExperimentConfig, optional
        Default: the paper's settings with the TP.
    progress : bool, default False
        Show the offline fits' progress (step by step of the hyperparameter search), then a bar over
        episodes (a widget in notebooks, text in a terminal).
    progress_position : int, default 0
        The bars' line in a terminal (1: below another run's, as ``compare`` in two processes shows them).

    Returns
    -------
    ExperimentResult
    """
    config = config_or_default(config)
    fit = _fit_showing_progress(config, progress, progress_position)
    return _finish(Experiment(config, fit=fit), progress, progress_position)


def compare(config: ExperimentConfig | None = None, progress: bool = False, a: float = DEFINITION_4_A,
            n_jobs: int | None = None) -> Comparison:
    """Run the TP and the GP paired on one config (its ``model`` field is ignored).

    Both runs share the world, its shift, the offline data with its outlier rows, the sequence of episode starts
    and goals and the agent's seed; only the regression model differs.  (The reference implementation ran them one
    after the other, unpaired.)

    Parameters
    ----------
    config : ExperimentConfig, optional
    progress : bool, default False
        Each model's fits and episodes as progress bars (with two processes, the GP's on a second line).
    a : float, default 100
        Definition 4's TSR threshold.
    n_jobs : {None, 1, 2}, default None
        Processes: 2 runs the GP in a second process while this one runs the TP (one BLAS thread each); 1 runs them
        one after the other here; None chooses 2 where this process may use two cores or more, else 1.  The records
        are the same either way, number for number.

    Returns
    -------
    Comparison
    """
    from .._internal.parallel import available_cores, in_second_process, stop_workers

    config = config_or_default(config)
    check_a(a)  # before any work starts
    if n_jobs is None:
        n_jobs = 2 if available_cores() >= 2 else 1
    if n_jobs not in (1, 2) or isinstance(n_jobs, bool):
        raise ValueError(f"n_jobs must be 1 or 2 (one process per model), or None to choose, got n_jobs={n_jobs!r}")
    if n_jobs == 2:
        # Each process prepares the world from the seed alone: the same world, data and episode seeds as in sequence
        gp = in_second_process(run_experiment, config.replace(model="gp"), progress=progress, progress_position=1)
        try:
            tp = run_experiment(config.replace(model="tp"), progress=progress)
            return Comparison(tp, gp.result(), a)
        except KeyboardInterrupt:
            stop_workers()
            raise
    experiments = paired_experiments(config, progress=progress)
    return Comparison(_finish(experiments["tp"], progress), _finish(experiments["gp"], progress), a)
