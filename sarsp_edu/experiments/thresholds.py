"""The threshold study: the three models' safety against the safe set's variance threshold sigma*^2.

The paper sets sigma*^2 = 0.8 once.  An action is safe only where the cost
model's predicted variance is at most sigma*^2, so a model whose fitted noise
keeps its variance above the threshold leaves every decision to the backup
rule (Tutorial 4, "3b. The GP agent"): the paper's safety result may hinge on
the threshold against each model's fitted noise.  The ablation's settings
``"default, variance threshold X"`` (``ablation.VARIANCE_THRESHOLDS``), beside
its default row at 0.8, run the TP and the GP on the ablation's cells and
seeds; ``sarsp-edu model-sweep`` runs the GP with Student-t noise on each of
those settings' folders, on the same worlds, data and episodes.  A
:class:`ThresholdStudy` reads both and tabulates, per threshold and model,
the task success rate, the total cost and the share of decisions the backup
rule took, and, per threshold, who beats whom in the paired runs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from .._internal.io import read_json
from ..config import VARIANCE_THRESHOLD
from .ablation import VARIANCE_THRESHOLDS, AblationResults, _t_interval, run_measures, setting_folder
from .sweep.model_tables import MODEL_NAMES
from .sweep.models import MODEL_SWEEP_FILE, load_model_sweep

__all__ = ["DEFAULT_SETTING", "THRESHOLD_MEASURES", "ThresholdStudy", "threshold_settings"]

#: the ablation's default row, whose threshold is the reference code's 0.8 (the paper prints none)
DEFAULT_SETTING = "default (per action, k=100, whole cost fit, 1,000-row reward fit)"
#: what the study tabulates for every threshold and model
THRESHOLD_MEASURES = ("backup_share", "total_cost", "task_success_rate", "mean_steps")


def threshold_settings() -> list:
    """The ablation settings of the study: the default row (sigma*^2 = 0.8) and one per other threshold."""
    return [DEFAULT_SETTING, *(f"default, variance threshold {threshold:g}" for threshold in VARIANCE_THRESHOLDS)]


@dataclass
class ThresholdStudy:
    """The runs of the threshold study, one row per threshold, configuration, seed and model.

    Attributes
    ----------
    runs : pandas.DataFrame
        Columns ``threshold``, ``setting``, ``m``, ``p``, ``nss``, ``seed``, ``model`` ("TP", "GP",
        "t-likelihood GP") and the measures of :func:`~sarsp_edu.experiments.ablation.run_measures`.
    planned : int, optional
        The runs the ablation plans per setting and model (its cells times its seeds).
    """

    runs: pd.DataFrame
    planned: int | None = None

    @classmethod
    def load(cls, ablation_dir, models_dir=None) -> "ThresholdStudy":
        """Read the study's stored runs: the TP and GP from an ablation's folder, the third model from another.

        Parameters
        ----------
        ablation_dir : path-like
            An ablation's results (``results/ablation``); its settings of :func:`threshold_settings` are read,
            those not run yet are left out.
        models_dir : path-like, optional
            A folder holding, per setting, the model sweep of a third model on that setting's folder
            (``<models_dir>/<setting folder>``, as ``sarsp-edu model-sweep --paired
            results/ablation/<setting folder> --out <models_dir>/<setting folder>`` writes it).

        Raises
        ------
        ValueError
            A model sweep in ``models_dir`` that ran on another folder than the ablation's setting.
        """
        ablation = AblationResults.load(ablation_dir)
        names = [name for name in threshold_settings() if name in ablation.sweeps]
        frame = ablation.runs()
        frame = frame[frame["setting"].isin(names)].copy()
        frame.insert(0, "threshold", [ablation.sweeps[name].base.variance_threshold for name in frame["setting"]])
        rows = []
        for name in names if models_dir is not None else ():
            folder = Path(models_dir) / setting_folder(name)
            if not (folder / MODEL_SWEEP_FILE).is_file():
                continue
            setting_dir = Path(ablation_dir) / setting_folder(name)
            ran_on = (folder / read_json(folder / MODEL_SWEEP_FILE, keys=("paired",))["paired"]).resolve()
            if ran_on != setting_dir.resolve():
                raise ValueError(f"{folder} ran on the paired sweep {ran_on}, not on the ablation's setting "
                                 f"{name!r} ({setting_dir.resolve()})")
            _, runs = load_model_sweep(folder)
            threshold = ablation.sweeps[name].base.variance_threshold
            for (m, p, nss, seed), result in sorted(runs.items()):
                rows.append({"threshold": threshold, "setting": name, "m": m, "p": p, "nss": nss, "seed": seed,
                             "model": MODEL_NAMES[result.config.model], **run_measures(result)})
        runs = pd.concat([frame, pd.DataFrame(rows)], ignore_index=True) if rows else frame
        design = read_json(Path(ablation_dir) / "ablation.json", keys=("cells", "seeds"))
        return cls(runs.sort_values(["threshold", "model", "m", "p", "nss", "seed"], kind="stable")
                   .reset_index(drop=True), planned=len(design["cells"]) * len(design["seeds"]))

    def complete(self) -> "ThresholdStudy":
        """The study less every (threshold, model) whose runs are not all stored yet, so that each mean is over
        the same configurations and seeds (:attr:`missing` says what is left out)."""
        counts = self.runs.groupby(["threshold", "model"])["seed"].transform("size")
        return ThresholdStudy(self.runs[counts == self.planned].reset_index(drop=True), self.planned)

    @property
    def missing(self) -> dict:
        """``{(threshold, model): runs stored}`` for each threshold and model with fewer runs than planned: every
        threshold of :func:`threshold_settings` for each model with runs stored (0 where none is)."""
        stored = self.runs.groupby(["threshold", "model"]).size().to_dict()
        every = sorted({VARIANCE_THRESHOLD, *VARIANCE_THRESHOLDS})
        return {(threshold, model): stored.get((threshold, model), 0) for threshold in every
                for model in self.models if stored.get((threshold, model), 0) != self.planned}

    @property
    def thresholds(self) -> list:
        """The thresholds with stored runs, smallest first."""
        return sorted(set(self.runs["threshold"]))

    @property
    def models(self) -> list:
        """The models with stored runs, in the order TP, GP, then the third."""
        return [name for name in MODEL_NAMES.values() if name in set(self.runs["model"])]

    def table(self) -> pd.DataFrame:
        """Per threshold and model: the runs, and each of :data:`THRESHOLD_MEASURES`' mean and 95% t-interval.

        The interval is over the (configuration, seed) runs, so it mixes the configurations' spread with
        run-to-run noise: read it as a width, not a test (:meth:`pairs` compares the models run by run).
        """
        out = []
        for threshold in self.thresholds:
            for model in self.models:
                group = self.runs[(self.runs["threshold"] == threshold) & (self.runs["model"] == model)]
                if not len(group):
                    continue
                row = {"threshold": threshold, "model": model, "runs": len(group)}
                for measure in THRESHOLD_MEASURES:
                    row[measure] = float(group[measure].mean())
                    row[f"{measure} low"], row[f"{measure} high"] = _t_interval(group[measure], measure=measure)
                out.append(row)
        return pd.DataFrame(out).set_index(["threshold", "model"])

    def pairs(self) -> pd.DataFrame:
        """Per threshold and pair of models, over the runs both have: who has the lower total cost, the higher TSR.

        Columns: ``runs`` (paired runs), ``lower total cost`` (the runs where the first model violated less,
        "k of n"), ``mean total cost difference`` (first minus second), ``higher TSR`` and
        ``mean TSR difference`` (points).
        """
        keys = ["threshold", "m", "p", "nss", "seed"]
        models, out = self.models, []
        pairs = [(a, b) for i, a in enumerate(models) for b in models[i + 1:]]
        for threshold in self.thresholds:
            here = self.runs[self.runs["threshold"] == threshold]
            for first, second in pairs:
                both = here[here["model"] == first].merge(here[here["model"] == second], on=keys,
                                                          suffixes=(" 1", " 2"))
                if not len(both):
                    continue
                cost = both["total_cost 1"] - both["total_cost 2"]
                tsr = both["task_success_rate 1"] - both["task_success_rate 2"]
                out.append({"threshold": threshold, "pair": f"{first} vs {second}", "runs": len(both),
                            "lower total cost": f"{int((cost < 0).sum())} of {len(both)}",
                            "mean total cost difference": float(cost.mean()),
                            "higher TSR": f"{int((tsr > 0).sum())} of {len(both)}",
                            "mean TSR difference": float(tsr.mean())})
        return pd.DataFrame(out).set_index(["threshold", "pair"])

    def lowest_threshold_off_backup(self, share: float = 50.0) -> dict:
        """Per model, the smallest threshold whose mean backup share is below ``share`` % (nan if none is).

        Parameters
        ----------
        share : float, default 50
            The backup share (%) below which a model is said to have left the backup.
        """
        table = self.table()
        found = {}
        for model in self.models:
            below = [threshold for threshold in self.thresholds
                     if (threshold, model) in table.index and table.loc[(threshold, model), "backup_share"] < share]
            found[model] = min(below) if below else math.nan
        return found
