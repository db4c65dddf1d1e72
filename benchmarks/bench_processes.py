"""Time our L-BFGS-B hyperparameter fit and our predict against scikit-learn's
on the same data (n = 500 and 1000 points, 5 features), and print the ratios
and both log marginal likelihoods.

Both fits maximise the plain log marginal likelihood (``prior=None``, no
subset: ``max_fit_points=None``) from amplitude = length scale = noise = 1,
with one L-BFGS-B run and no restarts.

Run by hand:  python benchmarks/bench_processes.py [--sizes 500 1000] [--repeats 3]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from _timing import median_seconds, one_core  # noqa: E402

from sarsp_edu import GaussianProcess, StudentTProcess  # noqa: E402


def data(n, seed=0):
    rng = np.random.default_rng(seed)
    X = rng.uniform(-3, 3, size=(n, 5))
    y = np.sin(X[:, 0]) * np.cos(0.5 * X[:, 1]) + 0.3 * X[:, 2] + 0.1 * rng.standard_normal(n)
    return X, y


def timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[500, 1000])
    parser.add_argument("--repeats", type=int, default=3, help="fits per timing (median)")
    args = parser.parse_args(argv)

    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import RBF as SkRBF, ConstantKernel, WhiteKernel

    def sk_model():
        kernel = ConstantKernel(1.0, (1e-10, 1e10)) * SkRBF(1.0, (1e-5, 1e5)) + WhiteKernel(1.0, (1e-5, 1e5))
        return GaussianProcessRegressor(kernel, alpha=0.0, n_restarts_optimizer=0)

    def ours():
        return GaussianProcess(optimizer="lbfgs", prior=None, max_fit_points=None)

    print("L-BFGS-B fit and predict, 5 features, one BLAS thread, median of "
          f"{args.repeats} fits / 20 predicts")
    header = (f"{'n':>5} | {'sklearn fit':>11} {'ours fit':>9} {'ratio':>6} | {'sklearn LML':>12} {'ours LML':>12} | "
              f"{'sklearn pred':>12} {'ours pred':>10} {'ratio':>6}")
    print(header)
    print("-" * len(header))
    for n in args.sizes:
        X, y = data(n)
        Xq, _ = data(n, seed=1)
        t_sk = median_seconds(lambda: sk_model().fit(X, y), args.repeats, warmup=0)
        t_us = median_seconds(lambda: ours().fit(X, y), args.repeats, warmup=0)
        sk = sk_model().fit(X, y)
        us = ours().fit(X, y)
        p_sk = median_seconds(lambda: sk.predict(Xq, return_std=True), 20)
        p_us = median_seconds(lambda: us.predict(Xq, return_var=True, include_noise=True), 20)
        print(f"{n:5d} | {t_sk:10.2f}s {t_us:8.2f}s {t_sk / t_us:5.1f}x | "
              f"{sk.log_marginal_likelihood_value_:12.4f} {us.log_marginal_likelihood():12.4f} | "
              f"{p_sk * 1e3:10.1f}ms {p_us * 1e3:8.1f}ms {p_sk / p_us:5.1f}x")
    # The TP has no scikit-learn counterpart; show its cost beside the GP's.
    X, y = data(args.sizes[-1])
    (tp, t_tp) = timed(lambda: StudentTProcess(optimizer="lbfgs", prior=None, max_fit_points=None).fit(X, y))
    print(f"\nStudentTProcess L-BFGS-B fit at n={args.sizes[-1]}: {t_tp:.2f}s, "
          f"{tp.n_iter_} iterations, LML {tp.log_marginal_likelihood():.4f}")
    (ad, t_ad) = timed(lambda: StudentTProcess().fit(X, y))
    print(f"StudentTProcess default fit (50 Adam steps, LogNormal priors) at n={args.sizes[-1]}: {t_ad:.2f}s")


if __name__ == "__main__":
    with one_core():
        main()
