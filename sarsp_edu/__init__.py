"""sarsp_edu: a teaching package for safe reinforcement learning with Gaussian
and Student-t processes, after "Hybrid Safe Reinforcement Learning: Tackling
Distribution Shift and Outliers with the Student-t's Process".

Each folder is a layer; a module imports only from its own layer and those
listed before it (``tests/test_layers.py`` checks every module-level import):

- ``_internal``: plumbing with no public API (atomic files, argument checks,
  BLAS threads, process pools, seeds to generators, the old import paths);
- ``config``: every setting (``ExperimentConfig``), the presets and the
  defaults, each defined once; loads no numerical library;
- ``models``: the RBF kernel, Cholesky algebra, the optimizers, GP and TP
  regression in closed form (``processes``), the tail limits in sympy;
- ``world``: the safe gridworld (a Gymnasium environment) and its shift, the
  offline data and its outliers, what a run prepares before its agent;
- ``agent``: the SARSP agent (Algorithm 1), its decision rule and parts;
- ``experiments``: runs and paired comparisons, the metrics and Definition 4,
  stored results, the 45-configuration sweep, Tables 1-4, the ablation;
- ``paper``: the paper's published numbers and the authors' own runs, for
  comparison only;
- ``teaching``: drawings, dashboards, tutorial 4's live run, the exercises and
  their grader, the course's notebooks and pages;
- ``cli``: the ``sarsp-edu`` command.

The most used names are importable from here (``from sarsp_edu import
SARSPAgent``).  The paths before 0.3 (``sarsp_edu.sarsp``,
``sarsp_edu.processes`` ...) still import, with a ``DeprecationWarning``, until
the next release (:mod:`sarsp_edu._internal.moved`).
"""

from __future__ import annotations

from ._internal import moved as _moved
from ._version import __version__

_moved.install()

#: False when run, True for type checkers (the standard idiom, without importing typing: the command starts sooner)
TYPE_CHECKING = False


def _register_environment() -> None:
    """Make ``gymnasium.make("sarsp_edu/SafeGridWorld-v0")`` work once sarsp_edu and gymnasium are imported."""
    import gymnasium

    from .config import GRID_SIZE

    if "sarsp_edu/SafeGridWorld-v0" not in gymnasium.registry:
        # T_max = n * n on the paper's 10 x 10 grid: TimeLimit truncates where the environment itself does
        gymnasium.register(id="sarsp_edu/SafeGridWorld-v0", entry_point="sarsp_edu.world.gridworld:SafeGridWorld",
                           max_episode_steps=GRID_SIZE * GRID_SIZE)


class _RegisterAfterGymnasium:
    """An import hook: registers the environment right after gymnasium's first import, wherever it happens.

    sarsp_edu does not import gymnasium (nor numpy) itself, so that the ``sarsp-edu`` command is interruptible
    from its first moment: its own handler says "interrupted" in one line, where an interrupt inside numpy's
    import printed a traceback.  ``gymnasium.make("sarsp_edu/SafeGridWorld-v0")`` works as before.
    """

    def find_spec(self, fullname, path=None, target=None):
        if fullname != "gymnasium":
            return None
        import importlib.util
        import sys

        if self in sys.meta_path:
            sys.meta_path.remove(self)  # once: the spec below is found by the other finders
        spec = importlib.util.find_spec(fullname)
        if spec is None or spec.loader is None or not hasattr(spec.loader, "exec_module"):
            return spec
        run = spec.loader.exec_module

        def exec_module(module):  # this spec's own loader: gymnasium's import, then the registration
            run(module)
            _register_environment()

        spec.loader.exec_module = exec_module
        return spec


def _install_registration() -> None:
    import sys

    if "gymnasium" in sys.modules:
        _register_environment()
    elif not any(isinstance(finder, _RegisterAfterGymnasium) for finder in sys.meta_path):
        sys.meta_path.insert(0, _RegisterAfterGymnasium())


_install_registration()

# Public names load their module on first use (PEP 562), so that the
# ``sarsp-edu`` command answers --help without importing scipy and pandas.
_LAZY = {
    "Comparison": "experiments.results",
    "Experiment": "experiments.experiment",
    "ExperimentConfig": "config",
    "ExperimentResult": "experiments.results",
    "StoredResultError": "experiments.results",
    "stored_results": "experiments.results",
    "compare": "experiments.experiment",
    "prefers": "experiments.metrics",
    "run_experiment": "experiments.experiment",
    "ACTION_NAMES": "world.gridworld",
    "DOWN": "world.gridworld",
    "LEFT": "world.gridworld",
    "RIGHT": "world.gridworld",
    "UP": "world.gridworld",
    "GridLayout": "world.gridworld",
    "SafeGridWorld": "world.gridworld",
    "cost_inputs": "world.offline",
    "reward_inputs": "world.offline",
    "RBF": "models.kernels",
    "ObservationBuffer": "world.offline",
    "OfflineData": "world.offline",
    "collect_offline_data": "world.offline",
    "inject_outliers": "world.offline",
    "plot_gridworld": "teaching.plotting",
    "plot_macro": "teaching.plotting",
    "plot_metric_curves": "teaching.plotting",
    "GaussianProcess": "models.processes",
    "NotFittedError": "models.processes",
    "ConvergenceWarning": "models.processes",
    "StudentTProcess": "models.processes",
    "StudentTLikelihoodGP": "models.processes",
    "Decision": "agent.decision",
    "SARSPAgent": "agent.sarsp",
    "SweepResults": "experiments.sweep",
    "run_sweep": "experiments.sweep",
    "summary_tables": "experiments.tables",
}



if TYPE_CHECKING:  # the same names for editors and type checkers (``name as name``: a re-export, PEP 484)
    from .agent.decision import (
        Decision as Decision,
    )
    from .agent.sarsp import (
        SARSPAgent as SARSPAgent,
    )
    from .config import (
        ExperimentConfig as ExperimentConfig,
    )
    from .experiments.experiment import (
        Experiment as Experiment,
        compare as compare,
        run_experiment as run_experiment,
    )
    from .experiments.metrics import (
        prefers as prefers,
    )
    from .experiments.results import (
        Comparison as Comparison,
        ExperimentResult as ExperimentResult,
        StoredResultError as StoredResultError,
        stored_results as stored_results,
    )
    from .experiments.sweep import (
        SweepResults as SweepResults,
        run_sweep as run_sweep,
    )
    from .experiments.tables import (
        summary_tables as summary_tables,
    )
    from .models.kernels import (
        RBF as RBF,
    )
    from .models.processes import (
        ConvergenceWarning as ConvergenceWarning,
        GaussianProcess as GaussianProcess,
        NotFittedError as NotFittedError,
        StudentTLikelihoodGP as StudentTLikelihoodGP,
        StudentTProcess as StudentTProcess,
    )
    from .teaching.plotting import (
        plot_gridworld as plot_gridworld,
        plot_macro as plot_macro,
        plot_metric_curves as plot_metric_curves,
    )
    from .world.gridworld import (
        ACTION_NAMES as ACTION_NAMES,
        DOWN as DOWN,
        LEFT as LEFT,
        RIGHT as RIGHT,
        UP as UP,
        GridLayout as GridLayout,
        SafeGridWorld as SafeGridWorld,
    )
    from .world.offline import (
        ObservationBuffer as ObservationBuffer,
        OfflineData as OfflineData,
        collect_offline_data as collect_offline_data,
        cost_inputs as cost_inputs,
        inject_outliers as inject_outliers,
        reward_inputs as reward_inputs,
    )

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

