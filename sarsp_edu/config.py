"""Every setting of an experiment, its defaults and its named presets, in one light module.

The defaults of Algorithm 1 and of the world are defined here once; the
agent, the world and the offline data read them from here.  Importing this
module loads no numerical library, so the ``sarsp-edu`` command can build its
flags (and answer ``--help``) at once.
"""

from __future__ import annotations

import dataclasses
import numbers
from dataclasses import dataclass, field, fields

from ._validation import (
    check_choice,
    check_fraction,
    check_int,
    check_nu,
    check_positive,
    check_switch_states,
)

__all__ = [
    "AgentSettings", "DataSettings", "ExperimentConfig", "ModelSettings", "PRESETS", "PRESET_DOCS", "PRESET_FIELDS",
    "WorldSettings", "preset_of",
]

# -- the world (paper section 5.1) ------------------------------------------
#: the paper's world: a 10 x 10 grid with 15 unsafe states
GRID_SIZE = 10
N_UNSAFE = 15
#: (dx, dy) of each action, RIGHT, DOWN, LEFT, UP (numbered as in the reference
#: implementation; y grows downwards, as the grid is drawn)
ACTION_MOVES = ((1, 0), (0, 1), (-1, 0), (0, -1))
#: where objects may be placed: the full grid (the paper's text) or never the
#: last row and column (the reference code)
PLACEMENTS = ("full", "reference")


def placement_span(size: int, placement: str = "full") -> int:
    """The side of the area where objects may be placed: the grid's, or one less off the last row and column."""
    return size if placement == "full" else size - 1


