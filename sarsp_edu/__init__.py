"""sarsp_edu: a teaching package for safe reinforcement learning with Gaussian
and Student-t processes, after "Hybrid Safe Reinforcement Learning: Tackling
Distribution Shift and Outliers with the Student-t's Process".
"""

from __future__ import annotations

from ._version import __version__

from .experiment import (
    Comparison,
    Experiment,
    ExperimentConfig,
    ExperimentResult,
    StoredResultError,
    compare,
    prefers,
    run_experiment,
)
from .gridworld import (
    ACTION_NAMES,
    DOWN,
    LEFT,
    RIGHT,
    UP,
    GridLayout,
    SafeGridWorld,
    cost_inputs,
    reward_inputs,
)
from .kernels import RBF
from .offline import ObservationBuffer, OfflineData, collect_offline_data, inject_outliers
from .plotting import plot_gridworld, plot_macro, plot_metric_curves
from .processes import GaussianProcess, NotFittedError, StudentTProcess
from .sarsp import Decision, SARSPAgent
from .sweep import SweepResults, run_sweep, summary_tables


__all__ = [
    "RBF",
    "GaussianProcess",
    "StudentTProcess",
    "NotFittedError",
    "SafeGridWorld",
    "GridLayout",
    "RIGHT",
    "DOWN",
    "LEFT",
    "UP",
    "ACTION_NAMES",
    "cost_inputs",
    "reward_inputs",
    "ObservationBuffer",
    "OfflineData",
    "collect_offline_data",
    "inject_outliers",
    "plot_gridworld",
    "SARSPAgent",
    "Decision",
    "ExperimentConfig",
    "Experiment",
    "ExperimentResult",
    "StoredResultError",
    "Comparison",
    "run_experiment",
    "compare",
    "prefers",
    "run_sweep",
    "SweepResults",
    "summary_tables",
    "plot_metric_curves",
    "plot_macro",
    "__version__",
]
