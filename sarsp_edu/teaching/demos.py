"""The computations behind the tutorials' dashboards: pure, seeded, unit-tested.

Each ``compute_*`` returns plain data (dicts of arrays and numbers) that a
``plot_*`` function in :mod:`sarsp_edu.teaching.plotting` draws and a dashboard in
:mod:`sarsp_edu.teaching.dashboards.tutorials` wires to sliders.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .._internal.rng import as_generator
from .._internal.validation import check_fraction, check_int, check_positive
from ..config import GRID_SIZE, N_UNSAFE, NU, OFFLINE_EPISODES, ExperimentConfig
from ..models.kernels import RBF
from ..models.processes import GaussianProcess, StudentTLikelihoodGP, StudentTProcess
from ..world.preparation import offline_world, prepare

__all__ = ["regression_data", "section2_factor", "compute_posteriors", "compute_robust", "compute_world",
           "compute_nu_path"]


def regression_data(n: int = 40, magnitude: float = 40.0, proportion: float = 0.1, seed: int = 0,
                    scale_inputs: bool = False, noise: float = 0.2):
    """A 1-D regression problem with outliers: ``y = sin(x) + 0.5 sin(3x) + noise`` on [0, 10].

    Outliers follow paper section 5.3: ``round(p * n)`` points drawn without
    replacement have their target (and, if ``scale_inputs``, their input)
    multiplied by ``m``.

    Parameters
    ----------
    n : int, default 40
        The number of points (at least 2).
    magnitude, proportion : float
        The outliers' ``m`` (> 0) and ``p`` (in [0, 1]).
    seed : None, int or numpy.random.Generator
    scale_inputs : bool, default False
        Multiply the outliers' inputs by ``m`` too, as the paper does.
    noise : float, default 0.2
        The standard deviation of the Gaussian noise added to every target.

    Returns
    -------
    X : ndarray of shape (n, 1)
    y : ndarray of shape (n,)
    outliers : ndarray of bool, shape (n,)
    """
    n = check_int("n", n, 2)
    magnitude = check_positive("magnitude", magnitude)
    proportion = check_fraction("proportion", proportion)
    rng = as_generator(seed)
    x = np.sort(rng.uniform(0.0, 10.0, n))
    y = np.sin(x) + 0.5 * np.sin(3 * x) + noise * rng.standard_normal(n)
    rows = rng.choice(n, size=int(round(proportion * n)), replace=False)
    outliers = np.zeros(n, dtype=bool)
    outliers[rows] = True
    y[rows] *= magnitude
    if scale_inputs:
        x = x.copy()
        x[rows] *= magnitude
    return x.reshape(-1, 1), y, outliers


@lru_cache(maxsize=None)
def section2_factor(nu: float) -> float:
    """The variance factor of Tutorial 2, section 2's TP at ``nu``: fixed hyperparameters (RBF(1.5, 0.5), noise
    0.5) fitted to the section's data (40 points, outliers of magnitude 10 in a tenth of them, seed 0); exercise
    2.6's check and its reader compare it at nu = 3 and 30 (computed once per nu)."""
    X, y, _ = regression_data(n=40, magnitude=10.0, proportion=0.1, seed=0)
    return float(StudentTProcess(RBF(1.5, 0.5), nu=nu, noise_variance=0.5, optimizer=None).fit(X, y).variance_scale_)


