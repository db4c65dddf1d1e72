"""The settings grouped as the code uses them, each setting's check written once.

:class:`WorldSettings`, :class:`DataSettings`, :class:`ModelSettings` and
:class:`AgentSettings` hold the defaults (from :mod:`~sarsp_edu.config.defaults`)
and run the check of each of their fields from :data:`CHECKS`.
"""

from __future__ import annotations

import dataclasses
import decimal
import fractions
import numbers
from dataclasses import dataclass, field, fields

from .._internal.validation import check_choice, check_fraction, check_int, check_nu, check_positive
from .defaults import (
    ADAM_STEPS,
    COST_DUPLICATES,
    COST_FIT_POINTS,
    GRID_SIZE,
    K_PRIOR,
    LEARNING_RATE,
    LIMITS,
    MODELS,
    N_MATCHING,
    N_SAMPLES,
    N_UNSAFE,
    NOISE_CONVENTIONS,
    NU,
    OFFLINE_EPISODES,
    OPTIMIZERS,
    PLACEMENTS,
    PREDICTIVE,
    PRIOR_DRAWS,
    PRIORS,
    RETRAIN_RULES,
    REWARD_DUPLICATES,
    REWARD_FIT_POINTS,
    VARIANCE_THRESHOLD,
    D,
    check_n_unsafe,
)


def _plain(value):
    """A numpy scalar as the Python number it holds (``np.int64(2)`` -> ``2``), a Decimal or Fraction as a float;
    anything else unchanged.

    Settings are saved as JSON, which takes Python numbers only.
    """
    if type(value).__module__ == "numpy" and getattr(value, "ndim", None) == 0 and hasattr(value, "item"):
        return value.item()
    if isinstance(value, (decimal.Decimal, fractions.Fraction)):  # exact numbers: the float they are closest to
        return float(value)
    return value


def _field(default, help: str, **metadata):
    return field(default=default, metadata={"help": help, **metadata})


# -- each setting's check, written once -----------------------------------------
def _check_nu(nu):
    if isinstance(nu, numbers.Real) and nu > LIMITS["nu"][0]:  # before check_nu's looser bound
        raise ValueError(f"nu must be a number above 2 and at most {LIMITS['nu'][0]:g} ({LIMITS['nu'][1]}), "
                         f"got nu={nu!r}")
    check_nu(nu)


def _check_bool(name):
    def check(value):
        if not isinstance(value, bool):
            raise ValueError(f"{name} must be True or False, got {name}={value!r}")
    return check


def _limited_int(name, low, allow_none=False):
    return lambda value: check_int(name, value, low, LIMITS[name][0], allow_none=allow_none, why=LIMITS[name][1])


#: setting -> the function that checks a value of it (raising a ValueError that names the setting,
#: the value and the valid range); each settings group below runs the checks of its own fields
CHECKS = {
    "model": lambda value: check_choice("model", value, MODELS),
    "nu": _check_nu,
    "noise_convention": lambda value: check_choice("noise_convention", value, NOISE_CONVENTIONS),
    "optimizer": lambda value: check_choice("optimizer", value, OPTIMIZERS),
    "learning_rate": lambda value: check_positive("learning_rate", value, *LIMITS["learning_rate"]),
    "optimizer_steps": _limited_int("optimizer_steps", 1),
    "prior": lambda value: check_choice("prior", value, PRIORS),
    "outlier_magnitude": lambda value: check_positive("outlier_magnitude", value, *LIMITS["outlier_magnitude"]),
    "outlier_proportion": lambda value: check_fraction("outlier_proportion", value),
    "cost_outliers": _check_bool("cost_outliers"),
    "reward_outliers": _check_bool("reward_outliers"),
    "offline_episodes": _limited_int("offline_episodes", 1),
    "cost_duplicates": lambda value: check_int("cost_duplicates", value, 1),
    "reward_duplicates": lambda value: check_int("reward_duplicates", value, 1),
    "grid_size": _limited_int("grid_size", 2),
    "placement": lambda value: check_choice("placement", value, PLACEMENTS),
    "max_steps": _limited_int("max_steps", 1, allow_none=True),
    "d": lambda value: check_positive("d", value),
    "variance_threshold": lambda value: check_positive("variance_threshold", value),
    "k_prior": _limited_int("k_prior", 1),
    "n_matching": _limited_int("n_matching", 0),
    "prior_draw": lambda value: check_choice("prior_draw", value, PRIOR_DRAWS),
    "predictive": lambda value: check_choice("predictive", value, PREDICTIVE),
    "n_samples": _limited_int("n_samples", 2),
    "cost_fit_points": _limited_int("cost_fit_points", 2, allow_none=True),
    "reward_fit_points": _limited_int("reward_fit_points", 2, allow_none=True),
    "retrain": lambda value: check_choice("retrain", value, RETRAIN_RULES),
    "episodes": _limited_int("episodes", 1),
    "seed": lambda value: check_int("seed", value, 0),
}


