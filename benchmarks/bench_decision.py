"""Time one SARSP-sized decision: mean and variance at 4 query points (one per
action) conditioned on 110 training points (a 100 + 10 strategic prior), with
fixed hyperparameters, for the GP and the TP, against scikit-learn doing the
same (fit with optimizer=None, then predict with return_std).

Run by hand:  python benchmarks/bench_decision.py [--repeats 2000]
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from _timing import median_seconds, one_core  # noqa: E402

from sarsp_edu import RBF, GaussianProcess, StudentTProcess  # noqa: E402


def cost_model_like_data(rng, n):
    """Inputs shaped like the cost model's: (action, x, y, unsafe x, unsafe y) on a 10x10 grid."""
    X = np.column_stack([rng.integers(0, 4, n), rng.integers(0, 10, (n, 4))]).astype(float)
    y = np.hypot(X[:, 1] - X[:, 3], X[:, 2] - X[:, 4]) + 0.1 * rng.standard_normal(n)
    return X, y


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2000)
    args = parser.parse_args(argv)

    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import RBF as SkRBF, ConstantKernel, WhiteKernel

    rng = np.random.default_rng(0)
    X_all, y_all = cost_model_like_data(rng, 4000)
    kernel = RBF(amplitude=1.4, length_scale=2.0)
    noise = 0.3
    ours = {
        "GP": GaussianProcess(kernel, noise_variance=noise, optimizer=None).fit(X_all[:200], y_all[:200]),
        "TP": StudentTProcess(kernel, nu=3.0, noise_variance=noise, optimizer=None).fit(X_all[:200], y_all[:200]),
    }
    sk_kernel = ConstantKernel(1.4**2, "fixed") * SkRBF(2.0, "fixed") + WhiteKernel(noise, "fixed")

    idx = rng.choice(len(X_all), 110, replace=False)
    X, y = X_all[idx], y_all[idx]
    Xq = np.column_stack([np.arange(4), np.tile(X[0, 1:], (4, 1))])

    def sklearn_decision():
        gpr = GaussianProcessRegressor(sk_kernel, alpha=0.0, optimizer=None).fit(X, y)
        return gpr.predict(Xq, return_std=True)

    sk_mean, sk_std = sklearn_decision()
    t_sk = median_seconds(sklearn_decision, args.repeats)
    print(f"SARSP-sized decision: 4 queries | 110 training points | 5 features | one BLAS thread | median of {args.repeats}")
    print(f"  scikit-learn GaussianProcessRegressor fit+predict : {t_sk * 1e6:8.1f} us")
    for name, model in ours.items():
        def decision(model=model):
            return model.condition(X, y).predict(Xq, return_var=True, include_noise=True)

        mean, var = decision()
        t = median_seconds(decision, args.repeats)
        if name == "GP":
            agree = np.allclose(mean, sk_mean, rtol=1e-8) and np.allclose(var, sk_std**2, rtol=1e-8)
            check = f"same numbers as scikit-learn: {agree}"
        else:
            check = f"variance scale {model.condition(X, y).variance_scale_:.3f} x GP"
        print(f"  sarsp_edu {name} condition+predict             : {t * 1e6:8.1f} us  "
              f"({t_sk / t:4.1f}x faster; {check})")


if __name__ == "__main__":
    with one_core():
        main()
