"""One experiment of the paper, run and measured as the paper runs and measures it.

``ExperimentConfig -> run_experiment -> ExperimentResult`` (per-episode
records and a summary); ``compare`` runs the TP and the GP *paired* on the same
world, shift, offline data, outliers and episode starts and goals, and applies
the paper's preference criterion (Definition 4).

Every random choice comes from streams spawned from ``config.seed`` by
purpose (world, offline data, outliers, shift, episodes, agent); none depends
on the model, so a TP run and a GP run with the same seed are paired by
construction, and the same seed gives the same numbers in any process.
"""

from __future__ import annotations

import copy
import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ._version import __version__
from ._io import StoredResultError, atomic_write_text, read_json
from ._threads import one_blas_thread
from ._validation import check_range
from .config import DEFINITION_4_A, PRESET_DOCS, PRESET_FIELDS, PRESETS, ExperimentConfig, preset_of
from .gridworld import SafeGridWorld
from .kernels import RBF
from .offline import collect_offline_data, inject_outliers
from .processes import GaussianProcess, StudentTProcess
from .sarsp import SARSPAgent

__all__ = [
    "ExperimentConfig",
    "Experiment",
    "ExperimentResult",
    "Comparison",
    "run_experiment",
    "compare",
    "prefers",
    "running_metrics",
    "percent_difference",
    "backup_share",
    "SUMMARY_METRICS",
    "RECORD_COLUMNS",
    "StoredResultError",
    "PRESETS",
    "PRESET_DOCS",
    "PRESET_FIELDS",
    "preset_of",
    "stuck_share",
    "cost_rate_undefined",
]


#: summary metrics, the paper's order (Tables 2-4)
SUMMARY_METRICS = ("mean_reward", "mean_cost", "total_cost", "task_success_rate", "mean_steps", "cost_rate")

#: every column of ``ExperimentResult.records`` and what it holds
RECORD_COLUMNS = {
    "episode": "episode number, from 1",
    "mean_reward": "running mean over episodes of the episode's summed reward (J_r)",
    "mean_cost": "running mean over episodes of the episode's violations",
    "total_cost": "running sum of violations",
    "task_success_rate": "running % of episodes that reached the goal (TSR)",
    "mean_steps": "running mean episode length",
    "cost_rate": "running total cost / steps of the episodes that reached the goal with zero cost (p_c, eq. 12); 0 while either is 0",
    "reward_mse": "this episode: mean squared error of the predicted reward of the taken action",
    "cost_prediction_error": "this episode: mean absolute error of the predicted cost signal of the taken action",
    "safe_action_variance": "this episode: mean predicted cost variance of the actions chosen as safe (NaN if none)",
    "backup_rate": "this episode: share of decisions where no action was safe and the backup chose",
    "corrective_updates": "running number of corrective updates of the cost model's data",
    "retrains": "running number of cost-model retrains",
    "final_cells": "this episode: distinct cells among the agent's last 10 positions (<= 2 on a failure: trapped)",
    "episode_reward": "this episode: summed reward",
    "episode_cost": "this episode: violations",
    "episode_steps": "this episode: steps",
    "task_completed": "this episode: whether the goal was reached",
    "start": "this episode: start cell (x, y)",
    "goal": "this episode: goal cell (x, y)",
}