def compute_posteriors(nu: float = NU, magnitude: float = 40.0, proportion: float = 0.1, seed: int = 0,
                       fit: bool = True, scale_inputs: bool = False, n: int = 40, noise_convention="shah"):
    """GP and TP fitted to the same data with outliers; posterior mean and variance on a grid.

    Parameters
    ----------
    nu : float
        The TP's degrees of freedom (> 2).
    magnitude, proportion : float
        The outliers' ``m`` and ``p``.
    seed : int
    fit : bool, default True
        Fit the hyperparameters (50 Adam steps, as the paper) or keep them at
        amplitude = length scale = noise variance = 1.
    scale_inputs : bool, default False
        Multiply the outliers' inputs by ``m`` too, as the paper does; they
        then leave the plotted range.
    n : int, default 40
        The number of points.
    noise_convention : {"shah", "tfp"}, default "shah"
        The TP's ``noise_convention``.

    Returns
    -------
    dict
        ``x_grid``, ``X``, ``y``, ``outliers``, and for ``"gp"`` and ``"tp"``
        a dict with ``mean``, ``var`` (latent), ``var_noisy``, ``kernel``,
        ``noise_variance``; ``tp_scale`` (the TP's variance factor
        (nu + beta - 2)/(nu + n - 2)), ``beta``, ``n``, ``nu``.
    """
    X, y, outliers = regression_data(n, magnitude, proportion, seed, scale_inputs)
    optimizer = "adam" if fit else None
    models = {
        "gp": GaussianProcess(RBF(), optimizer=optimizer),
        "tp": StudentTProcess(RBF(), nu=nu, optimizer=optimizer, noise_convention=noise_convention),
    }
    x_grid = np.linspace(0.0, 10.0, 300)
    out = {"x_grid": x_grid, "X": X[:, 0], "y": y, "outliers": outliers, "n": n, "nu": float(nu)}
    for name, model in models.items():
        model.fit(X, y)
        mean, var = model.predict(x_grid[:, None], return_var=True)
        _, var_noisy = model.predict(x_grid[:, None], return_var=True, include_noise=True)
        out[name] = {
            "mean": mean,
            "var": var,
            "var_noisy": var_noisy,
            "kernel": model.kernel_,
            "noise_variance": model.noise_variance_,
            "log_marginal_likelihood": model.log_marginal_likelihood(),
        }
    tp = models["tp"]
    out["tp_scale"] = tp.variance_scale_
    out["beta"] = tp.beta_
    return out


def compute_robust(nu: float = NU, magnitude: float = 10.0, proportion: float = 0.1, seed: int = 0, n: int = 40):
    """The GP, the TP and the GP with a Student-t likelihood, each fitted to the same data with outliers.

    The same ``nu`` goes to both Student-t models: as the TP's degrees of
    freedom (it scales the variance) and as the likelihood's (it decides how
    much each point is believed).  The GP and the TP fit their
    hyperparameters as the paper does (50 Adam steps); the Student-t
    likelihood GP fits its own by L-BFGS-B on the Laplace approximation.

    Parameters
    ----------
    nu : float
        The degrees of freedom of both Student-t models.
    magnitude, proportion : float
        The outliers' ``m`` (> 0) and ``p`` (in [0, 1]).
    seed : int
    n : int, default 40
        The number of points (:func:`regression_data`).

    Returns
    -------
    dict
        ``x_grid``, ``X``, ``y``, ``outliers``, ``truth`` (the noise-free
        function on the grid), ``nu``; ``mean`` and ``rmse`` (against the
        truth on the grid) of ``"gp"``, ``"tp"`` and ``"robust"``;
        ``robust_sd`` (the latent sd), ``weights``
        (:meth:`~sarsp_edu.models.processes.StudentTLikelihoodGP.outlier_weights`)
        and ``scale`` (the fitted noise scale).
    """
    X, y, outliers = regression_data(n, magnitude, proportion, seed)
    x_grid = np.linspace(0.0, 10.0, 300)
    truth = np.sin(x_grid) + 0.5 * np.sin(3 * x_grid)
    models = {
        "gp": GaussianProcess(RBF(), optimizer="adam"),
        "tp": StudentTProcess(RBF(), nu=nu, optimizer="adam"),
        "robust": StudentTLikelihoodGP(nu=nu),
    }
    out = {"x_grid": x_grid, "X": X[:, 0], "y": y, "outliers": outliers, "truth": truth, "nu": float(nu),
           "mean": {}, "rmse": {}}
    for name, model in models.items():
        mean = model.fit(X, y).predict(x_grid[:, None])
        out["mean"][name] = mean
        out["rmse"][name] = float(np.sqrt(np.mean((mean - truth) ** 2)))
    robust = models["robust"]
    out["robust_sd"] = robust.predict(x_grid[:, None], return_std=True)[1]
    out["weights"] = robust.outlier_weights()
    out["scale"] = robust.scale_
    return out


