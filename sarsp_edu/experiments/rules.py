"""The rule study: does the three models' ranking survive the choices it was measured under?

The three-model sweep ranked the TP, the GP and the GP with Student-t noise
under one safety rule (the noisy predictive variance against sigma*^2 = 0.8),
one ``likelihood_nu`` (3), one fit budget (50 Adam steps from 1.0) and one
outlier model (inputs and targets scaled by m).  Each question below changes
one of them, on the ablation's cells and seeds (``ABLATION_CELLS`` x
``ABLATION_SEEDS``, 80 episodes: the threshold study's six worlds), every run
paired with the stored ones on the same worlds:

- ``rule``: the latent variance (the paper's eqs. 5-6) against sigma*^2 in
  {0.1, 0.8, 10}, and the tail rule (the model's own predictive probability
  of a distance below d at most delta) at delta in {0.01, 0.05, 0.2}; the
  noisy rule's runs at 0.1, 0.8 and 10 are the ablation's, stored before;
- ``nu``: the Student-t noise's nu in {2.2, 2.5, 5, fitted} beside the stored
  3;
- ``fit``: each of those with one restart from narrow noise and a longer
  search in the offline fit, and the corrective updates' refits searching on
  from the last fit (:data:`CONVERGED_FIT`);
- ``threshold``: the noisy rule at sigma*^2 in {20, 50, 100};
- ``targets``: outliers in the targets only, at their clean inputs;
- ``cost model``: the GP with Student-t noise as the cost model beside the
  TP's reward model, so that safety and success are no longer confounded.

Which rule is the fairer is decided by a criterion set before the runs: the
rule under which the models, not the backup, take the decisions, that is
the lowest largest mean backup share over the three models
(:meth:`RuleStudy.fairest_rule`).  ``sarsp-edu rule-study`` runs the study
(resumable: each run is stored as it finishes) and prints its tables.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ..config import ABLATION_CELLS, ABLATION_SEEDS, FITTED_NU, RULE_QUESTIONS
from .ablation import run_ablation, setting_folder
from .sweep import CellsFailed
from .sweep.models import run_model_sweep
from .thresholds import DEFAULT_SETTING

__all__ = ["CONVERGED_FIT", "FAIR_CANDIDATES", "QUESTIONS", "RULE_SETTINGS", "STUDY_MEASURES", "RuleStudy",
           "StudySetting", "run_rule_study", "study_settings"]

#: the study's episodes per run: the ablation's, whose stored runs it is set beside
STUDY_EPISODES = 80
#: the fits of the ``fit`` question: one extra start, from narrow noise, and four times the paper's steps; the
#: online refits search on from the last fit (one start: a refit from 1 with restarts took each cell's refits from
#: minutes to hours, 88 at nu 2.2, m = 80, p = 0.4, and more than a session at nu 2.5)
CONVERGED_FIT = dict(fit_restarts=1, optimizer_steps=200, warm_refits=True)

#: the two rules the full-width sweep may run under, at the reference code's sigma*^2 and the tail
#: rule's default delta:
#: :meth:`RuleStudy.fairest_rule` chooses between them
FAIR_CANDIDATES = ("latent variance, threshold 0.8", "tail rule, delta 0.05")

#: the questions, in the order they are run and printed
QUESTIONS = RULE_QUESTIONS


@dataclass(frozen=True)
class StudySetting:
    """One setting of the study: its question, name, the models it runs and the settings it changes.

    ``stored`` names the ablation setting whose stored runs already are this setting's (the noisy rule at
    0.1, 0.8 and 10, nu = 3): nothing is run for it.
    """

    question: str
    name: str
    models: tuple
    changes: dict = field(default_factory=dict)
    stored: str | None = None

    @property
    def folder(self) -> str:
        return setting_folder(self.name)


_ALL = ("tp", "gp", "t-likelihood")
_T = ("t-likelihood",)
_NUS = (2.2, 2.5, 3.0, 5.0, FITTED_NU)


def _nu_name(nu) -> str:
    return "nu fitted" if nu == FITTED_NU else f"nu {nu:g}"


#: every setting, in the order the study runs them (the rule first: the full-width sweep waits on it)
RULE_SETTINGS = (
    StudySetting("rule", "noisy variance, threshold 0.8", _ALL, stored=DEFAULT_SETTING),
    StudySetting("rule", "latent variance, threshold 0.8", _ALL, dict(variance="latent")),
    StudySetting("rule", "tail rule, delta 0.05", _ALL, dict(safe_rule="tail", tail_delta=0.05)),
    StudySetting("rule", "noisy variance, threshold 0.1", _ALL, stored="default, variance threshold 0.1"),
    StudySetting("rule", "noisy variance, threshold 10", _ALL, stored="default, variance threshold 10"),
    StudySetting("rule", "latent variance, threshold 0.1", _ALL, dict(variance="latent", variance_threshold=0.1)),
    StudySetting("rule", "latent variance, threshold 10", _ALL, dict(variance="latent", variance_threshold=10.0)),
    StudySetting("rule", "tail rule, delta 0.01", _ALL, dict(safe_rule="tail", tail_delta=0.01)),
    StudySetting("rule", "tail rule, delta 0.2", _ALL, dict(safe_rule="tail", tail_delta=0.2)),
    *(StudySetting("nu", _nu_name(nu), _T, {} if nu == 3.0 else dict(likelihood_nu=nu),
                   stored=DEFAULT_SETTING if nu == 3.0 else None) for nu in _NUS),
    *(StudySetting("fit", f"{_nu_name(nu)}, restart, 200 steps, warm refits", _T,
                   {**({} if nu == 3.0 else dict(likelihood_nu=nu)), **CONVERGED_FIT}) for nu in _NUS),
    *(StudySetting("threshold", f"noisy variance, threshold {threshold:g}", _ALL,
                   dict(variance_threshold=float(threshold))) for threshold in (20, 50, 100)),
    StudySetting("targets", "outliers in the targets only", _ALL, dict(outliers="targets")),
    StudySetting("cost model", "t-likelihood cost model, TP reward model", _T, dict(reward_model="tp")),
)


def study_settings(questions=None) -> list:
    """The settings of ``questions`` (default all of :data:`QUESTIONS`), in the study's order.

    Raises
    ------
    ValueError
        A question that is not one of :data:`QUESTIONS`.
    """
    questions = QUESTIONS if questions is None else tuple(questions)
    unknown = sorted(set(questions) - set(QUESTIONS))
    if unknown:
        raise ValueError(f"questions must be among {list(QUESTIONS)}, got {unknown}")
    return [setting for setting in RULE_SETTINGS if setting.question in questions]


def run_rule_study(results_dir, ablation_dir, *, questions=None, n_jobs: int = 1, report=None) -> None:
    """Run every setting of the study not stored yet, in the study's order.

    Per setting: the TP and GP runs as one ablation setting (``<results_dir>/paired``, a sweep folder each, as
    ``sarsp-edu ablation`` writes them), then the GP with Student-t noise as a model sweep on those runs
    (``<results_dir>/t-likelihood/<setting folder>``); a setting of that model alone runs it on the
    ablation's default row, with the setting's changes.  Settings whose runs the ablation stored before are
    read from it, not run.

    Parameters
    ----------
    results_dir : path-like
        The study's folder (``results/rule-study``).
    ablation_dir : path-like
        The ablation's folder (``results/ablation``), which holds the stored TP and GP runs.
    questions : iterable of str, optional
        Only these of :data:`QUESTIONS`.
    n_jobs : int, default 1
        Worker processes.
    report : callable, optional
        Called with a line as each setting starts and each run is stored.
    """
    results_dir, ablation_dir = Path(results_dir), Path(ablation_dir)
    say = report if report is not None else (lambda line: None)
    failed = []
    for setting in study_settings(questions):
        if setting.stored is not None:
            continue
        say(f"{setting.question}: {setting.name}")
        try:
            if {"tp", "gp"} & set(setting.models):
                run_ablation({setting.name: setting.changes}, cells=ABLATION_CELLS, seeds=ABLATION_SEEDS,
                             episodes=STUDY_EPISODES, results_dir=results_dir / "paired", n_jobs=n_jobs,
                             command=f"sarsp-edu rule-study --out {results_dir} (setting {setting.name!r})")
                paired, changes = results_dir / "paired" / setting.folder, None
            else:
                paired, changes = ablation_dir / setting_folder(DEFAULT_SETTING), setting.changes
            if "t-likelihood" in setting.models:
                run_model_sweep(paired, results_dir / "t-likelihood" / setting.folder, n_jobs=n_jobs, report=say,
                                changes=changes)
        except CellsFailed as exc:  # the other settings still run; this one's failures are said, and raised at the end
            failed.append(setting.name)
            say(f"{setting.name}: {len(exc.failures)} run(s) raised: {sorted(exc.failures)}")
    if failed:
        raise RuntimeError(f"runs of {len(failed)} setting(s) raised, the others are stored: {failed}; rerun the "
                           "study to retry them")


#: what the study's tables give per setting and model, each with its 95% interval over the runs
STUDY_MEASURES = ("total_cost", "task_success_rate", "backup_share")


def _fitted(result) -> dict:
    """The cost model's offline fit of a stored run, as the tables print it (NaN for runs stored before 0.3,
    which did not record it)."""
    fit = (result.fits or {}).get("offline", {}).get("cost", {})
    return {"cost noise variance": fit.get("noise_variance"), "cost nu": fit.get("nu"),
            "cost gradient norm": fit.get("gradient_norm")}


@dataclass
class RuleStudy:
    """The stored runs of the study: one row per setting, configuration, seed and model.

    Attributes
    ----------
    runs : pandas.DataFrame
        Columns ``question``, ``setting``, ``m``, ``p``, ``nss``, ``seed``, ``model`` ("TP", "GP", "t-likelihood
        GP"), the measures of :func:`~sarsp_edu.experiments.ablation.run_measures` and the cost model's fit
        (:func:`_fitted`).
    planned : int
        The runs each setting plans per model (the ablation's cells times its seeds).
    """

    runs: object
    planned: int = len(ABLATION_CELLS) * len(ABLATION_SEEDS)

    @classmethod
    def load(cls, results_dir, ablation_dir, models_dir, questions=None) -> "RuleStudy":
        """Read every stored run of the study's settings (those not run yet are left out).

        Parameters
        ----------
        results_dir : path-like
            The study's folder (:func:`run_rule_study`'s).
        ablation_dir, models_dir : path-like
            The ablation's folder and the folder of the third model's runs on its settings
            (``results/ablation``, ``results/ablation-t-likelihood``): the settings stored before.
        questions : iterable of str, optional
            Only these of :data:`QUESTIONS`.
        """
        import pandas as pd

        from .ablation import AblationResults, run_measures
        from .sweep.model_tables import MODEL_NAMES
        from .sweep.models import MODEL_SWEEP_FILE, load_model_sweep

        results_dir, ablation_dir, models_dir = Path(results_dir), Path(ablation_dir), Path(models_dir)
        ablations = {}

        def ablation(folder):
            if folder not in ablations:
                ablations[folder] = AblationResults.load(folder) if (folder / "ablation.json").exists() else None
            return ablations[folder]

        rows = []
        for setting in study_settings(questions):
            stored = setting.stored
            paired = ablation(ablation_dir if stored else results_dir / "paired")
            name = stored or setting.name
            runs = {}
            if paired is not None and name in paired.sweeps and {"tp", "gp"} & set(setting.models):
                for key, comparison in paired.sweeps[name].comparisons.items():
                    runs.update({(key, model): getattr(comparison, model) for model in ("tp", "gp")})
            folder = (models_dir / setting_folder(stored)) if stored else results_dir / "t-likelihood" / setting.folder
            if "t-likelihood" in setting.models and (folder / MODEL_SWEEP_FILE).is_file():
                runs.update({(key, "t-likelihood"): result for key, result in load_model_sweep(folder)[1].items()})
            order = {model: i for i, model in enumerate(MODEL_NAMES)}  # TP, GP, then the third
            for ((m, p, nss, seed), model), result in sorted(runs.items(), key=lambda item: (order[item[0][1]],
                                                                                               item[0][0])):
                rows.append({"question": setting.question, "setting": setting.name, "m": m, "p": p, "nss": nss,
                             "seed": seed, "model": MODEL_NAMES[model], **run_measures(result), **_fitted(result)})
        return cls(pd.DataFrame(rows))

    def table(self, question: str):
        """Per setting of ``question`` and model: the runs stored, each of :data:`STUDY_MEASURES`' mean with its
        95% t-interval over the runs, and the medians of the cost model's fitted noise, nu and gradient norm.

        The interval is over the (configuration, seed) runs, so it mixes the configurations' spread with
        run-to-run noise: read it as a width, not a test (:meth:`pairs` compares the models run by run).  It is
        cut to the measure's range (a share and a rate lie in [0, 100], a cost is at least 0), which six runs
        far apart can overshoot.
        """
        import pandas as pd

        from .ablation import _t_interval

        if not len(self.runs):
            return pd.DataFrame()
        here = self.runs[self.runs["question"] == question]
        out = []
        for (setting, model), group in here.groupby(["setting", "model"], sort=False):
            row = {"setting": setting, "model": model, "runs": f"{len(group)} of {self.planned}"}
            for measure in STUDY_MEASURES:
                low, high = _t_interval(group[measure], measure=measure)
                row[measure] = float(group[measure].mean())
                row[f"{measure} 95% CI"] = f"[{low:.3g}, {high:.3g}]"
            for fitted in ("cost noise variance", "cost nu", "cost gradient norm"):
                values = pd.to_numeric(group[fitted], errors="coerce")
                row[f"median {fitted}"] = float(values.median()) if values.notna().any() else float("nan")
            out.append(row)
        return pd.DataFrame(out).set_index(["setting", "model"]) if out else pd.DataFrame()

    def pairs(self, question: str):
        """Per setting of ``question`` and pair of models, over the runs both have: in how many the first had the
        lower total cost and the higher TSR ("k of n"), and the mean differences (first minus second)."""
        import pandas as pd

        if not len(self.runs):
            return pd.DataFrame()
        here = self.runs[self.runs["question"] == question]
        keys, out = ["m", "p", "nss", "seed"], []
        for setting, runs in here.groupby("setting", sort=False):
            models = list(dict.fromkeys(runs["model"]))
            for i, first in enumerate(models):
                for second in models[i + 1:]:
                    both = runs[runs["model"] == first].merge(runs[runs["model"] == second], on=keys,
                                                               suffixes=(" 1", " 2"))
                    cost = both["total_cost 1"] - both["total_cost 2"]
                    tsr = both["task_success_rate 1"] - both["task_success_rate 2"]
                    out.append({"setting": setting, "pair": f"{first} vs {second}",
                                "lower total cost": f"{int((cost < 0).sum())} of {len(both)}",
                                "mean total cost difference": float(cost.mean()),
                                "higher TSR": f"{int((tsr > 0).sum())} of {len(both)}",
                                "mean TSR difference": float(tsr.mean())})
        return pd.DataFrame(out).set_index(["setting", "pair"]) if out else pd.DataFrame()

    def fairest_rule(self):
        """Of :data:`FAIR_CANDIDATES`, the rule whose largest mean backup share over the three models is the
        lowest (the criterion set before the runs: the models, not the backup, take the decisions), among
        those whose three models have every run stored; None while neither has."""
        table = self.table("rule")
        if table.empty:
            return None
        complete = {setting: group for setting, group in table.groupby(level="setting", sort=False)
                    if setting in FAIR_CANDIDATES and len(group) == 3
                    and all(runs == f"{self.planned} of {self.planned}" for runs in group["runs"])}
        if not complete:
            return None
        return min(complete, key=lambda setting: complete[setting]["backup_share"].max())
