"""Which part of SARSP carries which effect: the paired comparison under a list of settings.

An ablation runs the TP-versus-GP comparison of a few configurations and
seeds once per *setting* (a preset, with some fields changed) and tabulates,
for each setting and model, the task success rate, the mean episode length,
the total cost, the cost rate, the share of decisions taken by the backup
rule and the share of failed episodes that ended trapped on at most two
cells, each with a 95% interval over the (configuration, seed) runs.

``ABLATION_SETTINGS`` are the rows that explain how the package's old
behaviour (one prior per step, hyperparameters fitted on 500 rows) differs
from the reference code's (a prior per action, fits on the whole buffer).
Each setting's runs are a sweep folder of their own, so an interrupted
ablation resumes where it stopped.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import stats

from .._internal.io import StoredResultError, atomic_write_text, read_json
from .._version import __version__
from ..config import ABLATION_CELLS, ABLATION_SEEDS, PRESETS, ExperimentConfig
from .metrics import backup_share, trapped_episodes
from .sweep import CellsFailed, SweepResults, run_sweep
from .sweep.cells import _check_cell
from .sweep.failures import collecting
from .sweep.run import _grid

__all__ = [
    "ABLATION_CELLS",
    "ABLATION_SETTINGS",
    "PRIOR_AND_FITS",
    "VARIANCE_THRESHOLDS",
    "AblationResults",
    "cost_fit_length_scales",
    "run_ablation",
    "run_measures",
    "setting_config",
    "setting_folder",
]

#: the three configurations of the measurements in the reproduction issue: mild, middle, severe

_OLD_FITS = dict(cost_fit_points=500, reward_fit_points=500)

#: the thresholds sigma*^2 of the threshold study besides the default's 0.8
VARIANCE_THRESHOLDS = (0.1, 0.3, 2.0, 5.0, 10.0)
#: name -> settings: an optional "preset" (default "default") and ExperimentConfig fields to change
ABLATION_SETTINGS = {
    "per step, k=100, 500-row fits (the package before)":
        dict(prior_draw="per_step", k_prior=100, retrain="always", **_OLD_FITS),
    "per step, k=400, 500-row fits": dict(prior_draw="per_step", k_prior=400, retrain="always", **_OLD_FITS),
    "per step, k=400, sampled, 500-row fits":
        dict(prior_draw="per_step", k_prior=400, predictive="sample", retrain="always", **_OLD_FITS),
    "per action, k=100, 500-row fits": dict(prior_draw="per_action", k_prior=100, retrain="always", **_OLD_FITS),
    "per action, k=400, 500-row fits": dict(prior_draw="per_action", k_prior=400, retrain="always", **_OLD_FITS),
    "per step, k=100, default fits": dict(prior_draw="per_step"),
    "default (per action, k=100, whole cost fit, 1,000-row reward fit)": dict(),
    "default, retrain after every correction": dict(retrain="always"),
    "default, k=400": dict(k_prior=400),
    "default, reference placement and 101-step limit": dict(placement="reference", max_steps=101),
    "paper_text preset": dict(preset="paper_text"),
    "reference preset": dict(preset="reference"),
    # the reference preset less its slowest part: is the whole-buffer reward fit what lifts the levels?
    "reference preset, reward fit on 1,000 rows": dict(preset="reference", reward_fit_points=1000),
    # the safe set's variance threshold, which the paper sets once (0.8, the default row above): where does each
    # model stop taking the backup, and does the TP stay the safer model at every threshold?
    **{f"default, variance threshold {threshold:g}": dict(variance_threshold=threshold)
       for threshold in VARIANCE_THRESHOLDS},
}


def setting_config(setting: dict, **changes) -> ExperimentConfig:
    """The config of one ablation setting (its preset, its fields, then ``changes``).

    Parameters
    ----------
    setting : dict
        A value of :data:`ABLATION_SETTINGS`: config fields, and optionally ``"preset"`` (default ``"default"``).
    **changes
        Further config fields (the cell's outlier settings and seed, say); they override the setting's.
    """
    setting = dict(setting)
    preset = setting.pop("preset", "default")
    return ExperimentConfig.from_preset(preset, **{**setting, **changes})


#: the two questions of the reproduction issue as a 2 x 2 design: how the strategic
#: prior is drawn, and on how many rows the hyperparameters are fitted
PRIOR_AND_FITS = {
    ("per step", "500 rows"): "per step, k=100, 500-row fits (the package before)",
    ("per action", "500 rows"): "per action, k=100, 500-row fits",
    ("per step", "default fits"): "per step, k=100, default fits",
    ("per action", "default fits"): "default (per action, k=100, whole cost fit, 1,000-row reward fit)",
}


def cost_fit_length_scales(config: ExperimentConfig | None = None, rows: int = 500, seed: int = 0) -> pd.DataFrame:
    """Why fits on a few hundred random rows flatten the cost model: one buffer, four subsets, one fit each.

    The TP cost model (the config's settings, ``model="tp"``) is fitted on
    ``rows`` random rows of the offline cost buffer, on as many random rows
    with no outlier, on one row per distinct input, and on every row; each
    row of the result gives the subset's size, its distinct inputs and
    outlier rows, the fitted length scale and the kernel's correlation
    between inputs one and two grid steps apart.  ``REPRODUCTION.md``
    ("Why 500-row fits flatten the cost model") reads it.

    Parameters
    ----------
    config : ExperimentConfig, optional
        The world and offline data: by default the ablation's first cell,
        (m, p, nss) = (40, 0.2, 2), seed 0.
    rows : int, default 500
        The random subsets' size (the package's first release fitted on 500).
    seed : int, default 0
        Seeds the random subsets.
    """
    from ..world.preparation import prepare
    from .experiment import make_model

    if config is None:
        m, p, nss = ABLATION_CELLS[0]
        config = ExperimentConfig(outlier_magnitude=m, outlier_proportion=p, n_switch_states=nss, seed=0)
    data = prepare(config).data
    cost, outliers = data.cost, np.asarray(data.outlier_indices)
    clean = np.setdiff1d(np.arange(len(cost)), outliers)
    if isinstance(rows, bool) or not (isinstance(rows, (int, np.integer)) and 1 <= rows <= len(clean)):
        raise ValueError(f"rows must be a whole number in [1, {len(clean)}] (the buffer's clean rows), "
                         f"got rows={rows!r}")
    rng = np.random.default_rng(seed)
    subsets = {f"{rows} random rows": rng.choice(len(cost), rows, replace=False),
               f"{rows} random rows, no outlier": rng.choice(clean, rows, replace=False),
               "one row per distinct input": np.unique(cost.X, axis=0, return_index=True)[1],
               f"all {len(cost)} rows": np.arange(len(cost))}
    tp = dataclasses.replace(config, model="tp")
    table = []
    for label, idx in subsets.items():
        scale = float(make_model(tp).fit(cost.X[idx], cost.y[idx]).kernel_.length_scale)
        table.append({"fitted on": label, "rows": len(idx), "distinct inputs": len(np.unique(cost.X[idx], axis=0)),
                      "outlier rows": int(np.isin(idx, outliers).sum()), "length scale": scale,
                      "correlation, 1 step": float(np.exp(-1 / (2 * scale**2))),
                      "2 steps": float(np.exp(-4 / (2 * scale**2)))})
    return pd.DataFrame(table).set_index("fitted on")


def setting_folder(name: str) -> str:
    """The folder, inside an ablation's results, of the setting called ``name``."""
    return re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-")[:80]


#: each measure's range, to which its interval is cut (a few runs far apart can overshoot it)
MEASURE_RANGES = {"total_cost": (0.0, math.inf), "task_success_rate": (0.0, 100.0), "backup_share": (0.0, 100.0),
                  "mean_steps": (0.0, math.inf), "cost_rate": (0.0, math.inf)}


def _t_interval(values: np.ndarray, level: float = 0.95, measure: str | None = None) -> tuple:
    """The mean's t-interval, cut to ``measure``'s range (:data:`MEASURE_RANGES`) where one is named."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    if len(values) < 2:
        return (math.nan, math.nan)
    half = stats.t.ppf((1 + level) / 2, len(values) - 1) * values.std(ddof=1) / math.sqrt(len(values))
    low, high = MEASURE_RANGES.get(measure, (-math.inf, math.inf))
    return (max(values.mean() - half, low), min(values.mean() + half, high))


def run_measures(result) -> dict:
    """One run's measures as the ablation tabulates them: its episodes and successes, TSR, mean steps, total
    cost, cost rate, backup share (%), failures, trapped failures and retrains.

    Parameters
    ----------
    result : ExperimentResult
        A stored or fresh run (its ``records`` and ``summary``).
    """
    records, summary = result.records, result.summary
    failed = ~records["task_completed"].astype(bool)
    return {"episodes": len(records), "successes": int((~failed).sum()),
            "task_success_rate": summary["task_success_rate"], "mean_steps": summary["mean_steps"],
            "total_cost": summary["total_cost"], "cost_rate": summary["cost_rate"],
            "backup_share": 100.0 * backup_share(records), "failures": int(failed.sum()),
            "trapped_failures": int(trapped_episodes(records).sum()), "retrains": int(records["retrains"].iloc[-1])}


@dataclass
class AblationResults:
    """The sweeps of an ablation, one per setting.

    Attributes
    ----------
    sweeps : dict
        Setting name -> :class:`~sarsp_edu.experiments.sweep.SweepResults`.
    settings : dict
        Setting name -> the settings it changed.
    """

    sweeps: dict = field(default_factory=dict)
    settings: dict = field(default_factory=dict)

    def runs(self) -> pd.DataFrame:
        """One row per setting, configuration, seed and model, with the per-run measures and counts."""
        rows = []
        for name, sweep in self.sweeps.items():
            for (m, p, nss, seed), comparison in sorted(sweep.comparisons.items()):
                for model in ("tp", "gp"):
                    rows.append({"setting": name, "m": m, "p": p, "nss": nss, "seed": seed, "model": model.upper(),
                                 **run_measures(getattr(comparison, model))})
        return pd.DataFrame(rows)

    def table(self) -> pd.DataFrame:
        """Per setting and model: each measure's mean over runs with a 95% t-interval, and trapped failures.

        The interval is over the (configuration, seed) runs, so it mixes the
        configurations' spread with run-to-run noise: read it as a width,
        not a test.
        """
        runs = self.runs()
        out = []
        for (name, model), group in runs.groupby(["setting", "model"], sort=False):
            row = {"setting": name, "model": model, "runs": len(group)}
            for metric in ("task_success_rate", "mean_steps", "total_cost", "cost_rate", "backup_share"):
                low, high = _t_interval(group[metric], measure=metric)
                row[metric] = group[metric].mean()
                row[f"{metric} 95% CI"] = f"[{low:.3g}, {high:.3g}]"
            row["trapped failures"] = f"{group['trapped_failures'].sum()} of {group['failures'].sum()}"
            row["retrains"] = group["retrains"].mean()
            out.append(row)
        return pd.DataFrame(out).set_index(["setting", "model"])

    @classmethod
    def load(cls, results_dir) -> "AblationResults":
        """Every finished run of an ablation folder written by :func:`run_ablation`."""
        results_dir = Path(results_dir)
        meta = results_dir / "ablation.json"
        if not meta.exists():
            raise FileNotFoundError(f"{results_dir} is not an ablation results folder (no ablation.json)")
        payload = read_json(meta, keys=("settings",))
        if not isinstance(payload["settings"], dict):
            raise StoredResultError(f"{meta} holds settings={payload['settings']!r}, not a mapping of names to "
                                    "settings; it was edited")
        results = cls()
        for name, entry in payload["settings"].items():
            if not (isinstance(entry, dict) and isinstance(entry.get("changes"), dict)
                    and entry.get("folder") == setting_folder(name)):
                raise StoredResultError(f"{meta}: setting {name!r} holds {entry!r}, where an ablation stores its "
                                        f"changes and its folder {setting_folder(name)!r}; it was edited")
            folder = results_dir / entry["folder"]
            results.settings[name] = entry["changes"]
            if (folder / "sweep.json").exists():
                results.sweeps[name] = SweepResults.load(folder, allow_partial=True)
        return results


def _refuse_shared_folders(names) -> None:
    """Refuse two settings whose names give one folder: one's runs would be read as the other's."""
    held = {}
    for name in names:
        twin = held.setdefault(setting_folder(name), name)
        if twin != name:
            raise ValueError(f"settings {twin!r} and {name!r} would share the folder {setting_folder(name)!r}; give "
                             "them names that differ in their letters or digits")


def _write_meta(folder: Path, settings: dict, cells, seeds, episodes: int, command: str | None) -> None:
    """Write ``ablation.json``, or add these settings and this command to the one there.

    A folder holds one design (cells, seeds, episodes); settings may be added
    by later calls, each of which appends its command.
    """
    folder.mkdir(parents=True, exist_ok=True)
    meta = folder / "ablation.json"
    design = {"cells": [[float(m), float(p), int(nss)] for m, p, nss in cells], "seeds": [int(s) for s in seeds],
              "episodes": int(episodes)}
    entries = {name: {"folder": setting_folder(name), "changes": dict(s)} for name, s in settings.items()}
    payload = {**design, "settings": {}, "commands": [], "sarsp_edu_version": __version__}
    if meta.exists():
        stored = json.loads(meta.read_text(encoding="utf-8"))
        differing = [key for key in design if stored.get(key) != design[key]]
        if differing:
            raise ValueError(
                f"{folder} holds an ablation with other {', '.join(differing)} "
                f"({', '.join(f'{k}={stored.get(k)!r}' for k in differing)}); use another results folder"
            )
        for name, entry in entries.items():
            if name in stored["settings"] and stored["settings"][name] != entry:
                raise ValueError(f"{folder} holds setting {name!r} with other changes "
                                 f"{stored['settings'][name]['changes']!r}; use another results folder")
        _refuse_shared_folders([*stored["settings"], *entries])
        payload["settings"], payload["commands"] = stored["settings"], stored.get("commands", [])
    payload["settings"].update(entries)
    if command:
        payload["commands"].append(command)
    atomic_write_text(meta, json.dumps(payload, indent=2) + "\n")


def run_ablation(
    settings: dict | None = None,
    *,
    cells=ABLATION_CELLS,
    seeds=ABLATION_SEEDS,
    episodes: int = 80,
    results_dir=None,
    n_jobs: int = 1,
    progress: bool = False,
    command: str | None = None,
) -> AblationResults:
    """Run the paired TP-versus-GP comparison under each setting.

    Parameters
    ----------
    settings : dict, optional
        Name -> settings (an optional ``"preset"`` and ``ExperimentConfig``
        fields to change); default ``ABLATION_SETTINGS``.
    cells : sequence of (m, p, nss), default ``ABLATION_CELLS``
    seeds : sequence of int, default (0, 1)
    episodes : int, default 80
    results_dir : path, optional
        Store every run there, a sweep folder per setting, with
        ``ablation.json`` naming the settings, the cells, the seeds and the
        commands; a rerun resumes, and a later call may add settings.
    n_jobs : int, default 1
        Local worker processes for each setting's runs.
    progress : bool, default False
    command : str, optional
        The command line that made the results, added to ``ablation.json``.

    Returns
    -------
    AblationResults

    Raises
    ------
    CellsFailed
        If the run of some cell raised (:func:`~sarsp_edu.experiments.sweep.run_sweep`): every other cell of
        every setting was run (and stored), the exception's ``results`` holds them, and its ``failures`` are
        keyed ``(setting folder, m, p, nss, seed)``.
    """
    settings = dict(ABLATION_SETTINGS if settings is None else settings)
    if not settings:
        raise ValueError("settings must name at least one setting, got an empty dict")
    _refuse_shared_folders(settings)
    configs = {}
    for name, setting in settings.items():
        preset = dict(setting).get("preset", "default")
        if preset not in PRESETS:
            raise ValueError(f"setting {name!r} names preset={preset!r}; valid presets are {sorted(PRESETS)}")
        configs[name] = setting_config(setting, episodes=episodes)  # validates every field first
    for config in configs.values():  # and every cell under every setting: a refused call writes nothing
        _grid("cells", [tuple(cell) for cell in cells], lambda cell, config=config: _check_cell(config, cell))
    results = AblationResults(settings={name: dict(s) for name, s in settings.items()})
    folder = None if results_dir is None else Path(results_dir)
    if folder is not None:
        _write_meta(folder, settings, cells, seeds, episodes, command)
    with collecting(folder, results) as failures:
        for name, config in configs.items():
            try:
                results.sweeps[name] = run_sweep(
                    config, cells=cells, seeds=seeds, n_jobs=n_jobs, progress=progress,
                    results_dir=None if folder is None else folder / setting_folder(name),
                )
            except CellsFailed as exc:  # the other settings still run; each failure named with its setting's folder
                results.sweeps[name] = exc.results
                failures.update({(setting_folder(name), *key): failure for key, failure in exc.failures.items()})
    return results
