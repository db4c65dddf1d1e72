"""The modules' import paths before the package was grouped into layer folders (0.3), kept for one release.

``import sarsp_edu.sarsp`` (or ``from sarsp_edu.kernels import RBF``) still
works: it warns (``DeprecationWarning``) and gives the module at its new path,
the same module object, so that a name patched through the old path is patched
for the package too.  One import hook serves every old path, including the
submodules of a moved package (``sarsp_edu.processes.tp``), instead of a thin
file per module; :data:`MOVED` lists them.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
import warnings

__all__ = ["MOVED", "new_path", "install"]

#: old module path (under ``sarsp_edu``) -> its path since 0.3 (or 0.4, the renames at the end); a moved package's
#: submodules follow it
MOVED = {
    "_io": "_internal.io",
    "_parallel": "_internal.parallel",
    "_threads": "_internal.threads",
    "_validation": "_internal.validation",
    "rng": "_internal.rng",
    "kernels": "models.kernels",
    "linalg": "models.linalg",
    "optimizers": "models.optimizers",
    "tails": "models.tails",
    "processes": "models.processes",
    "gridworld": "world.gridworld",
    "offline": "world.offline",
    "preparation": "world.preparation",
    "sarsp": "agent.sarsp",
    "decision": "agent.decision",
    "parts": "agent.parts",
    "experiment": "experiments.experiment",
    "results": "experiments.results",
    "metrics": "experiments.metrics",
    "sweep": "experiments.sweep",
    "tables": "experiments.tables",
    "ablation": "experiments.ablation",
    "provenance": "experiments.provenance",
    "authors": "paper.authors",
    "plotting": "teaching.plotting",
    "demos": "teaching.demos",
    "exercises": "teaching.exercises",
    "course": "teaching.course",
    "pages": "teaching.pages",
    "prose": "teaching.prose",
    "dashboard": "teaching.dashboards.framework",
    "widgets": "teaching.dashboards.tutorials",
    "projector": "teaching.dashboards.projector",
    "markup": "teaching.live.markup",
    "fitcache": "teaching.live.fitcache",
    "live.dashboard": "teaching.live.view",
    "live.animation": "teaching.live.controller",  # the animation mixin became the LiveRun controller
    "live": "teaching.live",
    # renamed in 0.4, each for the one job it holds
    "models.processes.robust": "models.processes.likelihood",  # the GP with a Student-t likelihood
    "models.processes.settings": "models.processes.factory",  # make_model (the settings are config's)
    "teaching.exercises.answers": "teaching.exercises.parsing",  # reading a short answer
    "teaching.exercises.lookups": "teaching.exercises.short_answers",  # the short-answer exercises
}

_ROOT = "sarsp_edu"


def new_path(old: str) -> str | None:
    """The module path since 0.3 of an old one (``'sarsp_edu.processes.tp'`` -> ``'sarsp_edu.models.processes.tp'``).

    None for a path that did not move.

    >>> new_path("sarsp_edu.live.dashboard")
    'sarsp_edu.teaching.live.view'
    >>> new_path("sarsp_edu.config") is None
    True
    """
    if not old.startswith(_ROOT + "."):
        return None
    parts = old[len(_ROOT) + 1:].split(".")
    for end in range(len(parts), 0, -1):
        moved = MOVED.get(".".join(parts[:end]))
        if moved is not None:
            return ".".join([_ROOT, moved, *parts[end:]])
    return None


class _Alias:
    """Finds an old path and loads it as the module at its new path (a meta path finder and its loader, by their
    methods: ``importlib.abc`` is not imported, which would import ``typing`` at the package's start)."""

    def __init__(self):
        self._specs = {}  # new module name -> its own spec, which the import system overwrites with the alias's

    def find_spec(self, fullname, path=None, target=None):
        new = new_path(fullname)
        if new is None:
            return None
        return importlib.util.spec_from_loader(fullname, self, is_package=False)

    def create_module(self, spec):
        new = new_path(spec.name)
        warnings.warn(f"{spec.name} is now {new}; the old path works until the next release", DeprecationWarning,
                      stacklevel=2)
        module = importlib.import_module(new)
        self._specs[module.__name__] = module.__spec__
        return module

    def exec_module(self, module):
        # the module ran at its new path already: give it back its own spec
        module.__spec__ = self._specs.pop(module.__name__, module.__spec__)


def install() -> None:
    """Put the old paths' finder before the file finders (once)."""
    if not any(isinstance(finder, _Alias) for finder in sys.meta_path):
        sys.meta_path.insert(0, _Alias())
