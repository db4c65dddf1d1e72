"""Time the offline hyperparameter fits of the paper's models (50 Adam steps from 1.0,
LogNormal(0, 1) priors) on the offline data of one configuration, and show the
hyperparameters each fit finds:

- the cost model on its whole buffer (~4,700 rows, ~800 distinct inputs: the
  likelihood folds repeated inputs exactly, see linalg.group_rows);
- the reward model on random subsets of 500, 1,000 and 2,000 rows, and on
  the whole buffer (~4,900 distinct rows) with --whole-reward (minutes).

Run by hand:  python benchmarks/bench_fits.py [--seed 0] [--whole-reward]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))
from _timing import one_core  # noqa: E402

from sarsp_edu import ExperimentConfig  # noqa: E402
from sarsp_edu._internal.rng import draw_subset  # noqa: E402
from sarsp_edu.experiments.experiment import make_model  # noqa: E402
from sarsp_edu.world.preparation import prepare  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--whole-reward", action="store_true", help="also fit the reward model on every row")
    args = parser.parse_args(argv)
    config = ExperimentConfig(seed=args.seed)
    data = prepare(config).data
    print(f"m={config.outlier_magnitude:g} p={config.outlier_proportion:g} seed={args.seed}; one BLAS thread; "
          "50 Adam steps; a = amplitude, l = length scale, s2 = noise variance")
    sizes = [500, 1000, 2000] + ([None] if args.whole_reward else [])
    for model_name in ("tp", "gp"):
        jobs = [("cost", data.cost, None)] + [("reward", data.reward, size) for size in sizes]
        for label, buffer, size in jobs:
            rows = draw_subset(len(buffer), size, 0)
            model = make_model(config.replace(model=model_name))
            start = time.perf_counter()
            model.fit(buffer.X[rows], buffer.y[rows])
            seconds = time.perf_counter() - start
            print(f"  {model_name.upper()} {label:6s} {len(rows):5d} rows ({len(model.counts_):5d} distinct): "
                  f"{seconds:7.2f} s  a={model.kernel_.amplitude:8.3f} l={model.kernel_.length_scale:7.3f} "
                  f"s2={model.noise_variance_:.4f}")


if __name__ == "__main__":
    with one_core():
        main()
