"""Time one decision of the agent with a Student-t likelihood (model="t-likelihood") against the GP agent's,
on one prepared world at k = 100: 2 models x 4 actions, a fresh prior per action, each conditioned by its own
Laplace approximation; and each model's offline fit.  The target: a decision at most 3 times the GP's.

Run by hand:  python benchmarks/bench_likelihood.py [--repeats 100]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))
from _timing import median_seconds, one_core  # noqa: E402

from sarsp_edu import ExperimentConfig  # noqa: E402
from sarsp_edu.experiments.experiment import Experiment  # noqa: E402
from sarsp_edu.world.preparation import prepare  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=100)
    args = parser.parse_args(argv)

    config = ExperimentConfig(episodes=1, seed=0)
    prepared = prepare(config)
    print(f"one decision = 2 models x 4 actions, k = {config.k_prior}; one BLAS thread; median of {args.repeats}")
    decisions = {}
    for model in ("gp", "tp", "t-likelihood"):
        start = time.perf_counter()
        experiment = Experiment(config.replace(model=model), prepared=prepared)
        fit = time.perf_counter() - start
        observation, _ = experiment.env.reset(seed=1)
        decisions[model] = median_seconds(lambda agent=experiment.agent: agent.act(observation), args.repeats)
        print(f"  {model:13s} decision {decisions[model] * 1e3:6.2f} ms | offline fit (both models) {fit:5.1f} s")
    ratio = decisions["t-likelihood"] / decisions["gp"]
    print(f"t-likelihood decision / GP decision: {ratio:.1f} (target <= 3)")


if __name__ == "__main__":
    with one_core():
        main()