def running_metrics(episode_reward, episode_cost, episode_steps, task_completed) -> pd.DataFrame:
    """The paper's running metrics after each episode (section 5.2, eq. 12).

    Parameters
    ----------
    episode_reward, episode_cost, episode_steps, task_completed : array-like of shape (E,)

    Returns
    -------
    DataFrame with the columns of ``SUMMARY_METRICS``, one row per episode.

    Examples
    --------
    >>> m = running_metrics([-10, -30], [0, 2], [5, 20], [True, False])
    >>> m["cost_rate"].tolist()  # 2 violations / 5 clean successful steps
    [0.0, 0.4]
    """
    reward = np.asarray(episode_reward, dtype=float)
    cost = np.asarray(episode_cost, dtype=float)
    steps = np.asarray(episode_steps, dtype=float)
    done = np.asarray(task_completed, dtype=bool)
    count = np.arange(1, len(reward) + 1)
    total_cost = np.cumsum(cost)
    clean_steps = np.cumsum(np.where(done & (cost == 0), steps, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        cost_rate = np.where((total_cost > 0) & (clean_steps > 0), total_cost / clean_steps, 0.0)
    return pd.DataFrame(
        {
            "mean_reward": np.cumsum(reward) / count,
            "mean_cost": total_cost / count,
            "total_cost": total_cost,
            "task_success_rate": 100.0 * np.cumsum(done) / count,
            "mean_steps": np.cumsum(steps) / count,
            "cost_rate": cost_rate,
        }
    )


def make_model(config: ExperimentConfig):
    """A fresh, unfitted model as the config describes it (hyperparameters start at 1)."""
    common = dict(
        noise_variance=1.0,
        optimizer=config.optimizer,
        learning_rate=config.learning_rate,
        max_iter=config.optimizer_steps,
        prior=config.prior,
        max_fit_points=None,  # the agent draws the fit subsets
    )
    if config.model == "tp":
        return StudentTProcess(RBF(1.0, 1.0), nu=config.nu, noise_convention=config.noise_convention, **common)
    return GaussianProcess(RBF(1.0, 1.0), **common)


_STREAMS = ("world", "offline", "outliers", "shift", "episodes", "agent")

#: positions at the end of an episode inspected for a trap (``final_cells``)
FINAL_WINDOW = 10


def _streams(seed: int) -> dict:
    children = np.random.SeedSequence(seed).spawn(len(_STREAMS))
    return {name: np.random.default_rng(child) for name, child in zip(_STREAMS, children)}


@dataclass
class _Prepared:
    """What two paired runs share: the world after the shift and the offline data."""

    env: SafeGridWorld
    data: object
    layout_before: object
    episode_seeds: np.ndarray
    agent_seed: int
    seconds: float


def _prepare(config: ExperimentConfig) -> _Prepared:
    start = time.perf_counter()
    rngs = _streams(config.seed)
    env = SafeGridWorld(
        size=config.grid_size,
        n_unsafe=config.n_unsafe,
        d=config.d,
        max_steps=config.max_steps,
        placement=config.placement,
        seed=rngs["world"],
    )
    data = collect_offline_data(
        env,
        config.offline_episodes,
        rng=rngs["offline"],
        cost_duplicates=config.cost_duplicates,
        reward_duplicates=config.reward_duplicates,
    )
    if config.outlier_proportion > 0 and (config.cost_outliers or config.reward_outliers):
        data = inject_outliers(
            data,
            config.outlier_magnitude,
            config.outlier_proportion,
            rng=rngs["outliers"],
            cost=config.cost_outliers,
            reward=config.reward_outliers,
        )
    layout_before = env.layout()
    env.shift(config.n_switch_states, rng=rngs["shift"])
    episode_seeds = rngs["episodes"].integers(2**31 - 1, size=config.episodes)
    agent_seed = int(rngs["agent"].integers(2**63 - 1))
    return _Prepared(env, data, layout_before, episode_seeds, agent_seed, time.perf_counter() - start)


@dataclass
class StepRecord:
    """One agent step, as the live dashboard shows it."""

    episode: int
    t: int
    position: tuple
    next_position: tuple
    action: int
    decision: object
    reward: float
    info: dict
    outcome: object
    done: bool


class Experiment:
    """One run, advanced step by step or episode by episode.

    ``run_experiment`` drives it to the end; the live dashboard drives it a
    step at a time.  Construction collects the offline data, injects the
    outliers, fits both models and shifts the world.
    """

    def __init__(self, config: ExperimentConfig, *, prepared: _Prepared | None = None):
        if not isinstance(config, ExperimentConfig):
            raise TypeError(f"config must be an ExperimentConfig, got {type(config).__name__}")
        self.config = config
        prepared = _prepare(config) if prepared is None else prepared
        self.env = copy.deepcopy(prepared.env)
        self.data = prepared.data
        self.layout_before = prepared.layout_before
        self._episode_seeds = prepared.episode_seeds
        self.agent = SARSPAgent(
            make_model(config),
            make_model(config),
            prepared.data,
            d=config.d,
            variance_threshold=config.variance_threshold,
            k_prior=config.k_prior,
            n_matching=config.n_matching,
            prior_draw=config.prior_draw,
            predictive=config.predictive,
            n_samples=config.n_samples,
            cost_fit_points=config.cost_fit_points,
            reward_fit_points=config.reward_fit_points,
            retrain=config.retrain,
            rng=prepared.agent_seed,
        )
        start = time.perf_counter()
        with one_blas_thread():
            self.agent.fit()
        self.timings = {
            "data_seconds": prepared.seconds,
            "offline_fit_seconds": time.perf_counter() - start,
            "episode_seconds": 0.0,
            "retrain_seconds": 0.0,
        }
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
        records = self.records()
        timings = dict(self.timings)
        if self.act_seconds:
            timings["median_act_seconds"] = float(np.median(self.act_seconds))
            timings["median_step_seconds"] = float(np.median(self.step_seconds))
        timings["steps"] = len(self.act_seconds)
        return ExperimentResult(self.config, records, timings)


@dataclass
class ExperimentResult:
    """The outcome of one run.

    Attributes
    ----------
    config : ExperimentConfig
    records : pandas.DataFrame
        One row per episode; ``RECORD_COLUMNS`` documents each column.
    timings : dict
        Seconds spent on data, offline fits, episodes and retrains, the
        median seconds of one decision, and the number of steps.
    summary : dict
        The final value of each of ``SUMMARY_METRICS`` (the paper's run figures).
    """

    config: ExperimentConfig
    records: pd.DataFrame
    timings: dict = field(default_factory=dict)

    @property
    def summary(self) -> dict:
        if self.records.empty:
            return {name: math.nan for name in SUMMARY_METRICS}
        last = self.records.iloc[-1]
        return {name: float(last[name]) for name in SUMMARY_METRICS}

    def save(self, directory) -> Path:
        """Write ``records.csv`` and ``result.json`` (config, summary, timings) atomically.

        ``result.json`` is written last, so its presence marks a complete result.
        """
        directory = Path(directory)
        table = self.records.copy()
        for column in ("start", "goal"):
            table[column] = [f"{x} {y}" for x, y in table[column]]
        atomic_write_text(directory / "records.csv", table.to_csv(index=False))
        payload = {
            "config": self.config.to_dict(),
            "preset": self.config.preset,
            "summary": self.summary,
            "timings": self.timings,
            "sarsp_edu_version": __version__,
        }
        atomic_write_text(directory / "result.json", json.dumps(payload, indent=2, allow_nan=True) + "\n")
        return directory

    @classmethod
    def load(cls, directory) -> "ExperimentResult":
        """Read a result written by :meth:`save`."""
        directory = Path(directory)
        meta_path, csv_path = directory / "result.json", directory / "records.csv"
        if not meta_path.exists() or not csv_path.exists():
            raise FileNotFoundError(f"{directory} holds no complete result (records.csv and result.json)")
        payload = read_json(meta_path, keys=("config",))
        try:
            config = ExperimentConfig.from_dict(payload["config"])
        except (TypeError, ValueError) as exc:
            raise StoredResultError(f"{meta_path} holds an invalid config: {exc}") from None
        records = _read_records(csv_path, config.episodes)
        return cls(config, records, payload.get("timings", {}))


#: records columns that results stored by older versions may lack
_LATER_COLUMNS = {"final_cells": "0.2.0"}
#: records columns that may hold NaN (no action was chosen as safe in an episode)
_NAN_COLUMNS = {"safe_action_variance"}


def _read_records(path: Path, episodes: int) -> pd.DataFrame:
    """``records.csv`` of a stored result, checked row by row; :class:`StoredResultError` names what is wrong."""

    def bad(problem: str):
        return StoredResultError(f"{path} {problem}")

    try:
        records = pd.read_csv(path)
    except (OSError, UnicodeDecodeError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise bad(f"cannot be read ({str(exc).strip()})") from None
    missing = [c for c in RECORD_COLUMNS if c not in records.columns and c not in _LATER_COLUMNS]
    if missing:
        raise bad(f"lacks the columns {missing}")
    if len(records) != episodes or not np.array_equal(records["episode"], np.arange(1, episodes + 1)):
        raise bad(f"holds {len(records)} episodes where its config ran {episodes} (was it cut short?)")
    text_columns = ("start", "goal", "task_completed")
    for column in records.columns.intersection(list(RECORD_COLUMNS)):
        if column in text_columns:
            continue
        values = pd.to_numeric(records[column], errors="coerce")
        empty = values.isna() & (records[column].notna() | (column not in _NAN_COLUMNS))
        if empty.any():
            row = int(np.flatnonzero(empty.to_numpy())[0]) + 1
            raise bad(f"has no number in column {column!r} of episode {row}")
        records[column] = values
    done = records["task_completed"].astype(str)
    if not done.isin(["True", "False"]).all():
        raise bad("has a task_completed value other than True or False")
    records["task_completed"] = done == "True"
    for column in ("start", "goal"):
        cells = []
        for row, text in enumerate(records[column], start=1):
            parts = str(text).split()
            if len(parts) != 2 or not all(part.lstrip("-").isdigit() for part in parts):
                raise bad(f"has {column}={text!r} in episode {row}, not a cell 'x y'")
            cells.append((int(parts[0]), int(parts[1])))
        records[column] = cells
    return records


class _NoProgress:
    """What ``_progress`` gives when no bar is wanted: a context manager whose ``update`` does nothing."""

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> bool:
        return False

    def update(self, n: int = 1) -> None:
        pass


def _progress(total: int, desc: str, enabled: bool):
    """A tqdm bar over episodes, or a stand-in that does nothing.

    Even a disabled tqdm bar creates a multiprocessing lock, which a sweep's
    worker stopped by Ctrl-C would leave behind (with a warning); quiet runs
    create none.
    """
    if not enabled:
        return _NoProgress()
    from tqdm.auto import tqdm

    return tqdm(total=total, desc=desc, unit="episode", leave=False)


def _run(config: ExperimentConfig, prepared: _Prepared | None, progress: bool) -> ExperimentResult:
    with one_blas_thread():
        experiment = Experiment(config, prepared=prepared)
        with _progress(config.episodes, f"{config.model.upper()} episodes", progress) as bar:
            while not experiment.finished:
                experiment.run_episode()
                bar.update(1)
    return experiment.result()


def run_experiment(config: ExperimentConfig | None = None, progress: bool = False) -> ExperimentResult:
    """Run one experiment: world, offline data, outliers, fits, shift, episodes.

    Parameters
    ----------
    config : ExperimentConfig, optional
        Default: the paper's settings with the TP.
    progress : bool, default False
        Show a progress bar over episodes (a widget in notebooks, text in a terminal).

    Returns
    -------
    ExperimentResult
    """
    return _run(ExperimentConfig() if config is None else config, None, progress)


def percent_difference(tp: float, gp: float) -> float:
    """``(tp - gp) / |gp| * 100``, the paper's "TP vs GP" percentage (NaN when gp is 0 or either is NaN)."""
    if math.isnan(tp) or math.isnan(gp):
        return math.nan
    if gp == 0:
        return 0.0 if tp == 0 else math.nan
    return (tp - gp) / abs(gp) * 100.0


#: for each summary metric, whether a higher value is better
HIGHER_IS_BETTER = {
    "mean_reward": True,
    "mean_cost": False,
    "total_cost": False,
    "task_success_rate": True,
    "mean_steps": False,
    "cost_rate": False,
}


def better_of(metric: str, tp: float, gp: float) -> str:
    """``"TP"``, ``"GP"``, ``"tie"``, or ``"n/a"`` when either value is undefined (NaN)."""
    if math.isnan(tp) or math.isnan(gp):
        return "n/a"
    if tp == gp:
        return "tie"
    return "TP" if (tp > gp) == HIGHER_IS_BETTER[metric] else "GP"


def displayed_summary(summary: dict) -> dict:
    """A summary for display: an undefined cost rate becomes NaN (shown as n/a)."""
    if cost_rate_undefined(summary):
        return {**summary, "cost_rate": math.nan}
    return dict(summary)


def _check_a(a) -> float:
    return check_range("a", a, 1.0, 100.0, "a task success rate in %")


def backup_share(records: pd.DataFrame) -> float:
    """Share of all decisions in ``records`` taken by the backup rule (no action was safe)."""
    steps = records["episode_steps"].sum()
    return float((records["backup_rate"] * records["episode_steps"]).sum() / steps) if steps else math.nan


def stuck_share(records: pd.DataFrame) -> float:
    """Share of failed episodes (goal not reached) that ended trapped on at most 2 cells.

    A greedy agent that pushes into a wall, or steps back and forth between
    two cells, until the step limit (see ``final_cells``).  NaN when no
    episode failed.
    """
    failed = ~records["task_completed"].astype(bool)
    if not failed.any():
        return math.nan
    return float((records.loc[failed, "final_cells"] <= 2).mean())


def cost_rate_undefined(summary) -> bool:
    """Whether eq. 12's cost rate is undefined: violations, but no episode succeeded without one.

    Its denominator (the steps of clean successful episodes) is then 0.
    Records and summaries keep the paper's value 0 there, so that averages
    over configurations are the paper's; tables show ``n/a`` and
    Definition 4 does not decide.  ``summary`` needs ``total_cost`` and
    ``cost_rate``.
    """
    return bool(summary["total_cost"] > 0 and summary["cost_rate"] == 0)


def prefers(summary_1: dict, summary_2: dict, a: float = DEFINITION_4_A) -> bool | None:
    """Paper Definition 4: is agent 1 preferred to agent 2?

    ``A1 > A2`` iff ``p_c(A1) < p_c(A2)`` and at least one of
    ``J_r(A1) >= J_r(A2)``, ``TSR(A1) >= TSR(A2)`` or ``TSR(A1) >= a``.

    Parameters
    ----------
    summary_1, summary_2 : dict
        With ``mean_reward`` (J_r), ``cost_rate`` (p_c) and
        ``task_success_rate`` (TSR, in %).
    a : float, default 100.0
        The task-specific TSR threshold in [1, 100] (%).  The default is the
        strictest: the third branch then needs a perfect success rate.

    Returns
    -------
    bool, or None when either cost rate is undefined (see
    :func:`cost_rate_undefined`; needs ``total_cost`` in the summaries to
    tell): Definition 4 then cannot decide.

    Notes
    -----
    The cost-rate test is strict, so two agents with equal cost rates (both
    0, say) are never preferred to one another.

    Examples
    --------
    >>> tp = {"mean_reward": -70.0, "cost_rate": 0.010, "task_success_rate": 92.0}
    >>> gp = {"mean_reward": -120.0, "cost_rate": 0.012, "task_success_rate": 86.0}
    >>> prefers(tp, gp), prefers(gp, tp)
    (True, False)
    """
    a_value = _check_a(a)
    for name in ("mean_reward", "cost_rate", "task_success_rate"):
        for label, summary in (("summary_1", summary_1), ("summary_2", summary_2)):
            if name not in summary:
                raise ValueError(f"{label} lacks '{name}'; it needs mean_reward, cost_rate and task_success_rate")
    if any("total_cost" in summary and cost_rate_undefined(summary) for summary in (summary_1, summary_2)):
        return None
    if not summary_1["cost_rate"] < summary_2["cost_rate"]:
        return False
    return bool(
        summary_1["mean_reward"] >= summary_2["mean_reward"]
        or summary_1["task_success_rate"] >= summary_2["task_success_rate"]
        or summary_1["task_success_rate"] >= a_value
    )


@dataclass
class Comparison:
    """A paired TP-versus-GP comparison.

    Attributes
    ----------
    tp, gp : ExperimentResult
    a : float
        The TSR threshold used by ``prefers``.
    """

    tp: ExperimentResult
    gp: ExperimentResult
    a: float = DEFINITION_4_A

    @property
    def verdict(self) -> dict:
        """Definition 4 in both directions: ``{"tp_preferred": ..., "gp_preferred": ...}``.

        Each is None when a cost rate is undefined (see :func:`cost_rate_undefined`).
        """
        return {
            "tp_preferred": prefers(self.tp.summary, self.gp.summary, self.a),
            "gp_preferred": prefers(self.gp.summary, self.tp.summary, self.a),
        }

    @property
    def differences(self) -> dict:
        """``(TP - GP) / |GP| * 100`` for each summary metric."""
        tp, gp = self.tp.summary, self.gp.summary
        return {name: percent_difference(tp[name], gp[name]) for name in SUMMARY_METRICS}

    def table(self) -> pd.DataFrame:
        """Summary side by side: TP, GP, % difference and which is better.

        An undefined cost rate (see :func:`cost_rate_undefined`) is NaN here,
        and ``better`` is then ``"n/a"``.
        """
        tp, gp = displayed_summary(self.tp.summary), displayed_summary(self.gp.summary)
        rows = []
        for name in SUMMARY_METRICS:
            rows.append({"metric": name, "TP": tp[name], "GP": gp[name],
                         "TP vs GP (%)": percent_difference(tp[name], gp[name]),
                         "better": better_of(name, tp[name], gp[name])})
        return pd.DataFrame(rows).set_index("metric")

    def save(self, directory) -> Path:
        """``tp/`` and ``gp/`` result folders (the verdict is recomputed on load)."""
        directory = Path(directory)
        self.tp.save(directory / "tp")
        self.gp.save(directory / "gp")
        return directory

    @classmethod
    def load(cls, directory, a: float = DEFINITION_4_A) -> "Comparison":
        directory = Path(directory)
        return cls(ExperimentResult.load(directory / "tp"), ExperimentResult.load(directory / "gp"), a)


def compare(config: ExperimentConfig | None = None, progress: bool = False, a: float = DEFINITION_4_A) -> Comparison:
    """Run the TP and the GP paired on one config (its ``model`` field is ignored).

    Both runs share the world, its shift, the offline data with its outlier
    rows, the sequence of episode starts and goals and the agent's seed; only
    the regression model differs.  (The reference implementation ran them
    one after the other, unpaired.)

    Returns
    -------
    Comparison
    """
    config = ExperimentConfig() if config is None else config
    _check_a(a)  # before any work starts
    with one_blas_thread():
        prepared = _prepare(config)
        tp = _run(config.replace(model="tp"), prepared, progress)
        gp = _run(config.replace(model="gp"), prepared, progress)
    return Comparison(tp, gp, a)
