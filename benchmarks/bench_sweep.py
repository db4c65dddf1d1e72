"""Time the paper-size sweep: 45 configurations x (TP, GP), 250 episodes, with
n_jobs local workers, storing the cells in a results folder.

Run by hand:  python benchmarks/bench_sweep.py --out RESULTS_DIR [--jobs 2] [--seeds 0]
(rerunning on the same folder skips the finished cells; use a fresh folder to time)
"""

from __future__ import annotations

import argparse
import time

from sarsp_edu import ExperimentConfig
from sarsp_edu.experiments.sweep import run_sweep


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--episodes", type=int, default=250)
    parser.add_argument("--k-prior", type=int, default=None)
    parser.add_argument("--preset", default="default")
    args = parser.parse_args(argv)
    changes = {"episodes": args.episodes}
    if args.k_prior is not None:
        changes["k_prior"] = args.k_prior
    start = time.perf_counter()
    results = run_sweep(ExperimentConfig.from_preset(args.preset, **changes), seeds=args.seeds, results_dir=args.out,
                        n_jobs=args.jobs, progress=True)
    elapsed = time.perf_counter() - start
    print(f"{len(results)} cells ({2 * len(results)} runs of {args.episodes} episodes), "
          f"{args.jobs} jobs: {elapsed / 60:.1f} min  (target < 30 min for 45 cells, 1 seed, 2 jobs)")


if __name__ == "__main__":
    main()
