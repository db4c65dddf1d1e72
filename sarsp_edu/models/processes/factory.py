"""A model as the settings describe it: what an experiment's agent is given, unfitted."""

from __future__ import annotations

from ..._internal.validation import check_choice
from ...config import AGENT_NOISE_START, FITTED_NU, LIKELIHOOD_NU, ExperimentConfig
from ..kernels import RBF
from .gp import GaussianProcess
from .likelihood import StudentTLikelihoodGP
from .tp import StudentTProcess

__all__ = ["make_model"]


def make_model(config: ExperimentConfig, role: str = "cost"):
    """A fresh, unfitted model as the config's ``model_settings`` describe it (hyperparameters start at 1).

    Parameters
    ----------
    config : ExperimentConfig
        Its ``model`` ("tp", "gp" or "t-likelihood"), its ``reward_model`` and the fit's settings.
    role : {"cost", "reward"}, default "cost"
        Which of the agent's models: the reward model is of kind ``reward_model`` where the config names one.
    """
    check_choice("role", role, ("cost", "reward"))
    settings = config.model_settings
    kind = settings.model if role == "cost" or settings.reward_model is None else settings.reward_model
    common = dict(
        noise_variance=AGENT_NOISE_START,
        optimizer=settings.optimizer,
        learning_rate=settings.learning_rate,
        max_iter=settings.optimizer_steps,
        prior=settings.prior,
        max_fit_points=None,  # the agent draws the fit subsets
        n_restarts=settings.fit_restarts,
        warm_start=settings.warm_refits,
    )
    if kind == "tp":
        return StudentTProcess(RBF(1.0, 1.0), nu=settings.nu, noise_convention=settings.noise_convention, **common)
    if kind == "t-likelihood":  # the noise's scale starts at 1, as the others' noise variance
        fitted = settings.likelihood_nu == FITTED_NU  # then nu's search starts at the fixed value's default
        return StudentTLikelihoodGP(RBF(1.0, 1.0), nu=LIKELIHOOD_NU if fitted else settings.likelihood_nu,
                                    fit_nu=fitted, scale=AGENT_NOISE_START, optimizer=settings.optimizer,
                                    learning_rate=settings.learning_rate, max_iter=settings.optimizer_steps,
                                    prior=settings.prior, n_restarts=settings.fit_restarts,
                                    warm_start=settings.warm_refits)
    return GaussianProcess(RBF(1.0, 1.0), **common)
