"""``ExperimentConfig``: every setting of one run, flat, checked by making its groups; and the named presets."""

from __future__ import annotations

import functools
from dataclasses import dataclass, fields

from .._internal.validation import check_choice, check_switch_states
from .defaults import (
    ADAM_STEPS,
    COST_DUPLICATES,
    COST_FIT_POINTS,
    GRID_SIZE,
    K_PRIOR,
    LEARNING_RATE,
    LIKELIHOOD_NU,
    MODELS,
    N_MATCHING,
    N_SAMPLES,
    N_UNSAFE,
    NOISE_CONVENTIONS,
    NU,
    OFFLINE_EPISODES,
    OPTIMIZERS,
    OUTLIER_MODELS,
    PLACEMENTS,
    PREDICTIVE,
    PRIOR_DRAWS,
    PRIORS,
    RETRAIN_RULES,
    REWARD_DUPLICATES,
    REWARD_FIT_POINTS,
    SAFE_RULES,
    TAIL_DELTA,
    VARIANCE_THRESHOLD,
    VARIANCES,
    D,
)
from .settings import CHECKS, _field, _Settings, derive_group


@dataclass(frozen=True)
class ExperimentConfig(_Settings):
    """Every setting of one run; the defaults are the paper's (and its reference code's).

    Each setting is declared once, here: its group, its default and its help
    (``metadata["groups"]`` and ``metadata["help"]``; the ``sarsp-edu`` command
    builds its flags from the same text, a stored ``result.json`` has one key
    per field).  The code takes the settings in groups derived from these
    fields, :class:`WorldSettings`, :class:`DataSettings`,
    :class:`ModelSettings` and :class:`AgentSettings` (``d`` is in two);
    :attr:`world_settings` and the like give a config's, and each setting's
    check (:data:`~sarsp_edu.config.settings.CHECKS`) runs as they are made.
    """

    model: str = _field("model", "tp", "the regression model of both the cost and the reward model: 'tp', "
                        "'gp' or 't-likelihood' (a GP with Student-t noise, by the Laplace approximation)",
                        choices=MODELS)
    nu: float = _field("model", NU, "TP degrees of freedom, > 2 (paper: fixed at 3)")
    likelihood_nu: float | str = _field("model", LIKELIHOOD_NU, "degrees of freedom of model='t-likelihood''s "
                                        "Student-t noise, > 2, or 'fitted' (fitted with the other hyperparameters "
                                        "as 2 + e^eta, under a Gamma(2, 0.1) prior on nu - 2): unlike nu (the TP's, "
                                        "a heavy-tailed process), a heavy-tailed likelihood, whose mean discounts a "
                                        "point beyond sqrt(nu) noise scales", only_for="t-likelihood")
    reward_model: str | None = _field("model", None, "the reward model's kind when it differs from the cost "
                                      "model's ('tp', 'gp' or 't-likelihood'; None: model's), so that a model's "
                                      "safety can be measured beside another's reward model", choices=(*MODELS, None),
                                      since="0.3", shown_default="the model's")
    outlier_magnitude: float = _field("data", 40.0, "outlier magnitude m: outlier rows are "
                                      "multiplied by m (paper: 40, 60, 80)", flag="m")
    outlier_proportion: float = _field("data", 0.2, "outlier proportion p in [0, 1] (paper: "
                                       "0.2, 0.3, 0.4)", flag="p")
    n_switch_states: int = _field(None, 2, "nss: unsafe states moved by the covariate shift (paper: 2 to 10)",
                                  flag="nss")
    episodes: int = _field(None, 250, "online episodes (paper: 250)")
    offline_episodes: int = _field("data", OFFLINE_EPISODES, "random-policy episodes of offline data "
                                   "(paper: 100)")
    grid_size: int = _field("world", GRID_SIZE, "grid side n (paper: 10)")
    n_unsafe: int = _field("world", N_UNSAFE, "number of unsafe states (paper: 15)")
    d: float = _field(("world", "agent"), D, "safety threshold on the distance to the nearest unsafe state (paper: 1)")
    variance_threshold: float = _field("agent", VARIANCE_THRESHOLD,
                                       "sigma*^2: the largest cost variance of a safe action (reference code: 0.8)")
    variance: str = _field("agent", "noisy", "the cost variance the safe set compares with sigma*^2 (and whose "
                           "predictive the tail rule reads): 'noisy', a new observation's, the noise included (the "
                           "reference code's), or 'latent', the function's alone (the paper's eqs. 5-6)",
                           choices=VARIANCES, since="0.3")
    safe_rule: str = _field("agent", "variance", "the safety rule: 'variance' (predicted distance >= d and variance "
                            "<= sigma*^2, the paper's) or 'tail' (the model's own predictive probability of a "
                            "distance below d at most tail_delta)", choices=SAFE_RULES, since="0.3")
    tail_delta: float = _field("agent", TAIL_DELTA, "delta of safe_rule='tail': the largest predictive probability "
                               "of a violation a safe action may have, in (0, 0.5]", since="0.3")
    k_prior: int = _field("agent", K_PRIOR, "random rows in each strategic prior (paper's text: 100; the "
                          "reference code, which produced the paper's figures: 400)")
    n_matching: int = _field("agent", N_MATCHING, "rows matching each query added to the prior, at most "
                             "(paper: 10)")
    prior_draw: str = _field("agent", "per_action", "how strategic priors are drawn: 'per_action' (a fresh "
                             "prior for every action and model, as the reference code) or 'per_step' (one per "
                             "model and step, shared by the four actions, as the printed Algorithm 1)",
                             choices=PRIOR_DRAWS)
    outliers: str = _field("data", "inputs-and-targets", "how outlier rows are made: 'inputs-and-targets' (the "
                           "row's inputs and targets multiplied by m, as the paper's text and reference code) or "
                           "'targets' (the targets alone, at the row's clean inputs)", choices=OUTLIER_MODELS,
                           since="0.3")
    cost_outliers: bool = _field("data", True, "inject outliers into the cost model's data "
                                 "(paper: yes)")
    reward_outliers: bool = _field("data", True, "inject outliers into the reward model's data "
                                   "(paper: yes)")
    seed: int = _field(None, 0, "seed of every random choice of the run")
    max_steps: int | None = _field("world", None, "steps before an episode is truncated (default: "
                                   "grid_size^2, the paper's T_max)")
    placement: str = _field("world", "full", "where objects are placed: 'full' grid (paper's text) or "
                            "'reference' (never the last row/column, as the reference code)", choices=PLACEMENTS)
    cost_duplicates: int = _field("data", COST_DUPLICATES, "duplicate cap of the cost model's data "
                                  "(reference code: 12)")
    reward_duplicates: int = _field("data", REWARD_DUPLICATES, "duplicate cap of the reward model's data "
                                    "(reference code: 1)")
    predictive: str = _field("agent", "closed_form", "how predictions are made: 'closed_form' (exact) or "
                             "'sample' (the reference code's 150-draw estimate)", choices=PREDICTIVE)
    n_samples: int = _field("agent", N_SAMPLES, "draws per prediction with predictive='sample' (reference "
                            "code: 150)")
    noise_convention: str = _field("model", "tfp", "how the TP's predictive variance includes the "
                                   "noise: 'tfp' (unscaled, as the reference code's library; unlike a bare "
                                   "StudentTProcess, whose default is 'shah') or 'shah' (scaled)",
                                   choices=NOISE_CONVENTIONS)
    optimizer: str = _field("model", "adam", "hyperparameter optimiser: 'adam' (paper) or 'lbfgs'",
                            choices=OPTIMIZERS)
    learning_rate: float = _field("model", LEARNING_RATE, "Adam's learning rate (paper: 0.1)")
    optimizer_steps: int = _field("model", ADAM_STEPS, "Adam steps, or L-BFGS-B's iteration cap (paper: "
                                  "50 Adam steps)")
    fit_restarts: int = _field("model", 0, "extra starts of each hyperparameter search, the best objective kept: "
                               "the first from narrow noise (noise / e^4), then wide noise, short and long length "
                               "scales, low and high amplitude (paper: none)", since="0.3")
    warm_refits: bool = _field("model", False, "whether the corrective updates' refits search from the last fit's "
                               "hyperparameters, one start, where each otherwise starts again from 1 with "
                               "fit_restarts extra starts (reference code: from 1)", since="0.3")
    prior: str | None = _field("model", "lognormal", "hyperparameter priors: 'lognormal' (LogNormal(0, 1), "
                               "reference code) or None (plain marginal likelihood)", choices=PRIORS)
    cost_fit_points: int | None = _field("agent", COST_FIT_POINTS, "rows of the cost model's data for each "
                                         "hyperparameter fit (None: all ~4,700, as the reference code; exact and "
                                         "fast, the rows hold ~800 distinct inputs)")
    reward_fit_points: int | None = _field("agent", REWARD_FIT_POINTS, "rows drawn at random for the reward "
                                           "model's hyperparameter fit (None: all ~4,900, as the reference code, "
                                           "about 4 minutes a fit)")
    retrain: str = _field("agent", "if_changed", "when a corrective update retrains the cost model: 'if_changed' "
                          "(only when it changed the data, as the reference code), 'always' (the printed "
                          "Algorithm 1) or 'never'", choices=RETRAIN_RULES)

    def __post_init__(self):
        self._make_plain()
        CHECKS["model"](self.model)
        for name in ("world_settings", "data_settings", "model_settings", "agent_settings"):
            getattr(self, name)  # each group checks its own settings as it is made
        for name in ("episodes", "seed"):
            CHECKS[name](getattr(self, name))
        check_switch_states(self.n_switch_states, self.n_unsafe)

    def _group(self, group):
        """The settings of ``group`` that this config holds (checked as they are made)."""
        return group(**{f.name: getattr(self, f.name) for f in fields(group)})

    # each made once: the config is frozen, so its groups never change (cached_property writes the
    # instance's __dict__ directly, which a frozen dataclass allows)
    @functools.cached_property
    def world_settings(self) -> WorldSettings:
        """The world's settings: grid size, unsafe states, d, T_max, placement."""
        return self._group(WorldSettings)

    @functools.cached_property
    def data_settings(self) -> DataSettings:
        """The offline data's settings and its outliers' (m, p and which models get them)."""
        return self._group(DataSettings)

    @functools.cached_property
    def model_settings(self) -> ModelSettings:
        """The regression model (TP or GP, nu, the noise convention) and its hyperparameter fit."""
        return self._group(ModelSettings)

    @functools.cached_property
    def agent_settings(self) -> AgentSettings:
        """Algorithm 1's settings (d, sigma*^2, k, n, the prior draw, predictions, fits, retraining)."""
        return self._group(AgentSettings)

    @classmethod
    def from_preset(cls, name: str = "default", **changes) -> "ExperimentConfig":
        """The config of a named preset (see ``PRESETS``), with some fields changed.

        Parameters
        ----------
        name : str, default "default"
            A key of ``PRESETS``.
        **changes
            Fields to change from the preset's values (checked).

        Examples
        --------
        >>> ExperimentConfig.from_preset("reference").k_prior
        400
        >>> ExperimentConfig.from_preset("paper_text", episodes=20).prior_draw
        'per_step'
        """
        check_choice("preset", name, tuple(PRESETS))
        return cls(**{**PRESETS[name], **changes})

    @property
    def preset(self) -> str:
        """The preset whose settings this config has (``PRESET_FIELDS``), or ``"custom"``.

        Fields outside ``PRESET_FIELDS`` (the configuration m, p, nss, the
        seed, the number of episodes) do not count.
        """
        return preset_of(self)

    @property
    def offline_fit_steps(self) -> int | None:
        """Steps of the hyperparameter search in the agent's offline fit (cost and reward model), as progress
        counts them; None for L-BFGS, which takes as many as it needs."""
        return 2 * self.optimizer_steps * (1 + self.fit_restarts) if self.optimizer == "adam" else None

    def ignored_settings(self) -> dict:
        """The settings that this config's other choices leave unused: ``{field: reason}``.

        Examples
        --------
        >>> sorted(ExperimentConfig(model="gp").ignored_settings())
        ['likelihood_nu', 'n_samples', 'noise_convention', 'nu', 'tail_delta']
        """
        ignored = {}
        if self.predictive != "sample":
            ignored["n_samples"] = (f"predictions are exact (predictive={self.predictive!r}); it counts only with "
                                    "predictive='sample'")
        if self.optimizer != "adam":
            ignored["learning_rate"] = f"it is Adam's, and optimizer={self.optimizer!r}"
        kinds = self.model_kinds
        said = f"model={self.model!r}" + (f" and reward_model={self.reward_model!r}" if len(kinds) > 1 else "")
        if "tp" not in kinds:
            ignored["nu"] = f"it is the TP's degrees of freedom, and {said}"
            ignored["noise_convention"] = f"it says how the TP scales its noise, and {said}"
        if "t-likelihood" not in kinds:
            ignored["likelihood_nu"] = f"it is the Student-t noise's of model='t-likelihood', and {said}"
        if self.safe_rule != "tail":
            ignored["tail_delta"] = f"it is the tail rule's, and safe_rule={self.safe_rule!r}"
        if self.reward_model == self.model:
            ignored["reward_model"] = f"it names the cost model's own kind, model={self.model!r}"
        return ignored

    @property
    def model_kinds(self) -> tuple:
        """The kinds of the run's models: ``(model,)``, or ``(model, reward_model)`` where they differ."""
        if self.reward_model is None or self.reward_model == self.model:
            return (self.model,)
        return (self.model, self.reward_model)

    def to_dict(self) -> dict:
        """Every setting by name, as a stored ``result.json`` holds them (``from_dict`` reads it back); a setting
        of another model alone (``likelihood_nu`` of a TP run) is left out, and so is a setting added since
        results were first stored (``since``) while it holds its default."""
        return {f.name: getattr(self, f.name) for f in fields(self) if _stored(f, self)}

    @classmethod
    def from_dict(cls, values: dict) -> "ExperimentConfig":
        """A config from ``to_dict``'s output, also from results stored by sarsp_edu 0.1.

        Every field must be there (a stored config holds them all: a gap
        means the file was cut or edited, and a default filled in would be
        untrue), but those added since (``since``), which a config leaves out
        at their default: one read without them has their default.  Version
        0.1 had one ``fit_points`` for both models, a boolean ``retrain``
        (True: after every corrective update) and always one prior per step;
        such a config is read with exactly those settings.
        """
        values = dict(values)
        if "fit_points" in values:  # written by sarsp_edu 0.1
            points = values.pop("fit_points")
            values.setdefault("cost_fit_points", points)
            values.setdefault("reward_fit_points", points)
            values.setdefault("prior_draw", "per_step")
            if isinstance(values.get("retrain"), bool):
                values["retrain"] = "always" if values["retrain"] else "never"
            legacy = True
        else:
            legacy = False
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(values) - known)
        if unknown:
            raise ValueError(f"unknown ExperimentConfig fields {unknown}; valid fields are {sorted(known)}")
        kinds = {values.get("model", ExperimentConfig.model), values.get("reward_model")}
        lacking = sorted(f.name for f in fields(cls) if f.name not in values and "since" not in f.metadata
                         and f.metadata.get("only_for", values.get("model")) in kinds)
        if lacking and not legacy:  # a stored config holds every field: a gap means it was cut or edited
            raise ValueError(f"the config lacks the fields {lacking}, which every stored config holds")
        return cls(**values)


