"""What the settings are made of: each setting's check (:data:`CHECKS`), written once, and the groups' machinery.

Every setting is declared once, as a field of
:class:`~sarsp_edu.config.ExperimentConfig` tagged with its group
(:func:`_field`); :func:`derive_group` makes each group (``WorldSettings``,
``DataSettings``, ``ModelSettings``, ``AgentSettings``) from the fields tagged
with it, and each group runs the checks of its own fields as it is made.
"""

from __future__ import annotations

import dataclasses
import decimal
import fractions
import numbers
from dataclasses import field, fields

from .._internal.validation import check_choice, check_fraction, check_int, check_nu, check_positive
from .defaults import (
    FITTED_NU,
    LIMITS,
    MODELS,
    NOISE_CONVENTIONS,
    OPTIMIZERS,
    OUTLIER_MODELS,
    PLACEMENTS,
    PREDICTIVE,
    PRIOR_DRAWS,
    PRIORS,
    RETRAIN_RULES,
    SAFE_RULES,
    VARIANCES,
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


#: the settings groups, as the code takes them
GROUPS = ("world", "data", "model", "agent")


def _field(group, default, help: str, **metadata):
    """A setting: its group (a name of :data:`GROUPS`, a tuple of them, or None), its default, its help text.

    ``only_for="t-likelihood"`` marks a setting that one model alone reads: a
    stored config of another model leaves it out (so that results stored
    before it existed are still the same bytes) and is read back without it.
    ``since="0.3"`` marks a setting added after results were stored: a stored
    config leaves it out while it holds its default (which is how every run
    before it was made), and one read back without it gets that default.
    """
    groups = () if group is None else (group,) if isinstance(group, str) else tuple(group)
    unknown = sorted(set(groups) - set(GROUPS))
    if unknown:
        raise ValueError(f"a setting's group must be one of {GROUPS}, got {unknown}")
    return field(default=default, metadata={"help": help, "groups": groups, **metadata})


# -- each setting's check, written once -----------------------------------------
def _check_nu(nu):
    if isinstance(nu, numbers.Real) and nu > LIMITS["nu"][0]:  # before check_nu's looser bound
        raise ValueError(f"nu must be a number above 2 and at most {LIMITS['nu'][0]:g} ({LIMITS['nu'][1]}), "
                         f"got nu={nu!r}")
    check_nu(nu)


def _check_likelihood_nu(value):
    """The Student-t noise's degrees of freedom: > 2 (the noise's variance, which a safe action's predictive
    variance includes, is infinite below) and at most its limit, or ``"fitted"``."""
    if value == FITTED_NU:
        return
    number = value if isinstance(value, numbers.Real) and not isinstance(value, bool) else float("nan")
    if not (2 < number <= LIMITS["likelihood_nu"][0]):
        raise ValueError(f"likelihood_nu must be a number above 2 (the noise's variance is infinite at or below "
                         f"2) and at most {LIMITS['likelihood_nu'][0]:g} ({LIMITS['likelihood_nu'][1]}), or "
                         f"{FITTED_NU!r} (fitted with the other hyperparameters), got likelihood_nu={value!r}")


def _check_tail_delta(value):
    """The tail rule's delta: a probability in (0, 0.5] (above 0.5 an action whose predicted distance is below
    d could be called safe)."""
    number = value if isinstance(value, numbers.Real) and not isinstance(value, bool) else float("nan")
    if not (0 < number <= 0.5):
        raise ValueError("tail_delta must be a probability in (0, 0.5] (the largest predictive probability of a "
                         "violation a safe action may have; above 0.5 an action predicted closer than d to danger "
                         f"could pass), got tail_delta={value!r}")


def _check_reward_model(value):
    if value is not None:
        check_choice("reward_model", value, MODELS)


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
    "likelihood_nu": _check_likelihood_nu,
    "reward_model": _check_reward_model,
    "fit_restarts": lambda value: check_int("fit_restarts", value, 0, LIMITS["fit_restarts"][0],
                                            why=LIMITS["fit_restarts"][1]),
    "outliers": lambda value: check_choice("outliers", value, OUTLIER_MODELS),
    "variance": lambda value: check_choice("variance", value, VARIANCES),
    "safe_rule": lambda value: check_choice("safe_rule", value, SAFE_RULES),
    "tail_delta": _check_tail_delta,
    "noise_convention": lambda value: check_choice("noise_convention", value, NOISE_CONVENTIONS),
    "optimizer": lambda value: check_choice("optimizer", value, OPTIMIZERS),
    "learning_rate": lambda value: check_positive("learning_rate", value, *LIMITS["learning_rate"]),
    "optimizer_steps": _limited_int("optimizer_steps", 1),
    "prior": lambda value: check_choice("prior", value, PRIORS),
    "outlier_magnitude": lambda value: check_positive("outlier_magnitude", value, *LIMITS["outlier_magnitude"]),
    "outlier_proportion": lambda value: check_fraction("outlier_proportion", value),
    "cost_outliers": _check_bool("cost_outliers"),
    "reward_outliers": _check_bool("reward_outliers"),
    "warm_refits": _check_bool("warm_refits"),
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


# -- the groups, derived from the declared settings ---------------------------------------
class _WorldChecks(_Settings):
    """What the world's settings check together, and give ``SafeGridWorld``."""

    def __post_init__(self):
        super().__post_init__()
        check_n_unsafe(self.n_unsafe, self.grid_size, self.placement, size_name="grid_size")

    def env_kwargs(self) -> dict:
        """The keyword arguments of ``SafeGridWorld`` (and ``gymnasium.make``) for this world."""
        return dict(size=self.grid_size, n_unsafe=self.n_unsafe, d=self.d, max_steps=self.max_steps,
                    placement=self.placement)


def derive_group(settings, group: str, name: str, doc: str):
    """The frozen dataclass of one group: the fields of ``settings`` tagged with ``group``, same defaults and help.

    Parameters
    ----------
    settings : type
        The dataclass that declares every setting (``ExperimentConfig``).
    group : str
        One of :data:`GROUPS`.
    name, doc : str
        The group's class name and docstring.
    """
    base = _WorldChecks if group == "world" else _Settings
    declared = [(f.name, f.type, field(default=f.default, metadata=f.metadata))
                for f in fields(settings) if group in f.metadata.get("groups", ())]
    made = dataclasses.make_dataclass(name, declared, bases=(base,), frozen=True)
    made.__doc__, made.__module__ = doc, settings.__module__
    return made
