"""sarsp_edu: a teaching package for safe reinforcement learning with Gaussian
and Student-t processes, after "Hybrid Safe Reinforcement Learning: Tackling
Distribution Shift and Outliers with the Student-t's Process".

The layout, lowest layer first (a module imports only from those above it):

- ``config``: every setting (``ExperimentConfig``), the presets, and the
  defaults of the world, the data, the fits and Algorithm 1, each defined once;
  loads no numerical library.
- ``rng``: seeds to generators, uniform row subsets.
- ``kernels``: the RBF kernel and its gradient.
- ``linalg``: Cholesky factors and solves, repeated rows folded exactly.
- ``optimizers``: Adam (the paper's) and L-BFGS-B.
- ``processes``: GP and TP regression in closed form: the equations, the fits.
- ``tails``: the densities' tail limits in sympy (paper section 3.3).
- ``gridworld``: the safe gridworld (a Gymnasium environment) and its shift.
- ``offline``: the models' inputs, the training sets, offline data, outliers.
- ``sarsp``: the SARSP agent (Algorithm 1); ``decision``: its decision rule and records.
- ``metrics``: the paper's metrics, their comparison, Definition 4.
- ``results``: results of runs and paired comparisons, stored and read back.
- ``preparation``: what a run needs before its agent (world, data, outliers, shift, seeds).
- ``experiment``: one run, or a paired TP-vs-GP comparison, of a config.
- ``sweep``: the 45-configuration grid, run and stored cell by cell.
- ``tables``: the paper's Tables 1-4 and their statistics.
- ``ablation``: the comparison under several settings.
- ``paper``: the paper's published numbers, for comparison only.
- ``authors``: the authors' own per-episode records of the paper's runs, and ours beside them.
- ``demos``: the tutorials' computations (GP and TP on 1-D data, the world
  and its data as an experiment prepares them).
- ``plotting``: matplotlib drawings, ``plot_*(ax, data)``, no state; a package of
  ``style``, ``models`` (tutorials 1-2), ``world`` (3-4) and ``results`` (4-5).
- ``markup``: the same pictures as SVG and HTML strings, for live redraws.
- ``dashboard``: the redraw framework (``Dashboard``, ``Panel``, sliders).
- ``widgets``: the dashboards of tutorials 1-3 and 6 (and ``agent_dashboard``).
- ``live``: tutorial 4's live TP-versus-GP dashboard.
- ``exercises``: the tutorials' exercises: functions students write, graded
  on fresh inputs against the package, and short predictions.
- ``course``: source notebooks (nbgrader's format) to student notebooks and hand-outs.
- ``provenance``: which code computed a stored result.
- ``cli``: the ``sarsp-edu`` command.
- ``_io``, ``_validation``, ``_threads``, ``_version``: atomic files and
  stored-result errors, argument checks, BLAS threads, the version.
"""

from __future__ import annotations

from ._version import __version__


def _register_environment() -> None:
    """Make ``gymnasium.make("sarsp_edu/SafeGridWorld-v0")`` work once sarsp_edu is imported."""
    import gymnasium

    if "sarsp_edu/SafeGridWorld-v0" not in gymnasium.registry:
        # T_max = n * n on the paper's 10 x 10 grid: TimeLimit truncates where the environment itself does
        gymnasium.register(id="sarsp_edu/SafeGridWorld-v0", entry_point="sarsp_edu.gridworld:SafeGridWorld",
                           max_episode_steps=100)


_register_environment()

# Public names load their module on first use (PEP 562), so that the
# ``sarsp-edu`` command answers --help without importing scipy and pandas.
_LAZY = {
    "Comparison": "results",
    "Experiment": "experiment",
    "ExperimentConfig": "config",
    "ExperimentResult": "results",
    "StoredResultError": "results",
    "stored_results": "results",
    "compare": "experiment",
    "prefers": "metrics",
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
    "StudentTLikelihoodGP": "processes",
    "Decision": "decision",
    "SARSPAgent": "sarsp",
    "SweepResults": "sweep",
    "run_sweep": "sweep",
    "summary_tables": "tables",
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