#: the settings a preset fixes: how SARSP is run, not which configuration
PRESET_FIELDS = (
    "prior_draw",
    "k_prior",
    "n_matching",
    "predictive",
    "n_samples",
    "cost_fit_points",
    "reward_fit_points",
    "retrain",
    "placement",
    "max_steps",
    "noise_convention",
)

_DEFAULTS = {f.name: f.default for f in fields(ExperimentConfig)}

#: named sets of SARSP settings, each documented in ``PRESET_DOCS``
PRESETS = {
    # the package's defaults: the reference code's strategic prior, at teaching speed
    "default": {name: _DEFAULTS[name] for name in PRESET_FIELDS},
    # everything as the authors' code that produced the paper's figures
    "reference": dict(prior_draw="per_action", k_prior=400, n_matching=10, predictive="sample", n_samples=150,
                      cost_fit_points=None, reward_fit_points=None, retrain="if_changed", placement="reference",
                      max_steps=101, noise_convention="tfp"),
    # the printed Algorithm 1's settings (no preset changes the corrective check or S_u: see Tutorial 4)
    "paper_text": dict(prior_draw="per_step", k_prior=100, n_matching=10, predictive="closed_form",
                       n_samples=150, cost_fit_points=None, reward_fit_points=None, retrain="always",
                       placement="full", max_steps=None, noise_convention="tfp"),
}

