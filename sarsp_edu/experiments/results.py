"""Results of runs and paired comparisons, and how they are stored and read back.

A result folder holds ``records.csv`` (one row per episode) and
``result.json`` (config, preset, summary, timings), written atomically;
reading them back checks every file and names what is wrong
(:class:`StoredResultError`).
"""

from __future__ import annotations

import json
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from .._internal.io import StoredResultError, atomic_write_text, check_regular_file, read_json
from .._version import __version__
from ..config import DEFINITION_4_A, ExperimentConfig
from .metrics import (
    RECORD_COLUMNS,
    SUMMARY_METRICS,
    better_of,
    displayed_summary,
    percent_difference,
    prefers,
    running_metrics,
)
from .provenance import code_provenance

__all__ = ["ExperimentResult", "Comparison", "StoredResultError", "check_paired", "stored_results"]


@dataclass
class ExperimentResult:
    """The outcome of one run.

    Attributes
    ----------
    config : ExperimentConfig
    records : pandas.DataFrame
        One row per episode; ``RECORD_COLUMNS`` documents each column.
    timings : dict
        Seconds spent on data, offline fits, episodes and retrains, the
        median seconds of one decision, and the number of steps.
    summary : dict
        The final value of each of ``SUMMARY_METRICS`` (the paper's run figures).
    code : dict
        What computed it (:func:`~sarsp_edu.experiments.provenance.code_provenance`); empty
        for results stored before version 0.2.2, which did not record it.
    fits : dict
        The hyperparameters each model was fitted to: ``{"offline": {"cost": ..., "reward": ...}, "final":
        {"cost": ...}}``, each :func:`~sarsp_edu.models.processes.summary.fit_summary`'s (the final cost fit is
        the last retrain's); empty for results stored before version 0.3.
    """

    config: ExperimentConfig
    records: pd.DataFrame
    timings: dict = field(default_factory=dict)
    code: dict = field(default_factory=lambda: dict(code_provenance()))
    fits: dict = field(default_factory=dict)

    @property
    def summary(self) -> dict:
        if self.records.empty:
            return {name: math.nan for name in SUMMARY_METRICS}
        last = self.records.iloc[-1]
        return {name: float(last[name]) for name in SUMMARY_METRICS}

    def save(self, directory) -> Path:
        """Write ``records.csv`` and ``result.json`` (config, summary, timings) atomically.

        ``result.json`` is written last, so its presence marks a complete result.

        Parameters
        ----------
        directory : path-like
            A folder (made if missing); not a file.
        """
        directory = Path(directory)
        if directory.exists() and not directory.is_dir():
            raise NotADirectoryError(f"directory={str(directory)!r} is a file; a result is saved into a folder "
                                     "(records.csv and result.json)")
        table = self.records.copy()
        for column in ("start", "goal"):
            table[column] = [f"{x} {y}" for x, y in table[column]]
        atomic_write_text(directory / "records.csv", table.to_csv(index=False))
        payload = {
            "config": self.config.to_dict(),
            "preset": self.config.preset,
            "summary": self.summary,
            "timings": self.timings,
            "sarsp_edu_version": __version__,
            "code": self.code,
        }
        if self.fits:  # results stored before 0.3 have none: their files stay as they were
            payload["fits"] = self.fits
        atomic_write_text(directory / "result.json", json.dumps(payload, indent=2, allow_nan=True) + "\n")
        return directory

    @classmethod
    def load(cls, directory) -> "ExperimentResult":
        """Read a result written by :meth:`save`."""
        directory = Path(directory)
        meta_path, csv_path = directory / "result.json", directory / "records.csv"
        if not meta_path.exists() or not csv_path.exists():
            raise FileNotFoundError(f"{directory} holds no complete result (records.csv and result.json)")
        payload = read_json(meta_path, keys=("config",))
        try:
            config = ExperimentConfig.from_dict(payload["config"])
        except (TypeError, ValueError) as exc:
            raise StoredResultError(f"{meta_path} holds an invalid config: {exc}") from None
        records = _read_records(csv_path, config.episodes)
        for key in ("timings", "code", "fits"):
            if not isinstance(payload.get(key, {}), dict):
                raise StoredResultError(f"{meta_path} holds {key}={payload[key]!r}, where a result stores an object "
                                        "(names and values); it was edited")
        result = cls(config, records, payload.get("timings", {}), payload.get("code") or {}, payload.get("fits", {}))
        _check_summary(meta_path, payload.get("summary"), result.summary)
        _check_ranges(csv_path, records, config)
        return result


