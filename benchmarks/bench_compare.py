"""Time a paired TP-versus-GP comparison of a preset (250 episodes, m = 40,
p = 0.2, nss = 2): time per phase, the median time of one agent step, the
total wall time; then the summary beside the paper's Table 1 row.

By default the GP runs in a second process beside the TP (``compare``'s
``n_jobs=2``, one BLAS thread each); ``--jobs 1`` runs both in one process,
one after the other.

Run by hand:  python benchmarks/bench_compare.py [--preset default|reference|paper_text] [--episodes 250]
              [--seed 0] [--k-prior 100] [--jobs 1|2]
Targets (2 cores): 60 s with the default preset, 6 minutes with the reference preset.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))
from _timing import one_core  # noqa: E402

from sarsp_edu import ExperimentConfig, compare  # noqa: E402
from sarsp_edu.paper import TABLE1  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=250)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--k-prior", type=int, default=None, help="default: the preset's")
    parser.add_argument("--preset", default="default")
    parser.add_argument("--jobs", type=int, choices=(1, 2), default=2)
    args = parser.parse_args(argv)
    changes = {"episodes": args.episodes, "seed": args.seed}
    if args.k_prior is not None:
        changes["k_prior"] = args.k_prior
    config = ExperimentConfig.from_preset(args.preset, **changes)

    load = os.getloadavg()[0]
    start = time.perf_counter()
    comparison = compare(config, n_jobs=args.jobs)
    total = time.perf_counter() - start

    print(f"Paired compare, preset {config.preset}: {config.episodes} episodes, m={config.outlier_magnitude:g}, "
          f"p={config.outlier_proportion:g}, nss={config.n_switch_states}, k_prior={config.k_prior}, "
          f"seed={config.seed}; {args.jobs} process{'es' if args.jobs > 1 else ''}, one BLAS thread each; "
          f"load average before: {load:.2f} on {os.cpu_count()} cores")
    print(f"{'phase':38s} {'TP':>9s} {'GP':>9s}")
    rows = [
        ("offline data + outliers + shift (shared)", "data_seconds", 1.0, "s"),
        ("offline fits (cost + reward model)", "offline_fit_seconds", 1.0, "s"),
        ("episodes (with online retrains)", "episode_seconds", 1.0, "s"),
        ("  of which online retrains", "retrain_seconds", 1.0, "s"),
        ("median decision (2 models, 4 actions)", "median_act_seconds", 1e3, "ms"),
        ("median agent step (decide, step, learn)", "median_step_seconds", 1e3, "ms"),
        ("agent steps", "steps", 1.0, ""),
    ]
    for label, key, scale, unit in rows:
        tp, gp = comparison.tp.timings[key] * scale, comparison.gp.timings[key] * scale
        print(f"{label:38s} {tp:9.3f} {gp:9.3f} {unit}")
    print(f"{'retrains':38s} {comparison.tp.records['retrains'].iloc[-1]:9d} "
          f"{comparison.gp.records['retrains'].iloc[-1]:9d}")
    target = "360 s on 2 cores" if args.preset == "reference" else "60 s on 2 cores"
    print(f"total wall time for the paired comparison: {total:.1f} s  (target < {target})")

    print("\nSummary beside the paper's Table 1 row (m=40, p=0.2, nss=2):")
    table = comparison.table()
    print(f"{'metric':18s} {'ours TP':>10s} {'ours GP':>10s} {'paper TP':>10s} {'paper GP':>10s}")
    paper = TABLE1[(40.0, 0.2, 2)]
    for name, row in table.iterrows():
        paper_tp, paper_gp = paper["tp"].get(name, float("nan")), paper["gp"].get(name, float("nan"))
        print(f"{name:18s} {row['TP']:10.3f} {row['GP']:10.3f} {paper_tp:10.3f} {paper_gp:10.3f}")
    verdict = comparison.verdict
    print(f"Definition 4 (a=100): TP preferred {verdict['tp_preferred']}, GP preferred {verdict['gp_preferred']}")


if __name__ == "__main__":
    with one_core():
        main()
