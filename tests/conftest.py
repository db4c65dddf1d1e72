from __future__ import annotations

import numpy as np
import pytest


def make_data(seed: int, n: int = 30, d: int = 5, noise: float = 0.1):
    """A smooth function of d inputs with Gaussian noise."""
    rng = np.random.default_rng(seed)
    X = rng.uniform(-3, 3, size=(n, d))
    y = np.sin(X[:, 0]) + 0.5 * np.cos(X[:, -1] * 0.7) + noise * rng.standard_normal(n)
    return X, y


@pytest.fixture(params=[0, 1, 2, 3])
def dataset(request):
    """Several random data sets of different sizes and dimensions."""
    seed = request.param
    n, d = [(30, 5), (12, 1), (45, 3), (25, 2)][seed]
    return make_data(seed, n=n, d=d)