def _check_summary(meta_path: Path, stored, computed: dict) -> None:
    """Refuse a ``result.json`` whose summary is not its ``records.csv``'s last row (one of them was edited)."""
    if not isinstance(stored, dict):
        raise StoredResultError(f"{meta_path} lacks 'summary'")
    for name in SUMMARY_METRICS:
        value = stored.get(name)
        same = isinstance(value, (int, float)) and (
            (math.isnan(value) and math.isnan(computed[name]))
            or math.isclose(value, computed[name], rel_tol=1e-12, abs_tol=1e-12))
        if not same:
            raise StoredResultError(
                f"{meta_path} gives {name}={value!r} where the last row of records.csv beside it gives "
                f"{computed[name]!r}: one of the two was edited or comes from another run")


#: records columns that results stored by older versions may lack
_LATER_COLUMNS = {"final_cells": "0.2.0"}
#: records columns that may hold NaN (no action was chosen as safe in an episode)
_NAN_COLUMNS = {"safe_action_variance"}


def _read_records(path: Path, episodes: int) -> pd.DataFrame:
    """``records.csv`` of a stored result, checked row by row; :class:`StoredResultError` names what is wrong."""

    def bad(problem: str):
        return StoredResultError(f"{path} {problem}")

    check_regular_file(path)
    try:
        records = pd.read_csv(path)
    except (OSError, UnicodeDecodeError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise bad(f"cannot be read ({str(exc).strip()})") from None
    missing = [c for c in RECORD_COLUMNS if c not in records.columns and c not in _LATER_COLUMNS]
    if missing:
        raise bad(f"lacks the columns {missing}")
    if len(records) != episodes:
        raise bad(f"holds {len(records)} episodes where its config ran {episodes} (was it cut short?)")
    numbers = pd.to_numeric(records["episode"], errors="coerce").to_numpy()
    if not np.array_equal(numbers, np.arange(1, episodes + 1)):
        row = int(np.flatnonzero(numbers != np.arange(1, episodes + 1))[0]) + 1
        raise bad(f"has episode {records['episode'].iloc[row - 1]} in row {row}, where the episodes run 1 to "
                  f"{episodes} in order (rows moved, removed or edited)")
    text_columns = ("start", "goal", "task_completed")
    for column in records.columns.intersection(list(RECORD_COLUMNS)):
        if column in text_columns:
            continue
        values = pd.to_numeric(records[column], errors="coerce")
        empty = values.isna() & (records[column].notna() | (column not in _NAN_COLUMNS))
        if empty.any():
            row = int(np.flatnonzero(empty.to_numpy())[0]) + 1
            raise bad(f"has no number in column {column!r} of episode {row}")
        records[column] = values
    done = records["task_completed"].astype(str)
    if not done.isin(["True", "False"]).all():
        raise bad("has a task_completed value other than True or False")
    records["task_completed"] = done == "True"
    for column in ("start", "goal"):
        cells = []
        for row, text in enumerate(records[column], start=1):
            parts = str(text).split()
            if len(parts) != 2 or not all(re.fullmatch(r"-?[0-9]+", part) for part in parts):  # ASCII digits only
                raise bad(f"has {column}={text!r} in episode {row}, not a cell 'x y'")
            cells.append((int(parts[0]), int(parts[1])))
        records[column] = cells
    return records


#: the range of each stored records column, and whether it holds whole numbers
_RANGES = {"task_success_rate": (0, 100, False), "backup_rate": (0, 1, False), "final_cells": (0, 10, True),
           "episode_cost": (0, math.inf, True), "episode_steps": (1, math.inf, True), "total_cost": (0, math.inf, True),
           "corrective_updates": (0, math.inf, True), "retrains": (0, math.inf, True)}
_NON_NEGATIVE = ("mean_cost", "mean_steps", "cost_rate", "reward_mse", "cost_prediction_error",
                 "safe_action_variance")


def _check_ranges(path: Path, records: pd.DataFrame, config: ExperimentConfig) -> None:
    """Refuse a row whose value is out of its column's range or disagrees with the running columns it implies."""
    def where(column: str, mask) -> str:
        row = int(np.flatnonzero(np.asarray(mask))[0])
        value = records[column].iloc[row]
        return f"{path} has {column}={getattr(value, 'item', lambda: value)()!r} in episode {row + 1}"

    for column in records.columns.intersection(list(RECORD_COLUMNS)):
        if column in ("start", "goal", "task_completed"):
            continue
        values = records[column].to_numpy(dtype=float)
        low, high, whole = _RANGES.get(column, (0 if column in _NON_NEGATIVE else -math.inf, math.inf, False))
        wrong = ~np.isnan(values) & ((values < low) | (values > high) | np.isinf(values)
                                     | (whole & (values != np.round(values))))
        if wrong.any():
            kind = "a whole number " if whole else ""
            raise StoredResultError(f"{where(column, wrong)}: it must be {kind}in [{low:g}, {high:g}]")
    limit = config.max_steps or config.grid_size ** 2
    if (records["episode_steps"] > limit).any():
        raise StoredResultError(f"{where('episode_steps', records['episode_steps'] > limit)}: its config stops an "
                                f"episode after {limit} steps")
    for column in ("start", "goal"):
        off = [not (0 <= x < config.grid_size and 0 <= y < config.grid_size) for x, y in records[column]]
        if any(off):
            raise StoredResultError(f"{where(column, off)}: off the {config.grid_size} x {config.grid_size} grid")
    same = [start == goal for start, goal in zip(records["start"], records["goal"])]
    if any(same):
        raise StoredResultError(f"{where('goal', same)}: the episode's start, where no episode starts")
    running = running_metrics(records["episode_reward"], records["episode_cost"], records["episode_steps"],
                              records["task_completed"])
    for column in SUMMARY_METRICS:
        stored, implied = records[column].to_numpy(dtype=float), running[column].to_numpy()
        wrong = ~np.isclose(stored, implied, rtol=1e-9, atol=1e-9)
        if wrong.any():
            row = int(np.flatnonzero(wrong)[0])
            raise StoredResultError(
                f"{where(column, wrong)}, where the episodes' rewards, costs, steps and successes up to it give "
                f"{float(implied[row])!r}: a row was edited")


@dataclass
class Comparison:
    """A paired TP-versus-GP comparison.

    Attributes
    ----------
    tp, gp : ExperimentResult
    a : float
        The TSR threshold used by ``prefers``.
    """

    tp: ExperimentResult
    gp: ExperimentResult
    a: float = DEFINITION_4_A

    @property
    def verdict(self) -> dict:
        """Definition 4 in both directions: ``{"tp_preferred": ..., "gp_preferred": ...}``.

        Each is None when a cost rate is undefined (see :func:`cost_rate_undefined`).
        """
        return {
            "tp_preferred": prefers(self.tp.summary, self.gp.summary, self.a),
            "gp_preferred": prefers(self.gp.summary, self.tp.summary, self.a),
        }

    @property
    def differences(self) -> dict:
        """``(TP - GP) / |GP| * 100`` for each summary metric."""
        tp, gp = self.tp.summary, self.gp.summary
        return {name: percent_difference(tp[name], gp[name]) for name in SUMMARY_METRICS}

    def table(self) -> pd.DataFrame:
        """Summary side by side: TP, GP, % difference and which is better.

        An undefined cost rate (see :func:`cost_rate_undefined`) is NaN here,
        and ``better`` is then ``"n/a"``.
        """
        tp, gp = displayed_summary(self.tp.summary), displayed_summary(self.gp.summary)
        rows = []
        for name in SUMMARY_METRICS:
            rows.append({"metric": name, "TP": tp[name], "GP": gp[name],
                         "TP vs GP (%)": percent_difference(tp[name], gp[name]),
                         "better": better_of(name, tp[name], gp[name])})
        return pd.DataFrame(rows).set_index("metric")

    def save(self, directory) -> Path:
        """``tp/`` and ``gp/`` result folders (the verdict is recomputed on load)."""
        directory = Path(directory)
        self.tp.save(directory / "tp")
        self.gp.save(directory / "gp")
        return directory

    @classmethod
    def load(cls, directory, a: float = DEFINITION_4_A) -> "Comparison":
        """Read ``tp/`` and ``gp/``; refused unless they ran the same world and settings, each with its model.

        Parameters
        ----------
        directory : path-like
            The comparison's folder, as written by :meth:`save`.
        a : float, default ``DEFINITION_4_A``
            Definition 4's TSR threshold (%), which is not stored: the verdict is recomputed with it.

        Raises
        ------
        StoredResultError
            When the two runs differ in a setting, their models are not TP and GP, or their episodes differ.
        """
        directory = Path(directory)
        tp, gp = ExperimentResult.load(directory / "tp"), ExperimentResult.load(directory / "gp")
        ours, theirs = tp.config.to_dict(), gp.config.to_dict()
        differ = sorted(name for name in ours if name != "model" and ours[name] != theirs[name])
        if differ or (tp.config.model, gp.config.model) != ("tp", "gp"):
            details = ", ".join(f"{name} {ours[name]!r} against {theirs[name]!r}" for name in differ) or (
                f"models {tp.config.model!r} and {gp.config.model!r}")
            raise StoredResultError(f"{directory}: tp/ and gp/ are not one paired comparison ({details}); "
                                    "they come from two runs: run 'sarsp-edu compare' again into a new folder")
        check_paired(tp, gp, directory)
        return cls(tp, gp, a)


def check_paired(tp: ExperimentResult, gp: ExperimentResult, directory, names=("tp/", "gp/")) -> None:
    """Refuse two runs (a TP and a GP, say) whose episodes did not start and end at the same cells (they are paired).

    Parameters
    ----------
    tp, gp : ExperimentResult
        The two runs, whose records' ``start`` and ``goal`` columns are compared episode by episode.
    directory : path-like
        Named in the error.
    names : (str, str), default ("tp/", "gp/")
        The two runs' names in the error.

    Raises
    ------
    StoredResultError
        At the first episode that differs.
    """
    for column in ("start", "goal"):
        differ = [a != b for a, b in zip(tp.records[column], gp.records[column])]
        if any(differ):
            row = differ.index(True)
            raise StoredResultError(
                f"{directory}: {names[0]} and {names[1]} differ in episode {row + 1}'s {column} "
                f"({tp.records[column].iloc[row]} "
                f"against {gp.records[column].iloc[row]}), where a paired comparison runs both on the same "
                "episodes; one of the records was edited")


#: an environment variable naming the folder that holds the repository's stored results
RESULTS_VARIABLE = "SARSP_EDU_RESULTS"


def stored_results(name: str) -> Path:
    """The folder ``results/NAME`` stored with the sarsp_edu repository, found from where a notebook runs.

    Looks in ``$SARSP_EDU_RESULTS`` first, then in ``results/`` of the
    current folder and of every folder above it (a tutorial runs in
    ``tutorials/``, its source in ``tutorials/source/``, a hand-out in its
    own ``tutorials/``).

    Raises
    ------
    FileNotFoundError
        Saying which results are missing, where they were looked for, and
        how to get them.
    """
    here = Path.cwd().resolve()
    places = [Path(os.environ[RESULTS_VARIABLE])] if os.environ.get(RESULTS_VARIABLE) else []
    places += [folder / "results" for folder in (here, *here.parents)]
    for place in places:
        if (place / name).is_dir():
            return place / name
    raise FileNotFoundError(
        f"the stored results {name!r} were not found (looked for results/{name} in {here} and every folder "
        f"above it). The tutorials read results stored in the sarsp_edu repository: open the notebook inside "
        f"a clone of it or a course hand-out ('sarsp-edu course handout'), or set {RESULTS_VARIABLE} to the "
        "results folder of a clone"
    )