def unsafe_capacity(size: int, placement: str = "full") -> int:
    """The most unsafe states a world of this size always places, and shifts.

    Placement is uniform and greedy, and falls back to one colour of the
    chessboard when it paints itself into a corner.  The states a shift moves
    must avoid the kept states and their 4 neighbours (at most 5 cells each),
    the cells they leave, and the start, goal and agent.  For ``k`` of ``n``
    states that leaves at least ``S - 5(n - k) - k - 3`` free cells on an area
    of ``S`` cells, and the larger colour of them (at least half) holds ``k``
    cells that touch neither each other nor a kept state whenever
    ``n <= (S - 3) / 5``: 19 on the paper's 10 x 10 grid, 15 on the
    reference code's 9 x 9 placement area.  (The spacing rule alone would
    allow a whole chessboard colour, 50, which no shift could then move.)
    """
    span = placement_span(size, placement)
    return max((span * span - 3) // 5, 0)


def check_n_unsafe(n_unsafe, size: int, placement: str, size_name: str = "size") -> int:
    """``n_unsafe`` from 1 to :func:`unsafe_capacity`, with a message that names the true maximum."""
    capacity = unsafe_capacity(size, placement)
    if capacity < 1:
        smallest = 3 if placement == "full" else 4
        raise ValueError(
            f"{size_name} must be at least {smallest} with placement={placement!r}: a smaller grid leaves no "
            f"room for an unsafe state apart from the start, the goal and the agent, got {size_name}={size}"
        )
    span = placement_span(size, placement)
    if isinstance(n_unsafe, bool) or not isinstance(n_unsafe, numbers.Integral) or not 1 <= n_unsafe <= capacity:
        raise ValueError(
            f"n_unsafe must be an integer from 1 to {capacity}, the most unsafe states that can always be "
            f"placed and shifted apart on a {span}x{span} placement area, got n_unsafe={n_unsafe!r}"
        )
    return int(n_unsafe)


# -- the offline data (section 5.2) ------------------------------------------
#: random-policy episodes of offline data (paper: 100)
OFFLINE_EPISODES = 100
#: the reference implementation's duplicate caps
COST_DUPLICATES = 12
REWARD_DUPLICATES = 1

# -- the models (section 3.2) -------------------------------------------------
#: the TP's degrees of freedom, which the paper fixes at 3
NU = 3.0
#: the regression models an experiment can run
MODELS = ("tp", "gp")

# -- hyperparameter fits (section 5.2) ---------------------------------------
#: the optimisers a model may use (None: keep the constructor's hyperparameters)
OPTIMIZERS = ("adam", "lbfgs")
#: the paper's optimiser: 50 Adam steps with learning rate 0.1
ADAM_STEPS = 50
LEARNING_RATE = 0.1
#: hyperparameter priors: LogNormal(0, 1) on each (the reference code), or none
PRIORS = ("lognormal", None)
#: how the TP's predictive variance includes the noise: scaled with the rest
#: (Shah et al. 2014, GPy; a StudentTProcess's default) or added unscaled
#: (TensorFlow Probability, the reference code's library; the experiments')
NOISE_CONVENTIONS = ("shah", "tfp")

# -- the sweep and the comparison (sections 5.4-5.6) -------------------------
#: the paper's grid: 3 magnitudes x 3 proportions x 5 numbers of switch states
PAPER_MAGNITUDES = (40, 60, 80)
PAPER_PROPORTIONS = (0.2, 0.3, 0.4)
PAPER_SWITCH_STATES = (2, 4, 6, 8, 10)
#: Definition 4's TSR threshold a (%): the strictest, 100, unless a task says otherwise
DEFINITION_4_A = 100.0
#: the ablation's (m, p, nss) cells, one per row of the paper's grid, and its seeds
ABLATION_CELLS = ((40.0, 0.2, 2), (60.0, 0.3, 6), (80.0, 0.4, 10))
ABLATION_SEEDS = (0, 1)

# -- Algorithm 1 ---------------------------------------------------------------
#: how predictions are made: exact, or the reference code's sampled estimate
PREDICTIVE = ("closed_form", "sample")
#: how strategic priors are drawn: a fresh one for every action (the reference
#: code) or one per step shared by the four actions (the printed Algorithm 1)
PRIOR_DRAWS = ("per_action", "per_step")
#: when the corrective update retrains the cost model: only when it changed a
#: stored target or added a row (the reference code), after every corrective
#: update (the printed Algorithm 1), or never
RETRAIN_RULES = ("if_changed", "always", "never")

#: safety threshold on the predicted distance to danger (paper: 1)
D = 1.0
#: sigma*^2, the largest cost variance of a safe action (reference code: 0.8)
VARIANCE_THRESHOLD = 0.8
#: random rows in each strategic prior (paper's text: 100; reference code: 400)
K_PRIOR = 100
#: rows matching a query added to the prior, at most (paper and reference: 10)
N_MATCHING = 10
#: draws per prediction in the reference code's Monte Carlo estimate
N_SAMPLES = 150
#: rows of the cost model's data used for each hyperparameter fit (None: all,
#: as the reference code; exact and fast, because the ~4,700 rows hold only
#: ~800 distinct inputs, see linalg.group_rows)
COST_FIT_POINTS = None
#: rows drawn at random for the reward model's hyperparameter fit (None: all
#: ~4,900, as the reference code: 50 steps of a 4,900-point factorisation, about
#: four minutes; 1,000 rows give nearly the same hyperparameters in 2 s, see
#: benchmarks/bench_fits.py)
REWARD_FIT_POINTS = 1000


# -- upper bounds ------------------------------------------------------------
#: the largest value of each setting that can still be useful, and why: a value
#: beyond it is refused before any work starts (instead of a run that never
#: ends, a request for more memory than a laptop has, or an overflow deep in a
#: fit)
LIMITS = {
    "nu": (1e6, "beyond it the TP's variance factor is 1 to within (beta - n) / nu: a GP; use model='gp'"),
    "outlier_magnitude": (1e4, "outlier rows are multiplied by m; the paper uses 40 to 80, and at 10^4 an "
                               "outlier's square already dwarfs a clean row's by 10^8"),
    "episodes": (100_000, "the paper runs 250; 100,000 already take about a day on one core"),
    "offline_episodes": (10_000, "100 times the paper's 100; more only adds copies the duplicate caps drop"),
    "grid_size": (50, "an episode may take n^2 steps and the offline data grows with the grid; the paper's is 10"),
    "k_prior": (5_000, "every decision factorises a k x k matrix per action; the reference code used 400"),
    "n_matching": (1_000, "the paper adds at most 10 matching rows"),
    "max_steps": (100_000, "T_max is n^2 = 100 on the paper's grid"),
    "n_samples": (10_000, "every prediction draws this many samples of each prior; the reference code drew 150"),
    "optimizer_steps": (10_000, "the paper takes 50 Adam steps; L-BFGS-B converges in far fewer"),
    "learning_rate": (10.0, "Adam's steps are in log space: one step of 10 multiplies a hyperparameter by e^10"),
    "cost_fit_points": (100_000, "a fit factorises a matrix of this many rows; the buffers hold about 5,000"),
    "reward_fit_points": (100_000, "a fit factorises a matrix of this many rows; the buffers hold about 5,000"),
}


def _plain(value):
    """A numpy scalar as the Python number it holds (``np.int64(2)`` -> ``2``); anything else unchanged.

    Settings are saved as JSON, which takes Python numbers only.
    """
    if type(value).__module__ == "numpy" and getattr(value, "ndim", None) == 0 and hasattr(value, "item"):
        return value.item()
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
    """The world (paper section 5.1): :class:`~sarsp_edu.gridworld.SafeGridWorld` takes them (``env_kwargs``)."""

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
    :class:`~sarsp_edu.processes.StudentTProcess` defaults to ``"shah"``,
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
    """Algorithm 1's settings: what :class:`~sarsp_edu.sarsp.SARSPAgent` takes."""

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


_GROUPS = {"world_settings": WorldSettings, "data_settings": DataSettings, "model_settings": ModelSettings,
           "agent_settings": AgentSettings}


@dataclass(frozen=True)
class ExperimentConfig(_Settings):
    """Every setting of one run; the defaults are the paper's (and its reference code's).

    The settings are flat here (one flag each for the ``sarsp-edu`` command,
    one key each in a stored ``result.json``); the code takes them in groups,
    :attr:`world_settings`, :attr:`data_settings`, :attr:`model_settings` and
    :attr:`agent_settings`, which hold each group's defaults and checks: a
    config is checked by making its groups.  Each field's
    ``metadata["help"]`` documents it; the ``sarsp-edu`` command builds its
    flags from the same text.
    """

    model: str = _field(ModelSettings.model, "the regression model of both the cost and the reward model: 'tp' "
                        "or 'gp'", choices=MODELS)
    nu: float = _field(ModelSettings.nu, "TP degrees of freedom, > 2 (paper: fixed at 3)")
    outlier_magnitude: float = _field(DataSettings.outlier_magnitude, "outlier magnitude m: outlier rows are "
                                      "multiplied by m (paper: 40, 60, 80)", flag="m")
    outlier_proportion: float = _field(DataSettings.outlier_proportion, "outlier proportion p in [0, 1] (paper: "
                                       "0.2, 0.3, 0.4)", flag="p")
    n_switch_states: int = _field(2, "nss: unsafe states moved by the covariate shift (paper: 2 to 10)", flag="nss")
    episodes: int = _field(250, "online episodes (paper: 250)")
    offline_episodes: int = _field(DataSettings.offline_episodes, "random-policy episodes of offline data "
                                   "(paper: 100)")
    grid_size: int = _field(WorldSettings.grid_size, "grid side n (paper: 10)")
    n_unsafe: int = _field(WorldSettings.n_unsafe, "number of unsafe states (paper: 15)")
    d: float = _field(AgentSettings.d, "safety threshold on the distance to the nearest unsafe state (paper: 1)")
    variance_threshold: float = _field(AgentSettings.variance_threshold,
                                       "sigma*^2: the largest cost variance of a safe action (reference code: 0.8)")
    k_prior: int = _field(AgentSettings.k_prior, "random rows in each strategic prior (paper's text: 100; the "
                          "reference code, which produced the paper's figures: 400)")
    n_matching: int = _field(AgentSettings.n_matching, "rows matching each query added to the prior, at most "
                             "(paper: 10)")
    prior_draw: str = _field(AgentSettings.prior_draw, "how strategic priors are drawn: 'per_action' (a fresh "
                             "prior for every action and model, as the reference code) or 'per_step' (one per "
                             "model and step, shared by the four actions, as the printed Algorithm 1)",
                             choices=PRIOR_DRAWS)
    cost_outliers: bool = _field(DataSettings.cost_outliers, "inject outliers into the cost model's data "
                                 "(paper: yes)")
    reward_outliers: bool = _field(DataSettings.reward_outliers, "inject outliers into the reward model's data "
                                   "(paper: yes)")
    seed: int = _field(0, "seed of every random choice of the run")
    max_steps: int | None = _field(WorldSettings.max_steps, "steps before an episode is truncated (default: "
                                   "grid_size^2, the paper's T_max)")
    placement: str = _field(WorldSettings.placement, "where objects are placed: 'full' grid (paper's text) or "
                            "'reference' (never the last row/column, as the reference code)", choices=PLACEMENTS)
    cost_duplicates: int = _field(DataSettings.cost_duplicates, "duplicate cap of the cost model's data "
                                  "(reference code: 12)")
    reward_duplicates: int = _field(DataSettings.reward_duplicates, "duplicate cap of the reward model's data "
                                    "(reference code: 1)")
    predictive: str = _field(AgentSettings.predictive, "how predictions are made: 'closed_form' (exact) or "
                             "'sample' (the reference code's 150-draw estimate)", choices=PREDICTIVE)
    n_samples: int = _field(AgentSettings.n_samples, "draws per prediction with predictive='sample' (reference "
                            "code: 150)")
    noise_convention: str = _field(ModelSettings.noise_convention, "how the TP's predictive variance includes the "
                                   "noise: 'tfp' (unscaled, as the reference code's library; unlike a bare "
                                   "StudentTProcess, whose default is 'shah') or 'shah' (scaled)",
                                   choices=NOISE_CONVENTIONS)
    optimizer: str = _field(ModelSettings.optimizer, "hyperparameter optimiser: 'adam' (paper) or 'lbfgs'",
                            choices=OPTIMIZERS)
    learning_rate: float = _field(ModelSettings.learning_rate, "Adam's learning rate (paper: 0.1)")
    optimizer_steps: int = _field(ModelSettings.optimizer_steps, "Adam steps, or L-BFGS-B's iteration cap (paper: "
                                  "50 Adam steps)")
    prior: str | None = _field(ModelSettings.prior, "hyperparameter priors: 'lognormal' (LogNormal(0, 1), "
                               "reference code) or None (plain marginal likelihood)", choices=PRIORS)
    cost_fit_points: int | None = _field(AgentSettings.cost_fit_points, "rows of the cost model's data for each "
                                         "hyperparameter fit (None: all ~4,700, as the reference code; exact and "
                                         "fast, the rows hold ~800 distinct inputs)")
    reward_fit_points: int | None = _field(AgentSettings.reward_fit_points, "rows drawn at random for the reward "
                                           "model's hyperparameter fit (None: all ~4,900, as the reference code, "
                                           "about 4 minutes a fit)")
    retrain: str = _field(AgentSettings.retrain, "when a corrective update retrains the cost model: 'if_changed' "
                          "(only when it changed the data, as the reference code), 'always' (the printed "
                          "Algorithm 1) or 'never'", choices=RETRAIN_RULES)

    def __post_init__(self):
        self._make_plain()
        CHECKS["model"](self.model)
        for name in _GROUPS:  # each group checks its own settings as it is made
            getattr(self, name)
        for name in ("episodes", "seed"):
            CHECKS[name](getattr(self, name))
        check_switch_states(self.n_switch_states, self.n_unsafe)

    def _group(self, name: str):
        group = _GROUPS[name]
        made = group(**{f.name: getattr(self, f.name) for f in fields(group)})
        self.__dict__[name] = made  # kept: the config is frozen, so its groups never change
        return made

    @property
    def world_settings(self) -> WorldSettings:
        """The world's settings: grid size, unsafe states, d, T_max, placement."""
        return self.__dict__.get("world_settings") or self._group("world_settings")

    @property
    def data_settings(self) -> DataSettings:
        """The offline data's settings and its outliers' (m, p and which models get them)."""
        return self.__dict__.get("data_settings") or self._group("data_settings")

    @property
    def model_settings(self) -> ModelSettings:
        """The regression model (TP or GP, nu, the noise convention) and its hyperparameter fit."""
        return self.__dict__.get("model_settings") or self._group("model_settings")

    @property
    def agent_settings(self) -> AgentSettings:
        """Algorithm 1's settings (d, sigma*^2, k, n, the prior draw, predictions, fits, retraining)."""
        return self.__dict__.get("agent_settings") or self._group("agent_settings")

    @classmethod
    def from_preset(cls, name: str = "default", **changes) -> "ExperimentConfig":
        """The config of a named preset (see ``PRESETS``), with some fields changed.

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

    def ignored_settings(self) -> dict:
        """The settings that this config's other choices leave unused: ``{field: reason}``.

        Examples
        --------
        >>> sorted(ExperimentConfig(model="gp").ignored_settings())
        ['n_samples', 'noise_convention', 'nu']
        """
        ignored = {}
        if self.predictive != "sample":
            ignored["n_samples"] = (f"predictions are exact (predictive={self.predictive!r}); it counts only with "
                                    "predictive='sample'")
        if self.optimizer != "adam":
            ignored["learning_rate"] = f"it is Adam's, and optimizer={self.optimizer!r}"
        if self.model == "gp":
            ignored["nu"] = "it is the TP's degrees of freedom, and model='gp'"
            ignored["noise_convention"] = "it says how the TP scales its noise, and model='gp'"
        return ignored

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, values: dict) -> "ExperimentConfig":
        """A config from ``to_dict``'s output, also from results stored by sarsp_edu 0.1.

        Every field must be there (a stored config holds them all: a gap
        means the file was cut or edited, and a default filled in would be
        untrue).  Version 0.1 had one ``fit_points`` for both models, a
        boolean ``retrain`` (True: after every corrective update) and always
        one prior per step; such a config is read with exactly those settings.
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
        lacking = sorted(known - set(values))
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
    # the algorithm as the paper prints it
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
    "paper_text": "the algorithm as the paper prints it: one prior per step shared by the four actions, "
                  "k = 100, hyperparameters fitted on all the data, retrain after every corrective update, "
                  "the full grid and T_max = n^2",
}


def preset_of(config: "ExperimentConfig") -> str:
    """The name of the preset whose ``PRESET_FIELDS`` all equal the config's, or ``"custom"``."""
    for name, values in PRESETS.items():
        if all(getattr(config, key) == value for key, value in values.items()):
            return name
    return "custom"