PRESET_DOCS = {
    "default": "the reference code's strategic prior (a fresh prior per action) at teaching speed: k = 100, "
               "closed-form predictions, exact whole-buffer cost fits, reward fits on 1,000 random rows, "
               "the paper's full grid and T_max = n^2",
    "reference": "everything as the authors' code that produced the paper's figures: a prior per action, "
                 "k = 400, 150-draw sampled predictions, whole-buffer fits of both models, retrain only when "
                 "the data changed, placement off the last row and column, at most 101 steps an episode "
                 "(on one core, about 8 minutes a 250-episode run of one model, of which 4 are the reward "
                 "model's fit)",
    "paper_text": "the printed Algorithm 1's settings: one prior per step shared by the four actions, "
                  "k = 100, hyperparameters fitted on all the data, retrain after every corrective update, "
                  "the full grid and T_max = n^2 (the corrective check and S_u stay the package's: Tutorial 4 "
                  "lists every departure)",
}


#: the settings groups, each derived from the fields of ExperimentConfig tagged with it (``d`` is in two)
WorldSettings = derive_group(ExperimentConfig, "world", "WorldSettings", """The world (paper section 5.1):
    :class:`~sarsp_edu.world.gridworld.SafeGridWorld` takes them (``env_kwargs``).""")
