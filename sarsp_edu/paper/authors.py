"""The authors' own runs: their per-episode records of the paper's 90 runs, and ours beside them.

The paper prints means, medians and modes over its 45 configurations
(Tables 2-4) and six configurations (Table 1).  Its authors also published
the per-episode records of all 90 runs (TP and GP, one run per
configuration, 250 episodes, unseeded and unpaired); the package ships them
as ``sarsp_edu/data/authors_runs.csv.gz`` with their description
(``AUTHORS_RUNS.md`` beside it).  They give what the tables cannot: every
configuration's cost rate, Definition 4's verdict per configuration, medians
computed the same way as ours, and learning curves.

- :func:`load_authors_runs`: the 22,500 records in the package's column names;
- :class:`AuthorsRuns`: those runs as :func:`sarsp_edu.experiments.tables.summary_tables`
  reads a sweep, so that every table is computed from theirs as from ours;
- :func:`beside_authors`, :func:`agreement`: per configuration, ours beside
  theirs, and how often the two name the same better model, set beside how
  often two of our own seeds do;
- :func:`learning_curves`: running metrics per episode, mean over
  configurations, ours (with the spread over seeds) beside theirs;
- :func:`tables_beside_authors`, :func:`verdicts_beside_authors`: Tables 2
  and 3, and each configuration's cost rates and Definition 4 verdict,
  computed from theirs as from ours.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass
from importlib import resources

import numpy as np
import pandas as pd

from ..experiments.metrics import DEFINITION_4_A, SUMMARY_METRICS, better_of, running_metrics

__all__ = ["AUTHORS_EPISODES", "AUTHORS_RUNS_FILE", "AuthorsRuns", "agreement", "agreement_share", "beside_authors",
           "learning_curves", "load_authors_runs", "tables_beside_authors", "verdicts_beside_authors"]

#: the file, inside the package's data, of the authors' per-episode records
AUTHORS_RUNS_FILE = "authors_runs.csv.gz"

#: episodes in each of the authors' runs
AUTHORS_EPISODES = 250

#: the authors' column -> the package's (the per-episode columns the running metrics are computed from)
_RENAMED = {"observed_cost": "episode_cost", "steps": "episode_steps", "starting_location": "start",
            "goal_location": "goal"}
#: the authors' running columns, rounded to 3 decimals in their files -> the package's metric
AUTHORS_RUNNING = {"mean_reward": "mean_reward", "mean_cost": "mean_cost", "total_cost": "total_cost",
                   "task_success_rate": "task_success_rate", "mean_episode_steps": "mean_steps",
                   "observed_cost_rate": "cost_rate"}

_RUN = ["model", "m", "p", "nss"]


@functools.lru_cache(maxsize=1)
def _read() -> pd.DataFrame:
    with resources.files("sarsp_edu").joinpath("data", AUTHORS_RUNS_FILE).open("rb") as handle:
        raw = pd.read_csv(handle, compression="gzip")
    raw = raw.sort_values(_RUN + ["episode"], kind="stable").reset_index(drop=True)
    runs = raw.drop(columns=list(AUTHORS_RUNNING)).rename(columns=_RENAMED)
    runs["model"] = runs["model"].str.upper()
    for column in ("start", "goal"):  # "(4 1)" -> "4 1", as the package writes a cell
        runs[column] = runs[column].str.strip("()")
    # the episode's summed reward, from the running mean (exact: the authors' mean is not rounded)
    count = runs["episode"].to_numpy(dtype=float)
    mean = raw["mean_reward"].to_numpy()
    previous = np.where(runs["episode"] > 1, np.roll(mean * count, 1), 0.0)
    runs.insert(runs.columns.get_loc("episode") + 1, "episode_reward", mean * count - previous)
    metrics = []
    for _, run in runs.groupby(_RUN, sort=False):
        metrics.append(running_metrics(run["episode_reward"], run["episode_cost"], run["episode_steps"],
                                       run["task_completed"]).set_index(run.index))
    runs = pd.concat([runs, pd.concat(metrics)], axis=1)
    for theirs in AUTHORS_RUNNING:  # their own rounded values, kept to check ours against
        runs[f"authors_{theirs}"] = raw[theirs]
    return runs


def load_authors_runs() -> pd.DataFrame:
    """The authors' per-episode records of the paper's 90 runs, in the package's column names.

    Returns
    -------
    DataFrame, 22,500 rows (TP and GP x 45 configurations x 250 episodes),
    sorted by model, m, p, nss and episode, with columns

    - ``model`` ("TP" or "GP"), ``m``, ``p``, ``nss``, ``episode``;
    - the per-episode columns of the package's records: ``episode_reward``
      (from their running mean), ``episode_cost``, ``episode_steps``,
      ``task_completed``, ``start`` and ``goal`` ("x y");
    - the running metrics ``SUMMARY_METRICS``, recomputed from those with
      :func:`sarsp_edu.experiments.metrics.running_metrics` (their own, rounded to three
      decimals, are kept as ``authors_<their name>``, e.g.
      ``authors_observed_cost_rate``: they agree to that rounding);
    - their diagnostics under their own names (``reward_approximation_mse``,
      ``number_successful_corrective_updates``, ...).

    Examples
    --------
    >>> runs = load_authors_runs()
    >>> len(runs), runs["model"].unique().tolist()
    (22500, ['GP', 'TP'])
    """
    return _read().copy()


@dataclass
class AuthorsRuns:
    """The authors' 90 runs, read the way the package reads one of its sweeps.

    :func:`sarsp_edu.experiments.tables.summary_tables` accepts it in place of a
    :class:`~sarsp_edu.experiments.sweep.SweepResults` (one "seed", 0, per
    configuration), so that Table 1 with its cost rates and Definition 4's
    verdicts, the medians and the levels are computed from the authors'
    records exactly as from ours.

    Attributes
    ----------
    records : DataFrame
        :func:`load_authors_runs`.
    a : float
        Definition 4's TSR threshold.
    episode : int, optional
        The episode whose running metrics summarise a run (default: the
        last, 250): set it to a shorter sweep's length to compare like with
        like.
    """

    records: pd.DataFrame = None
    a: float = DEFINITION_4_A
    episode: int | None = None

    def __post_init__(self):
        if self.records is None:
            self.records = load_authors_runs()
        if self.episode is not None and not (isinstance(self.episode, (int, np.integer))
                                             and 1 <= self.episode <= AUTHORS_EPISODES):
            raise ValueError(f"episode must be a whole number in [1, {AUTHORS_EPISODES}] (the authors' runs), "
                             f"got episode={self.episode!r}")

    def __len__(self) -> int:
        return int(self.records.groupby(["m", "p", "nss"]).ngroups)

    def only(self, configurations) -> "AuthorsRuns":
        """The runs of the given ``(m, p, nss)`` configurations only (e.g. those a partial sweep holds)."""
        wanted = {(float(m), float(p), int(nss)) for m, p, nss in configurations}
        keep = [(float(m), float(p), int(nss)) in wanted
                for m, p, nss in zip(self.records.m, self.records.p, self.records.nss)]
        return AuthorsRuns(self.records[keep].reset_index(drop=True), a=self.a, episode=self.episode)

    def frame(self) -> pd.DataFrame:
        """One row per configuration and model: the metrics at ``episode`` (``SweepResults.frame``'s columns)."""
        if self.episode is None:
            last = self.records.groupby(_RUN, sort=False).tail(1)
        else:
            last = self.records[self.records["episode"] == self.episode]
        frame = last[["m", "p", "nss", "model", *SUMMARY_METRICS]].assign(seed=0)
        return frame[["m", "p", "nss", "seed", "model", *SUMMARY_METRICS]].sort_values(
            ["m", "p", "nss", "model"], ascending=[True, True, True, False]).reset_index(drop=True)


    def curves(self, metric: str, model: str, m: float, p: float) -> pd.DataFrame:
        """Per-episode values of ``metric`` for one (m, p), one column per nss: the paper's Figures 2-7.

        The same frame as :meth:`sarsp_edu.experiments.sweep.SweepResults.curves` (index
        episode, a column per nss), from the authors' one run per configuration.

        Parameters
        ----------
        metric : str
            One of ``SUMMARY_METRICS``.
        model : {"TP", "GP"}
            Either case.
        m, p : float
            The outlier magnitude and proportion (compared with ``numpy.isclose``).
        """
        if metric not in SUMMARY_METRICS:
            raise ValueError(f"metric must be one of {SUMMARY_METRICS}, got metric={metric!r}")
        if not isinstance(model, str) or model.upper() not in ("TP", "GP"):
            raise ValueError(f"model must be 'TP' or 'GP', got model={model!r}")
        runs = self.records[(self.records["model"] == model.upper()) & np.isclose(self.records["m"], m)
                            & np.isclose(self.records["p"], p)]
        if runs.empty:
            held = sorted({(float(a), float(b)) for a, b in zip(self.records["m"], self.records["p"])})
            raise ValueError(f"the authors' runs hold no configuration with m={m}, p={p}; their (m, p) are "
                             + ", ".join(f"({a:g}, {b:g})" for a, b in held))
        table = runs.pivot_table(index="episode", columns="nss", values=metric)
        table.columns = [int(nss) for nss in table.columns]
        return table


def beside_authors(results, metric: str, authors: AuthorsRuns | None = None) -> pd.DataFrame:
    """Per configuration, ``metric`` of our runs (mean over seeds) beside the authors' run.

    Parameters
    ----------
    results : SweepResults
        Our runs (any number of seeds per configuration).
    metric : str
        One of ``SUMMARY_METRICS``.
    authors : AuthorsRuns, optional

    Returns
    -------
    DataFrame indexed by (m, p, nss), for the configurations both hold, with
    columns ``ours TP``, ``ours GP``, ``authors TP``, ``authors GP``,
    ``ours better``, ``authors better`` ("TP", "GP" or "tie") and ``seeds``.
    """
    if metric not in SUMMARY_METRICS:
        raise ValueError(f"metric must be one of {SUMMARY_METRICS}, got metric={metric!r}")
    authors = AuthorsRuns() if authors is None else authors
    ours = results.frame()
    seeds = ours.groupby(["m", "p", "nss"])["seed"].nunique()
    ours = ours.pivot_table(index=["m", "p", "nss"], columns="model", values=metric, aggfunc="mean")
    theirs = authors.frame().pivot_table(index=["m", "p", "nss"], columns="model", values=metric)
    both = ours.index.intersection(theirs.index)
    if not len(both):
        raise ValueError("our runs and the authors' share no configuration")
    table = pd.DataFrame({"ours TP": ours.loc[both, "TP"], "ours GP": ours.loc[both, "GP"],
                          "authors TP": theirs.loc[both, "TP"], "authors GP": theirs.loc[both, "GP"]})
    table["ours better"] = [better_of(metric, t, g) for t, g in zip(table["ours TP"], table["ours GP"])]
    table["authors better"] = [better_of(metric, t, g) for t, g in zip(table["authors TP"], table["authors GP"])]
    table["seeds"] = seeds.loc[both]
    return table


def agreement_share(tp_1, gp_1, tp_2, gp_2) -> float:
    """The share (%) of configurations in which two runs name the same model better.

    Parameters
    ----------
    tp_1, gp_1, tp_2, gp_2 : array-like of shape (n,)
        One metric per configuration: the first run's TP and GP values and
        the second run's, in the same order of configurations.

    Returns
    -------
    float
        100 x (configurations where TP - GP has the same sign, not 0, in
        both runs) / n.  A tie in either run counts as a disagreement: it
        names no better model.  The metric's direction does not matter: both
        runs are read the same way.

    Examples
    --------
    >>> round(agreement_share([90, 80, 70], [85, 85, 70], [95, 70, 60], [80, 75, 65]), 1)  # the tie disagrees
    66.7
    """
    tp_1, gp_1, tp_2, gp_2 = (np.asarray(v, dtype=float) for v in (tp_1, gp_1, tp_2, gp_2))
    if not tp_1.shape == gp_1.shape == tp_2.shape == gp_2.shape or tp_1.ndim != 1 or not len(tp_1):
        raise ValueError(f"tp_1, gp_1, tp_2 and gp_2 must be 1-D arrays of one length n >= 1, got shapes "
                         f"{tp_1.shape}, {gp_1.shape}, {tp_2.shape}, {gp_2.shape}")
    first, second = np.sign(tp_1 - gp_1), np.sign(tp_2 - gp_2)
    return float(100.0 * np.mean((first == second) & (first != 0)))


def agreement(results, metric: str, authors: AuthorsRuns | None = None) -> pd.DataFrame:
    """How often two sets of runs name the same model better in ``metric``, configuration by configuration.

    One run per configuration is noisy: two runs of the same configuration
    with different seeds need not agree on which model did better.  The rows
    set "ours against the authors" beside that yardstick, measured on our own
    seeds.

    Parameters
    ----------
    results : SweepResults
        Our runs (any number of seeds per configuration).
    metric : str
        One of ``SUMMARY_METRICS``.
    authors : AuthorsRuns, optional
        The authors' runs; default ``AuthorsRuns()``, all of them.

    Returns
    -------
    DataFrame, one row per comparison: ours (mean over seeds) against the
    authors, each of our seeds against the authors, and each pair of our
    seeds against each other (only with several seeds); columns
    ``configurations``, ``agree`` and ``share`` (%).  A tie in either run
    counts as a disagreement.
    """
    authors = AuthorsRuns() if authors is None else authors
    table = beside_authors(results, metric, authors)
    theirs = table[["authors TP", "authors GP"]].set_axis(["TP", "GP"], axis=1)
    rows = [("ours (mean over seeds) vs the authors",
             table[["ours TP", "ours GP"]].set_axis(["TP", "GP"], axis=1), theirs)]
    frame = results.frame()
    wide = frame.pivot_table(index=["m", "p", "nss"], columns=["seed", "model"], values=metric)
    seeds = sorted(frame["seed"].unique())
    if len(seeds) > 1:
        runs = {seed: wide[seed].dropna() for seed in seeds}
        rows += [(f"our seed {seed} vs the authors", runs[seed], theirs) for seed in seeds]
        rows += [(f"our seed {a} vs our seed {b}", runs[a], runs[b]) for a, b in itertools.combinations(seeds, 2)]
    out = []
    for name, first, second in rows:
        common = first.index.intersection(second.index)
        first, second = first.loc[common], second.loc[common]
        share = agreement_share(first["TP"], first["GP"], second["TP"], second["GP"]) if len(common) else math.nan
        out.append({"comparison": name, "configurations": len(common),
                    "agree": int(round(share * len(common) / 100)), "share": share})
    return pd.DataFrame(out).set_index("comparison")


def learning_curves(results, metric: str, authors: AuthorsRuns | None = None) -> pd.DataFrame:
    """``metric`` per episode, mean over the configurations both hold: ours beside the authors'.

    Parameters
    ----------
    results : SweepResults
        Our runs (any number of seeds per configuration).
    metric : str
        One of ``SUMMARY_METRICS``.
    authors : AuthorsRuns, optional
        The authors' runs; default ``AuthorsRuns()``, all of them.

    Returns
    -------
    DataFrame indexed by episode (the authors' 250; ours NaN past our
    runs' end), with columns ``authors TP``, ``authors GP`` and, per model,
    ``ours TP`` (mean over seeds of the mean over configurations) with
    ``ours TP low`` and ``ours TP high`` (the lowest and highest seed's
    mean over configurations: the band over seeds; equal to ``ours TP``
    with one seed).
    """
    if metric not in SUMMARY_METRICS:
        raise ValueError(f"metric must be one of {SUMMARY_METRICS}, got metric={metric!r}")
    authors = AuthorsRuns() if authors is None else authors
    theirs = authors.only((m, p, nss) for m, p, nss, _ in results.comparisons).records
    if theirs.empty:
        raise ValueError("our runs and the authors' share no configuration")
    curves = theirs.pivot_table(index="episode", columns="model", values=metric, aggfunc="mean")
    out = pd.DataFrame({"authors TP": curves["TP"], "authors GP": curves["GP"]})
    for model in ("TP", "GP"):
        per_seed = {}
        for (m, p, nss, seed), comparison in sorted(results.comparisons.items()):
            records = getattr(comparison, model.lower()).records.set_index("episode")[metric]
            per_seed.setdefault(seed, []).append(records)
        seed_means = pd.DataFrame({seed: pd.concat(series, axis=1).mean(axis=1) for seed, series in per_seed.items()})
        seed_means = seed_means.reindex(out.index)
        out[f"ours {model}"] = seed_means.mean(axis=1)
        out[f"ours {model} low"] = seed_means.min(axis=1)
        out[f"ours {model} high"] = seed_means.max(axis=1)
    return out


def tables_beside_authors(tables: dict, authors_tables: dict, which: str = "mean") -> pd.DataFrame:
    """Our Table 2 (``which="mean"``) or Table 3 (``"median"``) beside the same table computed from the authors' runs.

    Parameters
    ----------
    tables, authors_tables : dict
        :func:`sarsp_edu.experiments.tables.summary_tables` of our sweep and of
        :class:`AuthorsRuns` (ideally over the same configurations).
    which : {"mean", "median"}

    Returns
    -------
    DataFrame, one row per summary metric: ``ours TP``, ``ours GP``,
    ``ours %``, ``authors TP``, ``authors GP``, ``authors %`` (TP against
    GP, relative to the GP).  Unlike the paper's printed tables these carry
    every digit, and the authors' medians and cost rates are computed the
    same way as ours.
    """
    if which not in ("mean", "median"):
        raise ValueError(f"which must be 'mean' or 'median', got which={which!r}")
    ours, theirs = tables[which], authors_tables[which]
    return pd.DataFrame({"ours TP": ours["TP"], "ours GP": ours["GP"], "ours %": ours["% change"],
                         "authors TP": theirs["TP"], "authors GP": theirs["GP"], "authors %": theirs["% change"]})


def verdicts_beside_authors(tables: dict, authors_tables: dict) -> pd.DataFrame:
    """Per configuration: each model's cost rate and Definition 4's verdict, ours beside the authors'.

    The paper's Table 1 gives six configurations and no cost rate; the
    authors' records give the cost rate, hence the verdict, at all 45.

    Parameters
    ----------
    tables, authors_tables : dict
        :func:`sarsp_edu.experiments.tables.summary_tables` of our sweep and of
        :class:`AuthorsRuns`; their ``"table1"`` is read.

    Returns
    -------
    DataFrame indexed by (m, p, nss), for the configurations both tables
    hold: ``ours p_c TP``, ``ours p_c GP``, ``ours verdict``,
    ``authors p_c TP``, ``authors p_c GP``, ``authors verdict`` (an
    undefined cost rate is NaN).
    """
    def wide(table1):
        frame = table1.set_index(["m", "p", "nss"])
        tp, gp = frame[frame.model == "TP"], frame[frame.model == "GP"]
        return pd.DataFrame({"p_c TP": tp["cost_rate"], "p_c GP": gp["cost_rate"], "verdict": tp["result"]})

    ours, theirs = wide(tables["table1"]), wide(authors_tables["table1"])
    both = ours.index.intersection(theirs.index)
    return pd.concat([ours.loc[both].add_prefix("ours "), theirs.loc[both].add_prefix("authors ")], axis=1)