class _Settings:
    """What the settings groups share: numpy scalars made Python numbers, each field checked, ``replace``."""

    def __post_init__(self):
        self._make_plain()
        for f in fields(self):
            if f.name in CHECKS:
                CHECKS[f.name](getattr(self, f.name))

    def _make_plain(self):
        """Numpy scalars become Python numbers, so that the settings save as JSON."""
        for f in fields(self):
            value = getattr(self, f.name)
            if _plain(value) is not value:
                object.__setattr__(self, f.name, _plain(value))

    def replace(self, **changes):
        """A copy with some fields changed (checked again)."""
        valid = [f.name for f in fields(self)]
        unknown = sorted(set(changes) - set(valid))
        if unknown:
            raise ValueError(f"{type(self).__name__} has no settings {unknown}; valid settings are {valid}")
        return dataclasses.replace(self, **changes)


# -- the settings, grouped as the code uses them ----------------------------------
@dataclass(frozen=True)
class WorldSettings(_Settings):
    """The world (paper section 5.1): :class:`~sarsp_edu.world.gridworld.SafeGridWorld` takes them (``env_kwargs``)."""

    grid_size: int = GRID_SIZE
    n_unsafe: int = N_UNSAFE
    d: float = D
    max_steps: int | None = None
    placement: str = "full"

    def __post_init__(self):
        super().__post_init__()
        check_n_unsafe(self.n_unsafe, self.grid_size, self.placement, size_name="grid_size")

    def env_kwargs(self) -> dict:
        """The keyword arguments of ``SafeGridWorld`` (and ``gymnasium.make``) for this world."""
        return dict(size=self.grid_size, n_unsafe=self.n_unsafe, d=self.d, max_steps=self.max_steps,
                    placement=self.placement)


@dataclass(frozen=True)
class DataSettings(_Settings):
    """The offline data and its outliers (sections 5.2-5.3): ``collect_offline_data`` and ``inject_outliers``."""

    offline_episodes: int = OFFLINE_EPISODES
    cost_duplicates: int = COST_DUPLICATES
    reward_duplicates: int = REWARD_DUPLICATES
    outlier_magnitude: float = 40.0
    outlier_proportion: float = 0.2
    cost_outliers: bool = True
    reward_outliers: bool = True


@dataclass(frozen=True)
class ModelSettings(_Settings):
    """The regression model of both the cost and the reward model, and its hyperparameter fit.

    ``noise_convention`` is ``"tfp"`` here, as in the reference code's
    library, whose runs the experiments reproduce; a bare
    :class:`~sarsp_edu.models.processes.StudentTProcess` defaults to ``"shah"``,
    Shah et al.'s (2014) own form, which the tutorials teach.
    """

    model: str = "tp"
    nu: float = NU
    noise_convention: str = "tfp"
    optimizer: str = "adam"
    learning_rate: float = LEARNING_RATE
    optimizer_steps: int = ADAM_STEPS
    prior: str | None = "lognormal"


@dataclass(frozen=True)
class AgentSettings(_Settings):
    """Algorithm 1's settings: what :class:`~sarsp_edu.agent.sarsp.SARSPAgent` takes."""

    d: float = D
    variance_threshold: float = VARIANCE_THRESHOLD
    k_prior: int = K_PRIOR
    n_matching: int = N_MATCHING
    prior_draw: str = "per_action"
    predictive: str = "closed_form"
    n_samples: int = N_SAMPLES
    cost_fit_points: int | None = COST_FIT_POINTS
    reward_fit_points: int | None = REWARD_FIT_POINTS
    retrain: str = "if_changed"
