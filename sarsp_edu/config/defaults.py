"""The paper's settings and their limits: each default of the world, the data, the models and Algorithm 1, once.

Every other module reads its defaults from here (through :mod:`sarsp_edu.config`).
"""

from __future__ import annotations

import numbers

__all__ = [
    "GRID_SIZE",
    "N_UNSAFE",
    "ACTION_MOVES",
    "PLACEMENTS",
    "OFFLINE_EPISODES",
    "COST_DUPLICATES",
    "REWARD_DUPLICATES",
    "NU",
    "LIKELIHOOD_NU",
    "LIKELIHOOD_SCALE",
    "AGENT_NOISE_START",
    "MODEL_TITLES",
    "MODELS",
    "OPTIMIZERS",
    "ADAM_STEPS",
    "HYPERPARAMETER_BOUNDS",
    "LEARNING_RATE",
    "PRIORS",
    "NOISE_CONVENTIONS",
    "FITTED_NU",
    "NU_PRIOR",
    "OUTLIER_MODELS",
    "VARIANCES",
    "SAFE_RULES",
    "TAIL_DELTA",
    "RULE_QUESTIONS",
    "PAPER_MAGNITUDES",
    "PAPER_PROPORTIONS",
    "PAPER_SWITCH_STATES",
    "DEFINITION_4_A",
    "ABLATION_CELLS",
    "ABLATION_SEEDS",
    "PREDICTIVE",
    "PRIOR_DRAWS",
    "RETRAIN_RULES",
    "D",
    "VARIANCE_THRESHOLD",
    "K_PRIOR",
    "N_MATCHING",
    "N_SAMPLES",
    "COST_FIT_POINTS",
    "REWARD_FIT_POINTS",
    "LIMITS",
    "placement_span",
    "unsafe_capacity",
    "check_n_unsafe",
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
    """The side of the area where objects may be placed: the grid's, or one less off the last row and column.

    Parameters
    ----------
    size : int
        Side of the grid, in cells.
    placement : str, default "full"
        One of :data:`PLACEMENTS`: ``"full"`` places on the whole grid; any other value (``"reference"``)
        never on the last row and column.

    Returns
    -------
    int
        ``size`` or ``size - 1``.
    """
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

    Parameters
    ----------
    size : int
        Side of the grid, in cells.
    placement : str, default "full"
        One of :data:`PLACEMENTS`: ``"full"`` places on the whole grid; any other value (``"reference"``)
        never on the last row and column.

    Returns
    -------
    int
        ``(span^2 - 3) // 5`` for the :func:`placement_span` ``span``, never below 0.
    """
    span = placement_span(size, placement)
    return max((span * span - 3) // 5, 0)


def check_n_unsafe(n_unsafe, size: int, placement: str, size_name: str = "size") -> int:
    """``n_unsafe`` from 1 to :func:`unsafe_capacity`, with a message that names the true maximum.

    Parameters
    ----------
    n_unsafe : int
        The number of unsafe states asked for (a bool is refused).
    size : int
        Side of the grid, in cells.
    placement : str
        One of :data:`PLACEMENTS`, as in :func:`placement_span`.
    size_name : str, default "size"
        The name the error messages give ``size`` (the caller's argument name).

    Returns
    -------
    int
        ``n_unsafe`` as a plain int.

    Raises
    ------
    ValueError
        If the grid leaves room for no unsafe state, or ``n_unsafe`` is not an integer in range.
    """
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
#: the regression models an experiment can run: the Student-t process, the GP, and a GP with Student-t noise
#: (a heavy-tailed likelihood, by the Laplace approximation: a question the paper does not ask)
MODELS = ("tp", "gp", "t-likelihood")
#: each model's title, as a dashboard's side and the command's header show it
MODEL_TITLES = {"tp": "Student-t process", "gp": "Gaussian process", "t-likelihood": "GP, Student-t noise"}
#: ``likelihood_nu`` that fits the Student-t noise's degrees of freedom with the other hyperparameters, as
#: nu = 2 + e^eta (so that the noise's variance stays finite) under :data:`NU_PRIOR`
FITTED_NU = "fitted"
#: the prior of a fitted nu: Gamma(shape 2, rate 0.1) on nu - 2 (Juarez and Steel 2010's weakly informative
#: prior on a Student-t's degrees of freedom, moved to start at 2): mode 12, mean 22, density 0 at nu = 2
NU_PRIOR = (2.0, 0.1)
#: the degrees of freedom of model="t-likelihood"'s Student-t noise: the TP's value, so that the comparison
#: moves the heavy tail from the process to the noise without making it heavier or lighter
LIKELIHOOD_NU = 3.0
#: the starting scale of the Student-t noise: of a ``StudentTLikelihoodGP`` made by hand (its fit moves it), and
#: of the agent's (``make_model``), which starts every model's noise at 1 (the GP's and TP's noise variance)
LIKELIHOOD_SCALE = 0.5
AGENT_NOISE_START = 1.0

#: how outliers are made (section 5.3): rows whose inputs and targets are multiplied by m (the paper's text
#: and the reference code: far-away, high-leverage rows), or rows whose targets alone are, at their clean
#: inputs (the outliers a Student-t likelihood is made for)
OUTLIER_MODELS = ("inputs-and-targets", "targets")

# -- hyperparameter fits (section 5.2) ---------------------------------------
#: the optimisers a model may use (None: keep the constructor's hyperparameters)
OPTIMIZERS = ("adam", "lbfgs")
#: the box a GP's or TP's hyperparameters are fitted in (each of amplitude, length scale, noise variance)
HYPERPARAMETER_BOUNDS = (1e-5, 1e5)
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

#: the variance a safe set compares with sigma*^2 (and the tail rule's predictive): a new observation's, the
#: noise included (the reference code's), or the latent function's alone (the paper's eqs. 5-6)
VARIANCES = ("noisy", "latent")
#: the safety rule: the predicted distance at least d with variance at most sigma*^2 (the paper's), or the
#: model's own predictive probability of a distance below d at most delta ("tail")
SAFE_RULES = ("variance", "tail")
#: delta of the tail rule: the largest predictive probability of a violation that a safe action may have
TAIL_DELTA = 0.05
#: the rule study's questions, in the order they are run and printed (:mod:`sarsp_edu.experiments.rules`)
RULE_QUESTIONS = ("rule", "nu", "fit", "threshold", "targets", "cost model")

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
    "likelihood_nu": (1e6, "beyond it the Student-t noise is Gaussian to every digit shown: a GP; use model='gp'"),
    "outlier_magnitude": (1e4, "outlier rows are multiplied by m; the paper uses 40 to 80, and at 10^4 an "
                               "outlier's square already dwarfs a clean row's by 10^8"),
    "episodes": (100_000, "the paper runs 250; 100,000 already take about a day on one core"),
    "offline_episodes": (10_000, "100 times the paper's 100; more only adds copies the duplicate caps drop"),
    "grid_size": (50, "an episode may take n^2 steps and the offline data grows with the grid; the paper's is 10"),
    "k_prior": (5_000, "every decision factorises a k x k matrix per action; the reference code used 400"),
    "n_matching": (1_000, "the paper adds at most 10 matching rows"),
    "max_steps": (100_000, "T_max is n^2 = 100 on the paper's grid"),
    "n_samples": (10_000, "every prediction draws this many samples of each prior; the reference code drew 150"),
    "fit_restarts": (20, "each restart is one more whole search; 20 already multiply a fit's time by 21"),
    "optimizer_steps": (10_000, "the paper takes 50 Adam steps; L-BFGS-B converges in far fewer"),
    "learning_rate": (10.0, "Adam's steps are in log space: one step of 10 multiplies a hyperparameter by e^10"),
    "cost_fit_points": (100_000, "a fit factorises a matrix of this many rows; the buffers hold about 5,000"),
    "reward_fit_points": (100_000, "a fit factorises a matrix of this many rows; the buffers hold about 5,000"),
}