DataSettings = derive_group(ExperimentConfig, "data", "DataSettings", """The offline data and its outliers (sections
    5.2-5.3): ``collect_offline_data`` and ``inject_outliers``.""")
ModelSettings = derive_group(ExperimentConfig, "model", "ModelSettings", """The regression model of both the cost
    and the reward model, and its hyperparameter fit.

    ``noise_convention`` is ``"tfp"`` here, as in the reference code's
    library, whose runs the experiments reproduce; a bare
    :class:`~sarsp_edu.models.processes.StudentTProcess` defaults to ``"shah"``,
    Shah et al.'s (2014) own form, which the tutorials teach.""")
AgentSettings = derive_group(ExperimentConfig, "agent", "AgentSettings", """Algorithm 1's settings: what
    :class:`~sarsp_edu.agent.sarsp.SARSPAgent` takes.""")


def _stored(field, config: "ExperimentConfig") -> bool:
    """Whether ``config`` stored holds ``field``: not one that another model alone reads, nor one added since
    results were first stored (``since``) while it holds its default, so that a run made as before stores the
    same bytes as before."""
    if "since" in field.metadata and getattr(config, field.name) == field.default:
        return False
    return field.metadata.get("only_for", config.model) in config.model_kinds


def preset_of(config: "ExperimentConfig") -> str:
    """The name of the preset whose ``PRESET_FIELDS`` all equal the config's, or ``"custom"``."""
    for name, values in PRESETS.items():
        if all(getattr(config, key) == value for key, value in values.items()):
            return name
    return "custom"


def config_or_default(config, name: str = "config") -> "ExperimentConfig":
    """``config`` checked to be an :class:`ExperimentConfig` (None: the default one).

    Parameters
    ----------
    config : ExperimentConfig or None
    name : str, default "config"
        The argument's name in the error message.

    Raises
    ------
    TypeError
        Naming the type given and how to make a config (a dict of settings is ``ExperimentConfig(**settings)``).
    """
    if config is None:
        return ExperimentConfig()
    if not isinstance(config, ExperimentConfig):
        hint = "; make one with ExperimentConfig(**settings)" if isinstance(config, dict) else ""
        raise TypeError(f"{name} must be an ExperimentConfig, got {type(config).__name__}{hint}")
    return config
