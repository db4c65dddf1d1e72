"""The paper's Tables 1-4 from a sweep's results, and the statistics behind them.

``summary_tables`` turns a sweep into Table 1 (every configuration, with
Definition 4's verdict), Tables 2-4 (mean, median and mode over
configurations) and what one run per configuration cannot give: bootstrap
intervals, a paired Wilcoxon signed-rank test, and intervals over seeds.
``tables_markdown`` writes them all as Markdown.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
from scipy import stats

from .metrics import (
    HIGHER_IS_BETTER,
    SUMMARY_METRICS,
    better_of,
    cost_rate_undefined,
    displayed_summary,
    percent_difference,
    prefers,
    symmetric_percent_difference,
)

if TYPE_CHECKING:
    from .sweep import SweepResults

__all__ = [
    "beside_paper", "bootstrap_ci", "frame_to_markdown", "paired", "paper_mode", "per_configuration", "sign_test",
    "summary_tables",
    "table1_beside_paper", "tables_markdown",
]


def paper_mode(values: np.ndarray) -> float:
    """The smallest of the most frequent values (scipy.stats.mode's rule).

    For a continuous metric whose values are all different this is simply
    the minimum, which is what the paper's Table 4 shows for mean reward.
    """
    return float(stats.mode(np.asarray(values, dtype=float), keepdims=False).mode)


def per_configuration(frame: pd.DataFrame) -> pd.DataFrame:
    """Mean over seeds of each (m, p, nss, model)."""
    return frame.groupby(["m", "p", "nss", "model"], as_index=False)[list(SUMMARY_METRICS)].mean()


def paired(frame: pd.DataFrame, metric: str):
    """``metric``'s TP and GP values, as two arrays in the same order of configurations (m, p, nss).

    Parameters
    ----------
    frame : pandas.DataFrame
        One row per configuration and model, with columns m, p, nss, model and ``metric``
        (as :func:`per_configuration` gives); several rows of one are averaged.
    metric : str
        The column to pair.
    """
    wide = frame.pivot_table(index=["m", "p", "nss"], columns="model", values=metric)
    return wide["TP"].to_numpy(), wide["GP"].to_numpy()


def sign_test(tp, gp) -> float:
    """The two-sided p-value of the sign test of paired values: does either model win more often than chance?

    Counts the configurations where ``tp > gp`` among those where they
    differ (ties carry no sign and are dropped) and returns the exact
    binomial p-value of that count under "each sign has probability 1/2";
    1.0 when every pair is a tie.  Unlike the Wilcoxon signed-rank test it
    ignores how large each difference is, and assumes nothing about their
    distribution.

    Parameters
    ----------
    tp, gp : array-like of shape (n,)
        Paired values, one per configuration (:func:`paired`).

    Examples
    --------
    >>> round(sign_test([3, 4, 5, 6, 7, 8], [1, 1, 1, 1, 1, 1]), 4)  # 6 wins of 6: 2 x (1/2)^6
    0.0312
    """
    tp, gp = np.asarray(tp, dtype=float), np.asarray(gp, dtype=float)
    if tp.shape != gp.shape or tp.ndim != 1:
        raise ValueError(f"tp and gp must be 1-D arrays of one length, got shapes {tp.shape} and {gp.shape}")
    differ = tp != gp
    n = int(differ.sum())
    if n == 0:
        return 1.0
    return float(stats.binomtest(int((tp > gp).sum()), n, 0.5).pvalue)


def bootstrap_ci(tp, gp, statistic, n_boot, rng, level=0.95):
    """A percentile interval of ``statistic(tp, gp)`` over resampled pairs; NaN from a single pair.

    ``tp`` and ``gp`` are paired arrays (:func:`paired`); each of ``n_boot``
    resamples draws pairs with replacement from ``rng``.  A single pair has
    no spread to resample, hence NaN.

    The resamples are drawn even then, so that the intervals computed after
    this one do not depend on how many pairs it had.

    Parameters
    ----------
    tp, gp : ndarray of shape (n,)
        The paired values.
    statistic : callable
        ``statistic(tp, gp) -> float`` of a resample; non-finite values are left out of the interval.
    n_boot : int
        The number of resamples.
    rng : numpy.random.Generator
        Draws the resamples.
    level : float, default 0.95
        The interval's coverage.

    Returns
    -------
    tuple of float
        The interval's lower and upper ends, ``(nan, nan)`` when it is undefined.
    """
    n = len(tp)
    if n == 0:
        return math.nan, math.nan
    idx = rng.integers(0, n, size=(n_boot, n))
    values = np.array([statistic(tp[i], gp[i]) for i in idx])
    values = values[np.isfinite(values)]
    if n < 2 or len(values) == 0:
        return math.nan, math.nan
    return tuple(np.quantile(values, [(1 - level) / 2, (1 + level) / 2]))


def summary_tables(results: "SweepResults", a: float | None = None, n_boot: int = 2000, rng=0) -> dict:
    """The paper's Tables 1-4 and the statistics behind them, as DataFrames.

    Parameters
    ----------
    results : SweepResults
    a : float, optional
        Definition 4's threshold (default: the results').
    n_boot : int, default 2000
        Bootstrap resamples for the confidence intervals.
    rng : None, int or numpy.random.Generator
        For the bootstrap.

    Returns
    -------
    dict of DataFrames
        ``"table1"``: every configuration, a TP row and a GP row, the
        verdict of Definition 4 and the symmetric % difference in total cost
        (the paper's Table 1 lists 6 of these rows); with several seeds, the
        mean over seeds.
        ``"mean"``: Table 2, mean over configurations, % change (TP vs GP,
        relative to the GP), its 95% bootstrap interval (configurations
        resampled in pairs), and the coefficients of variation.
        ``"median"`` and ``"mode"``: Tables 3 and 4.
        ``"levels"``: each model's mean over configurations with a 95%
        bootstrap interval (configurations resampled) and the number of
        configurations ``n``: how far the mean of this grid, or of the part
        of it stored, pins down a level to set beside the paper's.  An
        undefined cost rate (eq. 12 without a clean success) is left out of
        the model's cost-rate level (NaN when none is defined).
        ``"wilcoxon"``: a paired Wilcoxon signed-rank test of TP against GP
        over configurations, per metric; configurations where either cost
        rate is undefined are left out of its cost-rate test, and counted.
        ``"seeds"`` (only with several seeds): per configuration and metric,
        the % difference of the seed means with a bootstrap interval over seeds.
    """
    if len(results) == 0:
        raise ValueError("the sweep holds no finished cell")
    a = results.a if a is None else a
    boot_rng = np.random.default_rng(rng)
    raw = results.frame()
    per_config = per_configuration(raw)

    # Table 1
    rows = []
    for (m, p, nss), group in per_config.groupby(["m", "p", "nss"]):
        tp = group[group.model == "TP"].iloc[0]
        gp = group[group.model == "GP"].iloc[0]
        tp_first, gp_first = prefers(tp, gp, a), prefers(gp, tp, a)
        if tp_first is None:
            verdict = "n/a (p_c undefined)"
        else:
            verdict = "TP > GP" if tp_first else ("GP > TP" if gp_first else "neither")
        diff = symmetric_percent_difference(tp["total_cost"], gp["total_cost"])
        for row, label in ((tp, "TP"), (gp, "GP")):
            shown = displayed_summary(row)
            rows.append({"m": m, "p": p, "nss": nss, "model": label,
                         **{k: shown[k] for k in SUMMARY_METRICS},
                         "result": verdict if label == "TP" else f"{diff:.1f}%"})
    table1 = pd.DataFrame(rows)

    undefined = per_config.apply(cost_rate_undefined, axis=1)
    undefined_configs = int(undefined.groupby([per_config.m, per_config.p, per_config.nss]).any().sum())

    def central(function, with_spread):
        out = []
        for metric in SUMMARY_METRICS:
            tp, gp = paired(per_config, metric)
            row = {"metric": metric, "TP": function(tp), "GP": function(gp)}
            row["% change"] = percent_difference(row["TP"], row["GP"])
            row["better"] = better_of(metric, row["TP"], row["GP"]) if math.isfinite(row["% change"]) else "n/a"
            # eq. 12 is undefined where violations met no clean success; the
            # paper's 0 is kept in the averages, and counted here
            row["p_c undefined in"] = undefined_configs if metric == "cost_rate" else 0
            if with_spread:
                low, high = bootstrap_ci(
                    tp, gp, lambda t, g: percent_difference(function(t), function(g)), n_boot, boot_rng
                )
                row["95% CI low"], row["95% CI high"] = low, high
                row["CV TP (%)"] = _cv(tp)
                row["CV GP (%)"] = _cv(gp)
            out.append(row)
        return pd.DataFrame(out).set_index("metric")

    tables = {
        "table1": table1,
        "mean": central(np.mean, True),
        "median": central(np.median, False),
        "mode": central(paper_mode, False),
    }

    # eq. 12's undefined cost rates (kept as the paper's 0 in Tables 1-4) carry no value to test or average
    tp_defined, gp_defined = (~paired(per_config.assign(undefined=undefined), "undefined")[i].astype(bool)
                              for i in (0, 1))

    def defined(metric, tp, gp):
        """Masks of the configurations whose TP and GP values of ``metric`` are defined."""
        if metric != "cost_rate":
            return np.ones(len(tp), bool), np.ones(len(gp), bool)
        return tp_defined, gp_defined

    tests = []
    for metric in SUMMARY_METRICS:
        tp, gp = paired(per_config, metric)
        keep = np.logical_and(*defined(metric, tp, gp))
        tp, gp = tp[keep], gp[keep]
        diff = tp - gp
        if len(diff) == 0:
            statistic, pvalue = math.nan, math.nan
        elif np.all(diff == 0):
            statistic, pvalue = math.nan, 1.0
        else:
            test = stats.wilcoxon(tp, gp)
            statistic, pvalue = float(test.statistic), float(test.pvalue)
        tests.append({"metric": metric, "n": len(tp), "left out (p_c undefined)": int(np.sum(~keep)),
                      "median TP - GP": float(np.median(diff)) if len(diff) else math.nan,
                      "TP better in": int(np.sum(diff > 0) if HIGHER_IS_BETTER[metric] else np.sum(diff < 0)),
                      "W": statistic, "p-value": pvalue})
    tables["wilcoxon"] = pd.DataFrame(tests).set_index("metric")

    if raw["seed"].nunique() > 1:
        seed_rows = []
        for (m, p, nss), group in raw.groupby(["m", "p", "nss"]):
            wide = group.pivot_table(index="seed", columns="model", values=list(SUMMARY_METRICS))
            for metric in SUMMARY_METRICS:
                tp, gp = wide[(metric, "TP")].to_numpy(), wide[(metric, "GP")].to_numpy()
                low, high = bootstrap_ci(
                    tp, gp, lambda t, g: percent_difference(t.mean(), g.mean()), n_boot, boot_rng
                )
                seed_rows.append({"m": m, "p": p, "nss": nss, "metric": metric, "seeds": len(tp),
                                  "TP": tp.mean(), "GP": gp.mean(),
                                  "% change": percent_difference(tp.mean(), gp.mean()),
                                  "95% CI low": low, "95% CI high": high})
        tables["seeds"] = pd.DataFrame(seed_rows)

    # drawn last, so that the intervals above do not depend on it
    level_rows = []
    for metric in SUMMARY_METRICS:
        tp, gp = paired(per_config, metric)
        row = {"metric": metric}
        for label, values, keep in zip(("TP", "GP"), (tp, gp), defined(metric, tp, gp)):
            values = values[keep]
            row[label] = float(np.mean(values)) if len(values) else math.nan
            row[f"{label} 95% CI low"], row[f"{label} 95% CI high"] = bootstrap_ci(
                values, values, lambda t, g: np.mean(t), n_boot, boot_rng
            )
            row[f"{label} n"] = len(values)
        level_rows.append(row)
    tables["levels"] = pd.DataFrame(level_rows).set_index("metric")
    order = ["table1", "mean", "levels", "median", "mode", "wilcoxon", "seeds"]
    return {key: tables[key] for key in order if key in tables}


def _cv(values: np.ndarray) -> float:
    """Coefficient of variation, std / |mean| x 100 (sample std, as pandas)."""
    mean = float(np.mean(values))
    if len(values) < 2 or mean == 0:
        return math.nan
    return float(np.std(values, ddof=1) / abs(mean) * 100)


def frame_to_markdown(frame: pd.DataFrame, digits: int = 3) -> str:
    """A GitHub-flavoured Markdown table (no extra dependency).

    Parameters
    ----------
    frame : pandas.DataFrame
        The table; a named index becomes the first column.
    digits : int, default 3
        Decimals of each float (NaN is written ``nan``).
    """
    frame = frame.reset_index() if frame.index.name is not None else frame
    header = "| " + " | ".join(str(c) for c in frame.columns) + " |"
    rule = "|" + "|".join("---" for _ in frame.columns) + "|"

    def cell(value):
        if isinstance(value, (float, np.floating)):
            return "nan" if math.isnan(value) else f"{value:.{digits}f}"
        return str(value)

    lines = [header, rule]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in frame.itertuples(index=False)]
    return "\n".join(lines)


_TABLE_TITLES = {
    "table1": "Table 1: every configuration (TP row, GP row; Definition 4 and the % difference in total cost)",
    "mean": "Table 2: mean over configurations (% change relative to the GP, 95% bootstrap interval, CV)",
    "levels": "Each model's mean over configurations with a 95% bootstrap interval (configurations resampled)",
    "median": "Table 3: median over configurations",
    "mode": "Table 4: mode over configurations (the smallest most frequent value, as scipy.stats.mode)",
    "wilcoxon": "Paired Wilcoxon signed-rank test of TP against GP over configurations",
    "seeds": "Per configuration: % change of the seed means with a 95% bootstrap interval over seeds",
}


def tables_markdown(tables: dict, title: str = "sarsp_edu sweep: the paper's tables") -> str:
    """All tables of :func:`summary_tables` as one Markdown document.

    Parameters
    ----------
    tables : dict of DataFrames
        As :func:`summary_tables` returns; each becomes a section under its table's title.
    title : str
        The document's heading.
    """
    parts = [f"# {title}", ""]
    for key, frame in tables.items():
        parts += [f"## {_TABLE_TITLES.get(key, key)}", "", frame_to_markdown(frame), ""]
    return "\n".join(parts)


def _three_digits(value: float) -> str:
    """``value`` to 3 significant digits in fixed notation (57.6, -127, 0.00731, 2000)."""
    if value == 0 or not math.isfinite(value):
        return f"{value:g}"
    return f"{value:.{max(0, 2 - math.floor(math.log10(abs(value))))}f}"


def beside_paper(ours: pd.DataFrame, published: dict, levels: pd.DataFrame | None = None,
                 percents: dict | None = None) -> pd.DataFrame:
    """Our Table 2, 3 or 4 beside the paper's, one row per metric.

    Parameters
    ----------
    ours : DataFrame
        ``summary_tables(...)["mean"]``, ``["median"]`` or ``["mode"]``.
    published : dict
        ``{metric: (TP, GP)}``, e.g. ``sarsp_edu.paper.TABLE2``.
    levels : DataFrame, optional
        ``summary_tables(...)["levels"]``, with ``ours`` the ``"mean"``
        table: adds each model's 95% bootstrap interval beside its mean.
    percents : dict, optional
        The paper's printed "%" column (e.g. ``sarsp_edu.paper.TABLE2_PERCENT``),
        which it computed from unrounded values; without it the column is
        recomputed from ``published``'s rounded values.

    Returns
    -------
    DataFrame with columns ``ours TP``, ``ours GP``, ``ours %``, ``paper TP``,
    ``paper GP``, ``paper %`` (``%``: TP against GP, the paper's convention);
    with ``levels``, ``TP 95% CI`` after ``ours TP`` and ``GP 95% CI`` after
    ``ours GP``, each written ``[low, high]`` to 3 significant digits.
    """
    rows = []
    for metric, (paper_tp, paper_gp) in published.items():
        row = {"metric": metric}
        for model in ("TP", "GP"):
            row[f"ours {model}"] = ours.loc[metric, model]
            if levels is not None:
                low, high = (levels.loc[metric, f"{model} 95% CI {end}"] for end in ("low", "high"))
                row[f"{model} 95% CI"] = f"[{_three_digits(low)}, {_three_digits(high)}]"
        rows.append({**row, "ours %": ours.loc[metric, "% change"], "paper TP": paper_tp, "paper GP": paper_gp,
                     "paper %": (percent_difference(paper_tp, paper_gp) if percents is None
                                 else percents[metric])})
    return pd.DataFrame(rows).set_index("metric")


def table1_beside_paper(table1: pd.DataFrame, published: dict) -> pd.DataFrame:
    """Our Table 1 rows beside the paper's, for the configurations both hold.

    Parameters
    ----------
    table1 : DataFrame
        ``summary_tables(...)["table1"]``.
    published : dict
        ``{(m, p, nss): {"tp": {metric: value}, "gp": {...}}}``, e.g.
        ``sarsp_edu.paper.TABLE1``.

    Returns
    -------
    DataFrame indexed by ``(m, p, nss, metric)``, with columns ``ours TP``,
    ``paper TP``, ``ours GP``, ``paper GP``: one row per metric the paper
    gives, for each of its configurations that ``table1`` holds (none: an
    empty frame with those columns).
    """
    columns = ["ours TP", "paper TP", "ours GP", "paper GP"]
    ours = {(float(row.m), float(row.p), int(row.nss), row.model): row for row in table1.itertuples(index=False)}
    rows = []
    for (m, p, nss), paper_rows in published.items():
        key = (float(m), float(p), int(nss))
        if key + ("TP",) not in ours:
            continue
        for metric in paper_rows["tp"]:
            rows.append({"m": m, "p": p, "nss": nss, "metric": metric,
                         "ours TP": getattr(ours[key + ("TP",)], metric), "paper TP": paper_rows["tp"][metric],
                         "ours GP": getattr(ours[key + ("GP",)], metric), "paper GP": paper_rows["gp"][metric]})
    index = ["m", "p", "nss", "metric"]
    if not rows:
        return pd.DataFrame(columns=index + columns).set_index(index)
    return pd.DataFrame(rows).set_index(index)[columns]