def compute_nu_path(nus, magnitude: float = 40.0, proportion: float = 0.1, seed: int = 0, n: int = 40,
                    kernel=None, noise_variance=None):
    """How the TP's variance factor and likelihood move with nu, hyperparameters held fixed.

    The hyperparameters are ``kernel`` and ``noise_variance`` if given, else
    the GP's fit to the data; the GP with the same ones is the reference.

    Parameters
    ----------
    nus : sequence of float
        The TP's degrees of freedom to try (> 2).
    magnitude, proportion : float
        The outliers' ``m`` (> 0) and ``p`` (in [0, 1]).
    seed : int
    n : int, default 40
        The number of points (:func:`regression_data`).
    kernel : RBF, optional
    noise_variance : float, optional
        The hyperparameters to hold; both must be given, else the GP's fit is used.

    Returns
    -------
    dict with ``nus``, ``scale`` (the factor per nu), ``lml`` (TP log marginal
    likelihood per nu), ``gp_lml``, ``max_abs_var_gap`` (largest |TP - GP|
    latent variance on the grid, per nu).
    """
    X, y, _ = regression_data(n, magnitude, proportion, seed)
    if kernel is None or noise_variance is None:
        gp = GaussianProcess(RBF(), optimizer="adam").fit(X, y)
    else:
        gp = GaussianProcess(kernel, noise_variance=noise_variance, optimizer=None).fit(X, y)
    grid = np.linspace(0.0, 10.0, 200)[:, None]
    _, gp_var = gp.predict(grid, return_var=True)
    scale, lml, gap = [], [], []
    for nu in nus:
        tp = StudentTProcess(gp.kernel_, nu=nu, noise_variance=gp.noise_variance_, optimizer=None).fit(X, y)
        _, tp_var = tp.predict(grid, return_var=True)
        scale.append(tp.variance_scale_)
        lml.append(tp.log_marginal_likelihood())
        gap.append(float(np.max(np.abs(tp_var - gp_var))))
    return {"nus": np.asarray(nus, dtype=float), "scale": np.array(scale), "lml": np.array(lml),
            "gp_lml": gp.log_marginal_likelihood(), "max_abs_var_gap": np.array(gap)}


@lru_cache(maxsize=8)
def _offline_world(seed: int, offline_episodes: int, size: int, n_unsafe: int):
    config = ExperimentConfig(seed=seed, offline_episodes=offline_episodes, grid_size=size, n_unsafe=n_unsafe)
    return offline_world(config)


def compute_world(seed: int = 0, n_switch_states: int = 6, magnitude: float = 40.0, proportion: float = 0.2,
                  offline_episodes: int = OFFLINE_EPISODES, size: int = GRID_SIZE, n_unsafe: int = N_UNSAFE):
    """The world before and after the shift, the offline data's coverage and its outliers.

    Built by :func:`sarsp_edu.world.preparation.prepare`, as an experiment builds
    them: seed 0 here is the world, the data, the outliers and the shift of
    ``ExperimentConfig(seed=0, ...)`` in a run, a sweep and tutorial 4.  The
    world and its offline data are cached per seed, so moving the nss, m or
    p sliders only redoes the injection and the shift.

    Parameters
    ----------
    seed : int, default 0
    n_switch_states : int, default 6
        nss: the unsafe states the covariate shift moves.
    magnitude, proportion : float
        The outliers' ``m`` (> 0) and ``p`` (in [0, 1]).
    offline_episodes : int
        Random-policy episodes of offline data.
    size : int
        The grid's side.
    n_unsafe : int
        The number of unsafe states.

    Returns
    -------
    dict
        ``before`` and ``after`` (GridLayout), ``visits`` (size x size),
        ``transitions``, ``cost_rows``, ``reward_rows``, ``clean`` and
        ``dirty`` cost-model data (``X``, ``y``), ``outlier_rows``, and
        ``moved`` (indices of the states that moved).
    """
    seed = check_int("seed", seed, 0)
    offline_episodes = check_int("offline_episodes", offline_episodes, 1)
    config = ExperimentConfig(seed=seed, offline_episodes=offline_episodes, grid_size=size, n_unsafe=n_unsafe,
                              n_switch_states=n_switch_states, outlier_magnitude=magnitude,
                              outlier_proportion=proportion)
    prepared = prepare(config, offline=_offline_world(seed, offline_episodes, size, n_unsafe))
    data, dirty, before = prepared.clean_data, prepared.data, prepared.layout_before
    moved = prepared.env.moved_indices
    return {
        "before": before,
        "after": prepared.env.layout(),
        "moved": moved,
        "visits": data.visits,
        "transitions": data.transitions,
        "cost_rows": len(data.cost),
        "reward_rows": len(data.reward),
        "clean": {"X": data.cost.X, "y": data.cost.y},
        "dirty": {"X": dirty.cost.X, "y": dirty.cost.y},
        "outlier_rows": dirty.outlier_indices,
        "magnitude": float(magnitude),
        "proportion": float(proportion),
    }
