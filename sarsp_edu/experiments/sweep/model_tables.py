"""Tables of three models over a sweep's configurations: Table 2 with a third column, the paired tests, Definition 4,
and each configuration's three models side by side.

The cells a model sweep has run (:mod:`.models`) are set beside the same
cells' TP and GP runs: each configuration (m, p, nss) is the mean over the
seeds all three have run, as the paper's tables are; Table 2 is the mean over
configurations; the third model is tested against each of the other two over
configurations (Wilcoxon signed-rank, and the sign test of who is lower), and
Definition 4 is applied to every pair in every configuration.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy import stats

from ..metrics import SUMMARY_METRICS, prefers

__all__ = ["MODEL_NAMES", "model_sweep_curves", "model_sweep_frame", "model_sweep_tables"]

#: the models' names in tables and figures
MODEL_NAMES = {"tp": "TP", "gp": "GP", "t-likelihood": "t-likelihood GP"}


def model_sweep_frame(paired, runs: dict) -> pd.DataFrame:
    """One row per cell and model, for the cells the other model has run: m, p, nss, seed, model, the summaries.

    Parameters
    ----------
    paired : SweepResults
        The paired sweep.
    runs : dict
        ``{(m, p, nss, seed): ExperimentResult}`` of the other model (:func:`.models.load_model_sweep`).
    """
    rows = []
    for key, result in sorted(runs.items()):
        m, p, nss, seed = key
        comparison = paired.comparisons[key]
        for name, run in (("TP", comparison.tp), ("GP", comparison.gp), (MODEL_NAMES[result.config.model], result)):
            rows.append({"m": m, "p": p, "nss": nss, "seed": seed, "model": name, **run.summary})
    return pd.DataFrame(rows, columns=["m", "p", "nss", "seed", "model", *SUMMARY_METRICS])


def model_sweep_tables(paired, runs: dict, a: float | None = None) -> dict:
    """Table 2 of three models, the paired tests of the third against each other, Definition 4 per pair, and each
    configuration.

    Parameters
    ----------
    paired : SweepResults
    runs : dict
        As for :func:`model_sweep_frame`.
    a : float, optional
        Definition 4's threshold (default: the paired sweep's).

    Returns
    -------
    dict of DataFrames
        ``"mean"``: each metric's mean over configurations, a column per model, and the configurations'
        count; ``"tests"``: for the third model against TP and against GP and each metric, the median
        difference over configurations, the Wilcoxon signed-rank p-value and the sign test's (the share of
        configurations where the third model is lower, and its p-value); ``"definition4"``: for each ordered
        pair, in how many configurations Definition 4 prefers the first, the second, or neither;
        ``"configurations"``: each configuration's seeds run and its total cost, TSR and steps per model (the
        mean over those seeds), a row per (m, p, nss).
    """
    a = paired.a if a is None else a
    frame = model_sweep_frame(paired, runs)
    models = list(dict.fromkeys(frame["model"]))
    per_config = frame.groupby(["m", "p", "nss", "model"], sort=True)[list(SUMMARY_METRICS)].mean()
    wide = {model: per_config.xs(model, level="model") for model in models}
    mean = pd.DataFrame({model: wide[model].mean() for model in models})
    mean["configurations"] = len(wide[models[0]])
    third, tests, verdicts = models[-1], [], []
    for other in models[:-1]:
        for metric in SUMMARY_METRICS:
            difference = (wide[third][metric] - wide[other][metric]).dropna()
            nonzero = difference[difference != 0]
            lower, n = int((nonzero < 0).sum()), len(nonzero)
            tests.append({"against": other, "metric": metric, "median difference": float(difference.median()),
                          "wilcoxon p": float(stats.wilcoxon(nonzero).pvalue) if n > 1 else np.nan,
                          f"{third} lower": f"{lower} of {n}",
                          "sign test p": float(stats.binomtest(lower, n).pvalue) if n else np.nan})
    for first, second in ((third, "TP"), (third, "GP"), ("TP", "GP")):
        counts = {"first preferred": 0, "second preferred": 0, "neither": 0}
        for config in wide[first].index:
            one, two = wide[first].loc[config].to_dict(), wide[second].loc[config].to_dict()
            counts["first preferred" if prefers(one, two, a) else
                   "second preferred" if prefers(two, one, a) else "neither"] += 1
        verdicts.append({"pair": f"{first} vs {second}", **counts})
    shown = ("total_cost", "task_success_rate", "mean_steps")
    configurations = pd.DataFrame({f"{metric}: {model}": wide[model][metric] for metric in shown for model in models})
    seeds = frame[frame["model"] == third].groupby(["m", "p", "nss"])["seed"]
    configurations.insert(0, "seeds", seeds.agg(lambda run: ", ".join(str(seed) for seed in sorted(run))))
    return {"mean": mean, "tests": pd.DataFrame(tests).set_index(["against", "metric"]),
            "definition4": pd.DataFrame(verdicts).set_index("pair"), "configurations": configurations}


def model_sweep_curves(paired, runs: dict, metric: str) -> pd.DataFrame:
    """The learning curves of the three models: ``metric`` per episode, the mean over the cells the third has run.

    Parameters
    ----------
    paired : SweepResults
    runs : dict
        As for :func:`model_sweep_frame`.
    metric : str
        A records column, such as one of ``SUMMARY_METRICS`` (the running value after each episode).

    Returns
    -------
    pandas.DataFrame
        Indexed by episode, a column per model (TP, GP, the third).
    """
    if not runs:
        raise ValueError("runs holds no cell: the third model has run none of the paired sweep's cells yet")
    series = {}
    for key, result in sorted(runs.items()):
        comparison = paired.comparisons[key]
        for name, run in (("TP", comparison.tp), ("GP", comparison.gp), (MODEL_NAMES[result.config.model], result)):
            if metric not in run.records:
                raise ValueError(f"metric must be a records column such as {SUMMARY_METRICS}, got metric={metric!r}")
            series.setdefault(name, []).append(run.records.set_index("episode")[metric])
    return pd.DataFrame({name: pd.concat(values, axis=1).mean(axis=1) for name, values in series.items()})
