"""sarsp_edu: a teaching package for safe reinforcement learning with Gaussian
and Student-t processes, after "Hybrid Safe Reinforcement Learning: Tackling
Distribution Shift and Outliers with the Student-t's Process".
"""

from __future__ import annotations

from ._version import __version__


def _register_environment() -> None:
    """Make ``gymnasium.make("sarsp_edu/SafeGridWorld-v0")`` work once sarsp_edu is imported."""
    import gymnasium

    if "sarsp_edu/SafeGridWorld-v0" not in gymnasium.registry:
        gymnasium.register(id="sarsp_edu/SafeGridWorld-v0", entry_point="sarsp_edu.gridworld:SafeGridWorld")


_register_environment()

# Public names load their module on first use (PEP 562), so that the
# ``sarsp-edu`` command answers --help without importing scipy and pandas.
_LAZY = {
    "Comparison": "experiment",
    "Experiment": "experiment",
    "ExperimentConfig": "config",
    "ExperimentResult": "experiment",
    "StoredResultError": "experiment",
    "compare": "experiment",
    "prefers": "experiment",
    "run_experiment": "experiment",
    "ACTION_NAMES": "gridworld",
    "DOWN": "gridworld",
    "LEFT": "gridworld",
    "RIGHT": "gridworld",
    "UP": "gridworld",
    "GridLayout": "gridworld",
    "SafeGridWorld": "gridworld",
    "cost_inputs": "offline",
    "reward_inputs": "offline",
    "RBF": "kernels",
    "ObservationBuffer": "offline",
    "OfflineData": "offline",
    "collect_offline_data": "offline",
    "inject_outliers": "offline",
    "plot_gridworld": "plotting",
    "plot_macro": "plotting",
    "plot_metric_curves": "plotting",
    "GaussianProcess": "processes",
    "NotFittedError": "processes",
    "ConvergenceWarning": "processes",
    "StudentTProcess": "processes",
    "Decision": "sarsp",
    "SARSPAgent": "sarsp",
    "SweepResults": "sweep",
    "run_sweep": "sweep",
    "summary_tables": "sweep",
}


__all__ = [*_LAZY, "__version__"]


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'sarsp_edu' has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value  # the next lookup is an ordinary one
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))

