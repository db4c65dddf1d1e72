"""Time one SARSP decision with per-action strategic priors: 2 models x 4 actions,
each prediction conditioned on its own prior (k random rows of an offline
buffer plus that action's matching rows), at k = 100 and k = 400, against
scikit-learn doing the same 8 conditionings (fit with optimizer=None, then
predict with return_std). The hyperparameters are fixed, as in a decision.

Run by hand:  python benchmarks/bench_decision.py [--repeats 300]
"""

from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))
from _timing import median_seconds, one_core  # noqa: E402

from sarsp_edu import ExperimentConfig  # noqa: E402
from sarsp_edu.experiments.experiment import Experiment  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=300)
    args = parser.parse_args(argv)

    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import RBF as SkRBF, ConstantKernel, WhiteKernel

    print("one decision = 2 models x 4 actions, a fresh prior per action; one BLAS thread; "
          f"median of {args.repeats}")
    for k in (100, 400):
        experiment = Experiment(ExperimentConfig(k_prior=k, episodes=1, seed=0))
        agent, env = experiment.agent, experiment.env
        observation, _ = env.reset(seed=1)

        def ours():
            return agent.act(observation)

        # scikit-learn on the very priors the agent draws, with the agent's fitted hyperparameters
        from sarsp_edu.world.offline import cost_inputs, reward_inputs

        jobs = []
        for model, buffer, queries in ((agent.cost_model, agent.cost_data, cost_inputs(observation)),
                                       (agent.reward_model, agent.reward_data, reward_inputs(observation))):
            kernel = (ConstantKernel(model.kernel_.amplitude**2, "fixed") * SkRBF(model.kernel_.length_scale, "fixed")
                      + WhiteKernel(model.noise_variance_, "fixed"))
            for a, rows in enumerate(agent._priors(buffer, queries)):
                jobs.append((kernel, buffer.X[rows], buffer.y[rows], queries[a : a + 1]))

        def sklearn():
            return [GaussianProcessRegressor(kernel, alpha=0.0, optimizer=None).fit(X, y).predict(Xq, return_std=True)
                    for kernel, X, y, Xq in jobs]

        t_ours = median_seconds(ours, args.repeats)
        t_sk = median_seconds(sklearn, max(args.repeats // 5, 20))
        sizes = [len(job[1]) for job in jobs]
        print(f"  k = {k:3d} (priors of {min(sizes)}-{max(sizes)} rows): sarsp_edu {t_ours * 1e3:6.2f} ms | "
              f"scikit-learn, same 8 conditionings {t_sk * 1e3:7.2f} ms | {t_sk / t_ours:4.1f}x faster (target >= 5x)")


if __name__ == "__main__":
    with one_core():
        main()
