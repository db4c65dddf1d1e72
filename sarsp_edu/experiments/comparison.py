"""Several models paired on one configuration: two, three or more agents on the very same world.

:func:`~sarsp_edu.experiments.experiment.compare` pairs the TP and the GP,
as the paper does; :func:`compare_models` pairs any of ``MODELS`` (the GP
with a Student-t likelihood among them), each pair judged by Definition 4.
"""

from __future__ import annotations

from itertools import combinations
from pathlib import Path

import pandas as pd

from ..config import DEFINITION_4_A, MODELS, ExperimentConfig, config_or_default
from .experiment import _finish, experiments_on_one_world
from .metrics import SUMMARY_METRICS, check_a, displayed_summary, prefers

__all__ = ["ModelComparison", "compare_models"]


class ModelComparison:
    """The runs of several models on one world, their summaries side by side and Definition 4 for each pair.

    Parameters
    ----------
    results : dict
        Model name -> :class:`~sarsp_edu.experiments.results.ExperimentResult`, in the order shown.
    a : float, default 100
        Definition 4's TSR threshold.
    """

    def __init__(self, results: dict, a: float = DEFINITION_4_A):
        self.results = dict(results)
        self.a = check_a(a)

    def table(self) -> pd.DataFrame:
        """Each summary metric, a column per model (an undefined cost rate is NaN)."""
        return pd.DataFrame({model: pd.Series(displayed_summary(result.summary))[list(SUMMARY_METRICS)]
                             for model, result in self.results.items()})

    def verdicts(self) -> pd.DataFrame:
        """For each pair of models, in the order given: which one Definition 4 prefers, if either."""
        rows = []
        for first, second in combinations(self.results, 2):
            one, two = self.results[first].summary, self.results[second].summary
            forward, backward = prefers(one, two, self.a), prefers(two, one, self.a)
            verdict = ("cannot decide (a cost rate is undefined)" if forward is None or backward is None
                       else first if forward else second if backward else "neither")
            rows.append({"pair": f"{first} vs {second}", "preferred": verdict})
        return pd.DataFrame(rows).set_index("pair")

    def save(self, directory) -> Path:
        """Each model's run in ``directory/<model>/`` (:meth:`ExperimentResult.save`)."""
        directory = Path(directory)
        for model, result in self.results.items():
            result.save(directory / model)
        return directory


def compare_models(config: ExperimentConfig | None = None, models=MODELS, progress: bool = False,
                   a: float = DEFINITION_4_A) -> ModelComparison:
    """Run several models paired on one config: one world, shift, data, outlier rows and episodes for all.

    Parameters
    ----------
    config : ExperimentConfig, optional
        Its ``model`` field is ignored.
    models : sequence of str, default every model of ``MODELS``
        Two or more distinct names of ``MODELS``, in the order shown.
    progress : bool, default False
        Each model's fits and episodes as progress bars.
    a : float, default 100
        Definition 4's TSR threshold.

    Returns
    -------
    ModelComparison
    """
    config = config_or_default(config)
    check_a(a)
    models = list(models)
    unknown = [model for model in models if model not in MODELS]
    if unknown or len(set(models)) != len(models) or len(models) < 2:
        raise ValueError(f"models must be two or more distinct names of {list(MODELS)}, got models={models!r}")
    experiments = experiments_on_one_world(config, {model: {"model": model} for model in models},
                                           progress=progress)
    return ModelComparison({model: _finish(experiments[model], progress) for model in models}, a)
