"""Time one decision of the agent with a Student-t likelihood (model="t-likelihood") against the GP agent's,
on one prepared world at k = 100: 2 models x 4 actions, a fresh prior per action, each conditioned by its own
Laplace approximation; and each model's offline fit.  The target: a decision at most 3 times the GP's.

Then what a warm start would buy: the mode search of each of 40 priors the agent draws (cost and reward, 20 of
each), from the prior mean (the package's start) and from the offline fit's posterior mean at the prior's inputs,
with the steps each takes, the time of each (the warm start's own computation included), and how far apart the two
modes are.

Run by hand:  python benchmarks/bench_likelihood.py [--repeats 100]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
from scipy import linalg as sla

sys.path.insert(0, os.path.dirname(__file__))
from _timing import median_seconds, one_core  # noqa: E402

from sarsp_edu import ExperimentConfig  # noqa: E402
from sarsp_edu.experiments.experiment import Experiment  # noqa: E402
from sarsp_edu.models.linalg import distinct_rows  # noqa: E402
from sarsp_edu.models.processes.laplace import laplace_mode  # noqa: E402
from sarsp_edu.world.preparation import prepare  # noqa: E402


def warm_start_report(experiment, observation, priors: int = 20):
    """Cold against warm mode searches on priors the agent draws at ``observation`` (see the module's docstring)."""
    agent = experiment.agent
    rows = {"cold": [], "warm": []}
    gap = 0.0
    for target in ("cost", "reward"):
        model, buffer = getattr(agent, f"{target}_model"), getattr(agent, f"{target}_data")
        kernel = model.kernel_
        draws = [prior for _ in range(priors // 4) for prior in agent.strategic_prior(observation, target)]
        for prior in draws:
            first, group = distinct_rows(buffer.X[prior])
            U, y = buffer.X[prior][first], buffer.y[prior]
            K = kernel(U)
            start = time.perf_counter()
            cold = laplace_mode(K, y, group, model.nu, model.scale_)
            rows["cold"].append((cold.steps, time.perf_counter() - start))
            start = time.perf_counter()
            f0 = kernel(U, model.X_distinct_) @ model._mode.a  # the offline fit's posterior mean at the inputs
            a0 = sla.cho_solve((np.linalg.cholesky(K + 1e-10 * np.eye(len(U))), True), f0)
            warm = laplace_mode(K, y, group, model.nu, model.scale_, a0=a0)
            rows["warm"].append((warm.steps, time.perf_counter() - start))
            gap = max(gap, float(np.max(np.abs(cold.f - warm.f))))
    print(f"mode search on {len(rows['cold'])} priors the agent drew (cost and reward), mean per prior:")
    for name, found in rows.items():
        steps, seconds = np.mean(found, axis=0)
        print(f"  {name} start: {steps:4.1f} steps, {seconds * 1e3:5.2f} ms")
    print(f"  largest difference between the two modes: {gap:.1e}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=100)
    args = parser.parse_args(argv)

    config = ExperimentConfig(episodes=1, seed=0)
    prepared = prepare(config)
    print(f"one decision = 2 models x 4 actions, k = {config.k_prior}; one BLAS thread; median of {args.repeats}")
    decisions, experiments = {}, {}
    for model in ("gp", "tp", "t-likelihood"):
        start = time.perf_counter()
        experiment = experiments[model] = Experiment(config.replace(model=model), prepared=prepared)
        fit = time.perf_counter() - start
        observation, _ = experiment.env.reset(seed=1)
        decisions[model] = median_seconds(lambda agent=experiment.agent: agent.act(observation), args.repeats)
        print(f"  {model:13s} decision {decisions[model] * 1e3:6.2f} ms | offline fit (both models) {fit:5.1f} s")
    ratio = decisions["t-likelihood"] / decisions["gp"]
    print(f"t-likelihood decision / GP decision: {ratio:.1f} (target <= 3)")
    warm_start_report(experiments["t-likelihood"], observation)


if __name__ == "__main__":
    with one_core():
        main()
