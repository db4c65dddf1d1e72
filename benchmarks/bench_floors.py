"""The package's decisions and fits against the LAPACK work they cannot avoid, as ratios measured in one run.

- A decision (``SARSPAgent.act``: 2 models x 4 actions, a fresh prior each) at
  k = 100 and k = 400, against its floor: ``potrf`` + ``potrs`` on the same 8
  kernel matrices (with the right-hand sides the decision solves).
  Targets: at most 2.5x at k = 100, 1.5x at k = 400.  Beside it, the same
  decision with the cost buffer's kernel table turned off (every prior's
  kernel built from distances), to show what gathering from the table pays.
- One Adam step of the exact fit (log marginal likelihood and its gradient),
  against its floor: ``potrf`` + ``potri`` at the same size, at n = ~800
  distinct inputs (the cost model's grouped whole-buffer fit) and n = ~4,900
  (the ``reference`` preset's whole-buffer reward fit).  Target: 1.5x.
  Beside it, the step with the kernel exponentiated at every distance
  instead of at D2's distinct values (:class:`~sarsp_edu.models.kernels.DistanceLevels`).
- The grouped whole-buffer cost fit, whole (target: 1 s).

One BLAS thread; medians; the load average is printed first, as a busy
machine moves every number.

Run by hand:  python benchmarks/bench_floors.py [--repeats 200] [--skip-large]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
from scipy.linalg import lapack

sys.path.insert(0, os.path.dirname(__file__))
from _timing import median_seconds, one_core  # noqa: E402

from sarsp_edu import ExperimentConfig  # noqa: E402
from sarsp_edu.experiments.experiment import Experiment, make_model  # noqa: E402
from sarsp_edu.models.kernels import squared_distances  # noqa: E402
from sarsp_edu.models.linalg import group_rows  # noqa: E402
from sarsp_edu.world.offline import cost_inputs, reward_inputs  # noqa: E402
from sarsp_edu.world.preparation import prepare  # noqa: E402


def decision_floor(agent, observation, repeats):
    """potrf + potrs on the 8 kernel matrices one decision factorises (the agent's own priors)."""
    systems = []
    for model, buffer, queries in ((agent.cost_model, agent.cost_data, cost_inputs(observation)),
                                   (agent.reward_model, agent.reward_data, reward_inputs(observation))):
        for a, rows in enumerate(agent._priors(buffer, queries)):
            X = buffer.X[rows]
            K = model.kernel_.from_squared_distances(squared_distances(X))
            K.flat[:: len(rows) + 1] += model.noise_variance_
            k_star = model.kernel_.from_squared_distances(squared_distances(queries[a: a + 1], X))
            systems.append((np.asfortranarray(K), np.column_stack([buffer.y[rows], k_star.T])))

    def floor():
        for K, rhs in systems:
            L, _ = lapack.dpotrf(K, lower=1)
            lapack.dpotrs(L, rhs, lower=1)

    return median_seconds(floor, repeats), [K.shape[0] for K, _ in systems]


def act_without_kernel_table(agent, observation, repeats):
    """``act``'s median time with every prior's kernel built from distances (no table gathered)."""
    agent.prior_predictor.kernel_table = False
    try:
        return median_seconds(lambda: agent.act(observation), repeats)
    finally:
        agent.prior_predictor.kernel_table = True


def step_and_floor(model, buffer, rows, repeats):
    data = group_rows(buffer.X[rows], buffer.y[rows])
    D2 = squared_distances(data.X)
    work = np.empty((3,) + D2.shape)
    theta = model._initial_theta()
    levels = model._distance_levels(data.X, D2)  # as the fit: None for the reward buffer's 24 million distances
    step = median_seconds(lambda: model._log_joint(theta, D2, data, work, levels), repeats, warmup=1)
    every = median_seconds(lambda: model._log_joint(theta, D2, data, work), repeats, warmup=1) \
        if levels is not None else step
    K = model.kernel.from_squared_distances(D2)
    K.flat[:: D2.shape[0] + 1] += 1.0

    def floor():
        L, _ = lapack.dpotrf(K, lower=1)
        lapack.dpotri(L, lower=1, overwrite_c=1)

    return step, every, median_seconds(floor, repeats, warmup=1), D2.shape[0]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=200)
    parser.add_argument("--skip-large", action="store_true", help="leave out the n = ~4,900 fit step (a minute)")
    args = parser.parse_args(argv)
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; one BLAS thread; medians")

    print("decisions (SARSPAgent.act) against potrf + potrs of their 8 conditionings:")
    for k in (100, 400):
        experiment = Experiment(ExperimentConfig(k_prior=k, episodes=1, seed=0))
        agent, env = experiment.agent, experiment.env
        observation, _ = env.reset(seed=1)
        act = median_seconds(lambda: agent.act(observation), args.repeats)
        untabled = act_without_kernel_table(agent, observation, args.repeats)
        floor, sizes = decision_floor(agent, observation, args.repeats)
        target = 2.5 if k == 100 else 1.5
        print(f"  k = {k:3d} (priors of {min(sizes)}-{max(sizes)} rows): act {act * 1e3:6.2f} ms, floor "
              f"{floor * 1e3:6.2f} ms, ratio {act / floor:4.2f}x (target <= {target}x); without the kernel "
              f"table {untabled * 1e3:6.2f} ms ({untabled / floor:4.2f}x)")

    config = ExperimentConfig(seed=0)
    data = prepare(config).data
    print("one Adam step of the exact fit (value and gradient) against potrf + potri at the same size:")
    model = make_model(config.replace(model="tp"))
    jobs = [("cost, whole buffer (grouped)", data.cost, np.arange(len(data.cost)), max(args.repeats // 20, 5))]
    if not args.skip_large:
        jobs.append(("reward, whole buffer (reference)", data.reward, np.arange(len(data.reward)), 2))
    for label, buffer, rows, repeats in jobs:
        step, every, floor, n = step_and_floor(model, buffer, rows, repeats)
        print(f"  {label:34s} n = {n:5d}: step {step * 1e3:8.1f} ms, floor {floor * 1e3:8.1f} ms, "
              f"ratio {step / floor:4.2f}x (target <= 1.5x); the kernel on every distance instead of "
              f"D2's distinct values {every * 1e3:8.1f} ms")

    for name in ("tp", "gp"):
        model = make_model(config.replace(model=name))
        start = time.perf_counter()
        model.fit(data.cost.X, data.cost.y)
        print(f"grouped whole-buffer cost fit, {name.upper()}: {time.perf_counter() - start:.2f} s "
              f"({len(model.counts_)} distinct inputs of {len(data.cost)} rows; target <= 1 s)")


if __name__ == "__main__":
    with one_core():
        main()
