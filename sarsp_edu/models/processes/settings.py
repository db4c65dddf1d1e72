"""A model as the settings describe it: what an experiment's agent is given, unfitted."""

from __future__ import annotations

from ...config import ExperimentConfig
from ..kernels import RBF
from .gp import GaussianProcess
from .robust import StudentTLikelihoodGP
from .tp import StudentTProcess

__all__ = ["make_model"]


def make_model(config: ExperimentConfig):
    """A fresh, unfitted model as the config's ``model_settings`` describe it (hyperparameters start at 1).

    Parameters
    ----------
    config : ExperimentConfig
        Its ``model`` ("tp", "gp" or "t-likelihood") and the fit's settings.
    """
    settings = config.model_settings
    common = dict(
        noise_variance=1.0,
        optimizer=settings.optimizer,
        learning_rate=settings.learning_rate,
        max_iter=settings.optimizer_steps,
        prior=settings.prior,
        max_fit_points=None,  # the agent draws the fit subsets
    )
    if settings.model == "tp":
        return StudentTProcess(RBF(1.0, 1.0), nu=settings.nu, noise_convention=settings.noise_convention, **common)
    if settings.model == "t-likelihood":  # the noise's scale starts at 1, as the others' noise variance
        return StudentTLikelihoodGP(RBF(1.0, 1.0), nu=settings.likelihood_nu, scale=1.0,
                                    optimizer=settings.optimizer, learning_rate=settings.learning_rate,
                                    max_iter=settings.optimizer_steps, prior=settings.prior)
    return GaussianProcess(RBF(1.0, 1.0), **common)


#: positions at the end of an episode inspected for a trap (``final_cells``)
FINAL_WINDOW = 10
