"""The SARSP agent: the paper's Algorithm 1 (section 4).

At every step the agent

1. draws a *strategic prior* for each model: ``k`` random rows of its
   training set plus up to ``n`` rows whose input equals the query; by
   default a fresh one for every action, as the paper's reference code does
   (``prior_draw="per_action"``), or one per step shared by the four
   actions, as the printed Algorithm 1 reads (``prior_draw="per_step"``);
2. predicts, for every action, the cost signal (distance to danger) with its
   variance, and the reward;
3. overrides the actions it has learned are unsafe (``S_u``): cost -inf,
   variance +inf, reward -inf;
4. takes the *safe* action (variance <= sigma*^2 and predicted cost >= d) with
   the highest predicted reward or, when no action is safe, the *backup*: the
   action with the highest predicted reward;
5. after a step that violated the constraint, adds the pair to ``S_u`` and,
   if the cost model had been wrong, corrects its training set and retrains
   it.

Where the paper's text and its reference implementation differ, the agent
follows the reference implementation by default and makes the difference a
parameter (``prior_draw``, ``k_prior``, ``predictive``, ``retrain``, the fit
sizes); :class:`SARSPAgent`'s parameters say which is which.

The functions a decision is assembled from (the kernel, the GP posterior,
the TP's factor, the safe set, the choice with its backup, the corrective
test) are the agent's plug-in point: ``parts``, a
:class:`~sarsp_edu.agent.parts.DecisionParts`, whose defaults are the package's own.
"""

from __future__ import annotations

import time

import numpy as np

from .._internal.rng import as_generator, draw_row_mask, draw_subset
from .._internal.threads import one_blas_thread
from .._internal.validation import check_choice
from ..config import AgentSettings  # Algorithm 1's settings, defined once
from ..models.processes.laplace import noise_variance
from ..models.processes.likelihood import StudentTLikelihoodGP
from ..models.processes.predictive import probability_below, sample_moments
from ..world.offline import OfflineData, cost_inputs, reward_inputs
from .decision import Decision, LearnOutcome, choose_action, override_known_unsafe
from .parts import DecisionParts, corrective_applies, decide, model_parts_refusal, tail_rule_refusal
from .priors import PriorPredictor


class _Setting:
    """One of Algorithm 1's settings on the agent: ``agent.k_prior`` is ``agent.settings.k_prior``, and
    ``agent.k_prior = 400`` replaces ``agent.settings`` by a copy with that value (checked)."""

    def __set_name__(self, owner, name):
        self.name = name

    def __get__(self, agent, owner=None):
        return self if agent is None else getattr(agent.settings, self.name)

    def __set__(self, agent, value):
        agent.settings = agent.settings.replace(**{self.name: value})

# the decision rule and its records live in :mod:`sarsp_edu.agent.decision`; imported here, where readers look for them
__all__ = ["SARSPAgent", "Decision", "LearnOutcome", "choose_action", "override_known_unsafe"]


class SARSPAgent:
    """Safe and Robust Stochastic Process agent (paper Algorithm 1).

    Parameters
    ----------
    cost_model, reward_model : GaussianProcess or StudentTProcess
        Unfitted or fitted; :meth:`fit` trains them on the data.  Their
        ``max_fit_points`` is ignored: the agent draws the fit subsets itself
        (``cost_fit_points``, ``reward_fit_points``).
    data : OfflineData
        The offline training sets.  The agent works on a copy: its corrective
        updates never touch the caller's data.
    settings : AgentSettings, optional
        Algorithm 1's settings, below (``ExperimentConfig.agent_settings``
        gives a run's); default ``AgentSettings()``.  Each may also be given
        by name, ``SARSPAgent(cost, reward, data, k_prior=400)``, changing
        ``settings``; they are checked where the settings are made.
    d : float, default 1.0
        Safety threshold on the predicted distance to danger.
    variance_threshold : float, default 0.8
        sigma*^2, the largest predictive variance of a "safe" action (the
        reference implementation's 0.8).
    k_prior : int, default 100
        Random rows in each strategic prior (paper: 100; the reference code
        used 400).
    n_matching : int, default 10
        At most this many rows whose input equals an action's query are
        added to its prior (paper and reference: 10).
    prior_draw : {"per_action", "per_step"}, default "per_action"
        ``"per_action"``: each action's prediction, for each model, is
        conditioned on its own fresh prior (``k_prior`` random rows plus that
        action's matching rows), as the reference code that produced the
        paper's figures does.  ``"per_step"``: one prior per model and step,
        shared by the four actions (``k_prior`` random rows plus the matching
        rows of all four), as the printed Algorithm 1 draws one chi_c and one
        chi_r per step.  The difference decides how the agents behave (see
        Notes).
    predictive : {"closed_form", "sample"}, default "closed_form"
        ``"closed_form"``: exact predictive mean and variance, observation
        noise included.  ``"sample"``: the reference implementation's Monte
        Carlo estimate, the sample mean and variance of ``n_samples`` draws
        from the posterior predictive.
    n_samples : int, default 150
    cost_fit_points, reward_fit_points : int or None, default None and 1000
        Rows of each training set used to fit its hyperparameters: a random
        subset of that size, or all of them (``None``, the reference code).
        Every fit starts from the models' constructor values.
    retrain : {"if_changed", "always", "never"}, default "if_changed"
        When a corrective update retrains the cost model: only if it changed
        a stored target or added a row (the reference code: retraining on
        unchanged data would only repeat the last fit), after every
        corrective update, or never.
    unsafe_pairs : iterable of ((x, y), action), optional
        An initial ``S_u``; default empty.
    parts : DecisionParts or mapping, optional
        The functions each decision is assembled from (a mapping names some
        of them: ``{"choose": my_choose}``); default the package's own.  A
        replaced kernel, posterior or TP factor plugs into the models' one
        conditioning loop in place of their own step (:mod:`sarsp_edu.agent.parts`).
        The random draws are the same either way, so two agents whose parts
        compute the same values take the same decisions.
    refit_model : callable, optional
        ``refit_model(model, X, y)`` in place of ``model.fit(X, y)`` in a
        corrective update's refit (the capstone's check gives an agent whose
        data equal another's that one's refit); also the attribute of that name.
    rng : None, int or numpy.random.Generator
        Draws the priors, the fit subsets and the samples.

    Notes
    -----
    With one prior shared by the four actions, the four predictions of a
    step share their random rows, the ranking of the actions changes little
    from step to step, and a greedy agent can be trapped (pushing into a
    wall, or stepping back and forth between two cells) until the episode's
    step limit.  A prior per action makes every comparison between actions
    a little random, which breaks such loops.  ``REPRODUCTION.md`` measures
    the effect.

    The corrective update follows the reference implementation: only after a
    step that violated the constraint, and only if the re-predicted cost of
    the taken action was >= d (the model said safe) or, for a non-backup
    action, its variance was the lowest of all actions.  The paper's
    pseudo-code checks the condition after every step; its text says "if the
    predicted cost for the 'safe' action violates the safety constraint".
    ``S_u`` grows on a violation (distance < d); the paper's last line writes
    ``c <= d``.
    """

    def __init__(
        self,
        cost_model,
        reward_model,
        data: OfflineData,
        settings: AgentSettings | None = None,
        *,
        unsafe_pairs=None,
        parts=None,
        refit_model=None,
        rng=None,
        **changes,
    ):
        self.cost_model = cost_model
        self.reward_model = reward_model
        settings = AgentSettings() if settings is None else settings
        if not isinstance(settings, AgentSettings):
            raise TypeError(f"settings must be an AgentSettings, got {type(settings).__name__}")
        self.settings = settings.replace(**changes) if changes else settings
        self.rng = as_generator(rng)
        #: the strategic priors' conditioning and what keeps it quick (``prior_predictor.kernel_table``: a switch)
        self.prior_predictor = PriorPredictor()
        #: the functions each decision is assembled from (:class:`~sarsp_edu.agent.parts.DecisionParts`); the
        #: fits do not use them, so a fitted agent may be given others (``agent.parts = DecisionParts.of(...)``)
        #: before it acts
        self.parts = parts
        data = data.copy()
        self.cost_data = data.cost
        self.reward_data = data.reward
        self.unsafe_pairs: set = set()
        for position, action in unsafe_pairs or ():
            self.unsafe_pairs.add((tuple(int(v) for v in position), int(action)))
        self.corrective_updates = 0
        self.retrains = 0
        if refit_model is not None and not callable(refit_model):
            raise TypeError(f"refit_model must be a function refit_model(model, X, y) or None, got {refit_model!r}")
        self.refit_model = refit_model  #: the constructor's argument (None: ``model.fit``)
        #: callables told of each corrective update's refit of the cost model, as ``listener("begin")`` before it
        #: and ``listener("end")`` after it (in the thread that called ``learn``): the live run says "retraining"
        self.retrain_listeners: list = []

    @property
    def settings(self) -> AgentSettings:
        """Algorithm 1's settings, the one place they are kept (each also readable and settable by its name,
        ``agent.k_prior``; a new value replaces the settings, checked as a whole and against the parts)."""
        return self._settings

    @settings.setter
    def settings(self, settings: AgentSettings):
        if not isinstance(settings, AgentSettings):
            raise TypeError(f"settings must be an AgentSettings, got {type(settings).__name__}")
        parts = getattr(self, "_parts", None)  # None while the agent is being built: its parts come next
        if parts is not None and settings.safe_rule == "tail" and {"safe_set", "choose"} & set(parts.replaced()):
            raise ValueError(tail_rule_refusal(parts))
        self._settings = settings

    @property
    def parts(self) -> DecisionParts:
        """The functions each decision is assembled from; set to a DecisionParts, a mapping of some, or None
        (checked against the settings: the tail rule takes the package's safe set and choice)."""
        return self._parts

    @parts.setter
    def parts(self, parts):
        parts = DecisionParts.of(parts)
        if self.safe_rule == "tail" and {"safe_set", "choose"} & set(parts.replaced()):
            raise ValueError(tail_rule_refusal(parts))
        refusal = model_parts_refusal(parts, self.cost_model, self.reward_model)
        if refusal:
            raise ValueError(refusal)
        self._parts = parts

    # Algorithm 1's settings by name: each reads ``agent.settings`` and a new value replaces it (checked)
    d = _Setting()
    variance_threshold = _Setting()
    variance = _Setting()
    safe_rule = _Setting()
    tail_delta = _Setting()
    k_prior = _Setting()
    n_matching = _Setting()
    prior_draw = _Setting()
    predictive = _Setting()
    n_samples = _Setting()
    cost_fit_points = _Setting()
    reward_fit_points = _Setting()
    retrain = _Setting()

    # -- training -------------------------------------------------------------
    def _fit(self, model, buffer, fit_points, fit_model=None):
        rows = draw_subset(len(buffer), fit_points, self.rng)
        if fit_model is None:
            model.fit(buffer.X[rows], buffer.y[rows])
        else:
            fit_model(model, buffer.X[rows], buffer.y[rows])

    def fit(self, fit_model=None) -> "SARSPAgent":
        """Offline training: fit both models' hyperparameters on the data.

        With one BLAS thread (:func:`~sarsp_edu._internal.threads.one_blas_thread`):
        the agent's fits are a few hundred rows square, where more threads
        only add overhead, and many times more where the cores are busy.

        Parameters
        ----------
        fit_model : callable, optional
            ``fit_model(model, X, y)`` in place of ``model.fit(X, y)``, on the
            rows drawn for each model (:mod:`sarsp_edu.teaching.live.fitcache` restores a
            stored fit with it; the agent's random stream moves on the same).
        """
        with one_blas_thread():
            self._fit(self.cost_model, self.cost_data, self.cost_fit_points, fit_model)
            self._fit(self.reward_model, self.reward_data, self.reward_fit_points, fit_model)
        return self

    # -- prediction -------------------------------------------------------------
    def _matches(self, buffer, query) -> np.ndarray:
        rows = buffer.rows_of(query)
        if len(rows) > self.n_matching:
            rows = self.rng.choice(rows, size=self.n_matching, replace=False)
        return rows

    def _priors(self, buffer, queries: np.ndarray) -> list:
        """Row indices of the strategic prior of each query (see ``prior_draw``).

        ``per_action``: for each query, ``k`` fresh random rows plus up to
        ``n`` of its matching rows.  ``per_step``: one set, ``k`` random rows
        plus up to ``n`` matching rows of every query, returned once per query.
        """
        n = len(buffer)
        if self.prior_draw == "per_action":
            priors = []
            for query in queries:
                rows = draw_row_mask(n, self.k_prior, self.rng)
                if self.n_matching:
                    rows[self._matches(buffer, query)] = True  # the union (np.union1d) in the mask
                priors.append(np.flatnonzero(rows))
            return priors
        rows = draw_row_mask(n, self.k_prior, self.rng)
        if self.n_matching:
            for query in queries:
                rows[self._matches(buffer, query)] = True
        return [np.flatnonzero(rows)] * len(queries)

    def strategic_prior(self, observation, model: str = "cost") -> list:
        """Rows of one model's training set that a decision would condition on (a fresh draw).

        Parameters
        ----------
        observation : array-like of shape (8,)
        model : {"cost", "reward"}

        Returns
        -------
        list of 4 ndarrays of int
            For each action (RIGHT, DOWN, LEFT, UP), row indices into
            ``cost_data`` or ``reward_data``: ``k_prior`` random rows plus up to
            ``n_matching`` rows matching the action's input.  With
            ``prior_draw="per_step"`` the four are one shared array, which
            holds the matching rows of every action.
        """
        check_choice("model", model, ("cost", "reward"))
        if model == "cost":
            return self._priors(self.cost_data, cost_inputs(observation))
        return self._priors(self.reward_data, reward_inputs(observation))

    def _predict(self, model, buffer, queries, include_noise: bool = True):
        """Mean, variance, degrees of freedom and prior sizes of each query, each from its own prior."""
        priors = self._priors(buffer, queries)
        if self.prior_draw == "per_action":
            sets, query_sets = priors, queries[:, None, :]  # one query per prior
        else:
            sets, query_sets = priors[:1], queries[None, :, :]  # the four queries share one prior
        mean, var, df = self.prior_predictor.predict(model, buffer, sets, query_sets, parts=self.parts,
                                                     include_noise=include_noise)
        mean, var = mean.reshape(-1), var.reshape(-1)
        df = np.broadcast_to(df[:, None], query_sets.shape[:2]).reshape(-1)
        if self.predictive == "sample":
            mean, var = sample_moments(mean, var, df, self.n_samples, self.rng)
        return mean, var, df, np.array([len(r) for r in priors])

    def _predict_cost(self, x_cost):
        """The cost model's ``(mean, variance, tail, prior sizes)`` of each action, as the safety rule reads them.

        The variance is a new observation's (``variance="noisy"``) or the latent function's (``"latent"``).
        Under the tail rule, ``tail`` is each action's predictive probability of a distance below ``d``
        (:func:`~sarsp_edu.models.processes.predictive.probability_below`), else None.  The GP with Student-t
        noise has a Gaussian latent predictive; its noisy one under the tail rule adds the Student-t noise by
        quadrature, and its variance the noise's ``s^2 nu / (nu - 2)``.
        """
        model, noisy = self.cost_model, self.variance == "noisy"
        t_noise = noisy and self.safe_rule == "tail" and isinstance(model, StudentTLikelihoodGP)
        mean, var, df, sizes = self._predict(model, self.cost_data, x_cost, include_noise=noisy and not t_noise)
        tail = None
        if self.safe_rule == "tail":
            noise = (model.nu_, model.scale_) if t_noise else None
            tail = probability_below(self.d, mean, var, df, noise)
        if t_noise:
            var = var + noise_variance(model.nu_, model.scale_)
        return mean, var, tail, sizes

    def predict(self, observation):
        """Per-action predictions ``(mu_cost, var_cost, mu_reward, var_reward)`` with fresh priors (the cost
        variance of the kind ``variance`` says)."""
        mu_cost, var_cost, _, _ = self._predict_cost(cost_inputs(observation))
        mu_reward, var_reward, _, _ = self._predict(self.reward_model, self.reward_data, reward_inputs(observation))
        return mu_cost, var_cost, mu_reward, var_reward

    # -- Algorithm 1 ------------------------------------------------------------
    def act(self, observation):
        """Choose an action for ``observation``.

        Returns
        -------
        action : int
        decision : Decision
            The per-action predictions and whether the action was safe or the backup.
        """
        observation = np.asarray(observation, dtype=float)
        position = (int(observation[0]), int(observation[1]))
        x_cost, x_reward = cost_inputs(observation), reward_inputs(observation)
        mu_cost, var_cost, tail, n_cost = self._predict_cost(x_cost)
        mu_reward, var_reward, _, n_reward = self._predict(self.reward_model, self.reward_data, x_reward)
        known_unsafe = np.array([(position, a) in self.unsafe_pairs for a in range(len(mu_cost))])
        action, safe, backup = decide(
            self.parts, mu_cost, var_cost, mu_reward, known_unsafe, self.d, self.variance_threshold, tail,
            self.tail_delta,
        )
        decision = Decision(
            position=position,
            mu_cost=mu_cost,
            var_cost=var_cost,
            mu_reward=mu_reward,
            var_reward=var_reward,
            known_unsafe=known_unsafe,
            safe=safe,
            action=action,
            backup=backup,
            prior_size=(n_cost, n_reward),
            tail=tail,
        )
        return action, decision

    def learn(self, observation, action: int, info: dict, decision: Decision | None) -> LearnOutcome:
        """Update after a step: ``S_u``, and the corrective update of the cost model.

        Parameters
        ----------
        observation : array-like of shape (8,)
            The observation the action was chosen from.
        action : int
        info : dict
            ``step``'s info: ``"cost"`` (1 for a violation) and
            ``"distance_to_unsafe"`` (the observed cost signal).
        decision : Decision or None
            ``act``'s record for this step, which says whether the action was
            the backup (the corrective test depends on it); ``None`` for an
            action ``act`` did not choose, which is then taken as no backup.

        Returns
        -------
        LearnOutcome
        """
        outcome = LearnOutcome(violation=bool(info["cost"]))
        if not outcome.violation:
            return outcome
        observation = np.asarray(observation, dtype=float)
        position = (int(observation[0]), int(observation[1]))
        pair = (position, int(action))
        outcome.added_to_unsafe = pair not in self.unsafe_pairs
        self.unsafe_pairs.add(pair)
        # Re-predict from the same state (fresh priors), without the S_u override.
        x_cost = cost_inputs(observation)
        mu_cost, var_cost, _, _ = self._predict_cost(x_cost)
        was_backup = decision.backup if decision is not None else False
        if corrective_applies(self.parts, mu_cost, var_cost, int(action), self.d, was_backup):
            outcome.corrected = True
            outcome.buffer_update = self.cost_data.update(x_cost[action], info["distance_to_unsafe"])
            self.corrective_updates += 1
            changed = outcome.buffer_update != "unchanged"
            if self.retrain == "always" or (self.retrain == "if_changed" and changed):
                start = time.perf_counter()
                for listener in self.retrain_listeners:
                    listener("begin")
                try:
                    with one_blas_thread():  # as the offline fit: the same bits wherever learn is called from
                        self._fit(self.cost_model, self.cost_data, self.cost_fit_points, self.refit_model)
                finally:
                    for listener in self.retrain_listeners:
                        listener("end")
                outcome.retrain_seconds = time.perf_counter() - start
                outcome.retrained = True
                self.retrains += 1
        return outcome
